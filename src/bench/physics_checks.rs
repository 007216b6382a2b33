//! Physical checks with known answers (`proleg check-physics [--engine E]`): one module
//! (the snake's 72-mm tail link, 70 g) alone on the floor at the production settings of an
//! engine, against what physics says exactly:
//!
//! | check | scene | expected |
//! |---|---|---|
//! | friction onset | gravity tilted by θ in 0.5° steps (a tilted floor), μ 0.3, 0.5, 1.0 | slides from θ = atan μ, ±1° |
//! | sliding to rest | launched at 0.5 m/s, μ 0.5 | stops after v² / (2 μ g), ±5 % |
//! | resting contact | 10 s at rest | penetration < 0.5 mm, drift < 1 mm |
//! | drop | released 10 cm above the floor | at rest within 0.5 s, bounce < 2 mm |
//! | servo step | the whole snake without gravity, one joint's target stepped by 30° | the servo model's response (P at the gain, clamped to `maxvel`), ±1° |
//! | pendulum | a module hanging 5° off vertical from an unpowered hinge on a 1-t module resting on a ledge | period 2π √(I / (m g d)), ±1 % |
//! | servo stall | a level link whose weight pulls with 2 x `maxtorque` | gives way pushing with `maxtorque`, ±2 % |
//!
//! The same friction onset and resting contact on a height-field and a trimesh slope are in
//! [`super::terrain_checks`].

use std::fmt::Write as _;

use crate::bench::terrain_checks::{Terrain, resting_on_height_field, slope_onset};
use crate::config::Simulation;
use crate::config::body::Shape;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::sim::{BuildOptions, Simulator};

/// Why a check could not be run (a failing check is a [`Check`] with `pass` false).
#[derive(Debug, thiserror::Error)]
pub enum PhysicsCheckError {
    /// The scene does not build or run on the engine.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// The base simulation lacks what a scene is cut from.
    #[error("the base simulation cannot make this scene: {0}")]
    Scene(&'static str),
}

/// The strength of `base`'s gravity (m/s²): the checks keep it and choose its direction
/// (down, or tilted for a slope), and the answers they expect use it.
fn g(base: &Simulation) -> f64 {
    crate::measure::norm(base.environment.physics.gravity)
}

/// One check: what was measured against what physics says.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// What is checked.
    pub name: String,
    /// Measured value.
    pub measured: f64,
    /// Expected value (or the bound).
    pub expected: f64,
    /// Allowed difference (or, for an upper bound, 0; for a lower bound, -inf).
    pub tolerance: f64,
    /// Unit of the three numbers.
    pub unit: &'static str,
    /// Whether it passes.
    pub pass: bool,
}

impl Check {
    pub(crate) fn within(
        name: String,
        measured: f64,
        expected: f64,
        tolerance: f64,
        unit: &'static str,
    ) -> Check {
        let pass = (measured - expected).abs() <= tolerance;
        Check {
            name,
            measured,
            expected,
            tolerance,
            unit,
            pass,
        }
    }

    pub(crate) fn above(name: String, measured: f64, bound: f64, unit: &'static str) -> Check {
        Check {
            name,
            measured,
            expected: bound,
            tolerance: f64::NEG_INFINITY,
            unit,
            pass: measured > bound,
        }
    }

    pub(crate) fn below(name: String, measured: f64, bound: f64, unit: &'static str) -> Check {
        Check {
            name,
            measured,
            expected: bound,
            tolerance: 0.0,
            unit,
            pass: measured < bound,
        }
    }
}

/// The checks' scene: one module of `base`'s robot (its first link, no joints, no sensors,
/// no modules) on `base`'s floor with friction `mu`, on `engine`.
pub fn module_scene(base: &Simulation, engine: EngineKind, mu: f64) -> Simulation {
    let mut sim = base.clone().with_engine(Some(engine));
    sim.robot.links.truncate(1);
    sim.robot.joints.clear();
    sim.robot.sensors.clear();
    sim.actuation.modules.clear();
    for b in &mut sim.environment.bodies {
        for g in &mut b.geoms {
            g.friction = Some(mu);
        }
    }
    sim.environment.physics.gravity = [0.0, 0.0, -g(base)];
    sim
}

