//! The fixed-step pipeline (thesis Algorithm 1 around one physics step), as its own
//! schedule with ordered sets: `Sense -> Actuate -> Kernel -> Servo -> Physics -> Record
//! -> Clock`. One run of [`SimStep`] is one simulation step of δ seconds.

use bevy::ecs::schedule::ScheduleLabel;
use bevy::ecs::schedule::SingleThreadedExecutor;
use bevy::prelude::*;

use crate::sim::{clock, datalog, kernel, laser, physics, position, record, servo, tactile};

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
    /// Trajectories and data.
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
            (
                servo::sense_joints,
                position::sense_position,
                tactile::sense_tactile,
                laser::scan_lasers,
            )
                .in_set(SimSystems::Sense),
            kernel::actuate.in_set(SimSystems::Actuate),
            kernel::sum_outputs.in_set(SimSystems::Kernel),
            servo::drive_servos.in_set(SimSystems::Servo),
            physics::step_physics.in_set(SimSystems::Physics),
            (record::record, datalog::log_data).in_set(SimSystems::Record),
            clock::advance_clock.in_set(SimSystems::Clock),
        ),
    );
}
