//! The accuracy gate (`proleg bench --convergence CONFIG [--engine E]`): a scenario run at
//! the production physics settings and along a ladder of refinements until one more
//! refinement moves the displacement by less than [`CONVERGED`]; the last rung is the
//! converged reference. On rapier every physics step is split in 2, 4, 8, ... steps, each
//! with more solver substeps, exact Coulomb friction and no contact recycling; on MuJoCo in
//! 2, 4, 8, ... steps with the elliptic cone and twice the solver iterations. Prints displacement, final
//! heading and mean joint tracking error of each run and the production run's distance from
//! the reference; the gate is [`GATE`] on the displacement. The test suite runs it on the
//! four gate scenarios (tests/sim_convergence.rs) so no change trades accuracy for speed
//! unseen.

use std::fmt::Write as _;
use std::time::Instant;

use crate::bench::BenchError;
use crate::config::Simulation;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::measure::ground_distance;
use crate::sim::engine::EngineSettings;
use crate::sim::{BuildOptions, Simulator};

/// A refinement that changes the displacement by less than this fraction has converged.
pub const CONVERGED: f64 = 0.01;
/// The gate: production displacement within this fraction of the converged reference.
pub const GATE: f64 = 0.05;

/// What one run of a scenario did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RungOutcome {
    /// The engine and settings it ran with.
    pub settings: EngineSettings,
    /// Ground-plane distance of robot 0's centre of mass, start to end (m).
    pub displacement: f64,
    /// Tail-to-head heading at the end (degrees from +x).
    pub heading: f64,
    /// Mean over steps and joints of |servo target - joint angle| (degrees).
    pub tracking_error: f64,
    /// Wall-clock seconds the run took.
    pub wall: f64,
    /// Simulated seconds.
    pub seconds: f64,
}

impl RungOutcome {
    /// Simulated seconds per wall second.
    pub fn realtime_factor(&self) -> f64 {
        self.seconds / self.wall.max(1e-9)
    }

    /// Relative displacement difference from `reference`.
    pub fn displacement_error(&self, reference: &RungOutcome) -> f64 {
        (self.displacement - reference.displacement).abs() / reference.displacement.abs().max(1e-9)
    }

    /// Heading difference from `reference` (degrees, -180 ..= 180).
    pub fn heading_difference(&self, reference: &RungOutcome) -> f64 {
        let d = (self.heading - reference.heading).rem_euclid(360.0);
        if d > 180.0 { d - 360.0 } else { d }
    }
}

/// Runs `sim` for `seconds` with `settings` and measures what robot 0 did.
pub fn episode(
    sim: &Simulation,
    settings: EngineSettings,
    seconds: f64,
    registry: &ModuleRegistry,
) -> Result<RungOutcome, BenchError> {
    let opts = BuildOptions {
        robots: 1,
        seed: sim.files.simulation.properties.seed,
        record: false,
        engine: settings.into(),
        ..Default::default()
    };
    let mut s = Simulator::with_registry(sim, &opts, registry)?;
    let steps = (seconds / s.clock().dt).round().max(1.0) as u64;
    let start = s.com(0)?;
    let mut tracking = 0.0;
    let t = Instant::now();
    for _ in 0..steps {
        s.step();
        tracking += s.tracking_error(0)?;
    }
    let wall = t.elapsed().as_secs_f64();
    let end = s.com(0)?;
    let heading = s.heading(0)?;
    if !(end.iter().all(|v| v.is_finite()) && heading.is_finite()) {
        return Err(BenchError::BlewUp {
            settings: settings.to_string(),
        });
    }
    Ok(RungOutcome {
        settings,
        displacement: ground_distance(start, end),
        heading,
        tracking_error: tracking / steps as f64,
        wall,
        seconds: steps as f64 * s.clock().dt,
    })
}

/// A production run and its reference ladder.
#[derive(Debug, Clone, PartialEq)]
pub struct Convergence {
    /// The scenario (for printing).
    pub name: String,
    /// The run at the settings under test.
    pub production: RungOutcome,
    /// The refinements, coarsest first; the last is the reference.
    pub ladder: Vec<RungOutcome>,
    /// Whether the last refinement changed the displacement by less than [`CONVERGED`].
    pub converged: bool,
}

