//! `proleg import` and `proleg export mjcf`: other formats in and out, each result loaded
//! back as any configuration is, so a conversion never hands over a file `proleg check`
//! would refuse.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::cli::error::CliError;
use crate::config::environment::Articulation;
use crate::config::simulation::EngineKind;
use crate::control::{ModuleRegistry, load_simulation_in};
use crate::interop::urdf::{ImportOptions, UrdfImport, import_urdf_with, set_articulation};
use crate::sim::engine::EngineSettings;
use crate::sim::settle::SettleReport;

/// An import and the check of what it wrote.
#[derive(Debug, Clone)]
pub struct ImportReport {
    /// What was written and the warnings.
    pub import: UrdfImport,
    /// The check summary of the written simulation, when one was written.
    pub check: Option<String>,
    /// Whether the robot comes to rest on the floor with its joints held (`proleg settle`
    /// for [`crate::sim::settle::IMPORT_SETTLE_SECONDS`], on the simulation's engine), when
    /// the files load.
    pub settle: Option<SettleReport>,
    /// The articulation the import chose instead of the default, when it did: reduced
    /// coordinates for a robot that shook apart with maximal ones on rapier.
    pub articulation: Option<Articulation>,
}

impl fmt::Display for ImportReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.import)?;
        if let Some(c) = &self.check {
            write!(f, "proleg check: ok\n{c}")?;
        }
        if let Some(a) = self.articulation {
            writeln!(
                f,
                "articulation: {} (the environment's <articulation>): with maximal-coordinate joints rapier shook the robot apart",
                a.name()
            )?;
        }
        match &self.settle {
            Some(r) if r.settled() => writeln!(f, "proleg settle: {r}")?,
            Some(r) => writeln!(
                f,
                "warning: proleg settle: {r}; the robot does not stand as imported on rapier with either articulation (try `proleg settle --engine mujoco`)"
            )?,
            None => {}
        }
        Ok(())
    }
}

/// Why an import failed: the conversion, or the files it wrote.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The URDF (or a mesh it names) could not be converted.
    #[error("{0}")]
    Convert(#[from] crate::interop::InteropError),
    /// The files written do not load as `proleg check` would load them.
    #[error("the imported files do not load: {0}")]
    Load(crate::config::error::ConfigError),
    /// The imported robot could not be built or run to let it settle.
    #[error("the imported robot does not run: {0}")]
    Run(crate::sim::error::SimError),
}

/// `proleg import`: a URDF robot into configuration files.
#[derive(clap::Args, Debug)]
pub struct ImportArgs {
    /// The `.urdf` file.
    pub urdf: PathBuf,
    /// Output folder (default: imported/NAME).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Import a robot without any collision geometry (it falls through the floor) with a
    /// warning instead of refusing it.
    #[arg(long)]
    pub allow_no_collision: bool,
    /// Where package NAME of `package://NAME/...` mesh paths is (repeatable); looked up
    /// before the URDF's folders and `ROS_PACKAGE_PATH`.
    #[arg(long = "package-path", value_name = "NAME=DIR", value_parser = crate::interop::urdf::package_arg)]
    pub package_path: Vec<(String, PathBuf)>,
}

/// `proleg settle`: whether a robot comes to rest with its joints held.
#[derive(clap::Args, Debug)]
pub struct SettleArgs {
    /// The simulation file (an import's NAME.simulation.xml).
    pub config: PathBuf,
    /// Simulated seconds.
    #[arg(long, default_value_t = 2.0)]
    pub seconds: f64,
    /// The physics engine instead of the one the simulation file names (rapier, mujoco).
    #[arg(long)]
    pub engine: Option<EngineKind>,
    /// rapier settings instead of the production ones (key=value,...; as `proleg bench
    /// --physics`).
    #[arg(long, default_value = "")]
    pub physics: String,
}

/// `proleg import`: the URDF's robot, floor, gait and simulation files in `--out`
/// (default: imported/NAME).
pub fn import_command(
    a: &ImportArgs,
    registry: &ModuleRegistry,
) -> Result<ImportReport, ImportError> {
    let out = a.out.clone().unwrap_or_else(|| default_import_dir(&a.urdf));
    let opts = ImportOptions {
        allow_no_collision: a.allow_no_collision,
        packages: a.package_path.clone(),
        ..ImportOptions::from_env()
    };
    import_with(&a.urdf, &out, &opts, registry)
}

/// `proleg settle`: the report, or the report as the error ([`CliError::Failed`], exit
/// status 1) when the robot did not settle.
pub fn settle_command(a: &SettleArgs, registry: &ModuleRegistry) -> Result<String, CliError> {
    let r = settle(&a.config, a.seconds, a.engine, &a.physics, registry)?;
    if r.settled() {
        Ok(format!("{r}\n"))
    } else {
        Err(CliError::Failed(r.to_string()))
    }
}

