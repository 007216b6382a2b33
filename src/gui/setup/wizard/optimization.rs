//! The wizard's optimization page (thesis fig. 4.13): the registered parameters with
//! their joints and values, the algorithm's settings, cross-engine and robustness scoring.

use crate::compose::optimization::{Method, OptimizationSpec, Registration, ValueSet};
use crate::compose::wizard::Wizard;
use crate::config::cross_engine::{Combine, CrossEngine};
use crate::config::robustness::Robustness;
use crate::config::simulation::EngineKind;
use bevy_egui::egui;

pub(super) fn optimization_page(ui: &mut egui::Ui, w: &mut Wizard) {
    let joints = w.joint_count().unwrap_or(0);
    let parameters = w.behaviour.parameters(&w.registry);
    let o = &mut w.optimization;
    ui.label(match o.method {
        Method::Genetic => "Genetic algorithm",
        Method::GreatDeluge => "Modified great deluge",
        Method::CmaEs => "CMA-ES",
        Method::MapElites => "MAP-Elites",
    });
    let mut remove = None;
    for (i, r) in o.params.iter_mut().enumerate() {
        if registration_view(ui, i, r, joints) {
            remove = Some(i);
        }
    }
    if let Some(i) = remove {
        o.params.remove(i);
    }
    egui::ComboBox::from_label("register a parameter")
        .selected_text("choose…")
        .show_ui(ui, |ui| {
            for (m, p) in parameters {
                if ui.selectable_label(false, format!("{m} / {p}")).clicked() {
                    let d = w.registry.get(&m).and_then(|d| d.parameter(&p).cloned());
                    let (lo, hi) = d.map_or((0.0, 1.0), |d| (d.min, d.max));
                    o.params.push(Registration {
                        module: m.clone(),
                        parameter: p.clone(),
                        all_joints: true,
                        joints: Vec::new(),
                        uniform: true,
                        values: ValueSet::Range {
                            lower: lo.max(-1e3),
                            upper: hi.min(1e3),
                            increment: ((hi.min(1e3) - lo.max(-1e3)) / 100.0).max(0.0),
                        },
                    });
                }
            }
        });
    ui.separator();
    crate::gui::setup::codesign_view::morphology_settings(ui, o);
    ui.separator();
    algorithm_settings(ui, o);
    let mut limit = o.max_evaluations.is_some();
    ui.horizontal(|ui| {
        ui.checkbox(&mut limit, "stop after");
        let mut n = o.max_evaluations.unwrap_or(1000);
        ui.add_enabled(
            limit,
            egui::DragValue::new(&mut n)
                .range(1..=10_000_000)
                .suffix(" evaluations"),
        );
        o.max_evaluations = limit.then_some(n);
    });
    if let Err(e) = o.validate() {
        ui.colored_label(egui::Color32::RED, e.to_string());
    }
}

/// One registered parameter: joints, uniform or individual, its values; true when its
/// "remove" button was clicked.
fn registration_view(ui: &mut egui::Ui, i: usize, r: &mut Registration, joints: usize) -> bool {
    let mut remove = false;
    ui.group(|ui| {
        ui.horizontal(|ui| {
            ui.strong(format!("{}. {} / {}", i + 1, r.module, r.parameter));
            if ui.small_button("remove").clicked() {
                remove = true;
            }
        });
        ui.horizontal(|ui| {
            ui.checkbox(&mut r.all_joints, "all joints of the module");
            ui.checkbox(&mut r.uniform, "uniform (one gene)");
        });
        if !r.all_joints {
            r.joints.resize(joints, false);
            ui.horizontal_wrapped(|ui| {
                for (j, b) in r.joints.iter_mut().enumerate() {
                    ui.toggle_value(b, format!("J{}", j + 1));
                }
            });
        }
        match &mut r.values {
            ValueSet::Range {
                lower,
                upper,
                increment,
            } => {
                ui.horizontal(|ui| {
                    ui.add(egui::DragValue::new(lower).prefix("from "));
                    ui.add(egui::DragValue::new(upper).prefix("to "));
                    ui.add(
                        egui::DragValue::new(increment)
                            .prefix("step ")
                            .range(0.0..=f64::MAX),
                    );
                });
            }
            ValueSet::List(v) => {
                ui.label(format!("values: {v:?}"));
            }
        }
    });
    remove
}

