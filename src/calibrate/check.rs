//! What a calibration buys on a gait: a gait recorded on the robot is simulated twice —
//! with the robot file's servo model and with the calibrated one — and each simulated
//! joint's angles are compared with the recorded real ones at the recording's sample
//! times (RMS per joint). The simulation is the gait's own file (robot on its floor), so
//! the gap that remains is what the servo model does not cover (load, contacts).

use crate::calibrate::recording::Recording;
use crate::calibrate::replay::{ServoModel, rms};
use crate::calibrate::{CalibrateError, CalibrationReport, of_this_robot};
use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::sim::{BuildOptions, Simulator};

/// The tracking gap of a gait before and after calibration.
#[derive(Debug, Clone, PartialEq)]
pub struct GaitGap {
    /// The gait's recording.
    pub file: std::path::PathBuf,
    /// RMS (degrees) per joint between recorded and simulated angles, robot file's servos.
    pub before: Vec<f64>,
    /// The same with the calibrated servos.
    pub after: Vec<f64>,
}

impl std::fmt::Display for GaitGap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "gait {}: recorded against simulated angles (RMS deg), robot file's servos -> calibrated:",
            self.file.display()
        )?;
        for (j, (b, a)) in self.before.iter().zip(&self.after).enumerate() {
            writeln!(f, "  J{:<3} {b:>8.3} -> {a:>8.3}", j + 1)?;
        }
        Ok(())
    }
}

/// `sim` with `models` as its joints' servos.
pub fn with_servos(sim: &Simulation, models: &[ServoModel]) -> Simulation {
    let mut out = sim.clone();
    for (j, m) in out.robot.joints.iter_mut().zip(models) {
        j.servo_gain = Some(m.gain);
        j.max_vel = m.max_vel_deg_s.to_radians();
        j.dead_band_deg = m.dead_band_deg;
        j.latency_s = m.latency_s;
    }
    out
}

/// The simulated angles (degrees) of `sim`'s joints at `times`, per joint.
fn simulated(
    sim: &Simulation,
    times: &[f64],
    registry: &ModuleRegistry,
) -> Result<Vec<Vec<f64>>, CalibrateError> {
    let opts = BuildOptions {
        seed: sim.files.simulation.properties.seed,
        ..BuildOptions::default()
    };
    let mut s = Simulator::with_registry(sim, &opts, registry)?;
    let dt = s.clock().dt;
    let mut out = vec![Vec::with_capacity(times.len()); sim.robot.joints.len()];
    let mut done = 0u64;
    for t in times {
        let due = (t / dt).round().max(0.0) as u64;
        if due > done {
            s.run_steps(due - done);
            done = due;
        }
        for (series, state) in out.iter_mut().zip(s.joint_states(0)?) {
            series.push(state.angle);
        }
    }
    Ok(out)
}

/// The gap between the gait recording `gait` (of `sim`'s gait on the robot) and `sim`
/// simulated with the robot file's servos and with `report`'s calibrated ones.
pub fn gait_gap(
    gait: &Recording,
    sim: &Simulation,
    report: &CalibrationReport,
    registry: &ModuleRegistry,
) -> Result<GaitGap, CalibrateError> {
    let joints = of_this_robot(gait, sim)?;
    let calibrated: Vec<ServoModel> = (0..joints).map(|j| report.after(j)).collect();
    let gap = |angles: Vec<Vec<f64>>| -> Vec<f64> {
        angles
            .iter()
            .zip(&gait.real)
            .map(|(sim, real)| rms(sim, real))
            .collect()
    };
    Ok(GaitGap {
        file: gait.file.clone(),
        before: gap(simulated(sim, &gait.times, registry)?),
        after: gap(simulated(
            &with_servos(sim, &calibrated),
            &gait.times,
            registry,
        )?),
    })
}
