//! The `proleg` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use proleg::cli;

/// Design, simulate, optimize and drive chain-like modular robots.
#[derive(Parser)]
#[command(name = "proleg", version, about)]
struct Cli {
    /// Without a command: the control window on configs/demo.simulation.xml.
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Open the control window (3D viewer, toolbar, live plots, parameters) on a simulation.
    Gui(GuiArgs),
    /// Open the configuration window: beginner wizard, expert composition, environment editor.
    Wizard {
        /// The configuration folder (module parts, robots, environments, ...).
        #[arg(long, default_value = "configs")]
        configs: PathBuf,
        /// Where new files are written.
        #[arg(long, default_value = "configs/user")]
        out: PathBuf,
        /// Open this `*.env.xml` in the environment editor.
        #[arg(long, conflicts_with = "expert")]
        env: Option<PathBuf>,
        /// Open this `*.simulation.xml` in the expert composition.
        #[arg(long)]
        expert: Option<PathBuf>,
        /// Drive the window from a script (tests, screenshots; see proleg::gui::setup::script).
        #[arg(long)]
        script: Option<PathBuf>,
    },
    /// Validate a simulation file and everything it includes, and print a summary.
    Check {
        /// A `*.simulation.xml` file.
        config: PathBuf,
    },
    /// Throughput figures of the reference scenario (robot-steps per second, real-time factors).
    Bench(BenchArgs),
    /// Physical checks with known answers (friction onset on a slope, sliding to rest,
    /// resting contact, a drop, a servo step, a pendulum) on each engine at its production settings; exit 1 when one
    /// fails.
    CheckPhysics {
        /// The simulation whose robot's first link is the module checked.
        #[arg(long, default_value = DEMO_CONFIG)]
        config: PathBuf,
        /// Only this engine (default: rapier, and MuJoCo where its library is).
        #[arg(long)]
        engine: Option<proleg::config::simulation::EngineKind>,
    },
    /// Whether the robot comes to rest on the floor with its joints held: its lowest point
    /// within 1 cm of the floor after the time given; exit 1 when it sinks or hangs.
    Settle(SettleArgs),
    /// Fit the servo model (gain, top speed, dead band, latency) to a real-robot recording:
    /// the calibrated robot file and a picture of recorded against replayed angles.
    Calibrate(cli::calibrate::CalibrateArgs),
    /// Import a URDF robot: a robot file with its meshes, plus a floor, a sine on every
    /// joint and a simulation file, checked; what cannot be represented is listed.
    Import(ImportArgs),
    /// Write a simulation in another format.
    Export {
        #[command(subcommand)]
        command: ExportCommand,
    },
    /// Run one simulation headless and print what the robot did.
    Run(cli::run::RunRequest),
    /// Optimize the registered parameters of a GA / great-deluge simulation, headless.
    Optimize(cli::optimize::OptimizeOptions),
    /// Runs and best candidates of an experiment store; learning curves and TSV export.
    Results(ResultsArgs),
    /// Re-evaluate a stored candidate on fresh randomized episodes (friction, masses, servo
    /// torque and gain, start pose, sensor noise): how much of its score a gait keeps.
    Robustness(cli::robustness::RobustnessArgs),
    /// Run a simulation on each engine (closed loop) and measure each run the same way:
    /// displacement, heading, joint tracking, penetration, links in contact, slip; with the
    /// spread between engines and a PNG of the paths and joint angles.
    Compare(cli::compare::CompareArgs),
    /// Evaluate the pending candidates of a shared postgres:// store (runs of `proleg
    /// optimize --store URL` on any host), until stopped or idle.
    Worker(cli::worker::WorkerArgs),
    /// Real-robot mode: the simulation's control kernel drives Dynamixel servos on a port.
    Robot(cli::robot::RobotOptions),
    /// An emulated Dynamixel bus on a pseudo-terminal (try `proleg robot` without hardware).
    RobotEmulator(cli::robot::EmulatorOptions),
    /// The user module library: new plugin crates, building, the loaded modules.
    Plugin {
        #[command(subcommand)]
        command: cli::plugin::PluginCommand,
    },
    /// Learned policies' weights files: a new one over a simulation's gait, or one described.
    Policy {
        #[command(subcommand)]
        command: cli::policy::PolicyCommand,
    },
    /// Inspect recorded data files.
    Data {
        #[command(subcommand)]
        command: DataCommand,
    },
}

