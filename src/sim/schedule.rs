//! The fixed-step pipeline (thesis Algorithm 1 around one physics step), as its own
//! schedule with ordered sets: `Sense -> Actuate -> Kernel -> Servo -> Physics -> Record
//! -> Clock`. One run of [`SimStep`] is one simulation step of δ seconds.

use bevy::ecs::schedule::ScheduleLabel;
use bevy::ecs::schedule::SingleThreadedExecutor;
use bevy::prelude::*;

use crate::sim::{
    clock, datalog, energy, kernel, laser, physics, position, record, servo, tactile,
};

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

/// Adds the step schedule, its sets in order, and the core systems.
pub(super) fn plugin(app: &mut App) {
    let mut schedule = Schedule::new(SimStep);
    // Measured on 2 cores: the multi-threaded executor is ~20x slower per step here.
    schedule.set_executor(SingleThreadedExecutor::new());
    app.add_schedule(schedule);
    app.init_resource::<datalog::DataSettings>();
    app.configure_sets(
        SimStep,
        (
            SimSystems::Sense,
            SimSystems::Actuate,
            SimSystems::Kernel,
            SimSystems::Servo,
            SimSystems::Physics,
            SimSystems::Record,
            SimSystems::Clock,
        )
            .chain(),
    );
    app.add_systems(
        SimStep,
        (
            // Three of them write the robots' sensor readings: one fixed order.
            (
                servo::sense_joints,
                position::sense_position,
                tactile::sense_tactile,
                laser::scan_lasers,
            )
                .chain()
                .in_set(SimSystems::Sense),
            kernel::actuate.in_set(SimSystems::Actuate),
            kernel::sum_outputs.in_set(SimSystems::Kernel),
            servo::drive_servos.in_set(SimSystems::Servo),
            physics::step_physics.in_set(SimSystems::Physics),
            (energy::accumulate_energy, record::record, datalog::log_data)
                .chain()
                .in_set(SimSystems::Record),
            clock::advance_clock.in_set(SimSystems::Clock),
        ),
    );
}

#[cfg(test)]
mod tests {
    use bevy::ecs::schedule::{LogLevel, ScheduleBuildSettings};

    use super::*;

    /// As avian's `no_ambiguity_errors`: every pair of step systems that touch the same
    /// data runs in a fixed order, so a step cannot depend on the executor's choice.
    #[test]
    fn the_step_has_no_ambiguous_system_pairs() {
        let mut app = App::new();
        app.add_plugins(crate::sim::SimPlugin);
        let world = app.world_mut();
        let Some(mut schedule) = world.resource_mut::<Schedules>().remove(SimStep) else {
            panic!("SimPlugin adds the SimStep schedule");
        };
        schedule.set_build_settings(ScheduleBuildSettings {
            ambiguity_detection: LogLevel::Error,
            ..Default::default()
        });
        if let Err(e) = schedule.initialize(world) {
            panic!("ambiguous systems in SimStep: {e}");
        }
        assert!(schedule.graph().conflicting_systems().0.is_empty());
    }
}
