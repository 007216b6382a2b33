//! Drawing configuration geometry in Bevy, for every 3D view (control window, configuration
//! window, videos): a geometry's mesh and material, a pose as a transform, the lights.

use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;

use crate::config::body::{Geom, Shape};
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
        Shape::Trimesh { scale, .. } => {
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
            mesh
        }
    })
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
