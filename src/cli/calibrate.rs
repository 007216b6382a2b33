//! `proleg calibrate`: a recording's servo identification (`calibrate`), the calibrated
//! robot file beside the original (its part files found as before) or, with `-o DIR`, in
//! a folder that stands alone with a simulation on the calibrated robot, the
//! before/after picture, and with `--check GAIT` the gap between a gait on the robot
//! (recorded now on `--port`, or earlier in `--check-data`) and its simulation before and
//! after.

use std::path::{Path, PathBuf};

use crate::calibrate::check::{GaitGap, gait_gap};
use crate::calibrate::plot::plot_calibration;
use crate::calibrate::recording::read_recording;
use crate::calibrate::{
    CalibrateError, CalibrateOptions, CalibrationReport, calibrate, calibrated_robot_file,
};
use crate::cli::error::CliError;
use crate::config::bundle::{write_bundle, write_file};
use crate::config::simulation::write_simulation_file;
use crate::config::source::relative_path;
use crate::config::{FsSource, RecordingSource, load_simulation_with};
use crate::control::{ModuleRegistry, load_simulation_in};

/// `proleg calibrate`'s arguments.
#[derive(clap::Args, Debug)]
pub struct CalibrateArgs {
    /// The recording (a data file of `proleg robot`: desired and real joint positions).
    pub data: PathBuf,
    /// The simulation whose robot the recording drove.
    #[arg(long)]
    pub config: PathBuf,
    /// A folder for the calibrated robot, the picture and a simulation on the calibrated
    /// robot, with a copy of every file they need so the folder can be moved (default:
    /// only the calibrated robot file and the picture, beside the robot file).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// One servo model per joint instead of one for all.
    #[arg(long)]
    pub per_joint: bool,
    /// Fits from different seeds; their spread is the confidence.
    #[arg(long, default_value_t = 4)]
    pub runs: u32,
    /// Seed of the first fit.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// A gait's simulation file: its run on the robot against its simulation with the
    /// robot file's servos and with the calibrated ones.
    #[arg(long)]
    pub check: Option<PathBuf>,
    /// With --check: the gait's recording on the robot (else it is recorded on --port).
    #[arg(long, requires = "check")]
    pub check_data: Option<PathBuf>,
    /// With --check: the robot's port, to record the gait now.
    #[arg(long, requires = "check")]
    pub port: Option<PathBuf>,
    /// With --check --port: seconds of the gait on the robot (default: its file's).
    #[arg(long, requires = "port")]
    pub check_seconds: Option<f64>,
}

/// What `proleg calibrate` found and wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrateReport {
    /// The fit.
    pub report: CalibrationReport,
    /// The calibrated robot file.
    pub robot: PathBuf,
    /// With `-o`: the simulation on the calibrated robot, in a folder that also holds
    /// every file it needs (a copy of the configuration in its own layout).
    pub simulation: Option<PathBuf>,
    /// The before/after picture.
    pub plot: PathBuf,
    /// The gap on a gait, when checked.
    pub gait: Option<GaitGap>,
}

impl std::fmt::Display for CalibrateReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.report)?;
        writeln!(f, "calibrated robot file: {}", self.robot.display())?;
        if let Some(s) = &self.simulation {
            writeln!(f, "on the calibrated robot: {}", s.display())?;
        }
        writeln!(
            f,
            "recorded against replayed angles: {}",
            self.plot.display()
        )?;
        if let Some(g) = &self.gait {
            write!(f, "{g}")?;
        }
        Ok(())
    }
}

