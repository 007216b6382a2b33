//! Many environments stepped together: N [`Env`]s on a thread pool of their own (rayon;
//! with one thread, on the calling thread: no hand-over per step), their observations written into one preallocated array, their rewards, flags and
//! episode figures into one [`Lane`] each, resetting themselves as Gymnasium's autoreset
//! modes say. Each environment is stepped by one thread at a time and touches nothing of
//! the others, so the arrays are the same whatever the thread count.

use std::sync::Arc;

use rayon::prelude::*;

use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::gym::course::CourseCache;
use crate::gym::env::{Env, StepInfo};
use crate::gym::error::GymError;
use crate::gym::options::{Autoreset, EnvOptions, VecOptions};

/// One environment's outcome of the last step or reset.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Lane {
    /// The step's reward.
    pub reward: f64,
    /// The episode ended in the world.
    pub terminated: bool,
    /// The episode reached its duration.
    pub truncated: bool,
    /// This step reset the environment (next-step autoreset, or a reset).
    pub reset: bool,
    /// Same-step autoreset: the final observation of the ended episode is in
    /// [`VecEnv::final_observations`].
    pub has_final: bool,
    /// The episode (the ended one, when it ended this step).
    pub info: StepInfo,
    /// Next-step autoreset: the next step resets this environment.
    needs_reset: bool,
}

/// Where a [`VecEnv`]'s environments are stepped.
enum Threads {
    /// One after another on the calling thread.
    Caller,
    /// On a pool of two or more threads.
    Pool(rayon::ThreadPool),
}

/// What one environment's part of a reset or step is given.
struct LaneWork<'a> {
    /// The environment's index.
    index: usize,
    env: &'a mut Env,
    /// Its observation row.
    obs: &'a mut [f64],
    /// Its final-observation row (same-step autoreset).
    fin: &'a mut [f64],
    lane: &'a mut Lane,
}

impl<'a> LaneWork<'a> {
    /// Environment `index`'s environment, observation row, final-observation row and lane.
    fn new(
        index: usize,
        (env, obs, fin, lane): (&'a mut Env, &'a mut [f64], &'a mut [f64], &'a mut Lane),
    ) -> LaneWork<'a> {
        LaneWork {
            index,
            env,
            obs,
            fin,
            lane,
        }
    }
}

/// N environments of one simulation, stepped on a pool of threads.
pub struct VecEnv {
    envs: Vec<Env>,
    lanes: Vec<Lane>,
    obs: Vec<f64>,
    final_obs: Vec<f64>,
    threads: Threads,
    autoreset: Autoreset,
    obs_len: usize,
    action_len: usize,
}

impl VecEnv {
    /// `n` environments of `sim`, built in parallel on `threads` threads.
    pub fn new(
        sim: Arc<Simulation>,
        registry: &ModuleRegistry,
        opts: &EnvOptions,
        n: usize,
        vec: VecOptions,
    ) -> Result<VecEnv, GymError> {
        let VecOptions { threads, autoreset } = vec;
        if n == 0 {
            return Err(GymError::Option {
                option: "num_envs",
                value: n.to_string(),
                want: "give at least one environment",
            });
        }
        if threads == 0 {
            return Err(GymError::Option {
                option: "threads",
                value: threads.to_string(),
                want: "give at least one thread",
            });
        }
        // One cache of a suite task's courses for every lane: a course is held once.
        let cache = CourseCache::default();
        let make = |_| Env::sharing(sim.clone(), registry.clone(), opts.clone(), cache.clone());
        let (threads, envs) = if threads == 1 {
            let envs = (0..n).map(make).collect::<Result<Vec<Env>, GymError>>()?;
            (Threads::Caller, envs)
        } else {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .thread_name(|i| format!("proleg-env-{i}"))
                .build()
                .map_err(|e| GymError::Threads(e.to_string()))?;
            let envs = pool.install(|| {
                (0..n)
                    .into_par_iter()
                    .map(make)
                    .collect::<Result<Vec<Env>, GymError>>()
            })?;
            (Threads::Pool(pool), envs)
        };
        let obs_len = envs[0].layout().len();
        let action_len = envs[0].action_len();
        Ok(VecEnv {
            lanes: vec![Lane::default(); n],
            obs: vec![0.0; n * obs_len],
            final_obs: vec![0.0; n * obs_len],
            envs,
            threads,
            autoreset,
            obs_len,
            action_len,
        })
    }

    /// The environments.
    pub fn envs(&self) -> &[Env] {
        &self.envs
    }

