//! Drawing configuration geometry in Bevy, for every 3D view (control window, configuration
//! window, videos): a geometry's mesh and material, a pose as a transform, the lights, and
//! the metre grid on the ground (so that a crawling robot is seen to move over it).

use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;

use crate::config::body::{Geom, MeshCollision, Shape};
use crate::config::mesh::TriMesh;
use crate::config::transform::Pose;

/// The material of a geometry: its diffuse colour and transparency.
pub fn geom_material(g: &Geom) -> StandardMaterial {
    let [r, gr, b] = g.diffuse_color.unwrap_or([0.7, 0.7, 0.7]);
    let alpha = 1.0 - g.transparency.unwrap_or(0.0).clamp(0.0, 1.0);
    StandardMaterial {
        base_color: Color::srgba(r as f32, gr as f32, b as f32, alpha as f32),
        alpha_mode: if alpha < 0.9 {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        },
        perceptual_roughness: 0.8,
        // Terrain meshes often lie flush on the floor: draw them in front of it.
        depth_bias: if matches!(g.shape, Shape::Trimesh { .. }) {
            1000.0
        } else {
            0.0
        },
        ..default()
    }
}

/// The mesh of a geometry; a trimesh takes its parsed mesh from `tri` (None: a mesh that
/// was not loaded, which the loader has reported).
pub fn geom_mesh(shape: &Shape, tri: Option<&TriMesh>) -> Option<Mesh> {
    Some(match shape {
        Shape::Box { extents: [x, y, z] } => {
            Cuboid::new(2.0 * *x as f32, 2.0 * *y as f32, 2.0 * *z as f32).into()
        }
        Shape::Sphere { radius } => Sphere::new(*radius as f32).mesh().ico(3).ok()?,
        Shape::Cylinder { radius, height } => Cylinder::new(*radius as f32, *height as f32).into(),
        Shape::Trimesh {
            scale, collision, ..
        } => {
            let obj = tri?;
            let positions: Vec<[f32; 3]> = obj
                .vertices
                .iter()
                .map(|v| v.map(|c| (c * scale) as f32))
                .collect();
            let indices: Vec<u32> = obj.triangles.iter().flatten().copied().collect();
            let mut mesh = Mesh::new(
                PrimitiveTopology::TriangleList,
                RenderAssetUsages::default(),
            )
            .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
            .with_inserted_indices(Indices::U32(indices));
            mesh.duplicate_vertices();
            mesh.compute_flat_normals();
            if *collision == MeshCollision::HeightField {
                tint_by_height(&mut mesh);
            }
            mesh
        }
    })
}

/// Shades a height field's vertices by their height, from 70 % of its colour at its
/// lowest point to 125 % at its highest: a few centimetres of relief under a high sun
/// look flat otherwise (the material's colour multiplies the vertices').
fn tint_by_height(mesh: &mut Mesh) {
    let Some(positions) = mesh
        .attribute(Mesh::ATTRIBUTE_POSITION)
        .and_then(|a| a.as_float3())
    else {
        return;
    };
    let (lo, hi) = positions
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[2]), hi.max(p[2]))
        });
    let span = (hi - lo).max(1e-6);
    let colours: Vec<[f32; 4]> = positions
        .iter()
        .map(|p| {
            let k = 0.7 + 0.55 * (p[2] - lo) / span;
            [k, k, k, 1.0]
        })
        .collect();
    mesh.insert_attribute(Mesh::ATTRIBUTE_COLOR, colours);
}

/// A configuration pose as a Bevy transform (same frame: the scene root converts).
pub fn to_transform(p: &Pose) -> Transform {
    let [w, x, y, z] = p.rotation;
    let [tx, ty, tz] = p.translation;
    Transform::from_translation(Vec3::new(tx as f32, ty as f32, tz as f32))
        .with_rotation(Quat::from_xyzw(x as f32, y as f32, z as f32, w as f32).normalize())
}

