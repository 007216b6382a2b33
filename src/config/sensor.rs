//! Sensor configuration (thesis listings B.3, B.4) and sensors attached to robot links.
//!
//! A sensor file holds one `<sensor type="TactileSensor|BaseLaser2D">`. Robots attach
//! sensors with OpenRAVE's `<AttachedSensor name=".."><link>..</link>(pose)<sensor .../>`,
//! where the `<sensor>` is inline or names a file with `file="..."`.
//! Our extensions: a tactile pad's `<extents>` (half-extents, m) and `<debounce>` (steps).

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::transform::{POSE_ELEMENTS, Pose};
use crate::config::xml::dom::Element;
use crate::config::xml::read::{Reader, read_document};
use crate::config::xml::write::XmlWriter;

/// Default half-extents of a tactile pad (m).
pub const DEFAULT_PAD_EXTENTS: [f64; 3] = [0.012, 0.015, 0.002];

/// A binary touch sensor (a pad pressed or released), debounced.
#[derive(Debug, Clone, PartialEq)]
pub struct TactileSensor {
    /// Whether the sensor is on.
    pub power: bool,
    /// Half-extents of the pad (m).
    pub extents: [f64; 3],
    /// Consecutive steps a new state must last before it is reported.
    pub debounce: u32,
}

/// A planar laser range finder (OpenRAVE BaseLaser2D). Angles in degrees.
#[derive(Debug, Clone, PartialEq)]
pub struct Laser2d {
    /// First beam angle (degrees).
    pub min_angle: f64,
    /// Last beam angle (degrees).
    pub max_angle: f64,
    /// Angle between beams (degrees).
    pub resolution: f64,
    /// Longest range (m).
    pub max_range: f64,
    /// Time for one scan (s).
    pub scan_time: f64,
    /// Whether a viewer draws the beams (as written).
    pub render: bool,
    /// Whether the sensor is on.
    pub power: bool,
}

impl Laser2d {
    /// The beam angles (degrees): from `min_angle` to `max_angle` in steps of
    /// `resolution`.
    pub fn beam_angles(&self) -> Vec<f64> {
        let n = ((self.max_angle - self.min_angle) / self.resolution + 1e-9).floor() as usize + 1;
        (0..n)
            .map(|i| self.min_angle + i as f64 * self.resolution)
            .collect()
    }
}

/// `el`'s at most one `<name>` flag (0/1), else `default`.
fn flag(r: &Reader, el: &Element, name: &str, default: bool) -> ConfigResult<bool> {
    r.at_most_one(el, name)?
        .map(|c| r.flag(c))
        .transpose()
        .map(|v| v.unwrap_or(default))
}

/// A `<sensor type="BaseLaser2D">`'s settings.
fn read_laser(r: &Reader, el: &Element) -> ConfigResult<Laser2d> {
    r.only_children(
        el,
        &[
            "minangle",
            "maxangle",
            "resolution",
            "maxrange",
            "scantime",
            "render",
            "power",
        ],
    )?;
    let min_angle = r.opt_f64(el, "minangle")?.unwrap_or(-90.0);
    let max_angle = r.opt_f64(el, "maxangle")?.unwrap_or(90.0);
    if min_angle > max_angle {
        let c = r.required(el, "minangle")?;
        return Err(r.err(
            c.text_pos,
            ErrorKind::OutOfRange,
            format!("laser <minangle> {min_angle} is greater than <maxangle> {max_angle}"),
        ));
    }
    let positive = |name: &str, default: f64| -> ConfigResult<f64> {
        Ok(r.opt_positive(el, name)?.unwrap_or(default))
    };
    let laser = Laser2d {
        min_angle,
        max_angle,
        resolution: positive("resolution", 1.0)?,
        max_range: positive("maxrange", 5.0)?,
        scan_time: positive("scantime", 0.1)?,
        render: flag(r, el, "render", false)?,
        power: flag(r, el, "power", true)?,
    };
    check_scan(r, el, &laser)?;
    Ok(laser)
}

/// Most beams a laser may have: real planar scanners have up to a few thousand (a
/// Hokuyo UTM-30LX 1,081, a SICK LMS-5xx 1,901 at its finest).
pub const MAX_BEAMS: f64 = 10_000.0;

