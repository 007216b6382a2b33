//! Domain randomization: one episode's copy of a simulation with its physics drawn from
//! `<robustness>` ranges (environment friction, link masses, servo torque and gain, start
//! heading and position), and the sensor noise its world adds while it runs. Everything is
//! drawn from the episode's seed, so an episode is the same wherever and whenever it is
//! built again (a worker on another host, a replay).

use bevy::prelude::Component;

use crate::config::Simulation;
use crate::config::robustness::Robustness;
use crate::config::transform::{Pose, quat_mul};
use crate::rng::SimRng;
use crate::sim::engine::DEFAULT_FRICTION;
use crate::sim::servo::DEFAULT_SERVO_GAIN;

/// Gaussian noise on what a robot's modules read, added every step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SensorNoise {
    /// Standard deviation (degrees) on each measured joint angle.
    pub angle_deg: f64,
    /// Standard deviation (m) on each laser range.
    pub range_m: f64,
}

impl SensorNoise {
    /// Whether it adds anything.
    pub fn is_active(&self) -> bool {
        self.angle_deg > 0.0 || self.range_m > 0.0
    }
}

/// A robot's sensor noise and its own seeded stream (added when its world is built with
/// noise): modules read the noisy angles and ranges.
#[derive(Component, Debug, Clone)]
pub struct NoisySensors {
    /// How much noise.
    pub noise: SensorNoise,
    /// The robot's stream.
    pub rng: SimRng,
}

impl NoisySensors {
    /// Adds the angle noise to `angles` (degrees).
    pub fn perturb_angles(&mut self, angles: &mut [f64]) {
        if self.noise.angle_deg > 0.0 {
            for a in angles {
                *a += self.noise.angle_deg * self.rng.gaussian();
            }
        }
    }

    /// Adds the range noise to `ranges` (m), keeping them within `[0, max]`.
    pub fn perturb_ranges(&mut self, ranges: &mut [f64], max: f64) {
        if self.noise.range_m > 0.0 {
            for r in ranges {
                *r = (*r + self.noise.range_m * self.rng.gaussian()).clamp(0.0, max);
            }
        }
    }
}

/// One randomized episode: the simulation to build and the noise of its sensors.
#[derive(Debug, Clone)]
pub struct RandomizedEpisode {
    /// The episode's seed (its draws and the modules' own noise).
    pub seed: u64,
    /// The simulation with the drawn physics.
    pub sim: Simulation,
    /// The sensor noise of its world.
    pub noise: SensorNoise,
    /// What was drawn, for the store and for people.
    pub draws: String,
}

/// A factor uniform in `[1 - pct/100, 1 + pct/100]`.
fn factor(rng: &mut SimRng, pct: f64) -> f64 {
    1.0 + rng.range(-pct, pct) / 100.0
}

/// The episode of `sim` that `seed` draws from `r`'s ranges.
pub fn randomize(sim: &Simulation, r: &Robustness, seed: u64) -> RandomizedEpisode {
    let mut rng = SimRng::new(seed ^ 0x7261_6e64_6f6d_697a);
    let mut out = sim.clone();
    let friction = factor(&mut rng, r.friction_pct);
    let physics = &mut out.environment.physics;
    let default = physics.default_friction.unwrap_or(DEFAULT_FRICTION);
    physics.default_friction = Some(default * friction);
    for g in out
        .environment
        .bodies
        .iter_mut()
        .flat_map(|b| b.geoms.iter_mut())
    {
        if let Some(f) = g.friction.as_mut() {
            *f *= friction;
        }
    }
    let mut masses = (f64::INFINITY, f64::NEG_INFINITY);
    for l in &mut out.robot.links {
        let k = factor(&mut rng, r.mass_pct);
        l.mass *= k;
        if let Some(i) = &mut l.inertia {
            i.tensor = i.tensor.map(|v| v * k);
        }
        masses = (masses.0.min(k), masses.1.max(k));
    }
    for j in &mut out.robot.joints {
        j.max_torque *= factor(&mut rng, r.torque_pct);
        j.servo_gain =
            Some(j.servo_gain.unwrap_or(DEFAULT_SERVO_GAIN) * factor(&mut rng, r.gain_pct));
    }
    let heading = rng.range(-r.heading_deg, r.heading_deg);
    let (dx, dy) = (
        rng.range(-r.position_m, r.position_m),
        rng.range(-r.position_m, r.position_m),
    );
    out.environment.robot_pose = turned(&out.environment.robot_pose, heading, [dx, dy]);
    let draws = format!(
        "friction x{friction:.3}, masses x{:.3}..x{:.3}, heading {heading:+.1} deg, position {dx:+.3} {dy:+.3} m",
        masses.0, masses.1
    );
    RandomizedEpisode {
        seed,
        sim: out,
        noise: SensorNoise {
            angle_deg: r.angle_noise_deg,
            range_m: r.range_noise_m,
        },
        draws,
    }
}

/// `pose` turned by `deg` about the vertical through its origin and moved by `shift` (m).
fn turned(pose: &Pose, deg: f64, shift: [f64; 2]) -> Pose {
    let half = deg.to_radians() / 2.0;
    let about_z = [half.cos(), 0.0, 0.0, half.sin()];
    let t = pose.translation;
    Pose {
        translation: [t[0] + shift[0], t[1] + shift[1], t[2]],
        rotation: quat_mul(about_z, pose.rotation),
    }
}

/// The seeds of a run's `k` episodes, drawn from the run's seed: the same episodes for
/// every candidate (common random numbers), so candidates are compared on equal terms.
pub fn episode_seeds(run_seed: u64, k: u32) -> Vec<u64> {
    let mut rng = SimRng::new(run_seed ^ 0x6570_6973_6f64_6573);
    (0..k).map(|_| rng.next_u64()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_heading_turns_the_start_pose_about_the_vertical() {
        let p = Pose::from_translation([1.0, 2.0, 0.3]);
        let q = turned(&p, 90.0, [0.5, 0.0]);
        assert_eq!(q.translation, [1.5, 2.0, 0.3]);
        let x = q.rotate([1.0, 0.0, 0.0]);
        assert!((x[0]).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12, "{x:?}");
    }

    #[test]
    fn sensor_noise_is_seeded_and_keeps_ranges_in_bounds() {
        let noise = SensorNoise {
            angle_deg: 2.0,
            range_m: 0.5,
        };
        let mut a = NoisySensors {
            noise,
            rng: SimRng::new(7),
        };
        let mut b = a.clone();
        let (mut x, mut y) = ([10.0; 4], [10.0; 4]);
        a.perturb_angles(&mut x);
        b.perturb_angles(&mut y);
        assert_eq!(x, y);
        assert!(
            x.iter().all(|v| *v != 10.0 && (v - 10.0).abs() < 20.0),
            "{x:?}"
        );
        let mut r = [0.0, 1.0, 1.0];
        a.perturb_ranges(&mut r, 1.0);
        assert!(r.iter().all(|v| (0.0..=1.0).contains(v)), "{r:?}");
    }

    #[test]
    fn episode_seeds_follow_the_run_seed() {
        assert_eq!(episode_seeds(3, 4), episode_seeds(3, 4));
        assert_ne!(episode_seeds(3, 4), episode_seeds(4, 4));
        assert_eq!(episode_seeds(3, 4)[..2], episode_seeds(3, 2)[..]);
    }
}