/// The optimizer's own settings (GA, great deluge or CMA-ES).
fn algorithm_settings(ui: &mut egui::Ui, o: &mut OptimizationSpec) {
    match o.method {
        Method::Genetic => {
            ui.add(
                egui::DragValue::new(&mut o.ga.popsize)
                    .range(2..=10_000)
                    .prefix("population "),
            );
            ui.add(egui::Slider::new(&mut o.ga.pmut, 0.0..=1.0).text("mutation probability"));
            ui.add(egui::Slider::new(&mut o.ga.pcross, 0.0..=1.0).text("crossover probability"));
            ui.add(
                egui::DragValue::new(&mut o.ga.n_convergence)
                    .range(1..=10_000)
                    .prefix("convergence generations "),
            );
            ui.add(egui::Slider::new(&mut o.ga.p_convergence, 0.0..=1.0).text("convergence ratio"));
        }
        Method::GreatDeluge => {
            ui.add(
                egui::DragValue::new(&mut o.gd.credits)
                    .range(1..=10_000)
                    .prefix("credits "),
            );
            ui.add(
                egui::DragValue::new(&mut o.gd.retries)
                    .range(1..=100_000)
                    .prefix("retries "),
            );
            ui.add(
                egui::DragValue::new(&mut o.gd.initial_water_level)
                    .speed(0.01)
                    .prefix("initial water level "),
            );
            ui.add(
                egui::DragValue::new(&mut o.gd.rain)
                    .speed(0.001)
                    .prefix("rain "),
            );
            ui.add(
                egui::DragValue::new(&mut o.gd.confidence)
                    .range(1..=10_000)
                    .prefix("confidence "),
            );
        }
        Method::CmaEs => {
            ui.add(
                egui::DragValue::new(&mut o.cma.popsize)
                    .range(0..=10_000)
                    .prefix("samples per generation (0: 4 + 3 ln n) "),
            );
            ui.add(
                egui::Slider::new(&mut o.cma.sigma, 0.01..=1.0)
                    .text("initial step (of each range)"),
            );
            ui.add(
                egui::DragValue::new(&mut o.cma.restarts)
                    .range(0..=20)
                    .prefix("IPOP restarts "),
            );
        }
        Method::MapElites => crate::gui::setup::codesign_view::map_elites_settings(ui, o),
    }
    ui.checkbox(
        &mut o.random_start,
        "start from a random point (drawn from the seed)",
    );
    robustness_settings(ui, o);
    cross_engine_settings(ui, o);
}

/// Cross-engine scores: every candidate on rapier and MuJoCo, by the lower score or the
/// mean.
fn cross_engine_settings(ui: &mut egui::Ui, o: &mut OptimizationSpec) {
    let mut on = o.cross_engine.is_some();
    ui.checkbox(&mut on, "score on both engines (rapier and MuJoCo)");
    match (on, o.cross_engine.as_mut()) {
        (false, _) => o.cross_engine = None,
        (true, None) => {
            o.cross_engine = Some(CrossEngine {
                engines: EngineKind::ALL.to_vec(),
                combine: Combine::Min,
            })
        }
        (true, Some(c)) => {
            ui.horizontal(|ui| {
                ui.label("combined by");
                ui.radio_value(&mut c.combine, Combine::Min, "the lower (min)");
                ui.radio_value(&mut c.combine, Combine::Mean, "the mean");
            });
        }
    }
}

/// Robust fitness: K randomized episodes per candidate.
fn robustness_settings(ui: &mut egui::Ui, o: &mut OptimizationSpec) {
    let mut on = o.robustness.is_some();
    ui.checkbox(&mut on, "robust fitness (randomized episodes)");
    match (on, o.robustness.as_mut()) {
        (false, _) => o.robustness = None,
        (true, None) => o.robustness = Some(Robustness::typical()),
        (true, Some(r)) => {
            ui.add(
                egui::DragValue::new(&mut r.episodes)
                    .range(1..=1000)
                    .prefix("episodes "),
            );
            for (v, label, max) in [
                (&mut r.friction_pct, "friction +-% ", 90.0),
                (&mut r.mass_pct, "link masses +-% ", 90.0),
                (&mut r.torque_pct, "servo torque +-% ", 90.0),
                (&mut r.gain_pct, "servo gain +-% ", 90.0),
                (&mut r.heading_deg, "start heading +-deg ", 180.0),
                (&mut r.position_m, "start position +-m ", 10.0),
                (&mut r.angle_noise_deg, "angle noise sigma deg ", 90.0),
                (&mut r.range_noise_m, "range noise sigma m ", 10.0),
            ] {
                ui.add(
                    egui::DragValue::new(v)
                        .range(0.0..=max)
                        .speed(0.1)
                        .prefix(label),
                );
            }
        }
    }
}
