//! What a suite run shows: per task the mean distance over its test courses (each course
//! scored by the lower engine), the success rate (the goal line crossed on every engine) and
//! its share of the task's reference; and aggregates of the normalized scores (distance /
//! reference, or / goal where the task has none) as rliable recommends for few runs: the
//! interquartile mean with a 95 % stratified-bootstrap interval, for all tasks, the
//! trained families and the held-out ones.

use std::collections::BTreeMap;
use std::fmt;

use crate::config::simulation::EngineKind;
use crate::config::suite::{SuiteFile, Task};
use crate::rng::SimRng;
use crate::sim::episode::course::{EpisodeKey, EpisodeResult};

/// Bootstrap resamples of an interval.
pub const RESAMPLES: usize = 2000;

/// One task's figures.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TaskRow {
    /// The task.
    pub task: String,
    /// Its family.
    pub family: String,
    /// Its difficulty.
    pub difficulty: f64,
    /// Whether its family is held out of training.
    pub held_out: bool,
    /// Test courses scored (on every engine).
    pub courses: usize,
    /// Mean distance (m) along the course, each course by its lower engine.
    pub mean: f64,
    /// Share of courses whose goal line was crossed on every engine.
    pub success: f64,
    /// Mean distance over the task's reference, when it has one.
    pub share: Option<f64>,
    /// Mean |difference| between the engines' distances (m), with two engines.
    pub engine_gap: Option<f64>,
}

/// An interquartile mean with its interval.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Aggregate {
    /// Which tasks: "all", "trained families", "held-out families".
    pub label: String,
    /// Runs (task x course) it is over.
    pub runs: usize,
    /// Interquartile mean of the normalized scores.
    pub iqm: f64,
    /// 2.5 % bootstrap quantile.
    pub low: f64,
    /// 97.5 % bootstrap quantile.
    pub high: f64,
    /// Plain mean of the normalized scores.
    pub mean: f64,
}

/// The whole table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SuiteReport {
    /// The suite's name.
    pub suite: String,
    /// The controller scored.
    pub controller: String,
    /// The engines each course ran on.
    pub engines: Vec<String>,
    /// One row per task with every course done.
    pub tasks: Vec<TaskRow>,
    /// The aggregates.
    pub aggregates: Vec<Aggregate>,
}

/// A course's score: its lower engine's distance, and success on every engine.
struct Course {
    distance: f64,
    crossed: bool,
    gap: f64,
}

fn courses(
    task_index: usize,
    task: &Task,
    engines: &[EngineKind],
    done: &BTreeMap<EpisodeKey, EpisodeResult>,
) -> Vec<Course> {
    task.test
        .iter()
        .filter_map(|&seed| {
            let runs: Option<Vec<&EpisodeResult>> = engines
                .iter()
                .map(|&engine| {
                    done.get(&EpisodeKey {
                        task: task_index,
                        seed,
                        engine,
                    })
                })
                .collect();
            let runs = runs?;
            let lo = runs
                .iter()
                .map(|r| r.distance)
                .fold(f64::INFINITY, f64::min);
            let hi = runs
                .iter()
                .map(|r| r.distance)
                .fold(f64::NEG_INFINITY, f64::max);
            Some(Course {
                distance: lo,
                crossed: runs.iter().all(|r| r.crossed),
                gap: hi - lo,
            })
        })
        .collect()
}

/// Interquartile mean: the mean of the middle half (a quarter cut from each end).
pub fn iqm(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.to_vec();
    v.sort_by(f64::total_cmp);
    let cut = v.len() / 4;
    let mid = &v[cut..v.len() - cut];
    if mid.is_empty() {
        return f64::NAN;
    }
    mid.iter().sum::<f64>() / mid.len() as f64
}

/// IQM of `groups` (one vector of scores per task) and its 95 % interval, resampling each
/// task's scores with replacement (stratified bootstrap, seeded: the same table twice).
pub fn aggregate(label: &str, groups: &[Vec<f64>]) -> Option<Aggregate> {
    let all: Vec<f64> = groups.iter().flatten().copied().collect();
    if all.is_empty() {
        return None;
    }
    let mut rng = SimRng::new(0x5eed);
    let mut stats: Vec<f64> = (0..RESAMPLES)
        .map(|_| {
            let sample: Vec<f64> = groups
                .iter()
                .flat_map(|g| {
                    let n = g.len();
                    (0..n)
                        .map(|_| g[((rng.uniform() * n as f64) as usize).min(n - 1)])
                        .collect::<Vec<_>>()
                })
                .collect();
            iqm(&sample)
        })
        .collect();
    stats.sort_by(f64::total_cmp);
    let q = |p: f64| stats[((p * (RESAMPLES - 1) as f64).round() as usize).min(RESAMPLES - 1)];
    Some(Aggregate {
        label: label.to_string(),
        runs: all.len(),
        iqm: iqm(&all),
        low: q(0.025),
        high: q(0.975),
        mean: all.iter().sum::<f64>() / all.len() as f64,
    })
}

