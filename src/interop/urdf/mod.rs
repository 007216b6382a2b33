//! URDF import (`proleg import URDF -o DIR`): a URDF robot, parsed by the `urdf-rs` crate,
//! written as a proleg robot file with its meshes, plus a floor, a sine actuation and a
//! simulation file so that it runs at once.
//!
//! | URDF | proleg |
//! |---|---|
//! | link, `<collision>` box / sphere / cylinder | `<Body>` with `<Geom>` box / sphere / cylinder (turned: ours stand along y) |
//! | `<collision>` mesh (OBJ, STL, DAE), with scale | OBJ in `meshes/`, scaled, `type="convexhull"` |
//! | `<inertial>` mass, origin, inertia | `<Mass type="custom">` total, `<com>`, `<inertia>` (merged links: parallel-axis theorem); a negative mass or an indefinite tensor is an error naming the link, a tensor breaking the triangle inequality is balanced (warning) |
//! | revolute joint | hinge: axis, limits (deg), effort -> `maxtorque`, velocity -> `maxvel`; zero pose outside the limits: warning, the sine centred inside |
//! | continuous joint | hinge limited to +-180 deg (warning) |
//! | fixed joint | child link merged into its parent body |
//! | prismatic / floating / planar / spherical joint, capsule, other mesh formats, visual-only geometry, mimic, damping | warnings, listed in the report |
//! | a `<collision>` mesh farther from the `<visual>` of the same mesh than the mesh is large | imported as written, a warning naming both lines ([`lint`]) |

mod links;
mod lint;
mod meshes;
mod options;
mod outputs;
mod tree;
mod validate;

use std::fmt;
use std::path::{Path, PathBuf};

use crate::config::error::Pos;
use crate::config::kinbody::{Joint, KinBody};
use crate::config::robot::{RobotFile, write_robot_file};
use crate::config::transform::Pose;
use crate::interop::{InteropError, write_text};
use links::{Context, StandIn, body};
use meshes::MeshWriter;
pub use options::{ImportOptions, PackageArgError, package_arg};
pub use outputs::{SINE_AMPLITUDE_DEG, set_articulation};
use outputs::{lowest_point, write_run_files};
use tree::{Tree, is_hinge};

/// The sine's offset (deg) per hinge: 0 when the swing around 0 fits the joint's limits,
/// else the nearest centre that fits (the middle of a range narrower than the swing). A
/// joint whose limits exclude 0 — it starts outside them, as go1's knees do — is named in
/// a warning: a sine around 0 would be clamped at the limit and the joint never move.
fn gait_offsets(joints: &[Joint], warn: &mut Vec<String>) -> Vec<f64> {
    joints
        .iter()
        .map(|j| {
            let Some([lo, hi]) = j.limits_deg else {
                return 0.0;
            };
            if !(lo <= 0.0 && 0.0 <= hi) {
                warn.push(format!(
                    "joint {}: it starts at 0 deg, outside its limits {lo:.1}..{hi:.1} deg; the sine is centred inside them",
                    j.name
                ));
            }
            let a = SINE_AMPLITUDE_DEG;
            if hi - lo <= 2.0 * a {
                (lo + hi) / 2.0
            } else {
                0.0_f64.clamp(lo + a, hi - a)
            }
        })
        .collect()
}

/// What an import wrote and what it could not represent.
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfImport {
    /// The robot's name (from the URDF, made safe for file names).
    pub name: String,
    /// The robot file written.
    pub robot_file: PathBuf,
    /// The simulation file written beside it (floor, sine on every joint).
    pub simulation_file: Option<PathBuf>,
    /// Links in the URDF.
    pub urdf_links: usize,
    /// Joints in the URDF.
    pub urdf_joints: usize,
    /// Bodies written (links after merging those on fixed joints).
    pub bodies: usize,
    /// Hinges written (revolute and continuous joints).
    pub hinges: usize,
    /// Mesh files written.
    pub meshes: usize,
    /// What could not be represented, one line each.
    pub warnings: Vec<String>,
}

impl fmt::Display for UrdfImport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "imported {}: {} links and {} joints -> {} bodies, {} hinges, {} meshes",
            self.name, self.urdf_links, self.urdf_joints, self.bodies, self.hinges, self.meshes
        )?;
        writeln!(f, "robot: {}", self.robot_file.display())?;
        match &self.simulation_file {
            Some(s) => writeln!(f, "run it: proleg run {}", s.display())?,
            None => writeln!(f, "no hinge to drive: no simulation file written")?,
        }
        for w in &self.warnings {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}

