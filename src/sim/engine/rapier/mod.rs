//! The rapier engine: rapier3d's bodies, colliders and joints behind [`PhysicsEngine`].
//! Every rapier type of the crate lives in this module.
//!
//! - [`build`]: the world of a simulation (bodies, colliders, hinges, sensors)
//! - [`settings`]: substeps and tolerances scaled to the robot
//! - [`terrain`]: height fields, the floor as a half-space
//! - [`contact`]: the contact model in rapier's terms
//!
//! We drive rapier directly instead of through bevy_rapier's plugin: the fixed-step
//! pipeline needs physics as one set among ours, and headless runs must not pay for
//! syncing transforms nobody looks at (docs/DESIGN.md, "Deviations").

mod build;
pub mod contact;
pub mod settings;
pub mod terrain;

use rapier3d::prelude as rp;

use crate::config::simulation::EngineKind;
use crate::config::transform::Pose;
use crate::sim::engine::{
    BodyId, BodyState, ColliderView, ContactView, JointId, JointReading, LaserId, LaserSpec,
    MAX_BODY_SPEED, PadArea, PadId, PhysicsEngine, ShapeOutline, tangential_speed,
};

pub use settings::{PhysicsSettings, SettingsError};

/// Damping of the servo's velocity motor (N·m·s/rad): stiff enough that the torque limit,
/// not the motor model, bounds the servo.
pub const MOTOR_DAMPING: f64 = 10.0;

/// A joint closer than this to a limit (degrees) has its limit constraint active.
pub const LIMIT_MARGIN_DEG: f64 = 15.0;
/// ... or closer than it would move in this time at its current speed (s).
pub const LIMIT_LOOKAHEAD_S: f64 = 0.05;

/// A hinge's rapier joint: an impulse joint (production) or a multibody joint
/// ([`PhysicsSettings::multibody_joints`]).
#[derive(Debug, Clone, Copy)]
enum JointHandle {
    Impulse(rp::ImpulseJointHandle),
    Multibody(rp::MultibodyJointHandle),
}

/// A hinge: its rapier joint, the bodies it joins and its frame.
#[derive(Debug, Clone)]
struct Hinge {
    handle: JointHandle,
    parent: rp::RigidBodyHandle,
    child: rp::RigidBodyHandle,
    /// Unit hinge axis in the parent body's frame.
    axis_parent: rp::Vector,
    /// Inverse of the child's rotation relative to the parent at angle zero.
    rest_inv: rp::Rotation,
    limits_deg: [f64; 2],
    /// The limits rapier enforces (degrees): the joint's, widened to its start angle when
    /// it starts outside them (an imported robot's start pose can), so the limit never
    /// snaps it in; as the servo brings it inside, the limit closes behind it and never
    /// opens again.
    enforced_deg: [f64; 2],
}

impl Hinge {
    /// The limits to enforce on a joint at `angle` (degrees) that enforced `before`:
    /// `limits_deg`, or nearer to the angle while it has not come inside them yet.
    fn enforced(limits_deg: [f64; 2], before: [f64; 2], angle: f64) -> [f64; 2] {
        [
            limits_deg[0].min(before[0].max(angle)),
            limits_deg[1].max(before[1].min(angle)),
        ]
    }
}

/// A pad: its link and the link's colliders, each with the map from its frame to the pad's.
#[derive(Debug, Clone)]
struct Pad {
    area: PadArea,
    colliders: Vec<(rp::ColliderHandle, rp::Pose)>,
}

/// A laser: the spec and its rapier placement and filter.
#[derive(Debug, Clone)]
struct Laser {
    body: rp::RigidBodyHandle,
    pose: rp::Pose,
    directions: Vec<rp::Vector>,
    max_range: f64,
    groups: rp::InteractionGroups,
}

/// rapier's world and the tables from our ids to its handles.
pub struct RapierEngine {
    world: rp::PhysicsWorld,
    settings: PhysicsSettings,
    bodies: Vec<rp::RigidBodyHandle>,
    hinges: Vec<Hinge>,
    pads: Vec<Pad>,
    lasers: Vec<Laser>,
    /// A multibody link became non-finite or faster than [`MAX_BODY_SPEED`]: the world is
    /// no longer stepped (rapier's multibody solver panics on a NaN joint coordinate).
    diverged: bool,
}

impl RapierEngine {
    fn handle(&self, b: BodyId) -> Option<rp::RigidBodyHandle> {
        self.bodies.get(b.0 as usize).copied()
    }

