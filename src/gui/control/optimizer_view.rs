//! The optimization view, docked on the window's left: when the simulation's mode is an
//! optimization, run it on headless workers in the background exactly as `proleg optimize
//! CONFIG` does ([`crate::optimize::curriculum::run_request`]: the configuration file as saved,
//! a curriculum's stages one after another,
//! every evaluation stored in a SQLite store, by default the command line's
//! `CONFIG-STEM.results.sqlite`, shown and editable), show its progress, evaluations per
//! second, a live learning curve with the score's name and unit, the best candidate's
//! parameter values, replay the best candidate in the viewer (its values put into the shown
//! robot's kernel) and save it as an actuation file. Or
//! attach, read-only, to a run going on elsewhere (a shared `postgres://` store's driver and
//! workers, or any store) and draw its learning curve live
//! ([`crate::optimize::shared::follow::follow_run`]). Below, a store's runs with their
//! Replay action ([`results_view`]).

use std::sync::mpsc::{Receiver, channel};
use std::time::Instant;

use bevy::prelude::*;
use bevy_egui::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints, Points};

use crate::config::actuation::write_actuation_file;
use crate::config::fitness::Fitness;
use crate::gui::control::results_view::{self, StoredResults};
use crate::gui::control::session::SimSession;
use crate::optimize::curriculum::run_request;
use crate::optimize::error::OptimizeError;
use crate::optimize::experiment::{ExperimentReport, ExperimentRequest, default_store_path};
use crate::optimize::prepare::prepare;
use crate::optimize::result::actuation_with;
use crate::optimize::session::Evaluation;
use crate::optimize::settings::RunChoices;
use crate::optimize::shared::follow::{FOLLOW_POLL, Followed, follow_run};
use crate::optimize::space::{Genome, SearchSpace};
use crate::optimize::store::StoreLocation;
use crate::signal::StopFlag;

pub use crate::gui::error::SaveBestError;

/// A message from the optimization thread.
enum Report {
    Run(Box<crate::optimize::store::RunRow>),
    Eval(Evaluation),
    Done(Box<Result<ExperimentReport, OptimizeError>>),
    Detached(Result<Followed, crate::optimize::store::StoreError>),
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
    /// How the last run ended (empty before one ended).
    pub status: String,
    /// The SQLite store (path) the next run is recorded in.
    pub store: String,
    /// Where "Save best" writes the best candidate's actuation file.
    pub save_to: String,
    /// The score the run maximizes (its name and unit label the axis).
    pub fitness: Option<Fitness>,
    /// The store to attach to (a path or a postgres:// URL; its run: the latest unfinished).
    pub attach_to: String,
    /// Whether the view follows a run elsewhere (read-only) rather than running its own.
    pub attached: bool,
    /// The run being followed (attached), once the store said which.
    pub followed: Option<crate::optimize::store::RunRow>,
    /// The stored runs listed, with their Replay action.
    pub results: StoredResults,
    /// What the last "Save best" did.
    saved: Option<String>,
    /// Where the docked view was drawn last frame (egui points).
    pub panel: Option<egui::Rect>,
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

    /// Fills the store and actuation paths from the session's configuration file when
    /// they are empty (the command line's defaults).
    pub fn default_paths(&mut self, session: &SimSession) {
        if self.store.is_empty() {
            self.store = default_store_path(&session.path).display().to_string();
        }
        if self.save_to.is_empty() {
            let store = default_store_path(&session.path);
            let stem = store.display().to_string();
            let stem = stem.trim_end_matches(".results.sqlite");
            self.save_to = format!("{stem}.best.actuation.xml");
        }
        self.fitness = session.sim.optimizer.as_ref().map(|m| m.spec.fitness);
    }

