//! The wizard's robot page (thesis fig. 4.10): a new robot from its topology and part set,
//! or one that exists.

use crate::compose::robot_builder::{MAX_JOINTS, Orientation, PartSet, RobotSpec};
use crate::compose::wizard::{RobotChoice, Wizard};
use bevy_egui::egui;

pub(super) fn robot_page(ui: &mut egui::Ui, w: &mut Wizard) {
    let mut existing = matches!(w.robot, RobotChoice::Existing(_));
    ui.horizontal(|ui| {
        if ui.radio(!existing, "Build a robot").clicked() {
            existing = false;
            w.robot = RobotChoice::Build(w.spec.clone());
        }
        if ui.radio(existing, "Use an existing robot").clicked()
            && !existing
            && let Some(p) = w.existing_robots().first().cloned()
        {
            w.robot = RobotChoice::Existing(p);
        }
    });
    if let RobotChoice::Existing(current) = &w.robot {
        let mut chosen = current.clone();
        egui::ComboBox::from_label("robot file")
            .selected_text(
                chosen
                    .file_name()
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default(),
            )
            .show_ui(ui, |ui| {
                for p in w.existing_robots() {
                    let label = p
                        .file_name()
                        .map(|f| f.to_string_lossy().into_owned())
                        .unwrap_or_default();
                    ui.selectable_value(&mut chosen, p, label);
                }
            });
        w.robot = RobotChoice::Existing(chosen);
        match w.joint_count() {
            Ok(n) => ui.label(format!("{n} joints")),
            Err(e) => ui.colored_label(egui::Color32::RED, e.to_string()),
        };
        return;
    }
    robot_form(ui, &mut w.spec);
    w.robot = RobotChoice::Build(w.spec.clone());
}

/// The "Build a robot" form: name, joints and their orientations, module parts.
fn robot_form(ui: &mut egui::Ui, spec: &mut RobotSpec) {
    ui.horizontal(|ui| {
        ui.label("Name");
        ui.text_edit_singleline(&mut spec.name);
    });
    let mut n = spec.joints.len();
    if ui
        .add(egui::Slider::new(&mut n, 1..=MAX_JOINTS).text("joints"))
        .changed()
    {
        spec.joints.resize(n, Orientation::Pitch);
    }
    ui.label("Joint orientations (click to switch pitch / yaw):");
    ui.horizontal_wrapped(|ui| {
        for (i, o) in spec.joints.iter_mut().enumerate() {
            let label = match o {
                Orientation::Pitch => format!("J{} pitch", i + 1),
                Orientation::Yaw => format!("J{} yaw", i + 1),
            };
            if ui.button(label).clicked() {
                *o = match o {
                    Orientation::Pitch => Orientation::Yaw,
                    Orientation::Yaw => Orientation::Pitch,
                };
            }
        }
    });
    ui.horizontal(|ui| {
        if ui.button("all pitch").clicked() {
            spec.joints.fill(Orientation::Pitch);
        }
        if ui.button("alternate pitch / yaw").clicked() {
            for (i, o) in spec.joints.iter_mut().enumerate() {
                *o = if i % 2 == 0 {
                    Orientation::Pitch
                } else {
                    Orientation::Yaw
                };
            }
        }
    });
    egui::ComboBox::from_label("module parts")
        .selected_text(spec.parts.describe())
        .show_ui(ui, |ui| {
            for p in PartSet::ALL {
                ui.selectable_value(&mut spec.parts, p, p.describe());
            }
        });
    ui.label(format!(
        "{} modules, {:.0} mm long; touch sensors: {}",
        spec.modules(),
        match spec.parts {
            PartSet::Cube => 60.0,
            _ => 72.0,
        } * spec.modules() as f64,
        if spec.parts == PartSet::Touch {
            "12 pads per module, under the links"
        } else {
            "none"
        }
    ));
    if let Err(e) = spec.validate() {
        ui.colored_label(egui::Color32::RED, e.to_string());
    }
}
