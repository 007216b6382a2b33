//! OpenRAVE-style `<KinBody>`: bodies, hinge joints, attached sensors and includes of
//! other kinbody files (`<KinBody file=".." prefix="..">` with a placement pose).
//!
//! Used for module parts (`*.kinbody.xml`), the body of a robot file, and the objects
//! of an environment file. Joint units: `limitsdeg` in degrees, `maxvel` in rad/s,
//! `maxtorque` in N·m. Extension: `<servoGain>` (1/s), the proportional gain of the
//! joint's servo.

use crate::config::body::Body;
use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::sensor::AttachedSensor;
use crate::config::transform::{POSE_ELEMENTS, Pose};
use crate::config::xml::dom::Element;
use crate::config::xml::read::{Reader, read_document};
use crate::config::xml::write::XmlWriter;

/// A hinge joint between two bodies.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// The joint's name.
    pub name: String,
    /// Parent and child body names.
    pub bodies: [String; 2],
    /// The body whose frame `anchor` and `axis` are given in (the first body if absent).
    pub offset_from: Option<String>,
    /// Hinge point, in the frame of the parent body (or `offsetfrom`).
    pub anchor: [f64; 3],
    /// Hinge axis, in the same frame.
    pub axis: [f64; 3],
    /// Servo torque limit (N·m), when given.
    pub max_torque: Option<f64>,
    /// Servo speed limit (rad/s), when given.
    pub max_vel: Option<f64>,
    /// Angle limits (degrees), when given.
    pub limits_deg: Option<[f64; 2]>,
    /// Extension: the servo's proportional gain (1/s).
    pub servo_gain: Option<f64>,
    /// Extension `<servoDeadBand>`: the angle error (degrees) the servo does not correct.
    pub servo_dead_band: Option<f64>,
    /// Extension `<servoLatency>`: how long (s) a goal takes to reach the servo.
    pub servo_latency: Option<f64>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// An included kinbody file, placed by a pose and with names prefixed.
#[derive(Debug, Clone, PartialEq)]
pub struct Include {
    /// The path as written in the file.
    pub file: String,
    /// Prefix of the included names.
    pub prefix: String,
    /// Placement of the included kinbody.
    pub pose: Pose,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// A kinematic body: bodies, joints, sensors and included parts.
#[derive(Debug, Clone, PartialEq)]
pub struct KinBody {
    /// The kinbody's name, if any.
    pub name: Option<String>,
    /// Placement of the whole kinbody.
    pub pose: Pose,
    /// Included part files.
    pub includes: Vec<Include>,
    /// Its bodies.
    pub bodies: Vec<Body>,
    /// Its joints.
    pub joints: Vec<Joint>,
    /// Sensors attached to its bodies.
    pub sensors: Vec<AttachedSensor>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

const JOINT_CHILDREN: [&str; 12] = [
    "body",
    "offsetfrom",
    "anchor",
    "axis",
    "maxtorque",
    "maxvel",
    "limitsdeg",
    "limitsrad",
    "limits",
    "servogain",
    "servodeadband",
    "servolatency",
];

impl Joint {
    /// Reads it from its element; errors name the line.
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<Joint> {
        r.only_children(el, &JOINT_CHILDREN)?;
        r.only_attrs(el, &["name", "type", "enable"])?;
        let name = r.required_attr(el, "name")?.value.clone();
        if let Some(t) = el.attr("type")
            && !matches!(t.value.to_ascii_lowercase().as_str(), "hinge" | "revolute")
        {
            return Err(r.err(
                t.pos,
                ErrorKind::InvalidValue,
                format!(
                    "joint {name}: type \"{}\" is not supported; expected hinge",
                    t.value
                ),
            ));
        }
        let bodies: Vec<String> = el
            .children_named("body")
            .map(|b| r.text(b).map(str::to_string))
            .collect::<ConfigResult<_>>()?;
        let bodies: [String; 2] = bodies.try_into().map_err(|b: Vec<String>| {
            r.err(
                el.pos,
                ErrorKind::InvalidValue,
                format!(
                    "joint {name} needs exactly 2 <Body> elements, found {}",
                    b.len()
                ),
            )
        })?;
        let axis = r.array::<3>(r.required(el, "axis")?)?;
        if axis.iter().map(|v| v * v).sum::<f64>() < 1e-12 {
            let c = r.required(el, "axis")?;
            return Err(r.err(
                c.text_pos,
                ErrorKind::InvalidValue,
                format!("joint {name}: <axis> is zero"),
            ));
        }
        let anchor = r
            .at_most_one(el, "anchor")?
            .map(|c| r.array::<3>(c))
            .transpose()?
            .unwrap_or([0.0; 3]);
        let max_torque = r.opt_positive(el, "maxtorque")?;
        let max_vel = r.opt_positive(el, "maxvel")?;
        let servo_gain = r.opt_positive(el, "servogain")?;
        let servo_dead_band = r.opt_positive(el, "servodeadband")?;
        let servo_latency = r.opt_positive(el, "servolatency")?;
        let limits_deg = read_limits(r, el, &name)?;
        Ok(Joint {
            offset_from: r
                .at_most_one(el, "offsetfrom")?
                .map(|c| r.text(c).map(str::to_string))
                .transpose()?,
            name,
            bodies,
            anchor,
            axis,
            max_torque,
            max_vel,
            limits_deg,
            servo_gain,
            servo_dead_band,
            servo_latency,
            pos: el.pos,
        })
    }

