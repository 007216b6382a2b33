//! Fitness functions (thesis 3.4.3): what an episode scored. Higher is better for all of
//! them; cost of transport is negated so that the optimizers can maximize it too.

/// What one episode measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Episode {
    pub start_com: [f64; 3],
    pub end_com: [f64; 3],
    /// Travel direction at the start, degrees counter-clockwise from +x.
    pub start_heading: f64,
    /// Simulated seconds.
    pub time: f64,
    /// Mechanical energy the servos put out (J).
    pub energy: f64,
    /// Robot mass (kg).
    pub mass: f64,
}

/// How an episode is scored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fitness {
    /// Eq. 3.7: distance between start and end in the ground plane (m).
    Displacement,
    /// Distance travelled along the start heading (m; negative when backwards).
    Distance,
    /// Displacement per simulated second (m/s).
    MeanSpeed,
    /// Minus the cost of transport, energy / (weight x displacement).
    CostOfTransport,
}

impl Fitness {
    pub const NAMES: [&'static str; 4] = ["displacement", "distance", "speed", "cost-of-transport"];

    pub fn parse(s: &str) -> Result<Fitness, String> {
        match s.trim().to_ascii_lowercase().replace('_', "-").as_str() {
            "displacement" => Ok(Fitness::Displacement),
            "distance" => Ok(Fitness::Distance),
            "speed" | "mean-speed" => Ok(Fitness::MeanSpeed),
            "cost-of-transport" | "cot" => Ok(Fitness::CostOfTransport),
            _ => Err(format!(
                "unknown fitness {s:?}; expected one of {}",
                Fitness::NAMES.join(", ")
            )),
        }
    }

    /// The name files and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            Fitness::Displacement => "displacement",
            Fitness::Distance => "distance",
            Fitness::MeanSpeed => "speed",
            Fitness::CostOfTransport => "cost-of-transport",
        }
    }

    /// Whether episodes must accumulate the servos' energy.
    pub fn needs_energy(self) -> bool {
        self == Fitness::CostOfTransport
    }

    pub fn score(self, e: &Episode) -> f64 {
        let (dx, dy) = (e.end_com[0] - e.start_com[0], e.end_com[1] - e.start_com[1]);
        let displacement = (dx * dx + dy * dy).sqrt();
        match self {
            Fitness::Displacement => displacement,
            Fitness::Distance => {
                let h = e.start_heading.to_radians();
                dx * h.cos() + dy * h.sin()
            }
            Fitness::MeanSpeed => {
                if e.time > 0.0 {
                    displacement / e.time
                } else {
                    0.0
                }
            }
            Fitness::CostOfTransport => {
                let weight = e.mass * 9.81;
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

    #[test]
    fn scores() {
        let e = Episode {
            start_com: [0.0, 0.0, 0.05],
            end_com: [0.0, -3.0, 0.05],
            start_heading: 90.0,
            time: 30.0,
            energy: 10.0,
            mass: 0.5,
        };
        assert_eq!(Fitness::Displacement.score(&e), 3.0);
        assert!(
            (Fitness::Distance.score(&e) + 3.0).abs() < 1e-12,
            "backwards is negative"
        );
        assert_eq!(Fitness::MeanSpeed.score(&e), 0.1);
        assert!((Fitness::CostOfTransport.score(&e) + 10.0 / (0.5 * 9.81 * 3.0)).abs() < 1e-12);
        assert_eq!(
            Fitness::parse("Cost_of_transport"),
            Ok(Fitness::CostOfTransport)
        );
    }
}