/// Half height of the module's first box (m): its centre of mass rests this high.
pub(crate) fn half_height(sim: &Simulation) -> f64 {
    sim.robot.links[0]
        .geoms
        .iter()
        .find_map(|g| match g.shape {
            Shape::Box { extents } => Some(extents[2]),
            _ => None,
        })
        .unwrap_or(0.0)
}

/// A world of `sim` with one robot, as the checks build it.
pub(crate) fn world(
    sim: &Simulation,
    registry: &ModuleRegistry,
) -> Result<Simulator, PhysicsCheckError> {
    let opts = BuildOptions {
        robots: 1,
        record: false,
        ..Default::default()
    };
    Ok(Simulator::with_registry(sim, &opts, registry)?)
}

fn com(s: &Simulator) -> Result<[f64; 3], PhysicsCheckError> {
    Ok(s.com(0)?)
}

/// Steps of `seconds` in `s`.
fn steps(s: &Simulator, seconds: f64) -> u64 {
    (seconds / s.clock().dt).round() as u64
}

/// The tilt (degrees) from which the module slides with friction `mu`: gravity turned by
/// θ about x, θ from atan μ - 4° in 0.5° steps; sliding = more than 5 mm along the slope
/// in 1 s.
fn friction_onset(
    base: &Simulation,
    engine: EngineKind,
    mu: f64,
    registry: &ModuleRegistry,
) -> Result<Check, PhysicsCheckError> {
    let expected = mu.atan().to_degrees();
    let mut onset = f64::NAN;
    for theta in friction_probe_angles(expected) {
        let mut sim = module_scene(base, engine, mu);
        let t = theta.to_radians();
        sim.environment.physics.gravity = [0.0, -g(base) * t.sin(), -g(base) * t.cos()];
        let mut s = world(&sim, registry)?;
        let start = com(&s)?;
        s.run_steps(steps(&s, 1.0));
        let end = com(&s)?;
        if (start[1] - end[1]) > 0.005 {
            onset = theta;
            break;
        }
    }
    Ok(Check::within(
        format!("friction onset, mu {mu}"),
        onset,
        expected,
        1.0,
        "deg",
    ))
}

/// The tilts an onset search tries: from `expected` - 4° to + 4° in 0.5° steps.
pub(crate) fn friction_probe_angles(expected: f64) -> impl Iterator<Item = f64> {
    (0..=16).map(move |k| (expected - 4.0 + 0.5 * k as f64).max(0.0))
}

/// The distance a module launched at 0.5 m/s slides on friction `mu`.
fn sliding(
    base: &Simulation,
    engine: EngineKind,
    mu: f64,
    registry: &ModuleRegistry,
) -> Result<Check, PhysicsCheckError> {
    let v = 0.5;
    let sim = module_scene(base, engine, mu);
    let mut s = world(&sim, registry)?;
    s.run_steps(steps(&s, 0.2));
    let start = com(&s)?;
    s.set_link_velocity(0, 0, [0.0, v, 0.0])?;
    s.run_steps(steps(&s, 1.0));
    let end = com(&s)?;
    let expected = v * v / (2.0 * mu * g(base));
    Ok(Check::within(
        format!("sliding to rest from 0.5 m/s, mu {mu}"),
        end[1] - start[1],
        expected,
        0.05 * expected,
        "m",
    ))
}

/// Penetration and drift of a module at rest for 10 s.
fn resting(
    base: &Simulation,
    engine: EngineKind,
    registry: &ModuleRegistry,
) -> Result<Vec<Check>, PhysicsCheckError> {
    let sim = module_scene(base, engine, 0.5);
    let h = half_height(&sim);
    rest_figures(world(&sim, registry)?, h, "resting")
}

/// Penetration (below `h`, the resting height of the centre of mass), drift and jitter of
/// the module of `s` over 10 s after 0.5 s to settle, named `what: ...`.
pub(crate) fn rest_figures(
    mut s: Simulator,
    h: f64,
    what: &str,
) -> Result<Vec<Check>, PhysicsCheckError> {
    s.run_steps(steps(&s, 0.5));
    let start = com(&s)?;
    let (mut deepest, mut highest) = (f64::INFINITY, f64::NEG_INFINITY);
    for _ in 0..100 {
        s.run_steps(steps(&s, 0.1));
        let z = com(&s)?[2];
        deepest = deepest.min(z);
        highest = highest.max(z);
    }
    let end = com(&s)?;
    let drift = ((end[0] - start[0]).powi(2) + (end[1] - start[1]).powi(2)).sqrt();
    Ok(vec![
        Check::below(
            format!("{what}: penetration"),
            (h - deepest).max(0.0) * 1000.0,
            0.5,
            "mm",
        ),
        Check::below(format!("{what}: drift in 10 s"), drift * 1000.0, 1.0, "mm"),
        Check::below(
            format!("{what}: jitter (z range)"),
            (highest - deepest) * 1000.0,
            0.1,
            "mm",
        ),
    ])
}

