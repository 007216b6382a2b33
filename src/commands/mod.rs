//! The `proleg` command line as parsed ([`Cli`], clap) and its dispatch: each command to
//! its function in [`crate::cli`] (which returns a typed report) or to a window
//! ([`windows`]). `main.rs` parses, calls [`Commands::execute`] and prints what it returns.

pub mod windows;

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::cli;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::plugin_host::{PluginHost, ScanReport};

/// A command's text to print, or its error (each layer's typed error, turned into text
/// where it is printed).
pub type Printed = Result<String, Box<dyn std::error::Error>>;

/// A command's report as text, or its error.
fn printed<T: std::fmt::Display, E: std::error::Error + 'static>(r: Result<T, E>) -> Printed {
    r.map(|t| t.to_string()).map_err(|e| Box::new(e) as _)
}

/// Design, simulate, optimize and drive chain-like modular robots.
#[derive(Parser)]
#[command(name = "proleg", version, about)]
pub struct Cli {
    /// Without a command: the control window on configs/demo.simulation.xml.
    #[command(subcommand)]
    pub command: Option<Command>,
}

impl Cli {
    /// Whether the command is a window: a signal closes a window as its close button does
    /// (a clean exit), while it stops any other command (exit status 130 or 143).
    pub fn opens_a_window(&self) -> bool {
        matches!(
            self.command,
            None | Some(Command::Gui(_)) | Some(Command::Wizard(_))
        )
    }
}

/// The commands.
#[derive(Subcommand)]
pub enum Command {
    /// Open the control window (3D viewer, toolbar, live plots, parameters) on a simulation.
    Gui(windows::GuiArgs),
    /// Open the configuration window: beginner wizard, expert composition, environment editor.
    Wizard(windows::WizardArgs),
    /// Validate a simulation file and everything it includes, and print a summary.
    Check {
        /// A `*.simulation.xml` file.
        config: PathBuf,
    },
    /// Throughput figures of the reference scenario (robot-steps per second, real-time factors).
    Bench(cli::bench::BenchArgs),
    /// Physical checks with known answers (friction onset on a slope, sliding to rest,
    /// resting contact, a drop, a servo step, a pendulum) on each engine at its production settings; exit 1 when one
    /// fails.
    CheckPhysics(cli::bench::CheckPhysicsArgs),
    /// Whether the robot comes to rest on the floor with its joints held: its lowest point
    /// within 1 cm of the floor after the time given; exit 1 when it sinks or hangs.
    Settle(cli::interop::SettleArgs),
    /// Fit the servo model (gain, top speed, dead band, latency) to a real-robot recording:
    /// the calibrated robot file and a picture of recorded against replayed angles.
    Calibrate(cli::calibrate::CalibrateArgs),
    /// Import a URDF robot: a robot file with its meshes, plus a floor, a sine on every
    /// joint and a simulation file, checked; what cannot be represented is listed.
    Import(cli::interop::ImportArgs),
    /// Write a simulation in another format.
    Export {
        /// The format.
        #[command(subcommand)]
        command: ExportCommand,
    },
    /// Run one simulation headless and print what the robot did.
    Run(cli::run::RunRequest),
    /// Optimize a simulation's registered parameters (and a co-design run's body), headless:
    /// GA, great deluge, CMA-ES, OpenAI-ES or MAP-Elites, as its optimizer file names.
    Optimize(cli::optimize::OptimizeOptions),
    /// Runs and best candidates of an experiment store; learning curves and TSV export.
    Results(cli::results::ResultsArgs),
    /// Re-evaluate a stored candidate on fresh randomized episodes (friction, masses, servo
    /// torque and gain, start pose, sensor noise): how much of its score a gait keeps.
    Robustness(cli::robustness::RobustnessArgs),
    /// Write a generated course (rough, hills, steps, stairs, slope, pegs, channel, rubble)
    /// at a difficulty and seed as an ordinary environment file, to edit by hand.
    Terrain(cli::terrain::TerrainArgs),
    /// Score a controller on a task suite's held-out test courses on both engines: per task
    /// mean distance, success and share of its reference; interquartile means with
    /// bootstrap intervals; CSV and JSON; resumes where a stopped run left off.
    Suite(cli::suite::SuiteArgs),
    /// Run a simulation on each engine (closed loop) and measure each run the same way:
    /// displacement, heading, joint tracking, penetration, links in contact, slip; with the
    /// spread between engines and a PNG of the paths and joint angles.
    Compare(cli::compare::CompareArgs),
    /// Evaluate the pending candidates of a shared postgres:// store (runs of `proleg
    /// optimize --store URL` on any host) and the episodes of its suite runs (`proleg
    /// suite --store URL`), until stopped or idle.
    Worker(cli::worker::WorkerArgs),
    /// Serve a live web page over a store (SQLite or postgres://), read-only: runs,
    /// learning curves, evaluations; for runs on hosts without a display.
    Dashboard(cli::dashboard::DashboardArgs),
    /// Real-robot mode: the simulation's control kernel drives Dynamixel servos on a port.
    Robot(cli::robot::RobotOptions),
    /// An emulated Dynamixel bus on a pseudo-terminal (try `proleg robot` without hardware).
    RobotEmulator(cli::robot::EmulatorOptions),
    /// The user module library: new plugin crates, building, the loaded modules.
    Plugin {
        /// What to do.
        #[command(subcommand)]
        command: cli::plugin::PluginCommand,
    },
    /// Learned policies' weights files: a new one over a simulation's gait, or one described.
    Policy {
        /// What to do.
        #[command(subcommand)]
        command: cli::policy::PolicyCommand,
    },
    /// Inspect recorded data files.
    Data {
        /// What to do.
        #[command(subcommand)]
        command: DataCommand,
    },
}

