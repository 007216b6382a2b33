//! Builds the world of a loaded [`Simulation`]: environment bodies, and one or more copies
//! of the robot (links as rigid bodies with colliders, hinges as revolute joints with
//! limits and servo motors, a control kernel from the actuation file). Every entity gets
//! a `Name`. Robots of a batch share the environment but not each other: each has its own
//! collision group.

use bevy::prelude::*;
use rapier3d::prelude as rp;

use crate::config::Simulation;
use crate::config::body::{BodyKind, Geom, MeshCollision, Shape};
use crate::config::resolve::robot::{LinkInertia, geom_volume};
use crate::config::sensor::Sensor;
use crate::config::transform::Pose;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::rng::SimRng;
use crate::sensing::{Debounce, SensorData};
use crate::sim::clock::SimClock;
use crate::sim::energy::Energy;
use crate::sim::error::SimError;
use crate::sim::kernel::{Kernel, SimRobot};
use crate::sim::laser::{Laser2dSensor, beam_angles};
use crate::sim::physics::{MAX_ROBOTS_PER_WORLD, SimPhysics, group_bit, pose, vec3};
use crate::sim::physics_settings::PhysicsSettings;
use crate::sim::randomize::{NoisySensors, SensorNoise};
use crate::sim::record::{RecordSettings, Track};
use crate::sim::servo::{DEFAULT_SERVO_GAIN, JointState, MOTOR_DAMPING, Servo, SimJoint};
use crate::sim::tactile::{PadArea, RobotSensors, TactileSensor};
use crate::sim::terrain::{floor_halfspace, heightfield};

/// Friction of robot link surfaces; contacts take the smaller of the two coefficients, so
/// the terrain's friction decides unless it is higher than this.
pub const LINK_FRICTION: f64 = 1.0;
/// Friction of geometries that name none, when the environment gives no default.
pub const DEFAULT_FRICTION: f64 = 0.5;

/// How to build the world.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildOptions {
    /// Copies of the robot, each with its own kernel (1 ..= 31).
    pub robots: usize,
    /// Seed of the run (modules' noise, forked per robot).
    pub seed: u64,
    /// Record trajectories (off for throughput runs).
    pub record: bool,
    /// Physics settings instead of the robot's production ones (converged references,
    /// lever measurements).
    pub physics: Option<PhysicsSettings>,
    /// Noise on what modules read (randomized episodes; none by default).
    pub noise: SensorNoise,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            robots: 1,
            seed: 1,
            record: true,
            physics: None,
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
    /// Its rapier body.
    pub handle: rp::RigidBodyHandle,
}

/// A link of a robot.
#[derive(Component, Debug, Clone)]
pub struct SimLink {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index among the robot's links.
    pub index: usize,
    /// Its rapier body.
    pub handle: rp::RigidBodyHandle,
}

/// The loaded configuration the world was built from.
#[derive(Resource, Debug, Clone)]
pub struct LoadedSimulation(pub Simulation);

/// The rapier shape of a geometry and its placement in the geometry's frame (identity but
/// for height fields); a mesh takes the one parsed at load time. A height field on a body
/// that moves (`fixed` false) collides as its triangles: rapier's height fields have no
/// volume, hence no mass or inertia.
fn shape(g: &Geom, sim: &Simulation, fixed: bool) -> Result<(rp::SharedShape, rp::Pose), SimError> {
    let at_origin = |s| Ok((s, rp::Pose::IDENTITY));
    match &g.shape {
        Shape::Box { extents: [x, y, z] } => {
            at_origin(rp::SharedShape::cuboid(*x as f32, *y as f32, *z as f32))
        }
        Shape::Sphere { radius } => at_origin(rp::SharedShape::ball(*radius as f32)),
        Shape::Cylinder { radius, height } => at_origin(rp::SharedShape::cylinder(
            (height / 2.0) as f32,
            *radius as f32,
        )),
        Shape::Trimesh {
            file,
            scale,
            collision,
        } => {
            let err = |message: String| SimError::Mesh {
                file: file.clone(),
                message,
            };
            let mesh = sim
                .mesh(file)
                .ok_or_else(|| err("not among the meshes the configuration loaded".into()))?;
            match collision {
                MeshCollision::HeightField if fixed => {
                    let map = mesh.height_map().map_err(|why| err(why.into()))?;
                    Ok(heightfield(map, *scale))
                }
                MeshCollision::ConvexHull => {
                    let points: Vec<rp::Vector> = mesh
                        .vertices
                        .iter()
                        .map(|v| vec3(v.map(|c| c * scale)))
                        .collect();
                    let hull = rp::SharedShape::convex_hull(&points).ok_or_else(|| {
                        err("its convex hull is degenerate (flat or empty)".into())
                    })?;
                    at_origin(hull)
                }
                MeshCollision::Triangles | MeshCollision::HeightField => {
                    let vertices = mesh
                        .vertices
                        .iter()
                        .map(|v| vec3(v.map(|c| c * scale)))
                        .collect();
                    let trimesh = rp::SharedShape::trimesh(vertices, mesh.triangles.clone())
                        .map_err(|e| err(format!("{e:?}")))?;
                    at_origin(trimesh)
                }
            }
        }
    }
}

