//! Joints and their servos (the OpenMR controller the thesis used, 5.1): a proportional
//! controller on the angle error gives a velocity command, clamped to the joint's maximum
//! velocity, applied as a velocity motor whose torque is limited to the joint's maximum
//! torque. The joint's limits are enforced by the physics joint itself.

use bevy::prelude::*;
use rapier3d::prelude as rp;

use crate::sim::physics::SimPhysics;

/// Default proportional gain (1/s): a 1 Hz, 40° sine is followed within a few degrees.
pub const DEFAULT_SERVO_GAIN: f64 = 60.0;
/// Damping of rapier's velocity motor (N·m·s/rad): stiff enough that the torque limit,
/// not the motor model, bounds the servo.
pub const MOTOR_DAMPING: f32 = 10.0;

/// A joint closer than this to a limit (degrees) has its limit constraint active.
pub const LIMIT_MARGIN_DEG: f64 = 15.0;
/// ... or closer than it would move in this time at its current speed (s).
pub const LIMIT_LOOKAHEAD_S: f64 = 0.05;

/// A hinge of a simulated robot and where its bodies are in the physics world.
#[derive(Component, Debug, Clone)]
pub struct SimJoint {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index in the robot's joint order.
    pub index: usize,
    /// The rapier joint.
    pub handle: rp::ImpulseJointHandle,
    /// The body on the tail side.
    pub parent: rp::RigidBodyHandle,
    /// The body on the head side.
    pub child: rp::RigidBodyHandle,
    /// Unit hinge axis in the parent body's frame.
    pub(crate) axis_parent: rp::Vector,
    /// Inverse of the child's rotation relative to the parent at angle zero.
    pub(crate) rest_inv: rp::Rotation,
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

impl SimJoint {
    /// The hinge angle (degrees) and angular velocity (degrees/s) from the bodies' states.
    pub fn measure(&self, bodies: &rp::RigidBodySet) -> (f64, f64) {
        let (Some(p), Some(c)) = (bodies.get(self.parent), bodies.get(self.child)) else {
            return (0.0, 0.0);
        };
        let r1 = *p.rotation();
        let r2 = *c.rotation();
        let delta = r1.inverse() * r2 * self.rest_inv;
        let along = delta.x * self.axis_parent.x
            + delta.y * self.axis_parent.y
            + delta.z * self.axis_parent.z;
        let angle = 2.0 * along.atan2(delta.w);
        let angle = if angle > std::f32::consts::PI {
            angle - std::f32::consts::TAU
        } else if angle < -std::f32::consts::PI {
            angle + std::f32::consts::TAU
        } else {
            angle
        };
        let axis_world = r1 * self.axis_parent;
        let rel = c.angvel() - p.angvel();
        let velocity = rel.dot(axis_world);
        ((angle as f64).to_degrees(), (velocity as f64).to_degrees())
    }
}

/// Reads every joint's angle, velocity and last torque (part of the `Sense` set).
pub fn sense_joints(physics: Res<SimPhysics>, mut joints: Query<(&SimJoint, &mut JointState)>) {
    let substep = physics.substep_duration();
    let w = &physics.world;
    for (j, mut state) in &mut joints {
        let (angle, velocity) = j.measure(&w.bodies);
        state.angle = angle;
        state.velocity = velocity;
        // The motor's impulse in the last solver substep (the joint limit's impulse is not the
        // servo's); rapier splits a step into `num_solver_iterations` substeps.
        let axis = rp::JointAxis::AngX as usize;
        state.torque = w
            .impulse_joints
            .get(j.handle)
            .map_or(0.0, |ij| ij.data.motors[axis].impulse as f64 / substep);
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
    let w = &mut physics.world;
    for (j, servo, mut state) in &mut joints {
        let v = servo_command(servo, state.angle);
        state.commanded_velocity = v;
        if let Some(ij) = w.impulse_joints.get_mut(j.handle, false) {
            ij.data
                .set_motor_velocity(rp::JointAxis::AngX, v.to_radians() as f32, MOTOR_DAMPING);
            // The limit constraint costs a solver row every substep; it is only switched on
            // while the joint is close enough to a limit to reach it within a few steps.
            let [lo, hi] = servo.limits_deg;
            let margin = LIMIT_MARGIN_DEG.max(state.velocity.abs() * LIMIT_LOOKAHEAD_S);
            if state.angle < lo + margin || state.angle > hi - margin {
                ij.data.limit_axes |= rp::JointAxesMask::ANG_X;
            } else {
                ij.data.limit_axes &= !rp::JointAxesMask::ANG_X;
            }
        }
    }
}