#[derive(Subcommand)]
enum ExportCommand {
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
        engine: Option<proleg::config::simulation::EngineKind>,
    },
}

#[derive(Subcommand)]
enum DataCommand {
    /// Handlers, series, parts, frames and time span of a data file; says if it was cut.
    Info { file: PathBuf },
    /// Chosen series as a table (TSV, or CSV when OUT ends in .csv).
    Export {
        #[command(flatten)]
        pick: Selection,
    },
    /// Chosen series drawn into a PNG with axes, units and a legend.
    Plot {
        #[command(flatten)]
        pick: Selection,
        /// Image size in pixels, WIDTHxHEIGHT.
        #[arg(long, default_value = "1200x700", value_parser = cli::parse_size)]
        size: (u32, u32),
    },
}

/// A data file, the series chosen from it and where the result goes.
#[derive(clap::Args)]
struct Selection {
    file: PathBuf,
    /// x: simtime, realtime, stepcount or index.
    #[arg(long, default_value = "simtime")]
    x: String,
    /// Comma-separated Handler/series[a..b], e.g. "Robot_Data/y_pos,PatternGenerator_sinusoidal/Angle[0..4]".
    #[arg(long)]
    series: String,
    /// Output file.
    #[arg(short, long)]
    output: PathBuf,
}

/// A command's text to print, or its error (each layer's typed error, turned into text
/// here, where it is printed).
type Printed = Result<String, Box<dyn std::error::Error>>;

/// A command's report as text, or its error.
fn printed<T: std::fmt::Display, E: std::error::Error + 'static>(r: Result<T, E>) -> Printed {
    r.map(|t| t.to_string()).map_err(|e| Box::new(e) as _)
}

