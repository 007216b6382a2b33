//! The beginner wizard's pages (thesis 4.4.1, figs. 4.10-4.14): robot (topology, part set,
//! or an existing robot), behaviour (simple or grouped actuation, joints chosen in a
//! topological strip), environment (the editor), simulation properties, optimization
//! (registered parameters, algorithm settings) and the summary that saves and opens the
//! result. Every page explains itself; "Next" validates first.

use bevy_egui::egui;

use crate::compose::behaviour::{BehaviourSpec, Group, ModuleChoice};
use crate::compose::optimization::{Method, OptimizationSpec, Registration, ValueSet};
use crate::compose::robot_builder::{MAX_JOINTS, Orientation, PartSet, RobotSpec};
use crate::compose::wizard::{Page, RobotChoice, Wizard};
use crate::config::actuation::ParamValue;
use crate::config::cross_engine::{Combine, CrossEngine};
use crate::config::module_types::ModuleDescriptor;
use crate::config::robustness::Robustness;
use crate::config::simulation::EngineKind;
use crate::config::simulation::Mode;
use crate::gui::setup::state::{SetupState, Status};

/// What each page is for.
fn explanation(page: Page) -> &'static str {
    match page {
        Page::Robot => {
            "Describe the robot: how many joints it has and whether each turns up and down (pitch) or left and right (yaw). Choose the module parts; the touch set carries 12 pads under the links, which sensing modules need. Or pick a robot that already exists."
        }
        Page::Behaviour => {
            "Choose how the joints move. Simple: one module drives every joint. Grouped: select joints in the strip, make a group of them, and give it one or more modules (their outputs add up)."
        }
        Page::Environment => {
            "Build the terrain: drag objects from the library onto the views, click to select, drag to move. The yellow arrow is the robot's start pose. You may skip this page: the robot then crawls on a flat floor."
        }
        Page::Simulation => {
            "How the simulation runs: the mode (a single run or an optimization), the physics step width, how often data is sampled, how long a run lasts. You may skip this page to keep the defaults."
        }
        Page::Optimization => {
            "Register the module parameters the optimizer may change, the joints they apply to, and the values they may take. The algorithm settings start at the thesis's values."
        }
        Page::Summary => {
            "The files below will be written. Save them, then open the simulation in the control window."
        }
    }
}

/// The current page with its navigation.
pub fn show(ui: &mut egui::Ui, state: &mut SetupState) {
    let (i, n) = state.wizard.progress();
    let page = state.wizard.page;
    ui.heading(format!("Step {i} of {n}: {}", page.title()));
    ui.label(explanation(page));
    ui.separator();
    egui::ScrollArea::vertical()
        .max_height(ui.available_height() - 40.0)
        .show(ui, |ui| match page {
            Page::Robot => robot_page(ui, &mut state.wizard),
            Page::Behaviour => behaviour_page(ui, &mut state.wizard),
            Page::Environment => {
                ui.label(format!(
                    "{} objects in the scene; the library is on the left, the selection's properties on the right.",
                    state.wizard.env.objects.len()
                ));
            }
            Page::Simulation => simulation_page(ui, &mut state.wizard),
            Page::Optimization => optimization_page(ui, &mut state.wizard),
            Page::Summary => summary_page(ui, state),
        });
    ui.separator();
    ui.horizontal(|ui| {
        if ui.add_enabled(i > 1, egui::Button::new("◀ Back")).clicked() {
            state.wizard.back();
        }
        if page.optional() && ui.button("Skip").clicked() {
            let r = state.wizard.skip();
            state.report(r, |_| "page skipped: defaults kept".into());
        }
        if page != Page::Summary && ui.button("Next ▶").clicked() {
            let r = state.wizard.next_page();
            state.report(r, |_| String::new());
            if matches!(state.status, Some(Status::Info(ref s)) if s.is_empty()) {
                state.status = None;
            }
        }
    });
}

fn robot_page(ui: &mut egui::Ui, w: &mut Wizard) {
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

/// Joint selection state of the behaviour page (egui memory).
fn selection_id() -> egui::Id {
    egui::Id::new("behaviour joint selection")
}

fn behaviour_page(ui: &mut egui::Ui, w: &mut Wizard) {
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

fn simulation_page(ui: &mut egui::Ui, w: &mut Wizard) {
    crate::gui::setup::properties_view::show(ui, &mut w.props, &mut w.description);
    match w.props.mode {
        Mode::GeneticAlgorithm => w.optimization.method = Method::Genetic,
        Mode::GreatDeluge => w.optimization.method = Method::GreatDeluge,
        Mode::CmaEs => w.optimization.method = Method::CmaEs,
        Mode::MapElites => w.optimization.method = Method::MapElites,
        _ => {}
    }
}

fn optimization_page(ui: &mut egui::Ui, w: &mut Wizard) {
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

fn summary_page(ui: &mut egui::Ui, state: &mut SetupState) {
    let files = state.wizard.files();
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
    }
    match state.wizard.compose() {
        Ok(_) => ui.colored_label(
            egui::Color32::DARK_GREEN,
            "✔ the configuration checks (as proleg check)",
        ),
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
