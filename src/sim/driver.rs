//! Stepping the simulation from a running App (App-level tests): every `Update` runs
//! [`SimStep`] a number of times. The headless [`crate::sim::Simulator`], which the CLI,
//! the optimizers and the control window use, steps the schedule directly instead.

use bevy::prelude::*;

use crate::sim::schedule::SimStep;

/// Simulation steps per App update (0 pauses).
#[derive(Resource, Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepsPerUpdate(pub u32);

/// Runs the simulation steps of one update.
pub fn drive(world: &mut World) {
    let n = world.get_resource::<StepsPerUpdate>().map_or(0, |s| s.0);
    for _ in 0..n {
        world.run_schedule(SimStep);
    }
}

/// Adds [`drive`] to `Update`, paused until [`StepsPerUpdate`] is set above 0.
pub struct SimDriverPlugin;

impl Plugin for SimDriverPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(StepsPerUpdate(0));
        app.add_systems(Update, drive);
    }
}
