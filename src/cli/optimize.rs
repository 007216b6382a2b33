//! `proleg optimize`: a headless optimization run of a simulation in an optimization mode
//! (GA, great deluge, CMA-ES, OpenAI-ES or MAP-Elites, as its optimizer file names), with
//! progress, a table of every evaluation, and the best candidate written back as an
//! actuation file.

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
    };
    let experiment = Experiment::open(&request, registry)?;
    let (store, run) = experiment.run_id();
    if let Ok(mut k) = keeps.lock() {
        *k = format!(
            "every finished evaluation is kept in {store} (run {run}); --resume runs the rest"
        );
    }
    let (sim, session) = (experiment.simulation(), experiment.session());
    if !o.quiet {
        for w in &experiment.warnings {
            eprintln!("warning: {w}");
        }
        eprint!("{}", header(sim, session.space(), session.settings()));
        if o.resume {
            let (store, run) = experiment.run_id();
            eprintln!(
                "resuming run {run} of {store}: {} evaluations stored",
                experiment.stored()
            );
        }
    }
    let space = session.space().clone();
    let mut table = open_table(o.evaluations.as_deref(), &space)?;
    let max = session.settings().max_evaluations;
    let budget = Some(max).filter(|m| *m != u64::MAX);
    let mut table_error = None;
    let report = experiment.run(registry, |e: &Evaluation| {
        if let Some(w) = table.as_mut()
            && let Err(err) = write_row(w, e)
        {
            table_error.get_or_insert(err);
        }
        on_eval(e, budget);
    })?;
    let table_path = o.evaluations.as_deref().unwrap_or(Path::new(""));
    if let Some(mut w) = table
        && let Err(e) = w.flush()
    {
        table_error.get_or_insert(e);
    }
    match table_error {
        Some(e) => Err(CliError::write(table_path)(e)),
        None => Ok(report),
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

/// The evaluations table (TSV) with its header line, if asked for.
fn open_table(
    path: Option<&Path>,
    space: &SearchSpace,
) -> Result<Option<BufWriter<File>>, CliError> {
    let Some(p) = path else {
        return Ok(None);
    };
    let f = File::create(p).map_err(CliError::write(p))?;
    let mut w = BufWriter::new(f);
    let genes: Vec<String> = space.genes.iter().map(|g| g.label()).collect();
    writeln!(w, "evaluation\tround\tscore\tbest\t{}", genes.join("\t"))
        .map_err(CliError::write(p))?;
    Ok(Some(w))
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
        writeln!(
            out,
            "{} evaluations in {} rounds ({} simulated, {} from the store), {:.1} s",
            o.evaluations,
            o.rounds,
            o.simulated,
            o.evaluations - o.simulated,
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
