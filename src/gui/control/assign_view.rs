//! Assigning a module to joints in the running window: any registered type — standard
//! or a plugin module compiled a moment ago in the module library — on the joints of a
//! 0/1 mask. The world is rebuilt with the module added (the files stay as they are).
//! A `Policy` actuator's weights file is loaded here too (the world is rebuilt with it).

use bevy::prelude::*;
use bevy_egui::egui;

use crate::gui::control::session::SimSession;
use crate::gui::error::GuiError;

/// The form's state.
#[derive(Resource, Debug, Clone, Default)]
pub struct AssignState {
    /// The module type chosen.
    pub module: String,
    /// The joints it should drive, as a 0/1 mask.
    pub mask: String,
    /// The weights file to load into a Policy actuator.
    pub weights: String,
    /// The last assignment's outcome.
    pub message: Option<Result<String, String>>,
}

impl AssignState {
    /// Adds the chosen module; the outcome is kept for the form.
    pub fn assign(&mut self, session: &mut SimSession) -> Result<(), GuiError> {
        let result = session.add_module(&self.module, &self.mask);
        self.message = Some(match &result {
            Ok(()) => Ok(format!(
                "{} drives {} (world rebuilt)",
                self.module, self.mask
            )),
            Err(e) => Err(e.to_string()),
        });
        result
    }

    /// Loads the weights file into actuator `actuator`; the outcome is kept for the form.
    pub fn load_weights(
        &mut self,
        session: &mut SimSession,
        actuator: usize,
    ) -> Result<(), GuiError> {
        let result = session.load_weights(actuator, std::path::Path::new(self.weights.trim()));
        self.message = Some(match &result {
            Ok(()) => Ok(format!(
                "actuator {actuator} runs {} (world rebuilt)",
                self.weights.trim()
            )),
            Err(e) => Err(e.to_string()),
        });
        result
    }
}

/// Draws the form.
pub fn show(ui: &mut egui::Ui, session: &mut SimSession, state: &mut AssignState) {
    ui.strong("Assign a module to joints");
    let joints = session.sim.robot.joints.len();
    if state.mask.len() != joints {
        state.mask = "1".repeat(joints);
    }
    ui.horizontal(|ui| {
        let shown = if state.module.is_empty() {
            "choose…".to_string()
        } else {
            state.module.clone()
        };
        egui::ComboBox::from_id_salt("assign module")
            .selected_text(shown)
            .show_ui(ui, |ui| {
                // Built when opened, so modules compiled meanwhile are offered.
                let registry = session.registry.clone();
                for name in registry.names() {
                    let summary = registry.get(name).map_or("", |d| d.summary);
                    ui.selectable_value(&mut state.module, name.to_string(), name)
                        .on_hover_text(summary);
                }
            });
        ui.label("joints");
        ui.add(egui::TextEdit::singleline(&mut state.mask).desired_width(120.0))
            .on_hover_text("one 0/1 per joint, J1 first");
        if ui
            .add_enabled(!state.module.is_empty(), egui::Button::new("Add"))
            .clicked()
        {
            let _ = state.assign(session);
        }
    });
    let policies: Vec<usize> = session
        .sim
        .actuation
        .modules
        .iter()
        .enumerate()
        .filter(|(_, m)| m.descriptor.network)
        .map(|(i, _)| i)
        .collect();
    for i in policies {
        ui.horizontal(|ui| {
            ui.label(format!("actuator {i} weights"));
            ui.add(egui::TextEdit::singleline(&mut state.weights).desired_width(240.0))
                .on_hover_text("a .safetensors file (proleg policy init, an optimizer's best, Python's proleg.policy)");
            if ui.button("Load").clicked()
                && let Err(e) = state.load_weights(session, i)
            {
                // The form shows it too.
                bevy::log::warn!("weights not loaded: {e}");
            }
        });
    }
    match &state.message {
        Some(Ok(m)) => {
            ui.label(m);
        }
        Some(Err(e)) => {
            ui.colored_label(egui::Color32::LIGHT_RED, e);
        }
        None => {}
    }
}
