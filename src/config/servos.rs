//! The real robot's servos (our extension of robot files): which servo on the
//! bus drives which joint, with an angle offset and a direction, and the bus settings.
//!
//! ```xml
//! <Servos driver="dynamixel" baud="1000000" readEvery="10">
//!   <Servo joint="J1" id="1" offset="0" direction="1"/>
//!   <Servo joint="J2" id="2" offset="-3.5" direction="-1"/>
//! </Servos>
//! ```
//!
//! `offset` (degrees) is the servo's reading when the joint is straight, so the joint
//! angle is `direction × (servo angle − offset)`. `readEvery` is the period, in control
//! steps, of reading positions, currents and speeds back. A robot file without `<Servos>`
//! drives servo ids 1..N in joint order, offset 0, direction 1, at 1 Mbaud.

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::XmlWriter;

/// The servo bus drivers proleg has.
pub const DRIVERS: &[&str] = &["dynamixel"];
/// Default baud rate.
pub const DEFAULT_BAUD: u32 = 1_000_000;
/// Default read-back period (control steps).
pub const DEFAULT_READ_EVERY: u32 = 10;

/// One servo.
#[derive(Debug, Clone, PartialEq)]
pub struct ServoBinding {
    /// The joint's name in the robot file.
    pub joint: String,
    /// The servo's id on the bus (0..=252).
    pub id: u8,
    /// The servo's angle (degrees) with the joint straight.
    pub offset: f64,
    /// +1 or −1.
    pub direction: i8,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// The `<Servos>` element.
#[derive(Debug, Clone, PartialEq)]
pub struct ServoSection {
    /// The servo driver (`dynamixel`).
    pub driver: String,
    /// Bus speed (baud).
    pub baud: u32,
    /// Read the servos back every this many steps.
    pub read_every: u32,
    /// One servo per joint.
    pub servos: Vec<ServoBinding>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

impl ServoBinding {
    /// Reads one `<servo joint=".." id=".." offset=".." direction=".."/>`.
    fn read(r: &Reader, s: &Element) -> ConfigResult<ServoBinding> {
        r.only_attrs(s, &["joint", "id", "offset", "direction"])?;
        let joint = r.required_attr(s, "joint")?.value.trim().to_string();
        let id_attr = r.required_attr(s, "id")?;
        let id = r.u32_str(&id_attr.value, id_attr.pos, "id")?;
        if id > 252 {
            return Err(r.err(
                id_attr.pos,
                ErrorKind::OutOfRange,
                format!("servo id {id}: Dynamixel ids are 0..252"),
            ));
        }
        let offset = match s.attr("offset") {
            Some(a) => r.number(&a.value, a.pos, "offset")?,
            None => 0.0,
        };
        let direction = match s.attr("direction") {
            Some(a) => match a.value.trim() {
                "1" | "+1" => 1,
                "-1" => -1,
                other => {
                    return Err(r.err(
                        a.pos,
                        ErrorKind::InvalidValue,
                        format!("direction \"{other}\": write 1 or -1"),
                    ));
                }
            },
            None => 1,
        };
        Ok(ServoBinding {
            joint,
            id: id as u8,
            offset,
            direction,
            pos: s.pos,
        })
    }
}

impl ServoSection {
    /// Reads `<Servos>`.
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<ServoSection> {
        r.only_attrs(el, &["driver", "baud", "readevery"])?;
        r.only_children(el, &["servo"])?;
        let driver = match el.attr("driver") {
            Some(a) => {
                let d = a.value.trim().to_ascii_lowercase();
                if !DRIVERS.contains(&d.as_str()) {
                    return Err(r.err(
                        a.pos,
                        ErrorKind::InvalidValue,
                        format!(
                            "servo driver \"{}\" is unknown; drivers: {}",
                            a.value,
                            DRIVERS.join(", ")
                        ),
                    ));
                }
                d
            }
            None => DRIVERS[0].to_string(),
        };
        let whole = |name: &str, default: u32, min: u32| -> ConfigResult<u32> {
            match el.attr(name) {
                None => Ok(default),
                Some(a) => {
                    let v = r.u32_str(&a.value, a.pos, name)?;
                    if v < min {
                        return Err(r.err(
                            a.pos,
                            ErrorKind::OutOfRange,
                            format!("{name} = {v}: it must be at least {min}"),
                        ));
                    }
                    Ok(v)
                }
            }
        };
        let servos = el
            .children_named("servo")
            .map(|s| ServoBinding::read(r, s))
            .collect::<ConfigResult<Vec<_>>>()?;
        Ok(ServoSection {
            driver,
            baud: whole("baud", DEFAULT_BAUD, 1)?,
            read_every: whole("readevery", DEFAULT_READ_EVERY, 1)?,
            servos,
            pos: el.pos,
        })
    }

    /// Writes `<Servos>`.
    pub fn write(&self, w: &mut XmlWriter) {
        w.open(
            "Servos",
            &[
                ("driver", self.driver.clone()),
                ("baud", self.baud.to_string()),
                ("readEvery", self.read_every.to_string()),
            ],
        );
        for s in &self.servos {
            w.empty(
                "Servo",
                &[
                    ("joint", s.joint.clone()),
                    ("id", s.id.to_string()),
                    ("offset", s.offset.to_string()),
                    ("direction", s.direction.to_string()),
                ],
            );
        }
        w.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::xml::read::read_document;

    fn read(text: &str) -> ConfigResult<ServoSection> {
        let (doc, r) = read_document("s.robot.xml", text, "Servos", "servos")?;
        ServoSection::read(&r, &doc.root)
    }

    #[test]
    fn servos_read_with_defaults_and_write_back() {
        let s = read(
            r#"<Servos readEvery="5"><Servo joint="J1" id="3" offset="-2.5" direction="-1"/><Servo joint="J2" id="4"/></Servos>"#,
        )
        .unwrap();
        assert_eq!(
            (s.driver.as_str(), s.baud, s.read_every),
            ("dynamixel", 1_000_000, 5)
        );
        assert_eq!(
            (s.servos[0].id, s.servos[0].offset, s.servos[0].direction),
            (3, -2.5, -1)
        );
        assert_eq!((s.servos[1].offset, s.servos[1].direction), (0.0, 1));
        let mut w = XmlWriter::new();
        s.write(&mut w);
        let again = read(&w.finish()).unwrap();
        assert_eq!(again.servos.len(), 2);
        assert_eq!((again.servos[0].id, again.servos[0].direction), (3, -1));
        assert_eq!(again.read_every, 5);
    }

    #[test]
    fn bad_servo_entries_name_the_line_and_cause() {
        for (text, needle) in [
            (
                r#"<Servos driver="herkulex"/>"#,
                "servo driver \"herkulex\" is unknown",
            ),
            (
                r#"<Servos><Servo joint="J1" id="300"/></Servos>"#,
                "Dynamixel ids are 0..252",
            ),
            (
                r#"<Servos><Servo joint="J1" id="1" direction="2"/></Servos>"#,
                "write 1 or -1",
            ),
            (
                r#"<Servos><Servo joint="J1" id="1" offset="nan"/></Servos>"#,
                "finite number",
            ),
            (r#"<Servos readEvery="0"/>"#, "at least 1"),
            (r#"<Servos><Servo id="1"/></Servos>"#, "joint="),
        ] {
            let e = read(text).unwrap_err().to_string();
            assert!(
                e.contains(needle) && e.starts_with("s.robot.xml:1:"),
                "{text}: {e}"
            );
        }
    }
}