/// Sun with shadows and a soft ambient light.
pub fn spawn_lights(mut commands: Commands) {
    commands.insert_resource(GlobalAmbientLight {
        brightness: 400.0,
        ..default()
    });
    commands.spawn((
        Name::new("sun"),
        DirectionalLight {
            illuminance: 9000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(2.0, 6.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
}

/// Marks the metre lines drawn on a ground geometry ([`ground_grid`]); [`ShowGrid`] shows
/// or hides them all.
#[derive(Component)]
pub struct GroundGrid;

/// Whether the ground's metre grid is shown (default: yes).
#[derive(Resource, Clone, Copy, PartialEq, Eq)]
pub struct ShowGrid(pub bool);

impl Default for ShowGrid {
    fn default() -> Self {
        ShowGrid(true)
    }
}

/// Smallest side (m) of a box that gets a grid: a floor or a slope, not a step or a wall.
const GRID_MIN_SIDE: f64 = 2.0;

/// Lines every metre on the top face of a box at least [`GRID_MIN_SIDE`] long on both
/// horizontal sides, in the geometry's own frame (a slope's grid lies on the slope): the
/// mesh, or `None` for any other geometry.
pub fn ground_grid(shape: &Shape) -> Option<Mesh> {
    let Shape::Box { extents: [x, y, z] } = *shape else {
        return None;
    };
    if 2.0 * x < GRID_MIN_SIDE || 2.0 * y < GRID_MIN_SIDE {
        return None;
    }
    // Just above the face, so the depth test does not hide the lines in it.
    let top = (z + 0.002) as f32;
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let lines = |half: f64| (-(half.floor() as i64)..=(half.floor() as i64)).map(|k| k as f32);
    for k in lines(x) {
        positions.push([k, -y as f32, top]);
        positions.push([k, y as f32, top]);
    }
    for k in lines(y) {
        positions.push([-x as f32, k, top]);
        positions.push([x as f32, k, top]);
    }
    Some(
        Mesh::new(PrimitiveTopology::LineList, RenderAssetUsages::default())
            .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions),
    )
}

/// The grid's material: thin dark lines, unlit, half transparent.
pub fn grid_material() -> StandardMaterial {
    StandardMaterial {
        base_color: Color::srgba(0.05, 0.12, 0.05, 0.45),
        unlit: true,
        alpha_mode: AlphaMode::Blend,
        ..default()
    }
}

/// Spawns `shape`'s grid (if it gets one) as a child of `geom`, shown as [`ShowGrid`] says.
pub fn spawn_grid(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    geom: Entity,
    shape: &Shape,
    show: ShowGrid,
) {
    let Some(mesh) = ground_grid(shape) else {
        return;
    };
    let grid = commands
        .spawn((
            Name::new("ground grid"),
            GroundGrid,
            Mesh3d(meshes.add(mesh)),
            MeshMaterial3d(materials.add(grid_material())),
            Transform::default(),
            if show.0 {
                Visibility::Inherited
            } else {
                Visibility::Hidden
            },
        ))
        .id();
    commands.entity(geom).add_child(grid);
}

/// Shows or hides every grid when [`ShowGrid`] changes.
pub fn apply_show_grid(show: Res<ShowGrid>, mut grids: Query<&mut Visibility, With<GroundGrid>>) {
    if !show.is_changed() {
        return;
    }
    for mut v in &mut grids {
        *v = if show.0 {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_floor_gets_a_line_every_metre_and_a_step_none() {
        let floor = ground_grid(&Shape::Box {
            extents: [5.0, 2.5, 0.05],
        })
        .expect("a grid");
        // x: -5..=5 (11 lines), y: -2..=2 (5 lines), two points each.
        assert_eq!(floor.count_vertices(), 2 * (11 + 5));
        assert!(
            ground_grid(&Shape::Box {
                extents: [0.3, 2.0, 0.1]
            })
            .is_none()
        );
        assert!(ground_grid(&Shape::Sphere { radius: 3.0 }).is_none());
    }
}
