//! Who gets the pointer: the egui panels and windows, or the 3D scene behind them (both
//! windows: the control window's viewer, the configuration window's 3D views).
//!
//! egui's own "wants the pointer" is last frame's answer: at a few frames per second a
//! pointer that moves onto a panel and clicks within one frame was not over the panel last
//! frame, and the click went to the scene (it selected the floor). Here the pointer's
//! position *now* is tested against last frame's layout — the viewer's rectangle (what the
//! panels left free) and the floating windows' areas — and a press that began on the UI
//! keeps the scene out until every button is up (a slider dragged past its panel does not
//! drag the floor). While the scene does not get the pointer, picking hits the egui context
//! instead of the bodies behind ([`block_picking`]), and the camera does not orbit, pan or
//! zoom.

use bevy::picking::backend::{HitData, PointerHits};
use bevy::picking::pointer::{PointerId, PointerLocation};
use bevy::prelude::*;
use bevy::window::PrimaryWindow;
use bevy_egui::{EguiContexts, PrimaryEguiContext, egui};

/// Where the pointer is and whether the scene may have it.
#[derive(Resource, Debug, Default)]
pub struct PointerRouting {
    /// The viewer's rectangle last frame (egui points): the room the panels left.
    viewer: Option<egui::Rect>,
    /// The pointer is over a panel or a window now.
    pub over_ui: bool,
    /// The buttons held now were pressed over a panel or a window.
    press_on_ui: bool,
}

impl PointerRouting {
    /// Records the viewer's rectangle (call after the panels are laid out).
    pub fn set_viewer(&mut self, rect: egui::Rect) {
        self.viewer = Some(rect);
    }

    /// Whether the 3D scene gets the pointer (picking, dragging, orbit, zoom).
    pub fn scene_gets_pointer(&self) -> bool {
        !self.over_ui && !self.press_on_ui
    }

    /// Whether `pos` (egui points) is over a panel or a floating window of `ctx`.
    fn over(&self, ctx: &egui::Context, pos: egui::Pos2) -> bool {
        let outside_viewer = self.viewer.is_some_and(|r| !r.contains(pos));
        let on_window = ctx
            .layer_id_at(pos)
            .is_some_and(|l| l.order != egui::Order::Background);
        outside_viewer || on_window
    }
}

/// Updates [`PointerRouting`] from the pointer's position now (before picking runs).
pub fn route_pointer(
    windows: Query<&Window, With<PrimaryWindow>>,
    mut contexts: EguiContexts,
    buttons: Res<ButtonInput<MouseButton>>,
    mut routing: ResMut<PointerRouting>,
) {
    let Ok(ctx) = contexts.ctx_mut() else {
        return;
    };
    let over = windows
        .iter()
        .next()
        .and_then(|w| w.cursor_position().map(|c| (c, w.scale_factor())))
        .is_some_and(|(c, scale)| {
            let points = c * scale / ctx.pixels_per_point().max(0.01);
            routing.over(ctx, egui::pos2(points.x, points.y))
        });
    routing.over_ui = over;
    if buttons.get_just_pressed().next().is_some() {
        routing.press_on_ui = over || ctx.egui_is_using_pointer();
    } else if buttons.get_pressed().next().is_none() {
        routing.press_on_ui = false;
    }
}

/// While the scene does not get the pointer, every pointer hits the egui context first, so
/// that no body behind a panel is hovered, clicked or dragged.
pub fn block_picking(
    pointers: Query<(&PointerId, &PointerLocation)>,
    contexts: Query<(Entity, &Camera), With<PrimaryEguiContext>>,
    routing: Res<PointerRouting>,
    mut output: MessageWriter<PointerHits>,
) {
    if routing.scene_gets_pointer() {
        return;
    }
    let Some((entity, camera)) = contexts.iter().next() else {
        return;
    };
    for (pointer, location) in &pointers {
        if location.location.is_some() {
            output.write(PointerHits::new(
                *pointer,
                vec![(entity, HitData::new(entity, 0.0, None, None))],
                camera.order as f32 + 0.7,
            ));
        }
    }
}

/// The pointer routing's resource and systems, in `PreUpdate` between input and picking.
pub struct PointerRoutingPlugin;

impl Plugin for PointerRoutingPlugin {
    fn build(&self, app: &mut App) {
        use bevy::picking::PickingSystems;
        app.init_resource::<PointerRouting>().add_systems(
            PreUpdate,
            (route_pointer, block_picking)
                .chain()
                .in_set(PickingSystems::Backend),
        );
    }
}
