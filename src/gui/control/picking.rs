//! Selecting and moving bodies in the viewer (Bevy's mesh picking): a click selects the
//! body under the pointer, a left drag moves a robot (any of its links) or a dynamic object
//! over the ground plane — the static scenery only with Shift held, so that a left drag on
//! the ground orbits the camera — and the "Selected body" window shows and sets its
//! position. Nothing here reacts while the pointer belongs to the panels
//! ([`crate::gui::pointer`]). The shared gestures ([`crate::gui::view3d::picking`]) say what
//! the pointer did; systems here apply it to the simulator through
//! [`crate::sim::Simulator::translate_bodies`].

use bevy::prelude::*;
use bevy_egui::egui;

use crate::gui::control::scene::BodyVisual;
use crate::gui::control::session::SimSession;
use crate::gui::view3d::orbit::OrbitCamera;
use crate::gui::view3d::picking::{Gesture, GesturesPlugin, Grab};

/// The selected body and the drag in progress.
#[derive(Resource, Debug, Default)]
pub struct Selection {
    /// The selected body visual.
    pub body: Option<Entity>,
    /// A left drag on a body is going on (the camera does not orbit then).
    pub dragging: bool,
    /// The pointer was dragged since its last press: its release is no click.
    dragged: bool,
    /// Screen pixels dragged since the last frame.
    drag_pixels: Vec2,
    /// A position typed in the window (z up), to move the selection to.
    typed: Option<[f64; 3]>,
    /// A move asked for by a script (m, z up).
    nudge: [f64; 3],
}

impl Selection {
    /// Moves the selection by `delta` metres at the next frame.
    pub fn nudge(&mut self, delta: [f64; 3]) {
        for (n, d) in self.nudge.iter_mut().zip(delta) {
            *n += d;
        }
    }
}

/// Reads the pointer's gestures in order: a click selects the body under the pointer (or
/// clears the selection on empty space), unless the pointer was dragged since its press; a
/// primary drag on a movable body (or any body with Shift held) selects it and takes the
/// left button from the camera; the drag's motion is collected for [`apply_moves`].
pub fn read_gestures(
    mut gestures: MessageReader<Gesture>,
    visuals: Query<&BodyVisual>,
    mut sel: ResMut<Selection>,
) {
    for g in gestures.read() {
        match *g {
            Gesture::Press => sel.dragged = false,
            Gesture::Click { target } if !sel.dragged => sel.body = target,
            Gesture::Click { .. } => {}
            Gesture::DragStart(grab) => {
                sel.dragged = true;
                if let Some(Grab {
                    target: Some(b),
                    shift,
                    ..
                }) = grab
                    && (shift || visuals.get(b).is_ok_and(|v| v.movable))
                {
                    sel.body = Some(b);
                    sel.dragging = true;
                }
            }
            Gesture::Drag { delta, .. } if sel.dragging => sel.drag_pixels += delta,
            Gesture::Drag { .. } => {}
            Gesture::DragEnd => sel.dragging = false,
        }
    }
}

/// The bodies that move with body visual `v`: the whole robot for a link, else the body.
fn group(session: &SimSession, v: &BodyVisual) -> Vec<crate::sim::engine::BodyId> {
    match v.link {
        Some(_) => session.simulator.robot_bodies(0).unwrap_or_default(),
        None => vec![v.body],
    }
}

/// Applies the drag (over the ground plane, scaled by the camera distance) and typed
/// positions to the simulator.
pub fn apply_moves(
    mut sel: ResMut<Selection>,
    mut session: NonSendMut<SimSession>,
    visuals: Query<&BodyVisual>,
    cameras: Query<(&Transform, &OrbitCamera)>,
) {
    let Some(v) = sel.body.and_then(|e| visuals.get(e).ok()) else {
        sel.drag_pixels = Vec2::ZERO;
        sel.typed = None;
        sel.nudge = [0.0; 3];
        return;
    };
    let mut delta = std::mem::take(&mut sel.nudge);
    let px = std::mem::take(&mut sel.drag_pixels);
    if px != Vec2::ZERO
        && let Some((t, orbit)) = cameras.iter().next()
    {
        let right = t.right().as_vec3();
        let forward = Vec3::new(t.forward().x, 0.0, t.forward().z).normalize_or_zero();
        let d = (right * px.x - forward * px.y) * orbit.distance * 0.0015;
        // Bevy (x, y, z) -> configuration (x, -z, y); the drag stays on the ground plane.
        delta[0] += d.x as f64;
        delta[1] -= d.z as f64;
    }
    if let Some(target) = sel.typed.take()
        && let Some(now) = body_position(&session, v)
    {
        delta = [target[0] - now[0], target[1] - now[1], target[2] - now[2]];
    }
    if delta != [0.0; 3] {
        let bodies = group(&session, v);
        session.simulator.translate_bodies(&bodies, delta);
    }
}

/// A body's position (m, z up).
fn body_position(session: &SimSession, v: &BodyVisual) -> Option<[f64; 3]> {
    session.simulator.body_position(v.body)
}

/// The "Selected body" window.
pub fn show(
    ctx: &egui::Context,
    session: &SimSession,
    sel: &mut Selection,
    visuals: &Query<(&BodyVisual, &Name)>,
) {
    let Some((v, name)) = sel.body.and_then(|e| visuals.get(e).ok()) else {
        return;
    };
    let Some(mut pos) = body_position(session, v) else {
        return;
    };
    let mut keep = true;
    egui::Window::new("Selected body")
        .anchor(egui::Align2::LEFT_BOTTOM, [8.0, -290.0])
        .resizable(false)
        .show(ctx, |ui| {
            ui.label(name.as_str());
            if v.link.is_some() {
                ui.label("(dragging or typing moves the whole robot)");
            }
            let mut changed = false;
            ui.horizontal(|ui| {
                for (axis, p) in ["x", "y", "z"].iter().zip(pos.iter_mut()) {
                    ui.label(*axis);
                    changed |= ui
                        .add(
                            egui::DragValue::new(p)
                                .speed(0.005)
                                .max_decimals(3)
                                .suffix(" m"),
                        )
                        .changed();
                }
            });
            if changed {
                sel.typed = Some(pos);
            }
            keep = !ui.button("Deselect").clicked();
        });
    if !keep {
        sel.body = None;
    }
}

/// Selecting and dragging bodies with the pointer: the selection, the shared gestures
/// ([`crate::gui::view3d::picking`]) read and the drags applied each frame (after the
/// shortcuts).
pub struct PickingPlugin;

impl Plugin for PickingPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Selection>()
            .add_plugins(GesturesPlugin::<BodyVisual>::default())
            .add_systems(
                Update,
                (read_gestures, apply_moves)
                    .chain()
                    .in_set(crate::gui::control::schedule::GuiSystems::Pointer),
            );
    }
}
