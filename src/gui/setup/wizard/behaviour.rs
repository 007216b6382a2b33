//! The wizard's behaviour page (thesis fig. 4.11): one module on every joint, or groups of
//! joints chosen in a topological strip, each with its modules and their parameters.

use crate::compose::behaviour::{BehaviourSpec, Group, ModuleChoice};
use crate::compose::wizard::Wizard;
use crate::config::actuation::ParamValue;
use crate::config::module_types::ModuleDescriptor;
use bevy_egui::egui;

/// Joint selection state of the behaviour page (egui memory).
fn selection_id() -> egui::Id {
    egui::Id::new("behaviour joint selection")
}

pub(super) fn behaviour_page(ui: &mut egui::Ui, w: &mut Wizard) {
    let joints = w.joint_count().unwrap_or(0);
    let topology: Vec<char> = w.topology().chars().collect();
    let mut sel: Vec<bool> = ui
        .data_mut(|d| d.get_temp::<Vec<bool>>(selection_id()))
        .filter(|s| s.len() == joints)
        .unwrap_or_else(|| vec![false; joints]);
    let names = w.registry.names();
    let simple = w.behaviour.groups.len() == 1 && w.behaviour.groups[0].joints.iter().all(|b| *b);
    ui.horizontal(|ui| {
        if ui
            .radio(simple, "Simple: one module on all joints")
            .clicked()
            && !simple
            && let Some(m) = ModuleChoice::with_defaults(&w.registry, "PatternGenerator_sinusoidal")
        {
            w.behaviour = BehaviourSpec::simple(joints, m);
        }
        if ui.radio(!simple, "Grouped").clicked() && simple {
            w.behaviour.groups.clear();
        }
    });
    ui.label("Topology (click joints to select them for a new group):");
    ui.horizontal_wrapped(|ui| {
        for (i, s) in sel.iter_mut().enumerate() {
            let kind = topology.get(i).map_or('?', |c| c.to_ascii_uppercase());
            ui.toggle_value(s, format!("J{} {kind}", i + 1));
        }
    });
    ui.horizontal(|ui| {
        if ui.button("Make a group of the selected joints").clicked() && sel.iter().any(|b| *b) {
            if let Some(m) = ModuleChoice::with_defaults(&w.registry, "PatternGenerator_sinusoidal")
            {
                w.behaviour.groups.push(Group {
                    joints: sel.clone(),
                    modules: vec![m],
                });
            }
            sel.fill(false);
        }
        if ui.button("select none").clicked() {
            sel.fill(false);
        }
    });
    ui.data_mut(|d| d.insert_temp(selection_id(), sel));
    groups_view(ui, w, &names);
    if let Err(e) = w.behaviour.validate(&w.registry, joints) {
        ui.colored_label(egui::Color32::RED, e.to_string());
    }
}

/// The behaviour's groups, each with its modules and their parameters, a module picker
/// and its remove buttons.
fn groups_view(ui: &mut egui::Ui, w: &mut Wizard, names: &[&str]) {
    let mut remove_group = None;
    for (gi, g) in w.behaviour.groups.iter_mut().enumerate() {
        egui::CollapsingHeader::new(format!(
            "Group {}: joints {}",
            gi + 1,
            g.joints
                .iter()
                .map(|b| if *b { '1' } else { '0' })
                .collect::<String>()
        ))
        .default_open(true)
        .show(ui, |ui| {
            let mut remove_module = None;
            for (mi, m) in g.modules.iter_mut().enumerate() {
                ui.horizontal(|ui| {
                    ui.strong(&m.name);
                    if ui.small_button("remove").clicked() {
                        remove_module = Some(mi);
                    }
                });
                let Some(d) = w.registry.get(&m.name) else {
                    continue;
                };
                module_params_view(ui, m, d);
            }
            if let Some(mi) = remove_module {
                g.modules.remove(mi);
            }
            ui.horizontal(|ui| {
                egui::ComboBox::from_id_salt(("add module", gi))
                    .selected_text("add a module…")
                    .show_ui(ui, |ui| {
                        for n in names {
                            if ui.selectable_label(false, *n).clicked()
                                && let Some(m) = ModuleChoice::with_defaults(&w.registry, n)
                            {
                                g.modules.push(m);
                            }
                        }
                    });
                if ui.button("remove group").clicked() {
                    remove_group = Some(gi);
                }
            });
        });
    }
    if let Some(gi) = remove_group {
        w.behaviour.groups.remove(gi);
    }
}

/// The parameters of one module of a group, as drag values within their ranges.
fn module_params_view(ui: &mut egui::Ui, m: &mut ModuleChoice, d: &ModuleDescriptor) {
    for p in d.parameters {
        let Some((_, value)) = m.params.iter_mut().find(|(n, _)| p.answers_to(n)) else {
            continue;
        };
        ui.horizontal(|ui| {
            ui.label(format!("{} ({})", p.name, p.unit));
            match value {
                ParamValue::Uniform(v) => {
                    ui.add(
                        egui::DragValue::new(v)
                            .range(p.min..=p.max)
                            .speed((p.max - p.min) / 500.0),
                    )
                    .on_hover_text(p.help);
                }
                ParamValue::PerJoint(v) => {
                    for x in v.iter_mut() {
                        ui.add(egui::DragValue::new(x).range(p.min..=p.max));
                    }
                }
            }
        });
    }
}
