//! `proleg optimize`: a headless optimization run of a simulation whose mode is the genetic
//! algorithm or the great deluge, with progress, a table of every evaluation, and the
//! best candidate written back as an actuation file.

use std::fmt::{self, Write as _};
use std::fs::File;
use std::io::{BufWriter, Write as _};
use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use crate::cli::error::CliError;
use crate::config::actuation::write_actuation_file;
use crate::config::{FsSource, RecordingSource, Simulation, load_simulation_with};
use crate::control::ModuleRegistry;
use crate::optimize::fitness::Fitness;
use crate::optimize::robust::episode_records;
use crate::optimize::run::{
    Evaluation, Recording, RunChoices, RunOutcome, RunSettings, check_workers, optimize, prepare,
};
use crate::optimize::space::SearchSpace;
use crate::optimize::store::{EpisodeRecord, RunInfo, Store, StoreLocation, StoredEval};

/// Command-line options of `proleg optimize`.
#[derive(clap::Args)]
pub struct OptimizeOptions {
    /// A `*.simulation.xml` file whose mode is "Genetic Algorithm" or "Great Deluge".
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
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizeReport {
    /// The optimizer's outcome (best candidate, scores, evaluations, batching).
    pub outcome: RunOutcome,
    /// Wall seconds of the run.
    pub wall: f64,
    /// Simulated seconds per episode.
    pub duration: f64,
    /// Episodes per evaluation (robust fitness; else 1).
    pub episodes: u32,
    /// Worker threads.
    pub workers: usize,
    /// Candidates in the search space (eq. 3.3 / 3.5).
    pub space_size: f64,
    /// The best candidate's parameter values, by gene label.
    pub best_values: Vec<(String, f64)>,
    /// The experiment store (as it may be shown: no password) and the run's id in it.
    pub store: (String, i64),
    /// Where the best candidate was written as an actuation file.
    pub actuation: Option<PathBuf>,
    /// The physics engine the candidates ran on.
    pub engine: crate::config::simulation::EngineKind,
    /// The best candidate's score on each engine (runs with `<engines>`; else empty).
    pub best_engines: Vec<(crate::config::simulation::EngineKind, f64)>,
}

impl OptimizeReport {
    /// Evaluations simulated per wall hour (0 when everything came from the store).
    pub fn per_hour(&self) -> f64 {
        self.outcome.simulated as f64 / self.wall.max(1e-9) * 3600.0
    }
}

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
/// any) instead of drawing a progress bar: the control window's optimization view runs
/// its optimizations through here, so they are stored like the command line's.
pub fn run_observed(
    o: &OptimizeOptions,
    registry: &ModuleRegistry,
    on_eval: &mut dyn FnMut(&Evaluation, Option<u64>),
) -> Result<OptimizeReport, CliError> {
    // Every file the configuration reads is kept: the store holds it with the run, so a
    // worker on another host needs nothing but the store.
    let source = RecordingSource::new(&FsSource);
    let sim = load_simulation_with(&source, &o.config, registry)?.with_engine(o.engine);
    record_design_parts(&source, &sim);
    let fitness = o.fitness.as_deref().map(Fitness::parse).transpose()?;
    let settings = RunSettings::of(&sim, &o.choices(fitness))?;
    let (space, _) = prepare(&sim, registry)?;
    let location = match &o.store {
        Some(text) => StoreLocation::parse(text)?,
        None => StoreLocation::sqlite(default_store_path(&o.config)),
    };
    let shared = matches!(location, StoreLocation::Postgres(_));
    // Bad choices are refused before the store is touched.
    check_workers(&settings, shared)?;
    let mut store = Store::open(&location)?;
    if !o.quiet {
        eprint!("{}", header(&sim, &space, &settings));
    }
    let mut table = open_table(o.evaluations.as_deref(), &space)?;
    let info = run_info(&sim, &space, &settings);
    let episodes = episode_records(&sim, settings.seed);
    let run_files = (stored_files(&source, &o.config, &sim), episodes);
    let (run, known) = open_run(&mut store, &info, &run_files, o.resume, o.quiet)?;
    let shown = store.describe();
    let recording = Recording {
        store: &mut store,
        run,
        known,
        crash_after: o.crash_after,
    };
    let t = Instant::now();
    let budget = Some(settings.max_evaluations).filter(|m| *m != u64::MAX);
    let mut table_error = None;
    let outcome = optimize(
        &sim,
        &settings,
        registry,
        Some(recording),
        |e: &Evaluation| {
            if let Some(w) = table.as_mut()
                && let Err(err) = write_row(w, &space, e)
            {
                table_error.get_or_insert(err);
            }
            on_eval(e, budget);
        },
    );
    let outcome = outcome?;
    let table_path = o.evaluations.as_deref().unwrap_or(Path::new(""));
    if let Some(mut w) = table
        && let Err(e) = w.flush()
    {
        table_error.get_or_insert(e);
    }
    if let Some(e) = table_error {
        return Err(CliError::write(table_path)(e));
    }
    let wall = t.elapsed().as_secs_f64();
    let best_engines = store
        .runs()?
        .into_iter()
        .find(|r| r.id == run)
        .map(|r| r.best_engines)
        .unwrap_or_default();
    if let Some(p) = &o.out {
        write_best(p, &sim, (&space, registry), &outcome.best)?;
    }
    Ok(OptimizeReport {
        best_values: space
            .genes
            .iter()
            .zip(space.decode(&outcome.best))
            .map(|(g, v)| (g.label(), v))
            .collect(),
        outcome,
        wall,
        duration: settings.duration,
        episodes: episodes_per_candidate(&sim),
        workers: settings.workers,
        space_size: space.size(),
        store: (shown, run),
        actuation: o.out.clone(),
        engine: sim.engine(),
        best_engines,
    })
}

/// What identifies the run in the store; a run on another engine than rapier, or on
/// several, says so in its algorithm ("genetic algorithm on mujoco", "CMA-ES on
/// rapier+mujoco (min)"), so `results` tells the runs apart and `--resume` does not
/// continue a run of other engines.
fn run_info(sim: &Simulation, space: &SearchSpace, settings: &RunSettings) -> RunInfo {
    let cross = sim
        .optimizer
        .as_ref()
        .and_then(|m| m.spec.cross_engine.as_ref());
    let algorithm = match (cross, sim.engine()) {
        (Some(c), _) => format!("{} on {}", algorithm_label(sim), c.describe()),
        (None, crate::config::simulation::EngineKind::Rapier) => algorithm_label(sim).to_string(),
        (None, other) => format!("{} on {other}", algorithm_label(sim)),
    };
    RunInfo {
        config: sim.file.display().to_string(),
        algorithm,
        seed: settings.seed,
        fitness: settings.fitness.name().to_string(),
        duration: settings.duration,
        genes: space.genes.iter().map(|g| g.label()).collect(),
    }
}

/// Episodes per evaluation: the optimizer file's robust fitness K, else 1.
fn episodes_per_candidate(sim: &Simulation) -> u32 {
    sim.optimizer
        .as_ref()
        .and_then(|m| m.spec.robustness)
        .map_or(1, |r| r.episodes)
}

/// Writes the best candidate as an actuation file at `path`; the networks whose weights it
/// searched go to weights files beside it (`NAME.MODULE.safetensors`, F64: the weights
/// scored), which it names.
fn write_best(
    path: &Path,
    sim: &Simulation,
    (space, registry): (&SearchSpace, &ModuleRegistry),
    best: &[u32],
) -> Result<(), CliError> {
    let file = crate::optimize::result::write_candidate(path, sim, (space, registry), best)?;
    std::fs::write(path, write_actuation_file(&file)).map_err(CliError::write(path))
}

/// The optimizer's name as its file gives it.
fn algorithm_label(sim: &Simulation) -> &'static str {
    sim.optimizer
        .as_ref()
        .map(|m| m.spec.label())
        .unwrap_or("?")
}

