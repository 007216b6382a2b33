//! Builds rapier's world of a loaded [`Simulation`]: the environment's bodies, then each
//! robot's links (rigid bodies with colliders), hinges (revolute joints with limits and a
//! force-based velocity motor) and sensors. Bodies are inserted in a fixed order, so
//! rapier's handles and hence the trajectory depend only on the configuration. Robots of a
//! batch share the environment but not each other: each has its own collision group.

use rapier3d::prelude as rp;

use super::contact::{check, combine_rule};
use super::terrain::{floor_halfspace, heightfield};
use super::{
    Hinge, JointHandle, Laser, MOTOR_DAMPING, Pad, PhysicsSettings, RapierEngine, arr3, group_bit,
    pose, vec3,
};
use crate::config::Simulation;
use crate::config::body::{BodyKind, Geom, MeshCollision, Shape};
use crate::config::resolve::robot::{LinkInertia, geom_volume};
use crate::config::transform::Pose;
use crate::sim::engine::{
    BodyId, DEFAULT_FRICTION, JointId, LINK_FRICTION, LaserId, LaserSpec, Layout, PadArea, PadId,
    RobotLayout, SensorPart, sensor_parts,
};
use crate::sim::error::SimError;

impl RapierEngine {
    /// `sim`'s world with `robots` copies of the robot, integrated with `settings`.
    pub fn build(
        sim: &Simulation,
        robots: usize,
        settings: PhysicsSettings,
    ) -> Result<(RapierEngine, Layout), SimError> {
        check(&sim.environment.physics.contact_model())?;
        let dt = sim.files.simulation.properties.step_width;
        let world = rp::PhysicsWorld {
            gravity: vec3(sim.environment.physics.gravity),
            integration_parameters: settings.integration_parameters(dt),
            ..Default::default()
        };
        let mut engine = RapierEngine {
            world,
            settings,
            bodies: Vec::new(),
            hinges: Vec::new(),
            pads: Vec::new(),
            lasers: Vec::new(),
            diverged: false,
        };
        let environment = engine.environment(sim, robots)?;
        let parts = sensor_parts(sim);
        let robots = (0..robots)
            .map(|r| engine.robot(sim, r, &parts))
            .collect::<Result<_, _>>()?;
        Ok((
            engine,
            Layout {
                environment,
                robots,
            },
        ))
    }

    fn insert_body(&mut self, body: impl Into<rp::RigidBody>) -> (BodyId, rp::RigidBodyHandle) {
        let handle = self.world.bodies.insert(body);
        self.bodies.push(handle);
        (BodyId(self.bodies.len() as u32 - 1), handle)
    }

    fn attach(&mut self, colliders: Vec<rp::Collider>, handle: rp::RigidBodyHandle) {
        let w = &mut self.world;
        for c in colliders {
            w.colliders.insert_with_parent(c, handle, &mut w.bodies);
        }
        // rapier folds the colliders' and the additional mass properties into the body at
        // its first step; until then the body's centre of mass is its frame's origin, and the
        // robot's start centre of mass (a run's displacement) was off by up to 0.16 m.
        if let Some(body) = w.bodies.get_mut(handle) {
            body.recompute_mass_properties_from_colliders(&w.colliders);
        }
    }

