//! `proleg run`: one headless run of a simulation file, summarized.

use std::fmt::Write as _;
use std::path::Path;

use proleg::config::load_simulation;
use proleg::sim::{BuildOptions, Simulator};

/// Loads, runs and summarizes; the error is the message to print.
pub fn run(
    config: &Path,
    duration: Option<f64>,
    seed: Option<u64>,
    realtime: f64,
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
    let heading0 = simulator.heading(0).map_err(|e| e.to_string())?;
    let s = simulator.run_for(duration);
    let heading1 = simulator.heading(0).map_err(|e| e.to_string())?;
    let mut out = String::new();
    let f3 = |v: [f64; 3]| format!("{:.4} {:.4} {:.4}", v[0], v[1], v[2]);
    let _ = writeln!(out, "simulation      {}", sim.file.display());
    let _ = writeln!(
        out,
        "robot           {} (seed {})",
        sim.robot.name, opts.seed
    );
    let _ = writeln!(out, "steps           {}", s.steps);
    let _ = writeln!(out, "simulated time  {:.3} s", s.sim_time);
    let _ = writeln!(out, "wall time       {:.3} s", s.wall_time);
    let _ = writeln!(out, "real-time factor {:.1}", s.realtime_factor);
    let _ = writeln!(out, "start COM       {} m", f3(s.start_com));
    let _ = writeln!(out, "end COM         {} m", f3(s.end_com));
    let _ = writeln!(out, "displacement    {:.4} m (eq. 3.7)", s.displacement);
    let _ = writeln!(out, "mean speed      {:.4} m/s", s.mean_speed);
    let _ = writeln!(out, "heading         {heading0:.1} -> {heading1:.1} deg");
    Ok(out)
}
