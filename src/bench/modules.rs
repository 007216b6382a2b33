//! Module overhead (`proleg bench --module NAME`): a module (typically a plugin) against
//! the standard module it stands in for, in the reference scenario. The module replaces
//! the scenario's module of the same kind (same parameter names and values), and two
//! figures are compared: the full pipeline (what a user's run costs) and the control
//! kernel alone (the module's own cost, without physics to hide it).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use crate::config::Simulation;
use crate::control::load_simulation;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::rng::SimRng;

use super::{BenchError, world_of};
use crate::sim::SimError;

/// Rounds of the comparison; each round measures both modules, one after the other, so
/// a slow spell of the (shared) machine hits both; the fastest round of each counts.
pub const ROUNDS: usize = 5;

/// The simulation with every module of type `from` replaced by `to` (parameters by name).
pub fn swap_module(
    sim: &Simulation,
    from: &str,
    to: &str,
    registry: &ModuleRegistry,
) -> Result<Simulation, BenchError> {
    let target = registry
        .get(to)
        .ok_or_else(|| {
            BenchError::ModuleSwap(format!(
                "no module {to} is registered (build the plugins: proleg plugin build); known: {}",
                registry.names().join(", ")
            ))
        })?
        .clone();
    let mut out = sim.clone();
    let mut swapped = 0;
    for m in out.actuation.modules.iter_mut() {
        if !crate::config::xml::read::same_name(m.descriptor.type_name, from) {
            continue;
        }
        for p in m.params.iter_mut() {
            p.name = target
                .parameter(p.name)
                .ok_or_else(|| {
                    BenchError::ModuleSwap(format!("{to} has no parameter {} of {from}", p.name))
                })?
                .name;
        }
        m.descriptor = target.clone();
        swapped += 1;
    }
    if swapped == 0 {
        return Err(BenchError::ModuleSwap(format!(
            "the reference scenario has no {from} module to replace"
        )));
    }
    Ok(out)
}

/// A kernel of the scenario's actuation, reset, ready to step.
fn kernel(sim: &Simulation, registry: &ModuleRegistry) -> Result<ControlKernel, BenchError> {
    let limits: Vec<[f64; 2]> = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let mut k = ControlKernel::from_actuation(&sim.actuation, registry, limits)
        .map_err(SimError::Kernel)?;
    k.reset(&mut SimRng::new(1));
    Ok(k)
}

/// Wall seconds of `steps` steps of the kernel alone, joint angles held at 0.
fn kernel_once(template: &ControlKernel, dt: f64, steps: u64) -> Result<f64, BenchError> {
    let mut k = template.clone();
    let measured = vec![0.0; k.joints()];
    let mut checksum = 0.0;
    let t = Instant::now();
    for step in 0..steps {
        checksum += k.compute(step as f64 * dt, dt, step, &measured)[0];
    }
    let wall = t.elapsed().as_secs_f64();
    if !checksum.is_finite() {
        return Err(BenchError::NonFiniteAngles);
    }
    Ok(wall)
}

/// Wall seconds of `seconds` simulated by the full pipeline, after a second of warm-up.
fn pipeline_once(
    sim: &Simulation,
    seconds: f64,
    registry: &ModuleRegistry,
) -> Result<(f64, u64), BenchError> {
    let mut s = world_of(sim, 1, registry, None)?;
    let dt = s.clock().dt;
    s.run_steps((1.0 / dt).round() as u64);
    let steps = (seconds / dt).round() as u64;
    let t = Instant::now();
    s.run_steps(steps);
    Ok((t.elapsed().as_secs_f64(), steps))
}

/// The comparison of module `module` with the reference scenario's `reference` module.
pub fn report(
    config: &Path,
    seconds: f64,
    reference: &str,
    module: &str,
    registry: &ModuleRegistry,
) -> Result<String, BenchError> {
    let base = load_simulation(config)?;
    let swapped = swap_module(&base, reference, module, registry)?;
    let dt = base.files.simulation.properties.step_width;
    let (ka_template, kb_template) = (kernel(&base, registry)?, kernel(&swapped, registry)?);
    let kernel_steps = 1_000_000;
    let (mut pa, mut pb, mut ka, mut kb) =
        (f64::INFINITY, f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut steps = 0;
    for _ in 0..ROUNDS {
        let (wall, n) = pipeline_once(&base, seconds, registry)?;
        pa = pa.min(wall);
        steps = n;
        pb = pb.min(pipeline_once(&swapped, seconds, registry)?.0);
        ka = ka.min(kernel_once(&ka_template, dt, kernel_steps)?);
        kb = kb.min(kernel_once(&kb_template, dt, kernel_steps)?);
    }
    let rate = |wall: f64| steps as f64 / wall;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "module {module} in place of {reference}: {}, {seconds} s simulated, best of {ROUNDS} alternating rounds, 1 core",
        config.display()
    );
    let _ = writeln!(
        out,
        "{:<36} {:>16} {:>16} {:>10}",
        "", reference, module, "ratio"
    );
    let _ = writeln!(
        out,
        "{:<36} {:>16.0} {:>16.0} {:>9.3}x",
        "pipeline robot-steps/s",
        rate(pa),
        rate(pb),
        pa / pb
    );
    let _ = writeln!(
        out,
        "{:<36} {:>16.0} {:>16.0} {:>9.3}x",
        "control kernel alone, steps/s",
        kernel_steps as f64 / ka,
        kernel_steps as f64 / kb,
        ka / kb
    );
    let _ = writeln!(
        out,
        "real-time factor of the pipeline: {:.1}x vs {:.1}x",
        rate(pa) * dt,
        rate(pb) * dt
    );
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swapping_to_an_unknown_module_or_from_an_absent_one_is_an_error() {
        let config = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/demo.simulation.xml");
        let sim = load_simulation(&config).unwrap();
        let e = swap_module(
            &sim,
            "PatternGenerator_sinusoidal",
            "Nope",
            &ModuleRegistry::standard(),
        )
        .unwrap_err();
        assert!(
            matches!(&e, BenchError::ModuleSwap(m) if m.contains("no module Nope")),
            "{e}"
        );
        let e = swap_module(
            &sim,
            "Global_Adaptive_Touch",
            "DirectJointAccess",
            &ModuleRegistry::standard(),
        )
        .unwrap_err();
        assert!(
            matches!(&e, BenchError::ModuleSwap(m) if m.contains("no Global_Adaptive_Touch module")),
            "{e}"
        );
        let e = swap_module(
            &sim,
            "PatternGenerator_sinusoidal",
            "DirectJointAccess",
            &ModuleRegistry::standard(),
        )
        .unwrap_err();
        assert!(
            matches!(&e, BenchError::ModuleSwap(m) if m.contains("DirectJointAccess has no parameter Amplitude")),
            "{e}"
        );
    }
}