    /// The environment's bodies, shared by every robot of the batch (collision group 0).
    fn environment(&mut self, sim: &Simulation, robots: usize) -> Result<Vec<BodyId>, SimError> {
        let env = &sim.environment;
        let all_robots = (1..=robots as u32).fold(rp::Group::empty(), |g, i| g | group_bit(i));
        let env_groups = rp::InteractionGroups::new(
            group_bit(0),
            all_robots | group_bit(0),
            rp::InteractionTestMode::And,
        );
        let default_friction = env.physics.default_friction.unwrap_or(DEFAULT_FRICTION);
        let mut ids = Vec::with_capacity(env.bodies.len());
        for b in &env.bodies {
            let builder = match b.kind {
                BodyKind::Static => rp::RigidBodyBuilder::fixed(),
                BodyKind::Dynamic => rp::RigidBodyBuilder::dynamic().can_sleep(false),
            };
            let (id, handle) = self.insert_body(builder.pose(pose(&b.pose)));
            let friction = |g: &Geom| g.friction.unwrap_or(default_friction);
            let fixed = b.kind == BodyKind::Static;
            let mut cs = colliders(sim, &b.geoms, fixed, b.mass, friction, env_groups)?;
            if fixed && self.settings.halfspace_floor {
                for (c, g) in cs.iter_mut().zip(&b.geoms) {
                    if let Some((floor, at)) = floor_halfspace(&b.pose, g) {
                        c.set_shape(floor);
                        c.set_position_wrt_parent(at);
                    }
                }
            }
            self.attach(cs, handle);
            ids.push(id);
        }
        Ok(ids)
    }

    /// Robot `r` of the batch: links, hinges, sensors.
    fn robot(
        &mut self,
        sim: &Simulation,
        r: usize,
        parts: &[SensorPart],
    ) -> Result<RobotLayout, SimError> {
        let group = group_bit(r as u32 + 1);
        let filter = if sim.environment.physics.self_collision {
            group | group_bit(0)
        } else {
            group_bit(0)
        };
        let groups = rp::InteractionGroups::new(group, filter, rp::InteractionTestMode::And);
        let links = self.links(sim, groups)?;
        let joints = self.joints(sim, &links);
        let mut layout = RobotLayout {
            links,
            joints,
            ..RobotLayout::default()
        };
        for part in parts {
            match part {
                SensorPart::Pad { name, link, area } => {
                    let (body, _) = layout.links[*link];
                    let colliders = self.pad_colliders(body, area);
                    if colliders.iter().all(|(_, on)| !on) {
                        return Err(SimError::PadOffLink {
                            sensor: name.clone(),
                            link: sim.robot.links[*link].name.clone(),
                        });
                    }
                    self.pads.push(Pad {
                        area: *area,
                        colliders: colliders.into_iter().map(|(c, _)| c).collect(),
                    });
                    layout.pads.push(PadId(self.pads.len() as u32 - 1));
                }
                SensorPart::Laser {
                    link,
                    pose,
                    angles,
                    max_range,
                } => {
                    let (body, _) = layout.links[*link];
                    let spec = LaserSpec {
                        robot: r,
                        body,
                        pose: *pose,
                        angles: angles.clone(),
                        max_range: *max_range,
                    };
                    let handle = self.bodies[body.0 as usize];
                    self.lasers.push(Laser::new(&spec, handle, groups));
                    layout.lasers.push(LaserId(self.lasers.len() as u32 - 1));
                }
            }
        }
        Ok(layout)
    }

    /// Link bodies and colliders at the environment's robot pose, with their masses.
    fn links(
        &mut self,
        sim: &Simulation,
        groups: rp::InteractionGroups,
    ) -> Result<Vec<(BodyId, f64)>, SimError> {
        let start = &sim.environment.robot_pose;
        let mut out = Vec::with_capacity(sim.robot.links.len());
        for l in &sim.robot.links {
            let p = start.mul(&l.pose);
            let builder = if l.fixed {
                rp::RigidBodyBuilder::fixed()
            } else {
                rp::RigidBodyBuilder::dynamic()
            };
            let mut body = builder.pose(pose(&p)).can_sleep(false);
            // A link with its inertia given carries it on the body; its colliders add none.
            let collider_mass = match &l.inertia {
                Some(i) => {
                    body = body.additional_mass_properties(mass_properties(l.mass, i));
                    0.0
                }
                None => l.mass,
            };
            let (id, handle) = self.insert_body(body);
            let cs = colliders(
                sim,
                &l.geoms,
                false,
                collider_mass,
                |_| LINK_FRICTION,
                groups,
            )?;
            self.attach(cs, handle);
            out.push((id, l.mass));
        }
        Ok(out)
    }

