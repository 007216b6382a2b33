//! How an environment is set up: the engine, the control period, whether the policy drives
//! the joints alone or adds a residual to the simulation's own modules, and the reward
//! ([`EnvOptions`]); how N of them run together ([`VecOptions`]: threads, autoreset). The
//! one definition of every option, its default and its meaning: the Python package takes
//! them by name ([`EnvOptions::set`], [`VecOptions::set`]) and documents them from
//! [`documented`], so no default is written twice.

use std::path::PathBuf;

use crate::config::fitness::Fitness;
#[cfg(doc)]
use crate::config::robustness::Robustness;
use crate::config::simulation::EngineKind;
use crate::config::terrain::{Family, Tier};
use crate::gym::course::{CourseOptions, Split};
use crate::gym::error::GymError;

/// Whether the policy is the robot's only module or one more beside the file's modules.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionMode {
    /// The policy's targets are the joint targets (the file's modules are removed).
    Alone,
    /// The policy's targets are added to the sum of the file's modules (the kernel sums
    /// modules, thesis fig. 4.4); the observation then carries the generators' phases.
    Residual,
}

impl ActionMode {
    /// Reads `"alone"` or `"residual"`.
    pub fn parse(s: &str) -> Result<ActionMode, GymError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "alone" => Ok(ActionMode::Alone),
            "residual" => Ok(ActionMode::Residual),
            _ => Err(GymError::Option {
                option: "mode",
                value: s.to_string(),
                want: "give \"alone\" or \"residual\"",
            }),
        }
    }

    /// The name [`ActionMode::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            ActionMode::Alone => "alone",
            ActionMode::Residual => "residual",
        }
    }
}

/// An environment's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvOptions {
    /// The engine instead of the file's (`None`: the file's `<physicsEngine>`).
    pub engine: Option<EngineKind>,
    /// Simulated seconds between two actions (one environment step).
    pub control_period: f64,
    /// Alone or residual.
    pub mode: ActionMode,
    /// The fraction of each joint's half range that an action of 1 moves its target (default
    /// 1 alone, 0.25 as a residual).
    pub action_scale: Option<f64>,
    /// The fitness whose growth is the reward: the episode's return is the optimizers' score
    /// of the same episode (minus the energy term).
    pub fitness: Fitness,
    /// Reward lost per joule the servos put out.
    pub energy_weight: f64,
    /// Simulated seconds per episode (`None`: the task's, else the file's duration); then
    /// the episode is truncated.
    pub duration: Option<f64>,
    /// A suite task's terrain family: each reset builds the robot on one of its courses.
    pub terrain: Option<Family>,
    /// The task's difficulty (a tier's value).
    pub difficulty: f64,
    /// The suite holding the task.
    pub suite: Option<PathBuf>,
    /// Which of the task's seed lists resets draw from.
    pub split: Split,
    /// One course for every reset, instead of a drawn one.
    pub terrain_seed: Option<u64>,
    /// Every reset draws the world's physics from [`Robustness::typical`]'s ranges with
    /// the reset's seed, as `proleg robustness` draws its episodes.
    pub randomize: bool,
    /// Frames per simulated second of every episode's recording for the browser's 3D
    /// replay ([`crate::gym::Env::replay`]); 0: nothing is recorded.
    pub replay_fps: f64,
}

impl Default for EnvOptions {
    fn default() -> Self {
        EnvOptions {
            engine: None,
            control_period: 0.02,
            mode: ActionMode::Alone,
            action_scale: None,
            fitness: Fitness::Distance,
            energy_weight: 0.0,
            duration: None,
            terrain: None,
            difficulty: Tier::Medium.difficulty(),
            suite: None,
            split: Split::Train,
            terrain_seed: None,
            randomize: false,
            replay_fps: 0.0,
        }
    }
}

impl EnvOptions {
    /// The action scale in force.
    pub fn scale(&self) -> f64 {
        self.action_scale.unwrap_or(match self.mode {
            ActionMode::Alone => 1.0,
            ActionMode::Residual => 0.25,
        })
    }

