//! OpenAI's evolution strategy (Salimans et al. 2017) over real vectors, for the thousands
//! of weights of a policy network: each generation asks for `pairs` antithetic pairs
//! `mean ± sigma·ε` (ε standard normal), shapes the scores into centred ranks (only their
//! order counts, so a score's scale or an outlier does not), estimates the gradient
//! `Σ (rank⁺ − rank⁻) ε / (2·pairs·sigma)` and moves the mean by Adam, with an L2 weight
//! decay. Memory and work per generation are O(pairs · n) (CMA-ES's are O(n²) and O(n³)).
//! Deterministic: the perturbations come from one seeded stream.
//!
//! [`OpenAiEs`] is the strategy over real vectors; [`EsOptimizer`] puts it behind the
//! [`Optimizer`] interface (`<evolutionStrategy>` optimizer files): each gene's value in
//! units of its range, so `sigma` and the learning rate are fractions of each range as in
//! CMA-ES, the weight decay pulls every gene toward the value 0, and each candidate is the
//! genome of its nearest alleles. The start candidate is evaluated first, alone.

use crate::config::optimizer::EsSettings as EsFile;
use crate::optimize::Optimizer;
use crate::optimize::space::{Alleles, Genome, SearchSpace};
use crate::rng::SimRng;

/// The strategy's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EsSettings {
    /// Antithetic pairs per generation (2 × pairs candidates).
    pub pairs: usize,
    /// Perturbation scale.
    pub sigma: f64,
    /// Adam's step size.
    pub learning_rate: f64,
    /// L2 decay of the mean per step (a fraction of the learning rate).
    pub weight_decay: f64,
    /// Generations before the strategy stops.
    pub generations: usize,
}

impl Default for EsSettings {
    fn default() -> Self {
        EsSettings {
            pairs: 16,
            sigma: 0.05,
            learning_rate: 0.02,
            weight_decay: 0.005,
            generations: 100,
        }
    }
}

/// Adam's moment estimates.
#[derive(Debug, Clone)]
struct Adam {
    m: Vec<f64>,
    v: Vec<f64>,
    t: i32,
}

/// OpenAI-ES's state.
#[derive(Debug, Clone)]
pub struct OpenAiEs {
    settings: EsSettings,
    mean: Vec<f64>,
    /// This generation's perturbations, one per pair.
    noise: Vec<Vec<f64>>,
    adam: Adam,
    rng: SimRng,
    generation: usize,
    best: Option<(Vec<f64>, f64)>,
}

impl OpenAiEs {
    /// A search from `start` with `settings`, its perturbations drawn from `seed`.
    pub fn new(start: Vec<f64>, settings: EsSettings, seed: u64) -> OpenAiEs {
        let n = start.len();
        OpenAiEs {
            settings,
            mean: start,
            noise: Vec::new(),
            adam: Adam {
                m: vec![0.0; n],
                v: vec![0.0; n],
                t: 0,
            },
            rng: SimRng::new(seed),
            generation: 0,
            best: None,
        }
    }

    /// The search's centre (the policy it has learned).
    pub fn mean(&self) -> &[f64] {
        &self.mean
    }

    /// Generations told so far.
    pub fn generation(&self) -> usize {
        self.generation
    }

    /// Whether the last generation was told.
    pub fn finished(&self) -> bool {
        self.generation >= self.settings.generations
    }

    /// The best candidate scored and its score.
    pub fn best(&self) -> Option<(&[f64], f64)> {
        self.best.as_ref().map(|(x, s)| (x.as_slice(), *s))
    }

    /// This generation's candidates: `mean + sigma·ε_k` and `mean − sigma·ε_k` for each pair
    /// `k`, in that order (empty when finished).
    pub fn ask(&mut self) -> Vec<Vec<f64>> {
        if self.finished() {
            return Vec::new();
        }
        let n = self.mean.len();
        let rng = &mut self.rng;
        self.noise = (0..self.settings.pairs.max(1))
            .map(|_| (0..n).map(|_| rng.gaussian()).collect())
            .collect();
        let s = self.settings.sigma;
        self.noise
            .iter()
            .flat_map(|eps| {
                let plus = self.mean.iter().zip(eps).map(|(m, e)| m + s * e).collect();
                let minus = self.mean.iter().zip(eps).map(|(m, e)| m - s * e).collect();
                [plus, minus]
            })
            .collect()
    }

