//! The environment's observation: the layout and writer of
//! [`crate::control::observation`] (the `Policy` module writes the same vector), filled
//! from the world after each environment step. Joint angles and speeds, gravity and the
//! centre of mass are read as the engine has them after the last physics step (what the
//! module's next step senses); pads and lasers are the sensors' latest readings, taken at
//! the start of that physics step (the module sees them one physics step later). Every part is present; the generators' phases
//! only in residual mode (the file's modules run beside the policy).

use crate::control::observation::{
    ObsLayout, ObsParts, ObsSource, heading_velocity, write_observation,
};
use crate::gym::error::GymError;
use crate::sensing::SensorData;
use crate::sim::Simulator;

/// The layout of robot 0 of `world`; `residual` adds the phases of its kernel's generators.
pub fn layout_of(world: &Simulator, residual: bool) -> Result<ObsLayout, GymError> {
    let kernel = world.kernel(0)?;
    let phases = if residual {
        kernel.generators().len()
    } else {
        0
    };
    Ok(ObsLayout::new(
        kernel.joints(),
        world.sensors(0)?,
        phases,
        ObsParts::ALL,
    ))
}

/// Where robot 0 was at the last observation, for its velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Previous {
    /// Centre of mass (m).
    pub com: [f64; 3],
}

/// Room reused between observations (nothing is allocated once it has grown).
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    angles: Vec<f64>,
    sensors: SensorData,
    phases: Vec<f64>,
}

/// Writes robot 0's observation into `out` (of [`ObsLayout::len`] values); `period` is
/// the seconds since `prev`.
pub fn observe(
    world: &Simulator,
    layout: &ObsLayout,
    prev: &Previous,
    period: f64,
    scratch: &mut Scratch,
    out: &mut [f64],
) -> Result<(), GymError> {
    if out.len() != layout.len() {
        return Err(GymError::Shape {
            what: "the observation buffer",
            given: out.len(),
            want: layout.len(),
        });
    }
    let s = &mut scratch.sensors;
    s.clone_from(world.sensors(0)?);
    world.joint_motion_into(0, &mut scratch.angles, &mut s.joint_speeds)?;
    s.gravity_head = world.gravity_in_head(0)?;
    let com = world.com(0)?;
    let velocity = heading_velocity(prev.com, com, period, world.heading(0)?);
    let kernel = world.kernel(0)?;
    scratch.phases.resize(layout.phases, 0.0);
    kernel.phases_into(&mut scratch.phases);
    let src = ObsSource {
        angles: &scratch.angles,
        sensors: s,
        velocity,
        phases: &scratch.phases,
    };
    write_observation(layout, &src, out);
    Ok(())
}
