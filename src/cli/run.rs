//! `proleg run`: one headless run of a simulation file, summarized in a [`RunReport`];
//! with a data file, every data handler is recorded to a B.8 data file, closed well-formed
//! also on Ctrl-C and SIGTERM (the run stops at the next chunk of steps). The run is one
//! episode of the episode runner ([`Episode`]): a robot that leaves the world ends it
//! there, as it ends an optimizer's episode, and the summary is the robot's as it left.

use std::fmt;
use std::path::PathBuf;
use std::time::Instant;

use crate::cli::error::CliError;
use crate::cli::run_html;
use crate::config::Simulation;
use crate::config::fitness::Fitness;
use crate::config::simulation::EngineKind;
use crate::config::simulation::Mode;
use crate::control::{ModuleRegistry, load_simulation_in};
use crate::playback::{PoseStream, Recording, record_episode};
use crate::signal::StopFlag;
use crate::sim::datalog::DataSettings;
use crate::sim::engine::EngineSettings;
use crate::sim::{
    BuildOptions, Episode, EpisodeEnd, EpisodeSettings, Pacer, Pacing, RunSummary, Simulator,
    WorldExit,
};

/// What `proleg run` is asked to do (its command-line arguments).
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct RunRequest {
    /// A `*.simulation.xml` file.
    pub config: PathBuf,
    /// Simulated seconds (default: the file's duration).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Random seed (default: the file's seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Pace to real time times this factor (default 0: as fast as possible).
    #[arg(long, default_value_t = 0.0)]
    pub realtime: f64,
    /// Record every data handler to this XML data file (thesis B.8).
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Sample every this many steps (default: the file's accuracy).
    #[arg(long)]
    pub every: Option<u32>,
    /// Physics settings instead of the robot's production ones, as key=value,... (see
    /// `proleg bench --help`).
    #[arg(long, default_value = "")]
    pub physics: String,
    /// The physics engine instead of the one the simulation file names (rapier, mujoco).
    #[arg(long)]
    pub engine: Option<EngineKind>,
    /// Render the run off-screen into a video following the robot (.mp4, .webm, .gif by
    /// ffmpeg; a folder: PNG frames, also when no ffmpeg is installed). Needs the gui
    /// feature, no display.
    #[arg(long)]
    pub video: Option<PathBuf>,
    /// Frames per simulated second of the video or the 3D replay.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..))]
    pub fps: u32,
    /// Write the run as a 3D replay: one self-contained HTML page (the viewer and the
    /// bodies' poses inlined; opened from disk in any browser, no server, no network).
    #[arg(long, conflicts_with_all = ["video", "realtime"])]
    pub html: Option<PathBuf>,
    /// With --html: another simulation file run on the same seed and shown beside this
    /// one on one timeline (two controllers on one world).
    #[arg(long, requires = "html")]
    pub compare: Option<PathBuf>,
    /// With --html: the run also on this engine, shown beside it (rapier against MuJoCo).
    #[arg(long, requires = "html")]
    pub compare_engine: Option<EngineKind>,
    /// Video size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = crate::cli::parse_size)]
    pub size: (u32, u32),
    /// A video without the ground's metre grid.
    #[arg(long)]
    pub no_grid: bool,
    /// The video camera's place: DISTANCE,YAW,PITCH (metres from the robot; degrees about
    /// the vertical, 0 behind the robot looking along its start heading, positive from its
    /// left; degrees above the ground) [default: 0.75,-51.6,31.5]
    #[arg(long, requires = "video", value_parser = crate::cli::parse_camera)]
    pub camera: Option<[f64; 3]>,
}

impl RunRequest {
    /// A run of `config` with every option as the command line leaves it by default.
    pub fn of(config: PathBuf) -> RunRequest {
        RunRequest {
            config,
            duration: None,
            seed: None,
            realtime: 0.0,
            data: None,
            every: None,
            physics: String::new(),
            engine: None,
            video: None,
            fps: 30,
            size: (1280, 720),
            no_grid: false,
            camera: None,
            html: None,
            compare: None,
            compare_engine: None,
        }
    }
}

/// What a run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RunReport {
    /// The simulation file as loaded.
    pub simulation: PathBuf,
    /// The robot's name.
    pub robot: String,
    /// The physics engine and its settings.
    pub engine: String,
    /// The seed used.
    pub seed: u64,
    /// The file asks for real-robot control (this run simulated the twin).
    pub real_robot_mode: bool,
    /// Steps, times, start and end, displacement (eq. 3.7) and speed.
    pub summary: RunSummary,
    /// Heading at the start and at the end (degrees from +x).
    pub heading: (f64, f64),
    /// The data file and the rounds written to it.
    pub data: Option<(PathBuf, u64)>,
    /// Modules that failed during the run, with the cause.
    pub failures: Vec<(String, String)>,
    /// How the run ended before its duration, if it did.
    pub stopped: Option<RunStop>,
    /// The 3D replay page written (`--html`).
    pub html: Option<crate::cli::run_html::HtmlReport>,
}

