//! The optimization view: when the simulation's mode is a genetic algorithm or great
//! deluge, run that optimization on headless workers in the background (the same
//! [`crate::optimize::run::optimize`] as `proleg optimize`), show its progress, evaluations
//! per second, a live learning curve and the best candidate's parameter values, and replay
//! the best candidate in the viewer (its values put into the shown robot's kernel). Or
//! attach, read-only, to a run going on elsewhere (a shared `postgres://` store's driver and
//! workers, or any store) and draw its learning curve live
//! ([`crate::optimize::shared::follow::follow_run`]). Below, a store's runs with their
//! Replay action ([`results_view`]).

use std::sync::mpsc::{Receiver, channel};
use std::time::Instant;

use bevy::prelude::*;
use bevy_egui::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints, Points};

use crate::gui::control::results_view::{self, StoredResults};
use crate::gui::control::session::SimSession;
use crate::optimize::run::{
    Evaluation, Outcome, RunChoices, RunSettings, StopFlag, optimize, prepare,
};
use crate::optimize::shared::follow::{FOLLOW_POLL, Followed, follow_run};
use crate::optimize::space::{Genome, SearchSpace};
use crate::optimize::store::StoreLocation;

/// A message from the optimization thread.
enum Report {
    Eval(Evaluation),
    Done(Result<Outcome, String>),
    Detached(Result<Followed, String>),
}

/// The view's state and the running optimization, if any.
#[derive(Resource, Default)]
pub struct OptimizerView {
    /// Whether the window is shown.
    pub open: bool,
    /// Evaluations to run (the optimizer file's maximum when 0).
    pub max_evals: u64,
    /// Worker threads for the next run.
    pub workers: usize,
    /// (evaluation, score, best so far).
    pub curve: Vec<[f64; 3]>,
    /// The best candidate so far and its score.
    pub best: Option<(Genome, f64)>,
    /// When the run started.
    pub started: Option<Instant>,
    /// What the run is doing, or why it stopped.
    pub status: String,
    /// The store to attach to (a path or a postgres:// URL; its run: the latest unfinished).
    pub attach_to: String,
    /// Whether the view follows a run elsewhere (read-only) rather than running its own.
    pub attached: bool,
    /// The stored runs listed, with their Replay action.
    pub results: StoredResults,
    stop: StopFlag,
    rx: Option<std::sync::Mutex<Receiver<Report>>>,
    /// The search space of the session's world (by its generation), built once.
    space: Option<(u64, Option<SearchSpace>)>,
}

impl OptimizerView {
    /// A closed view that will run `workers` evaluation threads.
    pub fn new(workers: usize) -> Self {
        OptimizerView {
            workers,
            ..OptimizerView::default()
        }
    }

    /// Whether a run is going on.
    pub fn running(&self) -> bool {
        self.rx.is_some()
    }

    /// Starts optimizing the session's simulation in a background thread.
    pub fn start(&mut self, session: &SimSession) {
        if self.running() {
            return;
        }
        let sim = session.sim.clone();
        let choices = RunChoices {
            workers: Some(self.workers.max(1)),
            max_evaluations: (self.max_evals > 0).then_some(self.max_evals),
            ..RunChoices::default()
        };
        let settings = match RunSettings::of(&sim, &choices) {
            Ok(s) => s,
            Err(e) => {
                self.status = e;
                return;
            }
        };
        self.stop = settings.stop.clone();
        self.curve.clear();
        self.best = None;
        self.started = Some(Instant::now());
        self.status = "running".into();
        let registry = crate::plugin_host::registry();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let eval_tx = tx.clone();
            let result = optimize(&sim, &settings, &registry, None, |e| {
                let _ = eval_tx.send(Report::Eval(e.clone()));
            });
            let _ = tx.send(Report::Done(result));
        });
        self.rx = Some(std::sync::Mutex::new(rx));
    }

    /// Follows the latest unfinished run of the store `attach_to` names, read-only.
    pub fn attach(&mut self) {
        if self.running() {
            return;
        }
        let location = match StoreLocation::parse(self.attach_to.trim()) {
            Ok(l) => l,
            Err(e) => {
                self.status = e;
                return;
            }
        };
        self.stop = StopFlag::default();
        self.curve.clear();
        self.best = None;
        self.started = Some(Instant::now());
        self.attached = true;
        self.status = format!("attached to {location} (read-only)");
        let stop = self.stop.clone();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let eval_tx = tx.clone();
            let result = follow_run(&location, None, &stop, FOLLOW_POLL, |e| {
                let _ = eval_tx.send(Report::Eval(e.clone()));
            });
            let _ = tx.send(Report::Detached(result));
        });
        self.rx = Some(std::sync::Mutex::new(rx));
    }

    /// Asks the run to end after its current round (detaches from a followed run).
    pub fn stop(&self) {
        self.stop.stop();
    }

    /// Takes the thread's reports.
    pub fn poll(&mut self) {
        let mut done = None;
        if let Some(rx) = &self.rx
            && let Ok(rx) = rx.lock()
        {
            while let Ok(r) = rx.try_recv() {
                match r {
                    Report::Eval(e) => {
                        let score = if e.score.is_finite() {
                            e.score
                        } else {
                            f64::NAN
                        };
                        self.curve.push([e.number as f64 + 1.0, score, e.best]);
                        if self.best.as_ref().is_none_or(|(_, b)| e.score > *b) {
                            self.best = Some((e.genome.clone(), e.score));
                        }
                    }
                    Report::Done(r) => {
                        done = Some(match r {
                            Ok(o) => format!(
                                "finished: {} evaluations, best {:.4} ({})",
                                o.evaluations, o.best_score, o.batching
                            ),
                            Err(e) => format!("failed: {e}"),
                        })
                    }
                    Report::Detached(r) => {
                        done = Some(match r {
                            Ok(f) if f.finished => {
                                format!("run {} finished: {} evaluations", f.run, f.evaluations)
                            }
                            Ok(f) => format!(
                                "detached from run {} after {} evaluations",
                                f.run, f.evaluations
                            ),
                            Err(e) => format!("cannot attach: {e}"),
                        })
                    }
                }
            }
        }
        if let Some(status) = done {
            self.rx = None;
            self.status = status;
        }
    }

    /// Evaluations per second so far.
    pub fn rate(&self) -> f64 {
        let secs = self.started.map_or(0.0, |t| t.elapsed().as_secs_f64());
        if secs > 0.0 {
            self.curve.len() as f64 / secs
        } else {
            0.0
        }
    }
}