/// What is optimized: the genes, the problem size, the episode and the workers.
fn header(sim: &Simulation, space: &SearchSpace, settings: &RunSettings) -> String {
    let mut head = String::new();
    let label = algorithm_label(sim);
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
fn write_row(w: &mut BufWriter<File>, space: &SearchSpace, e: &Evaluation) -> std::io::Result<()> {
    let values: Vec<String> = space
        .decode(&e.genome)
        .iter()
        .map(|v| v.to_string())
        .collect();
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

/// The files to store with the run: as read, but the simulation file as `sim` has it when
/// `--engine` changed its engine (workers and replays then build the same world).
fn stored_files(
    source: &RecordingSource,
    config: &Path,
    sim: &Simulation,
) -> Vec<(String, String)> {
    let mut files = source.files();
    let top = crate::config::source::normalize(config)
        .display()
        .to_string();
    for (path, text) in files.iter_mut().filter(|(path, _)| *path == top) {
        let written = crate::config::simulation::parse_simulation_file(path, text)
            .map(|f| f.properties.engine);
        if written.is_ok_and(|e| e != sim.engine()) {
            *text = crate::config::simulation::write_simulation_file(&sim.files.simulation);
        }
    }
    files
}

/// A co-design run's part files (and the sensors and meshes they include), read through
/// `source` so that they are stored with the run (its bodies use parts the configuration's
/// own robot may not): a worker builds the bodies from the store alone. Parts that do not
/// load are a warning naming the file; the first body that needs them fails the run.
fn record_design_parts(source: &RecordingSource, sim: &Simulation) {
    // Resolving the sample bodies reads, and so records, every file they use.
    if let Err(e) = crate::optimize::design::body_files(sim, source) {
        eprintln!("warning: co-design parts: {e}");
    }
}

/// The store of `proleg optimize CONFIG` without `--store`: `CONFIG-STEM.results.sqlite`
/// in the working folder.
pub fn default_store_path(config: &Path) -> PathBuf {
    let stem = config
        .file_name()
        .and_then(|n| n.to_str())
        .map(|n| n.trim_end_matches(".xml").trim_end_matches(".simulation"))
        .unwrap_or("optimize");
    PathBuf::from(format!("{stem}.results.sqlite"))
}

/// A new run in the store (with its configuration `files` and randomized `episodes`), or with `resume` the last
/// unfinished one of the same configuration, seed, fitness and duration with its stored
/// evaluations.
fn open_run(
    store: &mut Store,
    info: &RunInfo,
    (files, episodes): &(Vec<(String, String)>, Vec<EpisodeRecord>),
    resume: bool,
    quiet: bool,
) -> Result<(i64, Vec<StoredEval>), CliError> {
    if !resume {
        return Ok((store.start_run(info, files, episodes)?, Vec::new()));
    }
    let Some(id) = store.find_unfinished(info)? else {
        return Err(CliError::NothingToResume {
            store: store.describe(),
            config: info.config.clone(),
            seed: info.seed,
            fitness: info.fitness.clone(),
            duration: info.duration,
        });
    };
    let known = store.evaluations(id)?;
    if !quiet {
        eprintln!(
            "resuming run {id} of {}: {} evaluations stored",
            store.describe(),
            known.len()
        );
    }
    Ok((id, known))
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

impl fmt::Display for OptimizeReport {
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
            let per_hour = self.per_hour();
            let engines: Vec<&str> = self.best_engines.iter().map(|(k, _)| k.name()).collect();
            let (on, worlds) = match engines.len() {
                0 => (self.engine.name().to_string(), 1.0),
                n => (engines.join("+"), n as f64),
            };
            writeln!(
                out,
                "throughput      {per_hour:.0} evaluations/h of {} on {} ({}); 6000 such evaluations (the thesis's experiment-2 budget, eq. 3.6) take {:.2} h",
                match self.episodes {
                    1 => format!("{} s", self.duration),
                    k => format!("{k} episodes of {} s", self.duration),
                },
                on,
                match self.workers {
                    0 => "all by workers of the shared store".to_string(),
                    w => format!(
                        "{:.1}x real time per local worker",
                        o.simulated as f64 * f64::from(self.episodes) * self.duration * worlds
                            / self.wall
                            / w as f64
                    ),
                },
                6000.0 / per_hour
            )?;
            writeln!(
                out,
                "brute force     {:.3e} candidates at this rate (eq. 3.4) take {:.3e} years",
                self.space_size,
                self.space_size / per_hour / (24.0 * 365.25)
            )?;
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
        Ok(())
    }
}
