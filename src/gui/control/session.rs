//! The simulation the window shows: a headless [`Simulator`] (the same core the CLI and the
//! optimizers use) held by the GUI, with the toolbar's controls (start / pause / restart,
//! delay, real-time factor, step width) and the pacing that advances it each frame,
//! decoupled from the frame rate.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::config::Simulation;
use crate::config::fitness::Fitness;
use crate::config::simulation::EngineKind;
use crate::control::ControlKernel;
use crate::control::{ModuleRegistry, load_simulation_in};
use crate::gui::error::GuiError;
use crate::optimize::replay::Replay;
use crate::sim::datalog::DataSettings;
use crate::sim::{
    BuildOptions, Episode, EpisodeEnd, EpisodeSettings, Pacer, Pacing, Simulator, WorldExit,
};

/// Longest a frame may spend stepping when the simulation runs as fast as possible, so the
/// window stays responsive (seconds).
const UNPACED_STEP_BUDGET: f64 = 0.12;

/// Bounds of the stepping time of a paced frame (seconds): a frame may spend on steps as
/// long as the previous frame took (so a slow renderer does not cap the real-time factor),
/// within these.
const PACED_STEP_BUDGET: (f64, f64) = (0.05, 0.25);

/// Why a run paused by itself; the toolbar shows it with what the user can do next.
#[derive(Debug, Clone, PartialEq)]
pub enum Halt {
    /// The simulation's duration (s) was reached.
    Duration(f64),
    /// Robot 0's centre of mass (m) left the world: below its lowest ground or beyond its
    /// sides.
    LeftWorld([f64; 3]),
    /// The physics diverged (robot 0's centre of mass is not a number).
    Diverged,
}

impl Halt {
    /// The message shown.
    pub fn message(&self) -> String {
        match self {
            Halt::Duration(d) => {
                format!("Paused at the simulation's duration, {d} s: Restart, or Continue past it.")
            }
            Halt::LeftWorld(c) => format!(
                "Paused: robot 0 left the world (centre of mass at x {:.2}, y {:.2}, z {:.2} m).",
                c[0], c[1], c[2]
            ),
            Halt::Diverged => "Paused: the physics diverged (robot 0's position is not a number); Restart, perhaps with a smaller step width.".to_string(),
        }
    }
}

/// The running simulation and its controls (a non-send resource: the simulator owns an App).
pub struct SimSession {
    /// The configuration file shown.
    pub path: PathBuf,
    /// The configuration shown.
    pub sim: Simulation,
    /// The running world.
    pub simulator: Simulator,
    /// The kernel as built, for the parameter dialog's Reset.
    pub initial_kernel: ControlKernel,
    /// Whether it runs (not paused).
    pub running: bool,
    /// Real-time factor and slow-motion delay (the toolbar's), applied from the next frame.
    pub pacing: Pacing,
    /// Step width δ (s) used at the next restart.
    pub step_width: f64,
    /// Wall seconds spent running since the last (re)start.
    pub real_time: f64,
    /// Steps due per frame at `pacing` (the pacer the CLI and the real-robot loop use).
    pacer: Pacer,
    /// The last error (load, restart), shown in the toolbar.
    pub error: Option<String>,
    /// Counts the worlds built (load, restart), so views know when to rebuild.
    pub generation: u64,
    /// The stored evaluation shown (`proleg gui --replay`, the results' Replay), rebuilt
    /// with its genome, seed and noise at every restart.
    pub replay: Option<Replay>,
    /// The episode the world runs (the episode runner's): its duration, the exit rule,
    /// robot 0's start for the replay's score.
    episode: Episode,
    /// The engine chosen on the command line (`--engine`), kept for every file loaded.
    pub engine: Option<EngineKind>,
    /// Why the run paused by itself, until it runs again.
    pub halt: Option<Halt>,
    /// Parameter values tuned before the last restart (which set the file's again).
    pub tuned: Option<Vec<crate::control::module::Parameters>>,
    /// Simulated second at which the run pauses quietly (a script's `run-until`).
    pub pause_at: Option<f64>,
    /// Whether the last frame ran: the first frame after a start takes no wall time
    /// (the window may have idled for minutes).
    was_running: bool,
    /// The module types the window offers: the standard library and its plugin host's
    /// modules ([`SimSession::sync_modules`] when the host loads more).
    pub registry: ModuleRegistry,
}

impl SimSession {
    /// Loads `path` and builds its world, paused, on `engine` instead of the file's when
    /// given.
    pub fn open(
        path: &Path,
        engine: Option<EngineKind>,
        registry: &ModuleRegistry,
    ) -> Result<SimSession, GuiError> {
        let sim = load_simulation_in(path, registry)?.with_engine(engine);
        let mut session = SimSession::with(path.to_path_buf(), sim, None, registry)?;
        session.engine = engine;
        Ok(session)
    }

