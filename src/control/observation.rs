//! The observation a policy sees: one flat vector of `f64` whose every index has a name
//! ([`ObsLayout::names`]). The Python environment (`crate::gym`) and the `Policy` actuation
//! module write it with the same function, [`write_observation`], so a policy trained
//! either way runs the same. Parts, in order (a part left out of [`ObsParts`] is absent):
//!
//! | slice | values | unit |
//! |---|---|---|
//! | `angle[j]` | each robot joint's angle | rad |
//! | `speed[j]` | each robot joint's angular speed | rad/s |
//! | `pad[p]` | each tactile pad, debounced: 1 pressed, 0 released | — |
//! | `laser[l][b]` | each laser beam's range, lasers in file order | m |
//! | `gravity_head.x/y/z` | gravity's direction in the head link's frame (unit) | — |
//! | `com_velocity.forward/lateral/up` | the centre of mass's mean velocity over the last control period, in the frame of the robot's current heading | m/s |
//! | `phase[g].sin/cos` | sine and cosine of each generator's phase at its first joint (every module of the kernel with a `Phase` series, in kernel order) | — |

use crate::sensing::SensorData;

/// Which parts an observation holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObsParts {
    /// Joint angles.
    pub angles: bool,
    /// Joint speeds.
    pub speeds: bool,
    /// Tactile pads.
    pub pads: bool,
    /// Laser ranges.
    pub lasers: bool,
    /// Gravity in the head's frame.
    pub gravity: bool,
    /// Centre-of-mass velocity in the heading frame.
    pub velocity: bool,
    /// Generator phases.
    pub phases: bool,
}

impl ObsParts {
    /// Every part.
    pub const ALL: ObsParts = ObsParts {
        angles: true,
        speeds: true,
        pads: true,
        lasers: true,
        gravity: true,
        velocity: true,
        phases: true,
    };
}

/// The observation's parts and their sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct ObsLayout {
    /// Robot joints.
    pub joints: usize,
    /// Tactile pads.
    pub pads: usize,
    /// Beams of every laser, in file order.
    pub beams: Vec<usize>,
    /// Generators whose phase is observed.
    pub phases: usize,
    /// The parts present.
    pub parts: ObsParts,
}

impl ObsLayout {
    /// The layout for a robot of `joints` joints with these sensors and `phases`
    /// generators, holding `parts`.
    pub fn new(joints: usize, sensors: &SensorData, phases: usize, parts: ObsParts) -> Self {
        ObsLayout {
            joints,
            pads: sensors.tactile.len(),
            beams: sensors.laser.iter().map(Vec::len).collect(),
            phases,
            parts,
        }
    }

    /// Values per observation.
    pub fn len(&self) -> usize {
        self.part_sizes().iter().sum()
    }

    /// The values each part holds in this observation, in [`ObsParts`] order (angles,
    /// speeds, pads, lasers, gravity, velocity, phases; 0 for a part switched off).
    pub fn part_sizes(&self) -> [usize; 7] {
        let p = &self.parts;
        let n = |on: bool, k: usize| if on { k } else { 0 };
        [
            n(p.angles, self.joints),
            n(p.speeds, self.joints),
            n(p.pads, self.pads),
            n(p.lasers, self.beams.iter().sum()),
            n(p.gravity, 3),
            n(p.velocity, 3),
            n(p.phases, 2 * self.phases),
        ]
    }

    /// Where part `k` (in [`ObsParts`] order, 0..7) lies in the observation; empty for a
    /// part switched off or an index past the last part.
    pub fn part_range(&self, k: usize) -> std::ops::Range<usize> {
        let sizes = self.part_sizes();
        let start: usize = sizes.iter().take(k).sum();
        start..start + sizes.get(k).copied().unwrap_or(0)
    }

    /// Whether the observation holds no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The name of every index, in order.
    pub fn names(&self) -> Vec<String> {
        let p = &self.parts;
        let mut n = Vec::with_capacity(self.len());
        if p.angles {
            n.extend((0..self.joints).map(|j| format!("angle[{j}]")));
        }
        if p.speeds {
            n.extend((0..self.joints).map(|j| format!("speed[{j}]")));
        }
        if p.pads {
            n.extend((0..self.pads).map(|p| format!("pad[{p}]")));
        }
        if p.lasers {
            for (l, beams) in self.beams.iter().enumerate() {
                n.extend((0..*beams).map(|b| format!("laser[{l}][{b}]")));
            }
        }
        if p.gravity {
            n.extend(["gravity_head.x", "gravity_head.y", "gravity_head.z"].map(String::from));
        }
        if p.velocity {
            n.extend(
                [
                    "com_velocity.forward",
                    "com_velocity.lateral",
                    "com_velocity.up",
                ]
                .map(String::from),
            );
        }
        if p.phases {
            for g in 0..self.phases {
                n.push(format!("phase[{g}].sin"));
                n.push(format!("phase[{g}].cos"));
            }
        }
        n
    }

    /// Whether `sensors`, `angles` and `phases` have the sizes this layout was made for.
    pub fn fits(&self, angles: usize, sensors: &SensorData, phases: usize) -> bool {
        angles == self.joints
            && sensors.joint_speeds.len() == self.joints
            && sensors.tactile.len() == self.pads
            && sensors.laser.len() == self.beams.len()
            && sensors
                .laser
                .iter()
                .zip(&self.beams)
                .all(|(l, b)| l.len() == *b)
            && phases == self.phases
    }
}

