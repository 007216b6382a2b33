//! The environment editor's panels (thesis 4.4.6): the object library (drag an item onto
//! a 3D view, or "Add" it ahead of the robot), the scene's object list, undo / redo,
//! load / save, "Preview"; and the side panel for the selection: position, heading
//! (fixed steps or a typed angle), scale, friction, static / dynamic, mass, colour,
//! delete; a generated terrain's difficulty and seed. Labels mark the top and side views.

use std::path::PathBuf;

use bevy_egui::egui;

use crate::compose::env_edit::{
    EDITOR_MAX_FRICTION, EditError, EnvEditor, Props, Selected, object_name,
};
use crate::config::terrain::{TerrainSpec, Tier};
use crate::gui::setup::preview::run_preview;
use crate::gui::setup::state::{SetupState, Status, Tool};

/// Seconds of the preview run.
pub const PREVIEW_SECONDS: f64 = 5.0;

/// The library and scene list (left panel); `overlaps` are the objects the robot would
/// start inside.
pub fn show_library(ui: &mut egui::Ui, state: &mut SetupState, overlaps: &[String]) {
    ui.heading("Object library");
    ui.label("Drag an object onto a 3D view; it lands on the ground or on what is below.");
    let items = state.library.clone();
    for (i, item) in items.iter().enumerate() {
        let id = egui::Id::new(("library", i));
        let r = ui
            .dnd_drag_source(id, i, |ui| {
                ui.selectable_label(state.library_choice == i, format!("⬛ {}", item.label()))
            })
            .response;
        if r.clicked() {
            state.library_choice = i;
        }
    }
    if ui.button("Add chosen object ahead of the robot").clicked()
        && let Some(item) = state.library.get(state.library_choice).cloned()
    {
        let env = state.env_mut();
        let r = env.robot_pose;
        let ahead = r.rotate([0.0, 1.0, 0.0]);
        env.add(
            &item,
            r.translation[0] + ahead[0],
            r.translation[1] + ahead[1],
        );
    }
    for e in state.env().mesh_errors() {
        ui.colored_label(egui::Color32::from_rgb(230, 80, 60), e.to_string());
    }
    for w in overlaps {
        ui.colored_label(egui::Color32::from_rgb(230, 140, 20), format!("⚠ {w}"));
    }
    ui.separator();
    ui.horizontal(|ui| {
        let env = state.env_mut();
        if ui
            .add_enabled(env.can_undo(), egui::Button::new("Undo"))
            .clicked()
        {
            env.undo();
        }
        if ui
            .add_enabled(env.can_redo(), egui::Button::new("Redo"))
            .clicked()
        {
            env.redo();
        }
    });
    scene_list(ui, state);
    ui.separator();
    ui.label("Top and side views: mouse wheel over them zooms.");
    ui.add(
        egui::Slider::new(&mut state.ortho_height, 0.1..=20.0)
            .text("view height (m)")
            .logarithmic(true),
    );
    ui.separator();
    file_buttons(ui, state);
}

/// The scene's list: the robot's start pose and every object, a click selects.
fn scene_list(ui: &mut egui::Ui, state: &mut SetupState) {
    ui.heading("Scene");
    let env = state.env_mut();
    let mut pick = None;
    if ui
        .selectable_label(env.selected == Some(Selected::Robot), "robot (start pose)")
        .clicked()
    {
        pick = Some(Selected::Robot);
    }
    egui::ScrollArea::vertical()
        .max_height(220.0)
        .show(ui, |ui| {
            for (i, o) in env.objects.iter().enumerate() {
                if ui
                    .selectable_label(env.selected == Some(Selected::Object(i)), object_name(o, i))
                    .clicked()
                {
                    pick = Some(Selected::Object(i));
                }
            }
        });
    if let Some(p) = pick
        && let Err(e) = env.select(Some(p))
    {
        state.status = Some(Status::Error(e.to_string()));
    }
}

