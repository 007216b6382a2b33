//! The human-readable summary `proleg check` prints for a loaded simulation.

use std::fmt::Write as _;

use crate::config::actuation::ParamValue;
use crate::config::body::BodyKind;
use crate::config::optimizer::{Algorithm, describe_range};
use crate::config::resolve::Simulation;
use crate::config::sensor::Sensor;
use crate::config::xml::write::{num, nums};

fn round(v: f64, digits: i32) -> String {
    let f = 10f64.powi(digits);
    num((v * f).round() / f)
}

/// Formats the summary of a loaded simulation: the simulation's properties, the robot,
/// the actuation, the environment, the optimizer, and the warnings.
pub fn summary(sim: &Simulation) -> String {
    let mut s = String::new();
    simulation_part(&mut s, sim);
    robot_part(&mut s, sim);
    actuation_part(&mut s, sim);
    environment_part(&mut s, sim);
    optimizer_part(&mut s, sim);
    for w in &sim.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    s
}

fn simulation_part(s: &mut String, sim: &Simulation) {
    let p = &sim.files.simulation.properties;
    let _ = writeln!(s, "simulation  {}", sim.file.display());
    if let Some(d) = &sim.files.simulation.description {
        let _ = writeln!(s, "  {d}");
    }
    let _ = writeln!(
        s,
        "  mode {}, physics {}, step {} ms, duration {} s ({} steps), seed {}, sampling every {} steps, recording {}",
        p.mode,
        p.engine,
        num(p.step_width * 1000.0),
        num(p.duration),
        (p.duration / p.step_width).round(),
        p.seed,
        p.accuracy,
        if p.storing_data { "on" } else { "off" }
    );
}

fn robot_part(s: &mut String, sim: &Simulation) {
    let r = &sim.robot;
    let _ = writeln!(s, "robot       {} ({})", r.name, r.file.display());
    let _ = writeln!(
        s,
        "  links {}: {}; total mass {} kg",
        r.links.len(),
        r.links
            .iter()
            .map(|l| l.name.as_str())
            .collect::<Vec<_>>()
            .join(" "),
        round(r.total_mass(), 4)
    );
    let _ = writeln!(s, "  joints {} [{}]:", r.joints.len(), r.pattern());
    for (i, j) in r.joints.iter().enumerate() {
        let _ = writeln!(
            s,
            "    {i} {:<6} {:<5} {} -> {}  limits {}..{} deg, max {} N·m, {} rad/s",
            j.name,
            j.orientation.to_string(),
            r.links[j.parent].name,
            r.links[j.child].name,
            num(j.limits_deg[0]),
            num(j.limits_deg[1]),
            num(j.max_torque),
            num(j.max_vel)
        );
    }
    let tactile = r
        .sensors
        .iter()
        .filter(|x| matches!(x.sensor, Sensor::Tactile(_)))
        .count();
    let lasers = r.sensors.len() - tactile;
    let _ = writeln!(
        s,
        "  sensors {}: {tactile} tactile, {lasers} laser",
        r.sensors.len()
    );
    let servos: Vec<String> = r
        .servos
        .joints
        .iter()
        .enumerate()
        .map(|(j, v)| {
            let sign = if v.direction < 0.0 { "-" } else { "" };
            format!("J{}={sign}{}", j + 1, v.id)
        })
        .collect();
    let _ = writeln!(
        s,
        "  servos ({} at {} baud, read every {} steps): {}",
        r.servos.driver,
        r.servos.baud,
        r.servos.read_every,
        servos.join(" ")
    );
}

fn actuation_part(s: &mut String, sim: &Simulation) {
    let _ = writeln!(s, "actuation   {}", sim.actuation.file.display());
    for m in &sim.actuation.modules {
        let params: Vec<String> = m
            .params
            .iter()
            .map(|p| match &p.value {
                ParamValue::Uniform(v) => format!("{}={}", p.name, num(*v)),
                ParamValue::PerJoint(v) => format!("{}=[{}]", p.name, nums(v)),
            })
            .collect();
        let _ = writeln!(
            s,
            "  {:<28} joints {}  {}",
            m.descriptor.type_name,
            m.joints,
            params.join(" ")
        );
    }
}