/// Why a run ended before its duration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunStop {
    /// Ctrl-C or SIGTERM.
    Interrupted,
    /// The robot left the world (or the physics diverged).
    Left(WorldExit),
}

/// Loads, runs and summarizes; the error is the message to print.
pub fn run(req: &RunRequest, registry: &ModuleRegistry) -> Result<RunReport, CliError> {
    let report = run_report(req, registry)?;
    match report.failures.first().cloned() {
        Some((module, cause)) => Err(CliError::ModuleFailed {
            report: report.to_string(),
            module,
            cause,
        }),
        None => Ok(report),
    }
}

/// The run's report, a module's failure in it included.
fn run_report(req: &RunRequest, registry: &ModuleRegistry) -> Result<RunReport, CliError> {
    let sim = load_simulation_in(&req.config, registry)?.with_engine(req.engine);
    let props = &sim.files.simulation.properties;
    let duration = checked_duration(req, props.duration)?;
    let seed = req.seed.unwrap_or(props.seed);
    let settings = EngineSettings::of(&sim, &req.physics)?;
    let mut simulator = Simulator::with_registry(&sim, &one_robot(seed, settings), registry)?;
    simulator.set_pacing(Pacing {
        realtime_factor: req.realtime,
        delay_ms: 0.0,
    });
    start_data(req, &mut simulator, props.accuracy)?;
    let heading0 = simulator.heading(0)?;
    let start_com = simulator.com(0)?;
    let wall = Instant::now();
    // The subscription must live as long as the run: a dropped one hears no signal.
    let subscription = crate::signal::subscribe()?;
    let stop = subscription.flag();
    let recording = req
        .html
        .as_ref()
        .map(|_| run_html::recording(req, run_html::label(&req.config, simulator.engine_kind())));
    let (stopped, stream) = run_in_chunks(
        &mut simulator,
        duration,
        &stop,
        recording.as_ref().map(|r| (&sim, r)),
    )?;
    let rounds = simulator.finish_data()?;
    let summary = RunSummary::new(
        simulator.clock().step,
        simulator.clock().dt,
        wall.elapsed().as_secs_f64(),
        start_com,
        simulator.com(0)?,
    );
    let html = match (&req.html, stream) {
        (Some(file), Some(stream)) => {
            let beside = run_html::compare_stream(req, registry, (duration, seed), &stop)?;
            let streams: Vec<&PoseStream> = std::iter::once(&stream).chain(&beside).collect();
            Some(run_html::write_page(file, &streams)?)
        }
        _ => None,
    };
    Ok(RunReport {
        simulation: sim.file.clone(),
        robot: sim.robot.name.clone(),
        engine: simulator.engine().settings(),
        seed,
        real_robot_mode: props.mode == Mode::RealRobot,
        summary,
        heading: (heading0, simulator.heading(0)?),
        data: req.data.clone().map(|f| (f, rounds)),
        failures: simulator
            .kernel(0)
            .map(|k| {
                k.failures()
                    .map(|(m, cause)| (m.to_string(), cause.to_string()))
                    .collect()
            })
            .unwrap_or_default(),
        stopped,
        html,
    })
}

/// How a run builds its world: one robot, `seed`, on `settings`' engine.
pub fn one_robot(seed: u64, settings: EngineSettings) -> BuildOptions {
    BuildOptions {
        robots: 1,
        seed,
        record: false,
        engine: settings.into(),
        ..Default::default()
    }
}

/// The run's duration (`--duration`, else the file's `duration`), checked with
/// `--realtime`.
fn checked_duration(req: &RunRequest, file_duration: f64) -> Result<f64, CliError> {
    let duration = req.duration.unwrap_or(file_duration);
    if !duration.is_finite() || duration < 0.0 {
        return Err(CliError::Option {
            option: "--duration",
            value: duration.to_string(),
            want: "give a number of seconds >= 0",
        });
    }
    if !req.realtime.is_finite() || req.realtime < 0.0 {
        return Err(CliError::Option {
            option: "--realtime",
            value: req.realtime.to_string(),
            want: "give a factor >= 0 (0 = as fast as possible)",
        });
    }
    Ok(duration)
}

/// Starts `--data`'s file, sampled every `--every` steps (else the file's `accuracy`).
fn start_data(req: &RunRequest, simulator: &mut Simulator, accuracy: u32) -> Result<(), CliError> {
    let Some(file) = &req.data else {
        return Ok(());
    };
    let every = req.every.unwrap_or(accuracy.max(1));
    if every == 0 {
        return Err(CliError::Option {
            option: "--every",
            value: "0".into(),
            want: "give a sampling period of at least 1 step",
        });
    }
    let settings = DataSettings {
        every,
        ..DataSettings::default()
    };
    simulator.record_to(file, settings)?;
    Ok(())
}