/// A module dropped from 10 cm: when it comes to rest, and how high it bounces.
fn drop(
    base: &Simulation,
    engine: EngineKind,
    registry: &ModuleRegistry,
) -> Result<Vec<Check>, PhysicsCheckError> {
    let mut sim = module_scene(base, engine, 0.5);
    sim.environment.robot_pose.translation[2] += 0.1;
    let h = half_height(&sim);
    let mut s = world(&sim, registry)?;
    let (mut landed, mut bounce, mut rest) = (false, 0.0f64, f64::NAN);
    let mut previous = com(&s)?[2];
    for k in 1..=steps(&s, 1.0) {
        s.step();
        let z = com(&s)?[2];
        let t = k as f64 * s.clock().dt;
        if !landed && z <= h + 0.001 {
            landed = true;
        }
        if landed {
            bounce = bounce.max(z - h);
            let settled = (z - previous).abs() / s.clock().dt < 0.005 && (z - h).abs() < 0.001;
            if settled && rest.is_nan() {
                rest = t;
            } else if !settled {
                rest = f64::NAN;
            }
        }
        previous = z;
    }
    Ok(vec![
        Check::below("drop from 10 cm: at rest after".into(), rest, 0.5, "s"),
        Check::below("drop from 10 cm: bounce".into(), bounce * 1000.0, 2.0, "mm"),
    ])
}

/// The largest difference (degrees) between joint 2's angle and the servo model's response
/// to a 30° step of its target, the snake floating without gravity (the servo's only load
/// is the links' inertia), over 0.3 s. The model is the servo stage's own discrete law:
/// each step the joint turns at the commanded speed, gain x error clamped to `maxvel`.
fn servo_step(
    base: &Simulation,
    engine: EngineKind,
    registry: &ModuleRegistry,
) -> Result<Check, PhysicsCheckError> {
    let mut sim = base.clone().with_engine(Some(engine));
    sim.environment.physics.gravity = [0.0; 3];
    sim.environment.robot_pose.translation[2] += 0.5;
    let joint = 2;
    let j = &sim.robot.joints[joint];
    let (gain, vmax) = (
        j.servo_gain
            .unwrap_or(crate::sim::servo::DEFAULT_SERVO_GAIN),
        j.max_vel.to_degrees(),
    );
    let mut s = world(&sim, registry)?;
    let dt = s.clock().dt;
    let mut targets = vec![0.0; sim.robot.joints.len()];
    targets[joint] = 30.0;
    s.set_joint_override(0, Some(targets))?;
    let (mut model, mut worst) = (0.0f64, 0.0f64);
    for _ in 0..steps(&s, 0.3) {
        s.step();
        model += (gain * (30.0 - model)).clamp(-vmax, vmax) * dt;
        let angle = s.joint_states(0)?[joint].angle;
        worst = worst.max((angle - model).abs());
    }
    Ok(Check::below(
        "servo step of 30 deg: largest error vs the model".into(),
        worst,
        1.0,
        "deg",
    ))
}

/// The hanging link of a [`hinge_scene`]: mass (kg), distance of its centre of mass from
/// the hinge (m), moment of inertia about the hinge (kg m²).
struct Hanging {
    mass: f64,
    distance: f64,
    inertia: f64,
}

/// How the hinge scene is set: the second link's angle `phi` (degrees), its mass (`None`:
/// its own) and the ledge's `gap` short of the hinge (m).
#[derive(Debug, Clone, Copy)]
struct HingePose {
    phi: f64,
    mass: Option<f64>,
    gap: f64,
}