    /// A stored evaluation's world (its configuration, genome, seed and noise), paused.
    pub fn open_replay(replay: Replay, registry: &ModuleRegistry) -> Result<SimSession, GuiError> {
        SimSession::with(
            PathBuf::from(&replay.config),
            replay.sim.clone(),
            Some(replay),
            registry,
        )
    }

    /// Offers the modules `registry` has (the window's plugin host loaded more).
    pub fn sync_modules(&mut self, registry: ModuleRegistry) {
        self.registry = registry;
    }

    fn with(
        path: PathBuf,
        sim: Simulation,
        replay: Option<Replay>,
        registry: &ModuleRegistry,
    ) -> Result<SimSession, GuiError> {
        let step_width = sim.files.simulation.properties.step_width;
        let pacing = Pacing::of(&sim.files.simulation.properties);
        let (simulator, initial_kernel) = build(&sim, step_width, replay.as_ref(), registry)?;
        let episode = begin_episode(&simulator, &sim, replay.as_ref())?;
        Ok(SimSession {
            path,
            sim,
            simulator,
            initial_kernel,
            running: false,
            pacing,
            pacer: Pacer::new(pacing, step_width),
            step_width,
            real_time: 0.0,
            error: None,
            generation: 0,
            replay,
            episode,
            engine: None,
            halt: None,
            tuned: None,
            pause_at: None,
            was_running: false,
            registry: registry.clone(),
        })
    }

    /// Shows stored evaluation `replay` instead (see [`SimSession::open_replay`]); on
    /// failure keeps the current world and records the error.
    pub fn load_replay(&mut self, replay: Replay) {
        if let Err(e) = self.try_load_replay(replay) {
            self.error = Some(e.to_string());
        }
    }

    /// [`SimSession::load_replay`], the error returned instead of recorded.
    pub fn try_load_replay(&mut self, replay: Replay) -> Result<(), GuiError> {
        let s = SimSession::open_replay(replay, &self.registry.clone())?;
        let generation = self.generation + 1;
        *self = s;
        self.generation = generation;
        Ok(())
    }

    /// The replayed episode's score so far (the optimizers' formula on robot 0 since the
    /// world was built); at the episode's duration it is the score the run stored.
    pub fn replay_score(&self) -> Option<Result<f64, crate::sim::SimError>> {
        self.replay.as_ref()?;
        Some(self.episode.score(&self.simulator, 0))
    }

    /// Loads another configuration; on failure keeps the current one and records the error
    /// (saying which one is still shown).
    pub fn load(&mut self, path: &Path) {
        match SimSession::open(path, self.engine, &self.registry.clone()) {
            Ok(s) => {
                let generation = self.generation + 1;
                *self = s;
                self.generation = generation;
            }
            Err(e) => self.error = Some(format!("{e}\n(still showing {})", self.path.display())),
        }
    }

    /// Rebuilds the world on `engine` (the toolbar's physics choice), paused; when it cannot
    /// be built there (MuJoCo's library missing, a model it rejects) the world and engine
    /// stay as they were and the error is shown.
    pub fn set_engine(&mut self, engine: EngineKind) {
        if engine == self.sim.engine() {
            return;
        }
        let sim = self.sim.clone().with_engine(Some(engine));
        match build(&sim, self.step_width, self.replay.as_ref(), &self.registry) {
            Ok((simulator, kernel)) => {
                self.sim = sim;
                self.engine = Some(engine);
                self.install(simulator, kernel);
            }
            Err(e) => self.error = Some(e.to_string()),
        }
    }

    /// Rebuilds the world from the configuration (with the chosen step width), paused. The
    /// parameter values are the file's again; values tuned since the last build are kept
    /// in [`SimSession::tuned`], to put back with [`SimSession::keep_tuned`].
    pub fn restart(&mut self) {
        let tuned = self.simulator.kernel(0).ok().map(|k| k.parameter_values());
        let was = self.initial_kernel.parameter_values();
        match build(
            &self.sim,
            self.step_width,
            self.replay.as_ref(),
            &self.registry,
        ) {
            Ok((simulator, kernel)) => {
                self.install(simulator, kernel);
                self.tuned = tuned.filter(|t| *t != was);
            }
            Err(e) => self.error = Some(e.to_string()),
        }
    }