/// Calibrates `a.config`'s servos on `a.data`.
pub fn run(a: &CalibrateArgs, registry: &ModuleRegistry) -> Result<CalibrateReport, CliError> {
    let source = RecordingSource::new(&FsSource);
    let sim = load_simulation_with(&source, &a.config, registry)?;
    let rec = read_recording(&a.data)?;
    let options = CalibrateOptions {
        per_joint: a.per_joint,
        runs: a.runs.max(1),
        seed: a.seed,
    };
    let report = calibrate(&rec, &sim, &options)?;
    let robot_file = &sim.robot.file;
    let beside = robot_file.parent().unwrap_or(Path::new("")).to_path_buf();
    let stem = file_stem(robot_file, ".robot", "robot");
    // The file's includes are written relative to the robot file's own folder, so they
    // resolve beside the original and, with `-o`, beside its copy in the same layout.
    let text = calibrated_robot_file(&sim, &report, &beside)?;
    let (dir, robot, simulation) = match &a.out {
        None => {
            let robot = beside.join(format!("{stem}.calibrated.robot.xml"));
            (beside, robot, None)
        }
        Some(out) => {
            let layout = write_bundle(&source.files(), out)?;
            let copy = layout.place(robot_file);
            let robot = copy
                .parent()
                .unwrap_or(out)
                .join(format!("{stem}.calibrated.robot.xml"));
            let sim_file = layout.place(&a.config);
            let sim_stem = file_stem(&sim_file, ".simulation", "calibrated");
            let sim_dir = sim_file.parent().unwrap_or(out).to_path_buf();
            let runs_it = sim_dir.join(format!("{sim_stem}.calibrated.simulation.xml"));
            let mut file = sim.files.simulation.clone();
            file.robot.path = relative_path(&sim_dir, &robot);
            write_file(&runs_it, &write_simulation_file(&file))?;
            (out.clone(), robot, Some(runs_it))
        }
    };
    std::fs::create_dir_all(&dir).map_err(CliError::write(&dir))?;
    std::fs::write(&robot, text).map_err(CliError::write(&robot))?;
    if let Some(s) = &simulation {
        load_simulation_in(s, registry)?;
    }
    let plot = dir.join(format!("{stem}.calibration.png"));
    plot_calibration(&rec, &report, &plot)?;
    let gait = match &a.check {
        Some(gait) => Some(check_gait(a, gait, &dir, &report, registry)?),
        None => None,
    };
    Ok(CalibrateReport {
        report,
        robot,
        simulation,
        plot,
        gait,
    })
}

/// `path`'s file name without `.xml` and `kind` (`.robot`), or `fallback`.
fn file_stem(path: &Path, kind: &str, fallback: &str) -> String {
    path.file_name()
        .and_then(|n| n.to_str())
        .map(|n| {
            n.trim_end_matches(".xml")
                .trim_end_matches(kind)
                .to_string()
        })
        .unwrap_or_else(|| fallback.to_string())
}

/// The gap on the gait `gait`: its recording (given, or made now on the port) against
/// its simulation before and after calibration.
fn check_gait(
    a: &CalibrateArgs,
    gait: &Path,
    dir: &Path,
    report: &CalibrationReport,
    registry: &ModuleRegistry,
) -> Result<GaitGap, CliError> {
    let sim = load_simulation_in(gait, registry)?;
    let data = match (&a.check_data, &a.port) {
        (Some(d), _) => d.clone(),
        (None, Some(port)) => {
            let data = dir.join("gait.check.data.xml");
            crate::cli::robot::robot(
                &crate::cli::robot::RobotOptions {
                    config: gait.to_path_buf(),
                    port: port.clone(),
                    baud: None,
                    duration: a
                        .check_seconds
                        .or(Some(sim.files.simulation.properties.duration)),
                    data: Some(data.clone()),
                    every: None,
                    read_every: None,
                    seed: None,
                },
                registry,
            )?;
            data
        }
        (None, None) => {
            return Err(CliError::Options(
                "--check needs the gait's recording (--check-data) or the robot's port (--port)",
            ));
        }
    };
    let rec = read_recording(&data)?;
    Ok(gait_gap(&rec, &sim, report, registry)?)
}

impl From<CalibrateError> for CliError {
    fn from(e: CalibrateError) -> Self {
        CliError::Calibrate(Box::new(e))
    }
}
