//! The configuration window (thesis 4.4): `proleg wizard` — the beginner wizard, the
//! expert dialog and the 3D environment editor — on the Bevy-free models of
//! [`crate::compose`]. Everything it writes is the ordinary XML of configs/.
//!
//! - [`state`]: what the window shows and edits; [`preview`]: robot preview, preview runs
//! - [`wizard`] (a file per page), [`expert_view`], [`properties_view`]: the egui views
//! - [`editor`]: the environment editor (its panels, keys, mouse and drops)
//! - [`scene`]: the 3D scene; [`cameras`]: perspective, top and side views
//! - [`script`], [`script_run`]: scripted driving for tests and screenshots
//! - [`codesign_view`]: the optimization page's MAP-Elites and co-design settings
//! - [`keys`]: the editor's keyboard shortcuts; [`schedule`]: the per-frame work's order

pub mod cameras;
pub mod codesign_view;
pub mod editor;
pub mod expert_view;
pub mod keys;
pub mod preview;
pub mod properties_view;
pub mod scene;
pub mod schedule;
#[cfg(feature = "scripts")]
pub mod script;
#[cfg(feature = "scripts")]
pub mod script_run;
pub mod state;
pub mod wizard;

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiGlobalSettings, EguiPrimaryContextPass, egui};

use crate::compose::wizard::Page;
use crate::gui::setup::scene::SceneCache;
#[cfg(feature = "scripts")]
use crate::gui::setup::script::SetupScript;
use crate::gui::setup::state::{SetupState, Status, Tool};

/// How `proleg wizard` starts.
#[derive(Debug, Clone)]
pub struct SetupOptions {
    /// The configuration folder (parts, robots, ...).
    pub configs: PathBuf,
    /// Where new files go.
    pub out: PathBuf,
    /// Open this environment file in the editor.
    pub env: Option<PathBuf>,
    /// Open this simulation in the expert dialog.
    pub expert: Option<PathBuf>,
    /// A script driving the window (tests, screenshots).
    pub script: Option<PathBuf>,
}

pub use crate::gui::setup::schedule::SetupSystems;

/// Opens the configuration window.
pub fn run(
    opts: &SetupOptions,
    plugins: crate::plugin_host::PluginHost,
) -> Result<(), crate::gui::error::GuiError> {
    #[cfg(feature = "scripts")]
    let script = match &opts.script {
        Some(p) => SetupScript(Some(script::load(p)?)),
        None => SetupScript::default(),
    };
    #[cfg(not(feature = "scripts"))]
    if let Some(p) = &opts.script {
        return Err(crate::gui::error::GuiError::NoScripts(p.clone()));
    }
    let mut state = SetupState::new(
        &opts.configs,
        &opts.out,
        &crate::compose::paths::timestamp_now(),
        plugins.registry(),
    );
    if let Some(env) = &opts.env {
        state.editor = crate::compose::env_edit::EnvEditor::load(env)?;
        state.editor_path = env.display().to_string();
        state.tool = Tool::Editor;
    }
    if let Some(sim) = &opts.expert {
        state.expert.composition = crate::compose::expert::Composition::open(sim)?;
        state.expert.path = sim.display().to_string();
        state.tool = Tool::Expert;
    }
    let mut app = App::new();
    crate::gui::desktop::add_window_plugins(&mut app, "proleg — new / edit configuration".into());
    #[cfg(feature = "scripts")]
    app.insert_resource(script)
        .add_systems(Update, script_run::run_script.in_set(SetupSystems::Script));
    app.insert_resource(state)
        .insert_resource(crate::gui::module_editor::ModuleEditor::new(plugins))
        .add_plugins(SetupWindowPlugin);
    match app.run() {
        AppExit::Success => Ok(()),
        AppExit::Error(code) => Err(crate::gui::error::GuiError::Closed {
            window: "configuration window",
            code,
        }),
    }
}

/// The configuration window's systems (everything but the window and the state).
pub struct SetupWindowPlugin;

impl Plugin for SetupWindowPlugin {
    fn build(&self, app: &mut App) {
        // One plugin per part, each with its state and systems in the sets of `schedule`;
        // the layout of the egui views (tools, wizard pages, expert dialog, editor) is
        // `draw_ui`'s.
        app.add_plugins((
            schedule::SetupSchedulePlugin,
            crate::gui::pointer::PointerRoutingPlugin,
            crate::gui::view3d::PointerMotionPlugin,
            keys::SetupKeysPlugin,
            editor::EditorPlugin,
            scene::SetupScenePlugin,
            cameras::SetupCamerasPlugin,
        ))
        .init_resource::<crate::gui::module_editor::ModuleEditor>()
        .add_systems(Startup, manual_egui_context)
        .add_systems(EguiPrimaryContextPass, draw_ui)
        .add_systems(PostUpdate, busy);
    }
}