fn environment_part(s: &mut String, sim: &Simulation) {
    let e = &sim.environment;
    match &e.file {
        Some(f) => {
            let _ = writeln!(s, "environment {}", f.display());
        }
        None => {
            let _ = writeln!(s, "environment (none)");
        }
    }
    let _ = writeln!(
        s,
        "  gravity {}, self-collision {}, {} articulation, {} objects",
        nums(&e.physics.gravity),
        if e.physics.self_collision {
            "on"
        } else {
            "off"
        },
        e.physics.articulation.name(),
        e.bodies.len()
    );
    for b in &e.bodies {
        let kind = match b.kind {
            BodyKind::Static => "static",
            BodyKind::Dynamic => "dynamic",
        };
        let geoms: Vec<String> = b.geoms.iter().map(|g| g.shape.describe()).collect();
        let shown = if geoms.len() > 3 {
            format!("{} and {} more", geoms[..3].join(", "), geoms.len() - 3)
        } else {
            geoms.join(", ")
        };
        let _ = writeln!(
            s,
            "    {} ({kind}) at {}: {shown}",
            b.name,
            nums(&b.pose.translation.map(|v| (v * 1e4).round() / 1e4))
        );
    }
    let _ = writeln!(
        s,
        "  robot pose: translation {}, rotation {}",
        nums(&e.robot_pose.translation),
        nums(&e.robot_pose.rotation)
    );
}

fn optimizer_part(s: &mut String, sim: &Simulation) {
    let Some(o) = &sim.optimizer else {
        return;
    };
    let _ = writeln!(s, "optimizer   {} ({})", o.spec.label(), o.file.display());
    algorithm_line(s, &o.spec.algorithm);
    for p in &o.parameters {
        let g = &p.genome;
        let values = if g.value_space == 0 {
            format!("values {}", nums(&g.values))
        } else {
            let pick = |v: &Vec<f64>| v[0];
            describe_range(pick(&g.lower), pick(&g.upper), pick(&g.increments))
        };
        let _ = writeln!(
            s,
            "  p{} {}.{} joints {} {} {} ({} {})",
            p.number,
            p.module,
            p.parameter.name,
            g.active_joints,
            if g.uniform { "uniform" } else { "individual" },
            values,
            if p.network {
                "one per network".to_string()
            } else {
                p.genes.to_string()
            },
            if p.network {
                "weight"
            } else if p.genes == 1 {
                "gene"
            } else {
                "genes"
            }
        );
    }
    let _ = writeln!(s, "  search space {:.4e} candidates", o.search_space());
}

/// The optimizer's settings, one line.
fn algorithm_line(s: &mut String, algorithm: &Algorithm) {
    match algorithm {
        Algorithm::Genetic(g) => {
            let _ = writeln!(
                s,
                "  population {}, p(mutation) {}, p(crossover) {}, convergence {} over {} generations",
                g.popsize,
                num(g.pmut),
                num(g.pcross),
                num(g.p_convergence),
                g.n_convergence
            );
        }
        Algorithm::GreatDeluge(g) => {
            let _ = writeln!(
                s,
                "  credits {}, retries {}, initial water level {}, rain {}, confidence {}",
                g.credits,
                g.retries,
                num(g.initial_water_level),
                num(g.rain),
                g.confidence
            );
        }
        Algorithm::Es(e) => {
            let _ = writeln!(
                s,
                "  population {} (antithetic pairs), sigma {}, learning rate {}, weight decay {} (fractions of each gene's range)",
                e.popsize,
                num(e.sigma),
                num(e.learning_rate),
                num(e.weight_decay)
            );
        }
        Algorithm::MapElites(m) => {
            let axes: Vec<String> = m
                .descriptors
                .iter()
                .map(|d| match d.yaw_share {
                    true => format!("yaw share in {} cells", d.bins),
                    false => format!("gene {} in {} cells", d.gene, d.bins),
                })
                .collect();
            let _ = writeln!(
                s,
                "  {} random candidates, then {} mutants per round (mutation {}); archive over {}",
                m.initial,
                m.batch,
                num(m.mutation),
                axes.join(" x ")
            );
        }
        Algorithm::CmaEs(c) => {
            let _ = writeln!(
                s,
                "  population {}, initial step size {} of each range, {} IPOP restarts",
                if c.popsize == 0 {
                    "4 + 3 ln n".to_string()
                } else {
                    c.popsize.to_string()
                },
                num(c.sigma),
                c.restarts
            );
        }
    }
}
