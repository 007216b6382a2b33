//! `proleg robot` (the real-robot mode on a serial port) and `proleg robot-emulator` (an
//! emulated Dynamixel bus on a pseudo-terminal to try it without hardware).

use std::fmt;
use std::path::PathBuf;

use crate::cli::error::CliError;
use crate::control::{ModuleRegistry, load_simulation_in};
use crate::robot_io::dynamixel::DynamixelChain;
use crate::robot_io::emulator::EmulatedBus;
use crate::robot_io::emulator::servo::ServoDynamics;
use crate::robot_io::real_mode::{RealOptions, RealSummary, run};

/// `proleg robot`'s arguments.
#[derive(clap::Args)]
pub struct RobotOptions {
    /// A `*.simulation.xml` file (its robot file's `<Servos>` maps joints to servos).
    pub config: PathBuf,
    /// The serial port of the servo bus (e.g. /dev/ttyUSB0).
    #[arg(long)]
    pub port: PathBuf,
    /// Baud rate (default: the robot file's, else 1000000).
    #[arg(long)]
    pub baud: Option<u32>,
    /// Seconds to run (default: until Ctrl-C).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Record every data handler to this B.8 data file.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Sample every this many steps (default: the file's accuracy).
    #[arg(long)]
    pub every: Option<u32>,
    /// Read positions, currents and speeds back every this many steps.
    #[arg(long)]
    pub read_every: Option<u32>,
    /// Seed of the modules' random numbers (default: the file's).
    #[arg(long)]
    pub seed: Option<u64>,
}

/// Runs the real-robot mode and summarizes it.
pub fn robot(o: &RobotOptions, registry: &ModuleRegistry) -> Result<RobotReport, CliError> {
    if let Some(d) = o.duration
        && !(d.is_finite() && d >= 0.0)
    {
        return Err(CliError::Option {
            option: "--duration",
            value: d.to_string(),
            want: "give a number of seconds >= 0",
        });
    }
    let sim = load_simulation_in(&o.config, registry)?;
    let mut chain = DynamixelChain::new(
        &o.port,
        o.baud,
        sim.robot.servos.clone(),
        &sim.robot.pattern(),
    );
    let stop = crate::signal::subscribe()?;
    let opts = RealOptions {
        duration: o.duration,
        read_every: o.read_every,
        every: o.every,
        seed: o.seed.unwrap_or(sim.files.simulation.properties.seed),
    };
    let summary = run(
        &sim,
        registry,
        &mut chain,
        &opts,
        o.data.as_deref(),
        &stop.flag().0,
    )?;
    let report = RobotReport {
        robot: sim.robot.name.clone(),
        port: o.port.clone(),
        data: o.data.clone(),
        summary,
    };
    match &report.summary.error {
        Some(e) => Err(CliError::RobotStopped {
            cause: e.clone(),
            report: report.to_string(),
        }),
        None => Ok(report),
    }
}

/// What a real-robot run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotReport {
    /// The robot's name.
    pub robot: String,
    /// The serial port.
    pub port: PathBuf,
    /// The data file, if one was recorded.
    pub data: Option<PathBuf>,
    /// Steps, read-backs, timing, last readings, shutdown.
    pub summary: RealSummary,
}

impl fmt::Display for RobotReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.summary;
        writeln!(
            out,
            "robot           {} on {}",
            self.robot,
            self.port.display()
        )?;
        writeln!(
            out,
            "steps           {} ({} read-backs, {} failed)",
            s.steps, s.reads, s.failed_reads
        )?;
        if let Some(e) = &s.last_read_error {
            writeln!(out, "last failed read {e}")?;
        }
        writeln!(out, "wall time       {:.3} s", s.wall)?;
        writeln!(out, "late steps      {}", s.late_steps)?;
        let angles: Vec<String> = s
            .readings
            .positions
            .iter()
            .map(|a| format!("{a:.1}"))
            .collect();
        writeln!(out, "last angles     {} deg", angles.join(" "))?;
        if let Some(d) = &self.data {
            writeln!(
                out,
                "data            {} ({} samples)",
                d.display(),
                s.samples
            )?;
        }
        match &s.shutdown_error {
            Some(e) => writeln!(out, "torque off      FAILED: {e}"),
            None => writeln!(out, "torque off      yes"),
        }
    }
}

/// `proleg robot-emulator`'s arguments.
#[derive(clap::Args)]
pub struct EmulatorOptions {
    /// Number of servos (ids 1..N).
    #[arg(long, default_value_t = 5)]
    pub servos: u8,
    /// Servo speed toward the goal (degrees/s).
    #[arg(long, default_value_t = 300.0)]
    pub speed: f64,
    /// Proportional gain (1/s; default: the top speed until the goal).
    #[arg(long)]
    pub gain: Option<f64>,
    /// Angle error left uncorrected (degrees).
    #[arg(long, default_value_t = 0.0)]
    pub dead_band: f64,
    /// How long a written goal takes to act (s).
    #[arg(long, default_value_t = 0.0)]
    pub latency: f64,
    /// Noise on the reported position (standard deviation, degrees).
    #[arg(long, default_value_t = 0.0)]
    pub noise: f64,
    /// Play between motor and output shaft (degrees).
    #[arg(long, default_value_t = 0.0)]
    pub backlash: f64,
}

impl EmulatorOptions {
    /// The servos' dynamics; an error names a value out of range.
    pub fn dynamics(&self) -> Result<ServoDynamics, CliError> {
        let check = |option: &'static str, v: f64, ok: bool| {
            if v.is_finite() && ok {
                Ok(v)
            } else {
                Err(CliError::Option {
                    option,
                    value: v.to_string(),
                    want: "give a number >= 0 (a speed and a gain > 0)",
                })
            }
        };
        Ok(ServoDynamics {
            speed_deg_s: check("--speed", self.speed, self.speed > 0.0)?,
            gain: match self.gain {
                Some(g) => check("--gain", g, g > 0.0)?,
                None => f64::INFINITY,
            },
            dead_band_deg: check("--dead-band", self.dead_band, self.dead_band >= 0.0)?,
            latency_s: check("--latency", self.latency, self.latency >= 0.0)?,
            noise_deg: check("--noise", self.noise, self.noise >= 0.0)?,
            backlash_deg: check("--backlash", self.backlash, self.backlash >= 0.0)?,
        })
    }
}

/// Runs an emulated bus until Ctrl-C.
pub fn emulator(o: &EmulatorOptions) -> Result<String, CliError> {
    if o.servos == 0 || o.servos > 252 {
        return Err(CliError::Option {
            option: "--servos",
            value: o.servos.to_string(),
            want: "give 1..252",
        });
    }
    let ids: Vec<u8> = (1..=o.servos).collect();
    let bus = EmulatedBus::start_with(&ids, o.dynamics()?)?;
    println!(
        "emulating {} Dynamixel servos (ids 1..{}) on {}",
        o.servos,
        o.servos,
        bus.path().display()
    );
    println!(
        "run e.g.: proleg robot configs/snake5p_real.simulation.xml --port {}",
        bus.path().display()
    );
    println!("Ctrl-C stops the emulator");
    let (tx, rx) = std::sync::mpsc::channel();
    let _signal = crate::signal::subscribe_with(move || {
        if tx.send(()).is_err() {
            // The emulator stopped already.
        }
    })?;
    // Waits for the signal (the sender lives as long as the subscription).
    rx.recv().unwrap_or(());
    let stats = bus.stats();
    Ok(format!(
        "stopped after {} packets ({} sync writes, {} sync reads)\n",
        stats.packets, stats.sync_writes, stats.sync_reads
    ))
}
