//! `proleg bench` (throughput figures, a module comparison, the accuracy gate, the stages'
//! shares) and `proleg check-physics` (checks with known answers on each engine).

use std::path::PathBuf;

use crate::bench::physics_checks;
use crate::cli::DEMO_CONFIG;
use crate::cli::error::CliError;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;

/// `proleg bench`: throughput figures, a module comparison or the accuracy gate.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// The reference simulation.
    #[arg(long, default_value = DEMO_CONFIG)]
    pub config: PathBuf,
    /// Simulated seconds per figure.
    #[arg(long, default_value_t = 30.0)]
    pub seconds: f64,
    /// Batch sizes (robots sharing one world) to measure besides 1.
    #[arg(long, value_delimiter = ',', default_values_t = vec![8, 31])]
    pub batches: Vec<usize>,
    /// Instead: compare this module (e.g. the plugin Plugin_sine) with the scenario's
    /// --reference module it replaces, pipeline and control kernel alone.
    #[arg(long)]
    pub module: Option<String>,
    /// The scenario's module that --module replaces.
    #[arg(long, default_value = "PatternGenerator_sinusoidal")]
    pub reference: String,
    /// Instead: the accuracy gate on this simulation: its displacement, final heading
    /// and joint tracking error at the production physics settings against a converged
    /// reference (finer steps, more substeps), for --seconds.
    #[arg(long, value_name = "CONFIG")]
    pub convergence: Option<PathBuf>,
    /// Instead: each stage's share of the step (Sense, Actuate, Kernel, Servo, Physics,
    /// Record, Clock) on rapier and, where its library is, MuJoCo, for --seconds.
    #[arg(long, conflicts_with_all = ["module", "convergence"])]
    pub stages: bool,
    /// Instead: every task of this suite's rate on each engine (the simulation's robot on
    /// the task's first test course) beside the flat floor's, for --seconds.
    #[arg(long, value_name = "SUITE", conflicts_with_all = ["module", "convergence", "stages"])]
    pub suite: Option<PathBuf>,
    /// Most refinements the reference ladder may take.
    #[arg(long, default_value_t = 5)]
    pub rungs: usize,
    /// Physics settings to use instead of the robot's production ones, as
    /// key=value,... (substeps, steps_per_step, length_unit, warmstart_joints,
    /// contact_recycling, coulomb_friction, pgs_iterations, contact_hz, contact_damping,
    /// halfspace_floor, multibody_joints).
    #[arg(long, default_value = "")]
    pub physics: String,
    /// The physics engine instead of the one the simulation file names (rapier,
    /// mujoco); on MuJoCo the figures end with MuJoCo's own rollout of the scenario.
    #[arg(long)]
    pub engine: Option<EngineKind>,
    /// Instead: the shared store's coordinator ceiling on this PostgreSQL store (a new
    /// run in it): evaluations per second handed out and taken back when evaluating costs
    /// nothing (postgres://USER@HOST/DB; password from PGPASSWORD or ~/.pgpass).
    #[arg(long, value_name = "URL", conflicts_with_all = ["module", "convergence", "stages"])]
    pub store: Option<String>,
    /// With --store: client threads claiming, each standing in for a worker host.
    #[arg(long, default_value_t = 8)]
    pub clients: usize,
    /// With --store: evaluations in all.
    #[arg(long, default_value_t = 20_000)]
    pub evaluations: u64,
    /// With --store: evaluations per round (the driver waits for each round).
    #[arg(long, default_value_t = 2_000)]
    pub round: u64,
    /// With --store: evaluations a client claims at once (1: one claim and one write per
    /// evaluation).
    #[arg(long, default_value_t = 64)]
    pub claim_batch: i64,
}

/// `proleg check-physics`: the module and the engines checked.
#[derive(clap::Args, Debug)]
pub struct CheckPhysicsArgs {
    /// The simulation whose robot's first link is the module checked.
    #[arg(long, default_value = DEMO_CONFIG)]
    pub config: PathBuf,
    /// Only this engine (default: rapier, and MuJoCo where its library is).
    #[arg(long)]
    pub engine: Option<EngineKind>,
}

/// `proleg bench`: a module against the one it replaces, the accuracy gate, the stages'
/// shares or the throughput figures, as text.
pub fn run(a: &BenchArgs, registry: &ModuleRegistry) -> Result<String, CliError> {
    if a.stages {
        let report = crate::bench::stages::report(&a.config, a.seconds, registry)?;
        return Ok(report.to_string());
    }
    if let Some(suite) = &a.suite {
        let rates = crate::bench::suite::rates(&a.config, suite, a.seconds, registry)?;
        return Ok(rates.to_string());
    }
    if let Some(url) = &a.store {
        return ceiling(a, url);
    }
    let figures = match (&a.module, &a.convergence) {
        (Some(module), _) => {
            crate::bench::modules::report(&a.config, a.seconds, &a.reference, module, registry)
        }
        (None, Some(config)) => crate::bench::convergence::run(
            config, a.seconds, a.rungs, &a.physics, a.engine, registry,
        ),
        (None, None) => {
            crate::bench::report(&a.config, a.seconds, &a.batches, &a.physics, a.engine)
        }
    };
    Ok(figures?)
}

/// `proleg bench --store`: the coordinator's ceiling on the store at `url`.
fn ceiling(a: &BenchArgs, url: &str) -> Result<String, CliError> {
    use crate::optimize::shared::ceiling::{CeilingSetup, measure_ceiling};
    use crate::optimize::store::StoreLocation;
    let StoreLocation::Postgres(target) = StoreLocation::parse(url)? else {
        return Err(CliError::Option {
            option: "--store",
            value: url.into(),
            want: "a postgres:// store (the coordinator of a SQLite store is the optimizing process)",
        });
    };
    if a.claim_batch < 1 || a.clients == 0 || a.evaluations == 0 || a.round == 0 {
        return Err(CliError::Option {
            option: "--claim-batch / --clients / --evaluations / --round",
            value: format!(
                "{} / {} / {} / {}",
                a.claim_batch, a.clients, a.evaluations, a.round
            ),
            want: "give each at least 1",
        });
    }
    let setup = CeilingSetup {
        evaluations: a.evaluations,
        round: a.round,
        clients: a.clients,
        batch: a.claim_batch,
    };
    let r = measure_ceiling(&target, setup)?;
    Ok(format!(
        "coordinator on {target}: {} evaluations in {:.2} s by {} clients claiming {} at once, rounds of {}\n\
         ceiling         {:.0} evaluations/s ({:.3} ms of store per evaluation)\n",
        r.evaluations,
        r.seconds,
        setup.clients,
        setup.batch,
        setup.round,
        r.per_second(),
        1000.0 / r.per_second()
    ))
}

/// `proleg check-physics`: the checks on each engine asked for, as one report; a check
/// that fails makes the report the error ([`CliError::Failed`], exit status 1).
pub fn check_physics(a: &CheckPhysicsArgs, registry: &ModuleRegistry) -> Result<String, CliError> {
    let base = crate::control::load_simulation_in(&a.config, registry)?;
    let engines = match a.engine {
        Some(e) => vec![e],
        None => crate::sim::engine::ready_engines(),
    };
    let mut text = String::new();
    let mut all_pass = true;
    for e in engines {
        let checks = physics_checks::run(&base, e, registry)?;
        all_pass &= checks.iter().all(|c| c.pass);
        text.push_str(&physics_checks::report(e, &checks));
    }
    if all_pass {
        Ok(text)
    } else {
        Err(CliError::Failed(text))
    }
}