/// What an observation is made of at one instant.
#[derive(Debug, Clone, Copy)]
pub struct ObsSource<'a> {
    /// Every robot joint's angle (degrees).
    pub angles: &'a [f64],
    /// The robot's sensors (joint speeds, pads, lasers, gravity in the head's frame).
    pub sensors: &'a SensorData,
    /// The centre of mass's velocity in the heading frame (m/s), see [`heading_velocity`].
    pub velocity: [f64; 3],
    /// Each generator's phase (degrees).
    pub phases: &'a [f64],
}

/// Writes the observation of `src` into `out`, laid out as `layout` says (the caller has
/// checked the sizes with [`ObsLayout::fits`]; missing values read as 0, extra ones are
/// dropped). Allocates nothing.
pub fn write_observation(layout: &ObsLayout, src: &ObsSource, out: &mut [f64]) {
    let p = &layout.parts;
    let mut k = 0;
    let mut put = |v: f64| {
        if let Some(slot) = out.get_mut(k) {
            *slot = v;
        }
        k += 1;
    };
    let fixed = |values: &[f64], i: usize| values.get(i).copied().unwrap_or(0.0);
    if p.angles {
        (0..layout.joints).for_each(|j| put(fixed(src.angles, j).to_radians()));
    }
    if p.speeds {
        let speeds = &src.sensors.joint_speeds;
        (0..layout.joints).for_each(|j| put(fixed(speeds, j).to_radians()));
    }
    if p.pads {
        for i in 0..layout.pads {
            let pressed = src.sensors.tactile.get(i).copied().unwrap_or(false);
            put(f64::from(u8::from(pressed)));
        }
    }
    if p.lasers {
        for (l, beams) in layout.beams.iter().enumerate() {
            let ranges = src.sensors.laser.get(l).map_or(&[][..], Vec::as_slice);
            (0..*beams).for_each(|b| put(fixed(ranges, b)));
        }
    }
    if p.gravity {
        src.sensors.gravity_head.iter().for_each(|g| put(*g));
    }
    if p.velocity {
        src.velocity.iter().for_each(|v| put(*v));
    }
    if p.phases {
        for g in 0..layout.phases {
            let (s, c) = fixed(src.phases, g).to_radians().sin_cos();
            put(s);
            put(c);
        }
    }
}

/// The mean velocity of a centre of mass that moved from `from` to `to` in `period`
/// seconds, in the frame of heading `heading` (degrees from +x): forward, lateral to the
/// left, up (m/s). Zero for a period that is not positive.
pub fn heading_velocity(from: [f64; 3], to: [f64; 3], period: f64, heading: f64) -> [f64; 3] {
    if period.is_nan() || period <= 0.0 {
        return [0.0; 3];
    }
    let v: [f64; 3] = std::array::from_fn(|k| (to[k] - from[k]) / period);
    let (s, c) = heading.to_radians().sin_cos();
    [v[0] * c + v[1] * s, -v[0] * s + v[1] * c, v[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensors() -> SensorData {
        let mut s = SensorData::new(2, &[3]);
        s.joint_speeds = vec![90.0, -180.0];
        s.tactile[1] = true;
        s.laser[0] = vec![0.5, 1.0, 1.5];
        s.gravity_head = [0.0, 0.0, -1.0];
        s
    }

    #[test]
    fn every_part_lands_at_its_named_index() {
        let s = sensors();
        let layout = ObsLayout::new(2, &s, 1, ObsParts::ALL);
        assert!(layout.fits(2, &s, 1));
        let src = ObsSource {
            angles: &[45.0, 0.0],
            sensors: &s,
            velocity: [0.1, 0.2, 0.3],
            phases: &[90.0],
        };
        let mut out = vec![f64::NAN; layout.len()];
        write_observation(&layout, &src, &mut out);
        let names = layout.names();
        assert_eq!(names.len(), out.len());
        let at = |name: &str| out[names.iter().position(|n| n == name).unwrap()];
        assert!((at("angle[0]") - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
        assert!((at("speed[1]") + std::f64::consts::PI).abs() < 1e-12);
        assert_eq!((at("pad[0]"), at("pad[1]")), (0.0, 1.0));
        assert_eq!(at("laser[0][2]"), 1.5);
        assert_eq!(at("gravity_head.z"), -1.0);
        assert_eq!(at("com_velocity.lateral"), 0.2);
        assert!((at("phase[0].sin") - 1.0).abs() < 1e-12 && at("phase[0].cos").abs() < 1e-12);
    }

    #[test]
    fn parts_left_out_are_absent() {
        let s = sensors();
        let parts = ObsParts {
            angles: false,
            pads: false,
            phases: false,
            ..ObsParts::ALL
        };
        let layout = ObsLayout::new(2, &s, 1, parts);
        assert_eq!(layout.len(), 2 + 3 + 3 + 3);
        assert_eq!(layout.names()[0], "speed[0]");
    }

    #[test]
    fn velocity_turns_with_the_heading() {
        let v = heading_velocity([0.0; 3], [0.0, 1.0, 0.0], 0.5, 90.0);
        assert!((v[0] - 2.0).abs() < 1e-12 && v[1].abs() < 1e-12);
        assert_eq!(heading_velocity([0.0; 3], [1.0; 3], 0.0, 0.0), [0.0; 3]);
    }
}
