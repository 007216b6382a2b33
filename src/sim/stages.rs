//! The step's stages as Bevy plugins, one per [`SimSystems`] set, gathered in the
//! [`SimPlugins`] group (after avian's `PhysicsPlugins`). A stage is replaced by disabling
//! its plugin and adding one that puts other systems into the same set:
//!
//! ```ignore
//! app.add_plugins(SimPlugins.build().disable::<ServoPlugin>().add(MyServoPlugin));
//! ```
//!
//! | plugin | set | systems, in order |
//! |---|---|---|
//! | [`StepSchedulePlugin`] | - | the `SimStep` schedule, its sets chained |
//! | [`SensePlugin`] | `Sense` | `servo::sense_joints`, `position::sense_position`, `tactile::sense_tactile`, `laser::scan_lasers` |
//! | [`ActuatePlugin`] | `Actuate` | `kernel::actuate` |
//! | [`KernelPlugin`] | `Kernel` | `kernel::sum_outputs` |
//! | [`ServoPlugin`] | `Servo` | `servo::drive_servos` |
//! | [`PhysicsStepPlugin`] | `Physics` | `physics::step_physics` |
//! | [`RecordPlugin`] | `Record` | `energy::accumulate_energy`, `record::record`, `datalog::log_data` |
//! | [`ClockPlugin`] | `Clock` | `clock::advance_clock` |
//!
//! [`StageTimerPlugin`] (not in the group; `proleg bench --stages`) adds a time stamp
//! between every two stages and sums each stage's wall time in [`StageTimes`].

use std::time::Instant;

use bevy::app::PluginGroupBuilder;
use bevy::prelude::*;

pub use crate::sim::schedule::StepSchedulePlugin;
use crate::sim::schedule::{SimStep, SimSystems};
use crate::sim::{
    clock, datalog, energy, kernel, laser, physics, position, record, servo, tactile,
};

/// The simulation core: the step schedule and one plugin per stage. The world itself is
/// built by [`crate::sim::spawn::build_world`] (the runner does it).
pub struct SimPlugins;

impl PluginGroup for SimPlugins {
    fn build(self) -> PluginGroupBuilder {
        PluginGroupBuilder::start::<Self>()
            .add(StepSchedulePlugin)
            .add(SensePlugin)
            .add(ActuatePlugin)
            .add(KernelPlugin)
            .add(ServoPlugin)
            .add(PhysicsStepPlugin)
            .add(RecordPlugin)
            .add(ClockPlugin)
    }
}

/// Joint angles and sensor readings (three of them write the robots' sensor readings:
/// one fixed order).
pub struct SensePlugin;

impl Plugin for SensePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            SimStep,
            (
                servo::sense_joints,
                position::sense_position,
                tactile::sense_tactile,
                laser::scan_lasers,
            )
                .chain()
                .in_set(SimSystems::Sense),
        );
    }
}

/// Every actuation module computes.
pub struct ActuatePlugin;

impl Plugin for ActuatePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(SimStep, kernel::actuate.in_set(SimSystems::Actuate));
    }
}

/// Module outputs summed per joint into servo targets.
pub struct KernelPlugin;

impl Plugin for KernelPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(SimStep, kernel::sum_outputs.in_set(SimSystems::Kernel));
    }
}

/// Servo targets into motor commands: the servo model.
pub struct ServoPlugin;

impl Plugin for ServoPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(SimStep, servo::drive_servos.in_set(SimSystems::Servo));
    }
}

/// One physics step of the engine.
pub struct PhysicsStepPlugin;

impl Plugin for PhysicsStepPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(SimStep, physics::step_physics.in_set(SimSystems::Physics));
    }
}

/// Energy, trajectories and data.
pub struct RecordPlugin;

impl Plugin for RecordPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            SimStep,
            (energy::accumulate_energy, record::record, datalog::log_data)
                .chain()
                .in_set(SimSystems::Record),
        );
    }
}

/// Step counter and simulated time.
pub struct ClockPlugin;

impl Plugin for ClockPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(SimStep, clock::advance_clock.in_set(SimSystems::Clock));
    }
}

/// Wall time spent in each stage, summed over the steps run since the timer was added.
#[derive(Resource, Debug, Clone, Default, PartialEq)]
pub struct StageTimes {
    /// Seconds per stage, in [`SimSystems::ALL`]'s order.
    pub seconds: [f64; SimSystems::ALL.len()],
    /// Steps timed.
    pub steps: u64,
    last: Option<Instant>,
}

