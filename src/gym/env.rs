//! One environment: a simulation file's world driven by a policy every control period.
//!
//! The policy is one more module of the robot's control kernel (a `DirectJointAccess` on
//! every joint, its `Angle` set from the action): alone, the kernel holds only it; as a
//! residual, the kernel sums it with the file's own modules (thesis fig. 4.4). An action
//! in [-1, 1] per joint moves the joint's target by `scale` times its half range, around the
//! middle of its limits (alone) or around the modules' sum (residual).
//!
//! The reward is the growth of proleg's own fitness over the step, minus `energy_weight`
//! times the joules the servos put out, so an episode's return is the optimizers' score of
//! the same episode (minus the energy term). An episode terminates when the robot leaves
//! the world or the physics diverges and is truncated at the duration: each episode is one
//! of the episode runner's ([`Episode`]), its exit rule checked after every action. Every reset builds a fresh world from the seed, so the
//! same seed and actions give the same trajectory, bit for bit; with `randomize` the reset's
//! seed also draws the world's physics (friction, masses, servos, start pose, sensor noise).
//! With `replay_fps`, every episode is recorded as it is stepped ([`crate::gym::replay`])
//! and [`Env::replay`] gives it as the browser's 3D replay plays it.

use std::sync::Arc;

use crate::config::Simulation;
use crate::config::robustness::Robustness;
use crate::control::ModuleRegistry;
use crate::control::observation::ObsLayout;
use crate::gym::course::{CourseCache, Courses};
use crate::gym::error::GymError;
use crate::gym::observe::{Previous, Scratch, layout_of, observe};
use crate::gym::options::{ActionMode, EnvOptions};
use crate::gym::replay::EnvReplay;
use crate::playback::PoseStream;
use crate::playback::record::steps_per_frame;
use crate::rng::SimRng;
use crate::sim::randomize::{SensorNoise, randomize};
use crate::sim::{BuildOptions, Episode, EpisodeEnd, EpisodeSettings, Simulator, WorldExit};

/// The module type that carries the policy's targets into the kernel.
const POLICY_MODULE: &str = "DirectJointAccess";
/// Its parameter that holds each joint's target.
const POLICY_PARAMETER: &str = "Angle";

/// What one environment step gave besides the observation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transition {
    /// The reward of the step.
    pub reward: f64,
    /// The episode ended in the world (the robot left it, the physics diverged).
    pub terminated: bool,
    /// The episode reached its duration.
    pub truncated: bool,
    /// The episode so far.
    pub info: StepInfo,
}

/// The episode so far, after a step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepInfo {
    /// Simulated seconds since the reset.
    pub time: f64,
    /// The fitness of the episode so far (the optimizers' score of it).
    pub score: f64,
    /// Joules the servos put out since the reset.
    pub energy: f64,
    /// How the robot left the world, when it did.
    pub exit: Option<WorldExit>,
    /// The terrain seed of the episode's course, on a suite task.
    pub terrain_seed: Option<u64>,
}

/// One running episode's bookkeeping: the episode runner's, and what the rewards need.
#[derive(Debug, Clone, PartialEq)]
struct EnvEpisode {
    run: Episode,
    prev: Previous,
    score: f64,
    energy: f64,
    steps: u64,
    over: bool,
}

/// An environment over one simulation file.
pub struct Env {
    sim: Arc<Simulation>,
    registry: ModuleRegistry,
    opts: EnvOptions,
    layout: ObsLayout,
    world: Simulator,
    /// The policy's actuator in the kernel.
    policy: usize,
    /// Per joint: the target at action 0 (alone: the middle of the limits) and the change
    /// at action 1.
    scaling: Vec<(f64, f64)>,
    /// The policy module's parameter range (degrees).
    range: (f64, f64),
    targets: Vec<f64>,
    scratch: Scratch,
    steps_per_action: u64,
    max_steps: u64,
    episode: EnvEpisode,
    /// The seed of the next reset without one, and where the last one came from.
    seeds: SimRng,
    ready: bool,
    episodes: u64,
    /// The running episode's recording for the 3D replay (with `replay_fps`).
    replay: Option<EnvReplay>,
    /// A suite task's courses, when the options name a terrain.
    courses: Option<Courses>,
    /// The running episode's course.
    terrain_seed: Option<u64>,
}