/// Load / Save (standalone editor) and Preview.
fn file_buttons(ui: &mut egui::Ui, state: &mut SetupState) {
    if state.tool == Tool::Editor {
        ui.label("Environment file:");
        ui.text_edit_singleline(&mut state.editor_path);
        ui.horizontal(|ui| {
            if ui.button("Load").clicked() {
                let p = PathBuf::from(state.editor_path.trim());
                let r = EnvEditor::load(&p);
                if let Some(e) = state.report(r, |_| format!("loaded {}", p.display())) {
                    state.editor = e;
                }
            }
            if ui.button("Save").clicked() {
                let p = PathBuf::from(state.editor_path.trim());
                let r = state.editor.save(&p);
                state.report(r, |_| format!("saved {}", p.display()));
            }
        });
    } else {
        ui.label(format!(
            "Saved with the configuration as {}",
            state.wizard.files().environment.display()
        ));
    }
    if ui
        .button("Preview: run the robot in this scene")
        .on_hover_text("Runs the wizard's robot and behaviour here for a few seconds")
        .clicked()
    {
        preview(state);
    }
    if let Some(p) = &state.preview {
        match p {
            Ok(run) => ui.label(format!(
                "Preview: the robot crawled {:.3} m in {PREVIEW_SECONDS} s (its path is drawn in orange in the views)",
                run.distance
            )),
            Err(e) => ui.colored_label(egui::Color32::RED, e.to_string()),
        };
    }
}

/// Runs the preview of the wizard's robot in the edited scene.
pub fn preview(state: &mut SetupState) {
    let mut w = state.wizard.clone();
    w.env = state.env().clone();
    let r = run_preview(&w, PREVIEW_SECONDS);
    state.status = Some(match &r {
        Ok(run) => Status::Info(format!(
            "preview: the robot crawled {:.3} m in {PREVIEW_SECONDS} s",
            run.distance
        )),
        Err(e) => Status::Error(format!("preview: {e}")),
    });
    state.preview = Some(r);
}

/// The selection's properties (right panel).
pub fn show_selection(ui: &mut egui::Ui, state: &mut SetupState) {
    ui.heading("Selection");
    let typed_yaw = &mut state.typed_yaw;
    let env = if state.tool == Tool::Editor {
        &mut state.editor
    } else {
        &mut state.wizard.env
    };
    let Some(sel) = env.selected else {
        ui.label("Click an object or the robot in a view, or in the scene list.");
        return;
    };
    let Some(props) = env.props(sel) else {
        return;
    };
    let mut result: Result<(), EditError> = Ok(());
    ui.strong(&props.name);
    let mut pos = props.position;
    ui.horizontal(|ui| {
        ui.label("position (m)");
        let mut changed = false;
        for v in &mut pos {
            changed |= ui
                .add(egui::DragValue::new(v).speed(0.01).max_decimals(4))
                .changed();
        }
        if changed {
            result = env.move_to(pos);
        }
    });
    ui.horizontal(|ui| {
        ui.label(format!("heading {:.1}°", props.yaw_deg));
        for step in [-90.0, -15.0, 15.0, 90.0] {
            if ui.button(format!("{step:+}°")).clicked() {
                result = env.rotate_by(step);
            }
        }
    });
    ui.horizontal(|ui| {
        ui.add(
            egui::DragValue::new(typed_yaw)
                .suffix("°")
                .range(-180.0..=180.0),
        );
        if ui.button("Set heading").clicked() {
            result = env.set_yaw(*typed_yaw);
        }
    });
    if props.editable {
        result = editable_properties(ui, env, &props);
    } else if let Some(terrain) = &props.terrain {
        result = terrain_properties(ui, env, terrain);
    } else if sel == Selected::Robot {
        ui.label("The robot placeholder sets the start pose: move and turn it.");
    } else {
        ui.label("An included kinbody file: move and turn it here, edit it in its file.");
    }
    if let Err(e) = result {
        state.status = Some(Status::Error(e.to_string()));
    }
}

