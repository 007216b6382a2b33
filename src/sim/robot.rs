//! The robot entity's component: which joint and link entities make the robot, in robot
//! order, and its bodies' masses. Every stage that works on a whole robot queries it.

use bevy::prelude::*;

/// A simulated robot: its joint and link entities in robot order.
#[derive(Component, Debug, Clone)]
pub struct SimRobot {
    /// Position in the batch (0 for a single robot).
    pub index: usize,
    /// Joint entities, in joint order.
    pub joints: Vec<Entity>,
    /// Link entities, in link order.
    pub links: Vec<Entity>,
    /// Link bodies and masses, for the centre of mass.
    pub bodies: Vec<(crate::sim::engine::BodyId, f64)>,
    /// Measured joint angles (degrees), gathered each step.
    pub(crate) measured: Vec<f64>,
}
