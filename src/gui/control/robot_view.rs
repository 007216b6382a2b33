//! The real-robot tab (thesis 4.5.4): connect to a Dynamixel chain on a serial port, a
//! servo table with live position, current, speed, temperature and hardware errors,
//! torque on/off, and driving: each frame the kernel's latest output goes to the servos
//! and the viewer's robot becomes the twin that follows the measured angles. Errors are
//! shown and switch the torque off; closing the window or disconnecting does too.
//!
//! A recording can be calibrated here too (gain, top speed, dead band, latency fitted,
//! before/after shown: [`crate::gui::control::calibration_view`]).
//!
//! The window's loop runs at the frame rate (the servos get the kernel's newest angles
//! once per frame); `proleg robot` runs the loop at the file's step width.

use bevy::prelude::*;
use bevy_egui::egui;

use crate::gui::control::session::SimSession;
use crate::gui::error::GuiError;
use crate::robot_io::dynamixel::DynamixelChain;
use crate::robot_io::{Info, Readings, RobotControl};

/// Frames between reads of temperatures and error flags.
const SLOW_READ_FRAMES: u64 = 15;

/// The tab's state and the connection.
#[derive(Resource)]
pub struct RobotView {
    /// Whether the tab is shown.
    pub open: bool,
    /// The serial port.
    pub port: String,
    /// Bus speed (baud).
    pub baud: u32,
    robot: Option<DynamixelChain>,
    /// The kernel's output drives the servos.
    pub drive: bool,
    /// The viewer's robot follows the measured angles.
    pub twin: bool,
    /// Whether the servos' torque is on.
    pub torque: bool,
    /// The last readings (positions, currents, speeds).
    pub readings: Readings,
    /// Each servo's temperature (°C).
    pub temperatures: Vec<f64>,
    /// Each servo's hardware error status.
    pub errors: Vec<f64>,
    /// Read-backs and goal writes so far, failed read-backs, and those in a row.
    pub reads: u64,
    /// Goal writes sent.
    pub writes: u64,
    /// Read-backs that failed.
    pub failed_reads: u64,
    failed_in_a_row: u32,
    frames: u64,
    /// The last error.
    pub error: Option<String>,
    /// The command line: `COMMAND [VALUE]` and the servo id it goes to (0: all).
    pub command: String,
    /// The servo a command goes to (0: all).
    pub command_target: u8,
    /// Servo calibration from a recording.
    pub calibration: crate::gui::control::calibration_view::CalibrationPanel,
}

impl Default for RobotView {
    fn default() -> Self {
        RobotView {
            open: false,
            port: "/dev/ttyUSB0".into(),
            baud: crate::config::servos::DEFAULT_BAUD,
            robot: None,
            drive: false,
            twin: true,
            torque: false,
            readings: Readings::default(),
            temperatures: Vec::new(),
            errors: Vec::new(),
            reads: 0,
            writes: 0,
            failed_reads: 0,
            failed_in_a_row: 0,
            frames: 0,
            error: None,
            command: "led 1".into(),
            command_target: 0,
            calibration: Default::default(),
        }
    }
}

impl Drop for RobotView {
    /// The window closes: torque off.
    fn drop(&mut self) {
        if let Some(r) = self.robot.as_mut()
            && let Err(e) = r.enable_servos(false)
        {
            bevy::log::error!(
                "closing the robot view: torque off failed ({e}); the servos may still hold"
            );
        }
    }
}

impl RobotView {
    /// Whether a robot is connected.
    pub fn connected(&self) -> bool {
        self.robot.is_some()
    }

    /// Connects to the session's robot on the port; reads it once.
    pub fn connect(&mut self, session: &SimSession) -> Result<(), GuiError> {
        self.disconnect_robot();
        let mut chain = DynamixelChain::new(
            std::path::Path::new(self.port.trim()),
            Some(self.baud),
            session.sim.robot.servos.clone(),
            &session.sim.robot.pattern(),
        );
        chain.connect()?;
        let n = chain.meta().joints;
        self.readings = Readings::new(n);
        self.temperatures = vec![0.0; n];
        self.errors = vec![0.0; n];
        self.robot = Some(chain);
        self.torque = false;
        self.error = None;
        self.frames = 0;
        self.exchange_once(None)?;
        Ok(())
    }

