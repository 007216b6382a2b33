//! The real-robot mode (thesis 4.3.3): the control kernel of a simulation file drives a
//! real robot in real time. Each step of the file's step width the kernel computes from
//! the latest measured angles and its goal angles go to the servos; every
//! `read_every` steps positions, currents and speeds are read back and feed the kernel
//! and the data file (the same B.8 format and handlers as a simulation: `Robot_Data`'s
//! joint series are the robot's readings, its body series are 0 — a real robot has no
//! ground-truth pose). On exit — the duration reached, Ctrl-C, or an error — the servos'
//! torque is switched off and the data file is closed.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::config::Simulation;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::data::FrameMeta;
use crate::data::store::DataStore;
use crate::data::write::HandlerFrames;
use crate::rng::SimRng;
use crate::robot_io::{Readings, RobotControl, RobotError};
use crate::sensing::SensorData;
use crate::sim::datalog::{ROBOT_SCALARS, RobotFrame, handlers_for};
use crate::sim::pacing::{Pacer, Pacing};

/// How the loop runs.
#[derive(Debug, Clone, PartialEq)]
pub struct RealOptions {
    /// Seconds to run; `None`: until stopped.
    pub duration: Option<f64>,
    /// Read back every this many steps (default: the robot file's `readEvery`).
    pub read_every: Option<u32>,
    /// Record a sample every this many steps (default: the file's accuracy).
    pub every: Option<u32>,
    /// Seed of the modules' random streams.
    pub seed: u64,
}

/// What a run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RealSummary {
    /// Steps run.
    pub steps: u64,
    /// Read-backs that succeeded.
    pub reads: u64,
    /// Read-backs that failed (a garbled or missing answer); the run goes on with the
    /// last good readings until [`MAX_FAILED_READS`] fail in a row.
    pub failed_reads: u64,
    /// Why the last failed read-back failed.
    pub last_read_error: Option<String>,
    /// Wall-clock seconds of the run, also of one an error stopped.
    pub wall: f64,
    /// Steps that started later than one step width behind their time.
    pub late_steps: u64,
    /// The last readings.
    pub readings: Readings,
    /// Samples written to the data file.
    pub samples: u64,
    /// The error that stopped the run, if one did (the servos were switched off).
    pub error: Option<String>,
    /// Switching the torque off at the end failed.
    pub shutdown_error: Option<String>,
}

/// Consecutive failed read-backs that stop the run (a bus has the odd garbled packet; a
/// servo that stopped answering fails every time).
pub const MAX_FAILED_READS: u32 = 3;

/// Samples per round handed to the data writer.
const ROUND: usize = 100;

/// The data file side of the loop: frames gathered and sent in rounds.
struct Recorder {
    store: DataStore,
    round: Vec<HandlerFrames>,
    samples: u64,
}

