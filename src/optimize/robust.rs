//! Robust fitness: a candidate's score over the K randomized episodes an optimizer file's
//! `<robustness>` asks for — their mean or a lower quantile. The episodes are drawn once per
//! run from its seed ([`episode_seeds`]) and are the same for every candidate (common random
//! numbers: candidates differ by their gait, not by their luck). A co-design body draws
//! its episodes from the same seeds with its own links and joints ([`RobustEpisodes::of_body`]):
//! the friction is the same for every body, the masses, servos and start pose follow the
//! body's link and joint count. With `<courses>`, episode k runs on the suite's train
//! course k (its scenery replaces the simulation's; the physics draws come on top).

use crate::config::Simulation;
use crate::config::courses::{TrainCourse, TrainCourses};
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
    /// The train courses the episodes run on, one each (`<courses>`), if any.
    pub courses: Option<TrainCourses>,
}

impl RobustEpisodes {
    /// The episodes `r` draws for a run of `sim` with seed `run_seed`, on `sim`'s own world.
    pub fn new(sim: &Simulation, r: &Robustness, run_seed: u64) -> RobustEpisodes {
        RobustEpisodes::on_courses(sim, r, run_seed, None)
    }

    /// The episodes `r` draws, episode k on train course k when `courses` are given.
    fn on_courses(
        sim: &Simulation,
        r: &Robustness,
        run_seed: u64,
        courses: Option<&TrainCourses>,
    ) -> RobustEpisodes {
        let episodes = episode_seeds(run_seed, r.episodes)
            .into_iter()
            .enumerate()
            .map(|(k, seed)| draw(sim, r, seed, courses.and_then(|c| c.course(k))))
            .collect();
        RobustEpisodes {
            episodes,
            quantile: r.quantile,
            spec: *r,
            courses: courses.cloned(),
        }
    }

    /// Episode `k` drawn for another robot than the run's own: `body`, a co-design
    /// candidate's simulation (none when the run has no episode `k`).
    pub fn of_body(&self, k: usize, body: &Simulation) -> Option<RandomizedEpisode> {
        let seed = self.episodes.get(k)?.seed;
        let course = self.courses.as_ref().and_then(|c| c.course(k));
        Some(draw(body, &self.spec, seed, course))
    }

    /// The episodes `sim`'s optimizer file asks for, if it asks for any: `<robustness>`'s
    /// draws, on `<courses>`' train courses when it names some (without `<robustness>`,
    /// one nominal episode per course).
    pub fn of(sim: &Simulation, run_seed: u64) -> Option<RobustEpisodes> {
        let opt = sim.optimizer.as_ref()?;
        let courses = opt.courses.as_ref();
        let r = match (opt.spec.robustness, courses) {
            (Some(r), _) => r,
            (None, Some(c)) => Robustness::nominal(c.len() as u32),
            (None, None) => return None,
        };
        Some(RobustEpisodes::on_courses(sim, &r, run_seed, courses))
    }

    /// The candidate's score from its episodes' scores.
    pub fn combine(&self, scores: &[f64]) -> f64 {
        combine(scores, self.quantile)
    }
}

/// The episode `seed` draws from `r` for `sim`, on `course` when given (its world
/// replaces `sim`'s scenery; the draws then say which course).
fn draw(
    sim: &Simulation,
    r: &Robustness,
    seed: u64,
    course: Option<&TrainCourse>,
) -> RandomizedEpisode {
    let Some(course) = course else {
        return randomize(sim, r, seed);
    };
    let mut on_course = sim.clone();
    on_course.environment = course.environment.clone();
    let mut e = randomize(&on_course, r, seed);
    e.draws = format!("course {} seed {}; {}", course.task, course.seed, e.draws);
    e
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