impl Env {
    /// An environment over `sim` (loaded with `registry`), built once with the file's seed;
    /// call [`Env::reset`] before the first step.
    pub fn new(
        sim: Arc<Simulation>,
        registry: ModuleRegistry,
        opts: EnvOptions,
    ) -> Result<Env, GymError> {
        Env::sharing(sim, registry, opts, CourseCache::default())
    }

    /// As [`Env::new`], keeping a suite task's courses in `cache` (a vector environment's
    /// lanes share one).
    pub fn sharing(
        sim: Arc<Simulation>,
        registry: ModuleRegistry,
        opts: EnvOptions,
        cache: CourseCache,
    ) -> Result<Env, GymError> {
        opts.check()?;
        let sim = match opts.engine {
            Some(e) if e != sim.engine() => Arc::new((*sim).clone().with_engine(Some(e))),
            _ => sim,
        };
        let props = &sim.files.simulation.properties;
        let dt = props.step_width;
        let ratio = opts.control_period / dt;
        if (ratio - ratio.round()).abs() > 1e-6 || ratio.round() < 1.0 {
            return Err(GymError::Option {
                option: "control_period",
                value: opts.control_period.to_string(),
                want: "give a whole number of the simulation's steps (its <stepWidth>)",
            });
        }
        let steps_per_action = ratio.round() as u64;
        let courses = opts
            .course()?
            .map(|c| Courses::new(&c, cache))
            .transpose()?;
        let duration = opts
            .duration
            .or(courses.as_ref().map(|c| c.task().duration))
            .unwrap_or(props.duration);
        let max_steps = (duration / opts.control_period).round().max(1.0) as u64;
        let seed = props.seed;
        let (world, terrain_seed) = match courses.as_ref() {
            Some(c) => {
                let t = c.pick(seed);
                let on_course = c.world(&sim, t)?;
                (
                    build(&on_course, &registry, seed, SensorNoise::default())?,
                    Some(t),
                )
            }
            None => (build(&sim, &registry, seed, SensorNoise::default())?, None),
        };
        let joints = world.kernel(0)?.joints();
        if joints == 0 {
            return Err(GymError::NoJoints {
                file: sim.file.display().to_string(),
            });
        }
        let run = Episode::begin(&world, episode_settings(&opts, steps_per_action, max_steps))?;
        let mut env = Env {
            layout: layout_of(&world, false)?,
            sim,
            registry,
            world,
            policy: 0,
            scaling: Vec::new(),
            range: (0.0, 0.0),
            targets: vec![0.0; joints],
            scratch: Scratch::default(),
            steps_per_action,
            max_steps,
            episode: EnvEpisode {
                run,
                prev: Previous { com: [0.0; 3] },
                score: 0.0,
                energy: 0.0,
                steps: 0,
                over: true,
            },
            seeds: SimRng::new(seed),
            ready: false,
            episodes: 0,
            replay: None,
            courses,
            terrain_seed,
            opts,
        };
        env.attach_policy()?;
        Ok(env)
    }

    /// The settings.
    pub fn options(&self) -> &EnvOptions {
        &self.opts
    }

    /// The simulation file's model.
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// Values per action (the robot's joints).
    pub fn action_len(&self) -> usize {
        self.targets.len()
    }

    /// The observation's layout.
    pub fn layout(&self) -> &ObsLayout {
        &self.layout
    }

    /// Physics steps per environment step.
    pub fn steps_per_action(&self) -> u64 {
        self.steps_per_action
    }

    /// Environment steps until an episode is truncated.
    pub fn max_steps(&self) -> u64 {
        self.max_steps
    }

    /// The running world (read-only: an environment's world changes through its steps).
    pub fn world(&self) -> &Simulator {
        &self.world
    }

    /// The running world, to lend to an off-screen renderer that draws it (and swaps it
    /// back); stepping or changing it changes the episode.
    pub fn world_mut(&mut self) -> &mut Simulator {
        &mut self.world
    }

    /// A suite task's courses, when the options name a terrain.
    pub fn courses(&self) -> Option<&Courses> {
        self.courses.as_ref()
    }

    /// The terrain seed of the running episode's course (a suite task's environment).
    pub fn terrain_seed(&self) -> Option<u64> {
        self.terrain_seed
    }

    /// Resets so far (each builds a new world).
    pub fn episodes(&self) -> u64 {
        self.episodes
    }

