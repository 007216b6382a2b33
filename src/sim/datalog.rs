//! Data handlers in the world (thesis 4.3.2, 5.5.2): one per actuation module (its
//! internal-data series), one per sensor type (tactile, laser) and `Robot_Data` (B.8's
//! robot series plus mechanical power and energy used, read from [`Energy`]). Every `every`-th step each
//! handler's frame goes into its ring buffer (live views) and, for the robot that stores
//! data, into the round being gathered, which is handed to the background writer every
//! `round_frames` samples. Buffers are allocated once; the step never touches the disk.

use bevy::prelude::*;

use crate::control::ControlKernel;
use crate::data::store::DataStore;
use crate::data::write::HandlerFrames;
use crate::data::{FrameMeta, HandlerSpec, RingBuffer};
use crate::measure::{ground_distance, norm, potential_energy};
use crate::sensing::SensorData;
use crate::sim::clock::SimClock;
use crate::sim::energy::Energy;
use crate::sim::kernel::Kernel;
use crate::sim::physics::SimPhysics;
use crate::sim::record::centre_of_mass;
use crate::sim::robot::SimRobot;
use crate::sim::servo::JointState;
use crate::sim::tactile::RobotSensors;

/// The robot handler's scalar series, then its per-joint series.
pub const ROBOT_SCALARS: [&str; 11] = [
    "speed",
    "x_pos",
    "y_pos",
    "z_pos",
    "alpha",
    "beta",
    "gamma",
    "potential_energy",
    "average_com_speed",
    "power",
    "energy",
];
/// The robot handler's per-joint series.
pub const ROBOT_JOINT_SERIES: [&str; 4] = [
    "desired_joint_positions",
    "real_joint_positions",
    "servo_currents",
    "servo_speeds",
];
/// The name of the robot handler (B.8).
pub const ROBOT_HANDLER: &str = "Robot_Data";

/// One `Robot_Data` frame: [`ROBOT_SCALARS`], then each of [`ROBOT_JOINT_SERIES`] over the
/// joints. The one place its layout is written, for simulated and real robots alike; each
/// per-joint part is any iterator of numbers, so writing a frame allocates nothing.
pub struct RobotFrame<D, A, C, S> {
    /// The scalar series, in [`ROBOT_SCALARS`]'s order (zeros where a real robot has no
    /// ground truth).
    pub scalars: [f64; ROBOT_SCALARS.len()],
    /// The kernel's desired joint angles.
    pub desired: D,
    /// The measured joint angles.
    pub angles: A,
    /// Servo currents (a real robot) or torques (the simulation).
    pub currents: C,
    /// Servo speeds.
    pub speeds: S,
}

impl<D, A, C, S> RobotFrame<D, A, C, S>
where
    D: IntoIterator<Item = f64>,
    A: IntoIterator<Item = f64>,
    C: IntoIterator<Item = f64>,
    S: IntoIterator<Item = f64>,
{
    /// Appends the frame to `out`.
    pub fn append_to(self, out: &mut Vec<f64>) {
        out.extend_from_slice(&self.scalars);
        out.extend(self.desired);
        out.extend(self.angles);
        out.extend(self.currents);
        out.extend(self.speeds);
    }
}

/// How data is sampled and kept.
#[derive(Resource, Debug, Clone, Copy, PartialEq)]
pub struct DataSettings {
    /// Sample every this many steps (the simulation file's `accuracy`).
    pub every: u32,
    /// Frames each ring buffer keeps.
    pub ring_frames: usize,
    /// Samples per round handed to the writer.
    pub round_frames: usize,
}

impl Default for DataSettings {
    fn default() -> Self {
        DataSettings {
            every: 1,
            ring_frames: 4096,
            round_frames: 500,
        }
    }
}

/// The data file robot 0 records into (absent: nothing is stored).
#[derive(Resource)]
pub struct DataSink {
    /// The data file's background writer.
    pub store: DataStore,
    /// Rounds handed to the writer so far.
    pub rounds_sent: u64,
    /// The first error of the writer, if any (later rounds are dropped).
    pub error: Option<crate::data::store::DataStoreError>,
}

/// A robot's data handlers and their buffers.
#[derive(Component, Debug, Clone)]
pub struct DataLog {
    /// The handlers, in file order.
    pub handlers: Vec<HandlerSpec>,
    /// One ring buffer per handler (live views).
    pub rings: Vec<RingBuffer>,
    frame: Vec<Vec<f64>>,
    round: Vec<HandlerFrames>,
    samples: u64,
    start_com: Option<[f64; 3]>,
    start_time: f64,
    total_mass: f64,
}

