//! The configuration window's cameras: the perspective view (orbit / pan / zoom), and in
//! the environment editor the synchronised orthographic top and side views (the thesis's
//! two projections) beside it, all centred on the selection; egui draws through a camera
//! of its own on top. Viewports follow the area the egui panels leave free.

use bevy::camera::visibility::RenderLayers;
use bevy::camera::{ClearColorConfig, Viewport};
use bevy::prelude::*;
use bevy_egui::PrimaryEguiContext;

use crate::compose::env_edit::Selected;
use crate::gui::setup::state::EditorDrag;
use crate::gui::setup::state::SetupState;
use crate::gui::view3d::orbit::{OrbitCamera, PointerMotion, to_bevy};

/// An orthographic view of the editor.
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrthoView {
    /// Looking down: x to the right, y up the screen.
    Top,
    /// Looking along -x: y to the right, z up.
    Side,
}

/// The render layer only egui's camera sees (nothing is on it: it draws just the UI).
const UI_LAYER: usize = 31;

/// Spawns the perspective, top, side and UI cameras.
pub fn spawn_cameras(mut commands: Commands) {
    let orbit = OrbitCamera {
        focus: Vec3::new(0.0, 0.05, -0.3),
        distance: 1.6,
        follow: false,
        ..OrbitCamera::default()
    };
    commands.spawn((
        Name::new("perspective view"),
        Camera3d::default(),
        Camera {
            order: 0,
            ..default()
        },
        orbit.transform(),
        orbit,
    ));
    for (view, order) in [(OrthoView::Top, 1), (OrthoView::Side, 2)] {
        commands.spawn((
            Name::new(format!("{view:?} view")),
            Camera3d::default(),
            Camera {
                order,
                is_active: false,
                // The perspective camera clears the whole window first.
                clear_color: ClearColorConfig::None,
                ..default()
            },
            Projection::Orthographic(OrthographicProjection {
                scaling_mode: bevy::camera::ScalingMode::FixedVertical {
                    viewport_height: 2.0,
                },
                ..OrthographicProjection::default_3d()
            }),
            view,
        ));
    }
    commands.spawn((
        Name::new("ui camera"),
        Camera3d::default(),
        Camera {
            order: 10,
            clear_color: ClearColorConfig::None,
            ..default()
        },
        RenderLayers::layer(UI_LAYER),
        PrimaryEguiContext,
    ));
}

/// The window position of the point the views centre on (selection, else the robot).
fn focus(state: &SetupState) -> Vec3 {
    let env = state.env();
    let p = env
        .selected
        .and_then(|s| env.pose(s))
        .or_else(|| env.pose(Selected::Robot))
        .map_or([0.0; 3], |p| p.translation);
    to_bevy(p)
}

/// Places the views in the area the panels leave: the perspective view on the left two
/// thirds, top and side views stacked on the right third while editing an environment.
pub fn layout_views(
    state: Res<SetupState>,
    window: Single<&Window>,
    mut persp: Query<&mut Camera, (Without<OrthoView>, With<OrbitCamera>)>,
    mut ortho: Query<
        (&mut Camera, &OrthoView, &mut Transform, &mut Projection),
        Without<OrbitCamera>,
    >,
) {
    let Some(area) = state.central else {
        return;
    };
    let scale = window.scale_factor();
    let to_vp = |min: Vec2, size: Vec2| {
        let pos = (min * scale).max(Vec2::ZERO).as_uvec2();
        let size = (size * scale).max(Vec2::splat(8.0)).as_uvec2();
        let max = window.physical_size();
        let size = size.min(max.saturating_sub(pos).max(UVec2::splat(1)));
        Some(Viewport {
            physical_position: pos,
            physical_size: size,
            ..default()
        })
    };
    let (min, size) = (
        Vec2::new(area.min.x, area.min.y),
        Vec2::new(area.width(), area.height()),
    );
    let editing = state.editing_env();
    let persp_w = if editing { size.x * 2.0 / 3.0 } else { size.x };
    for mut c in &mut persp {
        c.viewport = to_vp(min, Vec2::new(persp_w, size.y));
    }
    let centre = focus(&state);
    let side_w = size.x - persp_w;
    for (mut c, view, mut t, mut proj) in &mut ortho {
        c.is_active = editing;
        if !editing {
            continue;
        }
        let (y0, h) = match view {
            OrthoView::Top => (min.y, size.y / 2.0),
            OrthoView::Side => (min.y + size.y / 2.0, size.y / 2.0),
        };
        c.viewport = to_vp(Vec2::new(min.x + persp_w, y0), Vec2::new(side_w, h));
        *t = match view {
            OrthoView::Top => {
                Transform::from_translation(centre + Vec3::Y * 40.0).looking_at(centre, Vec3::NEG_Z)
            }
            OrthoView::Side => {
                Transform::from_translation(centre + Vec3::X * 40.0).looking_at(centre, Vec3::Y)
            }
        };
        if let Projection::Orthographic(o) = proj.as_mut() {
            o.scaling_mode = bevy::camera::ScalingMode::FixedVertical {
                viewport_height: state.ortho_height.max(0.05),
            };
            o.far = 100.0;
        }
    }
}

/// Mouse orbit (left drag on empty space), pan (right / middle drag), zoom (wheel) of the
/// perspective view ([`PointerMotion`]); the wheel over a side or top view zooms both.
pub fn orbit_camera(
    motion: Res<PointerMotion>,
    buttons: Res<ButtonInput<MouseButton>>,
    routing: Res<crate::gui::pointer::PointerRouting>,
    drag: Res<EditorDrag>,
    mut state: ResMut<SetupState>,
    mut cameras: Query<(&Camera, &mut OrbitCamera, &mut Transform)>,
) {
    if !routing.scene_gets_pointer() {
        return;
    }
    let cursor = motion.cursor;
    for (camera, mut orbit, mut t) in &mut cameras {
        let inside = cursor.is_some_and(|c| {
            camera
                .logical_viewport_rect()
                .is_some_and(|r| r.contains(c))
        });
        if inside && !drag.dragging {
            orbit.steer(&t, &buttons, motion.delta, motion.wheel);
        } else if !inside && cursor.is_some() && motion.wheel != 0.0 && state.editing_env() {
            state.ortho_height =
                (state.ortho_height * (1.0 - 0.1 * motion.wheel)).clamp(0.05, 40.0);
        }
        *t = orbit.transform();
    }
}

/// The perspective, top and side cameras: spawned at start, steered by the mouse, laid out
/// in the space the panels leave.
pub struct SetupCamerasPlugin;

impl Plugin for SetupCamerasPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, spawn_cameras).add_systems(
            Update,
            (orbit_camera, layout_views)
                .chain()
                .in_set(crate::gui::setup::schedule::SetupSystems::Views),
        );
    }
}