impl Convergence {
    /// The converged reference (the finest rung).
    pub fn reference(&self) -> &RungOutcome {
        self.ladder.last().unwrap_or(&self.production)
    }

    /// The production run's displacement error relative to the reference.
    pub fn displacement_error(&self) -> f64 {
        self.production.displacement_error(self.reference())
    }

    /// Whether the production run passes the gate against a converged reference.
    pub fn passes(&self) -> bool {
        self.converged && self.displacement_error() <= GATE
    }
}

/// Runs `sim` for `seconds` with `production` settings, then refines until converged (at
/// most `max_rungs` rungs).
pub fn check(
    name: &str,
    sim: &Simulation,
    production: EngineSettings,
    seconds: f64,
    max_rungs: usize,
    registry: &ModuleRegistry,
) -> Result<Convergence, BenchError> {
    let production_run = episode(sim, production, seconds, registry)?;
    let mut ladder: Vec<RungOutcome> = Vec::new();
    let mut settings = production.reference();
    let mut converged = false;
    while ladder.len() < max_rungs.max(2) {
        let run = episode(sim, settings, seconds, registry)?;
        if let Some(previous) = ladder.last() {
            converged = run.displacement_error(previous) < CONVERGED;
        }
        ladder.push(run);
        if converged {
            break;
        }
        settings = settings.refined(2);
    }
    Ok(Convergence {
        name: name.to_string(),
        production: production_run,
        ladder,
        converged,
    })
}

/// The check, formatted for the terminal.
pub fn report(c: &Convergence) -> String {
    let mut out = String::new();
    let r = c.reference();
    let _ = writeln!(
        out,
        "{}: {:.1} s simulated; reference = the finest rung ({})",
        c.name,
        r.seconds,
        if c.converged {
            "converged: its last refinement moved the displacement < 1 %"
        } else {
            "NOT converged within the rungs allowed"
        }
    );
    let _ = writeln!(
        out,
        "{:<12} {:>8} {:>9} {:>14} {:>12} {:>10}  settings",
        "run", "disp (m)", "vs ref", "heading (deg)", "track (deg)", "real-time"
    );
    let rows = std::iter::once(("production".to_string(), &c.production)).chain(
        c.ladder
            .iter()
            .enumerate()
            .map(|(i, o)| (format!("rung {}", i + 1), o)),
    );
    for (label, o) in rows {
        let _ = writeln!(
            out,
            "{:<12} {:>8.4} {:>8.2}% {:>14.1} {:>12.2} {:>9.1}x  {}",
            label,
            o.displacement,
            100.0 * o.displacement_error(r),
            o.heading,
            o.tracking_error,
            o.realtime_factor(),
            o.settings
        );
    }
    let p = &c.production;
    let _ = writeln!(
        out,
        "production vs reference: displacement {:+.2} %, final heading {:+.1} deg, tracking error {:+.2} deg; gate (displacement within {:.0} %): {}",
        100.0 * (p.displacement - r.displacement) / r.displacement.abs().max(1e-9),
        p.heading_difference(r),
        p.tracking_error - r.tracking_error,
        100.0 * GATE,
        if c.passes() { "PASS" } else { "FAIL" }
    );
    out
}

/// `proleg bench --convergence CONFIG`: the check of one configuration, its production
/// settings changed by `overrides` (`key=value,...`), printed; an error when it fails the
/// gate, so scripts can stop on it.
pub fn run(
    config: &std::path::Path,
    seconds: f64,
    max_rungs: usize,
    overrides: &str,
    engine: Option<EngineKind>,
    registry: &ModuleRegistry,
) -> Result<String, BenchError> {
    let sim = crate::control::load_simulation_in(config, registry)?.with_engine(engine);
    let production = EngineSettings::of(&sim, overrides)?;
    let c = check(
        &config.display().to_string(),
        &sim,
        production,
        seconds,
        max_rungs,
        registry,
    )?;
    let text = report(&c);
    if c.passes() {
        Ok(text)
    } else {
        Err(BenchError::GateFailed(text))
    }
}
