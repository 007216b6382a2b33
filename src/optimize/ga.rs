//! The genetic algorithm (thesis 3.4.2, B.7, tables 6.3 / 6.8), after GAlib's simple GA on
//! discrete allele arrays: a population of `popsize` genomes; parents by binary tournament
//! (*deviation:* GAlib's roulette wheel needs positive scores, ours may be negative);
//! one-point crossover with probability `pcross` (0 disables it, as table 6.8 does);
//! each gene mutated to a random allele with probability `pmut`; elitism (the best
//! survives). Mode 1 replaces the whole generation; mode 2 (steady state) replaces the
//! worst quarter. Stops at convergence (best of `nConvergence` generations ago divided
//! by the current best >= `pConvergence`) or after `max_evaluations`.

use crate::config::optimizer::GaSettings;
use crate::optimize::Optimizer;
use crate::optimize::space::{Genome, SearchSpace};
use crate::rng::SimRng;

/// The genetic algorithm's state.
pub struct GeneticAlgorithm {
    space: SearchSpace,
    settings: GaSettings,
    rng: SimRng,
    population: Vec<(Genome, f64)>,
    /// Candidates handed out and waiting for scores.
    pending: Vec<Genome>,
    best_per_generation: Vec<f64>,
    best: Option<(Genome, f64)>,
    evaluations: u64,
    max_evaluations: u64,
    done: bool,
}

impl GeneticAlgorithm {
    /// `start` (the configured values) is the first individual; the rest are random.
    pub fn new(
        space: SearchSpace,
        settings: GaSettings,
        start: Genome,
        seed: u64,
        max_evaluations: u64,
    ) -> Self {
        let mut rng = SimRng::new(seed);
        let n = settings.popsize.max(2) as usize;
        let mut pending = vec![start];
        while pending.len() < n {
            pending.push(space.random(&mut rng));
        }
        GeneticAlgorithm {
            space,
            settings,
            rng,
            population: Vec::new(),
            pending,
            best_per_generation: Vec::new(),
            best: None,
            evaluations: 0,
            max_evaluations,
            done: false,
        }
    }

    /// Generations scored so far.
    pub fn generations(&self) -> usize {
        self.best_per_generation.len()
    }

    fn tournament(&mut self) -> usize {
        let n = self.population.len() as u64;
        let a = (self.rng.next_u64() % n) as usize;
        let b = (self.rng.next_u64() % n) as usize;
        if self.population[a].1 >= self.population[b].1 {
            a
        } else {
            b
        }
    }

    fn child(&mut self) -> Genome {
        let p1 = self.tournament();
        let mut child = self.population[p1].0.clone();
        if self.rng.uniform() < self.settings.pcross && child.len() > 1 {
            let p2 = self.tournament();
            let cut = 1 + (self.rng.next_u64() % (child.len() as u64 - 1)) as usize;
            child[cut..].copy_from_slice(&self.population[p2].0[cut..]);
        }
        for (k, gene) in child.iter_mut().zip(&self.space.genes) {
            if self.rng.uniform() < self.settings.pmut {
                *k = (self.rng.next_u64() % u64::from(gene.alleles.count().max(1))) as u32;
            }
        }
        child
    }

    fn converged(&self) -> bool {
        let n = self.settings.n_convergence as usize;
        let g = self.best_per_generation.len();
        if n == 0 || g <= n {
            return false;
        }
        let (old, now) = (
            self.best_per_generation[g - 1 - n],
            self.best_per_generation[g - 1],
        );
        now != 0.0 && old / now >= self.settings.p_convergence
    }

    fn breed(&mut self) {
        let n = self.settings.popsize.max(2) as usize;
        let replace = if self.settings.ga_mode == 2 {
            n.div_ceil(4)
        } else {
            n - 1
        };
        let budget = self.max_evaluations.saturating_sub(self.evaluations) as usize;
        let count = replace.min(budget);
        self.pending = (0..count).map(|_| self.child()).collect();
    }
}

impl Optimizer for GeneticAlgorithm {
    fn ask(&mut self) -> Vec<Genome> {
        if self.done {
            Vec::new()
        } else {
            self.pending.clone()
        }
    }

    fn tell(&mut self, scores: &[f64]) {
        let children: Vec<(Genome, f64)> = std::mem::take(&mut self.pending)
            .into_iter()
            .zip(
                scores
                    .iter()
                    .map(|s| if s.is_finite() { *s } else { f64::NEG_INFINITY }),
            )
            .collect();
        self.evaluations += children.len() as u64;
        for (g, s) in &children {
            if self.best.as_ref().is_none_or(|b| *s > b.1) {
                self.best = Some((g.clone(), *s));
            }
        }
        if self.population.is_empty() {
            self.population = children;
        } else {
            // Elitism / steady state: the new individuals replace the worst.
            self.population.sort_by(|a, b| b.1.total_cmp(&a.1));
            let keep = self.population.len().saturating_sub(children.len()).max(1);
            self.population.truncate(keep);
            self.population.extend(children);
        }
        let gen_best = self
            .population
            .iter()
            .map(|p| p.1)
            .fold(f64::NEG_INFINITY, f64::max);
        self.best_per_generation.push(gen_best);
        if self.converged() || self.evaluations >= self.max_evaluations {
            self.done = true;
        } else {
            self.breed();
            if self.pending.is_empty() {
                self.done = true;
            }
        }
    }

    fn finished(&self) -> bool {
        self.done
    }

    fn best(&self) -> Option<(&Genome, f64)> {
        self.best.as_ref().map(|(g, s)| (g, *s))
    }
}
