//! Fitness functions (thesis 3.4.3): what an episode scored. Higher is better for all of
//! them; cost of transport is negated so that the optimizers can maximize it too. The
//! names live with the formats ([`crate::config::fitness`]); the scores here.

use crate::measure::{distance_along, ground_distance, norm};

pub use crate::config::fitness::Fitness;

/// What one episode measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Episode {
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
    pub fn score(self, e: &Episode) -> f64 {
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

    fn episode(gravity: f64) -> Episode {
        Episode {
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