    /// Starts an episode in a fresh world built with `seed` (as `proleg run` builds it with
    /// the file's `<seed>`) and writes its first observation into `obs`. Without a seed the
    /// world's seed is the next of a stream seeded by the last seed given (the file's at
    /// first), so a sequence of episodes is reproducible from its first seed.
    pub fn reset(&mut self, seed: Option<u64>, obs: &mut [f64]) -> Result<StepInfo, GymError> {
        let episode_seed = match seed {
            Some(s) => {
                self.seeds = SimRng::new(s);
                s
            }
            None => self.seeds.next_u64(),
        };
        let built = match self.courses.as_ref() {
            Some(c) => {
                let t = c.pick(episode_seed);
                self.terrain_seed = Some(t);
                c.world(&self.sim, t)?
            }
            None => Arc::clone(&self.sim),
        };
        self.world = self.episode_world(&built, episode_seed)?;
        self.attach_policy()?;
        self.replay = self.begin_replay(&built, episode_seed)?;
        let com = self.world.com(0)?;
        let settings = episode_settings(&self.opts, self.steps_per_action, self.max_steps);
        self.episode = EnvEpisode {
            run: Episode::begin(&self.world, settings)?,
            prev: Previous { com },
            score: 0.0,
            energy: 0.0,
            steps: 0,
            over: false,
        };
        self.ready = true;
        self.episodes += 1;
        self.observe(obs)?;
        Ok(StepInfo {
            terrain_seed: self.terrain_seed,
            ..StepInfo::default()
        })
    }

    /// One environment step: the action's targets held for one control period; the next
    /// observation is written into `obs`.
    pub fn step(&mut self, action: &[f64], obs: &mut [f64]) -> Result<Transition, GymError> {
        if !self.ready {
            return Err(GymError::State("step before reset: call reset first"));
        }
        if self.episode.over {
            return Err(GymError::State(
                "step after the episode ended (terminated or truncated): call reset",
            ));
        }
        self.set_targets(action)?;
        let end = self
            .episode
            .run
            .advance(&mut self.world, self.steps_per_action, None)?;
        self.episode.steps += 1;
        let time = self.episode.run.time(&self.world);
        let score = self.episode.run.score(&self.world, 0)?;
        let energy = self.world.energy(0)?.joules;
        let exit = match end {
            Some(EpisodeEnd::Left(exit)) => Some(exit),
            _ => None,
        };
        let diverged = exit == Some(WorldExit::Diverged);
        let reward = if diverged || !score.is_finite() {
            0.0
        } else {
            (score - self.episode.score) - self.opts.energy_weight * (energy - self.episode.energy)
        };
        let terminated = exit.is_some();
        let truncated = end == Some(EpisodeEnd::Duration);
        if diverged {
            // Nothing in a diverged world is a number worth showing a policy.
            obs.fill(0.0);
        } else {
            self.observe(obs)?;
            self.episode.prev = Previous {
                com: self.world.com(0)?,
            };
            self.episode.score = score;
            self.episode.energy = energy;
        }
        self.episode.over = terminated || truncated;
        if let Some(replay) = self.replay.as_mut() {
            replay.after_step(&self.world, self.episode.steps, score, end)?;
        }
        Ok(Transition {
            reward,
            terminated,
            truncated,
            info: StepInfo {
                time,
                score: self.episode.score,
                energy: self.episode.energy,
                exit,
                terrain_seed: self.terrain_seed,
            },
        })
    }

    /// Writes the observation of the world now into `obs`.
    fn observe(&mut self, obs: &mut [f64]) -> Result<(), GymError> {
        observe(
            &self.world,
            &self.layout,
            &self.episode.prev,
            self.opts.control_period,
            &mut self.scratch,
            obs,
        )
    }

    /// Checks `action` and hands its targets to the policy module.
    fn set_targets(&mut self, action: &[f64]) -> Result<(), GymError> {
        if action.len() != self.targets.len() {
            return Err(GymError::Shape {
                what: "the action",
                given: action.len(),
                want: self.targets.len(),
            });
        }
        let (lo, hi) = self.range;
        for (index, ((t, a), (centre, half))) in self
            .targets
            .iter_mut()
            .zip(action)
            .zip(&self.scaling)
            .enumerate()
        {
            if !a.is_finite() {
                return Err(GymError::NotFinite { index, value: *a });
            }
            *t = (centre + a.clamp(-1.0, 1.0) * half).clamp(lo, hi);
        }
        self.world.kernel_mut(0)?.set_parameter_values(
            self.policy,
            POLICY_PARAMETER,
            &self.targets,
        )?;
        Ok(())
    }

