//! The one mapping of a resolved simulation to MuJoCo's MJCF, used by the MuJoCo engine
//! (loaded from memory) and by `proleg export mjcf` (written to a file).
//!
//! | proleg | MJCF |
//! |---|---|
//! | robot links, hinges (tail to head) | nested `<body>`s under a free root, `<joint type="hinge">` with range |
//! | link mass spread over its geometry / given inertia | per-geom `mass` / `<inertial fullinertia>` |
//! | servo, in the engine: our P controller's velocity command, torque limit τ | a bounded velocity constraint: the hinge's `frictionloss` τ, `solreffriction` two engine steps, whose target speed the engine moves from 0 to the command every step (no extra dof) |
//! | servo, in an export: torque limit τ, speed limit v, gain g (1/s) | `<position>` actuator, `forcerange` ±τ, `kp` = g·τ/v, joint `damping` τ/v (so full torque gives speed v) |
//! | contact friction: the smaller of the two geometries' | `friction` per geom, `priority` so the smaller one wins |
//! | robots of a batch, self-collision off | `contype`/`conaffinity` bits: links meet the terrain (and their own robot with self-collision) |
//! | static environment bodies | `<frame>`s of the world body, their geoms named `BODY/k` (no MuJoCo body each: on a field of 424 pegs a body per peg ran the demo at 7x real time, frames at 34x) |
//! | boxes, spheres, cylinders, meshes, height fields | `box`, `sphere`, `cylinder` (turned: ours stand along y), `mesh` (MuJoCo collides as its convex hull), `hfield` |
//! [`geoms`] writes one geometry (shape, placement, friction, contact bits, assets);
//! [`contact`] the contact model in MuJoCo's terms.

pub mod contact;
pub mod geoms;

use crate::config::Simulation;
use crate::config::body::BodyKind;
use crate::config::resolve::robot::geom_volume;
use crate::config::transform::Pose;
use crate::config::xml::write::XmlWriter;
use crate::sim::engine::DEFAULT_FRICTION;
use crate::sim::engine::mujoco::{MujocoError, MujocoSettings};
use crate::sim::servo::DEFAULT_SERVO_GAIN;
use geoms::{Assets, Collision, geom_attrs, mj, pose_attrs};

/// How the servos are modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Servos {
    /// Bounded velocity constraints driven by proleg's servo stage every step (the engine):
    /// MuJoCo's friction loss on the hinge, whose constraint row the engine retargets
    /// from speed 0 to the stage's command between `mj_step1` and `mj_step2`, and the
    /// constraint solver (implicit, like rapier's motor constraint) gives the torque that
    /// reaches the commanded speed, at most τ. A `<velocity>` actuator on the hinge
    /// clamped to ±τ is explicit once clamped and oscillates on these light links
    /// (docs/MEASUREMENTS.md has the measurement). Read by another tool, this model's
    /// servos are brakes (target speed 0).
    Velocity,
    /// Position actuators approximating the servo on their own (an export for other tools).
    Position,
}

/// What to map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MjcfOptions {
    /// Copies of the robot (each its own collision bit; names prefixed `r<i>/` when > 1).
    pub robots: usize,
    /// The actuators.
    pub servos: Servos,
    /// Solver, cone and timestep refinement.
    pub settings: MujocoSettings,
}

/// An MJCF document and what it holds.
#[derive(Debug, Clone, PartialEq)]
pub struct Mjcf {
    /// The document.
    pub xml: String,
    /// Bodies (movable environment bodies and robot links) written; static environment
    /// bodies are frames of the world body.
    pub bodies: usize,
    /// Hinges (and actuators) written.
    pub joints: usize,
    /// Mesh and height-field assets written.
    pub assets: usize,
    /// Where MuJoCo will differ by construction, one line each.
    pub notes: Vec<String>,
}

/// The name prefix of robot `r` of a batch of `robots`.
pub fn robot_prefix(robots: usize, r: usize) -> String {
    if robots > 1 {
        format!("r{r}/")
    } else {
        String::new()
    }
}

/// The name of environment body `i` of `sim`: `env_NAME`, with `_i` appended when an
/// earlier environment body has the same name (MJCF names must be unique).
pub fn env_body_name(sim: &Simulation, i: usize) -> String {
    let bodies = &sim.environment.bodies;
    let name = &bodies[i].name;
    if bodies[..i].iter().any(|b| b.name == *name) {
        format!("env_{name}_{i}")
    } else {
        format!("env_{name}")
    }
}

/// The name of link `name` of the robot with `prefix`: its own, but MuJoCo's world body is
/// called `world` (the URDF convention for a fixed base), so a link of that name is renamed.
pub fn link_body_name(prefix: &str, name: &str) -> String {
    if prefix.is_empty() && name == "world" {
        "robot_world".into()
    } else {
        format!("{prefix}{name}")
    }
}