    /// Writes it as XML.
    pub fn write(&self, w: &mut XmlWriter) {
        w.open(
            "Joint",
            &[("type", "hinge".into()), ("name", self.name.clone())],
        );
        w.leaf("Body", &self.bodies[0]);
        w.leaf("Body", &self.bodies[1]);
        if let Some(o) = &self.offset_from {
            w.leaf("offsetfrom", o);
        }
        if self.anchor != [0.0; 3] {
            w.nums("anchor", &self.anchor);
        }
        w.nums("axis", &self.axis);
        if let Some(v) = self.max_torque {
            w.num("maxtorque", v);
        }
        if let Some(v) = self.max_vel {
            w.num("maxvel", v);
        }
        if let Some(l) = self.limits_deg {
            w.nums("limitsdeg", &l);
        }
        if let Some(g) = self.servo_gain {
            w.num("servoGain", g);
        }
        if let Some(d) = self.servo_dead_band {
            w.num("servoDeadBand", d);
        }
        if let Some(l) = self.servo_latency {
            w.num("servoLatency", l);
        }
        w.close();
    }
}

/// A joint's limits in degrees, from `<limitsdeg>`, or `<limitsrad>` / `<limits>` in
/// radians; at most one of them, lower <= upper, within ±180°.
fn read_limits(r: &Reader, el: &Element, name: &str) -> ConfigResult<Option<[f64; 2]>> {
    let mut limits_deg = None;
    for c in &el.children {
        let scale = if c.is("limitsdeg") {
            1.0
        } else if c.is("limitsrad") || c.is("limits") {
            180.0 / std::f64::consts::PI
        } else {
            continue;
        };
        if limits_deg.is_some() {
            return Err(r.err(
                c.pos,
                ErrorKind::InvalidValue,
                format!("joint {name}: limits given twice"),
            ));
        }
        let [lo, hi] = r.array::<2>(c)?;
        let (lo, hi) = (lo * scale, hi * scale);
        if lo > hi {
            return Err(r.err(
                c.text_pos,
                ErrorKind::OutOfRange,
                format!("joint {name}: lower limit {lo} deg is greater than upper limit {hi} deg"),
            ));
        }
        r.check_range(
            lo,
            -180.0,
            180.0,
            c.text_pos,
            &format!("joint {name}: lower limit (deg)"),
        )?;
        r.check_range(
            hi,
            -180.0,
            180.0,
            c.text_pos,
            &format!("joint {name}: upper limit (deg)"),
        )?;
        limits_deg = Some([lo, hi]);
    }
    Ok(limits_deg)
}

impl KinBody {
    /// Reads a `<KinBody>` that is not itself an include.
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<KinBody> {
        let mut allowed = vec!["kinbody", "body", "joint", "attachedsensor"];
        allowed.extend(POSE_ELEMENTS);
        r.only_children(el, &allowed)?;
        r.only_attrs(el, &["name"])?;
        let mut kb = KinBody {
            name: el.attr("name").map(|a| a.value.clone()),
            pose: Pose::read(r, el)?,
            includes: Vec::new(),
            bodies: Vec::new(),
            joints: Vec::new(),
            sensors: Vec::new(),
            pos: el.pos,
        };
        let body_count = el.children_named("body").count();
        for c in &el.children {
            if c.is("kinbody") {
                kb.includes.push(Include::read(r, c)?);
            } else if c.is("body") {
                // Unnamed bodies (the thesis's floor) are named after their kinbody.
                let default = match (&kb.name, body_count) {
                    (Some(n), 1) => n.clone(),
                    (Some(n), _) => format!("{n}{}", kb.bodies.len()),
                    (None, _) => format!("body{}", kb.bodies.len()),
                };
                kb.bodies.push(Body::read(r, c, &default)?);
            } else if c.is("joint") {
                kb.joints.push(Joint::read(r, c)?);
            } else if c.is("attachedsensor") {
                kb.sensors.push(AttachedSensor::read(r, c)?);
            }
        }
        Ok(kb)
    }