/// Prints a command's output, or its error, and gives the exit code.
fn finish(result: Printed) -> ExitCode {
    match result {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// What a headless build says when asked for a window.
#[cfg(not(feature = "gui"))]
const NO_WINDOWS: &str = "this proleg was built without the `gui` feature, so it has no windows: \
scripts/demo builds the complete program (it installs the Debian packages the windows need, \
libudev-dev among them, and runs `cargo build --release`); the headless commands work here \
(proleg --help)";

/// The simulation the window opens without arguments.
const DEMO_CONFIG: &str = "configs/demo.simulation.xml";

/// The control window, or why there is none in this build.
fn gui(
    config: &std::path::Path,
    engine: Option<proleg::config::simulation::EngineKind>,
    replay: Option<proleg::optimize::replay::Replay>,
    script: Option<&std::path::Path>,
    remote: Option<&std::path::Path>,
    plugins: proleg::plugin_host::PluginHost,
) -> Printed {
    #[cfg(feature = "gui")]
    {
        proleg::gui::run(config, engine, replay, script, remote, plugins)
            .map(|()| String::new())
            .map_err(Into::into)
    }
    #[cfg(not(feature = "gui"))]
    {
        let _ = (config, engine, replay, script, remote, plugins);
        Err(Box::new(cli::error::CliError::Options(NO_WINDOWS)))
    }
}

/// `proleg run --video`: the run rendered off-screen.
fn video(req: &cli::run::RunRequest, registry: &proleg::control::ModuleRegistry) -> Printed {
    if req.seed.is_some() || req.data.is_some() || !req.physics.is_empty() || req.realtime != 0.0 {
        return Err(Box::new(cli::error::CliError::Options(
            "--video renders the file's own run: leave out --seed, --data, --physics and --realtime",
        )));
    }
    #[cfg(feature = "gui")]
    {
        let out = req.video.clone().unwrap_or_default();
        let request = proleg::gui::video::VideoRequest {
            config: req.config.clone(),
            out,
            fps: req.fps,
            size: req.size,
            seconds: req.duration,
            engine: req.engine,
        };
        proleg::gui::video::record_video(&request, registry)
            .map(|r| r.to_string())
            .map_err(Into::into)
    }
    #[cfg(not(feature = "gui"))]
    {
        let _ = registry;
        Err(Box::new(cli::error::CliError::Options(NO_WINDOWS)))
    }
}

/// `proleg check-physics`: the checks on each engine asked for, as one report.
fn check_physics(
    config: &std::path::Path,
    engine: Option<proleg::config::simulation::EngineKind>,
    registry: &proleg::control::ModuleRegistry,
) -> Printed {
    use proleg::bench::physics_checks;
    use proleg::config::simulation::EngineKind;
    let base = proleg::control::load_simulation_in(config, registry)?;
    let engines = match engine {
        Some(e) => vec![e],
        None if proleg::sim::engine::mujoco::library::available() => {
            vec![EngineKind::Rapier, EngineKind::Mujoco]
        }
        None => vec![EngineKind::Rapier],
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
        Err(Box::new(cli::error::CliError::Failed(text)))
    }
}

/// Opens the configuration window.
fn wizard(opts: WizardOptions, plugins: proleg::plugin_host::PluginHost) -> Printed {
    #[cfg(feature = "gui")]
    {
        proleg::gui::setup::run(
            &proleg::gui::setup::SetupOptions {
                configs: opts.configs,
                out: opts.out,
                env: opts.env,
                expert: opts.expert,
                script: opts.script,
            },
            plugins,
        )
        .map(|()| String::new())
        .map_err(Into::into)
    }
    #[cfg(not(feature = "gui"))]
    {
        let _ = (opts, plugins);
        Err(Box::new(cli::error::CliError::Options(NO_WINDOWS)))
    }
}

/// The `wizard` command's arguments (read by the windows only, absent from a headless build).
#[cfg_attr(not(feature = "gui"), allow(dead_code))]
struct WizardOptions {
    configs: PathBuf,
    out: PathBuf,
    env: Option<PathBuf>,
    expert: Option<PathBuf>,
    script: Option<PathBuf>,
}

/// `proleg results`: what the stores hold, drawn and exported.
#[derive(clap::Args, Debug)]
struct ResultsArgs {
    /// Stores written by `proleg optimize`: SQLite files or postgres:// URLs (runs of all
    /// are drawn together).
    #[arg(required = true)]
    stores: Vec<String>,
    /// Only these runs (comma-separated ids).
    #[arg(long, value_delimiter = ',')]
    runs: Vec<i64>,
    /// Draw the learning curves (best score so far per evaluation) into this PNG.
    #[arg(long)]
    curve: Option<PathBuf>,
    /// Write every evaluation as TSV.
    #[arg(long)]
    export: Option<PathBuf>,
    /// Draw the first MAP-Elites run's archive (best score per cell of its two
    /// descriptors) into this PNG.
    #[arg(long)]
    map: Option<PathBuf>,
    /// Write the first run's evaluation N (or the best) as ordinary configuration files
    /// into the folder -o names: a co-design run's robot, actuation and simulation (inside
    /// the configuration's folder, where its parts and environment are found), any other
    /// run's actuation file with its networks' weights files.
    #[arg(long, value_name = "N|best", requires = "out")]
    export_robot: Option<String>,
    /// The folder --export-robot writes.
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Render a co-design run's best distinct bodies (the first run listed: choose it with
    /// --runs) off-screen, each replayed with its gait, into this PNG as a captioned grid.
    #[arg(long)]
    gallery: Option<PathBuf>,
    /// With --gallery: how many designs.
    #[arg(long, default_value_t = 6, requires = "gallery")]
    gallery_count: usize,
    /// With --gallery: each picture's size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x320", value_parser = cli::parse_size, requires = "gallery")]
    gallery_tile: (u32, u32),
    /// With --gallery: the moment of each design's episode shown (simulated seconds).
    #[arg(long, default_value_t = 3.0, requires = "gallery")]
    gallery_at: f64,
}

/// `proleg gui`: the control window on a simulation, or replaying a stored evaluation.
#[derive(clap::Args, Debug)]
struct GuiArgs {
    /// A `*.simulation.xml` file.
    #[arg(default_value = DEMO_CONFIG)]
    config: PathBuf,
    /// Replay a stored evaluation instead: the store (a results .sqlite file or a
    /// postgres:// URL) holding the run.
    #[arg(long, requires = "run")]
    replay: Option<String>,
    /// With --replay: the run's id (`proleg results STORE` lists them).
    #[arg(long, requires = "replay")]
    run: Option<i64>,
    /// With --replay: the evaluation's number, or "best".
    #[arg(long, default_value = "best", requires = "replay")]
    eval: String,
    /// With --replay of a run with robust fitness: the randomized episode (default 0).
    #[arg(long, requires = "replay")]
    episode: Option<u32>,
    /// Drive the window from a script (tests, screenshots; see proleg::gui::control::script).
    #[arg(long)]
    script: Option<PathBuf>,
    /// Gamepad bindings (`*.remote.xml`; default: configs/remote/default.remote.xml).
    #[arg(long)]
    remote: Option<PathBuf>,
    /// The physics engine instead of the one the simulation file names (rapier, mujoco).
    #[arg(long)]
    engine: Option<proleg::config::simulation::EngineKind>,
}

/// `proleg bench`: throughput figures, a module comparison or the accuracy gate.
#[derive(clap::Args, Debug)]
struct BenchArgs {
    /// The reference simulation.
    #[arg(long, default_value = "configs/demo.simulation.xml")]
    config: PathBuf,
    /// Simulated seconds per figure.
    #[arg(long, default_value_t = 30.0)]
    seconds: f64,
    /// Batch sizes (robots sharing one world) to measure besides 1.
    #[arg(long, value_delimiter = ',', default_values_t = vec![8, 31])]
    batches: Vec<usize>,
    /// Instead: compare this module (e.g. the plugin Plugin_sine) with the scenario's
    /// --reference module it replaces, pipeline and control kernel alone.
    #[arg(long)]
    module: Option<String>,
    /// The scenario's module that --module replaces.
    #[arg(long, default_value = "PatternGenerator_sinusoidal")]
    reference: String,
    /// Instead: the accuracy gate on this simulation: its displacement, final heading
    /// and joint tracking error at the production physics settings against a converged
    /// reference (finer steps, more substeps), for --seconds.
    #[arg(long, value_name = "CONFIG")]
    convergence: Option<PathBuf>,
    /// Instead: each stage's share of the step (Sense, Actuate, Kernel, Servo, Physics,
    /// Record, Clock) on rapier and, where its library is, MuJoCo, for --seconds.
    #[arg(long, conflicts_with_all = ["module", "convergence"])]
    stages: bool,
    /// Most refinements the reference ladder may take.
    #[arg(long, default_value_t = 5)]
    rungs: usize,
    /// Physics settings to use instead of the robot's production ones, as
    /// key=value,... (substeps, steps_per_step, length_unit, warmstart_joints,
    /// contact_recycling, coulomb_friction, pgs_iterations, contact_hz, contact_damping,
    /// halfspace_floor, multibody_joints).
    #[arg(long, default_value = "")]
    physics: String,
    /// The physics engine instead of the one the simulation file names (rapier,
    /// mujoco); on MuJoCo the figures end with MuJoCo's own rollout of the scenario.
    #[arg(long)]
    engine: Option<proleg::config::simulation::EngineKind>,
}

/// `proleg import`: a URDF robot into configuration files.
#[derive(clap::Args, Debug)]
struct ImportArgs {
    /// The `.urdf` file.
    urdf: PathBuf,
    /// Output folder (default: imported/NAME).
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Import a robot without any collision geometry (it falls through the floor) with a
    /// warning instead of refusing it.
    #[arg(long)]
    allow_no_collision: bool,
    /// Where package NAME of `package://NAME/...` mesh paths is (repeatable); looked up
    /// before the URDF's folders and `ROS_PACKAGE_PATH`.
    #[arg(long = "package-path", value_name = "NAME=DIR", value_parser = proleg::interop::urdf::package_arg)]
    package_path: Vec<(String, PathBuf)>,
}

/// `proleg settle`: whether a robot comes to rest with its joints held.
#[derive(clap::Args, Debug)]
struct SettleArgs {
    /// The simulation file (an import's NAME.simulation.xml).
    config: PathBuf,
    /// Simulated seconds.
    #[arg(long, default_value_t = 2.0)]
    seconds: f64,
    /// The physics engine instead of the one the simulation file names (rapier, mujoco).
    #[arg(long)]
    engine: Option<proleg::config::simulation::EngineKind>,
    /// rapier settings instead of the production ones (key=value,...; as `proleg bench
    /// --physics`).
    #[arg(long, default_value = "")]
    physics: String,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // The user module library: every command sees the plugin modules.
    let (mut host, plugins) = proleg::plugin_host::PluginHost::scan_default();
    let listing = matches!(cli.command, Some(Command::Plugin { .. }));
    if !listing {
        for message in plugins.messages() {
            eprintln!("warning: {message}");
        }
    }
    // The module types every command may use: the standard library and the plugins.
    let registry = host.registry();
    let Some(command) = cli.command else {
        return finish(gui(
            std::path::Path::new(DEMO_CONFIG),
            None,
            None,
            None,
            None,
            host,
        ));
    };
    finish(match command {
        Command::Gui(args) => gui_command(args, host, &registry),
        Command::Wizard {
            configs,
            out,
            env,
            expert,
            script,
        } => wizard(
            WizardOptions {
                configs,
                out,
                env,
                expert,
                script,
            },
            host,
        ),
        Command::Bench(args) => bench_command(&args, &registry),
        Command::Run(request) if request.video.is_some() => video(&request, &registry),
        Command::Run(request) => printed(cli::run::run(&request, &registry)),
        Command::Optimize(options) => printed(cli::optimize::run(&options, &registry)),
        Command::Results(args) => results_command(args, &registry),
        Command::Data { command } => match command {
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
        },
        Command::Plugin { command } => printed(cli::plugin::run(command, &mut host, &plugins)),
        Command::Worker(args) => printed(cli::worker::run(&args, &registry)),
        Command::Policy { command } => printed(cli::policy::run(&command, &registry)),
        Command::Robustness(args) => printed(cli::robustness::run(&args, &registry)),
        Command::Compare(args) => printed(cli::compare::run(&args, &registry)),
        Command::Robot(options) => printed(cli::robot::robot(&options, &registry)),
        Command::RobotEmulator(options) => printed(cli::robot::emulator(&options)),
        Command::Calibrate(args) => printed(cli::calibrate::run(&args, &registry)),
        Command::Import(args) => import_command(args, &registry),
        Command::Settle(args) => settle_command(&args, &registry),
        Command::Export {
            command:
                ExportCommand::Mjcf {
                    config,
                    out,
                    gait,
                    engine,
                },
        } => printed(cli::interop::export_mjcf(
            &config, &out, gait, engine, &registry,
        )),
        Command::CheckPhysics { config, engine } => check_physics(&config, engine, &registry),
        Command::Check { config } => printed(
            proleg::control::load_simulation_in(&config, &registry)
                .map(|sim| format!("{}ok\n", proleg::config::summary::summary(&sim))),
        ),
    })
}

/// The control window on `args.config`, or replaying the stored evaluation `--replay`
/// names.
fn gui_command(
    args: GuiArgs,
    host: proleg::plugin_host::PluginHost,
    registry: &proleg::control::ModuleRegistry,
) -> Printed {
    let GuiArgs {
        config,
        replay,
        run,
        eval,
        episode,
        script,
        remote,
        engine,
    } = args;
    match (replay, run) {
        (Some(store), Some(run)) => {
            let replay = proleg::optimize::replay::Which::parse(&eval).and_then(|which| {
                proleg::optimize::replay::replay_from(&store, run, which, episode, registry)
            })?;
            let replay = match engine {
                Some(e) => replay.on_engine(e),
                None => replay,
            };
            gui(
                &config,
                None,
                Some(replay),
                script.as_deref(),
                remote.as_deref(),
                host,
            )
        }
        _ => gui(
            &config,
            engine,
            None,
            script.as_deref(),
            remote.as_deref(),
            host,
        ),
    }
}

/// `proleg bench`: a module against the one it replaces, the accuracy gate, or the
/// throughput figures.
fn bench_command(a: &BenchArgs, registry: &proleg::control::ModuleRegistry) -> Printed {
    if a.stages {
        return printed(proleg::bench::stages::report(
            &a.config, a.seconds, registry,
        ));
    }
    let figures = match (&a.module, &a.convergence) {
        (Some(module), _) => {
            proleg::bench::modules::report(&a.config, a.seconds, &a.reference, module, registry)
        }
        (None, Some(config)) => proleg::bench::convergence::run(
            config, a.seconds, a.rungs, &a.physics, a.engine, registry,
        ),
        (None, None) => {
            proleg::bench::report(&a.config, a.seconds, &a.batches, &a.physics, a.engine)
        }
    };
    figures.map_err(Into::into)
}

/// `proleg results`: the stores' runs, curves, archives and exports.
fn results_command(a: ResultsArgs, registry: &proleg::control::ModuleRegistry) -> Printed {
    let export_robot = match a.export_robot.as_deref() {
        None => None,
        Some("best") => Some(None),
        Some(n) => Some(Some(n.parse().map_err(|_| {
            cli::error::CliError::Option {
                option: "--export-robot",
                value: n.to_string(),
                want: "give an evaluation number or best",
            }
        })?)),
    };
    let report = cli::results::run(
        &cli::results::ResultsOptions {
            stores: a.stores.clone(),
            runs: a.runs,
            curve: a.curve,
            export: a.export,
            map: a.map,
            export_robot: export_robot.map(|n| (n, a.out.unwrap_or_default())),
        },
        registry,
    )?;
    let Some(out) = a.gallery else {
        return Ok(report.to_string());
    };
    let run = report
        .stores
        .first()
        .and_then(|(_, runs)| runs.first())
        .ok_or(cli::error::CliError::NoRun(0))?
        .id;
    let gallery = gallery(
        GalleryArgs {
            store: a.stores[0].clone(),
            run,
            count: a.gallery_count,
            tile: a.gallery_tile,
            at: a.gallery_at,
            out,
        },
        registry,
    )?;
    Ok(format!("{report}{gallery}"))
}

/// What `--gallery` renders.
struct GalleryArgs {
    store: String,
    run: i64,
    count: usize,
    tile: (u32, u32),
    at: f64,
    out: PathBuf,
}

/// `proleg results --gallery`: the best bodies rendered off-screen.
fn gallery(g: GalleryArgs, registry: &proleg::control::ModuleRegistry) -> Printed {
    #[cfg(feature = "gui")]
    {
        let request = proleg::gui::video::gallery::GalleryRequest {
            store: g.store,
            run: g.run,
            count: g.count,
            tile: g.tile,
            at: g.at,
            out: g.out,
        };
        proleg::gui::video::gallery::render_gallery(&request, registry)
            .map(|r| r.to_string())
            .map_err(Into::into)
    }
    #[cfg(not(feature = "gui"))]
    {
        let _ = (g.store, g.run, g.count, g.tile, g.at, g.out, registry);
        Err(Box::new(cli::error::CliError::Options(NO_WINDOWS)))
    }
}

/// `proleg import`: the URDF's robot, floor, gait and simulation files in `--out`.
fn import_command(a: ImportArgs, registry: &proleg::control::ModuleRegistry) -> Printed {
    let out = a
        .out
        .unwrap_or_else(|| cli::interop::default_import_dir(&a.urdf));
    let opts = proleg::interop::urdf::ImportOptions {
        allow_no_collision: a.allow_no_collision,
        packages: a.package_path,
        ..proleg::interop::urdf::ImportOptions::from_env()
    };
    printed(cli::interop::import_with(&a.urdf, &out, &opts, registry))
}

/// `proleg settle`: the report, an error (exit 1) when the robot did not settle.
fn settle_command(a: &SettleArgs, registry: &proleg::control::ModuleRegistry) -> Printed {
    match cli::interop::settle(&a.config, a.seconds, a.engine, &a.physics, registry) {
        Err(e) => Err(Box::new(e)),
        Ok(r) if r.settled() => Ok(format!("{r}\n")),
        Ok(r) => Err(Box::new(cli::error::CliError::Failed(r.to_string()))),
    }
}
