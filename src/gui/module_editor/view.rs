//! The module library window: the declaration form (fig. 4.8), the source editor with
//! highlighting and Compile (fig. 4.9), the build output, and the loaded plugin modules.

use bevy_egui::egui;

use crate::gui::module_editor::{ModuleEditor, ParamRow, Status, highlight};
use crate::plugin_host;

/// Draws the window (when open) and collects a finished build.
pub fn show(ctx: &egui::Context, editor: &mut ModuleEditor) {
    editor.poll();
    if !editor.open {
        return;
    }
    let mut open = editor.open;
    egui::Window::new("Module library")
        .open(&mut open)
        .default_size([720.0, 640.0])
        .vscroll(true)
        .show(ctx, |ui| {
            egui::CollapsingHeader::new("Declare a new module")
                .default_open(editor.crate_name.is_none())
                .show(ui, |ui| declaration(ui, editor));
            ui.horizontal(|ui| {
                ui.label("Open:");
                let current = editor.crate_name.clone().unwrap_or_else(|| "—".into());
                egui::ComboBox::from_id_salt("module crates")
                    .selected_text(current)
                    .show_ui(ui, |ui| {
                        for c in editor.crates() {
                            if ui.selectable_label(false, &c).clicked()
                                && let Err(e) = editor.open_crate(&c)
                            {
                                editor.status = Status::Error(e.to_string());
                            }
                        }
                    });
                ui.label(format!("in {}", editor.workspace.display()));
            });
            ui.separator();
            source(ui, editor);
            status(ui, editor);
            if !editor.log.is_empty() {
                egui::CollapsingHeader::new("Build output")
                    .default_open(true)
                    .show(ui, |ui| build_log(ui, &editor.log));
            }
            egui::CollapsingHeader::new("Loaded plugin modules").show(ui, |ui| loaded(ui, editor));
        });
    editor.open = open;
}

fn declaration(ui: &mut egui::Ui, editor: &mut ModuleEditor) {
    let f = &mut editor.form;
    egui::Grid::new("declaration")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("Module name");
            ui.text_edit_singleline(&mut f.name);
            ui.end_row();
            ui.label("Summary");
            ui.text_edit_singleline(&mut f.summary);
            ui.end_row();
            ui.label("Helper functions");
            ui.text_edit_singleline(&mut f.helpers)
                .on_hover_text("comma-separated names, e.g. smooth, clamp_angle");
            ui.end_row();
            ui.label("Data series");
            ui.text_edit_singleline(&mut f.series)
                .on_hover_text("comma-separated names of the values logged per joint");
            ui.end_row();
        });
    ui.label("Parameters (per joint): name, initial value, range");
    let mut remove = None;
    egui::Grid::new("declared parameters")
        .num_columns(5)
        .show(ui, |ui| {
            for (i, p) in f.params.iter_mut().enumerate() {
                ui.add(egui::TextEdit::singleline(&mut p.name).desired_width(140.0));
                ui.add(
                    egui::DragValue::new(&mut p.initial)
                        .speed(0.1)
                        .prefix("initial "),
                );
                ui.add(egui::DragValue::new(&mut p.min).speed(0.1).prefix("min "));
                ui.add(egui::DragValue::new(&mut p.max).speed(0.1).prefix("max "));
                if ui.small_button("✖").clicked() {
                    remove = Some(i);
                }
                ui.end_row();
            }
        });
    if let Some(i) = remove {
        f.params.remove(i);
    }
    ui.horizontal(|ui| {
        if ui.button("+ parameter").clicked() {
            let n = editor.form.params.len() + 1;
            editor.form.params.push(ParamRow {
                name: format!("P{n}"),
                initial: 0.0,
                min: -100.0,
                max: 100.0,
            });
        }
        let problems = editor
            .form
            .declaration()
            .validate()
            .err()
            .map(|e| e.to_string());
        let ok = problems.is_none();
        if ui
            .add_enabled(ok, egui::Button::new("Generate module"))
            .on_disabled_hover_text(problems.clone().unwrap_or_default())
            .clicked()
            && let Err(e) = editor.declare()
        {
            editor.status = Status::Error(e.to_string());
        }
        if let Some(p) = problems {
            ui.colored_label(egui::Color32::LIGHT_RED, p);
        }
    });
}

fn source(ui: &mut egui::Ui, editor: &mut ModuleEditor) {
    let Some(name) = editor.crate_name.clone() else {
        ui.label("Declare a module or open one to edit its source.");
        return;
    };
    ui.horizontal(|ui| {
        ui.strong(format!(
            "{name}/src/lib.rs{}",
            if editor.modified { " *" } else { "" }
        ));
        if ui.button("Save").clicked()
            && let Err(e) = editor.save()
        {
            editor.status = Status::Error(e.to_string());
        }
        let building = editor.building();
        if ui
            .add_enabled(!building, egui::Button::new("⚙ Compile"))
            .on_hover_text("cargo build --release, then load the module")
            .clicked()
            && let Err(e) = editor.compile()
        {
            editor.status = Status::Error(e.to_string());
        }
        if building {
            ui.spinner();
        }
    });
    egui::ScrollArea::vertical()
        .id_salt("source")
        .max_height(360.0)
        .show(ui, |ui| {
            if highlight::code_editor(ui, &mut editor.source, 24).changed() {
                editor.modified = true;
            }
        });
}

fn status(ui: &mut egui::Ui, editor: &ModuleEditor) {
    match &editor.status {
        Status::None => {}
        Status::Info(m) => {
            ui.colored_label(egui::Color32::from_rgb(90, 170, 90), m);
        }
        Status::Error(m) => {
            ui.colored_label(egui::Color32::LIGHT_RED, m);
        }
    }
}

fn build_log(ui: &mut egui::Ui, log: &str) {
    egui::ScrollArea::vertical()
        .id_salt("build log")
        .max_height(200.0)
        .stick_to_bottom(true)
        .show(ui, |ui| {
            for line in log.lines() {
                let colour = if line.starts_with("error") {
                    egui::Color32::LIGHT_RED
                } else if line.starts_with("warning") {
                    egui::Color32::from_rgb(220, 180, 60)
                } else {
                    ui.visuals().text_color()
                };
                ui.label(egui::RichText::new(line).monospace().color(colour));
            }
        });
}

fn loaded(ui: &mut egui::Ui, editor: &mut ModuleEditor) {
    ui.horizontal(|ui| {
        let dirs: Vec<String> = plugin_host::library_dirs()
            .iter()
            .map(|d| d.display().to_string())
            .collect();
        if ui
            .button("Rescan library folders")
            .on_hover_text(dirs.join(", "))
            .clicked()
        {
            editor.rescan();
        }
    });
    for m in &editor.scan_messages {
        ui.colored_label(egui::Color32::LIGHT_RED, m);
    }
    let modules = editor.host.loaded();
    if modules.is_empty() {
        ui.label("none");
    }
    for p in modules {
        let names: Vec<&str> = p.descriptor.parameters.iter().map(|q| q.name).collect();
        ui.label(format!(
            "{} ({}) — {}",
            p.descriptor.type_name,
            names.join(", "),
            p.file.display()
        ));
    }
}
