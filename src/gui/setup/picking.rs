//! Mouse editing of the environment (Bevy's mesh picking): a click selects the object or
//! robot under the pointer, a left drag moves it — over the ground in the perspective and
//! top views (it rests on what lies below), in the y-z plane in the side view — as one
//! undo step; a library item dropped on a view lands where the pointer's ray meets the
//! ground. Rays come from the camera whose viewport holds the pointer.

use bevy::prelude::*;

use crate::compose::env_edit::Selected;
use crate::gui::pointer::PointerRouting;
use crate::gui::setup::cameras::OrthoView;
use crate::gui::setup::scene::ItemVisual;
use crate::gui::setup::state::{EditorDrag, SetupState};

/// The scene item an entity belongs to (itself or an ancestor).
fn item_of(e: Entity, parents: &Query<&ChildOf>, items: &Query<&ItemVisual>) -> Option<Selected> {
    let mut cur = e;
    for _ in 0..8 {
        if let Ok(i) = items.get(cur) {
            return Some(i.0);
        }
        cur = parents.get(cur).ok()?.parent();
    }
    None
}

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

/// Click: select what is under the pointer (empty space clears the selection).
pub fn on_click(
    mut click: On<Pointer<Click>>,
    parents: Query<&ChildOf>,
    items: Query<&ItemVisual>,
    routing: Res<PointerRouting>,
    mut state: ResMut<SetupState>,
) {
    click.propagate(false);
    // A click on a panel (the Selection panel's fields) is the panel's, not "empty space".
    if click.button != PointerButton::Primary
        || !state.editing_env()
        || !routing.scene_gets_pointer()
    {
        return;
    }
    let sel = item_of(click.original_event_target(), &parents, &items);
    let _ = state.env_mut().select(sel);
}

/// Drag start on an item: select it, start one undo step, remember the grip offset.
pub fn on_drag_start(
    mut ev: On<Pointer<DragStart>>,
    parents: Query<&ChildOf>,
    items: Query<&ItemVisual>,
    cameras: CameraQuery,
    routing: Res<PointerRouting>,
    mut state: ResMut<SetupState>,
    mut drag: ResMut<EditorDrag>,
) {
    ev.propagate(false);
    if ev.button != PointerButton::Primary || !state.editing_env() || !routing.scene_gets_pointer()
    {
        return;
    }
    let Some(sel) = item_of(ev.original_event_target(), &parents, &items) else {
        return;
    };
    let env = state.env_mut();
    if env.select(Some(sel)).is_err() {
        return;
    }
    let Some(at) = env.pose(sel).map(|p| p.translation) else {
        return;
    };
    let cam = ev.hit.camera;
    let Ok((_, c, gt, view)) = cameras.get(cam) else {
        return;
    };
    let Some(p) = plane_point((c, gt, view), ev.pointer_location.position, at[0]) else {
        return;
    };
    env.begin_drag();
    drag.dragging = true;
    drag.camera = Some(cam);
    drag.offset = [at[0] - p[0], at[1] - p[1], at[2] - p[2]];
}

/// Drag: move the selection to the pointer.
pub fn on_drag(
    mut ev: On<Pointer<Drag>>,
    cameras: CameraQuery,
    mut state: ResMut<SetupState>,
    drag: Res<EditorDrag>,
) {
    ev.propagate(false);
    let (true, Some(cam)) = (drag.dragging, drag.camera) else {
        return;
    };
    let Ok((_, c, gt, view)) = cameras.get(cam) else {
        return;
    };
    let env = state.env_mut();
    let Some(at) = env
        .selected
        .and_then(|s| env.pose(s))
        .map(|p| p.translation)
    else {
        return;
    };
    let Some(p) = plane_point((c, gt, view), ev.pointer_location.position, at[0]) else {
        return;
    };
    let o = drag.offset;
    let r = match view {
        Some(OrthoView::Side) => env.move_to([at[0], p[1] + o[1], (p[2] + o[2]).max(-10.0)]),
        _ => env.drag_to(p[0] + o[0], p[1] + o[1]),
    };
    if let Err(e) = r {
        state.status = Some(crate::gui::setup::state::Status::Error(e.to_string()));
    }
}

/// Drag end: the undo step is complete.
pub fn on_drag_end(
    mut ev: On<Pointer<DragEnd>>,
    mut state: ResMut<SetupState>,
    mut drag: ResMut<EditorDrag>,
) {
    ev.propagate(false);
    if drag.dragging {
        state.env_mut().end_drag();
        // The status line follows the object (it said where it was placed).
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

/// Mouse editing of the environment: the picking observers and library items dropped on a
/// view.
pub struct SetupPickingPlugin;

impl Plugin for SetupPickingPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<EditorDrag>()
            .add_observer(on_click)
            .add_observer(on_drag_start)
            .add_observer(on_drag)
            .add_observer(on_drag_end)
            .add_systems(
                Update,
                apply_drop.in_set(crate::gui::setup::schedule::SetupSystems::Drop),
            );
    }
}