/// Runs `duration` seconds as one episode, stopping early on `stop` (Ctrl-C / SIGTERM) or
/// when the robot leaves the world; says which stopped it. A paced run paces each chunk;
/// with `replay` (the loaded simulation and how to record), the run is recorded as a pose
/// stream (unpaced).
fn run_in_chunks(
    simulator: &mut Simulator,
    duration: f64,
    stop: &StopFlag,
    replay: Option<(&Simulation, &Recording)>,
) -> Result<(Option<RunStop>, Option<PoseStream>), CliError> {
    // `proleg run` reports displacement (the stream's score over time is it too).
    let settings = EpisodeSettings::new(simulator, duration, Fitness::Displacement);
    let mut episode = Episode::begin(simulator, settings)?;
    let pacer = Pacer::new(simulator.pacing(), simulator.clock().dt);
    let (end, stream) = match replay {
        Some((sim, recording)) => {
            let r = record_episode(sim, simulator, &mut episode, recording, Some(stop))?;
            (r.end, Some(r.stream))
        }
        None if pacer.is_paced() => (paced(simulator, &mut episode, &pacer, stop)?, None),
        None => (
            episode.run(simulator, Some(stop), |_| Ok::<(), CliError>(()))?,
            None,
        ),
    };
    let stopped = match end {
        EpisodeEnd::Duration => None,
        EpisodeEnd::Stopped => Some(RunStop::Interrupted),
        EpisodeEnd::Left(exit) => Some(RunStop::Left(exit)),
    };
    Ok((stopped, stream))
}

/// [`Episode::advance`] one step at a time against the wall clock (the exit rule still
/// reads the world at the cadence's steps only).
fn paced(
    simulator: &mut Simulator,
    episode: &mut Episode,
    pacer: &Pacer,
    stop: &StopFlag,
) -> Result<EpisodeEnd, CliError> {
    let wall = Instant::now();
    loop {
        if let Some(end) = episode.advance(simulator, 1, Some(stop))? {
            return Ok(end);
        }
        let k = episode.steps(simulator);
        if let Some(wait) = pacer.due(k).checked_sub(wall.elapsed()) {
            std::thread::sleep(wait);
        }
    }
}

impl fmt::Display for RunReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.summary;
        let f3 = |v: [f64; 3]| format!("{:.4} {:.4} {:.4}", v[0], v[1], v[2]);
        writeln!(out, "simulation      {}", self.simulation.display())?;
        writeln!(out, "robot           {} (seed {})", self.robot, self.seed)?;
        writeln!(out, "physics         {}", self.engine)?;
        if self.real_robot_mode {
            writeln!(
                out,
                "mode            Real Robot Control: this run simulates the robot's twin; \
                 `proleg robot {} --port PORT` drives the servos",
                self.simulation.display()
            )?;
        }
        writeln!(out, "steps           {}", s.steps)?;
        writeln!(out, "simulated time  {:.3} s", s.sim_time)?;
        writeln!(out, "wall time       {:.3} s", s.wall_time)?;
        writeln!(out, "real-time factor {:.1}", s.realtime_factor)?;
        writeln!(out, "start COM       {} m", f3(s.start_com))?;
        writeln!(out, "end COM         {} m", f3(s.end_com))?;
        writeln!(out, "displacement    {:.4} m (eq. 3.7)", s.displacement)?;
        writeln!(out, "mean speed      {:.4} m/s", s.mean_speed)?;
        let (h0, h1) = self.heading;
        writeln!(out, "heading         {h0:.1} -> {h1:.1} deg")?;
        if let Some((file, rounds)) = &self.data {
            writeln!(out, "data            {} ({rounds} rounds)", file.display())?;
        }
        if let Some(h) = &self.html {
            let frames: Vec<String> = h.frames.iter().map(ToString::to_string).collect();
            writeln!(
                out,
                "3D replay       {} ({:.2} MB, {} frames{})",
                h.file.display(),
                h.bytes as f64 / 1e6,
                frames.join(" + "),
                h.beside
                    .as_ref()
                    .map_or_else(String::new, |b| format!("; beside it: {b}"))
            )?;
        }
        for (module, cause) in &self.failures {
            writeln!(out, "module failed   {module}: {cause}")?;
        }
        match self.stopped {
            Some(RunStop::Interrupted) => writeln!(
                out,
                "interrupted     stopped early by a signal; the data file is closed"
            )?,
            Some(RunStop::Left(WorldExit::Left(c))) => writeln!(
                out,
                "left the world  at {:.3} s: its centre of mass {} m is off the scenery; \
                 the run ends there",
                s.sim_time,
                f3(c)
            )?,
            Some(RunStop::Left(WorldExit::Diverged)) => writeln!(
                out,
                "diverged        at {:.3} s: the physics blew up; the run ends there",
                s.sim_time
            )?,
            None => {}
        }
        Ok(())
    }
}