/// The first two links of `base`'s robot on `engine`: the first made 1 t and resting on a
/// ledge (a static box whose edge stops `gap` m short of the hinge), the second turned
/// about the hinge by `phi` degrees (-90: hanging straight down; 0: level, as built) and
/// made `mass` kg (`None`: its own), the hinge's limits wide.
fn hinge_scene(
    base: &Simulation,
    engine: EngineKind,
    pose: HingePose,
) -> Result<(Simulation, Hanging), PhysicsCheckError> {
    let HingePose { phi, mass, gap } = pose;
    use crate::config::body::BodyKind;
    use crate::config::transform::Pose;
    let mut sim = module_scene(base, engine, 0.5);
    if base.robot.links.len() < 2 || base.robot.joints.is_empty() {
        return Err(PhysicsCheckError::Scene("a robot of two links and a hinge"));
    }
    sim.robot.links = base.robot.links[..2].to_vec();
    sim.robot.joints = base.robot.joints[..1].to_vec();
    let j = &mut sim.robot.joints[0];
    j.limits_deg = [-179.0, 179.0];
    let (anchor, axis) = (j.anchor, j.axis);
    sim.robot.links[0].mass = 1000.0;
    let half = phi.to_radians() / 2.0;
    let turn = Pose {
        translation: [0.0; 3],
        rotation: [
            half.cos(),
            axis[0] * half.sin(),
            axis[1] * half.sin(),
            axis[2] * half.sin(),
        ],
    };
    let about_anchor = Pose::from_translation(anchor)
        .mul(&turn)
        .mul(&Pose::from_translation(anchor.map(|c| -c)));
    let link = &mut sim.robot.links[1];
    link.pose = about_anchor.mul(&link.pose);
    if let Some(m) = mass {
        link.mass = m;
    }
    // The ledge: everything below the first link up to `gap` before the hinge.
    let floor = sim
        .environment
        .bodies
        .first_mut()
        .ok_or(PhysicsCheckError::Scene("no floor"))?;
    floor.kind = BodyKind::Static;
    floor.pose = Pose::from_translation([0.0, anchor[1] - 0.5 - gap, -0.5]);
    if let Some(g) = floor.geoms.first_mut() {
        g.shape = Shape::Box {
            extents: [0.5, 0.5, 0.5],
        };
        g.pose = Pose::IDENTITY;
    }
    sim.environment.bodies.truncate(1);
    // The physical pendulum: the hanging link's box about the hinge.
    let l = &base.robot.links[1];
    let g = l
        .geoms
        .first()
        .ok_or(PhysicsCheckError::Scene("the second link has no geometry"))?;
    let Shape::Box {
        extents: [_, ey, ez],
    } = g.shape
    else {
        return Err(PhysicsCheckError::Scene(
            "the second link's geometry is not a box",
        ));
    };
    let centre = l.pose.mul(&g.pose).translation;
    let d = ((centre[1] - anchor[1]).powi(2) + (centre[2] - anchor[2]).powi(2)).sqrt();
    let m = mass.unwrap_or(l.mass);
    let inertia = m / 3.0 * (ey * ey + ez * ez) + m * d * d;
    Ok((
        sim,
        Hanging {
            mass: m,
            distance: d,
            inertia,
        },
    ))
}

/// A module hanging from an unpowered hinge, 5° off vertical: its period against the
/// physical pendulum's 2 pi sqrt(I / (m g d)).
fn pendulum(
    base: &Simulation,
    engine: EngineKind,
    registry: &ModuleRegistry,
) -> Result<Check, PhysicsCheckError> {
    let (mut sim, h) = hinge_scene(
        base,
        engine,
        HingePose {
            phi: -85.0,
            mass: None,
            gap: 0.03,
        },
    )?;
    sim.robot.joints[0].max_torque = 0.0;
    let expected =
        2.0 * std::f64::consts::PI * (h.inertia / (h.mass * g(base) * h.distance)).sqrt();
    // Measured: the mean time between upward zero crossings of the angle about its mean.
    let mut s = world(&sim, registry)?;
    let dt = s.clock().dt;
    let angles: Vec<f64> = (0..steps(&s, 3.0))
        .map(|_| {
            s.step();
            s.joint_states(0).map_or(f64::NAN, |j| j[0].angle)
        })
        .collect();
    let mean = angles.iter().sum::<f64>() / angles.len().max(1) as f64;
    let ups: Vec<f64> = angles
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < mean && w[1] >= mean)
        .map(|(k, _)| k as f64 * dt)
        .collect();
    let measured = match (ups.first(), ups.last()) {
        (Some(a), Some(b)) if ups.len() > 2 => (b - a) / (ups.len() - 1) as f64,
        _ => f64::NAN,
    };
    Ok(Check::within(
        "pendulum: period of a 5-deg swing".into(),
        measured,
        expected,
        0.01 * expected,
        "s",
    ))
}

