//! URDF links as proleg bodies: collision geometry as geoms, inertials merged into one
//! mass with its centre and inertia tensor.

use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};

use crate::config::body::{Body, BodyKind, Geom, Mass, MeshCollision, Shape};
use crate::config::body::{balanced_inertia, inertia_fault, principal_moments};
use crate::config::error::Pos;
use crate::interop::urdf::meshes::MeshWriter;
use crate::interop::urdf::tree::{Tree, origin};
use crate::interop::{InteropError, to_pose};

/// The body headed by link `head`: the collision geometry and the inertials of every link
/// merged into it. `warn` collects what cannot be represented. A mesh that cannot be read,
/// or a link whose inertial data no body can have, is an error naming the URDF.
pub fn body(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    head: usize,
    meshes: &mut MeshWriter,
    warn: &mut Vec<String>,
) -> Result<Body, InteropError> {
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
        for c in &link.collision {
            let at = tree.in_body(l) * origin(&c.origin);
            if let Some(mut g) = geom(&link.name, &c.geometry, &at, meshes, warn)? {
                g.diffuse_color = colour;
                geoms.push(g);
            }
        }
    }
    let mass = mass(robot, tree, head, warn).map_err(|e| InteropError::new(meshes.urdf(), e))?;
    Ok(Body {
        name: robot.links[head].name.clone(),
        kind: BodyKind::Dynamic,
        pose: to_pose(&tree.world[head]),
        geoms,
        mass,
        pos: Pos::default(),
    })
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
        urdf_rs::Geometry::Box { size } if size.iter().all(|v| *v > 0.0) => (
            Shape::Box {
                extents: [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0],
            },
            *at,
        ),
        urdf_rs::Geometry::Sphere { radius } if *radius > 0.0 => {
            (Shape::Sphere { radius: *radius }, *at)
        }
        urdf_rs::Geometry::Cylinder { radius, length } if *radius > 0.0 && *length > 0.0 => (
            Shape::Cylinder {
                radius: *radius,
                height: *length,
            },
            y_to_z(),
        ),
        urdf_rs::Geometry::Capsule { radius, length } if *radius > 0.0 => {
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
                        "link {link}: mesh {filename} is not OBJ or STL; its collision geometry is not imported"
                    ));
                    return Ok(None);
                }
            }
        }
        other => {
            warn.push(format!(
                "link {link}: a geometry of zero size is skipped: {other:?}"
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
/// massless link) and, with a mass, a positive definite inertia tensor ([`inertia_fault`]);
/// a tensor that only breaks the triangle inequality (real URDFs do, by a little: xarm6's
/// link2 by 0.7 %) is balanced in [`link_inertia`] with a warning.
fn check_inertial(link: &urdf_rs::Link) -> Result<(), String> {
    let i = &link.inertial;
    let name = &link.name;
    if !(i.mass.value >= 0.0 && i.mass.value.is_finite()) {
        return Err(format!(
            "link {name}: <inertial><mass value=\"{}\"/>: a mass must be >= 0 kg",
            i.mass.value
        ));
    }
    if i.mass.value == 0.0 {
        return Ok(());
    }
    let t = &i.inertia;
    let m = [
        t.ixx, t.ixy, t.ixz, t.ixy, t.iyy, t.iyz, t.ixz, t.iyz, t.izz,
    ];
    match inertia_fault(&m) {
        Some(fault) if fault.starts_with("not positive definite") => {
            Err(format!("link {name}: <inertial><inertia>: {fault}"))
        }
        _ => Ok(()),
    }
}

/// A link's inertia tensor (its inertial frame), balanced when it breaks the triangle
/// inequality (with a warning naming the link and by how much).
fn link_inertia(link: &urdf_rs::Link, warn: &mut Vec<String>) -> Matrix3<f64> {
    let t = &link.inertial.inertia;
    let m = [
        t.ixx, t.ixy, t.ixz, t.ixy, t.iyy, t.iyz, t.ixz, t.iyz, t.izz,
    ];
    let balanced = balanced_inertia(&m);
    if balanced != m {
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
    warn: &mut Vec<String>,
) -> Result<Option<Mass>, String> {
    let mut parts = Vec::new();
    for l in tree.members(head) {
        check_inertial(&robot.links[l])?;
        let i = &robot.links[l].inertial;
        if i.mass.value <= 0.0 {
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
        warn.push(format!(
            "link {name}: no <inertial> mass; its mass comes from its geometry (1000 kg/m^3)"
        ));
        return Ok(None);
    }
    let total: f64 = parts.iter().map(|p| p.0).sum();
    let com: Vector3<f64> = parts.iter().map(|p| p.1 * p.0).sum::<Vector3<f64>>() / total;
    let mut inertia = Matrix3::zeros();
    for (m, c, i) in &parts {
        let d = c - com;
        inertia += i + (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * *m;
    }
    let tensor: [f64; 9] = std::array::from_fn(|k| inertia[(k / 3, k % 3)]);
    let valid = (0..3).all(|k| inertia[(k, k)] > 0.0);
    if !valid {
        warn.push(format!(
            "link {name}: its inertia tensor has a diagonal entry <= 0; the inertia comes from its geometry"
        ));
    }
    Ok(Some(Mass {
        total,
        distribution: if valid { "custom" } else { "mimicgeom" }.into(),
        com: Some([com.x, com.y, com.z]),
        inertia: valid.then_some(tensor),
        pos: Pos::default(),
    }))
}
