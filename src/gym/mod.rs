//! Reinforcement-learning episodes over any simulation file, in the shape Gymnasium 1.x
//! gives them (reset, step, observation, reward, terminated, truncated), for the Python
//! package `proleg` (`python/`) and for Rust alike:
//!
//! | module | role |
//! |---|---|
//! | [`options`] | the environment's settings: engine, control period, alone or residual, reward |
//! | [`observe`] | the observation's layout (a name per index) and its reading from the world |
//! | [`course`] | a suite task's courses: each reset on a train (or test) course, generated once per seed |
//! | [`env`] | one environment: the policy as one more module of the kernel, the reward from the optimizers' fitness, termination on the control window's rule |
//! | [`replay`] | an episode recorded for the browser's 3D replay (`replay_fps`, Python's `save_html`) |
//! | [`statistics`] | a policy's starting point: observation statistics of the file's own gait, a network that outputs 0 |
//! | [`vector`] | N environments on a thread pool, autoreset next-step, same-step or disabled |
//! | [`error`] | [`GymError`] |
//!
//! Nothing here is Python: the binding crate converts arrays and errors and nothing else.

pub mod course;
pub mod env;
pub mod error;
pub mod observe;
pub mod options;
pub mod replay;
pub mod statistics;
pub mod vector;

pub use crate::control::observation::ObsLayout;
pub use env::{Env, StepInfo, Transition};
pub use error::GymError;
pub use options::{ActionMode, Autoreset, EnvOptions, OptionDoc, OptionValue, VecOptions};
pub use vector::{Lane, VecEnv};
