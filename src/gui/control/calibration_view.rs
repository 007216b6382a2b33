//! The real-robot tab's servo calibration: a recording (a data file of `proleg robot`, or
//! of this window) is calibrated in the background against the session's robot
//! (`calibrate`), and the tab shows the report and, per joint, the recorded angles against
//! the replay with the robot file's servo model and with the calibrated one.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::sync::{Mutex, PoisonError};

use bevy_egui::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints};

use crate::calibrate::recording::{Recording, read_recording};
use crate::calibrate::replay::replay;
use crate::calibrate::{CalibrateError, CalibrateOptions, CalibrationReport, calibrate};
use crate::config::Simulation;

/// A finished calibration and the lines it draws.
#[derive(Debug, Clone)]
pub struct Calibrated {
    /// The report.
    pub report: CalibrationReport,
    /// Per joint: (time, angle) of the recording, the replay before and after.
    lines: Vec<[Vec<[f64; 2]>; 3]>,
}

/// Why the panel has no calibration to show.
#[derive(Debug, thiserror::Error)]
pub enum PanelError {
    /// The calibration failed.
    #[error("{0}")]
    Calibrate(#[from] CalibrateError),
    /// Its thread ended without an answer.
    #[error("the calibration stopped without a result")]
    Stopped,
}

/// The panel's state.
#[derive(Default)]
pub struct CalibrationPanel {
    /// The recording to calibrate on.
    pub file: String,
    /// The running calibration's answer (behind a lock: the tab is shared by systems).
    job: Option<Mutex<Receiver<Result<Calibrated, CalibrateError>>>>,
    /// The last calibration.
    pub result: Option<Calibrated>,
    /// Why the last one failed.
    pub error: Option<PanelError>,
    /// The joint drawn.
    pub joint: usize,
    /// Open the panel at the next frame (a calibration started or ended).
    reveal: bool,
}

impl CalibrationPanel {
    /// Whether a calibration is running.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// Starts calibrating `sim`'s servos on the recording in `file`, in the background.
    pub fn start(&mut self, sim: &Simulation) {
        let (tx, rx) = channel();
        let (sim, file) = (sim.clone(), PathBuf::from(self.file.trim()));
        std::thread::spawn(move || {
            // The panel may be gone when the fit ends: nothing waits for it then.
            if tx.send(run(&file, &sim)).is_err() {
                bevy::log::info!("a calibration ended after its window closed");
            }
        });
        self.job = Some(Mutex::new(rx));
        self.error = None;
        self.reveal = true;
    }

    /// Whether the panel should open now (once per calibration started or ended).
    pub fn take_reveal(&mut self) -> bool {
        self.poll();
        std::mem::take(&mut self.reveal)
    }

    /// Takes a finished calibration's result.
    pub fn poll(&mut self) {
        let Some(job) = &self.job else {
            return;
        };
        let answer = job
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .try_recv();
        match answer {
            Ok(Ok(c)) => {
                self.result = Some(c);
                self.job = None;
                self.reveal = true;
            }
            Ok(Err(e)) => {
                self.error = Some(e.into());
                self.job = None;
                self.reveal = true;
            }
            Err(TryRecvError::Empty) => {}
            Err(TryRecvError::Disconnected) => {
                self.error = Some(PanelError::Stopped);
                self.job = None;
            }
        }
    }

    /// The panel.
    pub fn show(&mut self, ui: &mut egui::Ui, sim: &Simulation) {
        self.poll();
        ui.horizontal(|ui| {
            ui.label("Recording");
            ui.add(egui::TextEdit::singleline(&mut self.file).desired_width(260.0))
                .on_hover_text(
                    "a data file of proleg robot --data: desired and real joint positions",
                );
            if ui
                .add_enabled(
                    !self.running() && !self.file.trim().is_empty(),
                    egui::Button::new("Calibrate"),
                )
                .clicked()
            {
                self.start(sim);
            }
            if self.running() {
                ui.spinner();
                ui.label("fitting gain, top speed, dead band, latency…");
            }
        });
        if let Some(e) = &self.error {
            ui.colored_label(egui::Color32::LIGHT_RED, e.to_string());
        }
        let Some(c) = &self.result else {
            return;
        };
        ui.label(
            egui::RichText::new(c.report.to_string())
                .monospace()
                .size(11.0),
        );
        let joints = c.lines.len();
        ui.horizontal(|ui| {
            ui.label("Joint");
            for j in 0..joints {
                ui.selectable_value(&mut self.joint, j, format!("J{}", j + 1));
            }
        });
        let Some([real, before, after]) = c.lines.get(self.joint.min(joints.saturating_sub(1)))
        else {
            return;
        };
        Plot::new("calibration")
            .height(180.0)
            .legend(Legend::default())
            .show(ui, |p| {
                for (points, name, colour) in [
                    (real, "recorded", egui::Color32::WHITE),
                    (before, "robot file's servo", egui::Color32::LIGHT_RED),
                    (after, "calibrated", egui::Color32::LIGHT_BLUE),
                ] {
                    p.line(Line::new(name, PlotPoints::from(points.clone())).color(colour));
                }
            });
    }
}

/// Reads, calibrates and draws.
fn run(file: &std::path::Path, sim: &Simulation) -> Result<Calibrated, CalibrateError> {
    let rec = read_recording(file)?;
    let options = CalibrateOptions {
        per_joint: false,
        runs: 4,
        seed: 1,
    };
    let report = calibrate(&rec, sim, &options)?;
    let lines = lines(&rec, &report);
    Ok(Calibrated { report, lines })
}

/// Per joint: the recording, the replay before and after, as plot points.
fn lines(rec: &Recording, report: &CalibrationReport) -> Vec<[Vec<[f64; 2]>; 3]> {
    let points =
        |v: &[f64]| -> Vec<[f64; 2]> { rec.times.iter().zip(v).map(|(t, a)| [*t, *a]).collect() };
    (0..rec.joints())
        .map(|j| {
            let start = rec.real[j].first().copied().unwrap_or(0.0);
            [
                points(&rec.real[j]),
                points(&replay(
                    &report.before[j],
                    &rec.times,
                    &rec.desired[j],
                    start,
                )),
                points(&replay(
                    &report.after(j),
                    &rec.times,
                    &rec.desired[j],
                    start,
                )),
            ]
        })
        .collect()
}
