//! The one door to physics: the [`PhysicsEngine`] interface the step's stages, the runner's
//! typed reads, picking, dragging and drawing use, and the engines behind it.
//!
//! | engine | module | what it is |
//! |---|---|---|
//! | rapier | [`rapier`] | rapier3d, pure Rust, always built; the default |
//! | MuJoCo | [`mujoco`] | MuJoCo 4.0.0's C library, loaded at run time (`libloading`) |
//!
//! An engine is built from a resolved [`Simulation`] ([`build`]) and hands back a
//! [`Layout`]: engine-neutral ids ([`BodyId`], [`JointId`], [`PadId`], [`LaserId`]) of the
//! environment's bodies and of each robot's links, joints, pads and lasers, which the ECS
//! components keep. Every engine type (rapier's handles, MuJoCo's pointers) stays inside
//! its own module; `tests/layering.rs` enforces it.
//!
//! Semantics both engines share (docs/architecture.md, "Two engines behind one interface"): the servo's velocity command is
//! computed by our `Servo` stage and driven by a velocity constraint whose torque is
//! limited to the joint's `maxtorque` (rapier's motor, MuJoCo's hinge friction loss aimed at the command); the
//! contact friction is the smaller of the two surfaces'; links joined by a hinge do not
//! collide; a pad is touched when a contact patch of its link overlaps its area ([`pad`],
//! the engine-neutral test).

pub mod mujoco;
pub mod pad;
pub mod rapier;

use crate::config::Simulation;
use crate::config::simulation::EngineKind;
use crate::config::transform::Pose;
use crate::sim::error::SimError;

pub use mujoco::mjcf::Mjcf;
pub use pad::PadArea;

/// Most robots one world can hold (one collision group each, besides the environment).
pub const MAX_ROBOTS_PER_WORLD: usize = 31;

/// Friction of robot link surfaces; contacts take the smaller of the two coefficients, so
/// the terrain's friction decides unless it is higher than this.
pub const LINK_FRICTION: f64 = 1.0;

/// Friction of geometries that name none, when the environment gives no default.
pub const DEFAULT_FRICTION: f64 = 0.5;

/// Most robots one world of `kind` holds: MuJoCo's collision masks are 32-bit signed, so
/// it holds one robot fewer.
pub fn max_robots(kind: EngineKind) -> usize {
    match kind {
        EngineKind::Rapier => MAX_ROBOTS_PER_WORLD,
        EngineKind::Mujoco => MAX_ROBOTS_PER_WORLD - 1,
    }
}

/// A rigid body of the world (an environment body or a robot link).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub u32);

/// A hinge of a robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct JointId(pub u32);

/// A tactile pad of a robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PadId(pub u32);

/// A 2D laser of a robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LaserId(pub u32);

/// What a joint does now.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct JointReading {
    /// Degrees.
    pub angle: f64,
    /// Degrees per second.
    pub velocity: f64,
    /// Torque the servo motor applied in the last step (N·m).
    pub torque: f64,
}

/// Where a body is and how it moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// The body's frame in the world (m, z up).
    pub pose: Pose,
    /// Its centre of mass in the world (m).
    pub com: [f64; 3],
    /// Linear velocity of the centre of mass (m/s).
    pub linvel: [f64; 3],
    /// Mass (kg); 0 for a static body.
    pub mass: f64,
    /// Principal moments of inertia (kg·m²).
    pub inertia: [f64; 3],
    /// Whether it moves (not part of the static scenery).
    pub dynamic: bool,
}

/// The outline of a collision shape, for the debug view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShapeOutline {
    /// A box with these half extents, at the collider's pose.
    Box([f64; 3]),
    /// A sphere of this radius.
    Sphere(f64),
    /// Anything else, by its world-space bounding box.
    Bounds([f64; 3], [f64; 3]),
}

/// A collider as the debug view draws it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColliderView {
    /// Its pose in the world.
    pub pose: Pose,
    /// Its outline.
    pub shape: ShapeOutline,
    /// On a moving body.
    pub dynamic: bool,
}

