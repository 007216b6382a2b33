//! MuJoCo export (`proleg export mjcf`): a loaded simulation as one MJCF document, for a
//! cross-engine check of a gait or to carry a robot into MuJoCo-based tools.
//!
//! | proleg | MJCF |
//! |---|---|
//! | robot links, hinges (tail to head) | nested `<body>`s under a free root, `<joint type="hinge">` with range |
//! | link mass spread over its geometry / given inertia | per-geom `mass` / `<inertial fullinertia>` |
//! | servo: torque limit τ, speed limit v, gain g (1/s) | `<position>` actuator, `forcerange` ±τ, `kp` = g·τ/v, joint `damping` τ/v (so full torque gives speed v) |
//! | contact friction: the smaller of the two geometries' | `friction` per geom, `priority` so the smaller one wins |
//! | self-collision off | `contype`/`conaffinity`: links collide with the terrain only |
//! | boxes, spheres, cylinders, meshes, height fields | `box`, `sphere`, `cylinder` (turned: ours stand along y), `mesh` (MuJoCo collides as its convex hull), `hfield` |

mod geoms;

use std::path::Path;

use crate::config::Simulation;
use crate::config::body::BodyKind;
use crate::config::resolve::robot::geom_volume;
use crate::config::xml::write::XmlWriter;
use crate::interop::{InteropError, to_isometry, to_pose, write_text};
use crate::sim::servo::DEFAULT_SERVO_GAIN;
use geoms::{Assets, Collision, geom_attrs, mj, pose_attrs};

/// What an export wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfExport {
    /// Bodies (environment and robot links) written.
    pub bodies: usize,
    /// Hinges (and position actuators) written.
    pub joints: usize,
    /// Mesh and height-field assets written.
    pub assets: usize,
    /// Where MuJoCo will differ by construction, one line each.
    pub notes: Vec<String>,
}

/// Writes `sim` as MJCF to `out`.
pub fn export_mjcf(sim: &Simulation, out: &Path) -> Result<MjcfExport, InteropError> {
    let assets = Assets::collect(sim);
    let mut w = XmlWriter::new();
    w.open("mujoco", &[("model", sim.robot.name.clone())]);
    w.comment(&format!(
        "Exported by proleg from {}; the servo model and the contact friction rule are explained in proleg's docs/DESIGN.md.",
        sim.file.display()
    ));
    w.empty(
        "compiler",
        &[("angle", "radian".into()), ("autolimits", "true".into())],
    );
    w.empty(
        "option",
        &[
            (
                "timestep",
                mj(&[sim.files.simulation.properties.step_width]),
            ),
            ("gravity", mj(&sim.environment.physics.gravity)),
            ("integrator", "implicitfast".into()),
        ],
    );
    assets.write(&mut w, sim)?;
    w.open("worldbody", &[]);
    let env_bodies = environment(sim, &mut w, &assets)?;
    let joints = robot(sim, &mut w, &assets)?;
    w.close();
    actuators(sim, &mut w);
    w.close();
    write_text(out, &w.finish())?;
    Ok(MjcfExport {
        bodies: env_bodies + sim.robot.links.len(),
        joints,
        assets: assets.count(),
        notes: assets.notes.clone(),
    })
}

/// The environment's bodies: static ones as world geometry, dynamic ones free.
fn environment(
    sim: &Simulation,
    w: &mut XmlWriter,
    assets: &Assets,
) -> Result<usize, InteropError> {
    let env = &sim.environment;
    let default_friction = env
        .physics
        .default_friction
        .unwrap_or(crate::sim::spawn::DEFAULT_FRICTION);
    for b in &env.bodies {
        let mut attrs = vec![("name", format!("env_{}", b.name))];
        attrs.extend(pose_attrs(&b.pose));
        w.open("body", &attrs);
        let fixed = b.kind == BodyKind::Static;
        if !fixed {
            w.empty("freejoint", &[]);
        }
        let volume: f64 = b.geoms.iter().map(geom_volume).sum();
        for g in &b.geoms {
            let friction = g.friction.unwrap_or(default_friction);
            let mass = (!fixed).then(|| b.mass * geom_volume(g) / volume.max(1e-12));
            let attrs = geom_attrs(g, sim, assets, Collision::Terrain { friction }, mass)?;
            w.empty("geom", &attrs);
        }
        w.close();
    }
    Ok(env.bodies.len())
}