/// Whether the window must keep drawing: only while a script plays (everything else
/// happens in answer to input).
fn busy(
    script: Res<crate::gui::desktop::ScriptPending>,
    busy: Option<ResMut<crate::gui::desktop::Busy>>,
) {
    if let Some(mut busy) = busy {
        busy.set_if_neq(crate::gui::desktop::Busy(script.0));
    }
}

/// egui draws through its own camera (see [`cameras`]).
fn manual_egui_context(mut settings: ResMut<EguiGlobalSettings>) {
    settings.auto_create_primary_context = false;
}

/// Opens a simulation in a control window (a new proleg process, reaped when it closes).
pub fn open_control_window(state: &mut SetupState, sim: &Path) {
    match crate::gui::desktop::spawn_window("control window", &["gui"], sim) {
        Ok(_) => {
            state.opened.push(sim.to_path_buf());
            state.status = Some(Status::Info(format!(
                "opened {} in a control window",
                sim.display()
            )));
        }
        Err(e) => state.status = Some(Status::Error(e.to_string())),
    }
}

/// The panels of the current tool; records the area left to the 3D views and turns a
/// library item released over it into a drop.
pub(crate) fn draw_ui(
    mut contexts: EguiContexts,
    mut state: ResMut<SetupState>,
    mut modules: ResMut<crate::gui::module_editor::ModuleEditor>,
    cache: Res<SceneCache>,
    mut routing: ResMut<crate::gui::pointer::PointerRouting>,
) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    let state = state.as_mut();
    crate::gui::module_editor::view::show(&ctx, &mut modules);
    state.sync_modules(&modules);
    let mut root = egui::Ui::new(
        ctx.clone(),
        "configuration window".into(),
        egui::UiBuilder::new()
            .layer_id(egui::LayerId::background())
            .max_rect(ctx.viewport_rect()),
    );
    egui::Panel::top("tools").show(&mut root, |ui| {
        ui.horizontal(|ui| {
            ui.selectable_value(&mut state.tool, Tool::Wizard, "Wizard (beginner)");
            ui.selectable_value(&mut state.tool, Tool::Expert, "Expert composition");
            ui.selectable_value(&mut state.tool, Tool::Editor, "Environment editor");
            ui.separator();
            ui.toggle_value(&mut modules.open, "Module library")
                .on_hover_text("declare, write and compile your own actuation modules");
        });
    });
    egui::Panel::bottom("status").show(&mut root, |ui| match &state.status {
        Some(Status::Info(s)) => {
            ui.label(s);
        }
        Some(Status::Error(s)) => {
            ui.colored_label(egui::Color32::RED, s);
        }
        None => {
            ui.label("Ready.");
        }
    });
    let editing = state.editing_env();
    if editing {
        egui::Panel::left("library")
            .resizable(true)
            .default_size(250.0)
            .show(&mut root, |ui| {
                editor::view::show_library(ui, state, &cache.overlaps)
            });
    }
    right_panel(&mut root, state, editing);
    let central = root.available_rect_before_wrap();
    state.central = Some(central);
    // What the panels left holds the 3D views: the pointer there belongs to the scene.
    routing.set_viewer(central);
    if editing {
        editor::view::label_views(&ctx, state);
    } else if state.tool == Tool::Wizard
        && matches!(state.wizard.page, Page::Robot | Page::Behaviour)
        && let Some(Err(e)) = &cache.robot
    {
        egui::Area::new(egui::Id::new("robot preview error"))
            .fixed_pos(central.min + egui::vec2(10.0, 10.0))
            .show(&ctx, |ui| {
                ui.colored_label(egui::Color32::RED, format!("robot preview: {e}"));
            });
    }
    Ok(())
}

/// The tool's panel on the right: the wizard's pages (with the selection on the
/// environment page), the expert composition, or the editor's selection.
fn right_panel(root: &mut egui::Ui, state: &mut SetupState, editing: bool) {
    match state.tool {
        Tool::Wizard => {
            // Its own panel (and remembered width) on the environment page, where the
            // views need the room: one shared panel changed width a few frames after the
            // page did, moving the views under the pointer.
            egui::Panel::right(if editing { "wizard editing" } else { "wizard" })
                .resizable(true)
                .default_size(if editing { 330.0 } else { 470.0 })
                .show(root, |ui| {
                    if editing {
                        egui::Panel::bottom("wizard nav").show(ui, |ui| wizard::show(ui, state));
                        editor::view::show_selection(ui, state);
                    } else {
                        wizard::show(ui, state);
                    }
                });
        }
        Tool::Expert => {
            egui::Panel::right("expert")
                .resizable(true)
                .default_size(620.0)
                .show(root, |ui| expert_view::show(ui, state));
        }
        Tool::Editor => {
            egui::Panel::right("selection")
                .resizable(true)
                .default_size(330.0)
                .show(root, |ui| editor::view::show_selection(ui, state));
        }
    }
}