    /// The hinges: revolute impulse joints with limits and a force-based velocity motor.
    fn joints(&mut self, sim: &Simulation, links: &[(BodyId, f64)]) -> Vec<JointId> {
        let start = &sim.environment.robot_pose;
        let mut ids = Vec::with_capacity(sim.robot.joints.len());
        for j in &sim.robot.joints {
            let ph = self.bodies[links[j.parent].0.0 as usize];
            let ch = self.bodies[links[j.child].0.0 as usize];
            let w = &mut self.world;
            let (pp, cp) = (*w.bodies[ph].position(), *w.bodies[ch].position());
            let anchor = start.mul(&Pose::from_translation(j.anchor)).translation;
            let (a, n) = (vec3(anchor), vec3(start.rotate(j.axis)).normalize());
            let local_axis1 = pp.rotation.inverse() * n;
            // One world frame of the joint (x along the axis) seen from both bodies: the
            // joint's angle is 0 in the start pose whatever the links' orientations (frames
            // completed from each body's axis alone differ by the links' relative twist about
            // the axis, which offset rapier's limits and a multibody's coordinate).
            let frame = rp::Rotation::from_rotation_arc(rp::Vector::X, n);
            let enforced = [j.limits_deg[0].min(0.0), j.limits_deg[1].max(0.0)];
            let local_frame = |body: &rp::Pose| {
                rp::Pose::from_parts(
                    body.inverse_transform_point(a),
                    (body.rotation.inverse() * frame).normalize(),
                )
            };
            let data = rp::GenericJointBuilder::new(rp::JointAxesMask::LOCKED_REVOLUTE_AXES)
                .local_frame1(local_frame(&pp))
                .local_frame2(local_frame(&cp))
                .limits(rp::JointAxis::AngX, enforced.map(|d| d.to_radians() as f32))
                .motor_model(rp::JointAxis::AngX, rp::MotorModel::ForceBased)
                .motor_velocity(rp::JointAxis::AngX, 0.0, MOTOR_DAMPING as f32)
                .motor_max_force(rp::JointAxis::AngX, j.max_torque as f32)
                .contacts_enabled(false)
                .build();
            let handle = if self.settings.multibody_joints {
                // A loop cannot be a multibody: that joint stays an impulse joint.
                match w.multibody_joints.insert(ph, ch, data, true) {
                    Some(h) => JointHandle::Multibody(h),
                    None => JointHandle::Impulse(w.impulse_joints.insert(ph, ch, data, true)),
                }
            } else {
                JointHandle::Impulse(w.impulse_joints.insert(ph, ch, data, true))
            };
            self.hinges.push(Hinge {
                handle,
                parent: ph,
                child: ch,
                axis_parent: local_axis1.normalize(),
                rest_inv: (pp.rotation.inverse() * cp.rotation).inverse(),
                limits_deg: j.limits_deg,
                enforced_deg: enforced,
            });
            ids.push(JointId(self.hinges.len() as u32 - 1));
        }
        ids
    }

    /// The colliders of link `body`, each with the map from its frame to the pad's and
    /// whether the pad lies on it.
    fn pad_colliders(
        &self,
        body: BodyId,
        area: &PadArea,
    ) -> Vec<((rp::ColliderHandle, rp::Pose), bool)> {
        let w = &self.world;
        let Some(link) = w.bodies.get(self.bodies[body.0 as usize]) else {
            return Vec::new();
        };
        let from_link = pose(&area.pose).inverse();
        link.colliders()
            .iter()
            .filter_map(|h| {
                let c = w.colliders.get(*h)?;
                let to_pad = from_link * c.position_wrt_parent().copied().unwrap_or_default();
                let aabb = c.shape().compute_aabb(&to_pad);
                let on = area.touched_by([aabb.mins, aabb.maxs].into_iter().map(arr3));
                Some(((*h, to_pad), on))
            })
            .collect()
    }
}

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
                    let map = mesh.height_map().map_err(|why| err(why.to_string()))?;
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
                .friction_combine_rule(combine_rule(&sim.environment.physics.contact_model()))
                .collision_groups(groups)
                .build())
        })
        .collect()
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
