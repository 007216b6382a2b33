//! An episode's score (thesis 3.4.3), written once: the fitness functions' formulas over
//! what an episode measured ([`Measured`]), and [`robot_score`], a robot's score in a running
//! world, which every front (`proleg run`, the evaluator, the Gymnasium environment, the
//! control window, replays) reads through the episode runner. Higher is better for every
//! fitness; cost of transport is negated so that the optimizers can maximize it too. The
//! names live with the formats ([`crate::config::fitness`]).

use crate::config::fitness::Fitness;
use crate::measure::{distance_along, ground_distance, norm};
use crate::sim::Simulator;
use crate::sim::episode::exit::BLOW_UP_DISTANCE;
use crate::sim::error::SimError;

/// Where a robot started an episode.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RobotStart {
    /// Its centre of mass (m, z up).
    pub com: [f64; 3],
    /// Its tail-to-head heading (degrees from +x).
    pub heading: f64,
}

impl RobotStart {
    /// Where robot `index` of `sim` is now.
    pub fn of(sim: &Simulator, index: usize) -> Result<RobotStart, SimError> {
        Ok(RobotStart {
            com: sim.com(index)?,
            heading: sim.heading(index)?,
        })
    }
}

/// Robot `robot`'s score after an episode that started at `start` and ran `time` simulated
/// seconds: `-inf` for a blow-up (a non-finite or far-flung centre of mass) or an undefined
/// score, else the fitness.
pub fn robot_score(
    s: &Simulator,
    robot: usize,
    start: RobotStart,
    time: f64,
    fitness: Fitness,
) -> Result<f64, SimError> {
    let end = s.com(robot)?;
    if !end.iter().all(|v| v.is_finite()) || ground_distance(start.com, end) > BLOW_UP_DISTANCE {
        return Ok(f64::NEG_INFINITY);
    }
    let e = Measured {
        start_com: start.com,
        end_com: end,
        start_heading: start.heading,
        time,
        energy: s.energy(robot)?.joules,
        mass: s.mass(robot)?,
        gravity: s.gravity(),
    };
    let score = fitness.score(&e);
    Ok(if score.is_nan() {
        f64::NEG_INFINITY
    } else {
        score
    })
}

/// What one episode measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// Centre of mass at the start (m, z up).
    pub start_com: [f64; 3],
    /// Centre of mass at the end (m, z up).
    pub end_com: [f64; 3],
    /// Travel direction at the start, degrees counter-clockwise from +x.
    pub start_heading: f64,
    /// Simulated seconds.
    pub time: f64,
    /// Mechanical energy the servos put out (J).
    pub energy: f64,
    /// Robot mass (kg).
    pub mass: f64,
    /// The world's gravity (m/s², z up), for the robot's weight.
    pub gravity: [f64; 3],
}

impl Fitness {
    /// The score of an episode.
    pub fn score(self, e: &Measured) -> f64 {
        let displacement = ground_distance(e.start_com, e.end_com);
        match self {
            Fitness::Displacement => displacement,
            Fitness::Distance => distance_along(e.start_com, e.end_com, e.start_heading),
            Fitness::MeanSpeed => {
                if e.time > 0.0 {
                    displacement / e.time
                } else {
                    0.0
                }
            }
            Fitness::CostOfTransport => {
                let weight = e.mass * norm(e.gravity);
                if displacement <= 1e-6 || weight <= 0.0 {
                    f64::NEG_INFINITY
                } else {
                    -(e.energy / (weight * displacement))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn episode(gravity: f64) -> Measured {
        Measured {
            start_com: [0.0, 0.0, 0.05],
            end_com: [0.0, -3.0, 0.05],
            start_heading: 90.0,
            time: 30.0,
            energy: 10.0,
            mass: 0.5,
            gravity: [0.0, 0.0, -gravity],
        }
    }

    #[test]
    fn scores() {
        let e = episode(9.81);
        assert_eq!(Fitness::Displacement.score(&e), 3.0);
        assert!(
            (Fitness::Distance.score(&e) + 3.0).abs() < 1e-12,
            "backwards is negative"
        );
        assert_eq!(Fitness::MeanSpeed.score(&e), 0.1);
        assert!((Fitness::CostOfTransport.score(&e) + 10.0 / (0.5 * 9.81 * 3.0)).abs() < 1e-12);
    }

    #[test]
    fn cost_of_transport_weighs_with_the_world_gravity() {
        let mars = Fitness::CostOfTransport.score(&episode(3.71));
        assert!((mars + 10.0 / (0.5 * 3.71 * 3.0)).abs() < 1e-12, "{mars}");
    }
}
