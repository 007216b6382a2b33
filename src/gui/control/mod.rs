//! The control window (thesis 4.5): a 3D viewer of the running simulation with a toolbar,
//! live plots and the control-algorithm properties, built with Bevy's renderer and
//! bevy_egui. It drives the same headless [`crate::sim::Simulator`] the CLI and the
//! optimizers use; nothing here simulates.
//!
//! - [`session`]: the simulation shown and its pacing (start / pause / restart, speed)
//! - [`scene`]: meshes, lights and pads following the physics bodies
//! - [`camera`]: orbit / pan / zoom / follow; [`picking`]: select and drag bodies
//! - [`debug_view`]: collider outlines and contacts from the physics world
//! - [`toolbar`], [`params`], [`assign_view`], [`robot_view`] (the real robot),
//!   [`plots`], [`overlay`], [`inspect`], [`optimizer_view`],
//!   [`remote_view`]: the egui views
//! - [`script`], [`script_run`]: scripted driving for tests and screenshots
//! - [`keys`]: keyboard shortcuts; [`recorder`]: the Record button
//! - [`calibration_view`]: the real-robot tab's servo calibration; [`results_view`]: the
//!   stored results in the optimization view
//! - [`widgets`]: small egui helpers; [`schedule`]: the order of the per-frame work

pub mod assign_view;
pub mod calibration_view;
pub mod camera;
pub mod debug_view;
pub mod inspect;
pub mod keys;
pub mod optimizer_view;
pub mod overlay;
pub mod params;
pub mod picking;
pub mod plots;
pub mod recorder;
pub mod remote_view;
pub mod results_view;
pub mod robot_view;
pub mod scene;
pub mod schedule;
#[cfg(feature = "scripts")]
pub mod script;
#[cfg(feature = "scripts")]
pub mod script_run;
pub mod session;
pub mod toolbar;
pub mod widgets;

use std::path::Path;

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};

use crate::gui::control::assign_view::AssignState;
use crate::gui::control::debug_view::DebugView;
use crate::gui::control::inspect::InspectState;
use crate::gui::control::optimizer_view::OptimizerView;
use crate::gui::control::overlay::RobotOverlay;
use crate::gui::control::params::ParamsState;
use crate::gui::control::picking::Selection;
use crate::gui::control::plots::PlotsState;
use crate::gui::control::recorder::Recorder;
use crate::gui::control::remote_view::RemoteView;
use crate::gui::control::robot_view::RobotView;
use crate::gui::control::scene::BodyVisual;
#[cfg(feature = "scripts")]
use crate::gui::control::script::ScriptRunner;
use crate::gui::control::session::SimSession;
use crate::gui::control::toolbar::ToolbarState;
use crate::gui::error::GuiError;
use crate::gui::module_editor::ModuleEditor;
use crate::gui::view3d::orbit::OrbitCamera;
use crate::optimize::replay::Replay;
use crate::remote::gamepad::GamepadRemote;

/// Which of the docked views are open.
#[derive(Resource, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Panels {
    /// Whether the properties panel is shown.
    pub params: bool,
    /// Whether the live plots panel is shown.
    pub plots: bool,
}

/// The state of the egui views (what scripts and the UI pass change).
#[derive(SystemParam)]
pub struct Views<'w> {
    /// The toolbar.
    pub toolbar: ResMut<'w, ToolbarState>,
    /// The control-algorithm properties.
    pub params: ResMut<'w, ParamsState>,
    /// The live plots.
    pub plots: ResMut<'w, PlotsState>,
    /// Which side panels are shown.
    pub panels: ResMut<'w, Panels>,
    /// The data file inspection.
    pub inspect: ResMut<'w, InspectState>,
    /// The optimization view.
    pub optimizer: ResMut<'w, OptimizerView>,
    /// The physics debug view.
    pub debug: ResMut<'w, DebugView>,
    /// The selected body.
    pub selection: ResMut<'w, Selection>,
    /// The remote-control dialog.
    pub remote: ResMut<'w, RemoteView>,
    /// The gamepad bindings applied.
    pub gamepad: ResMut<'w, GamepadRemote>,
    /// The module library.
    pub modules: ResMut<'w, ModuleEditor>,
    /// Assigning a module to joints.
    pub assign: ResMut<'w, AssignState>,
    /// The real-robot tab.
    pub robot: ResMut<'w, RobotView>,
    /// The Record button's recorder.
    pub recorder: ResMut<'w, Recorder>,
    /// The camera's orbit.
    pub camera: Res<'w, camera::CameraReadout>,
    /// Whether a script still plays.
    pub script: ResMut<'w, crate::gui::desktop::ScriptPending>,
    /// Whether the ground's metre grid is shown.
    pub grid: ResMut<'w, crate::gui::view3d::meshes::ShowGrid>,
}

