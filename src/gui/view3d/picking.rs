//! The pointer's gestures on a 3D scene, recorded once for every window: Bevy's mesh picking
//! observers turn presses, clicks and drags into [`Gesture`] messages naming the scene
//! object hit — the entity carrying the window's marker component (a body visual, an
//! editor item), found up the parent chain — and each window reads them, in order, in a
//! system of its own that decides what they do. Clicks and grabs are recorded only while
//! the pointer belongs to the scene ([`crate::gui::pointer`]).

use std::marker::PhantomData;

use bevy::prelude::*;

use crate::gui::pointer::PointerRouting;

/// A primary-button drag that started on the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grab {
    /// The scene object under the pointer (None: nothing of the window's).
    pub target: Option<Entity>,
    /// The camera whose view the drag started in.
    pub camera: Entity,
    /// The pointer's window position (logical pixels).
    pub at: Vec2,
    /// Shift was held.
    pub shift: bool,
}

/// What the pointer did to the scene, in the order it happened.
#[derive(Message, Debug, Clone, Copy, PartialEq)]
pub enum Gesture {
    /// A button was pressed (what follows is a click unless the pointer is dragged).
    Press,
    /// A primary click on the scene, on `target` (None: empty space).
    Click {
        /// The scene object clicked.
        target: Option<Entity>,
    },
    /// A drag started: with a [`Grab`] when it is a primary drag on the scene.
    DragStart(Option<Grab>),
    /// The drag moved to `at`, by `delta` pixels.
    Drag {
        /// The pointer's window position.
        at: Vec2,
        /// Pixels moved since the last drag message.
        delta: Vec2,
    },
    /// The drag ended.
    DragEnd,
}

/// The scene object (the entity with marker `M`) that `e` belongs to: itself or an ancestor.
pub fn owner_of<M: Component>(
    e: Entity,
    parents: &Query<&ChildOf>,
    marked: &Query<(), With<M>>,
) -> Option<Entity> {
    let mut cur = e;
    for _ in 0..8 {
        if marked.contains(cur) {
            return Some(cur);
        }
        cur = parents.get(cur).ok()?.parent();
    }
    None
}

fn on_press(mut ev: On<Pointer<Press>>, mut out: MessageWriter<Gesture>) {
    ev.propagate(false);
    out.write(Gesture::Press);
}

fn on_click<M: Component>(
    mut ev: On<Pointer<Click>>,
    parents: Query<&ChildOf>,
    marked: Query<(), With<M>>,
    routing: Res<PointerRouting>,
    mut out: MessageWriter<Gesture>,
) {
    ev.propagate(false);
    if ev.button == PointerButton::Primary && routing.scene_gets_pointer() {
        let target = owner_of(ev.original_event_target(), &parents, &marked);
        out.write(Gesture::Click { target });
    }
}

fn on_drag_start<M: Component>(
    mut ev: On<Pointer<DragStart>>,
    parents: Query<&ChildOf>,
    marked: Query<(), With<M>>,
    keys: Res<ButtonInput<KeyCode>>,
    routing: Res<PointerRouting>,
    mut out: MessageWriter<Gesture>,
) {
    ev.propagate(false);
    let grab =
        (ev.button == PointerButton::Primary && routing.scene_gets_pointer()).then(|| Grab {
            target: owner_of(ev.original_event_target(), &parents, &marked),
            camera: ev.hit.camera,
            at: ev.pointer_location.position,
            shift: keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]),
        });
    out.write(Gesture::DragStart(grab));
}

fn on_drag(mut ev: On<Pointer<Drag>>, mut out: MessageWriter<Gesture>) {
    ev.propagate(false);
    out.write(Gesture::Drag {
        at: ev.pointer_location.position,
        delta: ev.delta,
    });
}

fn on_drag_end(mut ev: On<Pointer<DragEnd>>, mut out: MessageWriter<Gesture>) {
    ev.propagate(false);
    out.write(Gesture::DragEnd);
}

/// Records the pointer's [`Gesture`]s on scene objects marked with `M`.
pub struct GesturesPlugin<M: Component>(PhantomData<M>);

impl<M: Component> Default for GesturesPlugin<M> {
    fn default() -> Self {
        GesturesPlugin(PhantomData)
    }
}

impl<M: Component> Plugin for GesturesPlugin<M> {
    fn build(&self, app: &mut App) {
        app.add_message::<Gesture>()
            .add_observer(on_press)
            .add_observer(on_click::<M>)
            .add_observer(on_drag_start::<M>)
            .add_observer(on_drag)
            .add_observer(on_drag_end);
    }
}
