//! Consistency checks of a URDF that refuse nothing but say where a file contradicts
//! itself: a collision mesh placed away from the visual copy of the same mesh, so that the
//! link touches the floor where nothing is drawn (example-robot-data's `alex_nub_hands`:
//! each nub's `<collision>` has `xyz="0 1.57 0"` where its `<visual>` has `rpy="0 1.57 0"`,
//! and the humanoid leans on two phantom nubs 1.57 m beside its hands). The robot is
//! imported as written, as ROS, PyBullet and MuJoCo read it; the warning names both lines.

use crate::interop::urdf::validate::LinkLines;

/// The warning for collision `index` of `link`, a mesh of size `size` (its bounding box's
/// diagonal, m), when a `<visual>` of the same mesh and scale lies farther from it than the
/// mesh is large (the two copies do not overlap); `None` otherwise.
pub fn misplaced_collision(
    link: &urdf_rs::Link,
    lines: Option<&LinkLines>,
    index: usize,
    size: f64,
) -> Option<String> {
    let collision = link.collision.get(index)?;
    let (file, scale) = mesh_of(&collision.geometry)?;
    let (v, visual) = link
        .visual
        .iter()
        .enumerate()
        .find(|(_, v)| mesh_of(&v.geometry) == Some((file, scale)))?;
    let c = collision.origin.xyz.0;
    let d = distance(c, visual.origin.xyz.0);
    if d <= size {
        return None;
    }
    let line = |l: Option<&u32>| l.map(|l| format!("line {l}: ")).unwrap_or_default();
    let collision_at = line(lines.and_then(|l| l.collisions.get(index)));
    let visual_at = lines
        .and_then(|l| l.visuals.get(v))
        .map(|l| format!(" (line {l})"))
        .unwrap_or_default();
    let swapped = if distance(c, visual.origin.rpy.0) < 1e-9 {
        format!(
            "; its xyz ({}) is the visual's rpy: an rpy written as xyz?",
            triple(c)
        )
    } else {
        String::new()
    };
    Some(format!(
        "{collision_at}link {}: <collision> mesh {file} lies {d:.3} m from the <visual> of the same mesh{visual_at}, \
         farther than the mesh is large ({size:.3} m): the link touches where nothing is drawn{swapped}",
        link.name
    ))
}

/// The file and scale of a mesh geometry.
fn mesh_of(g: &urdf_rs::Geometry) -> Option<(&str, [f64; 3])> {
    match g {
        urdf_rs::Geometry::Mesh { filename, scale } => {
            Some((filename.as_str(), scale.map(|s| s.0).unwrap_or([1.0; 3])))
        }
        _ => None,
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

fn triple(v: [f64; 3]) -> String {
    format!("{} {} {}", v[0], v[1], v[2])
}
