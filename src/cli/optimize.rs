//! `proleg optimize`: a headless optimization run of a simulation in an optimization mode
//! (GA, great deluge, CMA-ES, OpenAI-ES or MAP-Elites, as its optimizer file names), with
//! progress, a table of every evaluation, and the best candidate written back as an
//! actuation file.

use std::cell::{Cell, RefCell};
use std::fmt::{self, Write as _};
use std::fs::File;
use std::io::{BufWriter, Write as _};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use crate::cli::error::CliError;
use crate::config::Simulation;
use crate::config::fitness::Fitness;
use crate::control::ModuleRegistry;
use crate::optimize::curriculum::{Curriculum, StageOf, StageSummary, run_request};
use crate::optimize::experiment::{Experiment, ExperimentReport, ExperimentRequest};
use crate::optimize::session::Evaluation;
use crate::optimize::settings::{RunChoices, RunSettings};
use crate::optimize::space::SearchSpace;

pub use crate::optimize::experiment::default_store_path;

/// Command-line options of `proleg optimize`.
#[derive(clap::Args)]
pub struct OptimizeOptions {
    /// A `*.simulation.xml` file in an optimization mode, naming its optimizer file (GA,
    /// great deluge, CMA-ES, OpenAI-ES or MAP-Elites; see docs/formats.md).
    pub config: PathBuf,
    /// Random seed (default: the file's seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Parallel evaluation threads (default: the number of cores; 0 with a postgres://
    /// store: only `proleg worker`s evaluate).
    #[arg(long)]
    pub workers: Option<usize>,
    /// Robots per world (default 1: scores independent of --workers; 0 splits each round
    /// evenly over the workers; more is faster on small robots, but scores can then move
    /// slightly with the batch size, see docs/MEASUREMENTS.md).
    #[arg(long, default_value_t = crate::optimize::settings::DEFAULT_BATCH)]
    pub batch: usize,
    /// Stop after this many evaluations (default: the optimizer file's <maxEvaluations>).
    #[arg(long = "max-evals")]
    pub max_evaluations: Option<u64>,
    /// Simulated seconds per episode (default: the file's duration).
    #[arg(long)]
    pub duration: Option<f64>,
    /// displacement (eq. 3.7), distance, speed or cost-of-transport (default: the
    /// optimizer file's <fitness>, else displacement).
    #[arg(long)]
    pub fitness: Option<String>,
    /// Write the best candidate as an actuation file.
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Write every evaluation (score, best so far, gene values) as TSV.
    #[arg(long)]
    pub evaluations: Option<PathBuf>,
    /// The experiment store: a SQLite file (default: CONFIG-STEM.results.sqlite here), or a
    /// postgres://USER@HOST[:PORT]/DATABASE URL shared with `proleg worker`s on other hosts
    /// (password from the URL, PGPASSWORD or ~/.pgpass; never printed).
    #[arg(long)]
    pub store: Option<String>,
    /// Continue the last unfinished run of the same configuration, seed, fitness and
    /// duration in the store, reusing its stored evaluations.
    #[arg(long)]
    pub resume: bool,
    /// With a postgres:// store: seconds a claim stays valid without a heartbeat (a killed
    /// worker's evaluations are claimed again this long after its last one; default 60).
    #[arg(long)]
    pub lease: Option<f64>,
    /// No progress on stderr.
    #[arg(long)]
    pub quiet: bool,
    /// The physics engine instead of the one the simulation file names (rapier, mujoco);
    /// stored with the run, so workers and replays use it too.
    #[arg(long)]
    pub engine: Option<crate::config::simulation::EngineKind>,
    /// Testing aid: abort (like kill -9) once this many evaluations are stored.
    #[arg(long, hide = true)]
    pub crash_after: Option<u64>,
}

impl OptimizeOptions {
    /// The run's choices these options make, with `fitness` parsed from them.
    fn choices(&self, fitness: Option<Fitness>) -> RunChoices {
        RunChoices {
            seed: self.seed,
            workers: self.workers,
            batch: self.batch,
            max_evaluations: self.max_evaluations,
            duration: self.duration,
            fitness,
            lease: self.lease,
        }
    }
}

/// What an optimization run found and how fast it went.
pub type OptimizeReport = ExperimentReport;

/// Runs the optimization the options ask for; progress goes to stderr unless quiet.
pub fn run(o: &OptimizeOptions, registry: &ModuleRegistry) -> Result<OptimizeReport, CliError> {
    let t = Instant::now();
    let mut progress: Option<Progress> = None;
    let report = run_observed(o, registry, &mut |e: &Evaluation, budget: Option<u64>| {
        progress
            .get_or_insert_with(|| Progress::new(budget, o.quiet))
            .show(e, t.elapsed().as_secs_f64());
    });
    if let Some(p) = progress {
        p.bar.finish_and_clear();
    }
    report
}

