//! The resolved robot: links, joints and sensors in the robot's frame, every reference
//! checked, defaults filled in. This is what the simulation builds entities from.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::config::body::{BodyKind, Geom, Shape};
use crate::config::error::{ConfigError, ConfigResult, ErrorKind, Pos};
use crate::config::mesh::Meshes;
use crate::config::resolve::flatten::{
    Flat, Flattener, PlacedBody, PlacedJoint, PlacedSensor, find_file, read_file,
};
use crate::config::resolve::physical;
use crate::config::robot::RobotFile;
use crate::config::sensor::{Sensor, SensorSource, parse_sensor_file};
use crate::config::source::FileSource;
use crate::config::transform::Pose;
use crate::config::xml::read::Reader;

/// Default joint limits (deg), torque (N·m) and speed (rad/s): the thesis's servo (B.2).
pub const DEFAULT_LIMITS_DEG: [f64; 2] = [-90.0, 90.0];
/// Servo torque limit when a joint gives none (N·m).
pub const DEFAULT_MAX_TORQUE: f64 = 0.4;
/// Servo speed limit when a joint gives none (rad/s).
pub const DEFAULT_MAX_VEL: f64 = 4.5;
/// Density used for bodies that give no mass (kg/m³, OpenRAVE's default).
pub const DEFAULT_DENSITY: f64 = 1000.0;

/// How a hinge bends the chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointOrientation {
    /// Axis horizontal and across the chain: bends up and down.
    Pitch,
    /// Axis vertical: bends sideways.
    Yaw,
    /// Axis along the chain: twists.
    Roll,
}

impl JointOrientation {
    /// `P`, `Y` or `R`, as in topology strings.
    pub fn letter(self) -> char {
        match self {
            JointOrientation::Pitch => 'P',
            JointOrientation::Yaw => 'Y',
            JointOrientation::Roll => 'R',
        }
    }
}

impl fmt::Display for JointOrientation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            JointOrientation::Pitch => "pitch",
            JointOrientation::Yaw => "yaw",
            JointOrientation::Roll => "roll",
        })
    }
}

/// One rigid link of the robot.
#[derive(Debug, Clone, PartialEq)]
pub struct Link {
    /// The link's (body's) name.
    pub name: String,
    /// Pose in the robot frame.
    pub pose: Pose,
    /// Its geometries.
    pub geoms: Vec<Geom>,
    /// kg.
    pub mass: f64,
    /// True when the file gave no mass and it was computed from the geometry.
    pub mass_from_geometry: bool,
    /// Fixed to the world (`<Body type="static">`: a fixed base such as an arm's, the
    /// root of the robot's tree only).
    pub fixed: bool,
    /// Centre of mass and inertia tensor when the file gives them (else the mass is
    /// spread over the geometry).
    pub inertia: Option<LinkInertia>,
}

/// A link's given centre of mass and inertia, in the link frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkInertia {
    /// Centre of mass (m).
    pub com: [f64; 3],
    /// Inertia tensor about the centre of mass (kg·m², row-major 3x3).
    pub tensor: [f64; 9],
}

impl Link {
    /// Centre of the link's geometry in the robot frame.
    pub fn centre(&self) -> [f64; 3] {
        if self.geoms.is_empty() {
            return self.pose.translation;
        }
        let mut c = [0.0; 3];
        for g in &self.geoms {
            let p = self.pose.mul(&g.pose).translation;
            for i in 0..3 {
                c[i] += p[i] / self.geoms.len() as f64;
            }
        }
        c
    }
}

/// One servo-driven hinge.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotJoint {
    /// The joint's name.
    pub name: String,
    /// The link on the tail side.
    pub parent: usize,
    /// The link on the head side.
    pub child: usize,
    /// Anchor point in the robot frame.
    pub anchor: [f64; 3],
    /// Unit axis in the robot frame.
    pub axis: [f64; 3],
    /// Angle limits (degrees).
    pub limits_deg: [f64; 2],
    /// Servo torque limit (N·m).
    pub max_torque: f64,
    /// Servo speed limit (rad/s).
    pub max_vel: f64,
    /// Servo gain (1/s) when the file sets one.
    pub servo_gain: Option<f64>,
    /// The angle error (degrees) the servo leaves uncorrected (0: none).
    pub dead_band_deg: f64,
    /// How long (s) a goal takes to reach the servo (0: at once).
    pub latency_s: f64,
    /// Pitch, yaw or roll, from its axis.
    pub orientation: JointOrientation,
}

