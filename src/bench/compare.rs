//! `proleg compare`: one simulation run closed loop on each engine, measured the same way —
//! displacement and heading, how well the joints track their servo targets, how deep and
//! how often the links touch the ground, how fast their contacts slide — with the spread
//! between the engines, and the centre-of-mass paths and joint angles drawn into one PNG
//! ([`super::compare_plot`]). The measured reason why two engines disagree on a gait.

use std::fmt;

use crate::config::Simulation;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::measure::ground_distance;
use crate::sim::engine::BodyId;
use crate::sim::{BuildOptions, SimError, Simulator};

/// Samples of the paths and joint angles kept per simulated second (for the plot).
const SAMPLES_PER_SECOND: f64 = 50.0;

/// Why a comparison could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// The world does not build or run on an engine.
    #[error("on {engine}: {source}")]
    Sim {
        /// The engine.
        engine: EngineKind,
        /// What failed.
        source: SimError,
    },
    /// Nothing to compare.
    #[error("--engines: name at least one engine (rapier, mujoco)")]
    NoEngine,
    /// The duration is no number of seconds.
    #[error("--duration {0}: give a number of seconds > 0")]
    Duration(f64),
    /// The plot could not be drawn.
    #[error("{file}: cannot draw: {message}")]
    Plot {
        /// The PNG.
        file: std::path::PathBuf,
        /// Why.
        message: String,
    },
}

/// One engine's run, measured.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineRun {
    /// The engine.
    pub engine: EngineKind,
    /// Ground distance of the centre of mass from start to end (m, eq. 3.7).
    pub displacement: f64,
    /// Heading at the start and at the end (degrees from +x).
    pub heading: (f64, f64),
    /// Mean over steps and joints of |servo target - angle| (degrees).
    pub tracking_mean: f64,
    /// Largest |servo target - angle| of any joint at any step (degrees, joint mean).
    pub tracking_max: f64,
    /// Mean over the steps with a link contact of the deepest link penetration (m).
    pub penetration_mean: f64,
    /// Deepest link penetration of the run (m).
    pub penetration_max: f64,
    /// Per link, the share of steps it touched something (0..1).
    pub contact_share: Vec<f64>,
    /// Mean slip speed of the links' touching contacts (m/s).
    pub slip_mean: f64,
    /// Centre of mass in the ground plane, sampled ([`SAMPLES_PER_SECOND`]).
    pub path: Vec<(f64, f64)>,
    /// Sample times (s) and each joint's angle then (degrees).
    pub joints: Vec<(f64, Vec<f64>)>,
}

/// The runs of one simulation on each engine.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The simulation file.
    pub config: String,
    /// Simulated seconds per run.
    pub duration: f64,
    /// One run per engine, in the order asked for.
    pub runs: Vec<EngineRun>,
}

impl Comparison {
    /// The smallest displacement as a share of the largest (1: the engines agree).
    pub fn agreement(&self) -> f64 {
        let (lo, hi) = self
            .runs
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), r| {
                (lo.min(r.displacement), hi.max(r.displacement))
            });
        if hi > 0.0 { lo / hi } else { 1.0 }
    }

    /// The run on `engine`, if it was compared.
    pub fn on(&self, engine: EngineKind) -> Option<&EngineRun> {
        self.runs.iter().find(|r| r.engine == engine)
    }
}

/// Runs `sim` for `duration` simulated seconds on each of `engines` (closed loop, the
/// file's seed) and measures each run.
pub fn compare(
    sim: &Simulation,
    engines: &[EngineKind],
    duration: f64,
    registry: &ModuleRegistry,
) -> Result<Comparison, CompareError> {
    if engines.is_empty() {
        return Err(CompareError::NoEngine);
    }
    if !(duration.is_finite() && duration > 0.0) {
        return Err(CompareError::Duration(duration));
    }
    let mut runs = Vec::with_capacity(engines.len());
    for &engine in engines {
        let fail = |source| CompareError::Sim { engine, source };
        runs.push(run_on(sim, engine, duration, registry).map_err(fail)?);
    }
    Ok(Comparison {
        config: sim.file.display().to_string(),
        duration,
        runs,
    })
}

/// What is summed over the steps of one run.
#[derive(Default)]
struct Tally {
    steps: u64,
    tracking_sum: f64,
    tracking_max: f64,
    contact_steps: u64,
    depth_sum: f64,
    depth_max: f64,
    touching_steps: Vec<u64>,
    slip_sum: f64,
    slip_count: u64,
}

