//! The robot builder (thesis 4.4.3): a snake or caterpillar chain from its topology — one
//! pitch or yaw orientation per joint — and a part set (plain modules, modules with touch
//! pads, cube modules). The result is an ordinary robot file that includes the module
//! parts of `configs/parts/`.

use crate::config::error::Pos;
use crate::config::kinbody::{Include, Joint, KinBody};
use crate::config::robot::RobotFile;
use crate::config::transform::Pose;

/// Why a robot cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BuildError {
    /// A robot or file name that is empty.
    #[error("{what}: give a name")]
    NoName {
        /// What the name names.
        what: &'static str,
    },
    /// A name with a character files cannot hold.
    #[error("{what} \"{name}\": '{bad}' is not allowed; use letters, digits, _ and -")]
    BadName {
        /// What the name names.
        what: &'static str,
        /// The name.
        name: String,
        /// Its first bad character.
        bad: char,
    },
    /// A topology letter that is neither p nor y.
    #[error("topology: joint {joint} is '{letter}'; write p (pitch) or y (yaw) per joint")]
    Topology {
        /// The joint (from 1).
        joint: usize,
        /// Its letter.
        letter: char,
    },
    /// A robot with no joints or too many.
    #[error("a robot needs 1 to {MAX_JOINTS} joints; this one has {0}")]
    JointCount(usize),
}

/// Most joints a built robot may have.
pub const MAX_JOINTS: usize = 32;

/// A joint's orientation in the chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Orientation {
    /// Turns about the robot's lateral (x) axis: up and down.
    Pitch,
    /// Turns about the vertical (z) axis: left and right.
    Yaw,
}

impl Orientation {
    /// `P` or `Y`, as in topology strings.
    pub fn letter(self) -> char {
        match self {
            Orientation::Pitch => 'p',
            Orientation::Yaw => 'y',
        }
    }

    fn axis(self) -> [f64; 3] {
        match self {
            Orientation::Pitch => [1.0, 0.0, 0.0],
            Orientation::Yaw => [0.0, 0.0, 1.0],
        }
    }
}

/// The module parts a robot is built from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartSet {
    /// 72 mm box modules (`TailP`, `PP` / `PY` / `YP`, `HeadP`).
    Plain,
    /// The same modules with touch pads under every link (thesis 6.2's detailed module).
    Touch,
    /// 60 mm cube concept modules (thesis 3.1.4).
    Cube,
}

impl PartSet {
    /// Every value, in the order the GUI lists them.
    pub const ALL: [PartSet; 3] = [PartSet::Plain, PartSet::Touch, PartSet::Cube];

    /// The name scripts use.
    pub fn name(self) -> &'static str {
        match self {
            PartSet::Plain => "plain",
            PartSet::Touch => "touch",
            PartSet::Cube => "cube",
        }
    }

    /// What the set is, for the GUI.
    pub fn describe(self) -> &'static str {
        match self {
            PartSet::Plain => "plain 72 mm modules",
            PartSet::Touch => "72 mm modules with 12 touch pads (sensing modules need them)",
            PartSet::Cube => "60 mm cube modules",
        }
    }

    /// Reads a name as files, scripts and the command line write it (None: unknown).
    pub fn parse(s: &str) -> Option<PartSet> {
        PartSet::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(s.trim()))
    }

    fn spacing(self) -> f64 {
        match self {
            PartSet::Cube => 0.06,
            _ => 0.072,
        }
    }
}

/// What the builder makes a robot from.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSpec {
    /// The robot's name.
    pub name: String,
    /// Each joint's orientation, tail to head.
    pub joints: Vec<Orientation>,
    /// Which module parts it is built of.
    pub parts: PartSet,
}

impl Default for RobotSpec {
    fn default() -> Self {
        RobotSpec {
            name: "mysnake".into(),
            joints: vec![Orientation::Pitch; 5],
            parts: PartSet::Plain,
        }
    }
}