pub use crate::gui::control::schedule::GuiSystems;

/// Opens the control window on `config`, or on the stored evaluation `replay` (`proleg gui
/// --replay`); with `script`, runs it (see [`script`]); with `remote`, binds the gamepad as
/// that `*.remote.xml` says (else the default binding).
pub fn run(
    config: &Path,
    engine: Option<crate::config::simulation::EngineKind>,
    replay: Option<Replay>,
    script: Option<&Path>,
    remote: Option<&Path>,
    plugins: crate::plugin_host::PluginHost,
) -> Result<(), GuiError> {
    let registry = plugins.registry();
    let session = match replay {
        Some(r) => SimSession::open_replay(r, &registry)?,
        None => open_or_fall_back(config, engine, &registry)?,
    };
    // A replay shows the configuration it was scored with (the one `Load` would reload).
    let typed = match &session.replay {
        Some(_) => session.path.clone(),
        None => config.to_path_buf(),
    };
    let mut remote_view = RemoteView::default();
    if let Some(r) = remote {
        remote_view.load(r)?;
    }
    #[cfg(feature = "scripts")]
    let runner = match script {
        Some(p) => ScriptRunner::new(script::load(p)?),
        None => ScriptRunner::default(),
    };
    #[cfg(not(feature = "scripts"))]
    if let Some(p) = script {
        return Err(GuiError::NoScripts(p.to_path_buf()));
    }
    let title = window_title(&session);
    // A real-robot configuration opens with the real-robot tab.
    let mut robot_view = RobotView::default();
    robot_view.open =
        session.sim.files.simulation.properties.mode == crate::config::simulation::Mode::RealRobot;
    let mut app = App::new();
    crate::gui::desktop::add_window_plugins(&mut app, title);
    #[cfg(feature = "scripts")]
    app.insert_resource(runner).add_systems(
        Update,
        script_run::run_script
            .after(sync_modules)
            .in_set(GuiSystems::Script),
    );
    app.insert_resource(ToolbarState::new(&typed))
        .insert_non_send(session)
        .insert_resource(remote_view)
        .insert_resource(robot_view)
        .insert_resource(ModuleEditor::new(plugins))
        .add_plugins(ControlWindowPlugin);
    match app.run() {
        AppExit::Success => Ok(()),
        AppExit::Error(code) => Err(GuiError::Closed {
            window: "control window",
            code,
        }),
    }
}

/// Offers the session the modules its plugin host loaded since the last call (the module
/// editor's build or rescan).
fn sync_modules(
    modules: Res<ModuleEditor>,
    mut session: NonSendMut<SimSession>,
    mut seen: Local<Option<u64>>,
) {
    if *seen != Some(modules.revision) {
        *seen = Some(modules.revision);
        session.sync_modules(modules.host.registry());
    }
}

/// The demo the window shows when the file asked for cannot be loaded.
const FALLBACK: &str = "configs/demo.simulation.xml";

/// The session of `config`; when it cannot be loaded, the window opens anyway — on the
/// demo, with the file's located error shown and its name kept in the Configuration field
/// to fix and load again, as the toolbar's Load does. Only when the demo cannot be loaded
/// either does the window not open (with `config`'s error).
fn open_or_fall_back(
    config: &Path,
    engine: Option<crate::config::simulation::EngineKind>,
    registry: &crate::control::ModuleRegistry,
) -> Result<SimSession, GuiError> {
    let error = match SimSession::open(config, engine, registry) {
        Ok(s) => return Ok(s),
        Err(e) => e,
    };
    match SimSession::open(Path::new(FALLBACK), engine, registry) {
        Ok(mut s) => {
            s.error = Some(format!("{error}\n(showing {FALLBACK} instead)"));
            Ok(s)
        }
        Err(_) => Err(error),
    }
}

