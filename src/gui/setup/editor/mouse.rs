//! Mouse editing of the environment, read from the shared gestures
//! ([`crate::gui::view3d::picking`]): a click selects the object or robot under the
//! pointer, a left drag moves it — over the ground in the perspective and
//! top views (it rests on what lies below), in the y-z plane in the side view — as one
//! undo step; a library item dropped on a view lands where the pointer's ray meets the
//! ground. Rays come from the camera whose viewport holds the pointer.

use bevy::prelude::*;

use crate::compose::env_edit::Selected;
use crate::gui::setup::cameras::OrthoView;
use crate::gui::setup::scene::ItemVisual;
use crate::gui::setup::state::{EditorDrag, SetupState};
use crate::gui::view3d::picking::{Gesture, Grab};

/// A Bevy world point in configuration coordinates (z up).
fn to_config(p: Vec3) -> [f64; 3] {
    [p.x as f64, -p.z as f64, p.y as f64]
}

/// Where the pointer's ray from `camera` meets the drag plane: the ground (z = 0) from
/// the perspective and top views, the vertical plane x = `x` from the side view.
fn plane_point(
    camera: (&Camera, &GlobalTransform, Option<&OrthoView>),
    window_pos: Vec2,
    x: f64,
) -> Option<[f64; 3]> {
    let (cam, gt, view) = camera;
    let ray = cam.viewport_to_world(gt, window_pos).ok()?;
    let (origin, normal) = match view {
        Some(OrthoView::Side) => (Vec3::new(x as f32, 0.0, 0.0), Vec3::X),
        _ => (Vec3::ZERO, Vec3::Y),
    };
    let d = ray.intersect_plane(origin, InfinitePlane3d::new(normal))?;
    Some(to_config(ray.get_point(d)))
}

type CameraQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static Camera,
        &'static GlobalTransform,
        Option<&'static OrthoView>,
    ),
>;

/// The active 3D camera whose viewport holds `pos` (the UI camera has no viewport).
pub fn camera_at(cameras: &CameraQuery, pos: Vec2) -> Option<Entity> {
    cameras
        .iter()
        .filter(|(_, c, _, _)| c.is_active && c.viewport.is_some())
        .find(|(_, c, _, _)| c.logical_viewport_rect().is_some_and(|r| r.contains(pos)))
        .map(|(e, ..)| e)
}

/// Reads the pointer's gestures in order while an environment is edited: a click selects
/// what is under it (empty space clears the selection), a drag moves the selection.
pub fn read_gestures(
    mut gestures: MessageReader<Gesture>,
    items: Query<&ItemVisual>,
    cameras: CameraQuery,
    mut state: ResMut<SetupState>,
    mut drag: ResMut<EditorDrag>,
) {
    for g in gestures.read() {
        match *g {
            Gesture::Click { target } if state.editing_env() => {
                let sel = target.and_then(|e| items.get(e).ok()).map(|i| i.0);
                if let Err(e) = state.env_mut().select(sel) {
                    state.status = Some(crate::gui::setup::state::Status::Error(e.to_string()));
                }
            }
            Gesture::DragStart(Some(grab)) if state.editing_env() => {
                start_drag(&grab, &items, &cameras, &mut state, &mut drag);
            }
            Gesture::Drag { at, .. } => drag_to(at, &cameras, &mut state, &drag),
            Gesture::DragEnd => end_drag(&mut state, &mut drag),
            _ => {}
        }
    }
}

/// A drag starts on an item: select it, start one undo step, remember the grip offset.
fn start_drag(
    grab: &Grab,
    items: &Query<&ItemVisual>,
    cameras: &CameraQuery,
    state: &mut SetupState,
    drag: &mut EditorDrag,
) {
    let Some(sel) = grab.target.and_then(|e| items.get(e).ok()).map(|i| i.0) else {
        return;
    };
    let env = state.env_mut();
    if env.select(Some(sel)).is_err() {
        return;
    }
    let Some(at) = env.pose(sel).map(|p| p.translation) else {
        return;
    };
    let Ok((_, c, gt, view)) = cameras.get(grab.camera) else {
        return;
    };
    let Some(p) = plane_point((c, gt, view), grab.at, at[0]) else {
        return;
    };
    env.begin_drag();
    drag.dragging = true;
    drag.camera = Some(grab.camera);
    drag.offset = [at[0] - p[0], at[1] - p[1], at[2] - p[2]];
}

/// The drag moves the selection to the pointer at `at`.
fn drag_to(at: Vec2, cameras: &CameraQuery, state: &mut SetupState, drag: &EditorDrag) {
    let (true, Some(cam)) = (drag.dragging, drag.camera) else {
        return;
    };
    let Ok((_, c, gt, view)) = cameras.get(cam) else {
        return;
    };
    let env = state.env_mut();
    let Some(now) = env
        .selected
        .and_then(|s| env.pose(s))
        .map(|p| p.translation)
    else {
        return;
    };
    let Some(p) = plane_point((c, gt, view), at, now[0]) else {
        return;
    };
    let o = drag.offset;
    let r = match view {
        Some(OrthoView::Side) => env.move_to([now[0], p[1] + o[1], (p[2] + o[2]).max(-10.0)]),
        _ => env.drag_to(p[0] + o[0], p[1] + o[1]),
    };
    if let Err(e) = r {
        state.status = Some(crate::gui::setup::state::Status::Error(e.to_string()));
    }
}

/// The drag ends: the undo step is complete, the status line says where the object went.
fn end_drag(state: &mut SetupState, drag: &mut EditorDrag) {
    if drag.dragging {
        state.env_mut().end_drag();
        let moved = state.env().selected.and_then(|sel| {
            let at = state.env().pose(sel)?.translation;
            let name = match sel {
                Selected::Robot => "robot start pose".to_string(),
                Selected::Object(i) => {
                    crate::compose::env_edit::object_name(state.env().objects.get(i)?, i)
                }
            };
            Some(format!(
                "{name} moved to {:.2} {:.2} {:.3} m",
                at[0], at[1], at[2]
            ))
        });
        if let Some(m) = moved {
            state.status = Some(crate::gui::setup::state::Status::Info(m));
        }
    }
    drag.dragging = false;
    drag.camera = None;
}

/// Places a dropped library item where the pointer's ray meets the ground.
pub fn apply_drop(mut state: ResMut<SetupState>, cameras: CameraQuery) {
    let Some((item, pos)) = state.drop.take() else {
        return;
    };
    let hit = camera_at(&cameras, pos)
        .and_then(|e| cameras.get(e).ok())
        .and_then(|(_, c, gt, view)| plane_point((c, gt, view), pos, 0.0));
    match hit {
        Some(p) => {
            let i = state.env_mut().add(&item, p[0], p[1]);
            let at = state
                .env()
                .pose(Selected::Object(i))
                .map_or([0.0; 3], |p| p.translation);
            state.status = Some(crate::gui::setup::state::Status::Info(format!(
                "{} placed at {:.2} {:.2} {:.3} m",
                item.label(),
                at[0],
                at[1],
                at[2]
            )));
        }
        None => {
            state.status = Some(crate::gui::setup::state::Status::Error(
                "drop the object on one of the 3D views".into(),
            ));
        }
    }
}