impl Recorder {
    fn sample(
        &mut self,
        kernel: &ControlKernel,
        r: &Readings,
        step: u64,
        dt: f64,
    ) -> Result<(), RealModeError> {
        let meta = FrameMeta::after_step(self.samples, step, dt);
        let actuators = kernel.actuators();
        for (h, frames) in self.round.iter_mut().enumerate() {
            frames.meta.push(meta);
            if let Some(a) = actuators.get(h) {
                let d = a.module.internal_data();
                for s in 0..d.names().len() {
                    frames.values.extend_from_slice(d.series(s));
                }
            } else {
                // Robot_Data: no ground-truth body series on a real robot.
                RobotFrame {
                    scalars: [0.0; ROBOT_SCALARS.len()],
                    desired: kernel.desired().iter().copied(),
                    angles: r.positions.iter().copied(),
                    currents: r.currents.iter().copied(),
                    speeds: r.speeds.iter().copied(),
                }
                .append_to(&mut frames.values);
            }
        }
        self.samples += 1;
        if self.round[0].len() >= ROUND {
            self.flush()?;
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), crate::data::store::DataStoreError> {
        if self.round.iter().all(HandlerFrames::is_empty) {
            return Ok(());
        }
        let round = self
            .round
            .iter_mut()
            .map(|f| HandlerFrames {
                meta: std::mem::take(&mut f.meta),
                values: std::mem::take(&mut f.values),
            })
            .collect();
        self.store.send(round)
    }
}

/// Why a run on the real robot could not start or stopped.
#[derive(Debug, thiserror::Error)]
pub enum RealModeError {
    /// The actuation's kernel cannot be built.
    #[error("{0}")]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// The robot has another number of servos than the configuration joints.
    #[error("the robot has {servos} servos, the configuration {joints} joints")]
    Joints {
        /// Servos on the bus.
        servos: usize,
        /// Joints of the configuration.
        joints: usize,
    },
    /// The bus or a servo failed.
    #[error("{0}")]
    Robot(#[from] RobotError),
    /// The data file could not be written.
    #[error("{0}")]
    Data(#[from] crate::data::store::DataStoreError),
}

/// The kernel of `sim` for the real robot, its modules made by `registry`, reset.
pub fn kernel_for(
    sim: &Simulation,
    seed: u64,
    registry: &ModuleRegistry,
) -> Result<ControlKernel, crate::control::kernel::KernelError> {
    let limits: Vec<[f64; 2]> = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let mut k = ControlKernel::from_actuation(&sim.actuation, registry, limits)?;
    k.reset(&mut SimRng::new(seed));
    Ok(k)
}

/// The data file's recorder, if a file is asked for.
fn recorder_for(
    data: Option<&Path>,
    kernel: &ControlKernel,
) -> Result<Option<Recorder>, RealModeError> {
    data.map(|path| -> Result<Recorder, RealModeError> {
        let handlers = handlers_for(kernel, &SensorData::default());
        let round = handlers
            .iter()
            .map(|h| HandlerFrames {
                meta: Vec::with_capacity(ROUND),
                values: Vec::with_capacity(ROUND * h.width()),
            })
            .collect();
        Ok(Recorder {
            store: DataStore::create(path, handlers)?,
            round,
            samples: 0,
        })
    })
    .transpose()
}

impl RealSummary {
    /// Nothing done yet, on `joints` joints.
    fn new(joints: usize) -> RealSummary {
        RealSummary {
            steps: 0,
            reads: 0,
            failed_reads: 0,
            last_read_error: None,
            wall: 0.0,
            late_steps: 0,
            readings: Readings::new(joints),
            samples: 0,
            error: None,
            shutdown_error: None,
        }
    }
}

/// Runs `sim`'s kernel on `robot` until the duration or `stop`; records into `data`.
/// The robot is connected and its servos enabled here; torque is off again at the end.
pub fn run(
    sim: &Simulation,
    registry: &ModuleRegistry,
    robot: &mut dyn RobotControl,
    opts: &RealOptions,
    data: Option<&Path>,
    stop: &AtomicBool,
) -> Result<RealSummary, RealModeError> {
    let props = &sim.files.simulation.properties;
    let dt = props.step_width;
    let mut kernel = kernel_for(sim, opts.seed, registry)?;
    let joints = kernel.joints();
    if robot.meta().joints != joints {
        return Err(RealModeError::Joints {
            servos: robot.meta().joints,
            joints,
        });
    }
    let plan = LoopPlan {
        dt,
        read_every: u64::from(
            opts.read_every
                .unwrap_or(sim.robot.servos.read_every)
                .max(1),
        ),
        every: u64::from(opts.every.unwrap_or(props.accuracy).max(1)),
        steps: opts.duration.map(|d| (d / dt).round() as u64),
    };
    robot.connect()?;
    let mut recorder = match recorder_for(data, &kernel) {
        Ok(r) => r,
        Err(e) => {
            robot.disconnect();
            return Err(e);
        }
    };
    let mut summary = RealSummary::new(joints);
    let started = Instant::now();
    let result = control_loop(&mut kernel, robot, &plan, stop, &mut recorder, &mut summary);
    // Also when an error ended the loop.
    summary.wall = started.elapsed().as_secs_f64();
    if let Err(e) = &result {
        summary.error = Some(e.to_string());
    }
    // Safe state whatever happened: torque off, then close.
    if let Err(e) = robot.enable_servos(false) {
        summary.shutdown_error = Some(e.to_string());
    }
    robot.disconnect();
    if let Some(mut r) = recorder {
        let flushed = r.flush();
        summary.samples = r.samples;
        let closed = r.store.finish();
        if summary.error.is_none() {
            flushed?;
            closed?;
        }
    }
    Ok(summary)
}

/// The real-time loop's timing: the step, how often servos are read and frames sampled,
/// and the steps to run (none: until stopped).
#[derive(Clone, Copy)]
struct LoopPlan {
    dt: f64,
    read_every: u64,
    every: u64,
    steps: Option<u64>,
}

/// Steps the kernel in real time on `robot` as `plan` says, reading the servos back and
/// sampling into `recorder`, until the steps are done, `stop` is raised or the servos fail.
fn control_loop(
    kernel: &mut ControlKernel,
    robot: &mut dyn RobotControl,
    plan: &LoopPlan,
    stop: &AtomicBool,
    recorder: &mut Option<Recorder>,
    summary: &mut RealSummary,
) -> Result<(), RealModeError> {
    robot.read(&mut summary.readings)?;
    summary.reads += 1;
    robot.set_joint_angles(&summary.readings.positions.clone())?;
    robot.enable_servos(true)?;
    let LoopPlan {
        dt,
        read_every,
        every,
        steps,
    } = *plan;
    let pacer = Pacer::new(Pacing::REAL_TIME, dt);
    let start = Instant::now();
    let mut step = 0u64;
    let mut failed_in_a_row = 0;
    // A real robot senses its joints only: no pads, lasers, gravity or position.
    let mut sensors = SensorData::default();
    while steps.is_none_or(|n| step < n) && !stop.load(Ordering::SeqCst) {
        let due = start + pacer.due(step);
        let now = Instant::now();
        if now > due + Duration::from_secs_f64(dt) {
            summary.late_steps += 1;
        } else if due > now {
            std::thread::sleep(due - now);
        }
        sensors.joint_speeds.clone_from(&summary.readings.speeds);
        let time = step as f64 * dt;
        kernel.compute_modules(time, dt, step, &summary.readings.positions, &sensors);
        let desired = kernel.sum();
        robot.set_joint_angles(desired)?;
        if (step + 1).is_multiple_of(read_every) {
            match robot.read(&mut summary.readings) {
                Ok(()) => {
                    summary.reads += 1;
                    failed_in_a_row = 0;
                }
                Err(e) => {
                    summary.failed_reads += 1;
                    summary.last_read_error = Some(e.to_string());
                    failed_in_a_row += 1;
                    if failed_in_a_row >= MAX_FAILED_READS {
                        return Err(e.into());
                    }
                }
            }
        }
        if (step + 1).is_multiple_of(every)
            && let Some(r) = recorder.as_mut()
        {
            r.sample(kernel, &summary.readings, step, dt)?;
        }
        step += 1;
        summary.steps = step;
    }
    Ok(())
}
