//! The physics debug view: every collider's shape outline (boxes, spheres; meshes by their
//! bounding box) and the contact points with their normals, drawn with gizmos straight from
//! the physics engine's view (either engine), so it shows what the physics sees rather than
//! the meshes.

use bevy::prelude::*;

use crate::gui::control::session::SimSession;
use crate::sim::engine::ShapeOutline;

/// Whether the debug view is on.
#[derive(Resource, Debug, Default, Clone, Copy)]
pub struct DebugView(pub bool);

/// Configuration frame (z up) to Bevy's (y up).
fn frame() -> Quat {
    Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)
}

fn point(p: [f64; 3]) -> Vec3 {
    frame() * Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

/// Draws collider outlines and contacts.
pub fn draw_debug(view: Res<DebugView>, session: NonSend<SimSession>, mut gizmos: Gizmos) {
    if !view.0 {
        return;
    }
    let engine = session.simulator.engine();
    for c in engine.colliders() {
        let [w, x, y, z] = c.pose.rotation;
        let rotation = frame() * Quat::from_xyzw(x as f32, y as f32, z as f32, w as f32);
        let centre = point(c.pose.translation);
        let colour = if c.dynamic {
            Color::srgb(1.0, 1.0, 0.2)
        } else {
            Color::srgb(0.2, 1.0, 1.0)
        };
        match c.shape {
            ShapeOutline::Box(he) => {
                gizmos.cube(
                    Transform::from_translation(centre)
                        .with_rotation(rotation)
                        .with_scale(Vec3::new(
                            2.0 * he[0] as f32,
                            2.0 * he[1] as f32,
                            2.0 * he[2] as f32,
                        )),
                    colour,
                );
            }
            ShapeOutline::Sphere(r) => {
                gizmos.sphere(Isometry3d::new(centre, rotation), r as f32, colour);
            }
            ShapeOutline::Bounds(lo, hi) => {
                let (lo, hi) = (point(lo), point(hi));
                gizmos.cube(
                    Transform::from_translation((lo + hi) / 2.0).with_scale((hi - lo).abs()),
                    colour,
                );
            }
        }
    }
    for c in engine.contacts() {
        let (at, n) = (point(c.point), point(c.normal));
        let colour = if c.touching {
            Color::srgb(1.0, 0.1, 0.1)
        } else {
            Color::srgb(1.0, 0.6, 0.1)
        };
        gizmos.sphere(Isometry3d::from_translation(at), 0.002, colour);
        gizmos.line(at, at + n * 0.02, colour);
    }
}

/// The physics debug view: collider outlines and contacts, drawn after the camera moved.
pub struct DebugViewPlugin;

impl Plugin for DebugViewPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<DebugView>().add_systems(
            Update,
            draw_debug.in_set(crate::gui::control::schedule::GuiSystems::Debug),
        );
    }
}
