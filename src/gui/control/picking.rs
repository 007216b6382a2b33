//! Selecting and moving bodies in the viewer (Bevy's mesh picking): a click selects the
//! body under the pointer, a left drag moves a robot (any of its links) or a dynamic object
//! over the ground plane — the static scenery only with Shift held, so that a left drag on
//! the ground orbits the camera — and the "Selected body" window shows and sets its
//! position. Nothing here reacts while the pointer belongs to the panels
//! ([`crate::gui::pointer`]). Picking observers only record what the pointer did; a system
//! applies it to the simulator through [`crate::sim::Simulator::translate_bodies`].

use bevy::prelude::*;
use bevy_egui::egui;

use crate::gui::control::camera::OrbitCamera;
use crate::gui::control::scene::BodyVisual;
use crate::gui::control::session::SimSession;
use crate::gui::pointer::PointerRouting;

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

/// The body visual an entity belongs to (itself or an ancestor).
fn body_of(e: Entity, parents: &Query<&ChildOf>, visuals: &Query<&BodyVisual>) -> Option<Entity> {
    let mut cur = e;
    for _ in 0..8 {
        if visuals.contains(cur) {
            return Some(cur);
        }
        cur = parents.get(cur).ok()?.parent();
    }
    None
}

/// Click: select the body under the pointer (or clear the selection on empty space).
pub fn on_click(
    mut click: On<Pointer<Click>>,
    parents: Query<&ChildOf>,
    visuals: Query<&BodyVisual>,
    routing: Res<PointerRouting>,
    mut sel: ResMut<Selection>,
) {
    click.propagate(false);
    if click.button == PointerButton::Primary && routing.scene_gets_pointer() && !sel.dragged {
        sel.body = body_of(click.original_event_target(), &parents, &visuals);
    }
}

/// A press: what follows is a click unless the pointer is dragged.
pub fn on_press(mut ev: On<Pointer<Press>>, mut sel: ResMut<Selection>) {
    ev.propagate(false);
    sel.dragged = false;
}

/// Drag start on a movable body (or any body with Shift held): select it and take the
/// left button from the camera.
pub fn on_drag_start(
    mut ev: On<Pointer<DragStart>>,
    parents: Query<&ChildOf>,
    visuals: Query<&BodyVisual>,
    keys: Res<ButtonInput<KeyCode>>,
    routing: Res<PointerRouting>,
    mut sel: ResMut<Selection>,
) {
    ev.propagate(false);
    sel.dragged = true;
    if ev.button != PointerButton::Primary || !routing.scene_gets_pointer() {
        return;
    }
    let shift = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
    if let Some(b) = body_of(ev.original_event_target(), &parents, &visuals)
        && (shift || visuals.get(b).is_ok_and(|v| v.movable))
    {
        sel.body = Some(b);
        sel.dragging = true;
    }
}

/// Drag: collect the pointer's motion.
pub fn on_drag(mut ev: On<Pointer<Drag>>, mut sel: ResMut<Selection>) {
    ev.propagate(false);
    if sel.dragging {
        sel.drag_pixels += ev.delta;
    }
}

/// Drag end.
pub fn on_drag_end(mut ev: On<Pointer<DragEnd>>, mut sel: ResMut<Selection>) {
    ev.propagate(false);
    sel.dragging = false;
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

/// Selecting and dragging bodies with the pointer: the selection, the picking observers,
/// the drags applied each frame (after the shortcuts).
pub struct PickingPlugin;

impl Plugin for PickingPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Selection>()
            .add_observer(on_click)
            .add_observer(on_drag_start)
            .add_observer(on_drag)
            .add_observer(on_drag_end)
            .add_systems(
                Update,
                apply_moves.in_set(crate::gui::control::schedule::GuiSystems::Pointer),
            );
    }
}
