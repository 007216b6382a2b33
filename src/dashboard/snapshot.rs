//! What the dashboard shows, read from the store by one thread: the runs and, for each, its
//! evaluations, read incrementally (a finished run once, an unfinished one from where the
//! last read ended) every [`POLL`]. Every page and event stream reads this in memory, so
//! twenty browsers cost the store what one does. Read-only: the store is opened with
//! [`Store::open_existing`] and only read, which the worker's least-privileged role allows.
//! A store that goes away (a PostgreSQL restart) is opened again; meanwhile the snapshot
//! says it is reconnecting.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};
use std::time::Duration;

use crate::control::ModuleRegistry;
use crate::dashboard::views::MapView;
use crate::optimize::store::pg_queue::QueueState;
use crate::optimize::store::{EpisodeRecord, RunRow, Store, StoreError, StoreLocation, StoredEval};

/// How often the store is read.
pub const POLL: Duration = Duration::from_millis(500);

/// The store as last read.
#[derive(Debug, Default)]
pub struct Snapshot {
    /// The store, as it may be shown (no password).
    pub store: String,
    /// Its runs, oldest first.
    pub runs: Vec<RunRow>,
    /// Each run's evaluations read so far, in number order (those done in order).
    pub evaluations: HashMap<i64, Vec<StoredEval>>,
    /// MAP-Elites runs' archives (`Err`: why it cannot be rebuilt here), kept up to date
    /// as their runs grow; runs of other algorithms have none.
    pub maps: HashMap<i64, Result<MapView, NoArchive>>,
    /// What each run is, read once: its engines and randomized episodes.
    pub details: HashMap<i64, RunDetails>,
    /// Unfinished shared runs' queues and workers, as last read.
    pub queues: HashMap<i64, QueueState>,
    /// Bumped whenever anything above changed (what the event stream announces).
    pub version: u64,
    /// Why the store cannot be read right now (it is being opened again).
    pub reconnecting: Option<String>,
}

/// The snapshot shared between the reader thread and the web server.
pub type Shared = Arc<RwLock<Snapshot>>;

/// What one read of the store found: its runs, and each run's evaluations after those
/// already held.
struct Read {
    runs: Vec<RunRow>,
    new: HashMap<i64, Vec<StoredEval>>,
    maps: HashMap<i64, Result<MapView, NoArchive>>,
    details: HashMap<i64, RunDetails>,
    queues: HashMap<i64, QueueState>,
}

/// What a run is, beyond its row: read once, from its stored configuration.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunDetails {
    /// The engines its candidates are scored on (`<engines>`: each; else the file's).
    pub engines: Vec<String>,
    /// Why the engines are not known (its configuration does not load here).
    pub unloadable: Option<String>,
    /// Its randomized episodes (robust fitness; empty without).
    pub episodes: Vec<EpisodeRecord>,
}

/// Opens the store (an error here is the dashboard's start failing) and reads it once.
pub fn first_read(
    location: &StoreLocation,
    registry: &ModuleRegistry,
) -> Result<(Store, Snapshot), StoreError> {
    let mut store = Store::open_existing(location)?;
    let read = read(&mut store, &Snapshot::default(), registry)?;
    let snapshot = Snapshot {
        store: store.describe(),
        runs: read.runs,
        evaluations: read.new,
        maps: read.maps,
        details: read.details,
        queues: read.queues,
        version: 1,
        reconnecting: None,
    };
    Ok((store, snapshot))
}

/// Reads the store into `shared` every [`POLL`] until `stop` is set, telling `changed` the
/// new version whenever something changed; a store that fails is opened again (the
/// snapshot says so meanwhile).
pub fn keep_reading(
    location: &StoreLocation,
    registry: &ModuleRegistry,
    store: Store,
    shared: &Shared,
    stop: &AtomicBool,
    changed: &dyn Fn(u64),
) {
    let mut store = Some(store);
    while !stop.load(Ordering::Relaxed) {
        std::thread::sleep(POLL);
        let open = match store.take() {
            Some(s) => Ok(s),
            None => Store::open_existing(location),
        };
        let result = open.and_then(|mut s| {
            let found = match shared.read() {
                Ok(held) => read(&mut s, &held, registry),
                Err(_) => read(&mut s, &Snapshot::default(), registry),
            }?;
            Ok((s, found))
        });
        let version = match result {
            Ok((s, found)) => {
                store = Some(s);
                publish(shared, Some(found), None)
            }
            Err(e) => publish(shared, None, Some(e.to_string())),
        };
        if let Some(v) = version {
            changed(v);
        }
    }
}