/// The report of the episodes in `done` for the tasks `selected` (indices).
pub fn report(
    suite: &SuiteFile,
    selected: &[usize],
    engines: &[EngineKind],
    controller: &str,
    done: &BTreeMap<EpisodeKey, EpisodeResult>,
) -> SuiteReport {
    let held = suite.held_out_families();
    let mut rows = Vec::new();
    let (mut all, mut trained, mut held_out) = (Vec::new(), Vec::new(), Vec::new());
    for &i in selected {
        let Some(task) = suite.tasks.get(i) else {
            continue;
        };
        let c = courses(i, task, engines, done);
        if c.is_empty() {
            continue;
        }
        let n = c.len() as f64;
        let mean = c.iter().map(|c| c.distance).sum::<f64>() / n;
        let norm = task.reference.unwrap_or(task.goal);
        let scores: Vec<f64> = c.iter().map(|c| c.distance / norm).collect();
        let family_held = held.contains(&task.terrain.family);
        if family_held {
            held_out.push(scores.clone());
        } else {
            trained.push(scores.clone());
        }
        all.push(scores);
        rows.push(TaskRow {
            task: task.name.clone(),
            family: task.terrain.family.name().to_string(),
            difficulty: task.terrain.difficulty,
            held_out: family_held,
            courses: c.len(),
            mean,
            success: c.iter().filter(|c| c.crossed).count() as f64 / n,
            share: task.reference.map(|r| mean / r),
            engine_gap: (engines.len() > 1).then(|| c.iter().map(|c| c.gap).sum::<f64>() / n),
        });
    }
    let aggregates = [
        aggregate("all tasks", &all),
        aggregate("trained families", &trained),
        aggregate("held-out families", &held_out),
    ]
    .into_iter()
    .flatten()
    .collect();
    SuiteReport {
        suite: suite.name.clone(),
        controller: controller.to_string(),
        engines: engines.iter().map(|e| e.name().to_string()).collect(),
        tasks: rows,
        aggregates,
    }
}

impl SuiteReport {
    /// The per-task table as CSV.
    pub fn csv(&self) -> String {
        let mut s = String::from(
            "task,family,difficulty,held_out,courses,mean_distance_m,success,share_of_reference,engine_gap_m\n",
        );
        for r in &self.tasks {
            let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4}"));
            s += &format!(
                "{},{},{},{},{},{:.4},{:.3},{},{}\n",
                r.task,
                r.family,
                r.difficulty,
                u8::from(r.held_out),
                r.courses,
                r.mean,
                r.success,
                opt(r.share),
                opt(r.engine_gap)
            );
        }
        s
    }
}

impl fmt::Display for SuiteReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "suite {}: {} on {} (each course scored by its lower engine)",
            self.suite,
            self.controller,
            self.engines.join(" + ")
        )?;
        writeln!(
            f,
            "{:<16} {:>7} {:>8} {:>10} {:>8} {:>9} {:>9}",
            "task", "courses", "held out", "mean (m)", "success", "of ref.", "gap (m)"
        )?;
        for r in &self.tasks {
            let opt = |v: Option<f64>, pct: bool| match v {
                Some(v) if pct => format!("{:.0} %", 100.0 * v),
                Some(v) => format!("{v:.3}"),
                None => "-".into(),
            };
            writeln!(
                f,
                "{:<16} {:>7} {:>8} {:>10.3} {:>7.0} % {:>9} {:>9}",
                r.task,
                r.courses,
                if r.held_out { "yes" } else { "" },
                r.mean,
                100.0 * r.success,
                opt(r.share, true),
                opt(r.engine_gap, false)
            )?;
        }
        for a in &self.aggregates {
            writeln!(
                f,
                "{}: IQM of normalized scores {:.3} [{:.3}, {:.3}] (95 % bootstrap, {} runs; mean {:.3})",
                a.label, a.iqm, a.low, a.high, a.runs, a.mean
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_interquartile_mean_drops_a_quarter_at_each_end() {
        assert_eq!(iqm(&[100.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, -50.0]), 3.5);
        assert_eq!(iqm(&[2.0]), 2.0);
    }

    #[test]
    fn the_interval_holds_the_estimate_and_narrows_with_more_runs() {
        let mut rng = SimRng::new(3);
        let few: Vec<Vec<f64>> = (0..2)
            .map(|_| (0..5).map(|_| rng.uniform()).collect())
            .collect();
        let many: Vec<Vec<f64>> = (0..2)
            .map(|_| (0..200).map(|_| rng.uniform()).collect())
            .collect();
        let (a, b) = (
            aggregate("few", &few).unwrap(),
            aggregate("many", &many).unwrap(),
        );
        assert!(a.low <= a.iqm && a.iqm <= a.high, "{a:?}");
        assert!(b.high - b.low < (a.high - a.low) / 2.0, "{a:?} {b:?}");
        assert_eq!(
            aggregate("few", &few),
            Some(a),
            "seeded: the same interval twice"
        );
    }
}