/// [`run`], telling `on_eval` of every evaluation (with the run's evaluation budget, if
/// any) instead of drawing a progress bar; the evaluations table and the header on stderr
/// are the command line's own.
pub fn run_observed(
    o: &OptimizeOptions,
    registry: &ModuleRegistry,
    on_eval: &mut dyn FnMut(&Evaluation, Option<u64>),
) -> Result<OptimizeReport, CliError> {
    let fitness = o.fitness.as_deref().map(Fitness::parse).transpose()?;
    // Ctrl-C / SIGTERM abandon the episodes in flight at once (the episode runner sees the
    // flag between chunks); what finished is stored and `--resume` runs the rest. The
    // signal thread says so the moment it arrives.
    let keeps = Arc::new(Mutex::new(String::from("nothing is stored yet")));
    let said = keeps.clone();
    let signal = crate::signal::subscribe_with(move || {
        let keeps = said.lock().map(|k| k.clone()).unwrap_or_default();
        eprintln!(
            "\nstopping: the episodes in flight are abandoned; {keeps} (Ctrl-C again quits at once)"
        );
    })?;
    let request = ExperimentRequest {
        config: o.config.clone(),
        engine: o.engine,
        choices: o.choices(fitness),
        store: o.store.clone(),
        resume: o.resume,
        out: o.out.clone(),
        stop: signal.flag(),
        crash_after: o.crash_after,
        stage: None,
    };
    let table = RefCell::new(Table::new(o.evaluations.as_deref())?);
    // The budget is the first run's (a curriculum's stages share it).
    let budget = Cell::new(None);
    let mut on_open = |stage: Option<StageOf<'_>>, experiment: &Experiment| {
        keep_note(&keeps, experiment);
        if !o.quiet {
            match stage {
                Some(s) => announce_stage(s.curriculum, s.number, experiment, o.resume),
                None => announce(experiment, o.resume),
            }
        }
        table.borrow_mut().head(experiment.session().space());
        if budget.get().is_none() {
            let max = experiment.session().settings().max_evaluations;
            budget.set(Some(Some(max).filter(|m| *m != u64::MAX)));
        }
    };
    let report = run_request(&request, registry, &mut on_open, &mut |e: &Evaluation| {
        table.borrow_mut().row(e);
        on_eval(e, budget.get().flatten());
    })?;
    table.into_inner().finish()?;
    Ok(report)
}

/// What the signal thread says a stop keeps: the experiment's store and run.
fn keep_note(keeps: &Mutex<String>, experiment: &Experiment) {
    let (store, run) = experiment.run_id();
    if let Ok(mut k) = keeps.lock() {
        *k = format!(
            "every finished evaluation is kept in {store} (run {run}); --resume runs the rest"
        );
    }
}

/// The header on stderr: warnings, what is optimized, and the run resumed.
fn announce(experiment: &Experiment, resume: bool) {
    let (sim, session) = (experiment.simulation(), experiment.session());
    for w in &experiment.warnings {
        eprintln!("warning: {w}");
    }
    eprint!("{}", header(sim, session.space(), session.settings()));
    if resume {
        let (store, run) = experiment.run_id();
        eprintln!(
            "resuming run {run} of {store}: {} evaluations stored",
            experiment.stored()
        );
    }
}

/// A curriculum's stage `k` (1-based) on stderr: the header before the first, then the
/// stage's tasks, the score that ends it and its budget.
fn announce_stage(curriculum: &Curriculum, k: usize, experiment: &Experiment, resume: bool) {
    if k == 1 {
        announce(experiment, false);
    }
    let settings = experiment.session().settings();
    let until = settings
        .until
        .map_or("the end of the budget".to_string(), |u| {
            format!("a best score of {u}")
        });
    let (store, run) = experiment.run_id();
    eprintln!(
        "curriculum stage {k} of {}: {} until {until}; run {run} of {store}{}",
        curriculum.len(),
        curriculum.tasks(k - 1).join(" "),
        match (resume, experiment.stored()) {
            (true, n) if n > 0 => format!(", {n} evaluations stored"),
            _ => String::new(),
        }
    );
}

/// The evaluations table (TSV), if asked for: created at once (a path that cannot be
/// written fails before anything runs), its header line written with the first stage's
/// genes, a row per evaluation; the first write error is kept and returned at the end.
struct Table<'a> {
    path: Option<&'a Path>,
    writer: Option<BufWriter<File>>,
    headed: bool,
    error: Option<std::io::Error>,
}

