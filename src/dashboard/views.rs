//! The dashboard's JSON: the runs and a run's evaluations as the page reads them. Numbers
//! that are not finite (a failed episode's `-inf`) are `null`; names are data, never markup
//! (the page puts them into text nodes).

use serde::Serialize;

use crate::dashboard::snapshot::Snapshot;
use crate::optimize::archive::StoredArchive;
use crate::optimize::store::table::EvaluationRow;
use crate::optimize::store::{EpisodeRecord, RunRow};

/// `GET /api/runs`.
#[derive(Debug, Serialize)]
pub struct RunsView {
    /// The store, as it may be shown (no password).
    pub store: String,
    /// The snapshot's version (what the event stream announced).
    pub version: u64,
    /// Why the store cannot be read right now, while it is opened again.
    pub reconnecting: Option<String>,
    /// The runs, newest first.
    pub runs: Vec<RunView>,
}

/// One run in the runs table.
#[derive(Debug, Serialize)]
pub struct RunView {
    /// The run's id.
    pub id: i64,
    /// The simulation file.
    pub config: String,
    /// The optimizer.
    pub algorithm: String,
    /// The run's seed.
    pub seed: u64,
    /// The fitness.
    pub fitness: String,
    /// Simulated seconds per episode.
    pub duration: f64,
    /// When it started (UTC).
    pub started: String,
    /// Finished, or still running (or stopped).
    pub finished: bool,
    /// Evaluations stored.
    pub evaluations: u64,
    /// The best score so far.
    pub best: Option<f64>,
    /// The best candidate's values, gene by gene.
    pub best_values: Vec<(String, f64)>,
    /// The best candidate's score on each engine.
    pub best_engines: Vec<(String, f64)>,
    /// Candidates rejected: co-design bodies unrun, modules failed during the episode.
    pub rejected: u64,
    /// The engines its candidates are scored on.
    pub engines: Vec<String>,
    /// Seconds of computing its evaluations took, summed (the store's wall times: the
    /// compute it used, not the simulated time, which is `duration` per episode).
    pub compute_seconds: f64,
    /// A shared run's evaluations waiting for a worker.
    pub pending: Option<u64>,
    /// A shared run's evaluations claimed by workers.
    pub running: Option<u64>,
    /// A shared run's workers.
    pub workers: Vec<WorkerView>,
}

/// A worker of a shared run.
#[derive(Debug, Serialize)]
pub struct WorkerView {
    /// Its name.
    pub worker: String,
    /// Evaluations it holds now.
    pub running: u64,
    /// Evaluations of the run it wrote.
    pub done: u64,
    /// When its lease ends (seconds since 1970, the database's clock; `null`: it holds
    /// nothing). Its heartbeat moves this on every third of a lease.
    pub lease_until: Option<f64>,
}

impl RunView {
    /// The view of run `r` of snapshot `s`.
    pub fn of(s: &Snapshot, r: &RunRow) -> RunView {
        let details = s.details.get(&r.id);
        let queue = s.queues.get(&r.id);
        RunView {
            id: r.id,
            config: r.info.config.clone(),
            algorithm: r.info.algorithm.clone(),
            seed: r.info.seed,
            fitness: r.info.fitness.clone(),
            duration: r.info.duration,
            started: r.started.clone(),
            finished: r.finished,
            evaluations: r.evaluations,
            best: r.best_score.filter(|s| s.is_finite()),
            best_values: r
                .info
                .genes
                .iter()
                .cloned()
                .zip(r.best_values.iter().flatten().copied())
                .collect(),
            best_engines: r
                .best_engines
                .iter()
                .map(|(k, s)| (k.to_string(), *s))
                .collect(),
            rejected: r.rejected,
            engines: details.map(|d| d.engines.clone()).unwrap_or_default(),
            compute_seconds: s
                .evaluations
                .get(&r.id)
                .map_or(0.0, |e| e.iter().map(|e| e.wall).sum()),
            pending: queue.map(|q| q.pending),
            running: queue.map(|q| q.running),
            workers: queue.map_or_else(Vec::new, |q| {
                q.workers
                    .iter()
                    .map(|w| WorkerView {
                        worker: w.worker.clone(),
                        running: w.running,
                        done: w.done,
                        lease_until: w.lease_until,
                    })
                    .collect()
            }),
        }
    }
}

/// `GET /api/runs/{id}?from=N`: the run's evaluations from number N on.
#[derive(Debug, Serialize)]
pub struct EvaluationsView {
    /// The run.
    pub run: RunView,
    /// Evaluations read in all (the next `from`).
    pub read: u64,
    /// Its randomized episodes (robust fitness), what each drew.
    pub episodes: Vec<EpisodeView>,
    /// Why its configuration does not load here, if it does not (no replays then).
    pub unloadable: Option<String>,
    /// Those from `from` on.
    pub evaluations: Vec<EvaluationView>,
}

/// A randomized episode of a robust run.
#[derive(Debug, Serialize)]
pub struct EpisodeView {
    /// Its number.
    pub episode: u32,
    /// Its seed.
    pub seed: u64,
    /// What it drew (friction, masses, start pose).
    pub draws: String,
}

