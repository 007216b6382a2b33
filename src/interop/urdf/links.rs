//! URDF links as proleg bodies: collision geometry as geoms, inertials merged into one
//! mass with its centre and inertia tensor.

use std::path::Path;

use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};

use crate::config::body::{Body, BodyKind, Geom, Mass, MeshCollision, Shape};
use crate::config::body::{MASSES, SIZES, balanced_inertia, inertia_fault, principal_moments};
use crate::config::error::Pos;
use crate::config::mesh::TriMesh;
use crate::interop::urdf::lint::misplaced_collision;
use crate::interop::urdf::meshes::MeshWriter;
use crate::interop::urdf::tree::{Tree, origin};
use crate::interop::urdf::validate::LinkLines;
use crate::interop::{InteropError, to_pose};

/// The smallest radius of gyration (m) an imported body keeps about any axis: a link whose
/// inertia is (nearly) singular — point masses, as `icub`'s hip and ankle links are
/// written — is given at least its mass times this squared. rapier solves joints between
/// bodies, not in reduced coordinates as MuJoCo does, and a 1e-8 kg m^2 link in a leg
/// shook `icub` through the floor; 1 cm is below any module's size.
pub const MIN_GYRATION_RADIUS: f64 = 0.01;

/// The mass a body gets when its links have neither an `<inertial>` mass nor geometry
/// (links that only chain hinges, as `human`'s and `romeo`'s do): 1 % of the lightest
/// link's. Without one an engine holds such a body in place (rapier: zero mass is infinite
/// mass) or refuses it (MuJoCo); PyBullet gives such links 1 kg and 1 kg m^2, which is
/// heavier than many robots. Its inertia is that of [`MIN_GYRATION_RADIUS`].
pub struct StandIn {
    /// Mass (kg).
    pub mass: f64,
}

impl StandIn {
    /// The stand-in for `robot`'s massless links.
    pub fn of(robot: &urdf_rs::Robot) -> StandIn {
        let lightest = robot
            .links
            .iter()
            .map(|l| l.inertial.mass.value)
            .filter(|m| *m >= MASSES.0 && m.is_finite())
            .fold(f64::INFINITY, f64::min);
        StandIn {
            mass: if lightest.is_finite() {
                (0.01 * lightest).max(MASSES.0)
            } else {
                0.01
            },
        }
    }

    /// Its principal moment about every axis (kg m^2).
    pub fn moment(&self) -> f64 {
        min_moment(self.mass)
    }
}

/// The smallest principal moment (kg m^2) a body of `mass` keeps.
fn min_moment(mass: f64) -> f64 {
    mass * MIN_GYRATION_RADIUS * MIN_GYRATION_RADIUS
}

/// What every body of one import shares: the stand-in for massless links and where each
/// link is written in the URDF (for errors).
pub struct Context {
    /// The mass and inertia of links without either.
    pub stand_in: StandIn,
    /// Where each link is written in the URDF, by name.
    pub lines: std::collections::BTreeMap<String, LinkLines>,
}

impl Context {
    /// `"line N: "` for link `name`, or nothing when its line is unknown.
    pub fn at(&self, name: &str) -> String {
        self.lines
            .get(name)
            .map(|l| format!("line {}: ", l.link))
            .unwrap_or_default()
    }
}

/// The body headed by link `head`: the collision geometry and the inertials of every link
/// merged into it. `warn` collects what cannot be represented. A mesh that cannot be read,
/// or a link whose inertial data no body can have, is an error naming the URDF. A root link
/// named `world` (the ROS convention) or a root without mass (PyBullet's) is a fixed base:
/// its body is static.
pub fn body(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    head: usize,
    meshes: &mut MeshWriter,
    ctx: &Context,
    warn: &mut Vec<String>,
) -> Result<Body, InteropError> {
    let stand_in = &ctx.stand_in;
    let geoms = body_geoms(robot, tree, head, meshes, ctx, warn)?;
    let mut mass = mass(
        robot,
        tree,
        head,
        !geoms.is_empty(),
        ctx,
        meshes.urdf(),
        warn,
    )?;
    let root = head == tree.order[0];
    let world = root && robot.links[head].name == "world";
    // PyBullet's convention: a root without mass is a fixed base (kuka_iiwa's link_0); a
    // mass from its geometry would be a gram under a 30 kg arm.
    let massless_root = root && !world && mass.is_none();
    if massless_root {
        warn.push(format!(
            "link {}: the root has no <inertial> mass, PyBullet's mark of a fixed base: it is fixed to the world",
            robot.links[head].name
        ));
    }
    let fixed = world || massless_root;
    if fixed {
        mass = None;
    } else if mass.is_none() && !geoms.is_empty() {
        warn.push(format!(
            "link {}: no <inertial> mass; its mass comes from its geometry (1000 kg/m^3)",
            robot.links[head].name
        ));
    } else if mass.is_none() {
        warn.push(format!(
            "link {}: no <inertial> mass and no geometry; it is given {:.3e} kg and {:.3e} kg m^2 (1 % of the lightest link), not left an anchor",
            robot.links[head].name, stand_in.mass, stand_in.moment()
        ));
        let k = stand_in.moment();
        mass = Some(Mass {
            total: stand_in.mass,
            distribution: "custom".into(),
            com: Some([0.0; 3]),
            inertia: Some([k, 0.0, 0.0, 0.0, k, 0.0, 0.0, 0.0, k]),
            pos: Pos::default(),
        });
    }
    Ok(Body {
        name: robot.links[head].name.clone(),
        kind: if fixed {
            BodyKind::Static
        } else {
            BodyKind::Dynamic
        },
        pose: to_pose(&tree.world[head]),
        geoms,
        mass,
        pos: Pos::default(),
    })
}

