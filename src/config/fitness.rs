//! The names of the fitness functions an optimizer file's `<fitness>` extension and the
//! command line choose from. How each one scores an episode is the optimizers' business
//! (`crate::sim::episode::score`); the format only knows the names.

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
    /// The names files and the command line use.
    pub const NAMES: [&'static str; 4] = ["displacement", "distance", "speed", "cost-of-transport"];

    /// Reads a name (case, `_` and `-` ignored; `mean-speed` and `cot` too).
    pub fn parse(s: &str) -> Result<Fitness, crate::config::error::UnknownName> {
        match s.trim().to_ascii_lowercase().replace('_', "-").as_str() {
            "displacement" => Ok(Fitness::Displacement),
            "distance" => Ok(Fitness::Distance),
            "speed" | "mean-speed" => Ok(Fitness::MeanSpeed),
            "cost-of-transport" | "cot" => Ok(Fitness::CostOfTransport),
            _ => Err(crate::config::error::UnknownName::new(
                "fitness",
                s,
                &Fitness::NAMES,
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

    /// The unit of its scores (cost of transport is a pure number, negated).
    pub fn unit(self) -> &'static str {
        match self {
            Fitness::Displacement | Fitness::Distance => "m",
            Fitness::MeanSpeed => "m/s",
            Fitness::CostOfTransport => "1",
        }
    }

    /// Its scores' axis label: name and unit ("displacement (m)").
    pub fn axis_label(self) -> String {
        format!("{} ({})", self.name(), self.unit())
    }

    /// Whether episodes must accumulate the servos' energy.
    pub fn needs_energy(self) -> bool {
        self == Fitness::CostOfTransport
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back() {
        for n in Fitness::NAMES {
            assert_eq!(Fitness::parse(n).map(Fitness::name), Ok(n));
        }
        assert_eq!(
            Fitness::parse("Cost_of_transport"),
            Ok(Fitness::CostOfTransport)
        );
        assert!(matches!(
            Fitness::parse("fastest"),
            Err(crate::config::error::UnknownName { name, .. }) if name == "fastest"
        ));
    }
}
