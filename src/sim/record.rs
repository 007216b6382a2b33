//! Recording what each robot does: every `every` steps its centre of mass, heading, and
//! per joint the desired angle, real angle, velocity and applied torque (the `Record`
//! set). Buffers are allocated once for the expected number of samples.

use bevy::prelude::*;

use crate::sim::clock::SimClock;
use crate::sim::engine::PhysicsEngine;
use crate::sim::kernel::Kernel;
use crate::sim::physics::SimPhysics;
use crate::sim::robot::SimRobot;
use crate::sim::servo::JointState;

/// Whether and how often to record.
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct RecordSettings {
    /// Whether trajectories are recorded.
    pub enabled: bool,
    /// Sampling period in steps (the simulation file's `accuracy`).
    pub every: u32,
}

/// One joint in one sample.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct JointSample {
    /// Angle the kernel asked for (degrees).
    pub desired: f64,
    /// Measured angle (degrees).
    pub angle: f64,
    /// Measured speed (degrees/s).
    pub velocity: f64,
    /// Torque the servo applied (N·m).
    pub torque: f64,
}

/// The recorded trajectory of one robot.
#[derive(Component, Debug, Clone, Default, PartialEq)]
pub struct Track {
    /// Joints per sample.
    pub joints_per_sample: usize,
    /// Simulated time of each sample (s).
    pub times: Vec<f64>,
    /// Centre of mass at each sample (m, z up).
    pub com: Vec<[f64; 3]>,
    /// Degrees, counter-clockwise from +x, of the tail-to-head direction in the ground plane.
    pub heading: Vec<f64>,
    /// `joints_per_sample` entries per sample.
    pub joints: Vec<JointSample>,
}

impl Track {
    /// An empty track with room for `samples` samples of `joints` joints.
    pub fn with_capacity(joints: usize, samples: usize) -> Self {
        Track {
            joints_per_sample: joints,
            times: Vec::with_capacity(samples),
            com: Vec::with_capacity(samples),
            heading: Vec::with_capacity(samples),
            joints: Vec::with_capacity(samples * joints),
        }
    }

    /// The joint samples of sample `i`.
    pub fn joints_at(&self, i: usize) -> &[JointSample] {
        &self.joints[i * self.joints_per_sample..(i + 1) * self.joints_per_sample]
    }

    /// Samples recorded.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
}

/// The mass-weighted centre of the robot's links (m).
pub fn centre_of_mass(engine: &dyn PhysicsEngine, robot: &SimRobot) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut mass = 0.0;
    for (b, m) in &robot.bodies {
        let c = engine.body_com(*b);
        for i in 0..3 {
            sum[i] += c[i] * m;
        }
        mass += m;
    }
    if mass > 0.0 {
        sum.map(|s| s / mass)
    } else {
        sum
    }
}

/// Direction from the first link (tail) to the last (head) in the ground plane, degrees.
pub fn heading(engine: &dyn PhysicsEngine, robot: &SimRobot) -> f64 {
    let pos = |i: usize| robot.bodies.get(i).map(|(b, _)| engine.body_com(*b));
    match (pos(0), robot.bodies.len().checked_sub(1).and_then(pos)) {
        (Some(a), Some(b)) => (b[1] - a[1]).atan2(b[0] - a[0]).to_degrees(),
        _ => 0.0,
    }
}

/// The world's gravity as a unit vector in the frame of the robot's head (its last link);
/// straight down in world coordinates when the robot has no link or no gravity.
pub fn gravity_in_head(engine: &dyn PhysicsEngine, robot: &SimRobot) -> [f64; 3] {
    let g = engine.gravity();
    let norm = crate::measure::norm(g);
    let down = if norm > 0.0 {
        g.map(|v| v / norm)
    } else {
        [0.0, 0.0, -1.0]
    };
    match robot.bodies.last().and_then(|(b, _)| engine.body(*b)) {
        Some(state) => crate::config::transform::Pose {
            translation: [0.0; 3],
            rotation: state.pose.rotation,
        }
        .inverse()
        .rotate(down),
        None => down,
    }
}

/// Samples every robot when the step is a multiple of the period.
pub fn record(
    settings: Res<RecordSettings>,
    clock: Res<SimClock>,
    physics: Res<SimPhysics>,
    mut robots: Query<(&SimRobot, &Kernel, &mut Track)>,
    states: Query<&JointState>,
) {
    if !settings.enabled || !(clock.step + 1).is_multiple_of(settings.every.max(1) as u64) {
        return;
    }
    let engine = physics.engine.as_ref();
    for (robot, kernel, mut track) in &mut robots {
        track.times.push(clock.time() + clock.dt);
        track.com.push(centre_of_mass(engine, robot));
        track.heading.push(heading(engine, robot));
        for (e, desired) in robot.joints.iter().zip(kernel.0.desired()) {
            let s = states.get(*e).copied().unwrap_or_default();
            track.joints.push(JointSample {
                desired: *desired,
                angle: s.angle,
                velocity: s.velocity,
                torque: s.torque,
            });
        }
    }
}
