//! Builds the world of a loaded [`Simulation`]: environment bodies, and one or more copies
//! of the robot (links as rigid bodies with colliders, hinges as revolute joints with
//! limits and servo motors, a control kernel from the actuation file). Every entity gets
//! a `Name`. Robots of a batch share the environment but not each other: each has its own
//! collision group.

use bevy::prelude::*;

use crate::config::Simulation;
use crate::config::sensor::Sensor;
use crate::config::simulation::EngineKind;
use crate::control::kernel::KernelError;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::rng::SimRng;
use crate::sensing::{Debounce, SensorData};
use crate::sim::clock::SimClock;
use crate::sim::energy::Energy;
use crate::sim::engine::{self, BodyId, EngineBuild, EngineSettings, RobotLayout};
use crate::sim::error::{ModuleMismatch, SimError};
use crate::sim::kernel::Kernel;
use crate::sim::laser::Laser2dSensor;
use crate::sim::physics::SimPhysics;
use crate::sim::randomize::{NoisySensors, SensorNoise};
use crate::sim::record::{RecordSettings, Track};
use crate::sim::robot::SimRobot;
use crate::sim::servo::{DEFAULT_SERVO_GAIN, JointState, Servo, SimJoint, TargetDelay};
use crate::sim::tactile::{RobotSensors, SimPad};

pub use crate::sim::engine::{DEFAULT_FRICTION, LINK_FRICTION};

/// How to build the world.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildOptions {
    /// Copies of the robot, each with its own kernel (1 ..= 31).
    pub robots: usize,
    /// Seed of the run (modules' noise, forked per robot).
    pub seed: u64,
    /// Record trajectories (off for throughput runs).
    pub record: bool,
    /// Which engine, with which settings.
    pub engine: EngineChoice,
    /// Noise on what modules read (randomized episodes; none by default).
    pub noise: SensorNoise,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            robots: 1,
            seed: 1,
            record: true,
            engine: EngineChoice::FromFile,
            noise: SensorNoise::default(),
        }
    }
}

/// Salt of the sensor-noise streams (apart from the modules' streams of the same seed).
const NOISE_STREAM: u64 = 0x6e6f_6973_6520_7374;

/// A static or dynamic body of the environment.
#[derive(Component, Debug, Clone)]
pub struct SimEnvObject {
    /// Position among the environment's bodies.
    pub index: usize,
    /// Its body in the physics engine.
    pub body: BodyId,
}

/// A link of a robot.
#[derive(Component, Debug, Clone)]
pub struct SimLink {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index among the robot's links.
    pub index: usize,
    /// Its body in the physics engine.
    pub body: BodyId,
}

/// The loaded configuration the world was built from.
#[derive(Resource, Debug, Clone)]
pub struct LoadedSimulation(pub Simulation);

/// The one answer to "which engine, with which settings" a world is built with.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum EngineChoice {
    /// The engine the simulation file names, with its production settings.
    #[default]
    FromFile,
    /// This engine instead of the file's, with its production settings (`--engine`).
    Production(EngineKind),
    /// An engine with settings other than the production ones (`--physics`, converged
    /// references); the settings name their engine.
    Tuned(EngineSettings),
}

impl From<EngineKind> for EngineChoice {
    fn from(kind: EngineKind) -> Self {
        EngineChoice::Production(kind)
    }
}

/// An engine named for one world (a cross-engine score) or none (the file's).
impl From<Option<EngineKind>> for EngineChoice {
    fn from(kind: Option<EngineKind>) -> Self {
        kind.map_or(EngineChoice::FromFile, EngineChoice::Production)
    }
}

impl From<EngineSettings> for EngineChoice {
    fn from(settings: EngineSettings) -> Self {
        EngineChoice::Tuned(settings)
    }
}

impl EngineChoice {
    /// The engine this choice builds `sim` on.
    pub fn kind_for(&self, sim: &Simulation) -> EngineKind {
        match self {
            EngineChoice::FromFile => sim.files.simulation.properties.engine,
            EngineChoice::Production(kind) => *kind,
            EngineChoice::Tuned(settings) => settings.kind(),
        }
    }