/// Colliders for a body's geometries, its mass split by volume; `fixed` for a static body.
fn colliders(
    sim: &Simulation,
    geoms: &[Geom],
    fixed: bool,
    mass: f64,
    friction: impl Fn(&Geom) -> f64,
    groups: rp::InteractionGroups,
) -> Result<Vec<rp::Collider>, SimError> {
    let volume: f64 = geoms.iter().map(geom_volume).sum::<f64>().max(1e-12);
    geoms
        .iter()
        .map(|g| {
            let (shape, at) = shape(g, sim, fixed)?;
            Ok(rp::ColliderBuilder::new(shape)
                .position(pose(&g.pose) * at)
                .mass((mass * geom_volume(g) / volume) as f32)
                .friction(friction(g) as f32)
                .friction_combine_rule(rp::CoefficientCombineRule::Min)
                .collision_groups(groups)
                .build())
        })
        .collect()
}

/// Builds the world of `sim` into `world` (resources and entities); returns the robots.
/// Bodies are inserted in a fixed order (environment, then each robot's links and joints),
/// so rapier's handles and hence the trajectory depend only on the configuration.
pub fn build_world(
    world: &mut World,
    sim: &Simulation,
    opts: &BuildOptions,
    registry: &ModuleRegistry,
) -> Result<Vec<Entity>, SimError> {
    if opts.robots == 0 || opts.robots > MAX_ROBOTS_PER_WORLD {
        return Err(SimError::TooManyRobots {
            requested: opts.robots,
            max: MAX_ROBOTS_PER_WORLD,
        });
    }
    let props = &sim.files.simulation.properties;
    let settings = opts
        .physics
        .unwrap_or_else(|| PhysicsSettings::for_robot(sim));
    let mut physics = SimPhysics::new(sim.environment.physics.gravity, props.step_width, settings);
    spawn_environment(world, &mut physics, sim, opts.robots)?;
    let limits: Vec<[f64; 2]> = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let template = ControlKernel::from_actuation(&sim.actuation, registry, limits)?;
    let mut rng = SimRng::new(opts.seed);
    let mut robots = Vec::with_capacity(opts.robots);
    for r in 0..opts.robots {
        let mut kernel = template.clone();
        kernel.reset(&mut rng.fork(r as u64));
        robots.push(spawn_robot(world, &mut physics, sim, opts, r, kernel)?);
    }
    world.insert_resource(SimClock::new(props.step_width));
    world.insert_resource(RecordSettings {
        enabled: opts.record,
        every: props.accuracy,
    });
    world.insert_resource(physics);
    world.insert_resource(LoadedSimulation(sim.clone()));
    Ok(robots)
}

/// The environment's bodies, shared by every robot of the batch (collision group 0).
fn spawn_environment(
    world: &mut World,
    physics: &mut SimPhysics,
    sim: &Simulation,
    robots: usize,
) -> Result<(), SimError> {
    let env = &sim.environment;
    let all_robots = (1..=robots as u32).fold(rp::Group::empty(), |g, i| g | group_bit(i));
    let env_groups = rp::InteractionGroups::new(
        group_bit(0),
        all_robots | group_bit(0),
        rp::InteractionTestMode::And,
    );
    let default_friction = env.physics.default_friction.unwrap_or(DEFAULT_FRICTION);
    for (index, b) in env.bodies.iter().enumerate() {
        let builder = match b.kind {
            BodyKind::Static => rp::RigidBodyBuilder::fixed(),
            BodyKind::Dynamic => rp::RigidBodyBuilder::dynamic().can_sleep(false),
        };
        let handle = physics.world.bodies.insert(builder.pose(pose(&b.pose)));
        let friction = |g: &Geom| g.friction.unwrap_or(default_friction);
        let fixed = b.kind == BodyKind::Static;
        let mut cs = colliders(sim, &b.geoms, fixed, b.mass, friction, env_groups)?;
        if b.kind == BodyKind::Static && physics.settings.halfspace_floor {
            for (c, g) in cs.iter_mut().zip(&b.geoms) {
                if let Some((floor, at)) = floor_halfspace(&b.pose, g) {
                    c.set_shape(floor);
                    c.set_position_wrt_parent(at);
                }
            }
        }
        for c in cs {
            let w = &mut physics.world;
            w.colliders.insert_with_parent(c, handle, &mut w.bodies);
        }
        world.spawn((
            Name::new(format!("environment: {}", b.name)),
            SimEnvObject { index, handle },
        ));
    }
    Ok(())
}

