//! The simulation clock (thesis eq. 4.1-4.2): a step counter, the simulated time, the step
//! width δ, and the wall-clock controls a runner applies between steps (delay μ per step,
//! real-time factor). Nothing here reads the wall clock inside a step.

use bevy::prelude::*;

/// Simulated time and the pacing settings.
#[derive(Resource, Debug, Clone, PartialEq)]
pub struct SimClock {
    /// Steps done.
    pub step: u64,
    /// Step width δ (s).
    pub dt: f64,
    /// Extra wall-clock delay per step μ (ms), for slow motion.
    pub delay_ms: f64,
    /// 1 = real time, 0 = as fast as possible.
    pub realtime_factor: f64,
}

impl SimClock {
    pub fn new(dt: f64) -> Self {
        SimClock {
            step: 0,
            dt,
            delay_ms: 0.0,
            realtime_factor: 0.0,
        }
    }

    /// Simulated time (s) of the current step: step · δ (no accumulated rounding).
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }
}

/// Advances the clock (the `Clock` set, last in the pipeline).
pub fn advance_clock(mut clock: ResMut<SimClock>) {
    clock.step += 1;
}
