//! The simulation clock (thesis eq. 4.1): a step counter, the simulated time and the step
//! width δ. Wall-clock pacing (delay μ per step, real-time factor, eq. 4.2) is the
//! runner's business between steps ([`crate::sim::pacing`]); nothing in a step reads the
//! wall clock.

use bevy::prelude::*;

/// Simulated time.
#[derive(Resource, Debug, Clone, PartialEq)]
pub struct SimClock {
    /// Steps done.
    pub step: u64,
    /// Step width δ (s).
    pub dt: f64,
}

impl SimClock {
    /// A clock at step 0 with step width `dt` (s).
    pub fn new(dt: f64) -> Self {
        SimClock { step: 0, dt }
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
