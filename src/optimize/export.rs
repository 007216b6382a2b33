//! A stored candidate written as a folder that stands on its own (`proleg results
//! --export-robot`): every file of its run's configuration as the store holds them, in
//! their own layout under the folder, and beside the run's simulation file the candidate's
//! own files and a simulation file that runs it. Nothing in the folder names a file outside
//! it, so it can be moved, shared or kept with a paper and still runs.

use std::path::{Path, PathBuf};

use crate::config::actuation::write_actuation_file;
use crate::config::bundle::write_bundle;
use crate::config::simulation::{FileRef, Mode, write_simulation_file};
use crate::config::source::FsSource;
use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::prepare::prepare;
use crate::optimize::store::{RunSpec, Store};

/// Writes evaluation `number` (with `None`, the best one) of run `run` into `dir` and
/// returns the simulation file that runs it, checked to load from there: for a co-design
/// run its body (`design.robot.xml`, `design.actuation.xml`, `design.simulation.xml`), for
/// any other run the candidate's actuation file (`candidate.actuation.xml`, with its
/// networks' weights beside it) and `candidate.simulation.xml`.
pub fn export_candidate(
    store: &mut Store,
    run: i64,
    number: Option<u64>,
    dir: &Path,
    registry: &ModuleRegistry,
) -> Result<PathBuf, OptimizeError> {
    let spec = store.run_spec(run)?;
    crate::optimize::shared::candidate_run(&spec)
        .map_err(|why| OptimizeError::Unevaluable { run, why })?;
    let evaluations = store.evaluations(run)?;
    let chosen = match number {
        Some(n) => evaluations.iter().find(|e| e.number == n),
        None => evaluations
            .iter()
            .filter(|e| e.score.is_finite())
            .max_by(|a, b| a.score.total_cmp(&b.score)),
    }
    .ok_or_else(|| crate::optimize::store::StoreError::NoRun {
        store: store.describe(),
        run,
    })?;
    let sim_file = write_configuration(&spec, dir)?;
    let sim_dir = sim_file.parent().unwrap_or(dir).to_path_buf();
    let mut sim = crate::control::load_simulation_in(&sim_file, registry).map_err(|e| {
        OptimizeError::DesignFiles {
            dir: dir.to_path_buf(),
            source: Box::new(e),
        }
    })?;
    // The candidate's file runs the episode it was scored on: the run's seed and duration
    // (`--duration` may have shortened the file's).
    let props = &mut sim.files.simulation.properties;
    props.seed = spec.info.seed;
    props.duration = spec.info.duration;
    let design = crate::optimize::design::Design::of(&sim, std::sync::Arc::new(FsSource));
    let main = match design {
        Some(design) => {
            let files = design.files(&chosen.genome, &sim_dir);
            for (p, t) in &files {
                write(p, t)?;
            }
            files[2].0.clone()
        }
        None => {
            let (space, _) = prepare(&sim, registry)?;
            let actuation = sim_dir.join("candidate.actuation.xml");
            let file = crate::optimize::result::write_candidate(
                &actuation,
                &sim,
                &space,
                registry,
                &chosen.genome,
            )?;
            write(&actuation, &write_actuation_file(&file))?;
            let mut runs_it = sim.files.simulation.clone();
            runs_it.actuation = FileRef {
                path: "candidate.actuation.xml".into(),
                pos: crate::config::error::Pos::new(0, 0),
            };
            runs_it.optimizer = None;
            runs_it.properties.mode = Mode::SingleRun;
            let path = sim_dir.join("candidate.simulation.xml");
            write(&path, &write_simulation_file(&runs_it))?;
            path
        }
    };
    crate::control::load_simulation_in(&main, registry).map_err(|e| {
        OptimizeError::DesignFiles {
            dir: dir.to_path_buf(),
            source: Box::new(e),
        }
    })?;
    Ok(main)
}

/// Writes the run's stored files under `dir` in their own layout and returns where its
/// simulation file went. The stored simulation file is written as it was run (single-run
/// mode is set only in the candidate's own file).
fn write_configuration(spec: &RunSpec, dir: &Path) -> Result<PathBuf, OptimizeError> {
    let layout = write_bundle(&spec.files, dir)?;
    Ok(layout.place(Path::new(&spec.info.config)))
}

fn write(path: &Path, text: &str) -> Result<(), OptimizeError> {
    std::fs::write(path, text).map_err(|source| OptimizeError::Write {
        path: path.to_path_buf(),
        source,
    })
}