/// Puts `genome`'s values into the session's kernel after a restart, and starts it.
pub fn replay(session: &mut SimSession, genome: &Genome) {
    let space = match prepare(&session.sim, &crate::plugin_host::registry()) {
        Ok((space, _)) => space,
        Err(e) => {
            session.error = Some(e);
            return;
        }
    };
    session.restart();
    let applied = session
        .simulator
        .kernel_mut(0)
        .map_err(|e| e.to_string())
        .and_then(|k| space.apply(genome, k).map_err(|e| e.to_string()));
    match applied {
        Ok(()) => session.running = true,
        Err(e) => session.error = Some(e),
    }
}

/// The best candidate's values and its Replay button.
fn best_candidate(
    ui: &mut egui::Ui,
    session: &mut SimSession,
    view: &OptimizerView,
    space: &SearchSpace,
) {
    let Some((genome, score)) = view.best.as_ref() else {
        return;
    };
    ui.label(format!("best candidate ({score:.4}):"));
    for (g, v) in space.genes.iter().zip(space.decode(genome)) {
        ui.monospace(format!("  {} = {v}", g.label()));
    }
    if ui.button("Replay best in the viewer").clicked() {
        replay(session, genome);
    }
}

/// Draws the optimization window (only for optimization modes).
pub fn show(ctx: &egui::Context, session: &mut SimSession, view: &mut OptimizerView) {
    let Some(model) = session.sim.optimizer.as_ref() else {
        return;
    };
    view.poll();
    let label = model.spec.label();
    let (generation, space) = match view.space.take() {
        Some((g, s)) if g == session.generation => (g, s),
        _ => (
            session.generation,
            prepare(&session.sim, &crate::plugin_host::registry())
                .ok()
                .map(|(s, _)| s),
        ),
    };
    let mut open = view.open;
    egui::Window::new("Optimization")
        .open(&mut open)
        .default_size([560.0, 420.0])
        .show(ctx, |ui| {
            ui.label(format!(
                "{label}; {} genes, problem size {:.3e}",
                space.as_ref().map_or(0, |s| s.genes.len()),
                space.as_ref().map_or(0.0, |s| s.size())
            ));
            ui.horizontal(|ui| {
                ui.label("evaluations (0 = file's limit)");
                ui.add(egui::DragValue::new(&mut view.max_evals).range(0..=1_000_000));
                ui.label("workers");
                ui.add(egui::DragValue::new(&mut view.workers).range(1..=64));
                if view.running() && !view.attached {
                    if ui.button("Stop").clicked() {
                        view.stop();
                    }
                } else if ui
                    .add_enabled(!view.running(), egui::Button::new("Start"))
                    .clicked()
                {
                    view.attached = false;
                    view.start(session);
                }
            });
            ui.horizontal(|ui| {
                ui.label("or follow a run elsewhere:");
                ui.add(
                    egui::TextEdit::singleline(&mut view.attach_to)
                        .hint_text("postgres://user@host/db or a .sqlite file")
                        .desired_width(260.0),
                );
                if view.running() && view.attached {
                    if ui.button("Detach").clicked() {
                        view.stop();
                    }
                } else if ui
                    .add_enabled(!view.running(), egui::Button::new("Attach"))
                    .clicked()
                {
                    view.attach();
                }
            });
            let best = view.best.as_ref().map_or(f64::NAN, |b| b.1);
            ui.monospace(format!(
                "{}: {} evaluations, best {:.4}, {:.2} evals/s",
                view.status,
                view.curve.len(),
                best,
                view.rate()
            ));
            Plot::new("learning curve")
                .height(200.0)
                .legend(Legend::default())
                .x_axis_label("evaluation")
                .y_axis_label("score")
                .show(ui, |p| {
                    let scores: Vec<[f64; 2]> = view.curve.iter().map(|c| [c[0], c[1]]).collect();
                    let bests: Vec<[f64; 2]> = view.curve.iter().map(|c| [c[0], c[2]]).collect();
                    p.points(Points::new("score", PlotPoints::from(scores)).radius(1.5));
                    p.line(Line::new("best so far", PlotPoints::from(bests)));
                });
            if let Some(space) = space.as_ref() {
                best_candidate(ui, session, view, space);
            }
            results_view::show(ui, session, &mut view.results);
        });
    view.open = open;
    view.space = Some((generation, space));
}