/// One sensor on a link.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSensor {
    /// The sensor's name.
    pub name: String,
    /// The link it sits on.
    pub link: usize,
    /// Pose in the link frame.
    pub pose: Pose,
    /// What it is.
    pub sensor: Sensor,
}

/// A robot ready to be simulated.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotModel {
    /// The robot's name.
    pub name: String,
    /// The robot file.
    pub file: PathBuf,
    /// Its links, in file order.
    pub links: Vec<Link>,
    /// Its joints, tail to head.
    pub joints: Vec<RobotJoint>,
    /// Its sensors.
    pub sensors: Vec<RobotSensor>,
    /// Every file read to build it (robot, parts, sensors, meshes).
    pub files: Vec<PathBuf>,
    /// The real robot's servos, one per joint in joint order.
    pub servos: ServoMap,
    /// The meshes its `trimesh` geometries name, parsed.
    pub meshes: Meshes,
}

/// The real robot's servo of one joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointServo {
    /// Bus id.
    pub id: u8,
    /// Servo angle (degrees) with the joint straight.
    pub offset: f64,
    /// +1 or −1.
    pub direction: f64,
}

impl JointServo {
    /// The servo angle (degrees) that puts the joint at `joint_deg`.
    pub fn servo_angle(&self, joint_deg: f64) -> f64 {
        self.direction * joint_deg + self.offset
    }

    /// The joint angle (degrees) of a servo angle.
    pub fn joint_angle(&self, servo_deg: f64) -> f64 {
        self.direction * (servo_deg - self.offset)
    }
}

/// The bus settings and the servo of every joint.
#[derive(Debug, Clone, PartialEq)]
pub struct ServoMap {
    /// The servo driver (`dynamixel`).
    pub driver: String,
    /// Bus speed (baud).
    pub baud: u32,
    /// Read positions, currents and speeds back every this many control steps.
    pub read_every: u32,
    /// One per robot joint, in joint order.
    pub joints: Vec<JointServo>,
}

impl ServoMap {
    /// Ids 1..=n in joint order, offset 0, direction 1, the default bus.
    pub fn default_for(joints: usize) -> ServoMap {
        ServoMap {
            driver: crate::config::servos::DRIVERS[0].to_string(),
            baud: crate::config::servos::DEFAULT_BAUD,
            read_every: crate::config::servos::DEFAULT_READ_EVERY,
            joints: (0..joints)
                .map(|j| JointServo {
                    id: (j + 1).min(252) as u8,
                    offset: 0.0,
                    direction: 1.0,
                })
                .collect(),
        }
    }
}

/// The servo map of a robot file's `<Servos>` against its joints.
fn resolve_servos(path: &Path, file: &RobotFile, joints: &[RobotJoint]) -> ConfigResult<ServoMap> {
    let Some(section) = &file.servos else {
        return Ok(ServoMap::default_for(joints.len()));
    };
    let r = Reader::new(path);
    let mut mapped: Vec<Option<JointServo>> = vec![None; joints.len()];
    let mut ids = Vec::new();
    for s in &section.servos {
        let j = joints
            .iter()
            .position(|j| j.name.eq_ignore_ascii_case(&s.joint))
            .ok_or_else(|| {
                let names: Vec<&str> = joints.iter().map(|j| j.name.as_str()).collect();
                r.err(
                    s.pos,
                    ErrorKind::UnknownReference,
                    format!(
                        "<Servo joint=\"{}\">: the robot has no such joint; its joints: {}",
                        s.joint,
                        names.join(", ")
                    ),
                )
            })?;
        if mapped[j].is_some() {
            return Err(r.err(
                s.pos,
                ErrorKind::InvalidValue,
                format!("joint {} has two servos", s.joint),
            ));
        }
        if ids.contains(&s.id) {
            return Err(r.err(
                s.pos,
                ErrorKind::InvalidValue,
                format!("servo id {} is used twice", s.id),
            ));
        }
        ids.push(s.id);
        mapped[j] = Some(JointServo {
            id: s.id,
            offset: s.offset,
            direction: f64::from(s.direction),
        });
    }
    let missing: Vec<&str> = joints
        .iter()
        .zip(&mapped)
        .filter(|(_, m)| m.is_none())
        .map(|(j, _)| j.name.as_str())
        .collect();
    if !missing.is_empty() {
        return Err(r.err(
            section.pos,
            ErrorKind::Missing,
            format!(
                "<Servos> gives no servo for joint(s) {}",
                missing.join(", ")
            ),
        ));
    }
    Ok(ServoMap {
        driver: section.driver.clone(),
        baud: section.baud,
        read_every: section.read_every,
        joints: mapped.into_iter().flatten().collect(),
    })
}

