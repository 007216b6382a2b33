//! The optimization page's MAP-Elites settings and co-design ranges: whether the body is
//! searched with the gait, and which bodies (module count, joint orientations, an optional
//! repeated motif, part sets), and the archive's two descriptors (a gene, a body's share
//! of yaw joints, or a quantity measured in the episode over a range).

use bevy_egui::egui;

use crate::compose::optimization::OptimizationSpec;
use crate::config::error::Pos;
use crate::config::morphology::Morphology;
use crate::config::optimizer::{DescriptorSpec, Measured, Quantity};
use crate::config::robot_builder::{MAX_JOINTS, Orientation, PartSet};

/// MAP-Elites' own settings: first random round, mutants per round, mutation rate, and
/// the two descriptors (a gene's place in its range, or a body's share of yaw joints).
pub fn map_elites_settings(ui: &mut egui::Ui, o: &mut OptimizationSpec) {
    let m = &mut o.map_elites;
    ui.add(
        egui::DragValue::new(&mut m.initial)
            .range(1..=100_000)
            .prefix("random candidates first "),
    );
    ui.add(
        egui::DragValue::new(&mut m.batch)
            .range(1..=10_000)
            .prefix("mutants per round "),
    );
    ui.add(egui::Slider::new(&mut m.mutation, 0.0..=1.0).text("gene redraw probability"));
    let co_design = o.morphology.is_some();
    for (axis, d) in ["x", "y"].into_iter().zip(m.descriptors.iter_mut()) {
        ui.horizontal(|ui| {
            ui.label(format!("{axis}:"));
            descriptor_kind(ui, axis, d, co_design);
            match &mut d.measured {
                Some(q) => {
                    ui.add(
                        egui::DragValue::new(&mut q.range[0])
                            .speed(0.01)
                            .prefix("from "),
                    );
                    ui.add(
                        egui::DragValue::new(&mut q.range[1])
                            .speed(0.01)
                            .prefix("to "),
                    );
                }
                None if !d.yaw_share => {
                    d.gene = d.gene.max(1);
                    ui.add(
                        egui::DragValue::new(&mut d.gene)
                            .range(1..=10_000)
                            .prefix("gene "),
                    );
                }
                None => {}
            }
            ui.add(
                egui::DragValue::new(&mut d.bins)
                    .range(1..=1000)
                    .prefix("cells "),
            );
        });
    }
    ui.label(if co_design {
        "genes: 1 module count, then the joints' orientations, the part set, the gait"
    } else {
        "genes are numbered from 1 in registration order"
    });
}

/// What a descriptor describes: a gene, a body's share of yaw joints (co-design only), or
/// a quantity measured in the episode.
fn descriptor_kind(ui: &mut egui::Ui, axis: &str, d: &mut DescriptorSpec, co_design: bool) {
    let now = match (&d.measured, d.yaw_share) {
        (Some(q), _) => q.quantity.label(),
        (None, true) => "share of yaw joints",
        (None, false) => "a gene",
    };
    egui::ComboBox::from_id_salt(("descriptor", axis))
        .selected_text(now)
        .show_ui(ui, |ui| {
            if ui.selectable_label(now == "a gene", "a gene").clicked() {
                (d.yaw_share, d.measured) = (false, None);
            }
            if co_design
                && ui
                    .selectable_label(d.yaw_share, "share of yaw joints")
                    .clicked()
            {
                (d.yaw_share, d.measured) = (true, None);
            }
            for (quantity, range) in [
                (Quantity::Height, [0.0, 0.08]),
                (Quantity::Curvature, [0.0, 120.0]),
            ] {
                let on = d.measured.is_some_and(|m| m.quantity == quantity);
                if ui.selectable_label(on, quantity.label()).clicked() && !on {
                    d.yaw_share = false;
                    d.measured = Some(Measured { quantity, range });
                }
            }
        });
    if !co_design {
        d.yaw_share = false;
    }
}

/// Whether the body is searched too, and within which ranges.
pub fn morphology_settings(ui: &mut egui::Ui, o: &mut OptimizationSpec) {
    let mut on = o.morphology.is_some();
    ui.checkbox(
        &mut on,
        "evolve the body too (co-design: each candidate builds its own chain)",
    );
    match (on, o.morphology.clone()) {
        (false, Some(_)) => o.set_morphology(None),
        (true, None) => o.set_morphology(Some(Morphology {
            modules: [3, 9],
            orientations: vec![Orientation::Pitch, Orientation::Yaw],
            motif: None,
            parts: vec![PartSet::Plain],
            pos: Pos::new(0, 0),
        })),
        (true, Some(mut m)) => {
            if ranges(ui, &mut m) {
                o.set_morphology(Some(m));
            }
        }
        (false, None) => {}
    }
}

/// The ranges' fields; true when one changed.
fn ranges(ui: &mut egui::Ui, m: &mut Morphology) -> bool {
    let before = m.clone();
    let most = MAX_JOINTS as u32 + 1;
    ui.horizontal(|ui| {
        ui.add(
            egui::DragValue::new(&mut m.modules[0])
                .range(2..=most)
                .prefix("modules from "),
        );
        ui.add(
            egui::DragValue::new(&mut m.modules[1])
                .range(2..=most)
                .prefix("to "),
        );
    });
    ui.horizontal(|ui| {
        ui.label("joints:");
        for o in [Orientation::Pitch, Orientation::Yaw] {
            let mut allowed = m.orientations.contains(&o);
            let name = if o == Orientation::Pitch {
                "pitch"
            } else {
                "yaw"
            };
            if ui.checkbox(&mut allowed, name).changed() {
                m.orientations.retain(|x| *x != o);
                if allowed {
                    m.orientations.push(o);
                    m.orientations.sort_by_key(|x| *x != Orientation::Pitch);
                }
            }
        }
    });
    ui.horizontal(|ui| {
        let mut motif = m.motif.is_some();
        ui.checkbox(&mut motif, "repeat a motif of");
        let mut k = m.motif.unwrap_or(2);
        ui.add_enabled(
            motif,
            egui::DragValue::new(&mut k)
                .range(1..=MAX_JOINTS as u32)
                .suffix(" joints"),
        );
        m.motif = motif.then_some(k);
    });
    ui.horizontal_wrapped(|ui| {
        ui.label("parts:");
        for p in PartSet::ALL {
            let mut allowed = m.parts.contains(&p);
            if ui.checkbox(&mut allowed, p.describe()).changed() {
                m.parts.retain(|x| *x != p);
                if allowed {
                    m.parts.push(p);
                }
            }
        }
    });
    *m != before
}