/// `proleg export`'s formats.
#[derive(Subcommand)]
pub enum ExportCommand {
    /// MuJoCo MJCF: robot, terrain, friction, the servos as position actuators.
    Mjcf {
        /// A `*.simulation.xml` file.
        config: PathBuf,
        /// The MJCF file to write.
        #[arg(short, long)]
        out: PathBuf,
        /// Also run the simulation this many seconds and write every step's servo targets
        /// to OUT.gait.tsv (for scripts/mujoco_gait.py), printing proleg's displacement.
        #[arg(long, value_name = "SECONDS")]
        gait: Option<f64>,
        /// With --gait: the engine that runs it instead of the file's (rapier, mujoco).
        #[arg(long, requires = "gait")]
        engine: Option<EngineKind>,
    },
}

/// `proleg data`'s views of a data file.
#[derive(Subcommand)]
pub enum DataCommand {
    /// Handlers, series, parts, frames and time span of a data file; says if it was cut.
    Info {
        /// The data file.
        file: PathBuf,
    },
    /// Chosen series as a table (TSV, or CSV when OUT ends in .csv).
    Export {
        /// What to export.
        #[command(flatten)]
        pick: Selection,
    },
    /// Chosen series drawn into a PNG with axes, units and a legend.
    Plot {
        /// What to draw.
        #[command(flatten)]
        pick: Selection,
        /// Image size in pixels, WIDTHxHEIGHT.
        #[arg(long, default_value = "1200x700", value_parser = cli::parse_size)]
        size: (u32, u32),
    },
}

/// A data file, the series chosen from it and where the result goes.
#[derive(clap::Args)]
pub struct Selection {
    /// The data file.
    pub file: PathBuf,
    /// x: simtime, realtime, stepcount or index.
    #[arg(long, default_value = "simtime")]
    pub x: String,
    /// Comma-separated Handler/series[a..b], e.g. "Robot_Data/y_pos,PatternGenerator_sinusoidal/Angle[0..4]".
    #[arg(long)]
    pub series: String,
    /// Output file.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// What every command runs with: the user module library (the plugins found) and the
/// module types it adds to the standard library.
pub struct Commands {
    host: PluginHost,
    scan: ScanReport,
    registry: ModuleRegistry,
}

impl Commands {
    /// Scans the user module library.
    pub fn open() -> Commands {
        let (host, scan) = PluginHost::scan_default();
        let registry = host.registry();
        Commands {
            host,
            scan,
            registry,
        }
    }

    /// What the scan of the plugins found wrong, to print as warnings (not before a
    /// command that lists the plugins itself).
    pub fn warnings(&self, cli: &Cli) -> Vec<String> {
        if matches!(cli.command, Some(Command::Plugin { .. })) {
            return Vec::new();
        }
        self.scan.messages()
    }