/// The collision geometry of every link merged into the body headed by `head`, coloured as
/// each link's visual; a link with a visual but no collision is named in `warn`.
fn body_geoms(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    head: usize,
    meshes: &mut MeshWriter,
    ctx: &Context,
    warn: &mut Vec<String>,
) -> Result<Vec<Geom>, InteropError> {
    let mut geoms = Vec::new();
    for l in tree.members(head) {
        let link = &robot.links[l];
        let colour = link_colour(robot, link);
        if link.collision.is_empty() && !link.visual.is_empty() {
            warn.push(format!(
                "link {}: it has <visual> but no <collision> geometry; proleg draws what collides, so it is not imported",
                link.name
            ));
        }
        for (ci, c) in link.collision.iter().enumerate() {
            let at = tree.in_body(l) * origin(&c.origin);
            let g = geom(&link.name, &c.geometry, &at, meshes, warn).map_err(|e| {
                // The URDF's place first, then what the mesh file says.
                InteropError::new(
                    meshes.urdf(),
                    format!("{}link {}: <collision> {e}", ctx.at(&link.name), link.name),
                )
            })?;
            if let Some(mut g) = g {
                if let Shape::Trimesh { file, .. } = &g.shape
                    && let Some(size) = meshes.mesh(file).map(diagonal)
                {
                    warn.extend(misplaced_collision(
                        link,
                        ctx.lines.get(&link.name),
                        ci,
                        size,
                    ));
                }
                g.diffuse_color = colour;
                geoms.push(g);
            }
        }
    }
    Ok(geoms)
}

/// The diagonal of `mesh`'s bounding box (m).
fn diagonal(mesh: &TriMesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt()
}

/// The colour of a link's first visual with one (inline or a named robot material).
fn link_colour(robot: &urdf_rs::Robot, link: &urdf_rs::Link) -> Option<[f64; 3]> {
    link.visual.iter().find_map(|v| {
        let m = v.material.as_ref()?;
        let c = m.color.as_ref().or_else(|| {
            robot
                .materials
                .iter()
                .find(|r| r.name == m.name)
                .and_then(|r| r.color.as_ref())
        })?;
        Some([c.rgba[0], c.rgba[1], c.rgba[2]].map(|v| v.clamp(0.0, 1.0)))
    })
}

/// One collision geometry at `at` (in its body's frame); `None` (with a warning) for what
/// proleg cannot represent.
/// Whether a size (a half-extent, a radius, a height; m) is one proleg's files hold.
fn size_ok(v: f64) -> bool {
    (SIZES.0..=SIZES.1).contains(&v)
}

