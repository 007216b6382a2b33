//! Joints and their servos (the OpenMR controller the thesis used, 5.1): a proportional
//! controller on the angle error gives a velocity command, clamped to the joint's maximum
//! velocity, applied as a velocity motor whose torque is limited to the joint's maximum
//! torque. The joint's limits are enforced by the physics joint itself. A servo may leave
//! errors within its dead band uncorrected and see its goals late (its latency, as a real
//! bus delivers them): [`servo_velocity`] is the law, the one the emulated servos and the
//! calibration's servo replay use too.

use bevy::prelude::*;

use crate::sim::engine::{JointId, JointReading};
use crate::sim::physics::SimPhysics;

/// Default proportional gain (1/s): a 1 Hz, 40° sine is followed within a few degrees.
pub const DEFAULT_SERVO_GAIN: f64 = 60.0;

/// A hinge of a simulated robot and its joint in the physics engine.
#[derive(Component, Debug, Clone)]
pub struct SimJoint {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index in the robot's joint order.
    pub index: usize,
    /// The engine's joint.
    pub id: JointId,
}

/// The servo's settings and its current target.
#[derive(Component, Debug, Clone, PartialEq)]
pub struct Servo {
    /// Desired angle (degrees), from the control kernel.
    pub target: f64,
    /// Proportional gain (1/s).
    pub gain: f64,
    /// N·m.
    pub max_torque: f64,
    /// rad/s.
    pub max_velocity: f64,
    /// Degrees.
    pub limits_deg: [f64; 2],
    /// The angle error (degrees) left uncorrected.
    pub dead_band: f64,
    /// The goals on their way to the servo (its latency).
    pub delay: TargetDelay,
}

/// Goals on their way to a servo: the last `n` targets in a fixed ring, `n` the latency in
/// steps (none without latency).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TargetDelay {
    ring: Vec<f64>,
    next: usize,
}

impl TargetDelay {
    /// A delay of `latency` seconds at steps of `dt` seconds (rounded to whole steps),
    /// holding `start` until the first goal arrives.
    pub fn new(latency: f64, dt: f64, start: f64) -> TargetDelay {
        let n = if dt > 0.0 && latency > 0.0 {
            (latency / dt).round() as usize
        } else {
            0
        };
        TargetDelay {
            ring: vec![start; n],
            next: 0,
        }
    }

    /// Sends `target`; returns the goal the servo sees now (the one sent `n` steps ago).
    pub fn pass(&mut self, target: f64) -> f64 {
        let Some(slot) = self.ring.get_mut(self.next) else {
            return target;
        };
        let seen = std::mem::replace(slot, target);
        self.next = (self.next + 1) % self.ring.len();
        seen
    }
}

/// The servo law: the velocity command (degrees/s) for an angle `error` (degrees) with
/// proportional `gain` (1/s), at most `max_deg_s`, none within the `dead_band` (degrees).
pub fn servo_velocity(gain: f64, max_deg_s: f64, dead_band: f64, error: f64) -> f64 {
    if error.abs() <= dead_band {
        return 0.0;
    }
    (gain * error).clamp(-max_deg_s, max_deg_s)
}

/// What the joint does now.
#[derive(Component, Debug, Clone, Copy, Default, PartialEq)]
pub struct JointState {
    /// Degrees.
    pub angle: f64,
    /// Degrees per second.
    pub velocity: f64,
    /// Torque the servo applied in the last step (N·m).
    pub torque: f64,
    /// Velocity the servo commanded (degrees per second).
    pub commanded_velocity: f64,
}

/// Reads every joint's angle, velocity and last torque (part of the `Sense` set).
pub fn sense_joints(physics: Res<SimPhysics>, mut joints: Query<(&SimJoint, &mut JointState)>) {
    for (j, mut state) in &mut joints {
        let r = physics.engine.joint(j.id);
        state.angle = r.angle;
        state.velocity = r.velocity;
        state.torque = r.torque;
    }
}

/// The velocity command of the proportional servo (degrees/s) toward the goal it sees,
/// `seen` (its target after its latency).
pub fn servo_command(servo: &Servo, seen: f64, angle: f64) -> f64 {
    servo_velocity(
        servo.gain,
        servo.max_velocity.to_degrees(),
        servo.dead_band,
        seen - angle,
    )
}

/// Turns each servo's target into a velocity-motor command (the `Servo` set).
pub fn drive_servos(
    mut physics: ResMut<SimPhysics>,
    mut joints: Query<(&SimJoint, &mut Servo, &mut JointState)>,
) {
    for (j, mut servo, mut state) in &mut joints {
        let target = servo.target;
        let seen = servo.delay.pass(target);
        let v = servo_command(&servo, seen, state.angle);
        state.commanded_velocity = v;
        let now = JointReading {
            angle: state.angle,
            velocity: state.velocity,
            torque: state.torque,
        };
        physics.engine.drive_joint(j.id, v, &now);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_law_clamps_and_leaves_the_dead_band_alone() {
        assert_eq!(servo_velocity(60.0, 300.0, 0.0, 2.0), 120.0);
        assert_eq!(servo_velocity(60.0, 300.0, 0.0, -10.0), -300.0);
        assert_eq!(servo_velocity(60.0, 300.0, 0.5, 0.4), 0.0);
        assert_eq!(servo_velocity(60.0, 300.0, 0.5, -0.6), -36.0);
    }

    #[test]
    fn a_latency_delays_goals_by_whole_steps() {
        let mut none = TargetDelay::new(0.0, 0.001, 0.0);
        assert_eq!(none.pass(3.0), 3.0);
        let mut three = TargetDelay::new(0.003, 0.001, 0.0);
        let seen: Vec<f64> = (1..=6).map(|k| three.pass(f64::from(k))).collect();
        assert_eq!(seen, [0.0, 0.0, 0.0, 1.0, 2.0, 3.0]);
    }
}
