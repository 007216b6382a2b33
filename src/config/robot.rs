//! Robot files (`*.robot.xml`, thesis listing B.2): `<Robot name>` holding one
//! `<KinBody>` (parts included by file and prefix, hinge joints) and attached sensors.
//! Our extension: `<Servos>` maps the joints to the real robot's servos
//! ([`crate::config::servos`]).

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::kinbody::KinBody;
use crate::config::sensor::AttachedSensor;
use crate::config::servos::ServoSection;
use crate::config::xml::read::read_document;
use crate::config::xml::write::XmlWriter;

/// A robot file as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotFile {
    /// The robot's name.
    pub name: String,
    /// Its kinbody.
    pub kinbody: KinBody,
    /// Sensors attached in the robot file.
    pub sensors: Vec<AttachedSensor>,
    /// The real robot's servos, when the file says.
    pub servos: Option<ServoSection>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// Reads a robot file's text.
pub fn parse_robot_file(file: &str, text: &str) -> ConfigResult<RobotFile> {
    let (doc, r) = read_document(file, text, "Robot", "a robot file")?;
    let root = &doc.root;
    r.only_children(root, &["kinbody", "attachedsensor", "servos"])?;
    r.only_attrs(root, &["name"])?;
    let kb = r.required(root, "kinbody")?;
    if kb.attr("file").is_some() {
        return Err(r.err(
            kb.pos,
            ErrorKind::InvalidValue,
            "the robot's <KinBody> holds the parts; include them inside it",
        ));
    }
    Ok(RobotFile {
        name: r.required_attr(root, "name")?.value.clone(),
        kinbody: KinBody::read(&r, kb)?,
        sensors: root
            .children_named("attachedsensor")
            .map(|s| AttachedSensor::read(&r, s))
            .collect::<ConfigResult<_>>()?,
        servos: r
            .at_most_one(root, "servos")?
            .map(|s| ServoSection::read(&r, s))
            .transpose()?,
        pos: root.pos,
    })
}

impl RobotFile {
    /// Rounds the poses and sizes it holds as files written for people hold them
    /// (`KinBody::round_for_people`), its sensors' poses too.
    pub fn round_for_people(&mut self) {
        self.kinbody.round_for_people();
        for s in &mut self.sensors {
            s.pose = s.pose.for_people();
        }
    }
}

/// Writes a robot file.
pub fn write_robot_file(robot: &RobotFile) -> String {
    let mut w = XmlWriter::new();
    w.open("Robot", &[("name", robot.name.clone())]);
    robot.kinbody.write(&mut w);
    for s in &robot.sensors {
        s.write(&mut w);
    }
    if let Some(s) = &robot.servos {
        s.write(&mut w);
    }
    w.finish()
}
