//! Wall-clock pacing of a simulation, the one pacer the command line, the control window
//! and the real-robot loop share: a real-time factor and a slow-motion delay per step
//! become a wall-clock period per step. Nothing here runs inside a step; the runners ask it
//! between steps how many are due (a window frame) or when the next one is (a blocking
//! loop).

use std::time::Duration;

use crate::config::simulation::SimulationProperties;

/// How fast a simulation runs against the wall clock.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pacing {
    /// Simulated seconds per wall second; 0 = as fast as possible.
    pub realtime_factor: f64,
    /// Extra wall-clock delay per step μ (ms), for slow motion (thesis eq. 4.2).
    pub delay_ms: f64,
}

impl Pacing {
    /// As fast as the machine goes (headless runs, optimizers, benchmarks).
    pub const UNPACED: Pacing = Pacing {
        realtime_factor: 0.0,
        delay_ms: 0.0,
    };

    /// Real time (a real robot, a simulation shown at 1x).
    pub const REAL_TIME: Pacing = Pacing {
        realtime_factor: 1.0,
        delay_ms: 0.0,
    };

    /// The pacing a simulation file asks for (`realtimeFactor`, `delay`); negative or
    /// non-finite values count as 0.
    pub fn of(props: &SimulationProperties) -> Pacing {
        let clean = |v: f64| if v.is_finite() { v.max(0.0) } else { 0.0 };
        Pacing {
            realtime_factor: clean(props.realtime_factor),
            delay_ms: clean(props.delay_ms),
        }
    }

    /// Wall seconds per step of `dt` simulated seconds: the slower of the real-time
    /// factor's period and the delay; 0 when unpaced.
    pub fn step_period(&self, dt: f64) -> f64 {
        let realtime = if self.realtime_factor > 0.0 {
            dt / self.realtime_factor
        } else {
            0.0
        };
        realtime.max(self.delay_ms / 1000.0).max(0.0)
    }
}

/// Steps due against the wall clock, for a given pacing and step width.
#[derive(Debug, Clone, PartialEq)]
pub struct Pacer {
    period: f64,
    /// Wall seconds received but not yet spent on steps (frame pacing).
    owed: f64,
}

impl Pacer {
    /// A pacer for steps of `dt` seconds.
    pub fn new(pacing: Pacing, dt: f64) -> Pacer {
        Pacer {
            period: pacing.step_period(dt),
            owed: 0.0,
        }
    }

    /// Follows a changed pacing or step width (a window's toolbar), keeping the wall time
    /// owed.
    pub fn retune(&mut self, pacing: Pacing, dt: f64) {
        self.period = pacing.step_period(dt);
    }

    /// Whether steps wait for the wall clock at all.
    pub fn is_paced(&self) -> bool {
        self.period > 0.0
    }

    /// When step `k` (counted from 1 since the pacer's start) is due, measured from that
    /// start: `k` periods. A blocking loop sleeps until then.
    pub fn due(&self, k: u64) -> Duration {
        Duration::from_secs_f64(k as f64 * self.period)
    }

    /// Steps due after `wall` more wall seconds (a window frame); `None` when unpaced (as
    /// many as the caller's budget allows). The remainder carries over to the next frame.
    pub fn steps_for(&mut self, wall: f64) -> Option<u64> {
        if !self.is_paced() {
            return None;
        }
        self.owed += wall.max(0.0);
        let n = (self.owed / self.period).floor();
        self.owed -= n * self.period;
        Some(n as u64)
    }

    /// Forgets the wall time owed (the caller could not keep up: no spiral of catching up).
    pub fn drop_backlog(&mut self) {
        self.owed = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slower_of_factor_and_delay_sets_the_period() {
        let p = Pacing {
            realtime_factor: 2.0,
            delay_ms: 0.0,
        };
        assert_eq!(p.step_period(0.001), 0.0005);
        let slow = Pacing {
            realtime_factor: 2.0,
            delay_ms: 10.0,
        };
        assert_eq!(slow.step_period(0.001), 0.01);
        assert_eq!(Pacing::UNPACED.step_period(0.001), 0.0);
    }

    #[test]
    fn frames_receive_the_steps_their_wall_time_owes() {
        // Binary fractions, so the sums are exact.
        let mut p = Pacer::new(Pacing::REAL_TIME, 0.25);
        assert_eq!(p.steps_for(0.625), Some(2));
        // The half step left over comes with the next frame.
        assert_eq!(p.steps_for(0.375), Some(2));
        assert_eq!(p.steps_for(0.125), Some(0));
        p.drop_backlog();
        assert_eq!(p.steps_for(0.125), Some(0));
        assert_eq!(Pacer::new(Pacing::UNPACED, 0.01).steps_for(1.0), None);
    }

    #[test]
    fn blocking_loops_wait_whole_periods() {
        let p = Pacer::new(Pacing::REAL_TIME, 0.002);
        assert_eq!(p.due(5), Duration::from_millis(10));
    }
}
