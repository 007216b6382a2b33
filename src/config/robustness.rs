//! Our extension `<robustness>` of optimizer files: score each candidate over K episodes
//! with randomized physics (domain randomization), by their mean or a lower quantile.
//!
//! ```xml
//! <robustness>
//!   <episodes>8</episodes>        <!-- K >= 1 -->
//!   <quantile>0.25</quantile>     <!-- optional: the lower quantile instead of the mean -->
//!   <friction>30</friction>       <!-- floor and obstacle friction, +- percent -->
//!   <mass>10</mass>               <!-- each link's mass, +- percent -->
//!   <servoTorque>20</servoTorque> <!-- each servo's torque limit, +- percent -->
//!   <servoGain>20</servoGain>     <!-- each servo's gain, +- percent -->
//!   <heading>20</heading>         <!-- start heading, +- degrees about the vertical -->
//!   <position>0.1</position>      <!-- start position, +- metres in x and y -->
//!   <angleNoise>1</angleNoise>    <!-- joint angles modules read: Gaussian, sigma degrees -->
//!   <rangeNoise>0.01</rangeNoise> <!-- laser ranges: Gaussian, sigma metres -->
//! </robustness>
//! ```
//!
//! Every range is optional (absent: 0, not randomized); factors are drawn uniformly.

use crate::config::error::{ConfigResult, ErrorKind};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::XmlWriter;

/// How each episode's physics and sensors are randomized, and how episodes are scored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Robustness {
    /// Episodes per candidate (K).
    pub episodes: u32,
    /// `Some(q)`: the score is the lower `q` quantile of the episodes' scores; `None`: their
    /// mean.
    pub quantile: Option<f64>,
    /// Friction of the environment's bodies, +- percent.
    pub friction_pct: f64,
    /// Each link's mass, +- percent.
    pub mass_pct: f64,
    /// Each servo's torque limit, +- percent.
    pub torque_pct: f64,
    /// Each servo's position gain, +- percent.
    pub gain_pct: f64,
    /// Start heading, +- degrees about the vertical.
    pub heading_deg: f64,
    /// Start position, +- metres along x and y.
    pub position_m: f64,
    /// Standard deviation (degrees) of the noise on the joint angles modules read.
    pub angle_noise_deg: f64,
    /// Standard deviation (m) of the noise on laser ranges.
    pub range_noise_m: f64,
}

/// The elements of `<robustness>`: (name as written, lower case, upper bound).
const RANGES: [(&str, &str, f64); 8] = [
    ("friction", "friction", 90.0),
    ("mass", "mass", 90.0),
    ("servoTorque", "servotorque", 90.0),
    ("servoGain", "servogain", 90.0),
    ("heading", "heading", 180.0),
    ("position", "position", 10.0),
    ("angleNoise", "anglenoise", 90.0),
    ("rangeNoise", "rangenoise", 10.0),
];

impl Robustness {
    /// `episodes` episodes scored by their mean, nothing randomized (the episodes of
    /// `<courses>` without `<robustness>`).
    pub fn nominal(episodes: u32) -> Robustness {
        Robustness {
            episodes,
            quantile: None,
            friction_pct: 0.0,
            mass_pct: 0.0,
            torque_pct: 0.0,
            gain_pct: 0.0,
            heading_deg: 0.0,
            position_m: 0.0,
            angle_noise_deg: 0.0,
            range_noise_m: 0.0,
        }
    }

    /// A starting point for a gait meant for a real robot: 8 episodes scored by their mean,
    /// friction +-30 %, masses +-10 %, servo torque and gain +-20 %, heading +-20 deg,
    /// position +-0.1 m, 1 deg of angle noise and 1 cm of range noise.
    pub fn typical() -> Robustness {
        Robustness {
            episodes: 8,
            quantile: None,
            friction_pct: 30.0,
            mass_pct: 10.0,
            torque_pct: 20.0,
            gain_pct: 20.0,
            heading_deg: 20.0,
            position_m: 0.1,
            angle_noise_deg: 1.0,
            range_noise_m: 0.01,
        }
    }

    /// The randomized ranges, in [`RANGES`] order.
    fn ranges(&self) -> [f64; 8] {
        [
            self.friction_pct,
            self.mass_pct,
            self.torque_pct,
            self.gain_pct,
            self.heading_deg,
            self.position_m,
            self.angle_noise_deg,
            self.range_noise_m,
        ]
    }

    /// A short description, e.g. `8 episodes, mean; friction +-30 %, mass +-10 %`.
    pub fn describe(&self) -> String {
        let score = match self.quantile {
            Some(q) => format!("lower {q} quantile"),
            None => "mean".into(),
        };
        let units = ["%", "%", "%", "%", "deg", "m", "deg", "m"];
        let ranges: Vec<String> = RANGES
            .iter()
            .zip(self.ranges())
            .zip(units)
            .enumerate()
            .filter(|(_, ((_, v), _))| *v > 0.0)
            .map(|(i, (((name, _, _), v), unit))| {
                let spread = if i < 6 { "+-" } else { "sigma " };
                format!("{name} {spread}{v} {unit}")
            })
            .collect();
        format!("{} episodes, {score}; {}", self.episodes, ranges.join(", "))
    }
}

