//! Tactile pads in the world: each is a thin box collider on its link; a pad touching
//! anything outside its own body (terrain, another robot) reads pressed once the contact
//! has lasted its debounce steps. Forces are not measured, as in the thesis (5.1); the
//! contact normal is. Runs in the `Sense` set and fills each robot's [`RobotSensors`].

use bevy::prelude::*;
use rapier3d::prelude as rp;

use crate::sensing::{Debounce, SensorData};
use crate::sim::physics::{SimPhysics, arr3};

/// One tactile pad.
#[derive(Component, Debug, Clone)]
pub struct TactileSensor {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index among the robot's tactile pads.
    pub index: usize,
    /// The pad's collider (a thin box on its link).
    pub collider: rp::ColliderHandle,
    /// Steps a new state must last before it is reported.
    pub debounce_steps: u32,
    /// Debounce state of the reading.
    pub state: Debounce,
    /// Whether a contact exists this step, before debouncing.
    pub raw: bool,
}

/// The latest sensor readings of a robot, given to its control kernel.
#[derive(Component, Debug, Clone, Default, PartialEq)]
pub struct RobotSensors(pub SensorData);

/// Raw contact of a pad and its normal (from the touched surface into the pad).
pub fn pad_contact(narrow: &rp::NarrowPhase, pad: rp::ColliderHandle) -> (bool, [f64; 3]) {
    let mut normal = [0.0; 3];
    let mut touching = false;
    for pair in narrow.contact_pairs_with(pad) {
        if !pair.has_any_active_contact() {
            continue;
        }
        touching = true;
        let sign = if pair.collider1 == pad { -1.0 } else { 1.0 };
        for m in pair.manifolds() {
            if !m.points.is_empty() {
                let n = arr3(m.data.normal);
                for i in 0..3 {
                    normal[i] += sign * n[i];
                }
            }
        }
    }
    let len = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
    if len > 0.0 {
        normal = normal.map(|v| v / len);
    }
    (touching, normal)
}

/// Updates every pad and the robots' sensor readings (part of the `Sense` set).
pub fn sense_tactile(
    physics: Res<SimPhysics>,
    mut pads: Query<&mut TactileSensor>,
    mut robots: Query<&mut RobotSensors>,
) {
    let narrow = &physics.world.narrow_phase;
    for mut pad in &mut pads {
        let (raw, normal) = pad_contact(narrow, pad.collider);
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