/// Puts what was read into `shared` (or only that the store cannot be read), bumping the
/// version when something changed: the new version then.
fn publish(shared: &Shared, found: Option<Read>, reconnecting: Option<String>) -> Option<u64> {
    let Ok(mut s) = shared.write() else {
        return None;
    };
    let mut changed = s.reconnecting != reconnecting;
    if let Some(found) = found {
        changed |= s.runs != found.runs;
        for (run, new) in found.new {
            if !new.is_empty() {
                changed = true;
                s.evaluations.entry(run).or_default().extend(new);
            }
        }
        s.runs = found.runs;
        if !found.details.is_empty() {
            changed = true;
            s.details.extend(found.details);
        }
        if s.queues != found.queues {
            changed = true;
            s.queues = found.queues;
        }
        for (run, map) in found.maps {
            if s.maps.get(&run) != Some(&map) {
                changed = true;
                s.maps.insert(run, map);
            }
        }
    }
    s.reconnecting = reconnecting;
    if changed {
        s.version += 1;
        Some(s.version)
    } else {
        None
    }
}

/// Reads the runs, and each run's evaluations after those `held` has (skipping a run that
/// was finished and fully read), keeping only those in number order: an evaluation is
/// shown once all before it are there.
fn read(store: &mut Store, held: &Snapshot, registry: &ModuleRegistry) -> Result<Read, StoreError> {
    let before: HashMap<i64, (bool, u64)> = held
        .runs
        .iter()
        .map(|r| (r.id, (r.finished, r.evaluations)))
        .collect();
    let runs = store.runs()?;
    let mut new = HashMap::new();
    let mut maps = HashMap::new();
    let mut details = HashMap::new();
    let mut queues = HashMap::new();
    for r in &runs {
        let engines_known = held
            .details
            .get(&r.id)
            .is_some_and(|d| r.best_engines.is_empty() || d.engines.len() == r.best_engines.len());
        if !engines_known {
            details.insert(r.id, details_of(store, r, registry)?);
        }
        if !r.finished
            && let Some(q) = store.queue_state(r.id)?
        {
            queues.insert(r.id, q);
        }
        let have = held.evaluations.get(&r.id).map_or(0, |v| v.len() as u64);
        let known = before.get(&r.id).copied();
        if known != Some((r.finished, r.evaluations)) && is_map_elites(r) {
            maps.insert(r.id, archive_of(store, r.id, registry));
        }
        if known.is_some_and(|(finished, _)| finished) && have == r.evaluations {
            continue;
        }
        let mut found = store.evaluations_from(r.id, have)?;
        let mut expected = have;
        found.retain(|e| {
            let keep = e.number == expected;
            if keep {
                expected += 1;
            }
            keep
        });
        new.insert(r.id, found);
    }
    Ok(Read {
        runs,
        new,
        maps,
        details,
        queues,
    })
}

/// A run's engines and episodes, from its stored configuration.
fn details_of(
    store: &mut Store,
    r: &RunRow,
    registry: &ModuleRegistry,
) -> Result<RunDetails, StoreError> {
    let spec = store.run_spec(r.id)?;
    let (engines, unloadable) = if r.best_engines.is_empty() {
        match crate::optimize::shared::stored_simulation(&spec, registry) {
            Ok(sim) => (vec![sim.engine().to_string()], None),
            Err(e) => (Vec::new(), Some(e.to_string())),
        }
    } else {
        (
            r.best_engines.iter().map(|(k, _)| k.to_string()).collect(),
            None,
        )
    };
    Ok(RunDetails {
        engines,
        unloadable,
        episodes: spec.episodes,
    })
}

/// Whether `r` is a MAP-Elites run (its archive is worth rebuilding).
fn is_map_elites(r: &RunRow) -> bool {
    r.info.algorithm.contains("MAP-Elites")
}

/// A MAP-Elites run's archive, rebuilt from its stored evaluations as `proleg results`
/// does; why not, when its configuration does not load here.
fn archive_of(
    store: &mut Store,
    run: i64,
    registry: &ModuleRegistry,
) -> Result<MapView, NoArchive> {
    match crate::optimize::archive::stored_archive(store, run, registry) {
        Ok(Some(a)) => Ok(MapView::of(&a)),
        Ok(None) => Err(NoArchive::NotKept(run)),
        Err(e) => Err(NoArchive::Unbuildable {
            run,
            cause: e.to_string(),
        }),
    }
}

/// Why a MAP-Elites run shows no archive. Kept in the snapshot (and compared between
/// reads), so the optimizer's error is kept as its message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoArchive {
    /// The run's configuration names no MAP-Elites optimizer.
    #[error("run {0} keeps no MAP-Elites archive")]
    NotKept(i64),
    /// Its configuration does not load here (a plugin module missing, say).
    #[error("run {run}: its archive cannot be rebuilt here: {cause}")]
    Unbuildable {
        /// The run.
        run: i64,
        /// The optimizer's error, as it reads.
        cause: String,
    },
}
