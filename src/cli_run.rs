//! `proleg run`: one headless run of a simulation file, summarized; with `--data`, every
//! data handler is recorded to a B.8 data file, closed well-formed also on Ctrl-C and
//! SIGTERM (the run stops at the next chunk of steps).

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use proleg::config::load_simulation;
use proleg::data::store::DataStore;
use proleg::sim::datalog::{DataSettings, handlers_for};
use proleg::sim::{BuildOptions, Simulator};

/// Where and how often `proleg run` records.
pub struct DataOptions<'a> {
    pub file: Option<&'a Path>,
    /// Sample every this many steps (default: the file's accuracy).
    pub every: Option<u32>,
}

/// Simulated seconds between checks for Ctrl-C / SIGTERM.
const CHUNK_SECONDS: f64 = 0.5;

/// Loads, runs and summarizes; the error is the message to print.
pub fn run(
    config: &Path,
    duration: Option<f64>,
    seed: Option<u64>,
    realtime: f64,
    data: DataOptions<'_>,
) -> Result<String, String> {
    let sim = load_simulation(config).map_err(|e| e.to_string())?;
    let props = &sim.files.simulation.properties;
    let duration = duration.unwrap_or(props.duration);
    if !duration.is_finite() || duration < 0.0 {
        return Err(format!(
            "--duration {duration}: give a number of seconds >= 0"
        ));
    }
    if !realtime.is_finite() || realtime < 0.0 {
        return Err(format!(
            "--realtime {realtime}: give a factor >= 0 (0 = as fast as possible)"
        ));
    }
    let opts = BuildOptions {
        robots: 1,
        seed: seed.unwrap_or(props.seed),
        record: false,
    };
    let mut simulator = Simulator::new(&sim, &opts).map_err(|e| e.to_string())?;
    {
        let mut clock = simulator
            .world_mut()
            .resource_mut::<proleg::sim::clock::SimClock>();
        clock.realtime_factor = realtime;
        clock.delay_ms = 0.0;
    }
    if let Some(file) = data.file {
        let every = data.every.unwrap_or(props.accuracy.max(1));
        if every == 0 {
            return Err("--every 0: give a sampling period of at least 1 step".into());
        }
        let handlers = {
            let kernel = simulator.kernel(0).map_err(|e| e.to_string())?;
            let sensors = simulator
                .world()
                .get::<proleg::sim::tactile::RobotSensors>(simulator.robots()[0])
                .map(|s| s.0.clone())
                .unwrap_or_default();
            handlers_for(kernel, &sensors)
        };
        let store = DataStore::create(file, handlers)?;
        let settings = DataSettings {
            every,
            ..DataSettings::default()
        };
        simulator.enable_data(settings, Some(store));
    }
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        // Only one handler per process; a second `run` in the same process keeps the first.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    let heading0 = simulator.heading(0).map_err(|e| e.to_string())?;
    let start_com = simulator.com(0).map_err(|e| e.to_string())?;
    let wall = Instant::now();
    let mut done = 0.0;
    let mut interrupted = false;
    while done < duration - 1e-9 {
        if stop.load(Ordering::SeqCst) {
            interrupted = true;
            break;
        }
        let chunk = CHUNK_SECONDS.min(duration - done);
        simulator.run_for(chunk);
        done += chunk;
    }
    let rounds = simulator.finish_data()?;
    let steps = simulator.clock().step;
    let end_com = simulator.com(0).map_err(|e| e.to_string())?;
    let heading1 = simulator.heading(0).map_err(|e| e.to_string())?;
    let s = proleg::sim::runner::RunSummary::new(
        steps,
        simulator.clock().dt,
        wall.elapsed().as_secs_f64(),
        start_com,
        end_com,
    );
    let mut out = String::new();
    let f3 = |v: [f64; 3]| format!("{:.4} {:.4} {:.4}", v[0], v[1], v[2]);
    let _ = writeln!(out, "simulation      {}", sim.file.display());
    let _ = writeln!(
        out,
        "robot           {} (seed {})",
        sim.robot.name, opts.seed
    );
    if props.mode == proleg::config::simulation::Mode::RealRobot {
        let _ = writeln!(
            out,
            "mode            Real Robot Control: this run simulates the robot's twin; \
             `proleg robot {} --port PORT` drives the servos",
            config.display()
        );
    }
    let _ = writeln!(out, "steps           {}", s.steps);
    let _ = writeln!(out, "simulated time  {:.3} s", s.sim_time);
    let _ = writeln!(out, "wall time       {:.3} s", s.wall_time);
    let _ = writeln!(out, "real-time factor {:.1}", s.realtime_factor);
    let _ = writeln!(out, "start COM       {} m", f3(s.start_com));
    let _ = writeln!(out, "end COM         {} m", f3(s.end_com));
    let _ = writeln!(out, "displacement    {:.4} m (eq. 3.7)", s.displacement);
    let _ = writeln!(out, "mean speed      {:.4} m/s", s.mean_speed);
    let _ = writeln!(out, "heading         {heading0:.1} -> {heading1:.1} deg");
    if let Some(file) = data.file {
        let _ = writeln!(out, "data            {} ({rounds} rounds)", file.display());
    }
    if let Ok(kernel) = simulator.kernel(0) {
        for (module, cause) in kernel.failures() {
            let _ = writeln!(out, "module failed   {module}: {cause}");
        }
    }
    if interrupted {
        let _ = writeln!(
            out,
            "interrupted     stopped early by a signal; the data file is closed"
        );
    }
    Ok(out)
}