/// A contact point as the debug view draws it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactView {
    /// Where (world, m).
    pub point: [f64; 3],
    /// The contact normal (unit).
    pub normal: [f64; 3],
    /// Penetrating (distance <= 0) rather than only predicted.
    pub touching: bool,
    /// How deep the shapes overlap (m; 0 when they only nearly touch).
    pub depth: f64,
    /// The two bodies in contact, where they are ours (a link or an environment body;
    /// `None` for static scenery such as the floor).
    pub bodies: [Option<BodyId>; 2],
    /// Speed (m/s) at which the two surfaces slide over each other at the point: their
    /// relative velocity without its normal part.
    pub slip: f64,
}

/// The part of `v` across `normal` (unit): its length, the tangential speed.
pub fn tangential_speed(v: [f64; 3], normal: [f64; 3]) -> f64 {
    let vn = v[0] * normal[0] + v[1] * normal[1] + v[2] * normal[2];
    let t = [
        v[0] - vn * normal[0],
        v[1] - vn * normal[1],
        v[2] - vn * normal[2],
    ];
    (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt()
}

/// The ids of one robot's parts, in the configuration's order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RobotLayout {
    /// Link bodies with their masses (kg).
    pub links: Vec<(BodyId, f64)>,
    /// Hinges.
    pub joints: Vec<JointId>,
    /// Tactile pads, in the robot's sensor order.
    pub pads: Vec<PadId>,
    /// Lasers, in the robot's sensor order.
    pub lasers: Vec<LaserId>,
}

/// What an engine built.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Layout {
    /// The environment's bodies, in the environment's order.
    pub environment: Vec<BodyId>,
    /// Each robot of the batch.
    pub robots: Vec<RobotLayout>,
}

/// How to build an engine's world.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineBuild {
    /// The engine and its settings.
    pub settings: EngineSettings,
    /// Copies of the robot (1 ..= [`MAX_ROBOTS_PER_WORLD`]).
    pub robots: usize,
}

/// The speed (m/s) above which a simulated body has blown up: no robot link moves at 1 km/s.
pub const MAX_BODY_SPEED: f64 = 1000.0;

/// A physics engine's world, as every stage of the step and every view reaches it. The
/// ids are those of the [`Layout`] the engine was built with; an unknown id reads as
/// zero / nothing.
pub trait PhysicsEngine: Send + Sync + 'static {
    /// Which engine this is.
    fn kind(&self) -> EngineKind;
    /// The world's gravity (m/s², z up).
    fn gravity(&self) -> [f64; 3];
    /// A description of the settings the world runs with (for reports).
    fn settings(&self) -> String;
    /// Advances the world by one simulation step (several engine steps when the settings
    /// refine it).
    fn step(&mut self);
    /// Whether the world blew up and is no longer stepped (rapier's multibody joints, whose
    /// solver panics on a non-finite state, stop before it: [`MAX_BODY_SPEED`]).
    fn diverged(&self) -> bool {
        false
    }
    /// Joint `j`'s angle, speed and last motor torque.
    fn joint(&self, j: JointId) -> JointReading;
    /// Drives joint `j`'s velocity motor at `velocity` (degrees/s) for the next step;
    /// `now` is what [`PhysicsEngine::joint`] read at the step's start.
    fn drive_joint(&mut self, j: JointId, velocity: f64, now: &JointReading);
    /// Body `b`'s centre of mass (world, m): the per-step read of the position sensor.
    fn body_com(&self, b: BodyId) -> [f64; 3];
    /// Everything about body `b`, or `None` for an unknown id.
    fn body(&self, b: BodyId) -> Option<BodyState>;
    /// Pad `p`'s raw contact this step and the summed contact normal (unit, pointing into
    /// the pad's link) of the patches that touch it.
    fn pad_contact(&self, p: PadId) -> (bool, [f64; 3]);
    /// Casts laser `l`'s beams; fills `ranges` (m), the maximum range where nothing is hit.
    fn scan(&self, l: LaserId, ranges: &mut [f64]);
    /// The height (m) of the first surface straight below (x, y) from [`PROBE_FROM`] m up
    /// (a robot there included), or `None` when nothing is below.
    fn height_below(&self, x: f64, y: f64) -> Option<f64>;
    /// Moves body `b` by `delta` (m), keeping its velocity and orientation.
    fn translate_body(&mut self, b: BodyId, delta: [f64; 3]);
    /// Sets body `b`'s angular velocity (rad/s).
    fn set_angular_velocity(&mut self, b: BodyId, angvel: [f64; 3]);
    /// Sets body `b`'s linear velocity (m/s): a launch, for the physical checks.
    fn set_linear_velocity(&mut self, b: BodyId, linvel: [f64; 3]);
    /// Every collider, for the debug view.
    fn colliders(&self) -> Vec<ColliderView>;
    /// Every contact point, for the debug view.
    fn contacts(&self) -> Vec<ContactView>;
}