/// Imports `urdf` into `out` and checks the simulation it wrote.
pub fn import(
    urdf: &Path,
    out: &Path,
    registry: &ModuleRegistry,
) -> Result<ImportReport, ImportError> {
    import_with(urdf, out, &ImportOptions::from_env(), registry)
}

/// [`import`] with `opts` (`proleg import --allow-no-collision --package-path NAME=DIR`).
pub fn import_with(
    urdf: &Path,
    out: &Path,
    opts: &ImportOptions,
    registry: &ModuleRegistry,
) -> Result<ImportReport, ImportError> {
    let mut import = import_urdf_with(urdf, out, opts)?;
    let mut settled = None;
    let mut articulation = None;
    let check = match &import.simulation_file {
        Some(sim) => match load_simulation_in(sim, registry) {
            Ok(mut s) => {
                let (report, chosen) = settle_articulation(&mut s, &import, registry)?;
                settled = Some(report);
                articulation = chosen;
                Some(crate::config::summary::summary(&s))
            }
            // Asked for: the robot without collision geometry is written, and `proleg
            // check` refuses it as it would any robot that falls through every floor.
            Err(e) if opts.allow_no_collision => {
                import
                    .warnings
                    .push(format!("proleg check refuses the files written: {e}"));
                None
            }
            Err(e) => return Err(ImportError::Load(e)),
        },
        None => None,
    };
    Ok(ImportReport {
        import,
        check,
        settle: settled,
        articulation,
    })
}

/// Lets the imported robot settle; on rapier, a robot that does not come to rest with
/// maximal-coordinate joints is tried with reduced ones ([`Articulation`]), and the
/// environment file asks for them when it then comes to rest (or settles where it did not). Returns the settle report of the
/// articulation written, and that articulation when it was changed.
fn settle_articulation(
    sim: &mut crate::config::Simulation,
    import: &UrdfImport,
    registry: &ModuleRegistry,
) -> Result<(SettleReport, Option<Articulation>), ImportError> {
    let opts = crate::sim::BuildOptions {
        robots: 1,
        record: false,
        ..Default::default()
    };
    let seconds = crate::sim::settle::IMPORT_SETTLE_SECONDS;
    let run = |s: &crate::config::Simulation| {
        crate::sim::settle::settle(s, seconds, &opts, registry).map_err(ImportError::Run)
    };
    let first = run(sim)?;
    if first.at_rest()
        || opts.engine.kind_for(sim) != EngineKind::Rapier
        || sim.environment.physics.articulation == Articulation::Reduced
    {
        return Ok((first, None));
    }
    sim.environment.physics.articulation = Articulation::Reduced;
    let reduced = run(sim)?;
    if !(reduced.at_rest() || reduced.settled() && !first.settled()) {
        sim.environment.physics.articulation = Articulation::Maximal;
        return Ok((first, None));
    }
    let dir = import.robot_file.parent().unwrap_or_else(|| Path::new("."));
    set_articulation(dir, &import.name, Articulation::Reduced)?;
    Ok((reduced, Some(Articulation::Reduced)))
}

/// The default output folder of an import: `imported/NAME` beside the working directory.
pub fn default_import_dir(urdf: &Path) -> PathBuf {
    let stem = urdf
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "robot".into());
    PathBuf::from("imported").join(stem)
}

/// An MJCF export and, when asked, the gait proleg ran for the cross-engine check.
#[derive(Debug, Clone)]
pub struct ExportReport {
    /// The MJCF file written.
    pub file: PathBuf,
    /// What it holds.
    pub export: crate::interop::mjcf::MjcfExport,
    /// The recorded gait, when `--gait SECONDS` was given.
    pub gait: Option<GaitRecord>,
}

/// The servo targets of a proleg run, one row per step, and how far the robot went.
#[derive(Debug, Clone, PartialEq)]
pub struct GaitRecord {
    /// The TSV written (`time` then one column per joint, degrees).
    pub file: PathBuf,
    /// Simulated seconds.
    pub seconds: f64,
    /// Steps recorded.
    pub steps: u64,
    /// Horizontal displacement of the robot's centre of mass in proleg (m).
    pub displacement: f64,
}

