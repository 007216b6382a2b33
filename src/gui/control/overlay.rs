//! The viewer overlay: robot 0's position, smoothed speed and heading, pads pressed, the
//! frame rate, and the follow-robot toggle.

use bevy::prelude::*;
use bevy_egui::egui;

use crate::gui::control::session::SimSession;
use crate::gui::control::toolbar::ToolbarState;
use crate::measure::ground_distance;

/// What the overlay shows, updated after the frame's steps.
#[derive(Resource, Debug, Clone, Default)]
pub struct RobotOverlay {
    /// Centre of mass (m, z up).
    pub com: [f64; 3],
    /// Ground speed (m/s), smoothed over about a second of simulated time.
    pub speed: f64,
    /// Tail-to-head heading (degrees from +x).
    pub heading: f64,
    /// Touch pads pressed.
    pub pressed: usize,
    /// Touch pads of the robot.
    pub pads: usize,
    last: Option<(f64, [f64; 3])>,
}

impl RobotOverlay {
    /// Reads the session's robot 0.
    pub fn observe(&mut self, session: &SimSession) {
        let Ok(com) = session.simulator.com(0) else {
            return;
        };
        let t = session.sim_time();
        match self.last {
            Some((t0, c0)) if t > t0 => {
                let v = ground_distance(c0, com) / (t - t0);
                let k = ((t - t0) / 1.0).min(1.0);
                self.speed += k * (v - self.speed);
            }
            Some((t0, _)) if t < t0 => self.speed = 0.0, // restarted
            _ => {}
        }
        self.last = Some((t, com));
        self.com = com;
        self.heading = session.simulator.heading(0).unwrap_or(0.0);
        let sensors = session.simulator.sensors(0).ok();
        (self.pressed, self.pads) = sensors.map_or((0, 0), |s| (s.pressed(), s.tactile.len()));
    }
}

/// Draws the overlay in the viewer's top-left corner, below the toolbar (whose bottom is
/// at `top`).
pub fn show(
    ctx: &egui::Context,
    o: &RobotOverlay,
    toolbar: &ToolbarState,
    follow: &mut bool,
    viewer: egui::Rect,
) {
    // In the viewer's top-left corner, clear of the docked panels.
    egui::Window::new("Robot")
        .anchor(
            egui::Align2::LEFT_TOP,
            [viewer.min.x + 8.0, viewer.min.y + 8.0],
        )
        .resizable(false)
        .collapsible(true)
        .show(ctx, |ui| {
            ui.monospace(format!(
                "x {:+.3}  y {:+.3}  z {:+.3} m",
                o.com[0], o.com[1], o.com[2]
            ));
            ui.monospace(format!(
                "speed {:.3} m/s  heading {:.0}°",
                o.speed, o.heading
            ));
            if o.pads > 0 {
                ui.monospace(format!("pads pressed {}/{}", o.pressed, o.pads));
            }
            ui.monospace(format!("{:.1} fps", toolbar.meter.fps()));
            ui.checkbox(follow, "follow robot");
        });
}

/// The robot overlay's state.
pub struct OverlayPlugin;

impl Plugin for OverlayPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<RobotOverlay>();
    }
}