/// Height (m) a [`PhysicsEngine::height_below`] probe is cast down from.
pub const PROBE_FROM: f64 = 100.0;

/// A laser as the engines cast it: on `body` at `pose`, beams at `angles` (radians, in the
/// sensor's x-y plane, 0 along +y, positive towards -x), up to `max_range` (m).
#[derive(Debug, Clone, PartialEq)]
pub struct LaserSpec {
    /// The robot it belongs to (index in the batch).
    pub robot: usize,
    /// Its link.
    pub body: BodyId,
    /// Its pose on the link.
    pub pose: Pose,
    /// Beam angles (rad).
    pub angles: Vec<f64>,
    /// Range (m).
    pub max_range: f64,
}

impl LaserSpec {
    /// Beam `i`'s direction in the sensor's frame.
    pub fn direction(angle: f64) -> [f64; 3] {
        [-angle.sin(), angle.cos(), 0.0]
    }
}

/// Whether engine `kind` can run here: rapier always; MuJoCo when its library loads (why
/// not, as [`SimError::Mujoco`], otherwise).
pub fn ready(kind: EngineKind) -> Result<(), SimError> {
    match kind {
        EngineKind::Rapier => Ok(()),
        EngineKind::Mujoco => mujoco::library::library()
            .map(|_| ())
            .map_err(SimError::from),
    }
}

/// The engines that can run here, rapier first.
pub fn ready_engines() -> Vec<EngineKind> {
    EngineKind::ALL
        .into_iter()
        .filter(|k| ready(*k).is_ok())
        .collect()
}

/// MuJoCo's model of `sim` as an MJCF document for other tools (`proleg export mjcf`, the
/// rollout baseline): the engine's own mapping of one robot, its servos written as
/// `<position>` actuators (MuJoCo's engine drives them through proleg's servo stage
/// instead).
pub fn mjcf_export(sim: &Simulation) -> Result<Mjcf, SimError> {
    let opts = mujoco::mjcf::MjcfOptions {
        robots: 1,
        servos: mujoco::mjcf::Servos::Position,
        settings: mujoco::MujocoSettings::default(),
    };
    Ok(mujoco::mjcf::mjcf(sim, &opts)?)
}

/// Whether MuJoCo accepts the MJCF file `path`: `Ok(false)` when its library is not
/// installed here (not checked), an error with MuJoCo's message when it refuses the file.
pub fn mjcf_check(path: &std::path::Path) -> Result<bool, SimError> {
    if ready(EngineKind::Mujoco).is_err() {
        return Ok(false);
    }
    mujoco::check_mjcf_file(path)?;
    Ok(true)
}

/// Builds `sim`'s world on the engine `opts` names.
pub fn build(
    sim: &Simulation,
    opts: &EngineBuild,
) -> Result<(Box<dyn PhysicsEngine>, Layout), SimError> {
    let max = max_robots(opts.settings.kind());
    if opts.robots == 0 || opts.robots > max {
        return Err(SimError::TooManyRobots {
            requested: opts.robots,
            max,
        });
    }
    match opts.settings {
        EngineSettings::Rapier(settings) => {
            let (engine, layout) = rapier::RapierEngine::build(sim, opts.robots, settings)?;
            Ok((Box::new(engine), layout))
        }
        EngineSettings::Mujoco(settings) => {
            let (engine, layout) = mujoco::MujocoEngine::build(sim, opts.robots, settings)?;
            Ok((Box::new(engine), layout))
        }
    }
}

/// A sensor of the robot as the engines place it.
#[derive(Debug, Clone, PartialEq)]
pub enum SensorPart {
    /// A tactile pad on link `link`.
    Pad {
        /// The sensor's name (for errors).
        name: String,
        /// Link index.
        link: usize,
        /// Its area on the link.
        area: PadArea,
    },
    /// A 2D laser on link `link`: pose on the link, beam angles (rad), range (m).
    Laser {
        /// Link index.
        link: usize,
        /// Pose on the link.
        pose: Pose,
        /// Beam angles (rad).
        angles: Vec<f64>,
        /// Range (m).
        max_range: f64,
    },
}