    /// Puts the policy module into the fresh world's kernel (alone: instead of the file's
    /// modules) and, the first time, fixes the observation's layout and the scaling.
    fn attach_policy(&mut self) -> Result<(), GymError> {
        let n = self.targets.len();
        let module = self
            .registry
            .create(POLICY_MODULE, n)
            .map_err(crate::control::kernel::KernelError::Create)?;
        let params = module.parameters();
        let param = params.index(POLICY_PARAMETER).map_err(|error| {
            crate::control::kernel::KernelError::Param {
                module: POLICY_MODULE,
                error,
            }
        })?;
        let d = &params.descriptors()[param];
        self.range = (d.min, d.max);
        let residual = self.opts.mode == ActionMode::Residual;
        let kernel = self.world.kernel_mut(0)?;
        if !residual {
            *kernel = kernel.emptied();
        }
        let scale = self.opts.scale();
        self.scaling = kernel
            .limits()
            .iter()
            .map(|[lo, hi]| {
                let half = 0.5 * (hi - lo) * scale;
                (if residual { 0.0 } else { 0.5 * (lo + hi) }, half)
            })
            .collect();
        self.policy = kernel.add(module, (0..n).collect())?;
        // The policy module has no `Phase` series: the layout lists the file's generators.
        self.layout = layout_of(&self.world, residual)?;
        Ok(())
    }
}

impl Env {
    /// The running episode's frames so far (all of them once it ended) as the browser's
    /// 3D replay plays them, titled `label` (else the file, episode and seed); recorded
    /// when the options ask for `replay_fps`.
    pub fn replay(&self, label: Option<&str>) -> Result<PoseStream, GymError> {
        if self.opts.replay_fps == 0.0 {
            return Err(GymError::State(
                "the environment records no replay: make it with replay_fps=30 (frames per simulated second)",
            ));
        }
        match self.replay.as_ref() {
            Some(r) => Ok(r.stream(label)),
            None => Err(GymError::State(
                "nothing recorded yet: call reset, then step the episode",
            )),
        }
    }

    /// The recording of the episode about to start on the fresh world (built from `sim`
    /// with `seed`), when the options ask for one.
    fn begin_replay(&self, sim: &Simulation, seed: u64) -> Result<Option<EnvReplay>, GymError> {
        let fps = self.opts.replay_fps;
        if fps == 0.0 {
            return Ok(None);
        }
        let name = sim.file.file_name().map_or_else(
            || sim.file.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let course = self
            .terrain_seed
            .map_or_else(String::new, |t| format!(", course {t}"));
        let label = format!(
            "{name}: episode {} (seed {seed}{course})",
            self.episodes + 1
        );
        let period = self.opts.control_period;
        EnvReplay::begin(
            sim,
            &self.world,
            steps_per_frame(fps, period).map_err(|_| GymError::Option {
                option: "replay_fps",
                value: fps.to_string(),
                want: "give 0 (no replay) or a positive number of frames per simulated second",
            })?,
            period,
            self.max_steps,
            (label, self.opts.fitness.name().to_string()),
        )
        .map(Some)
    }

    /// An episode's fresh world of `sim` with `seed`: with `randomize`, its physics drawn
    /// from the typical robustness ranges with that seed (the draw's own seed and sensor
    /// noise then build it), as `proleg robustness` draws an episode.
    fn episode_world(&self, sim: &Simulation, seed: u64) -> Result<Simulator, GymError> {
        if !self.opts.randomize {
            return build(sim, &self.registry, seed, SensorNoise::default());
        }
        let drawn = randomize(sim, &Robustness::typical(), seed);
        build(&drawn.sim, &self.registry, drawn.seed, drawn.noise)
    }
}

/// A fresh world of `sim` with `seed` and sensor `noise`, recording nothing (as the
/// optimizers build theirs).
fn build(
    sim: &Simulation,
    registry: &ModuleRegistry,
    seed: u64,
    noise: SensorNoise,
) -> Result<Simulator, GymError> {
    Ok(Simulator::with_registry(
        sim,
        &BuildOptions {
            seed,
            record: false,
            noise,
            ..Default::default()
        },
        registry,
    )?)
}

/// An episode of `max_steps` actions of `steps_per_action` steps, the exit rule read after
/// every action, scored by the environment's fitness.
fn episode_settings(opts: &EnvOptions, steps_per_action: u64, max_steps: u64) -> EpisodeSettings {
    EpisodeSettings {
        steps: Some(max_steps * steps_per_action),
        check_every: steps_per_action,
        fitness: opts.fitness,
        watch_world: true,
    }
}