/// `sim` as one MJCF document.
pub fn mjcf(sim: &Simulation, opts: &MjcfOptions) -> Result<Mjcf, MujocoError> {
    let assets = Assets::collect(sim);
    let mut w = XmlWriter::new();
    w.open("mujoco", &[("model", sim.robot.name.clone())]);
    w.comment(&format!(
        "Made by proleg from {}; the servo model and the contact friction rule are explained in proleg's docs/DESIGN.md.",
        sim.file.display()
    ));
    // balanceinertia: proleg's own check (config::body::inertia_fault) accepts tensors
    // within 1e-6 of the triangle inequality; MuJoCo's is exact, so the last rounding of
    // a balanced tensor is repaired by MuJoCo the way proleg balanced it.
    w.empty(
        "compiler",
        &[
            ("angle", "radian".into()),
            ("autolimits", "true".into()),
            ("balanceinertia", "true".into()),
        ],
    );
    option(sim, &opts.settings, &mut w);
    contact_default(sim, &mut w);
    assets.write(&mut w, sim)?;
    w.open("worldbody", &[]);
    let env_bodies = environment(sim, &mut w, &assets)?;
    for r in 0..opts.robots {
        robot(sim, opts, r, &mut w, &assets)?;
    }
    w.close();
    if opts.servos == Servos::Position {
        actuators(sim, &mut w);
    }
    w.close();
    Ok(Mjcf {
        xml: w.finish(),
        bodies: env_bodies + opts.robots * sim.robot.links.len(),
        joints: opts.robots * sim.robot.joints.len(),
        assets: assets.count(),
        notes: assets.notes.clone(),
    })
}

/// `<option>`: the engine's timestep (the simulation step divided by the refinement),
/// gravity, the implicit-fast integrator (velocity actuators' `kv` implicit), dense
/// Jacobians, cone and solver iterations. MuJoCo picks sparse Jacobians from 60 dofs (a
/// batch of 6 snakes): measured with the servo model of the time (a tendon to a reference
/// hinge per servo), the solver then ran out of its iterations and the world blew up
/// within 10 ms, dense stayed stable.
fn option(sim: &Simulation, s: &MujocoSettings, w: &mut XmlWriter) {
    let dt = timestep(sim, s);
    let mut attrs = vec![
        ("timestep", mj(&[dt])),
        ("gravity", mj(&sim.environment.physics.gravity)),
        ("integrator", "implicitfast".into()),
        ("jacobian", "dense".into()),
    ];
    attrs.push((
        "cone",
        contact::cone(&sim.environment.physics.contact_model()).into(),
    ));
    if let Some(n) = s.iterations {
        attrs.push(("iterations", n.to_string()));
    }
    w.empty("option", &attrs);
}

/// MuJoCo's timestep: the simulation step divided by the refinement.
fn timestep(sim: &Simulation, s: &MujocoSettings) -> f64 {
    sim.files.simulation.properties.step_width / s.steps_per_step.max(1) as f64
}

/// `<default>`: every geom's contact spring, from the environment's contact model.
fn contact_default(sim: &Simulation, w: &mut XmlWriter) {
    let model = sim.environment.physics.contact_model();
    w.open("default", &[]);
    w.empty("geom", &[("solref", mj(&contact::solref(&model)))]);
    w.close();
}

/// The environment's bodies: static ones fixed to the world, dynamic ones free.
fn environment(sim: &Simulation, w: &mut XmlWriter, assets: &Assets) -> Result<usize, MujocoError> {
    let env = &sim.environment;
    let default_friction = env.physics.default_friction.unwrap_or(DEFAULT_FRICTION);
    let mut bodies = 0;
    for (i, b) in env.bodies.iter().enumerate() {
        let name = env_body_name(sim, i);
        let fixed = b.kind == BodyKind::Static;
        let mut attrs = vec![("name", name.clone())];
        attrs.extend(pose_attrs(&b.pose));
        w.open(if fixed { "frame" } else { "body" }, &attrs);
        if !fixed {
            w.empty("freejoint", &[]);
            bodies += 1;
        }
        let volume: f64 = b.geoms.iter().map(geom_volume).sum();
        for (k, g) in b.geoms.iter().enumerate() {
            let friction = g.friction.unwrap_or(default_friction);
            let mass = (!fixed).then(|| b.mass * geom_volume(g) / volume.max(1e-12));
            let mut attrs = geom_attrs(g, sim, assets, Collision::Terrain { friction }, mass)?;
            if fixed {
                attrs.insert(0, ("name", static_geom_name(&name, k)));
            }
            w.empty("geom", &attrs);
        }
        w.close();
    }
    Ok(bodies)
}

/// The name of geometry `k` of the static environment body called `body` (an MJCF
/// `<frame>` of the world body, [`environment`]).
pub fn static_geom_name(body: &str, k: usize) -> String {
    format!("{body}/{k}")
}

