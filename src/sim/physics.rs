//! The physics world as a resource: the engine the simulation named (rapier or MuJoCo,
//! [`crate::sim::engine`]), stepped once per simulation step. Coordinates are the
//! configuration's (metres, z up); the viewer turns them into Bevy's y-up frame.

use bevy::prelude::*;

use crate::sim::engine::PhysicsEngine;

pub use crate::sim::engine::MAX_ROBOTS_PER_WORLD;

/// The world's physics engine.
#[derive(Resource)]
pub struct SimPhysics {
    /// The engine behind the one interface every stage uses.
    pub engine: Box<dyn PhysicsEngine>,
}

/// The physics step (the `Physics` set of the pipeline): one engine step (several when the
/// settings refine the simulation step: converged references).
pub fn step_physics(mut physics: ResMut<SimPhysics>) {
    physics.engine.step();
}