impl StageTimes {
    /// The stages' seconds summed.
    pub fn total(&self) -> f64 {
        self.seconds.iter().sum()
    }

    /// Each stage's share of the step (0 ..= 1), in [`SimSystems::ALL`]'s order.
    pub fn shares(&self) -> [f64; SimSystems::ALL.len()] {
        let total = self.total().max(1e-12);
        self.seconds.map(|s| s / total)
    }
}

/// Times every stage of the step (a time stamp before the first stage, between every two
/// and after the last); for benchmarks, not in [`SimPlugins`].
pub struct StageTimerPlugin;

impl Plugin for StageTimerPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<StageTimes>();
        let sets = SimSystems::ALL;
        app.add_systems(SimStep, stamp::<0>.before(sets[0]));
        app.add_systems(SimStep, stamp::<1>.after(sets[0]).before(sets[1]));
        app.add_systems(SimStep, stamp::<2>.after(sets[1]).before(sets[2]));
        app.add_systems(SimStep, stamp::<3>.after(sets[2]).before(sets[3]));
        app.add_systems(SimStep, stamp::<4>.after(sets[3]).before(sets[4]));
        app.add_systems(SimStep, stamp::<5>.after(sets[4]).before(sets[5]));
        app.add_systems(SimStep, stamp::<6>.after(sets[5]).before(sets[6]));
        app.add_systems(SimStep, stamp::<7>.after(sets[6]));
    }
}

/// Time stamp `I`: ends stage `I - 1` (when there is one) and starts stage `I`.
fn stamp<const I: usize>(mut times: ResMut<StageTimes>) {
    let now = Instant::now();
    if I > 0
        && let Some(last) = times.last
    {
        times.seconds[I - 1] += (now - last).as_secs_f64();
    }
    if I == SimSystems::ALL.len() {
        times.steps += 1;
        times.last = None;
    } else {
        times.last = Some(now);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::load_simulation;
    use crate::sim::engine::JointReading;
    use crate::sim::physics::SimPhysics;
    use crate::sim::servo::{JointState, SimJoint};
    use crate::sim::{BuildOptions, Simulator};

    /// A servo model that only brakes: every motor commanded to stand still.
    struct BrakePlugin;

    impl Plugin for BrakePlugin {
        fn build(&self, app: &mut App) {
            app.add_systems(SimStep, brake.in_set(SimSystems::Servo));
        }
    }

    fn brake(mut physics: ResMut<SimPhysics>, joints: Query<(&SimJoint, &JointState)>) {
        for (j, s) in &joints {
            let now = JointReading {
                angle: s.angle,
                velocity: s.velocity,
                torque: s.torque,
            };
            physics.engine.drive_joint(j.id, 0.0, &now);
        }
    }

    /// The largest joint angle (deg) of robot 0 over one second of the demo.
    fn largest_angle(mut s: Simulator) -> f64 {
        let mut most = 0.0_f64;
        for _ in 0..10 {
            s.run_steps(100);
            for j in s.joint_states(0).unwrap() {
                most = most.max(j.angle.abs());
            }
        }
        most
    }

    #[test]
    fn the_servo_stage_can_be_replaced_by_another_model() {
        let sim = load_simulation("configs/demo.simulation.xml").unwrap();
        let opts = BuildOptions::default();
        let registry = crate::control::ModuleRegistry::standard();
        let standard = Simulator::with_registry(&sim, &opts, &registry).unwrap();
        let stages = SimPlugins.build().disable::<ServoPlugin>().add(BrakePlugin);
        let braked = Simulator::with_stages(&sim, &opts, &registry, stages).unwrap();
        let (moving, held) = (largest_angle(standard), largest_angle(braked));
        assert!(moving > 20.0, "the sine drives the joints: {moving} deg");
        assert!(held < 2.0, "braking servos hold the joints: {held} deg");
    }

    #[test]
    fn the_stage_timer_times_every_stage_of_every_step() {
        let sim = load_simulation("configs/demo.simulation.xml").unwrap();
        let stages = SimPlugins.build().add(StageTimerPlugin);
        let registry = crate::control::ModuleRegistry::standard();
        let mut s =
            Simulator::with_stages(&sim, &BuildOptions::default(), &registry, stages).unwrap();
        s.run_steps(200);
        let times = s.stage_times().unwrap();
        assert_eq!(times.steps, 200);
        assert!(times.seconds.iter().all(|t| *t > 0.0), "{times:?}");
        let share: f64 = times.shares().iter().sum();
        assert!((share - 1.0).abs() < 1e-9);
    }
}