    /// Threads that step the environments.
    pub fn threads(&self) -> usize {
        match &self.threads {
            Threads::Caller => 1,
            Threads::Pool(pool) => pool.current_num_threads(),
        }
    }

    /// Runs `f` on every environment's part, in parallel on the pool (the first error
    /// found is returned; every environment touches only its own part).
    fn for_each_lane(
        &mut self,
        f: impl Fn(LaneWork<'_>) -> Result<(), GymError> + Sync,
    ) -> Result<(), GymError> {
        let o = self.obs_len;
        match &self.threads {
            Threads::Caller => self
                .envs
                .iter_mut()
                .zip(self.obs.chunks_mut(o))
                .zip(self.final_obs.chunks_mut(o))
                .zip(self.lanes.iter_mut())
                .enumerate()
                .try_for_each(|(index, (((env, obs), fin), lane))| {
                    f(LaneWork::new(index, (env, obs, fin, lane)))
                }),
            Threads::Pool(pool) => {
                let work = (
                    self.envs.par_iter_mut(),
                    self.obs.par_chunks_mut(o),
                    self.final_obs.par_chunks_mut(o),
                    self.lanes.par_iter_mut(),
                );
                pool.install(|| {
                    work.into_par_iter()
                        .enumerate()
                        .try_for_each(|(index, parts)| f(LaneWork::new(index, parts)))
                })
            }
        }
    }

    /// The autoreset mode.
    pub fn autoreset(&self) -> Autoreset {
        self.autoreset
    }

    /// Values per observation of one environment.
    pub fn obs_len(&self) -> usize {
        self.obs_len
    }

    /// Values per action of one environment.
    pub fn action_len(&self) -> usize {
        self.action_len
    }

    /// The observations of the last step or reset, environment after environment.
    pub fn observations(&self) -> &[f64] {
        &self.obs
    }

    /// Same-step autoreset: the final observations of the episodes that ended in the last
    /// step (rows of the others are stale; see [`Lane::has_final`]).
    pub fn final_observations(&self) -> &[f64] {
        &self.final_obs
    }

    /// Each environment's outcome of the last step or reset.
    pub fn lanes(&self) -> &[Lane] {
        &self.lanes
    }

    /// Resets the environments `mask` selects (all without one): environment i with
    /// `seed + i` when a seed is given, else with the next seed of its own stream.
    pub fn reset(&mut self, seed: Option<u64>, mask: Option<&[bool]>) -> Result<(), GymError> {
        let n = self.envs.len();
        if let Some(m) = mask
            && m.len() != n
        {
            return Err(GymError::Shape {
                what: "the reset mask",
                given: m.len(),
                want: n,
            });
        }
        self.for_each_lane(|w| {
            let i = w.index;
            if mask.is_some_and(|m| !m[i]) {
                return Ok(());
            }
            let info = w.env.reset(seed.map(|s| s.wrapping_add(i as u64)), w.obs)?;
            *w.lane = Lane {
                reset: true,
                info,
                ..Lane::default()
            };
            Ok(())
        })
    }

    /// One step of every environment with its row of `actions` (n x action_len values),
    /// resetting finished ones as the autoreset mode says.
    pub fn step(&mut self, actions: &[f64]) -> Result<(), GymError> {
        let a = self.action_len;
        let want = self.envs.len() * a;
        if actions.len() != want {
            return Err(GymError::Shape {
                what: "the actions",
                given: actions.len(),
                want,
            });
        }
        let mode = self.autoreset;
        self.for_each_lane(|w| {
            let i = w.index;
            step_lane(mode, w, &actions[i * a..(i + 1) * a])
        })
    }
}

/// One environment's step under `mode`.
fn step_lane(mode: Autoreset, work: LaneWork<'_>, action: &[f64]) -> Result<(), GymError> {
    let LaneWork {
        env,
        obs,
        fin,
        lane,
        ..
    } = work;
    if mode == Autoreset::NextStep && lane.needs_reset {
        let info = env.reset(None, obs)?;
        *lane = Lane {
            reset: true,
            info,
            ..Lane::default()
        };
        return Ok(());
    }
    let t = env.step(action, obs)?;
    let over = t.terminated || t.truncated;
    *lane = Lane {
        reward: t.reward,
        terminated: t.terminated,
        truncated: t.truncated,
        reset: false,
        has_final: false,
        info: t.info,
        needs_reset: mode == Autoreset::NextStep && over,
    };
    if mode == Autoreset::SameStep && over {
        fin.copy_from_slice(obs);
        lane.has_final = true;
        env.reset(None, obs)?;
    }
    Ok(())
}