    /// Whether every multibody link's pose is finite and its speed below
    /// [`MAX_BODY_SPEED`].
    fn multibody_links_sound(&self) -> bool {
        let max = MAX_BODY_SPEED as f32;
        self.hinges
            .iter()
            .filter(|h| matches!(h.handle, JointHandle::Multibody(_)))
            .filter_map(|h| self.world.bodies.get(h.child))
            .all(|b| b.translation().is_finite() && b.linvel().length() < max)
    }

    /// Duration of the last solver substep (s): the servos' torque is its motor impulse
    /// divided by it.
    fn substep_duration(&self) -> f64 {
        let p = &self.world.integration_parameters;
        p.dt as f64 / p.num_solver_iterations.max(1) as f64
    }
}

/// Bit of collision group `g`: group 0 is the environment, robot `i` of a batch uses `i + 1`.
fn group_bit(g: u32) -> rp::Group {
    rp::Group::from_bits_truncate(1u32 << g)
}

/// f64 triple to rapier's vector.
fn vec3(v: [f64; 3]) -> rp::Vector {
    rp::Vector::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

/// Rapier's vector to an f64 triple.
fn arr3(v: rp::Vector) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// Configuration pose (translation, quaternion w x y z) to rapier's pose.
fn pose(t: &Pose) -> rp::Pose {
    let [w, x, y, z] = t.rotation;
    rp::Pose::from_parts(
        vec3(t.translation),
        rp::Rotation::from_xyzw(x as f32, y as f32, z as f32, w as f32).normalize(),
    )
}

/// Rapier's pose to a configuration pose.
fn to_pose(p: &rp::Pose) -> Pose {
    let r = p.rotation;
    Pose {
        translation: arr3(p.translation),
        rotation: [r.w as f64, r.x as f64, r.y as f64, r.z as f64],
    }
}

impl Hinge {
    /// The hinge angle (degrees) and angular velocity (degrees/s) from the bodies' states.
    fn measure(&self, bodies: &rp::RigidBodySet) -> (f64, f64) {
        let (Some(p), Some(c)) = (bodies.get(self.parent), bodies.get(self.child)) else {
            return (0.0, 0.0);
        };
        let r1 = *p.rotation();
        let r2 = *c.rotation();
        let delta = r1.inverse() * r2 * self.rest_inv;
        let along = delta.x * self.axis_parent.x
            + delta.y * self.axis_parent.y
            + delta.z * self.axis_parent.z;
        let angle = 2.0 * along.atan2(delta.w);
        let angle = if angle > std::f32::consts::PI {
            angle - std::f32::consts::TAU
        } else if angle < -std::f32::consts::PI {
            angle + std::f32::consts::TAU
        } else {
            angle
        };
        let axis_world = r1 * self.axis_parent;
        let rel = c.angvel() - p.angvel();
        let velocity = rel.dot(axis_world);
        ((angle as f64).to_degrees(), (velocity as f64).to_degrees())
    }
}

impl PhysicsEngine for RapierEngine {
    fn kind(&self) -> EngineKind {
        EngineKind::Rapier
    }

    fn gravity(&self) -> [f64; 3] {
        arr3(self.world.gravity)
    }

    fn settings(&self) -> String {
        format!("rapier: {}", self.settings)
    }

    fn step(&mut self) {
        for _ in 0..self.settings.steps_per_step {
            if self.diverged {
                return;
            }
            self.world.step();
            if self.settings.multibody_joints {
                self.diverged = !self.multibody_links_sound();
            }
        }
    }

    fn diverged(&self) -> bool {
        self.diverged
    }

    fn joint(&self, j: JointId) -> JointReading {
        let Some(h) = self.hinges.get(j.0 as usize) else {
            return JointReading::default();
        };
        let (angle, velocity) = h.measure(&self.world.bodies);
        // The motor's impulse in the last solver substep (the joint limit's impulse is not the
        // servo's); rapier splits a step into `num_solver_iterations` substeps.
        let axis = rp::JointAxis::AngX as usize;
        let impulse = match h.handle {
            JointHandle::Impulse(handle) => self
                .world
                .impulse_joints
                .get(handle)
                .map(|ij| ij.data.motors[axis].impulse),
            JointHandle::Multibody(handle) => self
                .world
                .multibody_joints
                .get(handle)
                .and_then(|(mb, link)| mb.link(link))
                .map(|l| l.joint.data.motors[axis].impulse),
        };
        let torque = impulse.map_or(0.0, f64::from) / self.substep_duration();
        JointReading {
            angle,
            velocity,
            torque,
        }
    }

    fn drive_joint(&mut self, j: JointId, velocity: f64, now: &JointReading) {
        let Some(h) = self.hinges.get_mut(j.0 as usize) else {
            return;
        };
        let data = match h.handle {
            JointHandle::Impulse(handle) => self
                .world
                .impulse_joints
                .get_mut(handle, false)
                .map(|ij| &mut ij.data),
            JointHandle::Multibody(handle) => self
                .world
                .multibody_joints
                .get_mut(handle)
                .and_then(|(mb, link)| mb.link_mut(link))
                .map(|l| &mut l.joint.data),
        };
        let Some(data) = data else {
            return;
        };
        data.set_motor_velocity(
            rp::JointAxis::AngX,
            velocity.to_radians() as f32,
            MOTOR_DAMPING as f32,
        );
        // The limit constraint costs a solver row every substep; it is only switched on
        // while the joint is close enough to a limit to reach it within a few steps.
        let [lo, hi] = h.limits_deg;
        let enforced = Hinge::enforced(h.limits_deg, h.enforced_deg, now.angle);
        if enforced != h.enforced_deg && now.angle.is_finite() {
            h.enforced_deg = enforced;
            data.set_limits(rp::JointAxis::AngX, enforced.map(|d| d.to_radians() as f32));
        }
        let margin = LIMIT_MARGIN_DEG.max(now.velocity.abs() * LIMIT_LOOKAHEAD_S);
        if now.angle < lo + margin || now.angle > hi - margin {
            data.limit_axes |= rp::JointAxesMask::ANG_X;
        } else {
            data.limit_axes &= !rp::JointAxesMask::ANG_X;
        }
    }

    fn body_com(&self, b: BodyId) -> [f64; 3] {
        self.handle(b)
            .and_then(|h| self.world.bodies.get(h))
            .map_or([0.0; 3], |body| arr3(body.center_of_mass()))
    }

    fn body(&self, b: BodyId) -> Option<BodyState> {
        let body = self.world.bodies.get(self.handle(b)?)?;
        let props = body.mass_properties().local_mprops;
        Some(BodyState {
            pose: to_pose(body.position()),
            com: arr3(body.center_of_mass()),
            linvel: arr3(body.linvel()),
            mass: props.mass() as f64,
            inertia: arr3(props.principal_inertia()),
            dynamic: body.is_dynamic(),
        })
    }

    fn pad_contact(&self, p: PadId) -> (bool, [f64; 3]) {
        let Some(pad) = self.pads.get(p.0 as usize) else {
            return (false, [0.0; 3]);
        };
        let narrow = &self.world.narrow_phase;
        let mut normal = rp::Vector::ZERO;
        let mut touching = false;
        for (collider, to_pad) in &pad.colliders {
            for pair in narrow.contact_pairs_with(*collider) {
                if !pair.has_any_active_contact() {
                    continue;
                }
                let ours_first = pair.collider1 == *collider;
                for m in pair.manifolds() {
                    let points = m.points.iter().map(|c| {
                        let local = if ours_first {
                            m.subshape_pos1()
                                .map_or(c.local_p1, |p| p.transform_point(c.local_p1))
                        } else {
                            m.subshape_pos2()
                                .map_or(c.local_p2, |p| p.transform_point(c.local_p2))
                        };
                        arr3(to_pad.transform_point(local))
                    });
                    if pad.area.touched_by(points) {
                        touching = true;
                        normal += if ours_first {
                            -m.data.normal
                        } else {
                            m.data.normal
                        };
                    }
                }
            }
        }
        (touching, arr3(normal.normalize_or_zero()))
    }

    fn scan(&self, l: LaserId, ranges: &mut [f64]) {
        let Some(laser) = self.lasers.get(l.0 as usize) else {
            return;
        };
        let Some(body) = self.world.bodies.get(laser.body) else {
            return;
        };
        let at = body.position() * laser.pose;
        let filter = rp::QueryFilter::default()
            .groups(laser.groups)
            .exclude_rigid_body(laser.body);
        for (range, local) in ranges.iter_mut().zip(&laser.directions) {
            let ray = rp::Ray::new(at.translation, at.rotation * *local);
            *range = self
                .world
                .cast_ray(&ray, laser.max_range as f32, true, filter)
                .map_or(laser.max_range, |(_, toi)| toi as f64);
        }
    }

    fn height_below(&self, x: f64, y: f64) -> Option<f64> {
        let from = crate::sim::engine::PROBE_FROM;
        // Every collider in turn, not the broad phase's tree: that is built by the first
        // step, and a probe answers before it too.
        let ray = rp::Ray::new(vec3([x, y, from]), vec3([0.0, 0.0, -1.0]));
        let reach = (2.0 * from) as f32;
        self.world
            .colliders
            .iter()
            .filter_map(|(_, c)| c.shape().cast_ray(c.position(), &ray, reach, true))
            .min_by(f32::total_cmp)
            .map(|toi| from - toi as f64)
    }

    fn translate_body(&mut self, b: BodyId, delta: [f64; 3]) {
        let Some(h) = self.handle(b) else {
            return;
        };
        if let Some(body) = self.world.bodies.get_mut(h) {
            let t = arr3(body.translation());
            let moved = [t[0] + delta[0], t[1] + delta[1], t[2] + delta[2]];
            body.set_translation(vec3(moved), true);
        }
    }

    fn set_angular_velocity(&mut self, b: BodyId, angvel: [f64; 3]) {
        let Some(h) = self.handle(b) else {
            return;
        };
        if let Some(body) = self.world.bodies.get_mut(h) {
            body.set_angvel(vec3(angvel), true);
        }
    }

    fn set_linear_velocity(&mut self, b: BodyId, linvel: [f64; 3]) {
        let Some(h) = self.handle(b) else {
            return;
        };
        if let Some(body) = self.world.bodies.get_mut(h) {
            body.set_linvel(vec3(linvel), true);
        }
    }

    fn colliders(&self) -> Vec<ColliderView> {
        let w = &self.world;
        w.colliders
            .iter()
            .map(|(_, c)| {
                let dynamic = c
                    .parent()
                    .and_then(|b| w.bodies.get(b))
                    .is_some_and(|b| b.is_dynamic());
                let shape = if let Some(b) = c.shape().as_cuboid() {
                    ShapeOutline::Box(arr3(b.half_extents))
                } else if let Some(s) = c.shape().as_ball() {
                    ShapeOutline::Sphere(s.radius as f64)
                } else {
                    let aabb = c.compute_aabb();
                    ShapeOutline::Bounds(arr3(aabb.mins), arr3(aabb.maxs))
                };
                ColliderView {
                    pose: to_pose(c.position()),
                    shape,
                    dynamic,
                }
            })
            .collect()
    }

    fn contacts(&self) -> Vec<ContactView> {
        let w = &self.world;
        let ours = |h: Option<rp::RigidBodyHandle>| {
            let h = h?;
            let i = self.bodies.iter().position(|b| *b == h)?;
            Some(BodyId(i as u32))
        };
        let mut out = Vec::new();
        for pair in w.narrow_phase.contact_pairs() {
            let (Some(c1), Some(c2)) = (
                w.colliders.get(pair.collider1),
                w.colliders.get(pair.collider2),
            ) else {
                continue;
            };
            let velocity_at = |c: &rp::Collider, p: rp::Vector| {
                c.parent()
                    .and_then(|h| w.bodies.get(h))
                    .map_or(rp::Vector::ZERO, |b| b.velocity_at_point(p))
            };
            for m in pair.manifolds() {
                let normal = arr3(m.data.normal);
                for p in &m.points {
                    let at = c1.position().transform_point(p.local_p1);
                    let relative = arr3(velocity_at(c1, at) - velocity_at(c2, at));
                    out.push(ContactView {
                        point: arr3(at),
                        normal,
                        touching: p.dist <= 0.0,
                        depth: f64::from(-p.dist).max(0.0),
                        bodies: [ours(c1.parent()), ours(c2.parent())],
                        slip: tangential_speed(relative, normal),
                    });
                }
            }
        }
        out
    }
}

impl Laser {
    fn new(spec: &LaserSpec, body: rp::RigidBodyHandle, groups: rp::InteractionGroups) -> Self {
        Laser {
            body,
            pose: pose(&spec.pose),
            directions: spec
                .angles
                .iter()
                .map(|a| vec3(LaserSpec::direction(*a)))
                .collect(),
            max_range: spec.max_range,
            groups,
        }
    }
}
