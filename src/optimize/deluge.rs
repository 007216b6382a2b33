//! The modified great deluge (thesis 3.4.2, table 6.1 / 6.6): starting from the configured
//! candidate, each neighbour of the last accepted candidate is accepted when its score
//! reaches the water level, which then rises by `rain`. The neighbourhood radius starts at
//! one allele step and doubles every `confidence` failed retries; acceptance resets it.
//! `retries` failures in a row consume a credit and reset the radius; the search stops
//! when a failure finds no credit left (or after `max_evaluations`).
//!
//! Neighbours are handed out `batch` at a time so several can be evaluated in parallel;
//! they are judged in order as if one at a time, and those after an accepted one are
//! discarded (their base changed). The sequence of candidates depends on the seed and
//! `batch` only, never on the number of workers.

use crate::config::optimizer::GdSettings;
use crate::optimize::Optimizer;
use crate::optimize::space::{Genome, SearchSpace};
use crate::rng::SimRng;

/// The great deluge's state.
pub struct GreatDeluge {
    space: SearchSpace,
    settings: GdSettings,
    rng: SimRng,
    current: Genome,
    /// Whether `current` has been scored.
    started: bool,
    water: f64,
    retries: u32,
    credits: u32,
    batch: usize,
    pending: Vec<Genome>,
    best: Option<(Genome, f64)>,
    evaluations: u64,
    max_evaluations: u64,
    accepted: u64,
    done: bool,
}

impl GreatDeluge {
    /// A great deluge over `space` from `start`, handing out `batch` neighbours per round until `max_evaluations`.
    pub fn new(
        space: SearchSpace,
        settings: GdSettings,
        start: Genome,
        seed: u64,
        batch: usize,
        max_evaluations: u64,
    ) -> Self {
        GreatDeluge {
            water: settings.initial_water_level,
            credits: settings.credits,
            space,
            settings,
            rng: SimRng::new(seed),
            current: start,
            started: false,
            retries: 0,
            batch: batch.max(1),
            pending: Vec::new(),
            best: None,
            evaluations: 0,
            max_evaluations,
            accepted: 0,
            done: false,
        }
    }

    /// The current water level.
    pub fn water_level(&self) -> f64 {
        self.water
    }

    /// Candidates accepted so far.
    pub fn accepted(&self) -> u64 {
        self.accepted
    }

    /// Allele steps a neighbour may move each gene by, for `retries` failures.
    fn radius(&self, retries: u32) -> u32 {
        let doublings = retries / self.settings.confidence.max(1);
        1u32 << doublings.min(20)
    }

    fn neighbour(&mut self, retries: u32) -> Genome {
        let r = i64::from(self.radius(retries));
        let mut g = self.current.clone();
        loop {
            for (k, gene) in g.iter_mut().zip(&self.space.genes) {
                let n = i64::from(gene.alleles.count().max(1));
                let step = (self.rng.next_u64() % (2 * r as u64 + 1)) as i64 - r;
                *k = (i64::from(*k) + step).clamp(0, n - 1) as u32;
            }
            if g != self.current || self.space.size() <= 1.0 {
                return g;
            }
        }
    }
}

impl Optimizer for GreatDeluge {
    fn ask(&mut self) -> Vec<Genome> {
        if self.done {
            return Vec::new();
        }
        if !self.started {
            self.pending = vec![self.current.clone()];
        } else {
            let budget = self.max_evaluations.saturating_sub(self.evaluations) as usize;
            let n = self.batch.min(budget);
            // Each neighbour is drawn for the retry count it would be judged at.
            self.pending = (0..n as u32)
                .map(|i| self.neighbour(self.retries + i))
                .collect();
        }
        self.pending.clone()
    }

    fn tell(&mut self, scores: &[f64]) {
        let pending = std::mem::take(&mut self.pending);
        let scores: Vec<f64> = scores
            .iter()
            .map(|s| if s.is_finite() { *s } else { f64::NEG_INFINITY })
            .collect();
        // Every evaluation counts and may be the best, judged or not.
        self.evaluations += pending.len().min(scores.len()) as u64;
        for (g, s) in pending.iter().zip(&scores) {
            if self.best.as_ref().is_none_or(|b| *s > b.1) {
                self.best = Some((g.clone(), *s));
            }
        }
        for (g, s) in pending.into_iter().zip(scores) {
            if !self.started {
                self.started = true;
                if s >= self.water {
                    self.water += self.settings.rain;
                    self.accepted += 1;
                }
                continue;
            }
            if s >= self.water {
                self.current = g;
                self.water += self.settings.rain;
                self.retries = 0;
                self.accepted += 1;
                break; // later neighbours were drawn around the old candidate
            }
            self.retries += 1;
            if self.retries >= self.settings.retries.max(1) {
                if self.credits == 0 {
                    self.done = true;
                    break;
                }
                self.credits -= 1;
                self.retries = 0;
            }
        }
        if self.evaluations >= self.max_evaluations {
            self.done = true;
        }
    }

    fn finished(&self) -> bool {
        self.done
    }

    fn best(&self) -> Option<(&Genome, f64)> {
        self.best.as_ref().map(|(g, s)| (g, *s))
    }
}
