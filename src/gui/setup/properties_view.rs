//! The simulation properties fields (thesis 4.4.7), shared by the wizard's page and the
//! expert dialog: mode, step width, sampling, duration, seed, data file, viewer, and a
//! description.

use bevy_egui::egui;

use crate::config::simulation::{Mode, SimulationProperties};

/// The fields of `p` and the `description`.
pub fn show(ui: &mut egui::Ui, p: &mut SimulationProperties, description: &mut String) {
    egui::ComboBox::from_label("mode")
        .selected_text(p.mode.name())
        .show_ui(ui, |ui| {
            for m in [
                Mode::SingleRun,
                Mode::GeneticAlgorithm,
                Mode::GreatDeluge,
                Mode::CmaEs,
                Mode::MapElites,
            ] {
                ui.selectable_value(&mut p.mode, m, m.name());
            }
        });
    let mut ms = p.step_width * 1000.0;
    if ui
        .add(
            egui::DragValue::new(&mut ms)
                .range(0.01..=100.0)
                .speed(0.05)
                .prefix("step width ")
                .suffix(" ms"),
        )
        .changed()
    {
        p.step_width = ms / 1000.0;
    }
    ui.add(
        egui::DragValue::new(&mut p.accuracy)
            .range(1..=10_000)
            .prefix("accuracy (sample every) ")
            .suffix(" steps"),
    );
    ui.add(
        egui::DragValue::new(&mut p.duration)
            .range(0.1..=100_000.0)
            .prefix("duration ")
            .suffix(" s"),
    );
    ui.add(egui::DragValue::new(&mut p.seed).prefix("seed "));
    ui.checkbox(&mut p.storing_data, "store data in a file");
    ui.checkbox(&mut p.show_viewer, "show the viewer");
    ui.horizontal(|ui| {
        ui.label("description");
        ui.text_edit_singleline(description);
    });
}