    /// Writes the `<KinBody>` element.
    pub fn write(&self, w: &mut XmlWriter) {
        let attrs: Vec<(&str, String)> = self.name.iter().map(|n| ("name", n.clone())).collect();
        w.open("KinBody", &attrs);
        self.pose.write(w);
        for i in &self.includes {
            i.write(w);
        }
        for b in &self.bodies {
            b.write(w);
        }
        for j in &self.joints {
            j.write(w);
        }
        for s in &self.sensors {
            s.write(w);
        }
        w.close();
    }

    /// Rounds the poses and sizes it holds as files written for people hold them (0.1 mm,
    /// sizes 0.01 mm): what a program that computed them (wizard, editor, import) writes;
    /// the writer itself writes values as they are.
    pub fn round_for_people(&mut self) {
        self.pose = self.pose.for_people();
        for i in &mut self.includes {
            i.pose = i.pose.for_people();
        }
        for b in &mut self.bodies {
            b.round_for_people();
        }
        for s in &mut self.sensors {
            s.pose = s.pose.for_people();
        }
    }
}

impl Include {
    /// Reads it from its element; errors name the line.
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<Include> {
        r.only_children(el, &POSE_ELEMENTS)?;
        r.only_attrs(el, &["file", "prefix", "name"])?;
        let file = el.attr("file").ok_or_else(|| {
            r.err(
                el.pos,
                ErrorKind::Missing,
                "a nested <KinBody> must name a part file with file=\"...\"",
            )
        })?;
        Ok(Include {
            file: file.value.clone(),
            prefix: el
                .attr("prefix")
                .map(|a| a.value.clone())
                .unwrap_or_default(),
            pose: Pose::read(r, el)?,
            pos: file.pos,
        })
    }

    /// Writes it as XML.
    pub fn write(&self, w: &mut XmlWriter) {
        let mut attrs = Vec::new();
        if !self.prefix.is_empty() {
            attrs.push(("prefix", self.prefix.clone()));
        }
        attrs.push(("file", self.file.clone()));
        if self.pose.is_identity() {
            w.empty("KinBody", &attrs);
        } else {
            w.open("KinBody", &attrs);
            self.pose.write(w);
            w.close();
        }
    }
}

/// Reads a kinbody part file.
pub fn parse_kinbody_file(file: &str, text: &str) -> ConfigResult<KinBody> {
    let (doc, r) = read_document(file, text, "KinBody", "a kinbody file")?;
    if doc.root.attr("file").is_some() {
        return Err(r.err(
            doc.root.pos,
            ErrorKind::InvalidValue,
            "the root <KinBody> of a part file cannot include another file",
        ));
    }
    KinBody::read(&r, &doc.root)
}

/// Writes a kinbody part file.
pub fn write_kinbody_file(kb: &KinBody) -> String {
    let mut w = XmlWriter::new();
    kb.write(&mut w);
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_joints_servo_extensions_round_trip() {
        let text = r#"<KinBody name="k">
  <Body name="a"><Geom type="box"><extents>0.1 0.1 0.1</extents></Geom></Body>
  <Body name="b"><Geom type="box"><extents>0.1 0.1 0.1</extents></Geom></Body>
  <Joint type="hinge" name="J1"><Body>a</Body><Body>b</Body><axis>1 0 0</axis>
    <servoGain>24.75</servoGain><servoDeadBand>0.81</servoDeadBand><servoLatency>0.03</servoLatency>
  </Joint>
</KinBody>"#;
        let kb = parse_kinbody_file("k.kinbody.xml", text).unwrap();
        let j = &kb.joints[0];
        assert_eq!(
            (j.servo_gain, j.servo_dead_band, j.servo_latency),
            (Some(24.75), Some(0.81), Some(0.03))
        );
        let again = parse_kinbody_file("k.kinbody.xml", &write_kinbody_file(&kb)).unwrap();
        assert_eq!(again, kb);
    }
}
