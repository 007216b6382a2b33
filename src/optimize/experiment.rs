//! An optimization recorded in an experiment store, as `proleg optimize CONFIG` and the
//! control window's optimization view run it: [`Experiment::open`] reads the
//! configuration (keeping every file it reads, so the store holds them with the run and
//! a worker on another host needs nothing else), prepares and checks the [`Session`],
//! opens the store and starts the run there (or finds the unfinished one to resume);
//! [`Experiment::run`] runs it and writes the best candidate if asked.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::config::actuation::write_actuation_file;
use crate::config::simulation::EngineKind;
use crate::config::source::{FileSource, MemSource, Overlay};
use crate::config::{FsSource, RecordingSource, Simulation, load_simulation_with};
use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::robust::episode_records;
use crate::optimize::scorer::Recording;
use crate::optimize::session::{Evaluation, RunOutcome, Session};
use crate::optimize::settings::{RunChoices, RunSettings};
use crate::optimize::space::{Genome, SearchSpace};
use crate::optimize::store::{RunInfo, Store, StoreLocation, StoredEval};
use crate::signal::StopFlag;

/// What to optimize and where to record it.
#[derive(Debug, Clone, Default)]
pub struct ExperimentRequest {
    /// The simulation file (its mode an optimization, with an optimizer file).
    pub config: PathBuf,
    /// The physics engine instead of the file's (stored with the run).
    pub engine: Option<EngineKind>,
    /// The run's choices (seed, workers, budget, ...), defaults from the files.
    pub choices: RunChoices,
    /// The store: a SQLite file or a postgres:// URL (default: [`default_store_path`]).
    pub store: Option<String>,
    /// Continue the last unfinished run of the same configuration in the store.
    pub resume: bool,
    /// Write the best candidate here as an actuation file (its networks beside it).
    pub out: Option<PathBuf>,
    /// Raised to end the run after its current round (a signal, the window's Stop).
    pub stop: StopFlag,
    /// Testing aid: abort (like kill -9) once this many evaluations are stored.
    pub crash_after: Option<u64>,
    /// A curriculum's stage ([`crate::optimize::curriculum`]); none: the configuration as
    /// written, which must not be a curriculum.
    pub stage: Option<StageRequest>,
}

/// One stage of a curriculum as a run of its own: the optimizer file rewritten to train on
/// the stage's tasks (what the store keeps with the run, so workers and replays build the
/// stage's courses), its start and the score that ends it.
#[derive(Debug, Clone, PartialEq)]
pub struct StageRequest {
    /// The stage's name in the store ("curriculum stage 2 of 3 (steps-medium)"): part of
    /// the run's algorithm, which `--resume` matches.
    pub label: String,
    /// The optimizer file's path and the stage's text of it.
    pub optimizer: (PathBuf, String),
    /// The start candidate (the previous stage's best); none: the configured start.
    pub start: Option<Genome>,
    /// The best score that ends the stage (none: the budget does).
    pub until: Option<f64>,
    /// With `--resume`, a stage the store does not hold starts anew instead of failing
    /// (every stage but the first).
    pub may_start: bool,
}

/// An experiment opened: its run started (or found) in the store, ready to run.
pub struct Experiment {
    sim: Simulation,
    session: Session,
    store: Store,
    run: i64,
    known: Vec<StoredEval>,
    out: Option<PathBuf>,
    crash_after: Option<u64>,
    /// Co-design part files that did not load (the first body that needs them fails).
    pub warnings: Vec<String>,
}

/// What an optimization run found and how fast it went.
#[derive(Debug, Clone, PartialEq)]
pub struct ExperimentReport {
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
    pub engine: EngineKind,
    /// The best candidate's score on each engine (runs with `<engines>`; else empty).
    pub best_engines: Vec<(EngineKind, f64)>,
    /// A curriculum's stages, in order, this run the last (else empty).
    pub curriculum: Vec<crate::optimize::curriculum::StageSummary>,
}

impl ExperimentReport {
    /// Evaluations simulated per wall hour (0 when everything came from the store).
    pub fn per_hour(&self) -> f64 {
        self.outcome.simulated as f64 / self.wall.max(1e-9) * 3600.0
    }
}