/// The handlers of a robot with this kernel and these sensors.
pub fn handlers_for(kernel: &ControlKernel, sensors: &SensorData) -> Vec<HandlerSpec> {
    let mut out: Vec<HandlerSpec> = Vec::new();
    for a in kernel.actuators() {
        let d = a.module.internal_data();
        let base = a.module.descriptor().type_name;
        let same = out
            .iter()
            .filter(|h| h.name == base || h.name.starts_with(&format!("{base}.")))
            .count();
        let name = if same == 0 {
            base.to_string()
        } else {
            format!("{base}.{}", same + 1)
        };
        out.push(HandlerSpec {
            name,
            series: d.names().iter().map(|s| s.to_string()).collect(),
            parts: vec![a.joints.len(); d.names().len()],
        });
    }
    if !sensors.tactile.is_empty() {
        out.push(HandlerSpec::uniform(
            "tactile",
            &["pressed", "x-normals", "y-normals", "z-normals"],
            sensors.tactile.len(),
        ));
    }
    let beams: usize = sensors.laser.iter().map(Vec::len).sum();
    if beams > 0 {
        out.push(HandlerSpec::uniform("laser2d", &["range"], beams));
    }
    let joints = kernel.joints();
    let mut robot = HandlerSpec::uniform(ROBOT_HANDLER, &ROBOT_SCALARS, 1);
    for s in ROBOT_JOINT_SERIES {
        robot.series.push(s.to_string());
        robot.parts.push(joints);
    }
    out.push(robot);
    out
}

impl DataLog {
    /// Buffers for `handlers`, allocated once; `total_mass` (kg) is the robot's.
    pub fn new(handlers: Vec<HandlerSpec>, settings: &DataSettings, total_mass: f64) -> Self {
        let rings = handlers
            .iter()
            .map(|h| RingBuffer::new(h.width(), settings.ring_frames))
            .collect();
        let frame = handlers
            .iter()
            .map(|h| Vec::with_capacity(h.width()))
            .collect();
        let round = handlers
            .iter()
            .map(|h| HandlerFrames {
                meta: Vec::with_capacity(settings.round_frames),
                values: Vec::with_capacity(settings.round_frames * h.width()),
            })
            .collect();
        DataLog {
            handlers,
            rings,
            frame,
            round,
            samples: 0,
            start_com: None,
            start_time: 0.0,
            total_mass,
        }
    }

    /// The ring buffer of handler `name`.
    pub fn ring(&self, name: &str) -> Option<&RingBuffer> {
        self.handlers
            .iter()
            .position(|h| h.name == name)
            .map(|i| &self.rings[i])
    }

    /// Samples taken so far.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Takes the gathered round (for the writer), leaving empty buffers of the same size.
    fn take_round(&mut self) -> Vec<HandlerFrames> {
        self.round
            .iter_mut()
            .map(|f| {
                let (m, v) = (f.meta.capacity(), f.values.capacity());
                HandlerFrames {
                    meta: std::mem::replace(&mut f.meta, Vec::with_capacity(m)),
                    values: std::mem::replace(&mut f.values, Vec::with_capacity(v)),
                }
            })
            .collect()
    }
}

/// Roll (alpha), pitch (beta) and yaw (gamma) of a rotation, degrees.
fn euler(q: [f64; 4]) -> [f64; 3] {
    let [x, y, z, w] = q;
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    [roll.to_degrees(), pitch.to_degrees(), yaw.to_degrees()]
}

/// Samples every handler every `every` steps (the `Record` set, after the energy).
pub fn log_data(
    settings: Res<DataSettings>,
    clock: Res<SimClock>,
    physics: Res<SimPhysics>,
    mut sink: Option<ResMut<DataSink>>,
    mut robots: Query<(&SimRobot, &Kernel, &RobotSensors, &Energy, &mut DataLog)>,
    states: Query<&JointState>,
) {
    if !(clock.step + 1).is_multiple_of(settings.every.max(1) as u64) {
        return;
    }
    let meta_of = |samples| FrameMeta::after_step(samples, clock.step, clock.dt);
    for (robot, kernel, sensors, energy, mut log) in &mut robots {
        let log = &mut *log;
        let meta = meta_of(log.samples);
        let mut h = fill_module_frames(log, &kernel.0);
        h += fill_sensor_frames(log, h, &sensors.0);
        let parts = RobotParts {
            robot,
            kernel: &kernel.0,
            energy,
        };
        fill_robot_frame(log, h, &parts, &physics, &clock, &states);
        let storing = robot.index == 0 && sink.is_some();
        for i in 0..log.handlers.len() {
            log.rings[i].push(meta, &log.frame[i]);
            if storing {
                log.round[i].meta.push(meta);
                log.round[i].values.extend_from_slice(&log.frame[i]);
            }
        }
        log.samples += 1;
        if storing
            && log.round[0].len() >= settings.round_frames.max(1)
            && let Some(sink) = sink.as_mut()
        {
            let round = log.take_round();
            send(sink, round);
        }
    }
}

