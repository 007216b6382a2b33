//! Robust fitness: a candidate's score over the K randomized episodes an optimizer file's
//! `<robustness>` asks for — their mean or a lower quantile. The episodes are drawn once per
//! run from its seed ([`episode_seeds`]) and are the same for every candidate (common random
//! numbers: candidates differ by their gait, not by their luck). A co-design body draws
//! its episodes from the same seeds with its own links and joints ([`RobustEpisodes::of_body`]):
//! the friction is the same for every body, the masses, servos and start pose follow the
//! body's link and joint count.

use crate::config::Simulation;
use crate::config::robustness::Robustness;
use crate::optimize::store::EpisodeRecord;
use crate::sim::randomize::{RandomizedEpisode, episode_seeds, randomize};

/// The randomized episodes of a run.
#[derive(Debug, Clone)]
pub struct RobustEpisodes {
    /// The episodes, each with its seed and drawn physics.
    pub episodes: Vec<RandomizedEpisode>,
    /// How episode scores combine.
    pub quantile: Option<f64>,
    /// What is drawn.
    pub spec: Robustness,
}

impl RobustEpisodes {
    /// The episodes `r` draws for a run of `sim` with seed `run_seed`.
    pub fn new(sim: &Simulation, r: &Robustness, run_seed: u64) -> RobustEpisodes {
        let episodes = episode_seeds(run_seed, r.episodes)
            .into_iter()
            .map(|seed| randomize(sim, r, seed))
            .collect();
        RobustEpisodes {
            episodes,
            quantile: r.quantile,
            spec: *r,
        }
    }

    /// Episode `k` drawn for another robot than the run's own: `body`, a co-design
    /// candidate's simulation (none when the run has no episode `k`).
    pub fn of_body(&self, k: usize, body: &Simulation) -> Option<RandomizedEpisode> {
        let seed = self.episodes.get(k)?.seed;
        Some(randomize(body, &self.spec, seed))
    }

    /// The episodes `sim`'s optimizer file asks for, if it asks for any.
    pub fn of(sim: &Simulation, run_seed: u64) -> Option<RobustEpisodes> {
        let r = sim.optimizer.as_ref()?.spec.robustness?;
        Some(RobustEpisodes::new(sim, &r, run_seed))
    }

    /// The candidate's score from its episodes' scores.
    pub fn combine(&self, scores: &[f64]) -> f64 {
        combine(scores, self.quantile)
    }
}

/// The records of the episodes `sim`'s optimizer file asks for with seed `run_seed`, for
/// the store (none without robust fitness).
pub fn episode_records(sim: &Simulation, run_seed: u64) -> Vec<EpisodeRecord> {
    RobustEpisodes::of(sim, run_seed).map_or_else(Vec::new, |r| {
        r.episodes
            .iter()
            .enumerate()
            .map(|(i, e)| EpisodeRecord {
                episode: i as u32,
                seed: e.seed,
                draws: e.draws.clone(),
            })
            .collect()
    })
}

/// The mean of `scores`, or with `Some(q)` their lower `q` quantile (linear interpolation
/// between order statistics). A `-inf` episode (a blow-up) makes the mean `-inf`.
pub fn combine(scores: &[f64], quantile: Option<f64>) -> f64 {
    if scores.is_empty() {
        return f64::NEG_INFINITY;
    }
    match quantile {
        None => scores.iter().sum::<f64>() / scores.len() as f64,
        Some(q) => {
            let mut s = scores.to_vec();
            s.sort_by(f64::total_cmp);
            let at = q * (s.len() - 1) as f64;
            let (lo, hi) = (at.floor() as usize, at.ceil() as usize);
            let t = at - lo as f64;
            if t == 0.0 || !s[lo].is_finite() {
                s[lo]
            } else {
                s[lo] + t * (s[hi] - s[lo])
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_lower_quantile() {
        let s = [4.0, 1.0, 3.0, 2.0, 5.0];
        assert_eq!(combine(&s, None), 3.0);
        assert_eq!(combine(&s, Some(0.25)), 2.0);
        assert!((combine(&s, Some(0.1)) - 1.4).abs() < 1e-12);
        assert_eq!(combine(&[1.0, f64::NEG_INFINITY], None), f64::NEG_INFINITY);
        assert_eq!(combine(&[2.0, f64::NEG_INFINITY, 3.0], Some(0.5)), 2.0);
    }
}
