//! The wizard's summary page (thesis fig. 4.14): the files to be written (and how many
//! copies of the files they use go with them), saved and opened in the control window.

use crate::gui::setup::state::SetupState;
use bevy_egui::egui;

pub(super) fn summary_page(ui: &mut egui::Ui, state: &mut SetupState) {
    let files = state.wizard.files();
    let mut listed = 0;
    for p in [
        files.robot.clone(),
        Some(files.actuation.clone()),
        Some(files.environment.clone()),
        files.optimizer.clone(),
        Some(files.simulation.clone()),
    ]
    .into_iter()
    .flatten()
    {
        ui.monospace(p.display().to_string());
        listed += 1;
    }
    match state.wizard.compose() {
        Ok(all) => {
            let copies = all.len().saturating_sub(listed);
            if copies > 0 {
                ui.label(format!(
                    "and {copies} copies of the files it uses (parts, sensors, ...), so the folder stands alone"
                ));
            }
            ui.colored_label(
                egui::Color32::DARK_GREEN,
                "✔ the configuration checks (as proleg check)",
            )
        }
        Err(e) => ui.colored_label(egui::Color32::RED, e.to_string()),
    };
    ui.horizontal(|ui| {
        if ui.button("Save").clicked() {
            let r = state.wizard.save();
            state.report(r, |p| format!("saved {}", p.display()));
        }
        if let Some(sim) = state.wizard.saved.clone()
            && ui.button("Open in control window").clicked()
        {
            crate::gui::setup::open_control_window(state, &sim);
        }
    });
}
