//! `proleg optimize`: a headless optimization run of a simulation whose mode is the genetic
//! algorithm or the great deluge, with progress, a table of every evaluation, and the
//! best candidate written back as an actuation file.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use proleg::config::actuation::write_actuation_file;
use proleg::config::load_simulation;
use proleg::optimize::fitness::Fitness;
use proleg::optimize::result::actuation_with;
use proleg::optimize::run::{Evaluation, Recording, RunSettings, optimize, prepare};
use proleg::optimize::store::{RunInfo, Store};

/// Command-line options of `proleg optimize`.
#[derive(clap::Args)]
pub struct OptimizeOptions {
    /// A `*.simulation.xml` file whose mode is "Genetic Algorithm" or "Great Deluge".
    pub config: PathBuf,
    /// Random seed (default: the file's seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Parallel evaluation threads (default: the number of cores).
    #[arg(long)]
    pub workers: Option<usize>,
    /// Robots per world (default 0: each round split evenly over the workers).
    #[arg(long, default_value_t = 0)]
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
    /// The SQLite experiment store (default: CONFIG-STEM.results.sqlite here).
    #[arg(long)]
    pub store: Option<PathBuf>,
    /// Continue the last unfinished run of the same configuration, seed, fitness and
    /// duration in the store, reusing its stored evaluations.
    #[arg(long)]
    pub resume: bool,
    /// No progress on stderr.
    #[arg(long)]
    pub quiet: bool,
    /// Testing aid: abort (like kill -9) once this many evaluations are stored.
    #[arg(long, hide = true)]
    pub crash_after: Option<u64>,
}