/// Refuses a scan wider than a full turn (angles beyond ±360°) or of more than
/// [`MAX_BEAMS`] beams, at the element that says so: every beam is cast every scan.
fn check_scan(r: &Reader, el: &Element, l: &Laser2d) -> ConfigResult<()> {
    for (name, v) in [("minangle", l.min_angle), ("maxangle", l.max_angle)] {
        if v.abs() > 360.0 {
            let c = r.required(el, name)?;
            return Err(r.err(
                c.text_pos,
                ErrorKind::OutOfRange,
                format!("laser <{name}> {v} is beyond a full turn: give degrees within -360..360"),
            ));
        }
    }
    if l.max_angle - l.min_angle > 360.0 {
        let c = r.required(el, "maxangle")?;
        return Err(r.err(
            c.text_pos,
            ErrorKind::OutOfRange,
            format!(
                "laser scans {} degrees (<minangle> {} to <maxangle> {}): at most a full turn, 360",
                l.max_angle - l.min_angle,
                l.min_angle,
                l.max_angle
            ),
        ));
    }
    let beams = ((l.max_angle - l.min_angle) / l.resolution).floor() + 1.0;
    if beams > MAX_BEAMS {
        let pos = r
            .at_most_one(el, "resolution")?
            .map_or(el.pos, |c| c.text_pos);
        return Err(r.err(
            pos,
            ErrorKind::OutOfRange,
            format!(
                "laser has {beams} beams ({} degrees every {} degrees): at most {MAX_BEAMS}; give a coarser <resolution>",
                l.max_angle - l.min_angle,
                l.resolution
            ),
        ));
    }
    Ok(())
}

/// The kinds of sensor.
#[derive(Debug, Clone, PartialEq)]
pub enum Sensor {
    /// A touch pad.
    Tactile(TactileSensor),
    /// A planar laser range finder.
    Laser2d(Laser2d),
}

impl Sensor {
    /// The sensor's type name in files.
    pub fn type_name(&self) -> &'static str {
        match self {
            Sensor::Tactile(_) => "TactileSensor",
            Sensor::Laser2d(_) => "BaseLaser2D",
        }
    }

    /// Reads a `<sensor type="...">` element (the root of a sensor file, or inline).
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<Sensor> {
        let ty = r.required_attr(el, "type")?;
        match ty.value.to_ascii_lowercase().as_str() {
            "tactilesensor" | "tactile" => {
                r.only_children(el, &["power", "extents", "debounce"])?;
                let extents = match r.at_most_one(el, "extents")? {
                    Some(c) => {
                        let e = r.array::<3>(c)?;
                        if e.iter().any(|v| *v <= 0.0) {
                            return Err(r.err(
                                c.text_pos,
                                ErrorKind::OutOfRange,
                                "pad <extents> must all be > 0",
                            ));
                        }
                        e
                    }
                    None => DEFAULT_PAD_EXTENTS,
                };
                let debounce = r
                    .at_most_one(el, "debounce")?
                    .map(|c| r.u32(c))
                    .transpose()?
                    .unwrap_or(3);
                Ok(Sensor::Tactile(TactileSensor {
                    power: flag(r, el, "power", true)?,
                    extents,
                    debounce,
                }))
            }
            "baselaser2d" | "laser2d" => Ok(Sensor::Laser2d(read_laser(r, el)?)),
            other => Err(r.err(
                ty.pos,
                ErrorKind::InvalidValue,
                format!("unknown sensor type \"{other}\"; expected TactileSensor or BaseLaser2D"),
            )),
        }
    }

    /// Writes the `<sensor>` element.
    pub fn write(&self, w: &mut XmlWriter, extra_attrs: &[(&str, String)]) {
        let mut attrs = vec![("type", self.type_name().to_string())];
        attrs.extend(extra_attrs.iter().cloned());
        w.open("sensor", &attrs);
        match self {
            Sensor::Tactile(t) => {
                w.flag("power", t.power);
                w.nums("extents", &t.extents);
                w.leaf("debounce", &t.debounce.to_string());
            }
            Sensor::Laser2d(l) => {
                w.num("minangle", l.min_angle);
                w.num("maxangle", l.max_angle);
                w.num("resolution", l.resolution);
                w.num("maxrange", l.max_range);
                w.num("scantime", l.scan_time);
                w.flag("render", l.render);
                w.flag("power", l.power);
            }
        }
        w.close();
    }
}