impl RobotModel {
    /// `PYPYP`-style letters, one per joint.
    pub fn pattern(&self) -> String {
        self.joints.iter().map(|j| j.orientation.letter()).collect()
    }

    /// The sum of the links' masses (kg).
    pub fn total_mass(&self) -> f64 {
        self.links.iter().map(|l| l.mass).sum()
    }

    /// The index of the joint named `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
}

/// Volume of a geometry (m³), for default masses.
pub fn geom_volume(g: &Geom) -> f64 {
    match &g.shape {
        Shape::Box { extents: [x, y, z] } => 8.0 * x * y * z,
        Shape::Sphere { radius } => 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3),
        Shape::Cylinder { radius, height } => std::f64::consts::PI * radius * radius * height,
        // A mesh's volume is not computed; 1 cm³ keeps the body simulable.
        Shape::Trimesh { .. } => 1e-6,
    }
}

/// `v` as a unit vector; scaled by its largest component first, so that an axis written
/// with huge components (`-3.6e250 -0.2 -0.5`, whose squared length overflows) keeps its
/// direction instead of becoming zero. The reader refuses a zero axis before.
fn normalize(v: [f64; 3]) -> [f64; 3] {
    let m = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let v = v.map(|x| x / m);
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / n)
}

fn classify(axis: [f64; 3], chain: [f64; 3]) -> JointOrientation {
    let chain_len = (chain[0] * chain[0] + chain[1] * chain[1] + chain[2] * chain[2]).sqrt();
    if axis[2].abs() > 0.7 {
        JointOrientation::Yaw
    } else if chain_len > 1e-9
        && (axis[0] * chain[0] + axis[1] * chain[1] + axis[2] * chain[2]).abs() / chain_len > 0.7
    {
        JointOrientation::Roll
    } else {
        JointOrientation::Pitch
    }
}

/// Builds the robot model from a parsed robot file at `path`.
pub fn resolve_robot(
    src: &dyn FileSource,
    path: &Path,
    file: &RobotFile,
) -> ConfigResult<RobotModel> {
    let mut fl = Flattener::new(src, path);
    fl.out.files.push(path.to_path_buf());
    fl.add(&file.kinbody, path, "", &Pose::IDENTITY)?;
    let Flat {
        bodies,
        joints: placed_joints,
        sensors: mut placed_sensors,
        mut files,
        meshes,
    } = fl.out;
    if bodies.is_empty() {
        return Err(ConfigError::new(
            path,
            file.pos,
            ErrorKind::Missing,
            "the robot has no <Body>",
        ));
    }
    if let Some(e) = ConfigError::all(physical::robot_faults(path, file, &bodies, &placed_joints)) {
        return Err(e);
    }
    let links: Vec<Link> = bodies.iter().map(link_of).collect();
    let names = BodyNames(links.iter().map(|l| l.name.as_str()).collect());
    let joints = resolve_joints(&placed_joints, &links, &names)?;
    for s in &file.sensors {
        placed_sensors.push(crate::config::resolve::flatten::PlacedSensor {
            sensor: s.clone(),
            file: path.to_path_buf(),
        });
    }
    let sensors = resolve_sensors(src, &placed_sensors, &names, &mut files)?;
    files.sort();
    files.dedup();
    let servos = resolve_servos(path, file, &joints)?;
    Ok(RobotModel {
        name: file.name.clone(),
        file: path.to_path_buf(),
        links,
        joints,
        sensors,
        files,
        servos,
        meshes,
    })
}

/// A placed body as a link; without a `<Mass>`, its mass comes from its geometry.
fn link_of(pb: &PlacedBody) -> Link {
    let (mass, from_geom) = match &pb.body.mass {
        Some(m) => (m.total, false),
        None => (
            pb.body.geoms.iter().map(geom_volume).sum::<f64>().max(1e-6) * DEFAULT_DENSITY,
            true,
        ),
    };
    let inertia = pb.body.mass.as_ref().and_then(|m| {
        m.inertia.map(|tensor| LinkInertia {
            com: m.com.unwrap_or([0.0; 3]),
            tensor,
        })
    });
    Link {
        name: pb.body.name.clone(),
        pose: pb.world,
        geoms: pb.body.geoms.clone(),
        mass,
        mass_from_geometry: from_geom,
        fixed: pb.body.kind == BodyKind::Static,
        inertia,
    }
}