impl fmt::Display for ExportReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = &self.export;
        writeln!(
            f,
            "wrote {}: {} bodies, {} hinges with position servos, {} assets",
            self.file.display(),
            e.bodies,
            e.joints,
            e.assets
        )?;
        if e.loaded_by_mujoco {
            writeln!(f, "MuJoCo loads it")?;
        } else {
            writeln!(
                f,
                "not loaded in MuJoCo (its library is not installed: bash scripts/install-mujoco)"
            )?;
        }
        for n in &e.notes {
            writeln!(f, "note: {n}")?;
        }
        if let Some(g) = &self.gait {
            writeln!(
                f,
                "gait: {} ({} steps, {} s); proleg displacement {:.4} m",
                g.file.display(),
                g.steps,
                g.seconds,
                g.displacement
            )?;
            writeln!(
                f,
                "replay it in MuJoCo: python3 scripts/mujoco_gait.py {} {}",
                self.file.display(),
                g.file.display()
            )?;
        }
        Ok(())
    }
}

/// Exports `config` as MJCF to `out`; with `gait`, also runs it for that many seconds and
/// writes the servo targets of every step beside it (`OUT.gait.tsv`).
pub fn export_mjcf(
    config: &Path,
    out: &Path,
    gait: Option<f64>,
    engine: Option<crate::config::simulation::EngineKind>,
    registry: &ModuleRegistry,
) -> Result<ExportReport, CliError> {
    let sim = load_simulation_in(config, registry)?.with_engine(engine);
    let export = crate::interop::mjcf::export_mjcf(&sim, out)?;
    let gait = match gait {
        Some(seconds) if seconds > 0.0 && seconds.is_finite() => {
            Some(record_gait(&sim, out, seconds, registry)?)
        }
        Some(seconds) => {
            return Err(CliError::Option {
                option: "--gait",
                value: seconds.to_string(),
                want: "give seconds > 0",
            });
        }
        None => None,
    };
    Ok(ExportReport {
        file: out.to_path_buf(),
        export,
        gait,
    })
}

/// Runs `sim` for `seconds`, writing every step's servo targets.
fn record_gait(
    sim: &crate::config::Simulation,
    out: &Path,
    seconds: f64,
    registry: &ModuleRegistry,
) -> Result<GaitRecord, CliError> {
    use std::fmt::Write as _;
    let opts = crate::sim::BuildOptions {
        robots: 1,
        record: false,
        ..Default::default()
    };
    let mut s = crate::sim::Simulator::with_registry(sim, &opts, registry)?;
    let dt = sim.files.simulation.properties.step_width;
    let steps = (seconds / dt).round() as u64;
    let mut tsv = String::from("time");
    for j in &sim.robot.joints {
        tsv.push('\t');
        tsv.push_str(&j.name);
    }
    tsv.push('\n');
    let start = s.com(0)?;
    for k in 1..=steps {
        s.step();
        let _ = write!(tsv, "{:.6}", k as f64 * dt);
        for t in s.servo_targets(0)? {
            let _ = write!(tsv, "\t{t:.6}");
        }
        tsv.push('\n');
    }
    let end = s.com(0)?;
    let file = out.with_extension("gait.tsv");
    crate::interop::write_text(&file, &tsv)?;
    Ok(GaitRecord {
        file,
        seconds: steps as f64 * dt,
        steps,
        displacement: crate::measure::ground_distance(start, end),
    })
}

/// Why `proleg settle` could not measure.
#[derive(Debug, thiserror::Error)]
pub enum SettleError {
    /// Not a duration.
    #[error("--seconds {0}: give seconds > 0")]
    Seconds(f64),
    /// The configuration does not load.
    #[error("{0}")]
    Config(#[from] crate::config::error::ConfigError),
    /// A `--physics` setting that is not one.
    #[error("--physics: {0}")]
    Physics(crate::sim::engine::EngineSettingsError),
    /// The world could not be built or run.
    #[error("{0}")]
    Sim(#[from] crate::sim::error::SimError),
}

/// `proleg settle`: runs `config` for `seconds` with the joints held and reports where the
/// robot came to rest ([`crate::sim::settle`]).
pub fn settle(
    config: &Path,
    seconds: f64,
    engine: Option<crate::config::simulation::EngineKind>,
    physics: &str,
    registry: &ModuleRegistry,
) -> Result<crate::sim::settle::SettleReport, SettleError> {
    if !(seconds > 0.0 && seconds.is_finite()) {
        return Err(SettleError::Seconds(seconds));
    }
    let sim = load_simulation_in(config, registry)?.with_engine(engine);
    let settings = EngineSettings::of(&sim, physics).map_err(SettleError::Physics)?;
    let opts = crate::sim::BuildOptions {
        robots: 1,
        record: false,
        engine: settings.into(),
        ..Default::default()
    };
    Ok(crate::sim::settle::settle(&sim, seconds, &opts, registry)?)
}