/// Parses a topology such as `ppyp` (or `PYPY`, spaces ignored).
pub fn parse_topology(s: &str) -> Result<Vec<Orientation>, BuildError> {
    s.chars()
        .filter(|c| !c.is_whitespace())
        .enumerate()
        .map(|(i, c)| match c.to_ascii_lowercase() {
            'p' => Ok(Orientation::Pitch),
            'y' => Ok(Orientation::Yaw),
            other => Err(BuildError::Topology {
                joint: i + 1,
                letter: other,
            }),
        })
        .collect()
}

/// The topology as letters, `ppyp`.
pub fn topology_string(joints: &[Orientation]) -> String {
    joints.iter().map(|o| o.letter()).collect()
}

/// Whether `name` may name a robot and its files.
pub fn check_name(name: &str, what: &'static str) -> Result<(), BuildError> {
    if name.is_empty() {
        return Err(BuildError::NoName { what });
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
    {
        return Err(BuildError::BadName {
            what,
            name: name.to_string(),
            bad: c,
        });
    }
    Ok(())
}

impl RobotSpec {
    /// Why this robot cannot be built, if it cannot.
    pub fn validate(&self) -> Result<(), BuildError> {
        check_name(&self.name, "robot name")?;
        if self.joints.is_empty() || self.joints.len() > MAX_JOINTS {
            return Err(BuildError::JointCount(self.joints.len()));
        }
        Ok(())
    }

    /// Number of modules (joints + 1).
    pub fn modules(&self) -> usize {
        self.joints.len() + 1
    }

    /// The body in one phrase: `8 modules yppyppp plain`.
    pub fn summary(&self) -> String {
        format!(
            "{} modules {} {}",
            self.modules(),
            topology_string(&self.joints),
            self.parts.name()
        )
    }

    /// The robot file, its computed poses rounded for people (`RobotFile::round_for_people`);
    /// `parts_dir` is the parts folder as seen from the robot file (e.g. `../parts`).
    pub fn to_robot_file(&self, parts_dir: &str) -> RobotFile {
        let n = self.joints.len();
        let d = self.parts.spacing();
        let part = |file: &str| format!("{}/{file}.kinbody.xml", parts_dir.trim_end_matches('/'));
        let cube = self.parts == PartSet::Cube;
        let slot = |m: usize| if cube { m } else { m.saturating_sub(1) };
        let mut includes = Vec::with_capacity(n + 1);
        let mut bodies = Vec::with_capacity(n + 1);
        for m in 0..=n {
            let (file, prefix, body) = match self.parts {
                PartSet::Cube => ("Cube".to_string(), m.to_string(), format!("{m}Cube")),
                set => {
                    let touch = if set == PartSet::Touch { "Touch" } else { "" };
                    if m == 0 {
                        (format!("TailP{touch}"), String::new(), "Tail".to_string())
                    } else if m == n {
                        (format!("HeadP{touch}"), String::new(), "Head".to_string())
                    } else if set == PartSet::Touch {
                        ("PPTouch".to_string(), m.to_string(), format!("{m}Seg"))
                    } else {
                        let mid: String = [self.joints[m - 1], self.joints[m]]
                            .iter()
                            .map(|o| o.letter().to_ascii_uppercase())
                            .collect();
                        (mid, m.to_string(), format!("{m}Seg"))
                    }
                }
            };
            includes.push(Include {
                file: part(&file),
                prefix,
                // The tail reaches back from the first joint, every other module forward
                // from its joint, so the tail and module 1 both sit at 0. Rounded to µm
                // so files show 0.216, not 0.21599999999999997.
                pose: Pose::from_translation([0.0, (d * slot(m) as f64 * 1e6).round() / 1e6, 0.0]),
                pos: Pos::new(0, 0),
            });
            bodies.push(body);
        }
        let joints = self
            .joints
            .iter()
            .enumerate()
            .map(|(i, o)| Joint {
                name: format!("J{}", i + 1),
                bodies: [bodies[i].clone(), bodies[i + 1].clone()],
                offset_from: Some(bodies[i + 1].clone()),
                anchor: [0.0; 3],
                axis: o.axis(),
                max_torque: Some(0.4),
                max_vel: Some(4.5),
                limits_deg: Some([-90.0, 90.0]),
                servo_gain: None,
                servo_dead_band: None,
                servo_latency: None,
                pos: Pos::new(0, 0),
            })
            .collect();
        let mut file = RobotFile {
            name: self.name.clone(),
            kinbody: KinBody {
                name: Some(format!("k{}", self.name)),
                pose: Pose::IDENTITY,
                includes,
                bodies: Vec::new(),
                joints,
                sensors: Vec::new(),
                pos: Pos::new(0, 0),
            },
            sensors: Vec::new(),
            servos: None,
            pos: Pos::new(0, 0),
        };
        file.round_for_people();
        file
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::robot::{parse_robot_file, write_robot_file};

    #[test]
    fn topology_parses_and_names_the_bad_joint() {
        let t = parse_topology("p y P").unwrap();
        assert_eq!(
            t,
            vec![Orientation::Pitch, Orientation::Yaw, Orientation::Pitch]
        );
        assert_eq!(topology_string(&t), "pyp");
        assert!(matches!(
            parse_topology("ppx"),
            Err(BuildError::Topology {
                joint: 3,
                letter: 'x'
            })
        ));
    }

    #[test]
    fn built_robot_matches_the_hand_written_pitch_yaw_chain() {
        let spec = RobotSpec {
            name: "snake8py".into(),
            joints: parse_topology("pypypyp").unwrap(),
            parts: PartSet::Plain,
        };
        let built = spec.to_robot_file("../parts");
        let text = std::fs::read_to_string("configs/robots/snake8py.robot.xml").unwrap();
        let mut hand = parse_robot_file("snake8py.robot.xml", &text).unwrap();
        hand.sensors.clear(); // the hand-written one carries a laser
        assert_eq!(built.kinbody.joints, hand.kinbody.joints);
        let includes = |r: &RobotFile| -> Vec<(String, String, [f64; 3])> {
            r.kinbody
                .includes
                .iter()
                .map(|i| (i.file.clone(), i.prefix.clone(), i.pose.translation))
                .collect()
        };
        assert_eq!(includes(&built), includes(&hand));
        // Writing and reading back gives the same robot.
        let back = parse_robot_file("b.robot.xml", &write_robot_file(&built)).unwrap();
        assert_eq!(back, built);
    }

    #[test]
    fn built_touch_and_cube_robots_match_the_hand_written_ones() {
        for (file, topology, parts) in [
            ("tactile5p", "ppppp", PartSet::Touch),
            ("cube5", "ppppp", PartSet::Cube),
        ] {
            let spec = RobotSpec {
                name: file.into(),
                joints: parse_topology(topology).unwrap(),
                parts,
            };
            let built = spec.to_robot_file("../parts");
            let path = format!("configs/robots/{file}.robot.xml");
            let hand = parse_robot_file(&path, &std::fs::read_to_string(&path).unwrap()).unwrap();
            let poses = |r: &RobotFile| -> Vec<(String, [f64; 3])> {
                r.kinbody
                    .includes
                    .iter()
                    .map(|i| (i.file.clone(), i.pose.translation))
                    .collect()
            };
            assert_eq!(poses(&built), poses(&hand), "{file}");
            assert_eq!(built.kinbody.joints, hand.kinbody.joints, "{file}");
        }
    }

    #[test]
    fn validation_refuses_bad_names_and_sizes() {
        let mut s = RobotSpec::default();
        assert!(s.validate().is_ok());
        s.name = "my snake".into();
        assert!(matches!(
            s.validate(),
            Err(BuildError::BadName { bad: ' ', .. })
        ));
        s.name = "ok".into();
        s.joints.clear();
        assert!(matches!(s.validate(), Err(BuildError::JointCount(0))));
    }
}