/// The control window's systems and state (everything but the session and the window).
pub struct ControlWindowPlugin;

impl Plugin for ControlWindowPlugin {
    fn build(&self, app: &mut App) {
        // One plugin per view, each with its state and systems in the sets of
        // `schedule`; the layout of the egui views is `draw_ui`'s.
        app.add_plugins((
            schedule::SchedulePlugin,
            crate::gui::pointer::PointerRoutingPlugin,
            crate::gui::view3d::PointerMotionPlugin,
            keys::KeysPlugin,
            picking::PickingPlugin,
            camera::CameraPlugin,
            scene::ScenePlugin,
            overlay::OverlayPlugin,
            debug_view::DebugViewPlugin,
            recorder::RecorderPlugin,
        ))
        .add_plugins((
            plots::PlotsPlugin,
            params::ParamsPlugin,
            inspect::InspectPlugin,
            optimizer_view::OptimizerViewPlugin,
            remote_view::RemoteViewPlugin,
            robot_view::RobotViewPlugin,
        ))
        .init_resource::<ModuleEditor>()
        .insert_resource(Panels {
            params: true,
            plots: true,
        })
        .add_systems(Update, sync_modules.in_set(GuiSystems::Script))
        .add_systems(Update, simulate.in_set(GuiSystems::Simulate))
        .add_systems(EguiPrimaryContextPass, draw_ui)
        .add_systems(PostUpdate, (busy, title));
    }
}

/// The window's title names the configuration (or replay) shown, after every load.
fn title(session: NonSend<SimSession>, mut windows: Query<&mut Window>) {
    let want = window_title(&session);
    for mut w in &mut windows {
        if w.title != want {
            w.title = want.clone();
        }
    }
}

/// "proleg — FILE (ENGINE)", or "proleg — replay of LABEL".
fn window_title(session: &SimSession) -> String {
    match &session.replay {
        Some(r) => format!("proleg — replay of {}", r.label),
        None => format!(
            "proleg — {} ({})",
            session.path.display(),
            session.simulator.engine_kind()
        ),
    }
}

/// Whether the window must keep drawing: a simulation, a script, an optimization, a
/// recording, a real robot or a gamepad (polled each frame) is at work.
fn busy(
    session: NonSend<SimSession>,
    views: Views,
    gamepads: Query<(), With<Gamepad>>,
    busy: Option<ResMut<crate::gui::desktop::Busy>>,
) {
    let Some(mut busy) = busy else {
        return;
    };
    let now = session.running
        || views.script.0
        || views.optimizer.running()
        || views.recorder.recording()
        || views.robot.connected()
        || views.robot.calibration.running()
        || !gamepads.is_empty();
    busy.set_if_neq(crate::gui::desktop::Busy(now));
}

/// Runs this frame's simulation steps and updates the speed figures, both from the wall
/// time the frame took (`Time<Real>`: the virtual clock caps a frame at 0.25 s).
fn simulate(
    time: Res<Time<Real>>,
    mut session: NonSendMut<SimSession>,
    mut toolbar: ResMut<ToolbarState>,
    mut overlay: ResMut<RobotOverlay>,
) {
    session.advance(time.delta_secs_f64());
    let now = time.elapsed_secs_f64();
    toolbar.meter.frame(now, session.sim_time());
    overlay.observe(&session);
}