impl<'a> Table<'a> {
    fn new(path: Option<&'a Path>) -> Result<Self, CliError> {
        let writer = path
            .map(|p| {
                File::create(p)
                    .map(BufWriter::new)
                    .map_err(CliError::write(p))
            })
            .transpose()?;
        Ok(Table {
            path,
            writer,
            headed: false,
            error: None,
        })
    }

    /// Writes the header line (once: a curriculum's later stages add rows).
    fn head(&mut self, space: &SearchSpace) {
        if let Some(w) = self.writer.as_mut()
            && !self.headed
        {
            self.headed = true;
            if let Err(e) = write_header(w, space) {
                self.error.get_or_insert(e);
            }
        }
    }

    fn row(&mut self, e: &Evaluation) {
        if let Some(w) = self.writer.as_mut()
            && let Err(err) = write_row(w, e)
        {
            self.error.get_or_insert(err);
        }
    }

    fn finish(mut self) -> Result<(), CliError> {
        if let Some(mut w) = self.writer.take()
            && let Err(e) = w.flush()
        {
            self.error.get_or_insert(e);
        }
        match (self.error, self.path) {
            (Some(e), Some(p)) => Err(CliError::write(p)(e)),
            _ => Ok(()),
        }
    }
}

/// What is optimized: the genes, the problem size, the episode and the workers.
fn header(sim: &Simulation, space: &SearchSpace, settings: &RunSettings) -> String {
    let mut head = String::new();
    let label = crate::optimize::experiment::algorithm_label(sim);
    let cross = sim
        .optimizer
        .as_ref()
        .and_then(|m| m.spec.cross_engine.as_ref());
    let engines = match cross {
        Some(c) => format!("{}: each candidate scored on every engine", c.describe()),
        None => sim.engine().to_string(),
    };
    let _ = writeln!(
        head,
        "optimizing {} with the {label} on {engines}",
        sim.file.display(),
    );
    for g in &space.genes {
        let _ = writeln!(
            head,
            "  gene {:<40} {} values {}..{}",
            g.label(),
            g.alleles.count(),
            g.alleles.value(0),
            g.alleles.value(g.alleles.count().saturating_sub(1))
        );
    }
    let _ = writeln!(
        head,
        "problem size (eq. 3.3 / 3.5): {:.3e} candidates; {} s per episode, fitness {}, seed {}, {} worker(s)",
        space.size(),
        settings.duration,
        settings.fitness.name(),
        settings.seed,
        settings.workers
    );
    let spec = sim.optimizer.as_ref().map(|m| &m.spec);
    if let Some(r) = spec.and_then(|s| s.robustness.as_ref()) {
        let _ = writeln!(head, "robust fitness: {}", r.describe());
    }
    if spec.is_some_and(|s| s.random_start) {
        let _ = writeln!(head, "random start (drawn from seed {})", settings.seed);
    }
    head
}

/// The evaluations table's header line: the columns and the genes.
fn write_header(w: &mut BufWriter<File>, space: &SearchSpace) -> std::io::Result<()> {
    let genes: Vec<String> = space.genes.iter().map(|g| g.label()).collect();
    writeln!(w, "evaluation\tround\tscore\tbest\t{}", genes.join("\t"))
}

/// One evaluation as a table row.
fn write_row(w: &mut BufWriter<File>, e: &Evaluation) -> std::io::Result<()> {
    let values: Vec<String> = e.values.iter().map(|v| v.to_string()).collect();
    writeln!(
        w,
        "{}\t{}\t{}\t{}\t{}",
        e.number,
        e.round,
        e.score,
        e.best,
        values.join("\t")
    )
}

/// Progress on stderr: a bar on a terminal, else a line every 10 s (for logs).
struct Progress {
    bar: ProgressBar,
    log_lines: bool,
    last_report: f64,
}

impl Progress {
    fn new(budget: Option<u64>, quiet: bool) -> Progress {
        let bar = match (quiet, budget) {
            (true, _) => ProgressBar::hidden(),
            (false, Some(m)) => ProgressBar::new(m),
            (false, None) => ProgressBar::new_spinner(),
        };
        let style = match budget {
            Some(_) => "{bar:30} {pos}/{len} evaluations  {msg}  {per_sec}  ETA {eta}",
            None => "{spinner} {pos} evaluations  {msg}  {per_sec}",
        };
        if let Ok(st) = ProgressStyle::with_template(style) {
            bar.set_style(st);
        }
        // Lines for logs when stderr is not a terminal (the bar then stays hidden).
        let log_lines = !quiet && bar.is_hidden();
        Progress {
            bar,
            log_lines,
            last_report: 0.0,
        }
    }