/// Imports the URDF at `urdf` into `out_dir` with [`ImportOptions::from_env`].
pub fn import_urdf(urdf: &Path, out_dir: &Path) -> Result<UrdfImport, InteropError> {
    import_urdf_with(urdf, out_dir, &ImportOptions::from_env())
}

/// Imports the URDF at `urdf` into `out_dir`. A robot left without any collision geometry
/// (its links have only `<visual>`, or meshes in formats not read) would fall through the
/// floor: an error, or with `allow_no_collision` a warning.
pub fn import_urdf_with(
    urdf: &Path,
    out_dir: &Path,
    opts: &ImportOptions,
) -> Result<UrdfImport, InteropError> {
    let text = std::fs::read_to_string(urdf)
        .map_err(|e| InteropError::new(urdf, format!("cannot read: {e}")))?;
    let mut warnings = Vec::new();
    let cleaned = validate::cleaned(urdf, &text, &mut warnings)?;
    let robot = urdf_rs::read_from_string(&cleaned.text).map_err(|e| {
        InteropError::new(
            urdf,
            format!("not a valid URDF (urdf-rs, no line known): {e}"),
        )
    })?;
    let tree = Tree::new(urdf, &robot)?;
    warnings.extend(joint_warnings(&robot));
    let mut meshes = MeshWriter::new(urdf, out_dir, opts);
    let ctx = Context {
        stand_in: StandIn::of(&robot),
        lines: cleaned.lines,
    };
    let mut bodies = Vec::new();
    for &l in &tree.order {
        if tree.body_of[l] == l {
            bodies.push(body(&robot, &tree, l, &mut meshes, &ctx, &mut warnings)?);
        }
    }
    if bodies.iter().all(|b| b.geoms.is_empty()) {
        let why = no_collision_reason(&robot, &ctx);
        if !opts.allow_no_collision {
            return Err(InteropError::new(
                urdf,
                format!("{why}; import it anyway with --allow-no-collision"),
            ));
        }
        warnings.push(format!("{why} (imported anyway: --allow-no-collision)"));
    }
    let joints: Vec<Joint> = tree
        .order
        .iter()
        .filter_map(|&l| tree.parent_joint[l].map(|k| (l, k)))
        .filter(|&(_, k)| is_hinge(&robot.joints[k]))
        .map(|(l, k)| hinge(&robot, &tree, l, k, &mut warnings))
        .collect();
    // Files are named after the URDF (robot names such as "physics" say little).
    let stem = urdf.file_stem().map(|s| s.to_string_lossy().into_owned());
    let name = file_name(stem.as_deref().unwrap_or(&robot.name));
    let robot_file = out_dir.join(format!("{name}.robot.xml"));
    let mut file = RobotFile {
        name: name.clone(),
        kinbody: KinBody {
            name: Some(name.clone()),
            pose: Pose::IDENTITY,
            includes: Vec::new(),
            bodies,
            joints,
            sensors: Vec::new(),
            pos: Pos::default(),
        },
        sensors: Vec::new(),
        servos: None,
        pos: Pos::default(),
    };
    file.round_for_people();
    write_text(&robot_file, &write_robot_file(&file))?;
    let hinges = file.kinbody.joints.len();
    let offsets = gait_offsets(&file.kinbody.joints, &mut warnings);
    if hinges == 0 {
        warnings.push("no revolute or continuous joint: there is nothing to drive".into());
    }
    let low = lowest_point(&file.kinbody.bodies, &meshes);
    let simulation_file = Some(write_run_files(out_dir, &name, &offsets, low)?);
    Ok(UrdfImport {
        name,
        robot_file,
        simulation_file,
        urdf_links: robot.links.len(),
        urdf_joints: robot.joints.len(),
        bodies: file.kinbody.bodies.len(),
        hinges,
        meshes: meshes.count(),
        warnings,
    })
}

