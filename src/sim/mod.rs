//! The simulated world as ECS: the robot and terrain of a configuration built into
//! entities and a physics engine's world (rapier or MuJoCo, behind one interface), stepped
//! by a fixed-step pipeline of ordered system sets, plus a headless runner.
//!
//! - [`schedule`]: the [`SimStep`] schedule and its [`SimSystems`] sets
//! - [`stages`]: one plugin per stage in the [`SimPlugins`] group (replaceable), and the
//!   stage timer of `proleg bench --stages`
//! - [`spawn`]: building the world from a loaded simulation; [`robot`]: the robot
//!   entity's [`robot::SimRobot`]
//! - [`physics`], [`servo`], [`tactile`], [`laser`], [`kernel`], [`record`], [`clock`]: the stages of a step
//! - [`engine`]: the one door to physics ([`engine::PhysicsEngine`]) and the engines behind
//!   it (rapier, MuJoCo)
//! - [`energy`]: each robot's servo power and energy (the `Record` stage)
//! - [`position`]: body sensing, each robot's position and heading before the kernels run
//! - [`datalog`]: the data handlers in the world, recorded by the `Record` stage
//! - [`randomize`]: one randomized episode's physics and sensor noise
//! - [`settle`]: whether a robot comes to rest on its floor (`proleg settle`)
//! - [`error`]: errors building or running a world
//! - [`runner`]: [`Simulator`], the one door to a running world that the CLI, benchmarks,
//!   optimizers, the real-robot twin and the GUI use
//! - [`episode`]: the one episode runner ([`Episode`]): a prepared world run to its end
//!   (duration, leaving the world, divergence, a stop) and its robots scored
//! - [`pacing`]: the wall-clock pacer those runners share
//! - [`driver`]: stepping from a running App (GUI, App-level tests)

pub mod clock;
pub mod datalog;
pub mod driver;
pub mod energy;
pub mod engine;
pub mod episode;
pub mod error;
pub mod kernel;
pub mod laser;
pub mod pacing;
pub mod physics;
pub mod position;
pub mod randomize;
pub mod record;
pub mod robot;
pub mod runner;
pub mod schedule;
pub mod servo;
pub mod settle;
pub mod spawn;
pub mod stages;
pub mod tactile;

pub use driver::{SimDriverPlugin, StepsPerUpdate};
pub use episode::{EXIT_CHECK_SECONDS, Episode, EpisodeEnd, EpisodeSettings, WorldExit};
pub use error::SimError;
pub use pacing::{Pacer, Pacing};
pub use runner::{RunSummary, Simulator};
pub use schedule::{SimStep, SimSystems};
pub use spawn::{BuildOptions, EngineChoice};
pub use stages::{SimPlugins, StageTimerPlugin, StageTimes};
