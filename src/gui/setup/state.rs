//! The configuration window's state: which tool is open (wizard, expert dialog,
//! environment editor), their models from [`crate::compose`], the object library, the
//! last message, and what the 3D views need (the central area left by the panels, a drop
//! from the library waiting for its ray cast).

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use bevy_egui::egui;

use crate::compose::env_edit::EnvEditor;
use crate::compose::expert::Composition;
use crate::compose::library::{LibraryItem, library};
use crate::compose::wizard::{Page, Wizard};
use crate::config::simulation::SimulationProperties;

/// The tool on screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tool {
    /// The beginner wizard.
    Wizard,
    /// The expert composition.
    Expert,
    /// The environment editor.
    Editor,
}

/// The expert dialog's state.
#[derive(Debug, Clone)]
pub struct ExpertState {
    /// The composition edited.
    pub composition: Composition,
    /// Where "Save" writes the simulation file.
    pub path: String,
    /// The last check's summary or error, as the dialog shows it.
    pub check: Option<Result<String, String>>,
}

/// A message for the status line.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Information.
    Info(String),
    /// An error.
    Error(String),
}

/// Everything the configuration window shows and edits.
#[derive(Resource)]
pub struct SetupState {
    /// The tool shown.
    pub tool: Tool,
    /// The module library's revision the wizard's registry was made at.
    pub module_revision: u64,
    /// The wizard's model.
    pub wizard: Wizard,
    /// The standalone environment editor (the wizard's environment page has its own).
    pub editor: EnvEditor,
    /// Path typed for the editor's Load / Save.
    pub editor_path: String,
    /// The expert composition.
    pub expert: ExpertState,
    /// The last message.
    pub status: Option<Status>,
    /// The editor's object library.
    pub library: Vec<LibraryItem>,
    /// Library item chosen for "Add".
    pub library_choice: usize,
    /// Typed angle for "Set heading".
    pub typed_yaw: f64,
    /// Height of the side and top views in metres (their zoom).
    pub ortho_height: f32,
    /// The window area left to the 3D views (logical pixels), from the last UI pass.
    pub central: Option<egui::Rect>,
    /// A library item dropped at a window position, waiting for its ray cast.
    pub drop: Option<(LibraryItem, Vec2)>,
    /// The last preview run: the simulation file, the distance crawled and the path.
    pub preview:
        Option<Result<crate::gui::setup::preview::PreviewRun, crate::gui::error::GuiError>>,
    /// Simulation files opened in a control window.
    pub opened: Vec<PathBuf>,
}

impl SetupState {
    /// Offers the modules compiled in the module library since the last call (the
    /// library's `revision` counts its loads).
    pub fn sync_modules(&mut self, modules: &crate::gui::module_editor::ModuleEditor) {
        if modules.revision != self.module_revision {
            self.module_revision = modules.revision;
            self.wizard.registry = modules.host.registry();
        }
    }

    /// The window's state: the wizard on its first page (offering the standard modules and
    /// the loaded plugins), an empty scene, the expert composition of the demo.
    pub fn new(
        configs: &Path,
        out: &Path,
        stamp: &str,
        registry: crate::control::ModuleRegistry,
    ) -> Self {
        let mut wizard = Wizard::new(configs, out, stamp);
        wizard.registry = registry;
        let editor_file = out.join(format!("scene_{stamp}.env.xml"));
        let assets = configs.parent().unwrap_or(Path::new(".")).join("assets");
        let expert_path = out.join(format!("composed_{stamp}.simulation.xml"));
        SetupState {
            tool: Tool::Wizard,
            module_revision: 0,
            editor: EnvEditor::new(&editor_file),
            editor_path: editor_file.display().to_string(),
            expert: ExpertState {
                composition: Composition {
                    robot: configs.join("robots/snake5p.robot.xml"),
                    actuation: configs.join("actuation/snake5p_sine40.actuation.xml"),
                    environment: Some(configs.join("environments/flat.env.xml")),
                    optimizer: None,
                    properties: SimulationProperties::default(),
                    description: String::new(),
                },
                path: expert_path.display().to_string(),
                check: None,
            },
            wizard,
            status: None,
            library: library(&assets),
            library_choice: 0,
            typed_yaw: 0.0,
            ortho_height: 2.0,
            central: None,
            drop: None,
            preview: None,
            opened: Vec::new(),
        }
    }

    /// Whether the wizard is on a page after the terrain's, which show the robot in it.
    pub fn wizard_shows_terrain(&self) -> bool {
        self.tool == Tool::Wizard
            && matches!(
                self.wizard.page,
                Page::Simulation | Page::Optimization | Page::Summary
            )
    }

    /// Whether the environment editor is on screen (its 3D views, library, side panel).
    pub fn editing_env(&self) -> bool {
        self.tool == Tool::Editor
            || (self.tool == Tool::Wizard && self.wizard.page == Page::Environment)
    }

    /// The environment being edited.
    pub fn env(&self) -> &EnvEditor {
        if self.tool == Tool::Editor {
            &self.editor
        } else {
            &self.wizard.env
        }
    }

    /// The scene being edited (the editor's or the wizard's), to change.
    pub fn env_mut(&mut self) -> &mut EnvEditor {
        if self.tool == Tool::Editor {
            &mut self.editor
        } else {
            &mut self.wizard.env
        }
    }

    /// Records the outcome of an action for the status line.
    pub fn report<T, E: std::fmt::Display>(
        &mut self,
        r: Result<T, E>,
        ok: impl FnOnce(&T) -> String,
    ) -> Option<T> {
        match r {
            Ok(v) => {
                self.status = Some(Status::Info(ok(&v)));
                Some(v)
            }
            Err(e) => {
                self.status = Some(Status::Error(e.to_string()));
                None
            }
        }
    }
}

/// The drag in progress.
#[derive(Resource, Debug, Default)]
pub struct EditorDrag {
    /// Whether a drag is in progress.
    pub dragging: bool,
    /// The camera the drag started in.
    pub(super) camera: Option<Entity>,
    /// Item position minus the pointer's point on the drag plane at the start (m, z up).
    pub(super) offset: [f64; 3],
}