    /// The scores of the last `ask`'s candidates, in order (higher is better). Scores that
    /// are not finite rank lowest.
    pub fn tell(&mut self, candidates: &[Vec<f64>], scores: &[f64]) {
        if scores.len() != 2 * self.noise.len() || candidates.len() != scores.len() {
            return;
        }
        for (c, &s) in candidates.iter().zip(scores) {
            if s.is_finite() && self.best.as_ref().is_none_or(|(_, b)| s > *b) {
                self.best = Some((c.clone(), s));
            }
        }
        let ranks = centred_ranks(scores);
        let n = self.mean.len();
        let scale = 1.0 / (scores.len() as f64 * self.settings.sigma);
        let mut gradient = vec![0.0; n];
        for (k, eps) in self.noise.iter().enumerate() {
            let w = ranks[2 * k] - ranks[2 * k + 1];
            for (g, e) in gradient.iter_mut().zip(eps) {
                *g += w * e * scale;
            }
        }
        self.adam_step(&gradient);
        self.generation += 1;
    }

    /// One Adam ascent step along `gradient`, with the weight decay.
    fn adam_step(&mut self, gradient: &[f64]) {
        const B1: f64 = 0.9;
        const B2: f64 = 0.999;
        const EPS: f64 = 1e-8;
        let a = &mut self.adam;
        a.t += 1;
        let lr = self.settings.learning_rate * (1.0 - B2.powi(a.t)).sqrt() / (1.0 - B1.powi(a.t));
        let decay = self.settings.weight_decay;
        for (((x, g), m), v) in self
            .mean
            .iter_mut()
            .zip(gradient)
            .zip(a.m.iter_mut())
            .zip(a.v.iter_mut())
        {
            let g = g - decay * *x;
            *m = B1 * *m + (1.0 - B1) * g;
            *v = B2 * *v + (1.0 - B2) * g * g;
            *x += lr * *m / (v.sqrt() + EPS);
        }
    }
}

/// OpenAI-ES over a search space's genes.
#[derive(Debug, Clone)]
pub struct EsOptimizer {
    es: OpenAiEs,
    space: SearchSpace,
    /// Each gene's range (value of its last allele minus its first).
    spans: Vec<f64>,
    start: Option<Genome>,
    /// The last generation's points (in range units), for `tell`.
    asked: Vec<Vec<f64>>,
    best: Option<(Genome, f64)>,
    evaluations: u64,
    max_evaluations: u64,
}

fn span(a: &Alleles) -> f64 {
    let top = a.count().saturating_sub(1);
    let s = a.value(top) - a.value(0);
    if s > 0.0 { s } else { 1.0 }
}

impl EsOptimizer {
    /// The strategy from `start` with a file's settings, its perturbations drawn from
    /// `seed`, stopping after `max_evaluations`.
    pub fn new(
        space: SearchSpace,
        start: Genome,
        settings: &EsFile,
        seed: u64,
        max_evaluations: u64,
    ) -> EsOptimizer {
        let spans: Vec<f64> = space.genes.iter().map(|g| span(&g.alleles)).collect();
        let mean = space
            .decode(&start)
            .iter()
            .zip(&spans)
            .map(|(v, s)| v / s)
            .collect();
        let pairs = (settings.popsize as usize / 2).max(1);
        let core = EsSettings {
            pairs,
            sigma: settings.sigma,
            learning_rate: settings.learning_rate,
            weight_decay: settings.weight_decay,
            generations: usize::MAX,
        };
        EsOptimizer {
            es: OpenAiEs::new(mean, core, seed),
            space,
            spans,
            start: Some(start),
            asked: Vec::new(),
            best: None,
            evaluations: 0,
            max_evaluations,
        }
    }

    /// The genome nearest to a point in range units.
    fn genome(&self, x: &[f64]) -> Genome {
        self.space
            .genes
            .iter()
            .zip(x.iter().zip(&self.spans))
            .map(|(g, (v, s))| g.alleles.nearest(v * s))
            .collect()
    }

    /// The search's centre as a genome (the policy learned so far).
    pub fn mean(&self) -> Genome {
        self.genome(self.es.mean())
    }

    /// Generations told so far.
    pub fn generation(&self) -> usize {
        self.es.generation()
    }
}

