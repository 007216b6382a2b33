//! The observation: what a policy sees after each environment step, laid out as one flat
//! vector of `f64` whose every index has a name ([`ObsLayout::names`]):
//!
//! | slice | values | unit |
//! |---|---|---|
//! | `angle[j]` | each joint's angle | rad |
//! | `speed[j]` | each joint's angular speed | rad/s |
//! | `pad[p]` | each tactile pad, debounced: 1 pressed, 0 released | — |
//! | `laser[l][b]` | each laser beam's range, lasers in file order | m |
//! | `gravity_head.x/y/z` | gravity's direction in the head link's frame (unit) | — |
//! | `com_velocity.forward/lateral/up` | the centre of mass's mean velocity over the last control period, in the frame of the robot's current heading | m/s |
//! | `phase[g].sin/cos` | residual only: sine and cosine of each generator's phase at its first joint (every module with a `Phase` series) | — |

use crate::config::transform::Pose;
use crate::control::ControlKernel;
use crate::gym::error::GymError;
use crate::sim::Simulator;
use crate::sim::servo::JointState;

/// The observation's parts and their sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct ObsLayout {
    /// Robot joints.
    pub joints: usize,
    /// Tactile pads.
    pub pads: usize,
    /// Beams of every laser, in file order.
    pub beams: Vec<usize>,
    /// Generators whose phase is observed: (actuator index, index of its `Phase` series).
    pub phases: Vec<(usize, usize)>,
}

impl ObsLayout {
    /// The layout of robot 0 of `world`; `phases` adds the generators of `kernel` (the
    /// file's modules, in residual mode).
    pub fn of(world: &Simulator, kernel: Option<&ControlKernel>) -> Result<ObsLayout, GymError> {
        let sensors = world.sensors(0)?;
        let phases = kernel
            .map(|k| {
                k.actuators()
                    .iter()
                    .enumerate()
                    .filter_map(|(i, a)| {
                        let names = a.module.internal_data().names();
                        names.iter().position(|n| *n == "Phase").map(|s| (i, s))
                    })
                    .collect()
            })
            .unwrap_or_default();
        Ok(ObsLayout {
            joints: world.kernel(0)?.joints(),
            pads: sensors.tactile.len(),
            beams: sensors.laser.iter().map(Vec::len).collect(),
            phases,
        })
    }

    /// Values per observation.
    pub fn len(&self) -> usize {
        2 * self.joints + self.pads + self.beams.iter().sum::<usize>() + 6 + 2 * self.phases.len()
    }

    /// Whether the observation is empty (never: gravity and velocity are always there).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The name of every index, in order.
    pub fn names(&self) -> Vec<String> {
        let mut n = Vec::with_capacity(self.len());
        n.extend((0..self.joints).map(|j| format!("angle[{j}]")));
        n.extend((0..self.joints).map(|j| format!("speed[{j}]")));
        n.extend((0..self.pads).map(|p| format!("pad[{p}]")));
        for (l, beams) in self.beams.iter().enumerate() {
            n.extend((0..*beams).map(|b| format!("laser[{l}][{b}]")));
        }
        n.extend(["gravity_head.x", "gravity_head.y", "gravity_head.z"].map(String::from));
        n.extend(
            [
                "com_velocity.forward",
                "com_velocity.lateral",
                "com_velocity.up",
            ]
            .map(String::from),
        );
        for g in 0..self.phases.len() {
            n.push(format!("phase[{g}].sin"));
            n.push(format!("phase[{g}].cos"));
        }
        n
    }
}

/// Where robot 0 was at the last observation, for its velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Previous {
    /// Centre of mass (m).
    pub com: [f64; 3],
}

/// Writes robot 0's observation into `out` (of [`ObsLayout::len`] values); `joints` is
/// scratch room reused between calls, `period` the seconds since `prev`.
pub fn observe(
    world: &Simulator,
    layout: &ObsLayout,
    prev: &Previous,
    period: f64,
    joints: &mut Vec<JointState>,
    out: &mut [f64],
) -> Result<(), GymError> {
    if out.len() != layout.len() {
        return Err(GymError::Shape {
            what: "the observation buffer",
            given: out.len(),
            want: layout.len(),
        });
    }
    world.joint_states_into(0, joints)?;
    let (angles, rest) = out.split_at_mut(layout.joints);
    let (speeds, rest) = rest.split_at_mut(layout.joints);
    for ((a, s), j) in angles.iter_mut().zip(speeds.iter_mut()).zip(joints.iter()) {
        *a = j.angle.to_radians();
        *s = j.velocity.to_radians();
    }
    let sensors = world.sensors(0)?;
    let (pads, mut rest) = rest.split_at_mut(layout.pads);
    for (p, pressed) in pads.iter_mut().zip(&sensors.tactile) {
        *p = f64::from(u8::from(*pressed));
    }
    for (beams, ranges) in layout.beams.iter().zip(&sensors.laser) {
        let (slot, tail) = rest.split_at_mut(*beams);
        slot.copy_from_slice(ranges);
        rest = tail;
    }
    let (gravity, rest) = rest.split_at_mut(3);
    gravity.copy_from_slice(&gravity_in_head(world)?);
    let (velocity, phases) = rest.split_at_mut(3);
    velocity.copy_from_slice(&heading_velocity(world, prev, period)?);
    let kernel = world.kernel(0)?;
    for ((actuator, series), pair) in layout.phases.iter().zip(phases.chunks_exact_mut(2)) {
        let phase = kernel
            .actuators()
            .get(*actuator)
            .and_then(|a| a.module.internal_data().series(*series).first().copied())
            .unwrap_or(0.0)
            .to_radians();
        pair[0] = phase.sin();
        pair[1] = phase.cos();
    }
    Ok(())
}

/// The world's gravity, as a unit vector in the frame of robot 0's head (its last link).
fn gravity_in_head(world: &Simulator) -> Result<[f64; 3], GymError> {
    let g = world.gravity();
    let norm = crate::measure::norm(g);
    let down = if norm > 0.0 {
        g.map(|v| v / norm)
    } else {
        [0.0, 0.0, -1.0]
    };
    let head = match world.link_count(0)?.checked_sub(1) {
        Some(last) => world.body_state(world.link_body(0, last)?),
        None => None,
    };
    Ok(match head {
        Some(state) => Pose {
            translation: [0.0; 3],
            rotation: state.pose.rotation,
        }
        .inverse()
        .rotate(down),
        None => down,
    })
}

/// Robot 0's mean velocity since `prev`, in the frame of its current heading (forward,
/// lateral to the left, up).
fn heading_velocity(world: &Simulator, prev: &Previous, period: f64) -> Result<[f64; 3], GymError> {
    let com = world.com(0)?;
    let v: [f64; 3] = std::array::from_fn(|k| (com[k] - prev.com[k]) / period);
    let (s, c) = world.heading(0)?.to_radians().sin_cos();
    Ok([v[0] * c + v[1] * s, -v[0] * s + v[1] * c, v[2]])
}