    /// Starts optimizing the session's configuration file in a background thread, as
    /// `proleg optimize CONFIG --store STORE` would (on the engine shown).
    pub fn start(&mut self, session: &SimSession) {
        if self.running() {
            return;
        }
        self.default_paths(session);
        self.stop = StopFlag::default();
        let request = ExperimentRequest {
            config: session.path.clone(),
            engine: Some(session.simulator.engine_kind()),
            choices: RunChoices {
                workers: Some(self.workers.max(1)),
                max_evaluations: (self.max_evals > 0).then_some(self.max_evals),
                ..RunChoices::default()
            },
            store: Some(self.store.trim().to_string()),
            stop: self.stop.clone(),
            ..ExperimentRequest::default()
        };
        self.curve.clear();
        self.best = None;
        self.started = Some(Instant::now());
        self.status.clear();
        let registry = session.registry.clone();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let eval_tx = tx.clone();
            // The view closing drops the receiver; the run goes on to its end and is
            // stored like any other (`proleg results` lists it).
            // A curriculum's stages run one after another, numbered on as one curve.
            let result = run_request(&request, &registry, &mut |_, _| {}, &mut |e| {
                if eval_tx.send(Report::Eval(e.clone())).is_err() {
                    bevy::log::debug!("evaluation {} not shown: the view is closed", e.number);
                }
            });
            if tx.send(Report::Done(Box::new(result))).is_err() {
                bevy::log::info!("the optimization ended after its view closed; it is stored");
            }
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
                self.status = e.to_string();
                return;
            }
        };
        self.stop = StopFlag::default();
        self.curve.clear();
        self.best = None;
        self.followed = None;
        self.started = Some(Instant::now());
        self.attached = true;
        self.status.clear();
        let stop = self.stop.clone();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let (run_tx, eval_tx) = (tx.clone(), tx.clone());
            // The view closing drops the receiver: following stops.
            let on_run = |r: &crate::optimize::store::RunRow| {
                if run_tx.send(Report::Run(Box::new(r.clone()))).is_err() {
                    stop.stop();
                }
            };
            let result = follow_run(&location, None, &stop, FOLLOW_POLL, on_run, |e| {
                if eval_tx.send(Report::Eval(e.clone())).is_err() {
                    stop.stop();
                }
            });
            if tx.send(Report::Detached(result)).is_err() {
                bevy::log::debug!("stopped following: the view is closed");
            }
        });
        self.rx = Some(std::sync::Mutex::new(rx));
    }

    /// The run followed, as `RUN CONFIG this|other`: whether it searched this window's
    /// genes (its best candidate is then shown as this window's values), for a script's
    /// state file.
    pub fn followed_text(&self) -> String {
        let Some(r) = &self.followed else {
            return "none".into();
        };
        let ours = match &self.space {
            Some((_, Some(space))) => same_genes(r, space),
            _ => false,
        };
        let which = if ours { "this" } else { "other" };
        format!("{} {} {which}", r.id, r.info.config)
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
                    Report::Run(row) => self.followed = Some(*row),
                    Report::Eval(e) => {
                        let score = if e.score.is_finite() {
                            e.score
                        } else {
                            f64::NAN
                        };
                        self.curve.push([e.number as f64 + 1.0, score, e.best]);
                        // The best of the run, or of a curriculum's latest stage (its
                        // scores are on other courses than the stage before): an
                        // evaluation that is its run's best so far, unless it only ties.
                        if e.score == e.best && self.best.as_ref().is_none_or(|(_, b)| e.best != *b)
                        {
                            self.best = Some((e.genome.clone(), e.score));
                        }
                    }
                    Report::Done(r) => {
                        done = Some(match *r {
                            Ok(o) => {
                                self.results.store = self.store.clone();
                                self.results.list();
                                self.finished_status(&o)
                            }
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

    /// How a run ended: its evaluations, best and run in the store; for a curriculum, every
    /// stage's evaluations and the last stage's best.
    fn finished_status(&self, o: &ExperimentReport) -> String {
        let (first, last) = match (o.curriculum.first(), o.curriculum.last()) {
            (Some(first), Some(last)) => (first, last),
            _ => {
                return format!(
                    "finished: {} evaluations in {:.0} s, best {}; stored as run {} in {}",
                    o.outcome.evaluations,
                    o.wall,
                    self.score_text(o.outcome.best_score),
                    o.store.1,
                    o.store.0
                );
            }
        };
        let evaluations: u64 = o.curriculum.iter().map(|s| s.evaluations).sum();
        format!(
            "finished: curriculum stages 1-{} of {}, {evaluations} evaluations; stage {} ({}): best {}; stored as runs {}-{} in {}",
            last.number,
            last.of,
            last.number,
            last.tasks.join(" "),
            self.score_text(o.outcome.best_score),
            first.run,
            last.run,
            o.store.0
        )
    }

    /// A score with its unit ("3.4765 m").
    fn score_text(&self, score: f64) -> String {
        match self.fitness {
            Some(f) if f.unit() != "1" => format!("{score:.4} {}", f.unit()),
            _ => format!("{score:.4}"),
        }
    }

    /// The one status line: what the run does now, or how the last one ended.
    pub fn status_line(&self) -> String {
        if self.running() {
            let best = self
                .best
                .as_ref()
                .map_or("none yet".to_string(), |b| self.score_text(b.1));
            let doing = if self.attached {
                "following (read-only)"
            } else {
                "running"
            };
            format!(
                "{doing}: {} evaluations, best {best}, {:.2} evaluations/s",
                self.curve.len(),
                self.rate()
            )
        } else if self.status.is_empty() {
            format!("not started; runs are stored in {}", self.store)
        } else {
            self.status.clone()
        }
    }

    /// Writes the best candidate as an actuation file at `save_to`; returns the file.
    pub fn save_best(
        &self,
        session: &SimSession,
        space: &SearchSpace,
    ) -> Result<std::path::PathBuf, SaveBestError> {
        let (genome, _) = self.best.as_ref().ok_or(SaveBestError::NoCandidate)?;
        let path = std::path::PathBuf::from(self.save_to.trim());
        let file = actuation_with(&session.sim, space, genome);
        std::fs::write(&path, write_actuation_file(&file)).map_err(|source| {
            SaveBestError::Write {
                path: path.clone(),
                source,
            }
        })?;
        Ok(path)
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
    let space = match prepare(&session.sim, &session.registry) {
        Ok((space, _)) => space,
        Err(e) => {
            session.error = Some(e.to_string());
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

/// Whether run `r` searched the genes of `space` (the window's configuration).
fn same_genes(r: &crate::optimize::store::RunRow, space: &SearchSpace) -> bool {
    r.info.genes.len() == space.genes.len()
        && r.info
            .genes
            .iter()
            .zip(&space.genes)
            .all(|(a, g)| *a == g.label())
}

/// The best candidate's values and its Replay button.
fn best_candidate(
    ui: &mut egui::Ui,
    session: &mut SimSession,
    view: &mut OptimizerView,
    space: &SearchSpace,
    saved: &mut Option<String>,
) {
    let Some((genome, score)) = view.best.clone() else {
        return;
    };
    let (genome, score) = (&genome, &score);
    ui.label(format!("best candidate ({}):", view.score_text(*score)));
    // A followed run of another configuration: its genes are not this window's.
    if let Some(run) = view.followed.as_ref().filter(|r| !same_genes(r, space)) {
        ui.label(format!(
            "run {} is of {} ({}), not this window's configuration:",
            run.id, run.info.config, run.info.algorithm
        ));
        let values = run.best_values.iter().flatten();
        for (gene, value) in run.info.genes.iter().zip(values) {
            ui.monospace(format!("  {gene} {value}"));
        }
        ui.label(format!(
            "replay it with proleg gui --replay STORE --run {}",
            run.id
        ));
        return;
    }
    for (g, v) in space.genes.iter().zip(space.decode(genome)) {
        ui.monospace(format!("  {} = {v}", g.label()));
    }
    if ui.button("Replay best in the viewer").clicked() {
        replay(session, genome);
    }
    ui.horizontal(|ui| {
        if ui
            .button("Save best")
            .on_hover_text("writes the best candidate as an actuation file")
            .clicked()
        {
            *saved = Some(match view.save_best(session, space) {
                Ok(p) => format!("saved the best candidate to {}", p.display()),
                Err(e) => format!("error: {e}"),
            });
        }
        ui.add(egui::TextEdit::singleline(&mut view.save_to).desired_width(f32::INFINITY));
    });
    if let Some(m) = saved.as_ref() {
        ui.label(m);
    }
}

/// Draws the optimization view, docked on the left of `root` (only for optimization
/// modes).
pub fn show(root: &mut egui::Ui, session: &mut SimSession, view: &mut OptimizerView) {
    let Some(model) = session.sim.optimizer.as_ref() else {
        return;
    };
    view.poll();
    if view.store.is_empty() || view.fitness.is_none() {
        view.default_paths(session);
    }
    let label = model.spec.label();
    let (generation, space) = match view.space.take() {
        Some((g, s)) if g == session.generation => (g, s),
        _ => (
            session.generation,
            prepare(&session.sim, &session.registry)
                .ok()
                .map(|(s, _)| s),
        ),
    };
    let drawn = egui::Panel::left("optimization")
        .resizable(true)
        .default_size(440.0)
        .show(root, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("Optimization");
                ui.label(format!(
                    "{label}; {} genes, problem size {:.3e}",
                    space.as_ref().map_or(0, |s| s.genes.len()),
                    space.as_ref().map_or(0.0, |s| s.size())
                ));
                controls(ui, session, view);
                ui.add(
                    egui::Label::new(egui::RichText::new(view.status_line()).monospace()).wrap(),
                );
                learning_curve(ui, view);
                if let Some(space) = space.as_ref() {
                    let mut saved = view.saved.take();
                    best_candidate(ui, session, view, space, &mut saved);
                    view.saved = saved;
                }
                results_view::show(ui, session, &mut view.results);
            });
        });
    view.panel = Some(drawn.response.rect);
    view.space = Some((generation, space));
}

/// Evaluations, workers, the store, Start / Stop, and attaching to a run elsewhere.
fn controls(ui: &mut egui::Ui, session: &mut SimSession, view: &mut OptimizerView) {
    ui.horizontal(|ui| {
        ui.label("evaluations (0 = file's limit)");
        ui.add(egui::DragValue::new(&mut view.max_evals).range(0..=1_000_000));
        ui.label("workers");
        ui.add(egui::DragValue::new(&mut view.workers).range(1..=64));
    });
    ui.horizontal(|ui| {
        ui.label("store");
        ui.add_enabled(
            !view.running(),
            egui::TextEdit::singleline(&mut view.store).desired_width(f32::INFINITY),
        )
        .on_hover_text("a SQLite file; `proleg results FILE` lists its runs");
    });
    ui.horizontal(|ui| {
        if view.running() && !view.attached {
            if ui.button("Stop").clicked() {
                view.stop();
            }
        } else if ui
            .add_enabled(!view.running(), egui::Button::new("Start"))
            .on_hover_text("optimizes the configuration file as saved, like proleg optimize")
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
                .desired_width(200.0),
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
}

/// Scores and the best so far per evaluation, the axis named by the fitness and its unit.
fn learning_curve(ui: &mut egui::Ui, view: &OptimizerView) {
    let axis = view.fitness.map_or("score".to_string(), |f| {
        format!("score: {}", f.axis_label())
    });
    Plot::new("learning curve")
        .height(200.0)
        .legend(Legend::default())
        .x_axis_label("evaluation")
        .y_axis_label(axis)
        .show(ui, |p| {
            let scores: Vec<[f64; 2]> = view.curve.iter().map(|c| [c[0], c[1]]).collect();
            let bests: Vec<[f64; 2]> = view.curve.iter().map(|c| [c[0], c[2]]).collect();
            p.points(Points::new("score", PlotPoints::from(scores)).radius(1.5));
            p.line(Line::new("best so far", PlotPoints::from(bests)));
        });
}

/// The optimization view, its workers as many as the cores.
pub struct OptimizerViewPlugin;

impl Plugin for OptimizerViewPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(OptimizerView::new(
            std::thread::available_parallelism().map_or(1, |n| n.get()),
        ));
    }
}