    /// The suite task the options ask for, if they name a terrain.
    pub fn course(&self) -> Result<Option<CourseOptions>, GymError> {
        let Some(family) = self.terrain else {
            if self.terrain_seed.is_some() {
                return Err(GymError::NoTerrain("terrain_seed"));
            }
            return Ok(None);
        };
        let Some(suite) = self.suite.clone() else {
            return Err(GymError::Option {
                option: "suite",
                value: "None".into(),
                want: "a terrain task needs its suite file (the registered ids give the shipped one)",
            });
        };
        Ok(Some(CourseOptions {
            family,
            difficulty: self.difficulty,
            suite,
            split: self.split,
            terrain_seed: self.terrain_seed,
        }))
    }

    /// Refuses options no episode can run with.
    pub fn check(&self) -> Result<(), GymError> {
        let positive = |option, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(GymError::Option {
                    option,
                    value: v.to_string(),
                    want: "give a positive number",
                })
            }
        };
        positive("control_period", self.control_period)?;
        positive("action_scale", self.scale())?;
        if let Some(d) = self.duration {
            positive("duration", d)?;
        }
        if !(0.0..=1.0).contains(&self.difficulty) {
            return Err(GymError::Option {
                option: "difficulty",
                value: self.difficulty.to_string(),
                want: "give a number in [0, 1] or \"easy\", \"medium\", \"hard\"",
            });
        }
        self.course()?;
        if !(self.energy_weight.is_finite() && self.energy_weight >= 0.0) {
            return Err(GymError::Option {
                option: "energy_weight",
                value: self.energy_weight.to_string(),
                want: "give zero or a positive number",
            });
        }
        if !(self.replay_fps.is_finite() && self.replay_fps >= 0.0) {
            return Err(GymError::Option {
                option: "replay_fps",
                value: self.replay_fps.to_string(),
                want: "give 0 (no replay) or a positive number of frames per simulated second",
            });
        }
        if self.fitness == Fitness::CostOfTransport {
            return Err(GymError::Option {
                option: "fitness",
                value: self.fitness.name().to_string(),
                want: "the reward grows with displacement, distance or speed; cost of transport is undefined before the robot moves (use energy_weight)",
            });
        }
        Ok(())
    }
}

/// When a finished environment starts its next episode (Gymnasium 1.x's `AutoresetMode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Autoreset {
    /// On the step after the one that ended it: that step ignores the action and returns
    /// the first observation, reward 0, neither flag (Gymnasium's default).
    NextStep,
    /// On the step that ended it: the observation returned is the new episode's first, the
    /// last one of the ended episode is kept as its final observation.
    SameStep,
    /// Never by itself: finished environments are reset through
    /// [`crate::gym::VecEnv::reset`] with a mask.
    Disabled,
}

impl Autoreset {
    /// Reads Gymnasium's names (`next_step`, `same_step`, `disabled`, any case).
    pub fn parse(s: &str) -> Result<Autoreset, GymError> {
        match s.trim().to_ascii_lowercase().replace('-', "_").as_str() {
            "next_step" | "nextstep" => Ok(Autoreset::NextStep),
            "same_step" | "samestep" => Ok(Autoreset::SameStep),
            "disabled" => Ok(Autoreset::Disabled),
            _ => Err(GymError::Option {
                option: "autoreset_mode",
                value: s.to_string(),
                want: "give next_step, same_step or disabled",
            }),
        }
    }
    /// The name [`Autoreset::parse`] reads first.
    pub fn name(self) -> &'static str {
        match self {
            Autoreset::NextStep => "next_step",
            Autoreset::SameStep => "same_step",
            Autoreset::Disabled => "disabled",
        }
    }
}

/// A value given for an option by name (a keyword of the Python package).
#[derive(Debug, Clone, PartialEq)]
pub enum OptionValue {
    /// No value (`None`): the option's "not set", where it has one.
    Unset,
    /// A number.
    Number(f64),
    /// A name.
    Text(String),
}

/// One option as a user sees it: its keyword, its default written as Python writes it, and
/// what it sets.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionDoc {
    /// The keyword.
    pub name: &'static str,
    /// The default, as a Python literal.
    pub default: String,
    /// What it sets.
    pub doc: &'static str,
}

