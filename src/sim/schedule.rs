//! The fixed-step pipeline (thesis Algorithm 1 around one physics step), as its own
//! schedule with ordered sets: `Sense -> Actuate -> Kernel -> Servo -> Physics -> Record
//! -> Clock`. One run of [`SimStep`] is one simulation step of δ seconds. The systems of
//! each set come from the stage plugins of [`crate::sim::stages`].

use bevy::ecs::schedule::ScheduleLabel;
use bevy::ecs::schedule::SingleThreadedExecutor;
use bevy::prelude::*;

use crate::sim::datalog;

/// The schedule of one simulation step.
#[derive(ScheduleLabel, Debug, Clone, PartialEq, Eq, Hash)]
pub struct SimStep;

/// The ordered stages of a step.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SimSystems {
    /// Joint angles and sensor readings.
    Sense,
    /// Every actuation module computes.
    Actuate,
    /// Module outputs summed per joint into servo targets.
    Kernel,
    /// Servo targets into motor commands.
    Servo,
    /// One physics step.
    Physics,
    /// Energy, trajectories and data.
    Record,
    /// Step counter and simulated time.
    Clock,
}

impl SimSystems {
    /// Every stage, in the order a step runs them.
    pub const ALL: [SimSystems; 7] = [
        SimSystems::Sense,
        SimSystems::Actuate,
        SimSystems::Kernel,
        SimSystems::Servo,
        SimSystems::Physics,
        SimSystems::Record,
        SimSystems::Clock,
    ];

    /// The stage's name, as reports print it.
    pub fn name(self) -> &'static str {
        match self {
            SimSystems::Sense => "Sense",
            SimSystems::Actuate => "Actuate",
            SimSystems::Kernel => "Kernel",
            SimSystems::Servo => "Servo",
            SimSystems::Physics => "Physics",
            SimSystems::Record => "Record",
            SimSystems::Clock => "Clock",
        }
    }
}

/// The step schedule (single-threaded) with its sets chained in [`SimSystems::ALL`]'s
/// order; the stages' systems are added by their own plugins.
pub struct StepSchedulePlugin;

impl Plugin for StepSchedulePlugin {
    fn build(&self, app: &mut App) {
        let mut schedule = Schedule::new(SimStep);
        // Measured on 2 cores: the multi-threaded executor is ~20x slower per step here.
        schedule.set_executor(SingleThreadedExecutor::new());
        app.add_schedule(schedule);
        app.init_resource::<datalog::DataSettings>();
        for pair in SimSystems::ALL.windows(2) {
            app.configure_sets(SimStep, pair[0].before(pair[1]));
        }
    }
}

#[cfg(test)]
mod tests {
    use bevy::ecs::schedule::{LogLevel, ScheduleBuildSettings};

    use super::*;
    use crate::sim::stages::{SimPlugins, StageTimerPlugin};

    /// As avian's `no_ambiguity_errors`: every pair of step systems that touch the same
    /// data runs in a fixed order, so a step cannot depend on the executor's choice; with
    /// the stage timer too.
    #[test]
    fn the_step_has_no_ambiguous_system_pairs() {
        for timed in [false, true] {
            let mut app = App::new();
            app.add_plugins(SimPlugins);
            if timed {
                app.add_plugins(StageTimerPlugin);
            }
            let world = app.world_mut();
            let Some(mut schedule) = world.resource_mut::<Schedules>().remove(SimStep) else {
                panic!("SimPlugins add the SimStep schedule");
            };
            schedule.set_build_settings(ScheduleBuildSettings {
                ambiguity_detection: LogLevel::Error,
                ..Default::default()
            });
            if let Err(e) = schedule.initialize(world) {
                panic!("ambiguous systems in SimStep (timed: {timed}): {e}");
            }
            assert!(schedule.graph().conflicting_systems().0.is_empty());
        }
    }
}
