//! The physics debug view: every collider's shape outline (boxes, spheres; meshes by their
//! bounding box) and the contact points with their normals, drawn with gizmos straight from
//! the rapier world, so it shows what the physics sees rather than the meshes.

use bevy::prelude::*;
use rapier3d::prelude as rp;

use crate::gui::control::session::SimSession;

/// Whether the debug view is on.
#[derive(Resource, Debug, Default, Clone, Copy)]
pub struct DebugView(pub bool);

/// Configuration frame (z up) to Bevy's (y up).
fn frame() -> Quat {
    Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)
}

fn point(p: rp::Vector) -> Vec3 {
    frame() * Vec3::new(p.x, p.y, p.z)
}

/// Draws collider outlines and contacts.
pub fn draw_debug(view: Res<DebugView>, session: NonSend<SimSession>, mut gizmos: Gizmos) {
    if !view.0 {
        return;
    }
    let w = session.simulator.physics();
    for (_, c) in w.colliders.iter() {
        let pose = c.position();
        let r = pose.rotation;
        let rotation = frame() * Quat::from_xyzw(r.x, r.y, r.z, r.w);
        let centre = point(pose.translation);
        let colour = if c
            .parent()
            .and_then(|b| w.bodies.get(b))
            .is_some_and(|b| b.is_dynamic())
        {
            Color::srgb(1.0, 1.0, 0.2)
        } else {
            Color::srgb(0.2, 1.0, 1.0)
        };
        if let Some(b) = c.shape().as_cuboid() {
            let he = b.half_extents;
            gizmos.cube(
                Transform::from_translation(centre)
                    .with_rotation(rotation)
                    .with_scale(Vec3::new(2.0 * he.x, 2.0 * he.y, 2.0 * he.z)),
                colour,
            );
        } else if let Some(s) = c.shape().as_ball() {
            gizmos.sphere(Isometry3d::new(centre, rotation), s.radius, colour);
        } else {
            let aabb = c.compute_aabb();
            let (lo, hi) = (point(aabb.mins), point(aabb.maxs));
            gizmos.cube(
                Transform::from_translation((lo + hi) / 2.0).with_scale((hi - lo).abs()),
                colour,
            );
        }
    }
    for pair in w.narrow_phase.contact_pairs() {
        let Some(c1) = w.colliders.get(pair.collider1) else {
            continue;
        };
        for m in pair.manifolds() {
            let n = point(m.data.normal);
            for p in &m.points {
                let at = point(c1.position().transform_point(p.local_p1));
                let colour = if p.dist <= 0.0 {
                    Color::srgb(1.0, 0.1, 0.1)
                } else {
                    Color::srgb(1.0, 0.6, 0.1)
                };
                gizmos.sphere(Isometry3d::from_translation(at), 0.002, colour);
                gizmos.line(at, at + n * 0.02, colour);
            }
        }
    }
}