/// The egui views: toolbar on top, properties on the right, plots below, robot overlay.
fn draw_ui(
    mut contexts: EguiContexts,
    mut session: NonSendMut<SimSession>,
    mut views: Views,
    overlay: Res<RobotOverlay>,
    mut cameras: Query<&mut OrbitCamera>,
    visuals: Query<(&BodyVisual, &Name)>,
    mut routing: ResMut<crate::gui::pointer::PointerRouting>,
) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    let mut root = egui::Ui::new(
        ctx.clone(),
        "control window".into(),
        egui::UiBuilder::new()
            .layer_id(egui::LayerId::background())
            .max_rect(ctx.viewport_rect()),
    );
    let bar = egui::Panel::top("toolbar")
        .show(&mut root, |ui| show_toolbar(ui, &mut session, &mut views))
        .response
        .rect;
    show_docked(&mut root, &mut session, &mut views);
    // What the panels left is the viewer: the pointer there belongs to the scene.
    let viewer = root.available_rect_before_wrap();
    views.toolbar.layout.insert("toolbar", bar);
    views.toolbar.layout.insert("viewer", viewer);
    routing.set_viewer(viewer);
    toolbar::notices(&ctx, viewer, &mut session);
    let mut follow = cameras.iter().next().is_some_and(|c| c.follow);
    overlay::show(&ctx, &overlay, &views.toolbar, &mut follow, viewer);
    picking::show(&ctx, &session, &mut views.selection, &visuals);
    show_floating(&ctx, &mut session, &mut views);
    for mut c in &mut cameras {
        c.follow = follow;
    }
    Ok(())
}

/// The toolbar's run controls, then the switches of every view and the Record button.
fn show_toolbar(ui: &mut egui::Ui, session: &mut SimSession, views: &mut Views) {
    toolbar::show(ui, session, &mut views.toolbar);
    // Wrapped: the recording's path after the Record button is not cut off.
    ui.horizontal_wrapped(|ui| {
        ui.toggle_value(&mut views.panels.params, "Control algorithm properties");
        ui.toggle_value(&mut views.panels.plots, "Live plots");
        ui.toggle_value(&mut views.inspect.open, "Data file inspection");
        if session.sim.optimizer.is_some() {
            ui.toggle_value(&mut views.optimizer.open, "Optimization");
        }
        ui.toggle_value(&mut views.debug.0, "Physics debug view");
        // Changed only when clicked: the grid's visibility is applied on a change.
        let mut grid = views.grid.0;
        if ui.toggle_value(&mut grid, "Ground grid").changed() {
            views.grid.0 = grid;
        }
        ui.toggle_value(&mut views.remote.open, "Remote control");
        ui.toggle_value(&mut views.modules.open, "Module library");
        ui.toggle_value(&mut views.robot.open, "Real robot");
        ui.separator();
        recorder::button(ui, &mut views.recorder, &session.path);
    });
}

/// The docked views: live plots below, the optimization on the left, the control
/// algorithms' properties on the right (an optimization not shown is still polled).
fn show_docked(root: &mut egui::Ui, session: &mut SimSession, views: &mut Views) {
    if views.panels.plots {
        let now = session.sim_time();
        views.plots.refresh(session.simulator.data(0).ok(), now);
        let rect = egui::Panel::bottom("plots")
            .resizable(true)
            .default_size(270.0)
            .show(root, |ui| plots::show(ui, session, &mut views.plots))
            .response
            .rect;
        views.toolbar.layout.insert("plots", rect);
    }
    if views.optimizer.open && session.sim.optimizer.is_some() {
        optimizer_view::show(root, session, &mut views.optimizer);
    } else {
        views.optimizer.poll();
    }
    if views.panels.params {
        let rect = egui::Panel::right("params")
            .resizable(true)
            .default_size(330.0)
            .show(root, |ui| {
                assign_view::show(ui, session, &mut views.assign);
                ui.separator();
                params::show(ui, session, &mut views.params);
            })
            .response
            .rect;
        views.toolbar.layout.insert("params", rect);
    }
}

/// The floating windows: data file inspection, remote control, module library, real robot.
fn show_floating(ctx: &egui::Context, session: &mut SimSession, views: &mut Views) {
    if views.inspect.open {
        inspect::show(ctx, &mut views.inspect);
    }
    if views.remote.open {
        remote_view::show(ctx, &mut views.remote, &mut views.gamepad, session);
    }
    crate::gui::module_editor::view::show(ctx, &mut views.modules);
    if views.robot.open {
        robot_view::show(ctx, &mut views.robot, session);
    }
}