/// What each option of [`EnvOptions`] and [`VecOptions`] sets, in keyword order.
const DOCS: [(&str, &str); 16] = [
    (
        "engine",
        "the physics engine, \"rapier\" or \"mujoco\" (None: the file's)",
    ),
    (
        "control_period",
        "simulated seconds per environment step (a whole number of steps)",
    ),
    (
        "mode",
        "\"alone\" (the policy drives every joint) or \"residual\" (added to the file's modules)",
    ),
    (
        "action_scale",
        "the share of each joint's half range an action of 1 moves its target (None: 1 alone, 0.25 as a residual)",
    ),
    (
        "fitness",
        "the fitness whose growth is the reward: \"distance\", \"displacement\" or \"speed\"",
    ),
    ("energy_weight", "reward lost per joule the servos put out"),
    (
        "duration",
        "simulated seconds per episode (None: the file's duration)",
    ),
    (
        "terrain",
        "a suite task's terrain family (\"pegs\", \"rough\", ...): each reset builds the robot on one of its courses (None: the file's world)",
    ),
    (
        "difficulty",
        "the task's difficulty: \"easy\", \"medium\", \"hard\" or its number in [0, 1]",
    ),
    ("suite", "the suite file holding the task"),
    (
        "split",
        "\"train\" (resets draw the task's train seeds) or \"test\" (its held-out test seeds)",
    ),
    (
        "terrain_seed",
        "one course for every reset (None: drawn from the reset's seed)",
    ),
    (
        "randomize",
        "each reset draws the physics as `proleg robustness` does (friction, masses, servos, start pose, sensor noise) from its seed",
    ),
    (
        "replay_fps",
        "frames per simulated second of each episode's recording for the browser's 3D replay (save_html); 0: none (the frame period is the nearest whole number of steps)",
    ),
    (
        "threads",
        "threads stepping a vector environment's worlds (the machine's cores by default)",
    ),
    (
        "autoreset",
        "when a vector environment's finished episode restarts: \"next_step\", \"same_step\" or \"disabled\"",
    ),
];

/// Python's literal of an optional number.
fn py_number(v: Option<f64>) -> String {
    v.map_or_else(|| "None".to_string(), |v| format!("{v:?}"))
}

/// Every option of an environment and of a vector environment with its default (this
/// machine's core count for `threads`) and meaning, in keyword order.
pub fn documented() -> Vec<OptionDoc> {
    let e = EnvOptions::default();
    let v = VecOptions::default();
    let defaults = [
        e.engine
            .map_or_else(|| "None".to_string(), |k| format!("\"{k}\"")),
        py_number(Some(e.control_period)),
        format!("\"{}\"", e.mode.name()),
        py_number(e.action_scale),
        format!("\"{}\"", e.fitness.name()),
        py_number(Some(e.energy_weight)),
        py_number(e.duration),
        e.terrain
            .map_or_else(|| "None".to_string(), |f| format!("\"{f}\"")),
        py_number(Some(e.difficulty)),
        e.suite.as_ref().map_or_else(
            || "None".to_string(),
            |p| format!("{:?}", p.display().to_string()),
        ),
        format!("\"{}\"", e.split.name()),
        e.terrain_seed
            .map_or_else(|| "None".to_string(), |s| s.to_string()),
        if e.randomize { "True" } else { "False" }.to_string(),
        py_number(Some(e.replay_fps)),
        v.threads.to_string(),
        format!("\"{}\"", v.autoreset.name()),
    ];
    DOCS.iter()
        .zip(defaults)
        .map(|((name, doc), default)| OptionDoc { name, default, doc })
        .collect()
}

/// `value` as the option `option` wants it.
fn number(option: &'static str, value: &OptionValue) -> Result<f64, GymError> {
    match value {
        OptionValue::Number(v) => Ok(*v),
        other => Err(wrong(option, other, "give a number")),
    }
}

fn maybe_number(option: &'static str, value: &OptionValue) -> Result<Option<f64>, GymError> {
    match value {
        OptionValue::Unset => Ok(None),
        v => number(option, v).map(Some),
    }
}

fn text<'a>(option: &'static str, value: &'a OptionValue) -> Result<&'a str, GymError> {
    match value {
        OptionValue::Text(t) => Ok(t),
        other => Err(wrong(option, other, "give a name")),
    }
}

fn wrong(option: &'static str, value: &OptionValue, want: &'static str) -> GymError {
    GymError::Option {
        option,
        value: match value {
            OptionValue::Unset => "None".to_string(),
            OptionValue::Number(v) => v.to_string(),
            OptionValue::Text(t) => format!("{t:?}"),
        },
        want,
    }
}