impl Experiment {
    /// Loads and prepares `request`'s configuration, refuses bad choices before the store
    /// is touched, then opens the store and its run.
    pub fn open(
        request: &ExperimentRequest,
        registry: &ModuleRegistry,
    ) -> Result<Experiment, OptimizeError> {
        let overlay = request.stage.as_ref().map(|stage| Overlay {
            top: MemSource::new().with(&stage.optimizer.0, stage.optimizer.1.clone()),
            base: &FsSource,
        });
        let base: &dyn FileSource = match &overlay {
            Some(o) => o,
            None => &FsSource,
        };
        let source = RecordingSource::new(base);
        let sim = load_simulation_with(&source, &request.config, registry)
            .map_err(|e| OptimizeError::Config(Box::new(e)))?
            .with_engine(request.engine);
        if let Some(model) = &sim.optimizer
            && request.stage.is_none()
            && model
                .spec
                .courses
                .as_ref()
                .is_some_and(|c| !c.stages.is_empty())
        {
            return Err(OptimizeError::CurriculumAsOneRun {
                file: model.file.clone(),
            });
        }
        let warnings = design_part_warnings(&source, &sim);
        let settings = RunSettings {
            stop: request.stop.clone(),
            until: request.stage.as_ref().and_then(|s| s.until),
            ..RunSettings::of(&sim, &request.choices)?
        };
        let location = match &request.store {
            Some(text) => StoreLocation::parse(text)?,
            None => StoreLocation::sqlite(default_store_path(&request.config)),
        };
        let shared = matches!(location, StoreLocation::Postgres(_));
        let mut session = Session::prepare(&sim, &settings, registry, shared)?;
        if let Some(start) = request.stage.as_ref().and_then(|s| s.start.clone()) {
            session = session.starting_from(start)?;
        }
        let mut store = Store::open(&location)?;
        let mut info = run_info(&sim, session.space(), &settings);
        if let Some(stage) = &request.stage {
            info.algorithm = format!("{}, {}", info.algorithm, stage.label);
        }
        let files = stored_files(&source, &request.config, &sim);
        let found = match (request.resume, &request.stage) {
            (false, _) => None,
            (true, None) => Some(resumed_run(&mut store, &info)?),
            (true, Some(stage)) => match latest_run(&mut store, &info)? {
                Some(found) => Some(found),
                None if stage.may_start => None,
                None => Some(resumed_run(&mut store, &info)?),
            },
        };
        let (run, known) = match found {
            Some(found) => found,
            None => {
                let episodes = episode_records(&sim, settings.seed);
                (store.start_run(&info, &files, &episodes)?, Vec::new())
            }
        };
        Ok(Experiment {
            sim,
            session,
            store,
            run,
            known,
            out: request.out.clone(),
            crash_after: request.crash_after,
            warnings,
        })
    }

    /// The simulation as loaded (with the engine chosen).
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// The prepared session (search space, settings).
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// The store as it may be shown (no password) and the run's id in it.
    pub fn run_id(&self) -> (String, i64) {
        (self.store.describe(), self.run)
    }

    /// Evaluations an earlier attempt stored (resuming; else 0).
    pub fn stored(&self) -> usize {
        self.known.len()
    }

    /// Runs the experiment, telling `on_eval` of every evaluation, and writes the best
    /// candidate where the request asked.
    pub fn run(
        mut self,
        registry: &ModuleRegistry,
        on_eval: impl FnMut(&Evaluation),
    ) -> Result<ExperimentReport, OptimizeError> {
        let shown = self.store.describe();
        let recording = Recording {
            store: &mut self.store,
            run: self.run,
            known: std::mem::take(&mut self.known),
            crash_after: self.crash_after,
        };
        let t = Instant::now();
        let outcome = self.session.run(registry, Some(recording), on_eval)?;
        let wall = t.elapsed().as_secs_f64();
        let space = self.session.space();
        if let Some(p) = &self.out {
            write_best(p, &self.sim, space, registry, &outcome.best)?;
        }
        let settings = self.session.settings();
        Ok(ExperimentReport {
            best_values: space
                .genes
                .iter()
                .zip(space.decode(&outcome.best))
                .map(|(g, v)| (g.label(), v))
                .collect(),
            best_engines: outcome.best_engines.clone(),
            outcome,
            wall,
            duration: settings.duration,
            episodes: episodes_per_candidate(&self.sim),
            workers: settings.workers,
            space_size: space.size(),
            store: (shown, self.run),
            actuation: self.out.clone(),
            engine: self.sim.engine(),
            curriculum: Vec::new(),
        })
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

/// The optimizer's name as its file gives it.
pub fn algorithm_label(sim: &Simulation) -> &'static str {
    sim.optimizer
        .as_ref()
        .map(|m| m.spec.label())
        .unwrap_or("?")
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
        (None, EngineKind::Rapier) => algorithm_label(sim).to_string(),
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
    space: &SearchSpace,
    registry: &ModuleRegistry,
    best: &[u32],
) -> Result<(), OptimizeError> {
    let file = crate::optimize::result::write_candidate(path, sim, space, registry, best)?;
    std::fs::write(path, write_actuation_file(&file)).map_err(|source| OptimizeError::Write {
        path: path.to_path_buf(),
        source,
    })
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
fn design_part_warnings(source: &RecordingSource, sim: &Simulation) -> Vec<String> {
    // Resolving the sample bodies reads, and so records, every file they use.
    match crate::optimize::design::body_files(sim, source) {
        Ok(_) => Vec::new(),
        Err(e) => vec![format!("co-design parts: {e}")],
    }
}

/// The last run matching `info`, finished or not, with its stored evaluations: a
/// curriculum's stage resumed (a finished stage is replayed from the store, simulating
/// nothing, to its same best).
fn latest_run(
    store: &mut Store,
    info: &RunInfo,
) -> Result<Option<(i64, Vec<StoredEval>)>, OptimizeError> {
    match store.latest_run(info)? {
        Some(id) => Ok(Some((id, store.evaluations(id)?))),
        None => Ok(None),
    }
}

/// The last unfinished run matching `info`, with its stored evaluations.
fn resumed_run(store: &mut Store, info: &RunInfo) -> Result<(i64, Vec<StoredEval>), OptimizeError> {
    let Some(id) = store.find_unfinished(info)? else {
        return Err(OptimizeError::NothingToResume {
            store: store.describe(),
            config: info.config.clone(),
            seed: info.seed,
            fitness: info.fitness.clone(),
            duration: info.duration,
        });
    };
    Ok((id, store.evaluations(id)?))
}