    /// Puts the parameter values tuned before the last restart back (the toolbar's "Keep
    /// tuned values").
    pub fn keep_tuned(&mut self) {
        if let Some(values) = self.tuned.take()
            && let Ok(k) = self.simulator.kernel_mut(0)
        {
            k.restore_parameter_values(&values);
        }
    }

    /// Shows a newly built world, paused at 0.
    fn install(&mut self, simulator: Simulator, kernel: ControlKernel) {
        match begin_episode(&simulator, &self.sim, self.replay.as_ref()) {
            Ok(episode) => self.episode = episode,
            Err(e) => {
                self.error = Some(e.to_string());
                return;
            }
        }
        self.simulator = simulator;
        self.halt = None;
        self.tuned = None;
        self.initial_kernel = kernel;
        self.real_time = 0.0;
        self.pacer.drop_backlog();
        self.running = false;
        self.error = None;
        self.generation += 1;
    }

    /// Adds a module of type `name` (any registered type, plugins too) driving the joints
    /// whose mask character is `1` to the configuration shown, and rebuilds the world
    /// (paused at 0). The configuration files are not changed.
    pub fn add_module(&mut self, name: &str, mask: &str) -> Result<(), GuiError> {
        let registry = &self.registry;
        let descriptor = registry
            .get(name)
            .ok_or_else(|| GuiError::Missing {
                what: "module type",
                name: format!("{name} (known: {})", registry.names().join(", ")),
            })?
            .clone();
        let joints = self.sim.robot.joints.len();
        let bad = |why: String| GuiError::Mask {
            mask: mask.to_string(),
            why,
        };
        let bits = mask
            .trim()
            .chars()
            .map(|c| match c {
                '0' => Ok(false),
                '1' => Ok(true),
                other => Err(bad(format!("{other:?} is not 0 or 1"))),
            })
            .collect::<Result<Vec<bool>, GuiError>>()?;
        if bits.len() != joints {
            return Err(bad(format!(
                "{} characters; the robot has {joints} joints",
                bits.len()
            )));
        }
        if !bits.contains(&true) {
            return Err(bad("it selects no joint".into()));
        }
        let mut sim = self.sim.clone();
        sim.actuation
            .modules
            .push(crate::config::resolve::actuation::ModuleInstance {
                descriptor,
                joints: crate::config::mask::JointMask(bits),
                params: Vec::new(),
                weights: None,
                pos: crate::config::error::Pos::default(),
            });
        let (simulator, kernel) =
            build(&sim, self.step_width, self.replay.as_ref(), &self.registry)?;
        self.sim = sim;
        self.install(simulator, kernel);
        Ok(())
    }

    /// Gives actuator `actuator` (a `Policy`) the network of weights file `file` and
    /// rebuilds the world (paused at 0). The configuration files are not changed.
    pub fn load_weights(&mut self, actuator: usize, file: &Path) -> Result<(), GuiError> {
        let bytes = std::fs::read(file).map_err(|source| GuiError::Io {
            path: file.to_path_buf(),
            source,
        })?;
        let mut sim = self.sim.clone();
        let count = sim.actuation.modules.len();
        let module = sim.actuation.modules.get_mut(actuator).ok_or(
            crate::control::kernel::KernelError::NoSuchActuator {
                index: actuator,
                count,
            },
        )?;
        module.weights = Some(crate::config::resolve::WeightsFile {
            path: file.to_path_buf(),
            bytes: bytes.into(),
        });
        let (simulator, kernel) =
            build(&sim, self.step_width, self.replay.as_ref(), &self.registry)?;
        self.sim = sim;
        self.install(simulator, kernel);
        Ok(())
    }

    /// Simulated seconds so far.
    pub fn sim_time(&self) -> f64 {
        self.simulator.clock().time()
    }

    /// Steps toward simulated time `t` (rounded to whole steps), at most `budget` of them;
    /// true once there.
    pub fn step_to(&mut self, t: f64, budget: u64) -> bool {
        let target = (t / self.simulator.clock().dt).round().max(0.0) as u64;
        let left = target.saturating_sub(self.steps());
        self.simulator.run_steps(left.min(budget));
        left <= budget
    }

    /// Steps so far.
    pub fn steps(&self) -> u64 {
        self.simulator.clock().step
    }

    /// Runs again after a [`Halt`]: past the duration, or with the robot outside the world
    /// (the check is off until the next restart).
    pub fn continue_run(&mut self) {
        match self.halt.take() {
            Some(Halt::Duration(_) | Halt::LeftWorld(_)) => self.episode.continue_past(),
            Some(Halt::Diverged) | None => return,
        }
        self.running = true;
    }