    /// Runs the command (without one: the control window on the demo).
    pub fn execute(mut self, cli: Cli) -> Printed {
        let registry = &self.registry;
        let Some(command) = cli.command else {
            return windows::gui(&windows::GuiArgs::demo(), self.host, registry);
        };
        match command {
            Command::Gui(args) => windows::gui(&args, self.host, registry),
            Command::Wizard(args) => windows::wizard(args, self.host),
            Command::Run(request) if request.video.is_some() => windows::video(&request, registry),
            Command::Results(args) if args.gallery.is_some() => windows::results(&args, registry),
            Command::Plugin { command } => {
                printed(cli::plugin::run(command, &mut self.host, &self.scan))
            }
            Command::Bench(args) => printed(cli::bench::run(&args, registry)),
            Command::CheckPhysics(args) => printed(cli::bench::check_physics(&args, registry)),
            Command::Run(request) => printed(cli::run::run(&request, registry)),
            Command::Optimize(options) => printed(cli::optimize::run(&options, registry)),
            Command::Results(args) => {
                printed(args.options().and_then(|o| cli::results::run(&o, registry)))
            }
            Command::Data { command } => data(command),
            Command::Worker(args) => printed(cli::worker::run(&args, registry)),
            Command::Dashboard(args) => printed(cli::dashboard::run(
                &args,
                windows::video_renderer(),
                registry,
            )),
            Command::Policy { command } => printed(cli::policy::run(&command, registry)),
            Command::Robustness(args) => printed(cli::robustness::run(&args, registry)),
            Command::Terrain(args) => printed(cli::terrain::run(&args)),
            Command::Suite(args) => printed(cli::suite::run(&args, registry)),
            Command::Compare(args) => printed(cli::compare::run(&args, registry)),
            Command::Robot(options) => printed(cli::robot::robot(&options, registry)),
            Command::RobotEmulator(options) => printed(cli::robot::emulator(&options)),
            Command::Calibrate(args) => printed(cli::calibrate::run(&args, registry)),
            Command::Import(args) => printed(cli::interop::import_command(&args, registry)),
            Command::Settle(args) => printed(cli::interop::settle_command(&args, registry)),
            Command::Export {
                command:
                    ExportCommand::Mjcf {
                        config,
                        out,
                        gait,
                        engine,
                    },
            } => printed(cli::interop::export_mjcf(
                &config, &out, gait, engine, registry,
            )),
            Command::Check { config } => printed(
                crate::control::load_simulation_in(&config, registry)
                    .map(|sim| format!("{}ok\n", crate::config::summary::summary(&sim))),
            ),
        }
    }
}

/// `proleg data info / export / plot`.
fn data(command: DataCommand) -> Printed {
    match command {
        DataCommand::Info { file } => printed(cli::data::show_info(&file)),
        DataCommand::Export { pick } => printed(cli::data::export_table(
            &pick.file,
            &pick.x,
            &pick.series,
            &pick.output,
        )),
        DataCommand::Plot { pick, size } => printed(cli::data::plot_png(
            &pick.file,
            &pick.x,
            &pick.series,
            &pick.output,
            size,
        )),
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::{Cli, Command};

    /// clap's own checks of every command's arguments.
    #[test]
    fn the_command_line_passes_claps_checks() {
        <Cli as clap::CommandFactory>::command().debug_assert();
    }

    /// `RunRequest::of` is what the command line gives without options, and `--html`
    /// refuses what it cannot do (a paced run, a video) and what needs it.
    #[test]
    fn a_run_request_of_a_file_is_the_command_lines_default() {
        let parsed = Cli::try_parse_from(["proleg", "run", "a.simulation.xml"]).unwrap();
        let Some(Command::Run(req)) = parsed.command else {
            panic!("not a run");
        };
        assert_eq!(
            req,
            crate::cli::run::RunRequest::of("a.simulation.xml".into())
        );
        for refused in [
            &["run", "a.xml", "--html", "a.html", "--realtime", "1"][..],
            &["run", "a.xml", "--html", "a.html", "--video", "a.mp4"],
            &["run", "a.xml", "--compare", "b.xml"],
            &["run", "a.xml", "--compare-engine", "mujoco"],
            &["run", "a.xml", "--html", "a.html", "--fps", "0"],
        ] {
            let args = std::iter::once("proleg").chain(refused.iter().copied());
            assert!(Cli::try_parse_from(args).is_err(), "{refused:?} accepted");
        }
    }
}