/// Why a robot without collision geometry is refused, naming the links drawn but not
/// colliding (where the geometry would have been) with their lines.
fn no_collision_reason(robot: &urdf_rs::Robot, ctx: &Context) -> String {
    let drawn: Vec<String> = robot
        .links
        .iter()
        .filter(|l| !l.visual.is_empty())
        .take(4)
        .map(|l| format!("{}link {}", ctx.at(&l.name), l.name))
        .collect();
    format!(
        "no link has collision geometry proleg reads (only <visual>, or meshes in other \
         formats than OBJ, STL and DAE{}): the robot would fall through the floor",
        if drawn.is_empty() {
            format!(
                "; none of its {} links has <collision> or <visual>: a kinematic model",
                robot.links.len()
            )
        } else {
            format!("; <visual> only: {}", drawn.join(", "))
        }
    )
}

/// Warnings for joints proleg does not drive as the URDF says.
fn joint_warnings(robot: &urdf_rs::Robot) -> Vec<String> {
    let mut w = Vec::new();
    for j in &robot.joints {
        use urdf_rs::JointType as T;
        match j.joint_type {
            T::Prismatic | T::Floating | T::Planar | T::Spherical => w.push(format!(
                "joint {}: a {:?} joint is not supported; its child link is fixed to its parent",
                j.name, j.joint_type
            )),
            _ => {}
        }
        if let Some(m) = &j.mimic {
            w.push(format!(
                "joint {}: mimics {}; proleg drives it on its own",
                j.name, m.joint
            ));
        }
        if let Some(d) = &j.dynamics
            && (d.damping != 0.0 || d.friction != 0.0)
        {
            w.push(format!(
                "joint {}: damping {} and friction {} are not represented (the servo model sets them)",
                j.name, d.damping, d.friction
            ));
        }
    }
    w
}

/// The hinge of joint `k` whose child is link `child`: anchor and axis in the frame of the
/// parent's body.
fn hinge(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    child: usize,
    k: usize,
    warn: &mut Vec<String>,
) -> Joint {
    let j = &robot.joints[k];
    let parent_link = robot
        .links
        .iter()
        .position(|l| l.name == j.parent.link)
        .unwrap_or(child);
    let parent_body = tree.body_of[parent_link];
    let to_parent = tree.world[parent_body].inverse() * tree.world[child];
    // A direction of length 1e-6 or more (validate.rs), made a unit vector as URDF means it.
    let axis = to_parent.rotation
        * nalgebra::Vector3::new(j.axis.xyz[0], j.axis.xyz[1], j.axis.xyz[2]).normalize();
    let anchor = to_parent.translation.vector;
    let lim = &j.limit;
    let limits_deg = match j.joint_type {
        urdf_rs::JointType::Continuous => {
            warn.push(format!(
                "joint {}: continuous, limited to +-180 deg (proleg's servos hold positions)",
                j.name
            ));
            [-180.0, 180.0]
        }
        _ if lim.lower.is_finite() && lim.upper.is_finite() && lim.lower < lim.upper => {
            let (lo, hi) = (lim.lower.to_degrees(), lim.upper.to_degrees());
            if lo < -180.0 || hi > 180.0 {
                warn.push(format!(
                    "joint {}: limits {lo:.1}..{hi:.1} deg are cut to -180..180 (proleg's hinge range)",
                    j.name
                ));
            }
            [lo.max(-180.0), hi.min(180.0)]
        }
        _ => {
            warn.push(format!(
                "joint {}: limits {}..{} rad are not a range; +-180 deg is used",
                j.name, lim.lower, lim.upper
            ));
            [-180.0, 180.0]
        }
    };
    let positive = |v: f64, what: &str, default: &str, warn: &mut Vec<String>| {
        if v > 0.0 && v.is_finite() {
            Some(v)
        } else {
            warn.push(format!(
                "joint {}: no {what}; proleg's default {default} applies",
                j.name
            ));
            None
        }
    };
    Joint {
        name: j.name.clone(),
        bodies: [
            robot.links[parent_body].name.clone(),
            robot.links[child].name.clone(),
        ],
        offset_from: None,
        anchor: [anchor.x, anchor.y, anchor.z],
        axis: [axis.x, axis.y, axis.z],
        max_torque: positive(lim.effort, "effort", "0.4 N m", warn),
        max_vel: positive(lim.velocity, "velocity", "4.5 rad/s", warn),
        limits_deg: Some(limits_deg.map(|d| (d * 1e4).round() / 1e4)),
        servo_gain: None,
        servo_dead_band: None,
        servo_latency: None,
        pos: Pos::default(),
    }
}

/// A robot name as a file name: letters, digits, `_` and `-`.
fn file_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "robot".into() } else { s }
}