impl Tally {
    /// Adds the step just taken.
    fn add(&mut self, s: &Simulator, links: &[BodyId]) -> Result<(), SimError> {
        let tracking = s.tracking_error(0)?;
        self.steps += 1;
        self.tracking_sum += tracking;
        self.tracking_max = self.tracking_max.max(tracking);
        let mut deepest = None::<f64>;
        let mut touched = vec![false; links.len()];
        for c in s.engine().contacts() {
            if !c.touching {
                continue;
            }
            let mut ours = false;
            for b in c.bodies.iter().flatten() {
                if let Some(i) = links.iter().position(|l| l == b) {
                    touched[i] = true;
                    ours = true;
                }
            }
            if ours {
                deepest = Some(deepest.unwrap_or(0.0).max(c.depth));
                self.slip_sum += c.slip;
                self.slip_count += 1;
            }
        }
        if let Some(d) = deepest {
            self.contact_steps += 1;
            self.depth_sum += d;
            self.depth_max = self.depth_max.max(d);
        }
        self.touching_steps.resize(links.len(), 0);
        for (n, t) in self.touching_steps.iter_mut().zip(touched) {
            *n += u64::from(t);
        }
        Ok(())
    }
}

/// One run of `sim` on `engine`, measured.
fn run_on(
    sim: &Simulation,
    engine: EngineKind,
    duration: f64,
    registry: &ModuleRegistry,
) -> Result<EngineRun, SimError> {
    let opts = BuildOptions {
        robots: 1,
        seed: sim.files.simulation.properties.seed,
        engine: engine.into(),
        ..BuildOptions::default()
    };
    let mut s = Simulator::with_registry(sim, &opts, registry)?;
    let links = s.robot_bodies(0)?;
    let start = s.com(0)?;
    let heading0 = s.heading(0)?;
    let dt = s.clock().dt;
    let steps = (duration / dt).round() as u64;
    let every = ((1.0 / SAMPLES_PER_SECOND) / dt).round().max(1.0) as u64;
    let mut tally = Tally::default();
    let mut path = Vec::with_capacity((steps / every + 2) as usize);
    let mut joints = Vec::with_capacity(path.capacity());
    let mut sample = |s: &Simulator, step: u64| -> Result<(), SimError> {
        let c = s.com(0)?;
        path.push((c[0], c[1]));
        let angles = s.joint_states(0)?.iter().map(|j| j.angle).collect();
        joints.push((step as f64 * dt, angles));
        Ok(())
    };
    sample(&s, 0)?;
    for step in 1..=steps {
        s.step();
        tally.add(&s, &links)?;
        if step % every == 0 {
            sample(&s, step)?;
        }
    }
    let per_step = |v: f64, n: u64| if n > 0 { v / n as f64 } else { 0.0 };
    Ok(EngineRun {
        engine,
        displacement: ground_distance(start, s.com(0)?),
        heading: (heading0, s.heading(0)?),
        tracking_mean: per_step(tally.tracking_sum, tally.steps),
        tracking_max: tally.tracking_max,
        penetration_mean: per_step(tally.depth_sum, tally.contact_steps),
        penetration_max: tally.depth_max,
        contact_share: tally
            .touching_steps
            .iter()
            .map(|n| per_step(*n as f64, tally.steps))
            .collect(),
        slip_mean: per_step(tally.slip_sum, tally.slip_count),
        path,
        joints,
    })
}

/// One row's cell of a run, as printed.
type Cell = dyn Fn(&EngineRun) -> String;

impl fmt::Display for Comparison {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(out, "{}: {} s on each engine", self.config, self.duration)?;
        let col = |f: &dyn Fn(&EngineRun) -> String| -> String {
            self.runs.iter().map(|r| format!("{:>14}", f(r))).collect()
        };
        writeln!(out, "{:<28}{}", "", col(&|r| r.engine.to_string()))?;
        let rows: [(&str, &Cell); 7] = [
            ("displacement (m)", &|r| format!("{:.4}", r.displacement)),
            ("heading (deg)", &|r| {
                format!("{:.1}->{:.1}", r.heading.0, r.heading.1)
            }),
            ("tracking mean/max (deg)", &|r| {
                format!("{:.2}/{:.2}", r.tracking_mean, r.tracking_max)
            }),
            ("penetration mean (mm)", &|r| {
                format!("{:.3}", r.penetration_mean * 1e3)
            }),
            ("penetration max (mm)", &|r| {
                format!("{:.3}", r.penetration_max * 1e3)
            }),
            ("slip of contacts (m/s)", &|r| format!("{:.4}", r.slip_mean)),
            ("links in contact (mean %)", &|r| {
                let n = r.contact_share.len().max(1) as f64;
                format!("{:.1}", r.contact_share.iter().sum::<f64>() / n * 100.0)
            }),
        ];
        for (label, f) in rows {
            writeln!(out, "{label:<28}{}", col(f))?;
        }
        let links = self
            .runs
            .iter()
            .map(|r| r.contact_share.len())
            .max()
            .unwrap_or(0);
        for i in 0..links {
            let label = format!("  link {i} in contact (%)");
            writeln!(
                out,
                "{label:<28}{}",
                col(&|r| r
                    .contact_share
                    .get(i)
                    .map_or("-".into(), |s| format!("{:.1}", s * 100.0)))
            )?;
        }
        if self.runs.len() > 1 {
            writeln!(
                out,
                "spread: the smallest displacement is {:.1}% of the largest",
                self.agreement() * 100.0
            )?;
        }
        Ok(())
    }
}