impl Optimizer for EsOptimizer {
    fn ask(&mut self) -> Vec<Genome> {
        if self.finished() {
            return Vec::new();
        }
        if let Some(start) = &self.start {
            return vec![start.clone()];
        }
        self.asked = self.es.ask();
        self.asked.iter().map(|x| self.genome(x)).collect()
    }

    fn tell(&mut self, scores: &[f64]) {
        let told: Vec<Genome> = match self.start.take() {
            Some(start) => vec![start],
            None => {
                let points = std::mem::take(&mut self.asked);
                self.es.tell(&points, scores);
                points.iter().map(|x| self.genome(x)).collect()
            }
        };
        self.evaluations += told.len() as u64;
        for (g, s) in told.into_iter().zip(scores) {
            if s.is_finite() && self.best.as_ref().is_none_or(|b| *s > b.1) {
                self.best = Some((g, *s));
            }
        }
    }

    fn finished(&self) -> bool {
        self.evaluations >= self.max_evaluations
    }

    fn best(&self) -> Option<(&Genome, f64)> {
        self.best.as_ref().map(|(g, s)| (g, *s))
    }
}

/// Each score's rank mapped to [-0.5, 0.5] (lowest -0.5); non-finite scores rank lowest,
/// ties by order.
pub fn centred_ranks(scores: &[f64]) -> Vec<f64> {
    let n = scores.len();
    let key = |s: f64| if s.is_finite() { s } else { f64::NEG_INFINITY };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| key(scores[a]).total_cmp(&key(scores[b])).then(a.cmp(&b)));
    let mut ranks = vec![0.0; n];
    let span = (n.max(2) - 1) as f64;
    for (r, &i) in order.iter().enumerate() {
        ranks[i] = r as f64 / span - 0.5;
    }
    ranks
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cart-free toy task a linear policy must learn: a point mass on a line, pushed by
    /// `u = w · [x, v, 1]` (clamped to ±1) for 200 steps of 0.05 s from four starts; the
    /// score is minus the mean squared distance from 0 (plus a little of the push).
    fn balance(w: &[f64]) -> f64 {
        let mut cost = 0.0;
        for &(x0, v0) in &[(1.0, 0.0), (-0.5, 0.5), (0.3, -1.0), (-1.0, -0.2)] {
            let (mut x, mut v) = (x0, v0);
            for _ in 0..200 {
                let u = (w[0] * x + w[1] * v + w[2]).clamp(-1.0, 1.0);
                v += 0.05 * u;
                x += 0.05 * v;
                cost += x * x + 0.01 * u * u;
            }
        }
        -cost / 800.0
    }

    fn run(seed: u64) -> (f64, f64, Vec<f64>) {
        let start = vec![0.0; 3];
        let settings = EsSettings {
            pairs: 8,
            sigma: 0.1,
            learning_rate: 0.1,
            weight_decay: 0.0,
            generations: 60,
        };
        let mut es = OpenAiEs::new(start.clone(), settings, seed);
        while !es.finished() {
            let c = es.ask();
            let s: Vec<f64> = c.iter().map(|w| balance(w)).collect();
            es.tell(&c, &s);
        }
        (balance(&start), balance(es.mean()), es.mean().to_vec())
    }

    #[test]
    fn the_strategy_learns_a_linear_policy_that_balances_the_toy_task() {
        let (before, after, w) = run(7);
        println!("score {before} -> {after}, weights {w:?}");
        // Doing nothing leaves the mass drifting (a mean squared distance of 10.5); the
        // learned feedback (negative position and speed gains) brings it to 0.05 with
        // seed 7: the test asks for under 0.25, a 40-fold improvement in 960 episodes.
        assert!(before < -10.0, "{before}");
        assert!(after > -0.25, "{before} -> {after} with {w:?}");
        assert!(w[0] < 0.0 && w[1] < 0.0, "{w:?}");
        // 60 generations of 16 episodes: the same seed, the same weights.
        assert_eq!(run(7).2, w);
    }

    #[test]
    fn ranks_ignore_scale_and_put_failures_last() {
        assert_eq!(centred_ranks(&[3.0, 1.0, 2.0]), vec![0.5, -0.5, 0.0]);
        assert_eq!(centred_ranks(&[300.0, f64::NAN, 2.0]), vec![0.5, -0.5, 0.0]);
        assert_eq!(centred_ranks(&[1e9, -1e9]), vec![0.5, -0.5]);
    }
}