/// The robot's body names, in link order, for references by name.
struct BodyNames<'a>(Vec<&'a str>);

impl BodyNames<'_> {
    /// The link named `name`; the error (at `file`, `pos`) lists the bodies.
    fn find(&self, name: &str, file: &Path, pos: Pos, what: &str) -> ConfigResult<usize> {
        self.0.iter().position(|n| *n == name).ok_or_else(|| {
            ConfigError::new(
                file,
                pos,
                ErrorKind::UnknownReference,
                format!(
                    "{what} names body \"{name}\", which the robot does not have; bodies: {}",
                    self.0.join(", ")
                ),
            )
        })
    }
}

/// The hinges between links: parent and child by name, anchor and axis in the robot's
/// frame, limits and servo settings with their defaults, pitch / yaw from the axis.
fn resolve_joints(
    placed: &[PlacedJoint],
    links: &[Link],
    names: &BodyNames<'_>,
) -> ConfigResult<Vec<RobotJoint>> {
    let mut joints = Vec::with_capacity(placed.len());
    for pj in placed {
        let j = &pj.joint;
        let what = format!("joint {}", j.name);
        let fail = |message: String| {
            Err(ConfigError::new(
                &pj.file,
                j.pos,
                ErrorKind::InvalidValue,
                message,
            ))
        };
        if joints.iter().any(|o: &RobotJoint| o.name == j.name) {
            return fail(format!("joint name \"{}\" is used twice", j.name));
        }
        let parent = names.find(&j.bodies[0], &pj.file, j.pos, &what)?;
        let child = names.find(&j.bodies[1], &pj.file, j.pos, &what)?;
        if parent == child {
            return fail(format!("{what} joins body \"{}\" to itself", j.bodies[0]));
        }
        let frame = match &j.offset_from {
            Some(o) => links[names.find(o, &pj.file, j.pos, &format!("{what} <offsetfrom>"))?].pose,
            None => links[parent].pose,
        };
        let anchor = frame.mul(&Pose::from_translation(j.anchor)).translation;
        let axis = normalize(frame.rotate(normalize(j.axis)));
        let chain = {
            let (a, b) = (links[parent].centre(), links[child].centre());
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
        };
        joints.push(RobotJoint {
            name: j.name.clone(),
            parent,
            child,
            anchor,
            axis,
            limits_deg: j.limits_deg.unwrap_or(DEFAULT_LIMITS_DEG),
            max_torque: j.max_torque.unwrap_or(DEFAULT_MAX_TORQUE),
            max_vel: j.max_vel.unwrap_or(DEFAULT_MAX_VEL),
            servo_gain: j.servo_gain,
            dead_band_deg: j.servo_dead_band.unwrap_or(0.0),
            latency_s: j.servo_latency.unwrap_or(0.0),
            orientation: classify(axis, chain),
        });
    }
    Ok(joints)
}

/// The sensors on links, inline or read from their files (added to `files`).
fn resolve_sensors(
    src: &dyn FileSource,
    placed: &[PlacedSensor],
    names: &BodyNames<'_>,
    files: &mut Vec<PathBuf>,
) -> ConfigResult<Vec<RobotSensor>> {
    let mut sensors = Vec::with_capacity(placed.len());
    for ps in placed {
        let s = &ps.sensor;
        if sensors.iter().any(|o: &RobotSensor| o.name == s.name) {
            return Err(ConfigError::new(
                &ps.file,
                s.pos,
                ErrorKind::InvalidValue,
                format!("sensor name \"{}\" is used twice", s.name),
            ));
        }
        let link = names.find(&s.link, &ps.file, s.pos, &format!("sensor {}", s.name))?;
        let sensor = match &s.source {
            SensorSource::Inline(sensor) => sensor.clone(),
            SensorSource::File { path: written, pos } => {
                let p = find_file(src, &ps.file, written, *pos, "sensor")?;
                let text = read_file(src, &p, &ps.file, *pos)?;
                files.push(p.clone());
                parse_sensor_file(&p.display().to_string(), &text)
                    .map_err(|e| e.included_from(&ps.file, *pos))?
            }
        };
        sensors.push(RobotSensor {
            name: s.name.clone(),
            link,
            pose: s.pose,
            sensor,
        });
    }
    Ok(sensors)
}