    /// The engine and settings this choice builds `sim` with.
    pub fn settings_for(&self, sim: &Simulation) -> EngineSettings {
        match self {
            EngineChoice::Tuned(settings) => *settings,
            _ => EngineSettings::production(sim, self.kind_for(sim)),
        }
    }
}

/// Builds the world of `sim` into `world` (resources and entities); returns the robots.
/// The engine builds its bodies in a fixed order (environment, then each robot's links and
/// joints), so the trajectory depends only on the configuration.
pub fn build_world(
    world: &mut World,
    sim: &Simulation,
    opts: &BuildOptions,
    registry: &ModuleRegistry,
) -> Result<Vec<Entity>, SimError> {
    let props = &sim.files.simulation.properties;
    let limits: Vec<[f64; 2]> = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let template = ControlKernel::from_actuation(&sim.actuation, registry, limits)?;
    check_modules(sim, &template)?;
    let (physics, layout) = engine::build(
        sim,
        &EngineBuild {
            settings: opts.engine.settings_for(sim),
            robots: opts.robots,
        },
    )?;
    for (index, body) in layout.environment.iter().enumerate() {
        let name = &sim.environment.bodies[index].name;
        world.spawn((
            Name::new(format!("environment: {name}")),
            SimEnvObject { index, body: *body },
        ));
    }
    let mut rng = SimRng::new(opts.seed);
    let mut robots = Vec::with_capacity(opts.robots);
    for (r, parts) in layout.robots.iter().enumerate() {
        let mut kernel = template.clone();
        kernel.reset(&mut rng.fork(r as u64));
        robots.push(spawn_robot(world, sim, opts, r, parts, kernel));
    }
    world.insert_resource(SimClock::new(props.step_width));
    world.insert_resource(RecordSettings {
        enabled: opts.record,
        every: props.accuracy,
    });
    world.insert_resource(SimPhysics { engine: physics });
    world.insert_resource(LoadedSimulation(sim.clone()));
    Ok(robots)
}

/// Refuses, before anything is built, a module that cannot run on the robot's
/// observation (a `Policy` whose network reads another number of inputs), naming the
/// actuation file and the module's line.
pub fn check_modules(sim: &Simulation, kernel: &ControlKernel) -> Result<(), SimError> {
    kernel
        .check_observation(&declared_sensors(sim))
        .map_err(|cause| {
            let pos = match &cause {
                KernelError::Observation { number, .. } => sim
                    .actuation
                    .modules
                    .get(number - 1)
                    .map(|m| m.pos)
                    .unwrap_or_default(),
                _ => Default::default(),
            };
            SimError::Module(Box::new(ModuleMismatch {
                file: sim.actuation.file.clone(),
                pos,
                cause,
            }))
        })
}

/// The robot's sensor readings as its file declares them (pads, each laser's beams),
/// empty: the observation's shape.
fn declared_sensors(sim: &Simulation) -> SensorData {
    let mut pads = 0;
    let mut beams = Vec::new();
    for s in &sim.robot.sensors {
        match &s.sensor {
            Sensor::Laser2d(l) => beams.push(l.beam_angles().len()),
            Sensor::Tactile(_) => pads += 1,
        }
    }
    let mut sensors = SensorData::new(pads, &beams);
    sensors.joint_speeds = vec![0.0; sim.robot.joints.len()];
    sensors
}