    /// Advances the simulation for a frame that took `frame_wall` wall seconds: the steps
    /// the pacer says are due (several per frame when faster than the frame rate), or as
    /// many as fit in the frame's budget when unpaced; stops at the duration and when the
    /// robot leaves the world ([`Halt`], the episode runner's end). Returns steps run.
    pub fn advance(&mut self, frame_wall: f64) -> u64 {
        if !self.running {
            self.was_running = false;
            return 0;
        }
        self.halt = None;
        let dt = self.simulator.clock().dt;
        self.pacer.retune(self.pacing, dt);
        if !self.was_running {
            // Started this frame: the wall time before it was idle, not owed.
            self.was_running = true;
            self.pacer.drop_backlog();
            return 0;
        }
        self.real_time += frame_wall;
        let (budget, due) = match self.pacer.steps_for(frame_wall) {
            Some(n) => (
                frame_wall.clamp(PACED_STEP_BUDGET.0, PACED_STEP_BUDGET.1),
                n,
            ),
            None => (UNPACED_STEP_BUDGET, u64::MAX),
        };
        let steps = match self.pause_at {
            Some(t) => {
                let last = (t / dt).round().max(0.0) as u64;
                due.min(last.saturating_sub(self.steps()))
            }
            None => due,
        };
        let (started, first) = (Instant::now(), self.steps());
        // Step in small chunks so the budget is checked without reading the clock each step.
        let mut left = steps;
        loop {
            let chunk = left.min(50);
            match self.episode.advance(&mut self.simulator, chunk, None) {
                Ok(Some(end)) => {
                    self.halt_at(end);
                    break;
                }
                Ok(None) => {}
                Err(e) => {
                    self.error = Some(e.to_string());
                    self.running = false;
                    break;
                }
            }
            left -= chunk;
            if left == 0 || self.pause_reached() {
                break;
            }
            if started.elapsed().as_secs_f64() > budget {
                // Cannot keep up: drop the backlog instead of spiralling.
                self.pacer.drop_backlog();
                break;
            }
        }
        self.pause_reached();
        self.steps() - first
    }

    /// Pauses quietly at a script's `run-until` second; true when it did.
    fn pause_reached(&mut self) -> bool {
        let now = self.steps() as f64 * self.simulator.clock().dt;
        if self.pause_at.is_some_and(|t| now >= t - 1e-9) {
            self.pause_at = None;
            self.running = false;
            return true;
        }
        false
    }

    /// Pauses the run with the [`Halt`] of how its episode ended.
    fn halt_at(&mut self, end: EpisodeEnd) {
        self.running = false;
        self.halt = match end {
            EpisodeEnd::Duration => Some(Halt::Duration(
                self.sim.files.simulation.properties.duration,
            )),
            EpisodeEnd::Left(WorldExit::Left(c)) => Some(Halt::LeftWorld(c)),
            EpisodeEnd::Left(WorldExit::Diverged) => Some(Halt::Diverged),
            EpisodeEnd::Stopped => None,
        };
    }
}

/// The episode a window runs on `simulator`: the file's duration (none when it is 0), and
/// a replay's fitness for its score.
fn begin_episode(
    simulator: &Simulator,
    sim: &Simulation,
    replay: Option<&Replay>,
) -> Result<Episode, crate::sim::SimError> {
    let duration = sim.files.simulation.properties.duration;
    let fitness = replay.map_or(Fitness::Distance, Replay::fitness);
    let mut settings = EpisodeSettings::new(simulator, duration, fitness);
    if duration <= 0.0 {
        settings.steps = None;
    }
    Episode::begin(simulator, settings)
}

/// A simulator for `sim` at step width `dt`, recording into ring buffers for the live
/// plots, and a copy of its kernel as built; with `replay`, built with its seed and noise
/// and its candidate's values in the kernel.
fn build(
    sim: &Simulation,
    dt: f64,
    replay: Option<&Replay>,
    registry: &ModuleRegistry,
) -> Result<(Simulator, ControlKernel), GuiError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(GuiError::StepWidth(dt));
    }
    let mut sim = sim.clone();
    sim.files.simulation.properties.step_width = dt;
    let opts = match replay {
        Some(r) => r.build_options(true),
        None => BuildOptions {
            robots: 1,
            seed: sim.files.simulation.properties.seed,
            record: true,
            ..Default::default()
        },
    };
    let mut simulator = Simulator::with_registry(&sim, &opts, registry)?;
    if let Some(r) = replay {
        r.apply(&mut simulator)?;
    }
    let every = sim.files.simulation.properties.accuracy.max(1);
    simulator.enable_data(
        DataSettings {
            every,
            ..DataSettings::default()
        },
        None,
    );
    let kernel = simulator.kernel(0)?.clone();
    Ok((simulator, kernel))
}