    fn show(&mut self, e: &Evaluation, secs: f64) {
        self.bar.set_position(e.number + 1);
        self.bar.set_message(format!("best {:.4}", e.best));
        if self.log_lines && (secs - self.last_report >= 10.0 || e.number == 0) {
            self.last_report = secs;
            let rate = (e.number + 1) as f64 / secs.max(1e-9);
            eprintln!(
                "  evaluations {:>6}  round {:>5}  best {:.4}  {:.0} evaluations/h",
                e.number + 1,
                e.round,
                e.best,
                rate * 3600.0
            );
        }
    }
}

impl fmt::Display for ExperimentReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        let o = &self.outcome;
        curriculum_lines(&self.curriculum, out)?;
        writeln!(
            out,
            "{} evaluations in {} rounds ({} simulated, {} from the store), {:.1} s",
            o.evaluations,
            o.rounds,
            o.simulated,
            o.evaluations.saturating_sub(o.simulated),
            self.wall
        )?;
        if o.simulated > 0 {
            throughput(self, out)?;
        }
        writeln!(out, "evaluation      {}", o.batching)?;
        let (store, run) = &self.store;
        writeln!(out, "store           {store} (run {run})")?;
        if let Some(s0) = o.start_score {
            let whence = if o.start_drawn {
                "drawn from the seed"
            } else if self.curriculum.last().is_some_and(|s| s.number > 1) {
                "the previous stage's best"
            } else {
                "the configured values"
            };
            writeln!(out, "start score {s0:.4} ({whence})")?;
        }
        let gain = o
            .start_score
            .filter(|s| *s > 0.0)
            .map(|s0| {
                format!(
                    " ({:+.1}% over the start)",
                    (o.best_score / s0 - 1.0) * 100.0
                )
            })
            .unwrap_or_default();
        writeln!(out, "best score  {:.4}{gain}", o.best_score)?;
        for (engine, score) in &self.best_engines {
            writeln!(out, "  on {engine:<8} {score:.4}")?;
        }
        // A network's weights are many: the first few stand for them (the file holds all).
        const SHOWN: usize = 12;
        for (label, v) in self.best_values.iter().take(SHOWN) {
            writeln!(out, "  {label:<40} {v}")?;
        }
        if self.best_values.len() > SHOWN {
            writeln!(
                out,
                "  ... and {} more values",
                self.best_values.len() - SHOWN
            )?;
        }
        if let Some(p) = &self.actuation {
            writeln!(out, "best actuation written to {}", p.display())?;
        }
        if o.stopped {
            writeln!(
                out,
                "stopped         by a signal before the optimizer finished; the run stays unfinished (--resume continues it)"
            )?;
        }
        Ok(())
    }
}

/// A curriculum's stages, one line each, before the last stage's report.
fn curriculum_lines(stages: &[StageSummary], out: &mut fmt::Formatter<'_>) -> fmt::Result {
    for s in stages {
        let ended = match (s.until, s.reached) {
            (Some(u), true) => format!("reached {u}"),
            (Some(u), false) => format!("did not reach {u}: the curriculum ends here"),
            (None, _) => "the last stage".to_string(),
        };
        writeln!(
            out,
            "curriculum stage {} of {} ({}): best {:.4} in {} evaluations ({} simulated), {ended}; run {}",
            s.number,
            s.of,
            s.tasks.join(" "),
            s.best_score,
            s.evaluations,
            s.simulated,
            s.run
        )?;
    }
    if let Some(last) = stages.last() {
        writeln!(out, "the lines below are stage {}'s", last.number)?;
    }
    Ok(())
}

/// The report's throughput lines: evaluations per hour, real time per worker, the thesis's
/// budget and brute force at this rate.
fn throughput(r: &ExperimentReport, out: &mut fmt::Formatter<'_>) -> fmt::Result {
    let o = &r.outcome;
    let per_hour = r.per_hour();
    let engines: Vec<&str> = r.best_engines.iter().map(|(k, _)| k.name()).collect();
    let (on, worlds) = match engines.len() {
        0 => (r.engine.name().to_string(), 1.0),
        n => (engines.join("+"), n as f64),
    };
    writeln!(
        out,
        "throughput      {per_hour:.0} evaluations/h of {} on {} ({}); 6000 such evaluations (the thesis's experiment-2 budget, eq. 3.6) take {:.2} h",
        match r.episodes {
            1 => format!("{} s", r.duration),
            k => format!("{k} episodes of {} s", r.duration),
        },
        on,
        match r.workers {
            0 => "all by workers of the shared store".to_string(),
            w => format!(
                "{:.1}x real time per local worker",
                o.simulated as f64 * f64::from(r.episodes) * r.duration * worlds
                    / r.wall
                    / w as f64
            ),
        },
        6000.0 / per_hour
    )?;
    writeln!(
        out,
        "brute force     {:.3e} candidates at this rate (eq. 3.4) take {:.3e} years",
        r.space_size,
        r.space_size / per_hour / (24.0 * 365.25)
    )?;
    Ok(())
}
