//! Joints and their servos (the OpenMR controller the thesis used, 5.1): a proportional
//! controller on the angle error gives a velocity command, clamped to the joint's maximum
//! velocity, applied as a velocity motor whose torque is limited to the joint's maximum
//! torque. The joint's limits are enforced by the physics joint itself.

use bevy::prelude::*;

use crate::sim::engine::{JointId, JointReading};
use crate::sim::physics::SimPhysics;

/// Default proportional gain (1/s): a 1 Hz, 40° sine is followed within a few degrees.
pub const DEFAULT_SERVO_GAIN: f64 = 60.0;

pub use crate::sim::engine::rapier::MOTOR_DAMPING;

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

/// The velocity command of the proportional servo (degrees/s).
pub fn servo_command(servo: &Servo, angle: f64) -> f64 {
    let max = servo.max_velocity.to_degrees();
    (servo.gain * (servo.target - angle)).clamp(-max, max)
}

/// Turns each servo's target into a velocity-motor command (the `Servo` set).
pub fn drive_servos(
    mut physics: ResMut<SimPhysics>,
    mut joints: Query<(&SimJoint, &Servo, &mut JointState)>,
) {
    for (j, servo, mut state) in &mut joints {
        let v = servo_command(servo, state.angle);
        state.commanded_velocity = v;
        let now = JointReading {
            angle: state.angle,
            velocity: state.velocity,
            torque: state.torque,
        };
        physics.engine.drive_joint(j.id, v, &now);
    }
}