    /// Torque off and closes the port; a failed torque-off is added to [`RobotView::error`]
    /// (the servos may still hold).
    fn disconnect_robot(&mut self) {
        if let Some(mut r) = self.robot.take() {
            if let Err(e) = r.enable_servos(false) {
                let note = format!("torque off failed ({e}); the servos may still hold");
                self.error = Some(match self.error.take() {
                    Some(before) => format!("{before}; {note}"),
                    None => note,
                });
            }
            r.disconnect();
        }
        self.torque = false;
        self.drive = false;
    }

    /// Torque off, closes the port, and the viewer's robot follows the kernel again.
    pub fn disconnect(&mut self, session: &mut SimSession) {
        self.disconnect_robot();
        if let Err(e) = session.simulator.set_joint_override(0, None) {
            self.error = Some(e.to_string());
        }
    }

    /// Torque on or off for every servo.
    pub fn set_torque(&mut self, on: bool) -> Result<(), GuiError> {
        let r = self
            .robot
            .as_mut()
            .ok_or(GuiError::NotNow("not connected"))?;
        r.enable_servos(on)?;
        self.torque = on;
        Ok(())
    }

    /// Sends the command line (`COMMAND [VALUE...]`) to every servo or one id.
    pub fn send(&mut self) -> Result<(), GuiError> {
        let mut words = self.command.split_whitespace();
        let name = words
            .next()
            .ok_or(GuiError::NotNow("type a command, e.g. led 1"))?
            .to_string();
        let values = words
            .map(|w| {
                w.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| GuiError::Missing {
                        what: "number",
                        name: format!("{w:?}"),
                    })
            })
            .collect::<Result<Vec<f64>, GuiError>>()?;
        let target = match self.command_target {
            0 => crate::robot_io::Target::All,
            id => crate::robot_io::Target::Id(id),
        };
        let r = self
            .robot
            .as_mut()
            .ok_or(GuiError::NotNow("not connected"))?;
        Ok(r.send_command(&name, &values, target)?)
    }

    /// One frame's exchange: goals out (when driving), readings in.
    fn exchange_once(&mut self, goals: Option<&[f64]>) -> Result<(), GuiError> {
        let r = self
            .robot
            .as_mut()
            .ok_or(GuiError::NotNow("not connected"))?;
        if let Some(g) = goals {
            r.set_joint_angles(g)?;
            self.writes += 1;
        }
        self.frames += 1;
        // A garbled answer now and then is survived; a servo that keeps failing is not.
        let read = r.read(&mut self.readings).and_then(|()| {
            if (self.frames - 1).is_multiple_of(SLOW_READ_FRAMES) {
                r.request(Info::Temperatures, &mut self.temperatures)?;
                r.request(Info::Errors, &mut self.errors)?;
            }
            Ok(())
        });
        match read {
            Ok(()) => {
                self.reads += 1;
                self.failed_in_a_row = 0;
                Ok(())
            }
            Err(e) => {
                self.failed_reads += 1;
                self.failed_in_a_row += 1;
                if self.failed_in_a_row >= crate::robot_io::real_mode::MAX_FAILED_READS {
                    Err(e.into())
                } else {
                    Ok(())
                }
            }
        }
    }

    /// The frame's exchange with the robot and the twin's targets; an error switches
    /// the torque off and disconnects.
    pub fn update(&mut self, session: &mut SimSession) {
        if self.robot.is_none() {
            return;
        }
        let goals = if self.drive && self.torque {
            match session.simulator.kernel(0) {
                Ok(k) => Some(k.desired().to_vec()),
                Err(e) => {
                    self.error = Some(e.to_string());
                    None
                }
            }
        } else {
            None
        };
        match self.exchange_once(goals.as_deref()) {
            Ok(()) => {
                let twin = self.twin.then(|| self.readings.positions.clone());
                if let Err(e) = session.simulator.set_joint_override(0, twin) {
                    self.error = Some(e.to_string());
                }
            }
            Err(e) => {
                self.error = Some(format!("{e}; torque switched off, disconnected"));
                self.disconnect(session);
            }
        }
    }
}

/// Before the frame's steps: the exchange with the robot.
pub fn exchange(mut view: ResMut<RobotView>, mut session: NonSendMut<SimSession>) {
    view.update(&mut session);
}