/// Robot `r`'s links as a tree of bodies from its root, the hinges in the children.
fn robot(
    sim: &Simulation,
    opts: &MjcfOptions,
    r: usize,
    w: &mut XmlWriter,
    assets: &Assets,
) -> Result<(), MujocoError> {
    let robot = &sim.robot;
    let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
    for (k, j) in robot.joints.iter().enumerate() {
        if parent_joint[j.child].replace(k).is_some() {
            return Err(MujocoError::NotATree {
                file: robot.file.display().to_string(),
                cause: format!(
                    "link {} is the child of two joints",
                    robot.links[j.child].name
                ),
            });
        }
    }
    let tree = Tree {
        sim,
        prefix: robot_prefix(opts.robots, r),
        collision: Collision::Link {
            robot: r,
            self_collision: sim.environment.physics.self_collision,
        },
        servos: opts.servos,
        dt: timestep(sim, &opts.settings),
        assets,
    };
    let mut written = 0;
    for root in (0..robot.links.len()).filter(|&l| parent_joint[l].is_none()) {
        let at = sim.environment.robot_pose.mul(&robot.links[root].pose);
        written += tree.link(root, &at, None, w)?;
    }
    if written != robot.links.len() {
        return Err(MujocoError::NotATree {
            file: robot.file.display().to_string(),
            cause: "the joints form a cycle".into(),
        });
    }
    Ok(())
}

/// What writing one robot's links needs.
struct Tree<'a> {
    sim: &'a Simulation,
    prefix: String,
    collision: Collision,
    servos: Servos,
    /// The engine's timestep (s).
    dt: f64,
    assets: &'a Assets,
}

impl Tree<'_> {
    /// Link `l` as a body at `at` (its parent's frame), its hinge and its children; returns
    /// how many links it wrote.
    fn link(
        &self,
        l: usize,
        at: &Pose,
        joint: Option<usize>,
        w: &mut XmlWriter,
    ) -> Result<usize, MujocoError> {
        let robot = &self.sim.robot;
        let link = &robot.links[l];
        let name = link_body_name(&self.prefix, &link.name);
        let mut attrs = vec![("name", name.clone())];
        attrs.extend(pose_attrs(at));
        w.open("body", &attrs);
        match joint {
            // A fixed link (a robot's fixed base) hangs on the world without a joint.
            None if link.fixed => {}
            None => w.empty("freejoint", &[("name", format!("{name}_free"))]),
            Some(k) => self.hinge(k, w),
        }
        if let Some(i) = &link.inertia {
            let t = i.tensor;
            w.empty(
                "inertial",
                &[
                    ("pos", mj(&i.com)),
                    ("mass", mj(&[link.mass])),
                    (
                        "fullinertia",
                        crate::config::xml::write::nums(&[t[0], t[4], t[8], t[1], t[2], t[5]]),
                    ),
                ],
            );
        }
        let volume: f64 = link.geoms.iter().map(geom_volume).sum();
        for g in &link.geoms {
            let mass = link
                .inertia
                .is_none()
                .then(|| link.mass * geom_volume(g) / volume.max(1e-12));
            let attrs = geom_attrs(g, self.sim, self.assets, self.collision, mass)?;
            w.empty("geom", &attrs);
        }
        let mut written = 1;
        let here = link.pose.inverse();
        for (k, j) in robot
            .joints
            .iter()
            .enumerate()
            .filter(|(_, j)| j.parent == l)
        {
            let rel = here.mul(&robot.links[j.child].pose);
            written += self.link(j.child, &rel, Some(k), w)?;
        }
        w.close();
        Ok(written)
    }

    /// Hinge `k` in its child's frame: range; in the engine, the servo's friction loss
    /// (its torque limit, as stiff as MuJoCo allows: a time constant of two engine steps);
    /// in an export, the damping that caps the speed at full torque at the servo's speed
    /// limit.
    fn hinge(&self, k: usize, w: &mut XmlWriter) {
        let robot = &self.sim.robot;
        let j = &robot.joints[k];
        let child = robot.links[j.child].pose.inverse();
        let anchor = child.transform_point(j.anchor);
        let axis = child.rotate(j.axis);
        let mut attrs = vec![
            ("name", format!("{}{}", self.prefix, j.name)),
            ("type", "hinge".into()),
            ("pos", mj(&anchor)),
            ("axis", mj(&axis)),
            ("range", mj(&j.limits_deg.map(f64::to_radians))),
        ];
        match self.servos {
            Servos::Velocity => {
                attrs.push(("frictionloss", mj(&[j.max_torque])));
                attrs.push(("solreffriction", mj(&[2.0 * self.dt, 1.0])));
            }
            Servos::Position => attrs.push(("damping", mj(&[j.max_torque / j.max_vel]))),
        }
        w.empty("joint", &attrs);
    }
}

/// A position actuator per hinge (an export's servo): torque limit, and the gain that gives
/// the servo's velocity response `g * error` against the joint damping.
fn actuators(sim: &Simulation, w: &mut XmlWriter) {
    w.open("actuator", &[]);
    for j in &sim.robot.joints {
        let gain = j.servo_gain.unwrap_or(DEFAULT_SERVO_GAIN);
        let damping = j.max_torque / j.max_vel;
        let torque = j.max_torque;
        w.empty(
            "position",
            &[
                ("name", j.name.clone()),
                ("joint", j.name.clone()),
                ("kp", mj(&[gain * damping])),
                ("forcerange", mj(&[-torque, torque])),
                ("ctrlrange", mj(&j.limits_deg.map(f64::to_radians))),
            ],
        );
    }
    w.close();
}
