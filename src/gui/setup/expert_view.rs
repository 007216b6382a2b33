//! The expert dialog (thesis 4.4.2): one screen composing a simulation from the robot,
//! actuation, environment and optimizer files found in the configuration and user
//! folders, with the simulation properties; check, save, open in the control window, or
//! edit the environment in the editor.

use std::path::{Path, PathBuf};

use bevy_egui::egui;

use crate::compose::behaviour::BehaviourSpec;
use crate::compose::env_edit::EnvEditor;
use crate::compose::expert::{Composition, Part, catalog};
use crate::compose::wizard::{Page, RobotChoice};
use crate::config::actuation::parse_actuation_file;
use crate::gui::error::GuiError;
use crate::gui::setup::state::{SetupState, Tool};

fn short(p: &Path) -> String {
    let s = p.display().to_string();
    match s.find("configs/") {
        Some(i) => s[i..].to_string(),
        None => s,
    }
}

/// One file choice; `optional` adds "none".
fn choose(
    ui: &mut egui::Ui,
    part: Part,
    current: &mut Option<PathBuf>,
    files: &[PathBuf],
    optional: bool,
) {
    egui::ComboBox::from_label(part.label())
        .width(420.0)
        .selected_text(current.as_deref().map_or("none".into(), short))
        .show_ui(ui, |ui| {
            if optional {
                ui.selectable_value(current, None, "none");
            }
            for f in files {
                ui.selectable_value(current, Some(f.clone()), short(f));
            }
        });
}

/// Hands the composition to the wizard (existing robot, its actuation as groups, the
/// environment, the properties) and opens it on the behaviour page.
pub fn edit_in_wizard(state: &mut SetupState) {
    let c = state.expert.composition.clone();
    let r = (|| -> Result<(), GuiError> {
        let text = std::fs::read_to_string(&c.actuation).map_err(GuiError::io(&c.actuation))?;
        let a = parse_actuation_file(&c.actuation.display().to_string(), &text)?;
        let env = match &c.environment {
            Some(p) => EnvEditor::load(p)?,
            None => EnvEditor::new(state.wizard.files().environment),
        };
        let w = &mut state.wizard;
        w.robot = RobotChoice::Existing(c.robot.clone());
        w.joint_count()?;
        w.behaviour = BehaviourSpec::from_actuation_file(&a);
        w.env = env;
        w.props = c.properties.clone();
        w.description = c.description.clone();
        w.page = Page::Behaviour;
        w.env.file = w.files().environment;
        Ok(())
    })();
    if state
        .report(r, |_| "the wizard took over the composition".into())
        .is_some()
    {
        state.tool = Tool::Wizard;
    }
}

/// Opens the composition of the simulation file `path`, checked as the control window
/// loads it; a broken file keeps the current composition and shows the located error.
pub fn open(state: &mut SetupState, path: &std::path::Path) {
    let r = Composition::open_checked(path, &state.wizard.registry);
    state.expert.check = r.as_ref().err().map(|e| Err(e.to_string()));
    if let Some(c) = state.report(r, |_| format!("opened {}", path.display())) {
        state.expert.composition = c;
    }
}

/// The expert dialog.
pub fn show(ui: &mut egui::Ui, state: &mut SetupState) {
    ui.heading("Compose a simulation from existing files");
    let dirs = [
        state.wizard.configs_dir.clone(),
        state.wizard.out_dir.clone(),
    ];
    let c = &mut state.expert.composition;
    for part in Part::ALL {
        let files = catalog(part, &dirs);
        match part {
            Part::Robot => {
                let mut v = Some(c.robot.clone());
                choose(ui, part, &mut v, &files, false);
                c.robot = v.unwrap_or_else(|| c.robot.clone());
            }
            Part::Actuation => {
                let mut v = Some(c.actuation.clone());
                choose(ui, part, &mut v, &files, false);
                c.actuation = v.unwrap_or_else(|| c.actuation.clone());
            }
            Part::Environment => choose(ui, part, &mut c.environment, &files, true),
            Part::Optimizer => choose(ui, part, &mut c.optimizer, &files, true),
        }
    }
    ui.separator();
    crate::gui::setup::properties_view::show(ui, &mut c.properties, &mut c.description);
    ui.separator();
    ui.horizontal(|ui| {
        ui.label("simulation file");
        ui.add(egui::TextEdit::singleline(&mut state.expert.path).desired_width(420.0));
    });
    let path = PathBuf::from(state.expert.path.trim());
    ui.horizontal(|ui| action_buttons(ui, state, &path));
    match &state.expert.check {
        Some(Ok(s)) => {
            ui.colored_label(egui::Color32::DARK_GREEN, format!("✔ {s}"));
        }
        Some(Err(e)) => {
            ui.colored_label(egui::Color32::RED, e);
        }
        None => {}
    }
}

/// Open, Check, Save, Open in the control window, Edit in the wizard, Edit environment.
fn action_buttons(ui: &mut egui::Ui, state: &mut SetupState, path: &Path) {
    if ui
        .button("Open")
        .on_hover_text("Load the composition of this simulation file")
        .clicked()
    {
        open(state, path);
    }
    if ui.button("Check").clicked() {
        state.expert.check = Some(
            state
                .expert
                .composition
                .check(path, &state.wizard.registry)
                .map_err(|e| e.to_string()),
        );
    }
    if ui.button("Save").clicked() {
        let r = state.expert.composition.save(path, &state.wizard.registry);
        state.report(r, |_| format!("saved {}", path.display()));
    }
    if ui.button("Open in control window").clicked() {
        match state.expert.composition.save(path, &state.wizard.registry) {
            Ok(()) => crate::gui::setup::open_control_window(state, path),
            Err(e) => state.expert.check = Some(Err(e.to_string())),
        }
    }
    if ui
        .button("Edit in the wizard")
        .on_hover_text(
            "The wizard takes this robot, its actuation groups, environment and properties",
        )
        .clicked()
    {
        edit_in_wizard(state);
    }
    if let Some(env) = state.expert.composition.environment.clone()
        && ui.button("Edit environment").clicked()
    {
        let r = EnvEditor::load(&env);
        if let Some(e) = state.report(r, |_| format!("editing {}", env.display())) {
            state.editor = e;
            state.editor_path = env.display().to_string();
            state.tool = Tool::Editor;
        }
    }
}