/// Where an attached sensor's definition lives.
#[derive(Debug, Clone, PartialEq)]
pub enum SensorSource {
    /// Written in place.
    Inline(Sensor),
    /// A sensor file, as written (resolved relative to the including file).
    File {
        /// The path as written.
        path: String,
        /// Where it was written.
        pos: Pos,
    },
}

/// A sensor attached to a link of the robot.
#[derive(Debug, Clone, PartialEq)]
pub struct AttachedSensor {
    /// The sensor's name.
    pub name: String,
    /// The body it is attached to.
    pub link: String,
    /// Pose in the link's frame.
    pub pose: Pose,
    /// The sensor, inline or from a file.
    pub source: SensorSource,
    /// Where it was written (line, column).
    pub pos: Pos,
}

impl AttachedSensor {
    /// Reads it from its element; errors name the line.
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<AttachedSensor> {
        let mut allowed = vec!["link", "sensor"];
        allowed.extend(POSE_ELEMENTS);
        r.only_children(el, &allowed)?;
        r.only_attrs(el, &["name"])?;
        let name = r.required_attr(el, "name")?.value.clone();
        let link = r.text(r.required(el, "link")?)?.to_string();
        let s = r.required(el, "sensor")?;
        let source = match s.attr("file") {
            Some(f) => {
                r.only_attrs(s, &["file", "type"])?;
                if !s.children.is_empty() {
                    return Err(r.err(
                        s.pos,
                        ErrorKind::InvalidValue,
                        "a <sensor file=...> takes no inline settings",
                    ));
                }
                SensorSource::File {
                    path: f.value.clone(),
                    pos: f.pos,
                }
            }
            None => {
                r.only_attrs(s, &["type"])?;
                SensorSource::Inline(Sensor::read(r, s)?)
            }
        };
        Ok(AttachedSensor {
            name,
            link,
            pose: Pose::read(r, el)?,
            source,
            pos: el.pos,
        })
    }

    /// Writes it as XML.
    pub fn write(&self, w: &mut XmlWriter) {
        w.open("AttachedSensor", &[("name", self.name.clone())]);
        w.leaf("link", &self.link);
        self.pose.write(w);
        match &self.source {
            SensorSource::Inline(s) => s.write(w, &[]),
            SensorSource::File { path, .. } => w.empty("sensor", &[("file", path.clone())]),
        }
        w.close();
    }
}

/// Reads a sensor file's text.
pub fn parse_sensor_file(file: &str, text: &str) -> ConfigResult<Sensor> {
    let (doc, r) = read_document(file, text, "sensor", "a sensor file")?;
    r.only_attrs(&doc.root, &["type"])?;
    Sensor::read(&r, &doc.root)
}

/// Writes a sensor file.
pub fn write_sensor_file(sensor: &Sensor) -> String {
    let mut w = XmlWriter::new();
    sensor.write(&mut w, &[]);
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn laser(min: &str, max: &str, resolution: &str) -> ConfigResult<Sensor> {
        parse_sensor_file(
            "l.sensor.xml",
            &format!(
                "<sensor type=\"BaseLaser2D\">\n  <minangle>{min}</minangle>\n  <maxangle>{max}</maxangle>\n  <resolution>{resolution}</resolution>\n</sensor>\n"
            ),
        )
    }

    /// A scan is at most a full turn of at most MAX_BEAMS beams (fuzzing found a laser of
    /// 10^13 beams that the world then tried to cast: regression input
    /// fuzz/regressions/sensor_file/laser-scan-beyond-a-full-turn).
    #[test]
    fn a_laser_scans_at_most_a_full_turn_in_at_most_ten_thousand_beams() {
        let Ok(Sensor::Laser2d(l)) = laser("-180", "180", "0.25") else {
            panic!("a full turn at a quarter degree loads");
        };
        assert_eq!(l.beam_angles().len(), 1441);
        let e = laser("-11111111111111.1", "90", "1").unwrap_err();
        assert_eq!((e.kind, e.pos.line), (ErrorKind::OutOfRange, 2), "{e}");
        assert!(e.to_string().contains("beyond a full turn"), "{e}");
        let e = laser("-300", "300", "1").unwrap_err();
        assert_eq!(e.pos.line, 3, "{e}");
        assert!(e.to_string().contains("at most a full turn"), "{e}");
        let e = laser("-90", "90", "0.001").unwrap_err();
        assert_eq!(e.pos.line, 4, "{e}");
        assert!(e.to_string().contains("180001 beams"), "{e}");
    }
}