/// The robot's sensors as engine parts, in the robot's sensor order.
pub fn sensor_parts(sim: &Simulation) -> Vec<SensorPart> {
    use crate::config::sensor::Sensor;
    sim.robot
        .sensors
        .iter()
        .map(|s| match &s.sensor {
            Sensor::Laser2d(l) => SensorPart::Laser {
                link: s.link,
                pose: s.pose,
                angles: l.beam_angles().iter().map(|a| a.to_radians()).collect(),
                max_range: l.max_range,
            },
            Sensor::Tactile(t) => SensorPart::Pad {
                name: s.name.clone(),
                link: s.link,
                area: PadArea {
                    pose: s.pose,
                    half_extents: t.extents,
                },
            },
        })
        .collect()
}

/// An engine with its settings: what a world is built with ([`EngineBuild`],
/// `BuildOptions::settings`) and what a converged-reference ladder refines. Chosen in one
/// place, [`EngineSettings::of`], from the simulation (its file's engine or `--engine`) and
/// the command line's overrides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EngineSettings {
    /// rapier with these settings.
    Rapier(rapier::PhysicsSettings),
    /// MuJoCo with these settings.
    Mujoco(mujoco::MujocoSettings),
}

/// Settings that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum EngineSettingsError {
    /// rapier's overrides that do not parse.
    #[error("{0}")]
    Rapier(#[from] rapier::SettingsError),
    /// Overrides (rapier's `key=value` list) for a run on another engine.
    #[error("--physics sets rapier's settings; this run is on {0}")]
    NotRapier(EngineKind),
}

impl EngineSettings {
    /// `kind`'s production settings for `sim`'s robot.
    pub fn production(sim: &Simulation, kind: EngineKind) -> EngineSettings {
        match kind {
            EngineKind::Rapier => {
                EngineSettings::Rapier(rapier::PhysicsSettings::production_for(sim))
            }
            EngineKind::Mujoco => EngineSettings::Mujoco(mujoco::MujocoSettings::default()),
        }
    }

    /// The engine `sim` runs on ([`Simulation::engine`]: its file's, or the one
    /// `with_engine` chose) with its production settings and `overrides` (rapier's
    /// `key=value,...`; none on MuJoCo).
    pub fn of(sim: &Simulation, overrides: &str) -> Result<EngineSettings, EngineSettingsError> {
        match EngineSettings::production(sim, sim.engine()) {
            EngineSettings::Rapier(p) => Ok(EngineSettings::Rapier(p.parse_overrides(overrides)?)),
            mujoco if overrides.trim().is_empty() => Ok(mujoco),
            other => Err(EngineSettingsError::NotRapier(other.kind())),
        }
    }

    /// The first rung of the converged reference ladder for these production settings: on
    /// rapier [`rapier::PhysicsSettings::reference`], on MuJoCo two steps per simulation
    /// step with the elliptic cone and more solver iterations
    /// ([`mujoco::MujocoSettings::reference`]).
    pub fn reference(self) -> EngineSettings {
        match self {
            EngineSettings::Rapier(p) => EngineSettings::Rapier(p.reference()),
            EngineSettings::Mujoco(p) => {
                EngineSettings::Mujoco(mujoco::MujocoSettings::reference(2 * p.steps_per_step))
            }
        }
    }

    /// Which engine.
    pub fn kind(&self) -> EngineKind {
        match self {
            EngineSettings::Rapier(_) => EngineKind::Rapier,
            EngineSettings::Mujoco(_) => EngineKind::Mujoco,
        }
    }

    /// The same settings with every simulation step split into `factor` times as many
    /// engine steps.
    pub fn refined(self, factor: u32) -> Self {
        match self {
            EngineSettings::Rapier(s) => EngineSettings::Rapier(s.refined(factor)),
            EngineSettings::Mujoco(s) => EngineSettings::Mujoco(mujoco::MujocoSettings {
                steps_per_step: s.steps_per_step * factor,
                ..s
            }),
        }
    }
}

impl std::fmt::Display for EngineSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EngineSettings::Rapier(s) => write!(f, "{s}"),
            EngineSettings::Mujoco(s) => write!(f, "{s}"),
        }
    }
}