/// A generated terrain's difficulty (a slider, the tiers marked) and seed, and its
/// deletion; the last change's result.
fn terrain_properties(
    ui: &mut egui::Ui,
    env: &mut EnvEditor,
    terrain: &TerrainSpec,
) -> Result<(), EditError> {
    let mut result = Ok(());
    ui.label(format!(
        "A generated {} course, {:.0} m long and {:.1} m wide: its bodies come from its difficulty and seed.",
        terrain.family, terrain.length, terrain.width
    ));
    let (mut difficulty, mut seed) = (terrain.difficulty, terrain.seed);
    let tiers: Vec<String> = Tier::ALL
        .iter()
        .map(|t| format!("{} {}", t.name(), t.difficulty()))
        .collect();
    let slider = ui
        .add(egui::Slider::new(&mut difficulty, 0.0..=1.0).text("difficulty"))
        .on_hover_text(format!("tiers: {}", tiers.join(", ")));
    let seed_box = ui
        .horizontal(|ui| {
            ui.label("seed");
            ui.add(egui::DragValue::new(&mut seed).range(0..=u32::MAX as u64))
        })
        .inner;
    if slider.changed() || seed_box.changed() {
        result = env.set_terrain(difficulty, seed);
    }
    if ui.button("Delete").clicked() {
        result = env.delete();
    }
    result
}

/// Size, friction, dynamics, mass, colour and deletion of an editable object; the last
/// change's result.
fn editable_properties(
    ui: &mut egui::Ui,
    env: &mut EnvEditor,
    props: &Props,
) -> Result<(), EditError> {
    let mut result = Ok(());
    ui.label(format!(
        "size {:.3} x {:.3} x {:.3} m",
        props.size[0], props.size[1], props.size[2]
    ));
    ui.horizontal(|ui| {
        ui.label("scale");
        for f in [0.5, 0.9, 1.1, 2.0] {
            if ui.button(format!("×{f}")).clicked() {
                result = env.scale([f; 3]);
            }
        }
    });
    ui.horizontal(|ui| {
        for (axis, k) in [("x", 0), ("y", 1), ("z", 2)] {
            if ui.button(format!("{axis} ×2")).clicked() {
                let mut f = [1.0; 3];
                f[k] = 2.0;
                result = env.scale(f);
            }
            if ui.button(format!("{axis} ×½")).clicked() {
                let mut f = [1.0; 3];
                f[k] = 0.5;
                result = env.scale(f);
            }
        }
    });
    let mut mu = props.friction.unwrap_or(0.5);
    if ui
        .add(egui::Slider::new(&mut mu, 0.0..=EDITOR_MAX_FRICTION).text("friction (Coulomb)"))
        .changed()
    {
        result = env.set_friction(mu);
    }
    let mut dynamic = props.dynamic;
    if ui
        .checkbox(&mut dynamic, "dynamic (pushed around)")
        .changed()
    {
        result = env.set_dynamic(dynamic);
    }
    if props.dynamic {
        let mut kg = props.mass.unwrap_or(1.0);
        ui.horizontal(|ui| {
            ui.label("mass");
            if ui
                .add(
                    egui::DragValue::new(&mut kg)
                        .speed(0.01)
                        .range(0.001..=1000.0)
                        .suffix(" kg"),
                )
                .changed()
            {
                result = env.set_mass(kg);
            }
        });
    }
    let c = props.colour.unwrap_or([0.7, 0.7, 0.7]);
    let mut rgb = [c[0] as f32, c[1] as f32, c[2] as f32];
    ui.horizontal(|ui| {
        ui.label("colour");
        if ui.color_edit_button_rgb(&mut rgb).changed() {
            result = env.set_colour(rgb.map(f64::from));
        }
    });
    if ui.button("Delete").clicked() {
        result = env.delete();
    }
    result
}

/// Names the top and side views over their viewports.
pub fn label_views(ctx: &egui::Context, state: &SetupState) {
    let Some(area) = state.central else {
        return;
    };
    let x = area.min.x + area.width() * 2.0 / 3.0 + 6.0;
    for (name, y) in [
        ("Top view: x to the right, y up", area.min.y + 4.0),
        (
            "Side view: y to the right, z up",
            area.min.y + area.height() / 2.0 + 4.0,
        ),
    ] {
        egui::Area::new(egui::Id::new(name))
            .fixed_pos(egui::pos2(x, y))
            .order(egui::Order::Background)
            .interactable(false)
            .show(ctx, |ui| {
                ui.label(
                    egui::RichText::new(name)
                        .strong()
                        .background_color(egui::Color32::from_black_alpha(120))
                        .color(egui::Color32::WHITE),
                );
            });
    }
}
