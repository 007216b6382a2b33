//! How an environment is set up: the engine, the control period, whether the policy drives
//! the joints alone or adds a residual to the simulation's own modules, and the reward.

use crate::config::fitness::Fitness;
use crate::config::simulation::EngineKind;
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
    /// Simulated seconds per episode (`None`: the file's duration); then the episode is
    /// truncated.
    pub duration: Option<f64>,
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
        if !(self.energy_weight.is_finite() && self.energy_weight >= 0.0) {
            return Err(GymError::Option {
                option: "energy_weight",
                value: self.energy_weight.to_string(),
                want: "give zero or a positive number",
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