/// Robot `r` of the batch: its root entity with kernel, sensors, track and energy, and its
/// links, joints and sensors as children.
fn spawn_robot(
    world: &mut World,
    physics: &mut SimPhysics,
    sim: &Simulation,
    opts: &BuildOptions,
    r: usize,
    kernel: ControlKernel,
) -> Result<Entity, SimError> {
    let model = &sim.robot;
    let props = &sim.files.simulation.properties;
    let group = group_bit(r as u32 + 1);
    let filter = if sim.environment.physics.self_collision {
        group | group_bit(0)
    } else {
        group_bit(0)
    };
    let groups = rp::InteractionGroups::new(group, filter, rp::InteractionTestMode::And);
    let name = if opts.robots == 1 {
        model.name.clone()
    } else {
        format!("{} #{r}", model.name)
    };
    let robot = world.spawn(Name::new(name)).id();
    let (links, bodies) = spawn_links(world, physics, sim, robot, groups)?;
    let joints = spawn_joints(world, physics, sim, robot, &bodies);
    let sensors = spawn_sensors(world, physics, sim, robot, &bodies, groups)?;
    let samples =
        (props.duration / props.step_width / props.accuracy.max(1) as f64).ceil() as usize + 1;
    let n = model.joints.len();
    world.entity_mut(robot).insert((
        SimRobot {
            index: r,
            joints,
            links,
            bodies,
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
    Ok(robot)
}

/// Link bodies and colliders at the environment's robot pose; returns the link entities and
/// the bodies with their masses.
#[allow(clippy::type_complexity)]
fn spawn_links(
    world: &mut World,
    physics: &mut SimPhysics,
    sim: &Simulation,
    robot: Entity,
    groups: rp::InteractionGroups,
) -> Result<(Vec<Entity>, Vec<(rp::RigidBodyHandle, f64)>), SimError> {
    let start = &sim.environment.robot_pose;
    let mut entities = Vec::with_capacity(sim.robot.links.len());
    let mut bodies = Vec::with_capacity(sim.robot.links.len());
    for (i, l) in sim.robot.links.iter().enumerate() {
        let p = start.mul(&l.pose);
        let mut body = rp::RigidBodyBuilder::dynamic()
            .pose(pose(&p))
            .can_sleep(false);
        // A link with its inertia given carries it on the body; its colliders add none.
        let collider_mass = match &l.inertia {
            Some(i) => {
                body = body.additional_mass_properties(mass_properties(l.mass, i));
                0.0
            }
            None => l.mass,
        };
        let handle = physics.world.bodies.insert(body);
        for c in colliders(
            sim,
            &l.geoms,
            false,
            collider_mass,
            |_| LINK_FRICTION,
            groups,
        )? {
            let w = &mut physics.world;
            w.colliders.insert_with_parent(c, handle, &mut w.bodies);
        }
        bodies.push((handle, l.mass));
        let link = SimLink {
            robot,
            index: i,
            handle,
        };
        let name = Name::new(format!("link {}", l.name));
        entities.push(world.spawn((name, link, ChildOf(robot))).id());
    }
    Ok((entities, bodies))
}

/// Rapier's mass properties of a link's given mass, centre of mass and inertia tensor.
fn mass_properties(mass: f64, i: &LinkInertia) -> rp::MassProperties {
    let m = i.tensor.map(|v| v as f32);
    let matrix = rp::Matrix::from_cols(
        rp::Vector::new(m[0], m[3], m[6]),
        rp::Vector::new(m[1], m[4], m[7]),
        rp::Vector::new(m[2], m[5], m[8]),
    );
    rp::MassProperties::with_inertia_matrix(vec3(i.com), mass as f32, matrix)
}

/// The hinges: revolute impulse joints with limits and a force-based velocity motor, each
/// an entity with its servo and joint state.
fn spawn_joints(
    world: &mut World,
    physics: &mut SimPhysics,
    sim: &Simulation,
    robot: Entity,
    bodies: &[(rp::RigidBodyHandle, f64)],
) -> Vec<Entity> {
    let start = &sim.environment.robot_pose;
    let mut entities = Vec::with_capacity(sim.robot.joints.len());
    for (i, j) in sim.robot.joints.iter().enumerate() {
        let (ph, _) = bodies[j.parent];
        let (ch, _) = bodies[j.child];
        let w = &mut physics.world;
        let (pp, cp) = (*w.bodies[ph].position(), *w.bodies[ch].position());
        let anchor = start.mul(&Pose::from_translation(j.anchor)).translation;
        let (a, n) = (vec3(anchor), vec3(start.rotate(j.axis)).normalize());
        let local_axis1 = pp.rotation.inverse() * n;
        let data = rp::GenericJointBuilder::new(rp::JointAxesMask::LOCKED_REVOLUTE_AXES)
            .local_anchor1(pp.inverse_transform_point(a))
            .local_anchor2(cp.inverse_transform_point(a))
            .local_axis1(local_axis1)
            .local_axis2(cp.rotation.inverse() * n)
            .limits(
                rp::JointAxis::AngX,
                [
                    j.limits_deg[0].to_radians() as f32,
                    j.limits_deg[1].to_radians() as f32,
                ],
            )
            .motor_model(rp::JointAxis::AngX, rp::MotorModel::ForceBased)
            .motor_velocity(rp::JointAxis::AngX, 0.0, MOTOR_DAMPING)
            .motor_max_force(rp::JointAxis::AngX, j.max_torque as f32)
            .contacts_enabled(false)
            .build();
        let handle = w.impulse_joints.insert(ph, ch, data, true);
        let joint = SimJoint {
            robot,
            index: i,
            handle,
            parent: ph,
            child: ch,
            axis_parent: local_axis1.normalize(),
            rest_inv: (pp.rotation.inverse() * cp.rotation).inverse(),
        };
        let servo = Servo {
            target: 0.0,
            gain: j.servo_gain.unwrap_or(DEFAULT_SERVO_GAIN),
            max_torque: j.max_torque,
            max_velocity: j.max_vel,
            limits_deg: j.limits_deg,
        };
        let name = Name::new(format!("joint {}", j.name));
        let e = world.spawn((name, joint, servo, JointState::default(), ChildOf(robot)));
        entities.push(e.id());
    }
    entities
}

/// Lasers and tactile pads (areas on their links' colliders); returns the robot's empty
/// sensor readings, sized for them, or an error for a pad that lies on none of its link's
/// geometries.
fn spawn_sensors(
    world: &mut World,
    physics: &mut SimPhysics,
    sim: &Simulation,
    robot: Entity,
    bodies: &[(rp::RigidBodyHandle, f64)],
    groups: rp::InteractionGroups,
) -> Result<SensorData, SimError> {
    let step_width = sim.files.simulation.properties.step_width;
    let mut pads = 0;
    let mut beams = Vec::new();
    for s in &sim.robot.sensors {
        let name = Name::new(format!("sensor {}", s.name));
        let (body, _) = bodies[s.link];
        match &s.sensor {
            Sensor::Laser2d(l) => {
                let angles: Vec<f64> = beam_angles(l).iter().map(|a| a.to_radians()).collect();
                beams.push(angles.len());
                let laser = Laser2dSensor {
                    robot,
                    index: beams.len() - 1,
                    body,
                    pose: pose(&s.pose),
                    angles,
                    max_range: l.max_range,
                    period: (l.scan_time / step_width).round().max(1.0) as u64,
                    groups,
                };
                world.spawn((name, laser, ChildOf(robot)));
            }
            Sensor::Tactile(t) => {
                let area = PadArea {
                    pose: pose(&s.pose),
                    half_extents: vec3(t.extents),
                };
                let colliders = pad_colliders(physics, body, &area);
                if colliders.iter().all(|(_, on)| !on) {
                    return Err(SimError::PadOffLink {
                        sensor: s.name.clone(),
                        link: sim.robot.links[s.link].name.clone(),
                    });
                }
                let sensor = TactileSensor {
                    robot,
                    index: pads,
                    link: body,
                    area,
                    colliders: colliders.into_iter().map(|(c, _)| c).collect(),
                    debounce_steps: t.debounce,
                    state: Debounce::default(),
                    raw: false,
                };
                world.spawn((name, sensor, ChildOf(robot)));
                pads += 1;
            }
        }
    }
    Ok(SensorData::new(pads, &beams))
}

/// The colliders of link `body`, each with the map from its frame to the pad's and whether
/// the pad lies on it.
fn pad_colliders(
    physics: &SimPhysics,
    body: rp::RigidBodyHandle,
    area: &PadArea,
) -> Vec<((rp::ColliderHandle, rp::Pose), bool)> {
    let w = &physics.world;
    let Some(link) = w.bodies.get(body) else {
        return Vec::new();
    };
    let from_link = area.pose.inverse();
    link.colliders()
        .iter()
        .filter_map(|h| {
            let c = w.colliders.get(*h)?;
            let to_pad = from_link * c.position_wrt_parent().copied().unwrap_or_default();
            Some(((*h, to_pad), area.lies_on(c.shape(), &to_pad)))
        })
        .collect()
}
