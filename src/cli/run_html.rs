//! `proleg run --html`: the run recorded as a pose stream ([`crate::playback`]) and written
//! as one self-contained 3D replay page; with `--compare FILE` or `--compare-engine ENGINE`,
//! a second run (another simulation file on the same seed, or the same file on another
//! engine) recorded alike and shown beside it on one timeline.

use std::path::{Path, PathBuf};

use crate::cli::error::CliError;
use crate::cli::run::RunRequest;
use crate::config::Simulation;
use crate::config::fitness::Fitness;
use crate::config::simulation::EngineKind;
use crate::control::{ModuleRegistry, load_simulation_in};
use crate::playback::{PoseStream, Recording, record_episode};
use crate::signal::StopFlag;
use crate::sim::engine::EngineSettings;
use crate::sim::{Episode, EpisodeSettings, Simulator};

/// What `--html` wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct HtmlReport {
    /// The page.
    pub file: PathBuf,
    /// Its size (bytes).
    pub bytes: u64,
    /// Frames of each replay on it.
    pub frames: Vec<usize>,
    /// What the second replay shows, when there is one.
    pub beside: Option<String>,
}

/// The label of a run of `file` on `engine`.
pub fn label(file: &Path, engine: EngineKind) -> String {
    let name = file.file_name().map_or_else(
        || file.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    format!("{name} on {engine}")
}

/// How `req` records its replays.
pub fn recording(req: &RunRequest, label: String) -> Recording {
    Recording {
        fps: f64::from(req.fps),
        label,
    }
}

/// The second replay `--compare` / `--compare-engine` ask for, run for `duration` seconds
/// from `seed` (`None` when neither is given).
pub fn compare_stream(
    req: &RunRequest,
    registry: &ModuleRegistry,
    (duration, seed): (f64, u64),
    stop: &StopFlag,
) -> Result<Option<PoseStream>, CliError> {
    if req.compare.is_none() && req.compare_engine.is_none() {
        return Ok(None);
    }
    let file = req.compare.as_ref().unwrap_or(&req.config);
    let engine = req.compare_engine.or(req.engine);
    let sim = load_simulation_in(file, registry)?.with_engine(engine);
    // Physics overrides name one engine's settings: they apply to the same engine only.
    let physics = if req.compare_engine.is_some() {
        ""
    } else {
        req.physics.as_str()
    };
    let settings = EngineSettings::of(&sim, physics)?;
    let opts = crate::cli::run::one_robot(seed, settings);
    let mut simulator = Simulator::with_registry(&sim, &opts, registry)?;
    let rec = recording(req, label(file, simulator.engine_kind()));
    Ok(Some(record_run(
        &sim,
        &mut simulator,
        duration,
        &rec,
        stop,
    )?))
}

/// Runs `duration` seconds of `simulator` (built from `sim`) as one episode, recorded.
fn record_run(
    sim: &Simulation,
    simulator: &mut Simulator,
    duration: f64,
    rec: &Recording,
    stop: &StopFlag,
) -> Result<PoseStream, CliError> {
    let settings = EpisodeSettings::new(simulator, duration, Fitness::Displacement);
    let mut episode = Episode::begin(simulator, settings)?;
    Ok(record_episode(sim, simulator, &mut episode, rec, Some(stop))?.stream)
}

/// Writes the page of `streams` to `file`.
pub fn write_page(file: &Path, streams: &[&PoseStream]) -> Result<HtmlReport, CliError> {
    let bytes = crate::playback::page::write_standalone(file, streams)?;
    Ok(HtmlReport {
        file: file.to_path_buf(),
        bytes,
        frames: streams.iter().map(|s| s.frames).collect(),
        beside: streams.get(1).map(|s| s.label.clone()),
    })
}