fn geom(
    link: &str,
    g: &urdf_rs::Geometry,
    at: &Isometry3<f64>,
    meshes: &mut MeshWriter,
    warn: &mut Vec<String>,
) -> Result<Option<Geom>, InteropError> {
    // proleg's cylinders stand along y, URDF's along z: turn y onto z.
    let y_to_z = || at * UnitQuaternion::from_euler_angles(std::f64::consts::FRAC_PI_2, 0.0, 0.0);
    let (shape, pose) = match g {
        urdf_rs::Geometry::Box { size } if size.iter().all(|v| size_ok(v / 2.0)) => (
            Shape::Box {
                extents: [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0],
            },
            *at,
        ),
        urdf_rs::Geometry::Sphere { radius } if size_ok(*radius) => {
            (Shape::Sphere { radius: *radius }, *at)
        }
        urdf_rs::Geometry::Cylinder { radius, length } if size_ok(*radius) && size_ok(*length) => (
            Shape::Cylinder {
                radius: *radius,
                height: *length,
            },
            y_to_z(),
        ),
        urdf_rs::Geometry::Capsule { radius, length }
            if size_ok(*radius) && size_ok(length + 2.0 * radius) =>
        {
            warn.push(format!(
                "link {link}: a capsule (r {radius} m, length {length} m) is imported as a cylinder of its full length"
            ));
            let height = length + 2.0 * radius;
            (
                Shape::Cylinder {
                    radius: *radius,
                    height,
                },
                y_to_z(),
            )
        }
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.map(|s| s.0).unwrap_or([1.0; 3]);
            match meshes.convert(filename, scale)? {
                Some(file) => (
                    Shape::Trimesh {
                        file,
                        scale: 1.0,
                        collision: MeshCollision::ConvexHull,
                    },
                    *at,
                ),
                None => {
                    warn.push(format!(
                        "link {link}: mesh {filename} is not OBJ, STL or DAE; its collision geometry is not imported"
                    ));
                    return Ok(None);
                }
            }
        }
        other => {
            warn.push(format!(
                "link {link}: a geometry of zero size, or outside proleg's {} to {} m, is skipped: {other:?}",
                SIZES.0, SIZES.1
            ));
            return Ok(None);
        }
    };
    Ok(Some(Geom {
        shape,
        pose: to_pose(&pose),
        diffuse_color: None,
        ambient_color: None,
        transparency: None,
        friction: None,
        visible: true,
        pos: Pos::default(),
    }))
}

/// A link's `<inertial>` as a rigid body could have it: a mass not negative (zero: a
/// massless link) and, with a mass, an inertia tensor whose principal moments are not
/// negative. A singular tensor (a point mass, as contact frames are written, or a thin rod)
/// is accepted and made turnable when its body's tensor is formed ([`turnable`]); a tensor
/// that only breaks the triangle inequality (real URDFs do, by a little: xarm6's link2 by
/// 0.7 %) is balanced in [`link_inertia`] with a warning.
fn check_inertial(link: &urdf_rs::Link, at: &str, urdf: &Path) -> Result<(), InteropError> {
    let i = &link.inertial;
    let name = &link.name;
    if !(0.0..=MASSES.1).contains(&i.mass.value) {
        return Err(InteropError::new(
            urdf,
            format!(
                "{at}link {name}: <inertial><mass value=\"{}\"/>: a mass must be between 0 and {} kg",
                i.mass.value, MASSES.1
            ),
        ));
    }
    if i.mass.value == 0.0 {
        return Ok(());
    }
    let [a, b, c] = principal_moments(&tensor_of(link));
    if !(a.is_finite() && b.is_finite() && c.is_finite()) || a < -1e-6 * c.abs().max(1e-12) {
        return Err(InteropError::new(
            urdf,
            format!(
                "{at}link {name}: <inertial><inertia>: not positive semi-definite (principal moments {a:.4e}, {b:.4e}, {c:.4e} kg m^2): no body has it"
            ),
        ));
    }
    Ok(())
}

/// A link's `<inertia>` as a row-major tensor.
fn tensor_of(link: &urdf_rs::Link) -> [f64; 9] {
    let t = &link.inertial.inertia;
    [
        t.ixx, t.ixy, t.ixz, t.ixy, t.iyy, t.iyz, t.ixz, t.iyz, t.izz,
    ]
}

/// A body's merged tensor (of `mass` kg) made one a body can turn with: a principal moment
/// below [`min_moment`] (point masses, a rod) is raised to it (with a warning), then the
/// triangle inequality is balanced.
fn turnable(name: &str, t: [f64; 9], mass: f64, warn: &mut Vec<String>) -> [f64; 9] {
    let [a, b, c] = principal_moments(&t);
    let floor = min_moment(mass);
    if a >= floor {
        return balanced_inertia(&t);
    }
    warn.push(format!(
        "link {name}: a principal moment of its inertia is below that of a radius of gyration of {} cm (moments {a:.3e}, {b:.3e}, {c:.3e} kg m^2: point masses or a rod); each is raised to at least {floor:.3e} kg m^2",
        MIN_GYRATION_RADIUS * 100.0
    ));
    let e = nalgebra::Matrix3::from_row_slice(&t).symmetric_eigen();
    let l = e.eigenvalues.map(|v| v.max(floor));
    let m = e.eigenvectors * Matrix3::from_diagonal(&l) * e.eigenvectors.transpose();
    balanced_inertia(&std::array::from_fn(|k| m[(k / 3, k % 3)]))
}

