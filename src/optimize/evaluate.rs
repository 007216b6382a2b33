//! Evaluating candidates: each is a fresh, seeded headless episode of the simulation.
//! Candidates are batched, up to `batch` robots sharing one world (they do not touch each
//! other), and the batches are spread over `workers` threads. A physics blow-up (a
//! non-finite or far-flung centre of mass) scores the candidate `-inf` and the run goes on.

use std::sync::Mutex;
use std::sync::mpsc::channel;
use std::time::Instant;

use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::measure::ground_distance;
use crate::optimize::fitness::{Episode, Fitness};
use crate::optimize::space::{Genome, SearchSpace};
use crate::sim::physics::MAX_ROBOTS_PER_WORLD;
use crate::sim::{BuildOptions, Simulator};

/// Farther than this from the start (m) counts as a blow-up.
const BLOW_UP_DISTANCE: f64 = 1000.0;

/// Runs candidates.
pub struct Evaluator {
    /// The simulation every episode runs.
    pub sim: Simulation,
    /// The module types episodes may create (standard library, loaded plugins).
    pub registry: ModuleRegistry,
    /// How genomes map to module parameters.
    pub space: SearchSpace,
    /// How episodes are scored.
    pub fitness: Fitness,
    /// Simulated seconds per episode.
    pub duration: f64,
    /// Seed of every episode.
    pub seed: u64,
    /// Robots per world.
    pub batch: usize,
    /// Worker threads.
    pub workers: usize,
}

impl Evaluator {
    /// Scores of `genomes`, in order.
    pub fn evaluate(&self, genomes: &[Genome]) -> Result<Vec<f64>, String> {
        self.evaluate_with(genomes, |_, _, _| {})
    }

    /// Scores of `genomes`, in order; `on_batch(first, scores, wall_seconds)` is called on
    /// this thread as each batch finishes (to store results before the round ends).
    pub fn evaluate_with(
        &self,
        genomes: &[Genome],
        mut on_batch: impl FnMut(usize, &[f64], f64),
    ) -> Result<Vec<f64>, String> {
        let batch = self.batch.clamp(1, MAX_ROBOTS_PER_WORLD);
        let chunks: Vec<(usize, &[Genome])> = genomes
            .chunks(batch)
            .enumerate()
            .map(|(i, c)| (i * batch, c))
            .collect();
        let next = Mutex::new(0usize);
        let mut results = vec![f64::NAN; genomes.len()];
        let mut error = None;
        let (tx, rx) = channel::<(usize, Result<Vec<f64>, String>, f64)>();
        std::thread::scope(|s| {
            for _ in 0..self.workers.clamp(1, chunks.len().max(1)) {
                let tx = tx.clone();
                let (next, chunks) = (&next, &chunks);
                s.spawn(move || {
                    loop {
                        let i = {
                            let Ok(mut n) = next.lock() else { return };
                            let i = *n;
                            *n += 1;
                            i
                        };
                        let Some((start, chunk)) = chunks.get(i) else {
                            return;
                        };
                        let t = Instant::now();
                        let r = self.run_batch(chunk);
                        let failed = r.is_err();
                        if tx.send((*start, r, t.elapsed().as_secs_f64())).is_err() || failed {
                            return;
                        }
                    }
                });
            }
            drop(tx);
            for (start, r, wall) in rx {
                match r {
                    Ok(scores) => {
                        results[start..start + scores.len()].copy_from_slice(&scores);
                        on_batch(start, &scores, wall);
                    }
                    Err(e) => {
                        error.get_or_insert(e);
                    }
                }
            }
        });
        match error {
            Some(e) => Err(e),
            None => Ok(results),
        }
    }

    /// One world with a robot per genome.
    pub fn run_batch(&self, genomes: &[Genome]) -> Result<Vec<f64>, String> {
        let opts = BuildOptions {
            robots: genomes.len(),
            seed: self.seed,
            record: false,
            physics: None,
        };
        let mut s = Simulator::with_registry(&self.sim, &opts, &self.registry)
            .map_err(|e| e.to_string())?;
        for (i, g) in genomes.iter().enumerate() {
            let kernel = s.kernel_mut(i).map_err(|e| e.to_string())?;
            self.space.apply(g, kernel).map_err(|e| e.to_string())?;
        }
        let mut start = Vec::with_capacity(genomes.len());
        for i in 0..genomes.len() {
            start.push((
                s.com(i).map_err(|e| e.to_string())?,
                s.heading(i).map_err(|e| e.to_string())?,
            ));
        }
        let dt = s.clock().dt;
        let steps = (self.duration / dt).round() as u64;
        s.run_steps(steps);
        let time = steps as f64 * dt;
        let gravity = s.gravity();
        let mut scores = Vec::with_capacity(genomes.len());
        for (i, (com0, heading0)) in start.into_iter().enumerate() {
            let end = s.com(i).map_err(|e| e.to_string())?;
            if !end.iter().all(|v| v.is_finite()) || ground_distance(com0, end) > BLOW_UP_DISTANCE {
                scores.push(f64::NEG_INFINITY);
                continue;
            }
            let e = Episode {
                start_com: com0,
                end_com: end,
                start_heading: heading0,
                time,
                energy: s.energy(i).map_err(|e| e.to_string())?.joules,
                mass: s.mass(i).map_err(|e| e.to_string())?,
                gravity,
            };
            let score = self.fitness.score(&e);
            scores.push(if score.is_nan() {
                f64::NEG_INFINITY
            } else {
                score
            });
        }
        Ok(scores)
    }
}