/// Draws the tab.
pub fn show(ctx: &egui::Context, view: &mut RobotView, session: &mut SimSession) {
    let mut open = view.open;
    egui::Window::new("Real robot")
        .open(&mut open)
        .default_size([640.0, 560.0])
        .show(ctx, |ui| {
            ui.horizontal(|ui| {
                ui.label("Port");
                ui.add_enabled(
                    !view.connected(),
                    egui::TextEdit::singleline(&mut view.port).desired_width(160.0),
                );
                ui.label("Baud");
                ui.add_enabled(!view.connected(), egui::DragValue::new(&mut view.baud));
                if view.connected() {
                    if ui.button("Disconnect").clicked() {
                        view.disconnect(session);
                    }
                } else if ui.button("Connect").clicked()
                    && let Err(e) = view.connect(session)
                {
                    view.error = Some(e.to_string());
                }
            });
            if let Some(e) = &view.error {
                ui.colored_label(egui::Color32::LIGHT_RED, e);
            }
            let reveal = view.calibration.take_reveal();
            egui::CollapsingHeader::new("Calibrate the servo model from a recording")
                .open(reveal.then_some(true))
                .show(ui, |ui| view.calibration.show(ui, &session.sim));
            if !view.connected() {
                ui.label(format!(
                    "Dynamixel (Protocol 2.0) servos, ids {:?} for joints J1..J{} (the robot \
                     file's <Servos>); no hardware? proleg robot-emulator",
                    session
                        .sim
                        .robot
                        .servos
                        .joints
                        .iter()
                        .map(|j| j.id)
                        .collect::<Vec<_>>(),
                    session.sim.robot.joints.len()
                ));
                return;
            }
            ui.horizontal(|ui| {
                let mut torque = view.torque;
                if ui.checkbox(&mut torque, "Torque on").changed()
                    && let Err(e) = view.set_torque(torque)
                {
                    view.error = Some(e.to_string());
                }
                ui.checkbox(&mut view.drive, "Kernel drives the servos")
                    .on_hover_text("start the simulation: each frame the kernel's angles go out");
                ui.checkbox(&mut view.twin, "Viewer shows the measured pose");
                ui.label(format!(
                    "{} reads ({} failed), {} writes",
                    view.reads, view.failed_reads, view.writes
                ));
            });
            servo_table(ui, view, session);
            ui.horizontal(|ui| {
                ui.label("Command");
                ui.add(egui::TextEdit::singleline(&mut view.command).desired_width(140.0))
                    .on_hover_text("torque 0|1, led 0|1, goal DEG, reboot");
                ui.label("to id (0: all)");
                ui.add(egui::DragValue::new(&mut view.command_target).range(0..=252));
                if ui.button("Send").clicked() {
                    view.error = view.send().err().map(|e| e.to_string());
                }
            });
        });
    view.open = open;
}

fn servo_table(ui: &mut egui::Ui, view: &RobotView, session: &SimSession) {
    let desired = session
        .simulator
        .kernel(0)
        .map(|k| k.desired().to_vec())
        .unwrap_or_default();
    egui::Grid::new("servos")
        .striped(true)
        .num_columns(8)
        .show(ui, |ui| {
            for h in [
                "joint",
                "id",
                "goal °",
                "position °",
                "current A",
                "speed °/s",
                "temp °C",
                "error",
            ] {
                ui.strong(h);
            }
            ui.end_row();
            let r = &view.readings;
            for (j, servo) in session.sim.robot.servos.joints.iter().enumerate() {
                ui.label(format!("J{}", j + 1));
                ui.label(servo.id.to_string());
                ui.monospace(format!("{:+.1}", desired.get(j).copied().unwrap_or(0.0)));
                ui.monospace(format!(
                    "{:+.1}",
                    r.positions.get(j).copied().unwrap_or(0.0)
                ));
                ui.monospace(format!("{:.3}", r.currents.get(j).copied().unwrap_or(0.0)));
                ui.monospace(format!("{:+.1}", r.speeds.get(j).copied().unwrap_or(0.0)));
                ui.monospace(format!(
                    "{:.0}",
                    view.temperatures.get(j).copied().unwrap_or(0.0)
                ));
                let e = view.errors.get(j).copied().unwrap_or(0.0);
                if e == 0.0 {
                    ui.label("—");
                } else {
                    ui.colored_label(egui::Color32::LIGHT_RED, format!("{e:.0}"));
                }
                ui.end_row();
            }
        });
}

/// The real-robot tab: its state and the exchange with the servos each frame (after the
/// gamepad).
pub struct RobotViewPlugin;

impl Plugin for RobotViewPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<RobotView>().add_systems(
            Update,
            exchange.in_set(crate::gui::control::schedule::GuiSystems::Robot),
        );
    }
}