/// Robot `r` of the batch: its root entity with kernel, sensors, track and energy, and its
/// links, joints and sensors as children.
fn spawn_robot(
    world: &mut World,
    sim: &Simulation,
    opts: &BuildOptions,
    r: usize,
    parts: &RobotLayout,
    kernel: ControlKernel,
) -> Entity {
    let model = &sim.robot;
    let props = &sim.files.simulation.properties;
    let name = if opts.robots == 1 {
        model.name.clone()
    } else {
        format!("{} #{r}", model.name)
    };
    let robot = world.spawn(Name::new(name)).id();
    let links = parts
        .links
        .iter()
        .enumerate()
        .map(|(index, (body, _))| {
            let name = Name::new(format!("link {}", model.links[index].name));
            let link = SimLink {
                robot,
                index,
                body: *body,
            };
            world.spawn((name, link, ChildOf(robot))).id()
        })
        .collect();
    let joints = spawn_joints(world, sim, robot, parts);
    let sensors = spawn_sensors(world, sim, robot, parts);
    let samples =
        (props.duration / props.step_width / props.accuracy.max(1) as f64).ceil() as usize + 1;
    let n = model.joints.len();
    world.entity_mut(robot).insert((
        SimRobot {
            index: r,
            joints,
            links,
            bodies: parts.links.clone(),
            measured: vec![0.0; n],
        },
        Kernel(kernel),
        RobotSensors(sensors),
        Track::with_capacity(n, if opts.record { samples } else { 0 }),
        Energy::default(),
    ));
    if opts.noise.is_active() {
        world.entity_mut(robot).insert(NoisySensors {
            noise: opts.noise,
            rng: SimRng::new(opts.seed ^ NOISE_STREAM).fork(r as u64),
        });
    }
    robot
}

/// The hinges, each an entity with its servo and joint state.
fn spawn_joints(
    world: &mut World,
    sim: &Simulation,
    robot: Entity,
    parts: &RobotLayout,
) -> Vec<Entity> {
    sim.robot
        .joints
        .iter()
        .zip(&parts.joints)
        .enumerate()
        .map(|(index, (j, id))| {
            let joint = SimJoint {
                robot,
                index,
                id: *id,
            };
            let servo = Servo {
                target: 0.0,
                gain: j.servo_gain.unwrap_or(DEFAULT_SERVO_GAIN),
                max_torque: j.max_torque,
                max_velocity: j.max_vel,
                limits_deg: j.limits_deg,
                dead_band: j.dead_band_deg,
                delay: TargetDelay::new(
                    j.latency_s,
                    sim.files.simulation.properties.step_width,
                    0.0,
                ),
            };
            let name = Name::new(format!("joint {}", j.name));
            world
                .spawn((name, joint, servo, JointState::default(), ChildOf(robot)))
                .id()
        })
        .collect()
}

/// Lasers and tactile pads as entities; returns the robot's empty sensor readings, sized
/// for them.
fn spawn_sensors(
    world: &mut World,
    sim: &Simulation,
    robot: Entity,
    parts: &RobotLayout,
) -> SensorData {
    let step_width = sim.files.simulation.properties.step_width;
    let (mut pads, mut lasers) = (parts.pads.iter().enumerate(), parts.lasers.iter());
    let mut beams = Vec::new();
    for s in &sim.robot.sensors {
        let name = Name::new(format!("sensor {}", s.name));
        let (body, _) = parts.links[s.link];
        match &s.sensor {
            Sensor::Laser2d(l) => {
                let Some(id) = lasers.next() else {
                    continue;
                };
                beams.push(l.beam_angles().len());
                let laser = Laser2dSensor {
                    robot,
                    index: beams.len() - 1,
                    laser: *id,
                    max_range: l.max_range,
                    period: (l.scan_time / step_width).round().max(1.0) as u64,
                };
                world.spawn((name, laser, ChildOf(robot)));
            }
            Sensor::Tactile(t) => {
                let Some((index, id)) = pads.next() else {
                    continue;
                };
                let sensor = SimPad {
                    robot,
                    index,
                    pad: *id,
                    link: body,
                    area: engine::PadArea {
                        pose: s.pose,
                        half_extents: t.extents,
                    },
                    debounce_steps: t.debounce,
                    state: Debounce::default(),
                    raw: false,
                };
                world.spawn((name, sensor, ChildOf(robot)));
            }
        }
    }
    let mut sensors = SensorData::new(parts.pads.len(), &beams);
    sensors.joint_speeds = vec![0.0; sim.robot.joints.len()];
    sensors
}