/// Reads `<robustness>` (a child of the optimizer file's root).
pub fn read_robustness(r: &Reader, el: &Element) -> ConfigResult<Robustness> {
    let mut allowed = vec!["episodes", "quantile"];
    allowed.extend(RANGES.iter().map(|(_, lower, _)| *lower));
    r.only_children(el, &allowed)?;
    r.only_attrs(el, &[])?;
    let episodes_el = r.required(el, "episodes")?;
    let episodes = r.u32(episodes_el)?;
    if !(1..=1000).contains(&episodes) {
        return Err(r.err(
            episodes_el.pos,
            ErrorKind::InvalidValue,
            format!("episodes must be 1 ..= 1000, not {episodes}"),
        ));
    }
    let quantile = match r.at_most_one(el, "quantile")? {
        Some(q) => {
            let v = r.f64(q)?;
            if !(v > 0.0 && v < 1.0) {
                return Err(r.err(
                    q.pos,
                    ErrorKind::InvalidValue,
                    format!("quantile must lie strictly between 0 and 1, not {v}"),
                ));
            }
            Some(v)
        }
        None => None,
    };
    let mut v = [0.0; 8];
    for (slot, (_, lower, max)) in v.iter_mut().zip(RANGES) {
        if let Some(e) = r.at_most_one(el, lower)? {
            *slot = r.f64_in(e, 0.0, max)?;
        }
    }
    Ok(Robustness {
        episodes,
        quantile,
        friction_pct: v[0],
        mass_pct: v[1],
        torque_pct: v[2],
        gain_pct: v[3],
        heading_deg: v[4],
        position_m: v[5],
        angle_noise_deg: v[6],
        range_noise_m: v[7],
    })
}

/// Writes `<robustness>`.
pub fn write_robustness(w: &mut XmlWriter, rb: &Robustness) {
    w.open("robustness", &[]);
    w.leaf("episodes", &rb.episodes.to_string());
    if let Some(q) = rb.quantile {
        w.num("quantile", q);
    }
    for ((name, _, _), v) in RANGES.iter().zip(rb.ranges()) {
        if v > 0.0 {
            w.num(name, v);
        }
    }
    w.close();
}

#[cfg(test)]
mod tests {
    use crate::config::optimizer::{parse_optimizer_file, write_optimizer_file};

    fn with(robustness: &str) -> String {
        format!(
            r#"<cmaEvolutionStrategy><properties><numOfParametersToOptimize>1</numOfParametersToOptimize>
<registeredParameters><parameter number="0" controlAlgorithm="PatternGenerator_sinusoidal" parameter="Amplitude"/></registeredParameters></properties>
<genomeConfig number="0" allJoints="1" genomeType="1" valueType="1" valueSpace="1" activeJoints="11111">
<upperBounds>80</upperBounds><lowerBounds>0</lowerBounds><boundsIncrements>1</boundsIncrements>
<lowerBoundTypes>1</lowerBoundTypes><upperBoundTypes>1</upperBoundTypes><uniform>1</uniform></genomeConfig>
{robustness}
</cmaEvolutionStrategy>"#
        )
    }

    #[test]
    fn robustness_is_read_written_and_checked() {
        let text = with(
            "<robustness><episodes>4</episodes><quantile>0.25</quantile><friction>30</friction><angleNoise>0.5</angleNoise></robustness>",
        );
        let f = parse_optimizer_file("o.xml", &text).unwrap();
        let r = f.robustness.unwrap();
        assert_eq!((r.episodes, r.quantile), (4, Some(0.25)));
        assert_eq!(
            (r.friction_pct, r.mass_pct, r.angle_noise_deg),
            (30.0, 0.0, 0.5)
        );
        assert!(
            r.describe().contains("lower 0.25 quantile"),
            "{}",
            r.describe()
        );
        let back = parse_optimizer_file("o.xml", &write_optimizer_file(&f)).unwrap();
        assert_eq!(back, f);
        for (bad, says) in [
            (
                "<robustness><episodes>0</episodes></robustness>",
                "episodes must be",
            ),
            (
                "<robustness><episodes>2</episodes><quantile>1</quantile></robustness>",
                "quantile",
            ),
            (
                "<robustness><episodes>2</episodes><mass>-3</mass></robustness>",
                "mass",
            ),
            (
                "<robustness><episodes>2</episodes><gravity>3</gravity></robustness>",
                "gravity",
            ),
            (
                "<robustness><quantile>0.5</quantile></robustness>",
                "episodes",
            ),
        ] {
            let e = parse_optimizer_file("o.xml", &with(bad))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("o.xml:") && e.to_lowercase().contains(says),
                "{bad}: {e}"
            );
        }
    }
}