/// A link's inertia tensor (its inertial frame), balanced when it breaks the triangle
/// inequality (with a warning naming the link and by how much).
fn link_inertia(link: &urdf_rs::Link, warn: &mut Vec<String>) -> Matrix3<f64> {
    let m = tensor_of(link);
    let balanced = balanced_inertia(&m);
    if balanced != m && principal_moments(&m)[0] > 0.0 {
        let [a, b, c] = principal_moments(&m);
        warn.push(format!(
            "link {}: its inertia's principal moments break the triangle inequality ({a:.4e} + {b:.4e} < {c:.4e} kg m^2, by {:.1} %); the two smaller were raised to balance it, as MuJoCo's balanceinertia does",
            link.name,
            (c - a - b) / c * 100.0
        ));
    }
    Matrix3::from_row_slice(&balanced)
}

/// The merged mass of a body's links: total, centre and inertia about it in the body
/// frame (parallel-axis theorem). `None` (mass from the geometry) when no link has one;
/// an error naming the link when one's inertial data is not physical.
fn mass(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    head: usize,
    has_geometry: bool,
    ctx: &Context,
    urdf: &Path,
    warn: &mut Vec<String>,
) -> Result<Option<Mass>, InteropError> {
    let mut parts = Vec::new();
    for l in tree.members(head) {
        let link = &robot.links[l];
        check_inertial(link, &ctx.at(&link.name), urdf)?;
        let i = &robot.links[l].inertial;
        if i.mass.value <= 0.0 {
            continue;
        }
        if i.mass.value < MASSES.0 {
            warn.push(format!(
                "link {}: its mass {} kg is below proleg's {} kg; it is taken as no mass",
                link.name, i.mass.value, MASSES.0
            ));
            continue;
        }
        let frame = tree.in_body(l) * origin(&i.origin);
        let r = frame.rotation.to_rotation_matrix().into_inner();
        let local = link_inertia(&robot.links[l], warn);
        parts.push((
            i.mass.value,
            frame.translation.vector,
            r * local * r.transpose(),
        ));
    }
    let name = &robot.links[head].name;
    if parts.is_empty() {
        return Ok(None);
    }
    let total: f64 = parts.iter().map(|p| p.0).sum();
    if total > MASSES.1 {
        return Err(InteropError::new(
            urdf,
            format!(
                "link {name}: the links merged into its body weigh {total} kg, above proleg's {} kg",
                MASSES.1
            ),
        ));
    }
    let com: Vector3<f64> = parts.iter().map(|p| p.1 * p.0).sum::<Vector3<f64>>() / total;
    let mut inertia = Matrix3::zeros();
    for (m, c, i) in &parts {
        let d = c - com;
        inertia += i + (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * *m;
    }
    let tensor: [f64; 9] = std::array::from_fn(|k| inertia[(k / 3, k % 3)]);
    let [a, b, c] = principal_moments(&tensor);
    if has_geometry && a < min_moment(total) {
        // Point masses on a body with a shape: the shape's inertia at the URDF's mass, as
        // MuJoCo's inertiafromgeom and PyBullet's URDF_USE_INERTIA_FROM_FILE-less load do.
        warn.push(format!(
            "link {name}: its inertia is (nearly) singular (principal moments {a:.3e}, {b:.3e}, {c:.3e} kg m^2: point masses); its {total} kg are spread over its collision geometry instead"
        ));
        return Ok(Some(Mass {
            total,
            distribution: "mimicgeom".into(),
            com: None,
            inertia: None,
            pos: Pos::default(),
        }));
    }
    let written = turnable(name, tensor, total, warn);
    // The robot file's own rule (one door): links merged from absurd distances (a fuzzed
    // joint 1e52 m away) give a tensor whose smallest moment is lost to rounding.
    if let Some(fault) = inertia_fault(&written) {
        return Err(InteropError::new(
            urdf,
            format!(
                "link {name}: the links merged into its body have an inertia no body can have: {fault} (are its fixed joints' origins where they should be?)"
            ),
        ));
    }
    Ok(Some(Mass {
        total,
        distribution: "custom".into(),
        com: Some([com.x, com.y, com.z]),
        inertia: Some(written),
        pos: Pos::default(),
    }))
}