impl EnvOptions {
    /// Sets the option called `name` (see [`documented`]); an unknown name is an error
    /// listing the known ones.
    pub fn set(&mut self, name: &str, value: &OptionValue) -> Result<(), GymError> {
        match name {
            "engine" => {
                self.engine = match value {
                    OptionValue::Unset => None,
                    v => Some(
                        EngineKind::parse(text("engine", v)?)
                            .ok_or_else(|| wrong("engine", v, "give \"rapier\" or \"mujoco\""))?,
                    ),
                }
            }
            "control_period" => self.control_period = number("control_period", value)?,
            "mode" => self.mode = ActionMode::parse(text("mode", value)?)?,
            "action_scale" => self.action_scale = maybe_number("action_scale", value)?,
            "fitness" => {
                self.fitness = Fitness::parse(text("fitness", value)?).map_err(|_| {
                    wrong(
                        "fitness",
                        value,
                        "give \"distance\", \"displacement\" or \"speed\"",
                    )
                })?
            }
            "energy_weight" => self.energy_weight = number("energy_weight", value)?,
            "duration" => self.duration = maybe_number("duration", value)?,
            "terrain" => {
                self.terrain = match value {
                    OptionValue::Unset => None,
                    v => Some(Family::parse(text("terrain", v)?).map_err(|_| {
                        wrong(
                            "terrain",
                            v,
                            "give a family: rough, hills, steps, stairs, slope, pegs, channel or rubble",
                        )
                    })?),
                }
            }
            "difficulty" => {
                self.difficulty = match value {
                    OptionValue::Text(t) => Tier::parse(t)
                        .ok_or_else(|| {
                            wrong("difficulty", value, "give easy, medium, hard or a number")
                        })?
                        .difficulty(),
                    v => number("difficulty", v)?,
                }
            }
            "suite" => {
                self.suite = match value {
                    OptionValue::Unset => None,
                    v => Some(PathBuf::from(text("suite", v)?)),
                }
            }
            "split" => self.split = Split::parse(text("split", value)?)?,
            "terrain_seed" => {
                self.terrain_seed = match maybe_number("terrain_seed", value)? {
                    None => None,
                    Some(s) if s >= 0.0 && s.fract() == 0.0 && s < 9.0e15 => Some(s as u64),
                    Some(_) => {
                        return Err(wrong(
                            "terrain_seed",
                            value,
                            "give a whole number of at least 0",
                        ));
                    }
                }
            }
            "randomize" => {
                self.randomize = match value {
                    OptionValue::Number(v) if *v == 0.0 || *v == 1.0 => *v == 1.0,
                    other => return Err(wrong("randomize", other, "give True or False")),
                }
            }
            "replay_fps" => self.replay_fps = number("replay_fps", value)?,
            _ => return Err(unknown(name)),
        }
        Ok(())
    }
}

/// An option no environment has.
fn unknown(name: &str) -> GymError {
    GymError::UnknownOption {
        name: name.to_string(),
        known: DOCS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", "),
    }
}

/// How N environments run together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VecOptions {
    /// Threads stepping the worlds (1: on the calling thread).
    pub threads: usize,
    /// When a finished episode restarts.
    pub autoreset: Autoreset,
}

impl Default for VecOptions {
    fn default() -> Self {
        VecOptions {
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            autoreset: Autoreset::NextStep,
        }
    }
}

impl VecOptions {
    /// Sets the option called `name` (`threads`, `autoreset`), else hands it to `env`'s.
    pub fn set(
        &mut self,
        env: &mut EnvOptions,
        name: &str,
        value: &OptionValue,
    ) -> Result<(), GymError> {
        match name {
            "threads" => {
                let n = number("threads", value)?;
                if !(n >= 1.0 && n.fract() == 0.0) {
                    return Err(wrong("threads", value, "give a whole number of at least 1"));
                }
                self.threads = n as usize;
            }
            "autoreset" => self.autoreset = Autoreset::parse(text("autoreset", value)?)?,
            "replay_fps" if *value != OptionValue::Number(0.0) => {
                return Err(wrong(
                    "replay_fps",
                    value,
                    "a vector environment records no replay: record one episode with proleg.ProlegEnv(..., replay_fps=30)",
                ));
            }
            _ => env.set(name, value)?,
        }
        Ok(())
    }
}
