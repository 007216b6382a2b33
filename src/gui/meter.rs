//! Frame rate and real-time factor as achieved over the last second of wall time.
//!
//! Both windows read their speed from here rather than from Bevy's `Time<Virtual>`, whose
//! delta is capped at 0.25 s: at 2.6 frames/s the capped delta made a window report
//! "4.0 fps" and "1.0x" while it simulated at 0.65x. The meter keeps the frames of the last
//! second as (wall time, simulated time) pairs and divides the differences.

use std::collections::VecDeque;

/// How far back the figures look (wall seconds).
const WINDOW: f64 = 1.0;

/// Frames of the last second and what they say.
#[derive(Debug, Clone, Default)]
pub struct SpeedMeter {
    /// (wall seconds, simulated seconds) at each frame, oldest first; at most a second
    /// old plus the frame before it.
    frames: VecDeque<(f64, f64)>,
}

impl SpeedMeter {
    /// Records a frame drawn at wall time `wall` (seconds, any origin) with the simulation
    /// at `sim` seconds.
    pub fn frame(&mut self, wall: f64, sim: f64) {
        if let Some(&(_, last_sim)) = self.frames.back()
            && sim < last_sim
        {
            // Restarted: the old frames measure another run.
            self.frames.clear();
        }
        self.frames.push_back((wall, sim));
        // Keep one frame at or before the window's start, so the span covers a full second.
        while self.frames.len() > 2 && self.frames[1].0 <= wall - WINDOW {
            self.frames.pop_front();
        }
    }

    /// Forgets the frames (a new world, a pause): the figures restart from the next frames.
    pub fn reset(&mut self) {
        self.frames.clear();
    }

    /// Wall seconds the figures cover.
    fn span(&self) -> Option<(f64, f64)> {
        let (&(w0, s0), &(w1, s1)) = (self.frames.front()?, self.frames.back()?);
        (w1 > w0).then_some((w1 - w0, s1 - s0))
    }

    /// Frames per wall second over the last second; 0 before two frames.
    pub fn fps(&self) -> f64 {
        self.span()
            .map_or(0.0, |(wall, _)| (self.frames.len() - 1) as f64 / wall)
    }

    /// Simulated seconds per wall second over the last second; 0 before two frames.
    pub fn factor(&self) -> f64 {
        self.span().map_or(0.0, |(wall, sim)| sim / wall)
    }

    /// The speed readout: the achieved factor, and what was asked when it falls short of
    /// `requested` (0: as fast as possible) by more than 10 %.
    pub fn readout(&self, requested: f64, running: bool) -> String {
        let achieved = self.factor();
        if !running {
            return "paused".to_string();
        }
        if requested <= 0.0 {
            return format!("{achieved:.2}x (as fast as possible)");
        }
        if achieved < 0.9 * requested {
            format!("{achieved:.2}x of {requested:.2}x requested")
        } else {
            format!("{achieved:.2}x")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_frames_are_measured_not_capped() {
        // 2.5 frames per second, 0.65 simulated seconds per wall second.
        let mut m = SpeedMeter::default();
        for i in 0..10 {
            let wall = i as f64 * 0.4;
            m.frame(wall, wall * 0.65);
        }
        assert!((m.fps() - 2.5).abs() < 1e-9, "{}", m.fps());
        assert!((m.factor() - 0.65).abs() < 1e-9, "{}", m.factor());
        assert_eq!(m.readout(1.0, true), "0.65x of 1.00x requested");
        assert_eq!(m.readout(0.7, true), "0.65x");
        assert_eq!(m.readout(0.0, true), "0.65x (as fast as possible)");
        assert_eq!(m.readout(1.0, false), "paused");
    }

    #[test]
    fn the_window_is_the_last_second() {
        let mut m = SpeedMeter::default();
        // Ten slow frames, then sixty fast ones at real time: only the fast ones count.
        for i in 0..10 {
            m.frame(i as f64 * 0.5, i as f64 * 0.1);
        }
        let (w0, s0) = (4.5, 0.9);
        for i in 1..=60 {
            let dt = i as f64 / 60.0;
            m.frame(w0 + dt, s0 + dt);
        }
        assert!((m.fps() - 60.0).abs() < 1.0, "{}", m.fps());
        assert!((m.factor() - 1.0).abs() < 0.02, "{}", m.factor());
        // A restart (simulated time going back) starts over.
        m.frame(5.6, 0.0);
        assert_eq!(m.fps(), 0.0);
    }
}