impl EpisodeView {
    /// The view of a stored episode.
    pub fn of(e: &EpisodeRecord) -> EpisodeView {
        EpisodeView {
            episode: e.episode,
            seed: e.seed,
            draws: e.draws.clone(),
        }
    }
}

/// One evaluation.
#[derive(Debug, Serialize)]
pub struct EvaluationView {
    /// Its number.
    pub number: u64,
    /// Its round.
    pub round: u64,
    /// Its score (`null`: a failed episode or a rejected body).
    pub score: Option<f64>,
    /// The run's best score so far, with this one (`null` before any).
    pub best: Option<f64>,
    /// Its parameter values.
    pub values: Vec<f64>,
    /// Its score on each engine.
    pub engines: Vec<(String, f64)>,
    /// Why its body was rejected unrun.
    pub rejected: Option<String>,
    /// Measured descriptors (MAP-Elites).
    pub measures: Vec<f64>,
    /// Wall seconds of its evaluation.
    pub wall: f64,
}

impl EvaluationView {
    /// The view of an evaluation's row ([`crate::optimize::store::table`]).
    pub fn of(row: &EvaluationRow) -> EvaluationView {
        let e = &row.eval;
        EvaluationView {
            number: e.number,
            round: e.round,
            score: Some(e.score).filter(|s| s.is_finite()),
            best: Some(row.best).filter(|s| s.is_finite()),
            values: e.values.clone(),
            engines: e.engines.iter().map(|(k, s)| (k.to_string(), *s)).collect(),
            rejected: e.rejected.clone(),
            measures: e.measures.clone(),
            wall: e.wall,
        }
    }
}

/// `GET /api/runs/{id}/map`: a MAP-Elites run's archive, as `proleg results` reads it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MapView {
    /// The two descriptors (x, y).
    pub labels: [String; 2],
    /// Cells along x and along y.
    pub bins: [usize; 2],
    /// The filled cells: x, y, the elite's score and its values.
    pub cells: Vec<MapCell>,
    /// Cells in all.
    pub total: usize,
    /// The best elite's score.
    pub best: Option<f64>,
    /// `proleg results`' line on it (coverage, QD-score, best body).
    pub summary: String,
}

/// A filled cell.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MapCell {
    /// Column.
    pub x: usize,
    /// Row.
    pub y: usize,
    /// The elite's score.
    pub score: f64,
    /// The elite's genome (allele indices).
    pub genome: Vec<u32>,
}

impl MapView {
    /// The view of a stored archive.
    pub fn of(a: &StoredArchive) -> MapView {
        let nx = a.archive.axes[0].bins;
        let cells = a
            .archive
            .cells
            .iter()
            .enumerate()
            .filter_map(|(i, c)| {
                c.as_ref().map(|(g, score)| MapCell {
                    x: i % nx,
                    y: i / nx,
                    score: *score,
                    genome: g.clone(),
                })
            })
            .collect();
        MapView {
            labels: a.labels.clone(),
            bins: [nx, a.archive.axes[1].bins],
            cells,
            total: a.archive.cells.len(),
            best: a.archive.best().map(|(_, s)| s).filter(|s| s.is_finite()),
            summary: a.summary(),
        }
    }
}

/// `GET /api/runs/{id}/evaluations/{n}/data.json`: every series of a replay's data file
/// against simulated time, for the page's plots.
#[derive(Debug, Serialize)]
pub struct DataPlotView {
    /// Series titles (`Handler/series[part]`), one per column of `values`.
    pub titles: Vec<String>,
    /// Simulated seconds of each sample.
    pub time: Vec<f64>,
    /// Per series, its value at each sample (`null`: not sampled then, or not finite).
    pub values: Vec<Vec<Option<f64>>>,
}

/// The plot of data file `path`: every series of every handler against simulated time.
pub fn data_plot(path: &std::path::Path) -> Result<DataPlotView, crate::data::read::DataError> {
    use crate::data::export::{SeriesSelector, XAxis, for_each_row};
    let header = crate::data::read::info(path)?;
    let wanted: Vec<SeriesSelector> = header
        .handlers
        .iter()
        .flat_map(|h| {
            h.series.iter().map(|s| SeriesSelector {
                handler: h.name.clone(),
                series: s.clone(),
                parts: None,
            })
        })
        .collect();
    let mut time = Vec::new();
    let mut values: Vec<Vec<Option<f64>>> = Vec::new();
    let (_, _, columns) = for_each_row(path, XAxis::SimTime, &wanted, |cols, t, row| {
        if values.is_empty() {
            values = vec![Vec::new(); cols.len()];
        }
        time.push(t);
        for (series, v) in values.iter_mut().zip(row) {
            series.push(Some(*v).filter(|v| v.is_finite()));
        }
        Ok(())
    })?;
    if values.is_empty() {
        values = vec![Vec::new(); columns.len()];
    }
    Ok(DataPlotView {
        titles: columns.into_iter().map(|c| c.title).collect(),
        time,
        values,
    })
}
