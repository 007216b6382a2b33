//! The control kernel in the pipeline: each robot's [`ControlKernel`] computes its modules
//! from the measured joint angles (`Actuate`; with their noise in randomized episodes), sums them (`Kernel`) and hands the sums to
//! the servos.

use bevy::prelude::*;

use crate::control::ControlKernel;
use crate::sim::clock::SimClock;
use crate::sim::randomize::NoisySensors;
use crate::sim::robot::SimRobot;
use crate::sim::servo::{JointState, Servo};
use crate::sim::tactile::RobotSensors;

/// The robot's control kernel.
#[derive(Component, Debug, Clone)]
pub struct Kernel(pub ControlKernel);

/// Servo targets (degrees, one per joint) that replace the kernel's sums: the simulated
/// twin of a real robot follows the real robot's angles with it.
#[derive(Component, Debug, Clone, PartialEq)]
pub struct JointOverride(pub Vec<f64>);

/// Gathers the measured angles and lets every module compute (the `Actuate` set).
pub fn actuate(
    clock: Res<SimClock>,
    mut robots: Query<(
        &mut SimRobot,
        &mut Kernel,
        &RobotSensors,
        Option<&mut NoisySensors>,
    )>,
    states: Query<&JointState>,
) {
    let time = clock.time();
    for (mut robot, mut kernel, sensors, noise) in &mut robots {
        let robot = &mut *robot;
        for (slot, e) in robot.measured.iter_mut().zip(&robot.joints) {
            *slot = states.get(*e).map_or(0.0, |s| s.angle);
        }
        if let Some(mut n) = noise {
            n.perturb_angles(&mut robot.measured);
        }
        kernel
            .0
            .compute_modules(time, clock.dt, clock.step, &robot.measured, &sensors.0);
    }
}

/// Sums the module outputs joint-wise and sets the servo targets (the `Kernel` set).
pub fn sum_outputs(
    mut robots: Query<(&SimRobot, &mut Kernel, Option<&JointOverride>)>,
    mut servos: Query<&mut Servo>,
) {
    for (robot, mut kernel, over) in &mut robots {
        let sums = kernel.0.sum();
        let desired = over.map_or(sums, |o| o.0.as_slice());
        for (e, d) in robot.joints.iter().zip(desired) {
            if let Ok(mut s) = servos.get_mut(*e) {
                s.target = *d;
            }
        }
    }
}