/// The robot's links as a tree of bodies from its root, the hinges in the children.
fn robot(sim: &Simulation, w: &mut XmlWriter, assets: &Assets) -> Result<usize, InteropError> {
    let robot = &sim.robot;
    let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
    for (k, j) in robot.joints.iter().enumerate() {
        if parent_joint[j.child].replace(k).is_some() {
            return Err(InteropError::new(
                &robot.file,
                format!(
                    "link {} is the child of two joints: MJCF needs a tree",
                    robot.links[j.child].name
                ),
            ));
        }
    }
    let self_collision = sim.environment.physics.self_collision;
    let mut written = 0;
    for root in (0..robot.links.len()).filter(|&l| parent_joint[l].is_none()) {
        let at = sim.environment.robot_pose.mul(&robot.links[root].pose);
        written += link(sim, root, &at, None, self_collision, w, assets)?;
    }
    if written != robot.links.len() {
        return Err(InteropError::new(
            &robot.file,
            "the joints form a cycle: MJCF needs a tree",
        ));
    }
    Ok(robot.joints.len())
}

/// Link `l` as a body at `at` (its parent's frame), its hinge and its children; returns
/// how many links it wrote.
fn link(
    sim: &Simulation,
    l: usize,
    at: &crate::config::transform::Pose,
    joint: Option<usize>,
    self_collision: bool,
    w: &mut XmlWriter,
    assets: &Assets,
) -> Result<usize, InteropError> {
    let robot = &sim.robot;
    let link = &robot.links[l];
    let mut attrs = vec![("name", link.name.clone())];
    attrs.extend(pose_attrs(at));
    w.open("body", &attrs);
    match joint {
        None => w.empty("freejoint", &[("name", format!("{}_free", link.name))]),
        Some(k) => hinge(sim, k, w),
    }
    if let Some(i) = &link.inertia {
        let t = i.tensor;
        w.empty(
            "inertial",
            &[
                ("pos", mj(&i.com)),
                ("mass", mj(&[link.mass])),
                (
                    "fullinertia",
                    crate::config::xml::write::nums(&[t[0], t[4], t[8], t[1], t[2], t[5]]),
                ),
            ],
        );
    }
    let volume: f64 = link.geoms.iter().map(geom_volume).sum();
    for g in &link.geoms {
        let mass = link
            .inertia
            .is_none()
            .then(|| link.mass * geom_volume(g) / volume.max(1e-12));
        let attrs = geom_attrs(g, sim, assets, Collision::Link { self_collision }, mass)?;
        w.empty("geom", &attrs);
    }
    let mut written = 1;
    let here = to_isometry(&link.pose);
    for (k, j) in robot
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.parent == l)
    {
        let rel = to_pose(&(here.inverse() * to_isometry(&robot.links[j.child].pose)));
        written += self::link(sim, j.child, &rel, Some(k), self_collision, w, assets)?;
    }
    w.close();
    Ok(written)
}

/// Hinge `k` in its child's frame: range, and the damping that caps the speed at full
/// torque at the servo's speed limit.
fn hinge(sim: &Simulation, k: usize, w: &mut XmlWriter) {
    let j = &sim.robot.joints[k];
    let child = to_isometry(&sim.robot.links[j.child].pose).inverse();
    let anchor = child * nalgebra::Point3::from(j.anchor);
    let axis = child.rotation * nalgebra::Vector3::from(j.axis);
    w.empty(
        "joint",
        &[
            ("name", j.name.clone()),
            ("type", "hinge".into()),
            ("pos", mj(&[anchor.x, anchor.y, anchor.z])),
            ("axis", mj(&[axis.x, axis.y, axis.z])),
            ("range", mj(&j.limits_deg.map(f64::to_radians))),
            ("damping", mj(&[j.max_torque / j.max_vel])),
        ],
    );
}

/// A position actuator per hinge: torque limit, and the gain that gives the servo's
/// velocity response `g * error` against the joint damping.
fn actuators(sim: &Simulation, w: &mut XmlWriter) {
    w.open("actuator", &[]);
    for j in &sim.robot.joints {
        let gain = j.servo_gain.unwrap_or(DEFAULT_SERVO_GAIN);
        let damping = j.max_torque / j.max_vel;
        let torque = j.max_torque;
        w.empty(
            "position",
            &[
                ("name", j.name.clone()),
                ("joint", j.name.clone()),
                ("kp", mj(&[gain * damping])),
                ("forcerange", mj(&[-torque, torque])),
                ("ctrlrange", mj(&j.limits_deg.map(f64::to_radians))),
            ],
        );
    }
    w.close();
}