/// One frame per actuation module: its internal-data series; returns the frames filled.
fn fill_module_frames(log: &mut DataLog, kernel: &ControlKernel) -> usize {
    for (h, a) in kernel.actuators().iter().enumerate() {
        let f = &mut log.frame[h];
        f.clear();
        let d = a.module.internal_data();
        for s in 0..d.names().len() {
            f.extend_from_slice(d.series(s));
        }
    }
    kernel.actuators().len()
}

/// The `tactile` and `laser2d` frames from handler `h` on (those the robot has); returns
/// the frames filled.
fn fill_sensor_frames(log: &mut DataLog, mut h: usize, sensors: &SensorData) -> usize {
    let first = h;
    if !sensors.tactile.is_empty() {
        let f = &mut log.frame[h];
        f.clear();
        f.extend(sensors.tactile.iter().map(|p| if *p { 1.0 } else { 0.0 }));
        for axis in 0..3 {
            f.extend(sensors.tactile_normals.iter().map(|n| n[axis]));
        }
        h += 1;
    }
    if sensors.laser.iter().any(|l| !l.is_empty()) {
        let f = &mut log.frame[h];
        f.clear();
        for l in &sensors.laser {
            f.extend_from_slice(l);
        }
        h += 1;
    }
    h - first
}

/// What `Robot_Data` reads of one robot: the robot, its kernel and its energy.
#[derive(Clone, Copy)]
struct RobotParts<'a> {
    robot: &'a SimRobot,
    kernel: &'a ControlKernel,
    energy: &'a Energy,
}

/// The `Robot_Data` frame (handler `h`): speed, centre of mass, head orientation, potential
/// energy under the world's gravity, average speed, power and energy, then per joint the
/// desired and real angles, torques and speeds.
fn fill_robot_frame(
    log: &mut DataLog,
    h: usize,
    parts: &RobotParts<'_>,
    physics: &SimPhysics,
    clock: &SimClock,
    states: &Query<&JointState>,
) {
    let RobotParts {
        robot,
        kernel,
        energy,
    } = *parts;
    let engine = physics.engine.as_ref();
    let gravity = engine.gravity();
    let com = centre_of_mass(engine, robot);
    let start = *log.start_com.get_or_insert(com);
    if log.samples == 0 {
        log.start_time = clock.time();
    }
    let (mut momentum, mut potential) = ([0.0; 3], 0.0);
    for (b, m) in &robot.bodies {
        if let Some(body) = engine.body(*b) {
            for (p, v) in momentum.iter_mut().zip(body.linvel) {
                *p += m * v;
            }
            potential += potential_energy(*m, body.com, gravity);
        }
    }
    let speed = norm(momentum) / log.total_mass.max(1e-12);
    let head = robot
        .bodies
        .last()
        .and_then(|(b, _)| engine.body(*b))
        .map(|b| {
            let [w, x, y, z] = b.pose.rotation;
            euler([x, y, z, w])
        })
        .unwrap_or_default();
    let elapsed = clock.time() + clock.dt - log.start_time;
    let avg = if elapsed > 0.0 {
        ground_distance(start, com) / elapsed
    } else {
        0.0
    };
    let joint = |e: &Entity| states.get(*e).copied().unwrap_or_default();
    let f = &mut log.frame[h];
    f.clear();
    RobotFrame {
        scalars: [
            speed,
            com[0],
            com[1],
            com[2],
            head[0],
            head[1],
            head[2],
            potential,
            avg,
            energy.power,
            energy.joules,
        ],
        desired: kernel.desired().iter().copied(),
        angles: robot.joints.iter().map(|e| joint(e).angle),
        currents: robot.joints.iter().map(|e| joint(e).torque),
        speeds: robot.joints.iter().map(|e| joint(e).velocity),
    }
    .append_to(f);
}

fn send(sink: &mut DataSink, round: Vec<HandlerFrames>) {
    if sink.error.is_some() {
        return;
    }
    match sink.store.send(round) {
        Ok(()) => sink.rounds_sent += 1,
        Err(e) => sink.error = Some(e),
    }
}

/// Hands robot 0's unsent frames to the writer (before closing the file).
pub fn flush_round(world: &mut World) {
    let mut pending = None;
    let mut q = world.query::<(&SimRobot, &mut DataLog)>();
    for (robot, mut log) in q.iter_mut(world) {
        if robot.index == 0 && !log.round.iter().all(HandlerFrames::is_empty) {
            pending = Some(log.take_round());
        }
    }
    if let (Some(round), Some(mut sink)) = (pending, world.get_resource_mut::<DataSink>()) {
        send(&mut sink, round);
    }
}