pub fn run(o: &OptimizeOptions) -> Result<String, String> {
    let sim = load_simulation(&o.config).map_err(|e| e.to_string())?;
    let props = &sim.files.simulation.properties;
    let duration = o.duration.unwrap_or(props.duration);
    if !duration.is_finite() || duration <= 0.0 {
        return Err(format!(
            "--duration {duration}: give a number of seconds > 0"
        ));
    }
    let spec = sim.optimizer.as_ref().map(|m| &m.spec);
    let fitness = match &o.fitness {
        Some(f) => Fitness::parse(f)?,
        None => spec.map(|s| s.fitness).unwrap_or(Fitness::Displacement),
    };
    let max_evaluations = o.max_evaluations.or(spec.and_then(|s| s.max_evaluations));
    let workers = o.workers.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    if workers == 0 {
        return Err("--workers 0: give at least 1".into());
    }
    let settings = RunSettings {
        seed: o.seed.unwrap_or(props.seed),
        workers,
        batch: o.batch,
        deluge_batch: 8,
        max_evaluations: max_evaluations.unwrap_or(u64::MAX),
        duration,
        fitness,
        stop: Default::default(),
    };
    let (space, _) = prepare(&sim)?;
    let mut head = String::new();
    let label = sim
        .optimizer
        .as_ref()
        .map(|m| m.spec.label())
        .unwrap_or("?");
    let _ = writeln!(head, "optimizing {} with the {label}", sim.file.display());
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
        "problem size (eq. 3.3 / 3.5): {:.3e} candidates; {} s per episode, fitness {}, seed {}, {workers} worker(s)",
        space.size(),
        duration,
        fitness.name(),
        settings.seed
    );
    if !o.quiet {
        eprint!("{head}");
    }
    let mut table = match &o.evaluations {
        Some(p) => {
            let f = std::fs::File::create(p)
                .map_err(|e| format!("{}: cannot create: {e}", p.display()))?;
            let mut w = std::io::BufWriter::new(f);
            let genes: Vec<String> = space.genes.iter().map(|g| g.label()).collect();
            writeln!(w, "evaluation\tround\tscore\tbest\t{}", genes.join("\t"))
                .map_err(|e| format!("{}: {e}", p.display()))?;
            Some(w)
        }
        None => None,
    };
    let store_path = o.store.clone().unwrap_or_else(|| {
        let stem = o
            .config
            .file_name()
            .and_then(|n| n.to_str())
            .map(|n| n.trim_end_matches(".xml").trim_end_matches(".simulation"))
            .unwrap_or("optimize");
        PathBuf::from(format!("{stem}.results.sqlite"))
    });
    let mut store = Store::open(&store_path)?;
    if let Some(n) = o.crash_after {
        store.crash_after(n);
    }
    let info = RunInfo {
        config: sim.file.display().to_string(),
        algorithm: label.to_string(),
        seed: settings.seed,
        fitness: fitness.name().to_string(),
        duration,
        genes: space.genes.iter().map(|g| g.label()).collect(),
    };
    let (run, known) = match (o.resume, store.find_unfinished(&info)?) {
        (true, Some(id)) => {
            let known = store.evaluations(id)?;
            if !o.quiet {
                eprintln!(
                    "resuming run {id} of {}: {} evaluations stored",
                    store_path.display(),
                    known.len()
                );
            }
            (id, known)
        }
        (true, None) => {
            return Err(format!(
                "--resume: {} holds no unfinished run of {} with seed {}, fitness {} and {duration} s episodes",
                store_path.display(),
                sim.file.display(),
                settings.seed,
                fitness.name()
            ));
        }
        (false, _) => (store.start_run(&info)?, Vec::new()),
    };
    let recording = Recording {
        store: &mut store,
        run,
        known,
    };
    let t = Instant::now();
    let bar = if o.quiet {
        ProgressBar::hidden()
    } else {
        match max_evaluations {
            Some(m) => ProgressBar::new(m),
            None => ProgressBar::new_spinner(),
        }
    };
    let style = match max_evaluations {
        Some(_) => "{bar:30} {pos}/{len} evaluations  {msg}  {per_sec}  ETA {eta}",
        None => "{spinner} {pos} evaluations  {msg}  {per_sec}",
    };
    if let Ok(st) = ProgressStyle::with_template(style) {
        bar.set_style(st);
    }
    // Lines for logs when stderr is not a terminal (the bar then stays hidden).
    let log_lines = !o.quiet && bar.is_hidden();
    let mut last_report = 0.0;
    let mut table_error = None;
    let outcome = optimize(&sim, &settings, Some(recording), |e: &Evaluation| {
        if let Some(w) = table.as_mut() {
            let values: Vec<String> = space
                .decode(&e.genome)
                .iter()
                .map(|v| v.to_string())
                .collect();
            if let Err(err) = writeln!(
                w,
                "{}\t{}\t{}\t{}\t{}",
                e.number,
                e.round,
                e.score,
                e.best,
                values.join("\t")
            ) {
                table_error.get_or_insert(err.to_string());
            }
        }
        bar.set_position(e.number + 1);
        bar.set_message(format!("best {:.4}", e.best));
        let secs = t.elapsed().as_secs_f64();
        if log_lines && (secs - last_report >= 10.0 || e.number == 0) {
            last_report = secs;
            let rate = (e.number + 1) as f64 / secs.max(1e-9);
            eprintln!(
                "  evaluations {:>6}  round {:>5}  best {:.4}  {:.0} evaluations/h",
                e.number + 1,
                e.round,
                e.best,
                rate * 3600.0
            );
        }
    });
    bar.finish_and_clear();
    let outcome = outcome?;
    if let Some(mut w) = table {
        w.flush().map_err(|e| e.to_string())?;
    }
    if let Some(e) = table_error {
        return Err(format!("writing the evaluations table: {e}"));
    }
    let wall = t.elapsed().as_secs_f64();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} evaluations in {} rounds ({} simulated, {} from the store), {:.1} s",
        outcome.evaluations,
        outcome.rounds,
        outcome.simulated,
        outcome.evaluations - outcome.simulated,
        wall
    );
    if outcome.simulated > 0 {
        let per_hour = outcome.simulated as f64 / wall * 3600.0;
        let _ = writeln!(
            out,
            "throughput      {per_hour:.0} evaluations/h of {duration} s ({:.1}x real time per worker); 6000 such evaluations (the thesis's experiment-2 budget, eq. 3.6) take {:.2} h",
            outcome.simulated as f64 * duration / wall / workers as f64,
            6000.0 / per_hour
        );
        let _ = writeln!(
            out,
            "brute force     {:.3e} candidates at this rate (eq. 3.4) take {:.3e} years",
            space.size(),
            space.size() / per_hour / (24.0 * 365.25)
        );
    }
    let _ = writeln!(out, "evaluation      {}", outcome.batching);
    let _ = writeln!(out, "store           {} (run {run})", store_path.display());
    if let Some(s0) = outcome.start_score {
        let _ = writeln!(out, "start score {s0:.4} (the configured values)");
    }
    let gain = outcome
        .start_score
        .filter(|s| *s > 0.0)
        .map(|s0| {
            format!(
                " ({:+.1}% over the start)",
                (outcome.best_score / s0 - 1.0) * 100.0
            )
        })
        .unwrap_or_default();
    let _ = writeln!(out, "best score  {:.4}{gain}", outcome.best_score);
    for (g, v) in space.genes.iter().zip(space.decode(&outcome.best)) {
        let _ = writeln!(out, "  {:<40} {v}", g.label());
    }
    if let Some(p) = &o.out {
        let file = actuation_with(&sim, &space, &outcome.best);
        std::fs::write(p, write_actuation_file(&file))
            .map_err(|e| format!("{}: cannot write: {e}", p.display()))?;
        let _ = writeln!(out, "best actuation written to {}", p.display());
    }
    Ok(out)
}
