//! Tactile pads in the world. A pad is an area on its link's surface, not a collider of
//! its own: it reads the contact points of its link's colliders, and is touched when a
//! contact patch (the box around one contact manifold's points) overlaps the pad's box.
//! A touch by anything outside its own body (terrain, another robot) reads pressed once
//! it has lasted its debounce steps. Forces are not measured, as in the thesis (5.1); the
//! contact normal is. Runs in the `Sense` set and fills each robot's [`RobotSensors`].
//!
//! Reading the link's own contacts instead of giving each pad a collider saves the
//! narrow phase and the solver a pad's contacts (docs/MEASUREMENTS.md has the figures).

use bevy::prelude::*;

use crate::sensing::{Debounce, SensorData};
use crate::sim::engine::{BodyId, PadArea, PadId};
use crate::sim::physics::SimPhysics;

/// A tactile pad of a robot: its engine pad and debounce state.
#[derive(Component, Debug, Clone)]
pub struct SimPad {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index among the robot's pads (the order of `SensorData::tactile`).
    pub index: usize,
    /// The engine's pad.
    pub pad: PadId,
    /// The link it sits on.
    pub link: BodyId,
    /// Its area on the link.
    pub area: PadArea,
    /// Consecutive steps a new state must last.
    pub debounce_steps: u32,
    /// Debounce state.
    pub state: Debounce,
    /// Contact this step, before debouncing.
    pub raw: bool,
}

/// Each robot's sensor readings as its modules see them.
#[derive(Component, Debug, Clone, Default, PartialEq)]
pub struct RobotSensors(pub SensorData);

/// Reads every pad's contact, debounces it and stores it with its normal (part of the
/// `Sense` set).
pub fn sense_tactile(
    physics: Res<SimPhysics>,
    mut pads: Query<&mut SimPad>,
    mut robots: Query<&mut RobotSensors>,
) {
    for mut pad in &mut pads {
        let (raw, normal) = physics.engine.pad_contact(pad.pad);
        pad.raw = raw;
        let steps = pad.debounce_steps;
        let pressed = pad.state.update(raw, steps);
        if let Ok(mut sensors) = robots.get_mut(pad.robot) {
            let i = pad.index;
            if let Some(p) = sensors.0.tactile.get_mut(i) {
                *p = pressed;
            }
            if let Some(n) = sensors.0.tactile_normals.get_mut(i) {
                *n = if pressed { normal } else { [0.0; 3] };
            }
        }
    }
}