/// A servo against a load twice its torque limit: a level link made so heavy that
/// gravity's torque about the hinge is 2 x `maxtorque`, its target level. The servo stalls:
/// it gives way (the link sinks more than 10° below its target within 0.5 s) while
/// pushing with exactly its `maxtorque` (the mean while the link sinks through its first
/// 30°, where the load stays above 1.7 x `maxtorque`; within 2 %).
fn servo_stall(
    base: &Simulation,
    engine: EngineKind,
    registry: &ModuleRegistry,
) -> Result<Vec<Check>, PhysicsCheckError> {
    let limit = base
        .robot
        .joints
        .first()
        .map(|j| j.max_torque)
        .ok_or(PhysicsCheckError::Scene("a robot with a hinge"))?;
    let (_, level) = hinge_scene(
        base,
        engine,
        HingePose {
            phi: 0.0,
            mass: None,
            gap: 0.03,
        },
    )?;
    let mass = 2.0 * limit / (g(base) * level.distance);
    let (sim, _) = hinge_scene(
        base,
        engine,
        HingePose {
            phi: 0.0,
            mass: Some(mass),
            gap: 0.03,
        },
    )?;
    let mut s = world(&sim, registry)?;
    s.set_joint_override(0, Some(vec![0.0]))?;
    // While the link sinks through its first 30° the load stays above 1.7 x maxtorque.
    let (mut sunk, mut torque, mut k) = (0.0f64, 0.0, 0u32);
    for _ in 0..steps(&s, 0.5) {
        s.step();
        let j = s.joint_states(0)?[0];
        if sunk < 30.0 {
            torque += j.torque.abs();
            k += 1;
        }
        sunk = sunk.max(j.angle.abs());
    }
    let torque = torque / f64::from(k.max(1));
    Ok(vec![
        Check::above(
            "servo stall at 2x maxtorque: gives way".into(),
            sunk,
            10.0,
            "deg",
        ),
        Check::within(
            "servo stall at 2x maxtorque: torque".into(),
            torque,
            limit,
            0.02 * limit,
            "N m",
        ),
    ])
}

/// Every check on `engine`, the module taken from `base` (the demo's snake).
pub fn run(
    base: &Simulation,
    engine: EngineKind,
    registry: &ModuleRegistry,
) -> Result<Vec<Check>, PhysicsCheckError> {
    let mut checks = Vec::new();
    for mu in [0.3, 0.5, 1.0] {
        checks.push(friction_onset(base, engine, mu, registry)?);
    }
    for terrain in [Terrain::HeightField, Terrain::Triangles] {
        checks.push(slope_onset(base, engine, 0.5, terrain, registry)?);
    }
    checks.push(sliding(base, engine, 0.5, registry)?);
    checks.extend(resting(base, engine, registry)?);
    checks.extend(resting_on_height_field(base, engine, registry)?);
    checks.extend(drop(base, engine, registry)?);
    checks.push(servo_step(base, engine, registry)?);
    checks.extend(servo_stall(base, engine, registry)?);
    checks.push(pendulum(base, engine, registry)?);
    Ok(checks)
}

/// The checks as a table.
pub fn report(engine: EngineKind, checks: &[Check]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "physical checks on {engine} (production settings)");
    let _ = writeln!(
        out,
        "{:<42} {:>10} {:>16}  result",
        "check", "measured", "expected"
    );
    for c in checks {
        let expected = if c.tolerance > 0.0 {
            format!("{:.4} ± {:.4}", c.expected, c.tolerance)
        } else if c.tolerance < 0.0 {
            format!("> {:.4}", c.expected)
        } else {
            format!("< {:.4}", c.expected)
        };
        let _ = writeln!(
            out,
            "{:<42} {:>10.4} {:>16} {}  {}",
            c.name,
            c.measured,
            expected,
            c.unit,
            if c.pass { "PASS" } else { "FAIL" }
        );
    }
    let failed = checks.iter().filter(|c| !c.pass).count();
    let _ = writeln!(
        out,
        "{} of {} checks pass",
        checks.len() - failed,
        checks.len()
    );
    out
}
