//! The main toolbar (thesis 4.5.1): load a configuration, start / pause / restart, delay
//! between steps, real-time factor or as fast as possible, physics step width, and the
//! simulated time, real time, step counter and achieved speed.

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use bevy_egui::egui;

use crate::gui::control::session::{Halt, SimSession};
use crate::gui::meter::SpeedMeter;

/// The toolbar's own state.
#[derive(Resource, Debug, Clone)]
pub struct ToolbarState {
    /// The configuration path being typed.
    pub path: String,
    /// Simulation files found under `configs/`, for the quick-load list.
    pub known: Vec<PathBuf>,
    /// Frames per second and real-time factor achieved over the last wall second.
    pub meter: SpeedMeter,
    /// Where the toolbar, the docked panels and the viewer were drawn last frame, by name
    /// (the GUI tests check that they hold still when notices come and go).
    pub layout: std::collections::BTreeMap<&'static str, egui::Rect>,
}

impl ToolbarState {
    /// The toolbar showing configuration `current`.
    pub fn new(current: &Path) -> Self {
        ToolbarState {
            path: current.display().to_string(),
            known: simulation_files(Path::new("configs")),
            meter: SpeedMeter::default(),
            layout: std::collections::BTreeMap::new(),
        }
    }
}

/// `*.simulation.xml` files directly in `dir`, sorted.
pub fn simulation_files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.flatten()
                .map(|e| e.path())
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| n.ends_with(".simulation.xml") && !n.starts_with('_'))
                })
                .collect()
        })
        .unwrap_or_default();
    out.sort();
    out
}

/// Draws the toolbar.
pub fn show(ui: &mut egui::Ui, session: &mut SimSession, state: &mut ToolbarState) {
    ui.horizontal_wrapped(|ui| {
        configuration(ui, session, state);
        ui.separator();
        run_buttons(ui, session);
        ui.separator();
        pacing(ui, session);
    });
    ui.horizontal(|ui| readout(ui, session, state));
}

/// The configuration field, Load, the known configurations and the configuration window.
fn configuration(ui: &mut egui::Ui, session: &mut SimSession, state: &mut ToolbarState) {
    ui.label("Configuration:");
    // As wide as the path (within reason), so it is not cut off.
    let width = (state.path.chars().count() as f32 * 7.5 + 16.0).clamp(260.0, 560.0);
    let field = ui.add(egui::TextEdit::singleline(&mut state.path).desired_width(width));
    let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    if ui.button("Load").clicked() || entered {
        session.load(Path::new(state.path.trim()));
    }
    egui::ComboBox::from_id_salt("known configs")
        .selected_text("configs/ …")
        .show_ui(ui, |ui| {
            for p in state.known.clone() {
                if ui
                    .selectable_label(false, p.display().to_string())
                    .clicked()
                {
                    state.path = p.display().to_string();
                    session.load(&p);
                }
            }
        });
    if ui
        .button("New / edit configuration…")
        .on_hover_text("Opens the configuration window: wizard, expert composition (on this simulation), environment editor")
        .clicked()
    {
        session.error = crate::gui::desktop::spawn_window(
            "configuration window",
            &["wizard", "--expert"],
            &session.path,
        )
        .err()
        .map(|e| e.to_string());
    }
}

/// Start/Pause and Restart.
fn run_buttons(ui: &mut egui::Ui, session: &mut SimSession) {
    let label = if session.running {
        "⏸ Pause"
    } else {
        "▶ Start"
    };
    if ui.button(label).clicked() {
        session.running = !session.running;
    }
    if ui.button("⟲ Restart").clicked() {
        session.restart();
    }
}

/// Delay, real-time factor, step width and the physics engine.
fn pacing(ui: &mut egui::Ui, session: &mut SimSession) {
    ui.label("Delay (ms/step):");
    ui.add(
        egui::DragValue::new(&mut session.pacing.delay_ms)
            .range(0.0..=1000.0)
            .speed(0.5),
    );
    ui.label("Real-time factor:");
    if session.pacing.realtime_factor > 0.0 {
        ui.add(
            egui::DragValue::new(&mut session.pacing.realtime_factor)
                .range(0.01..=1000.0)
                .speed(0.05),
        );
    } else {
        // The same field, disabled, as narrow as the number it stands for: the row wraps
        // and measures as it did (a wider text here pushed the rest of the row down).
        let mut zero = 0.0;
        ui.add_enabled(
            false,
            egui::DragValue::new(&mut zero).custom_formatter(|_, _| "max".into()),
        )
        .on_disabled_hover_text("as fast as possible");
    }
    if ui
        .selectable_label(session.pacing.realtime_factor == 1.0, "sync 1x")
        .clicked()
    {
        session.pacing.realtime_factor = 1.0;
    }
    if ui
        .selectable_label(session.pacing.realtime_factor == 0.0, "max")
        .clicked()
    {
        session.pacing.realtime_factor = 0.0;
    }
    ui.label("Step width δ (s):");
    ui.add(
        egui::DragValue::new(&mut session.step_width)
            .range(0.0001..=0.05)
            .speed(0.0001)
            .max_decimals(4),
    )
    .on_hover_text("used from the next restart");
    ui.label("Physics:");
    let now = session.simulator.engine_kind();
    egui::ComboBox::from_id_salt("physics engine")
        .selected_text(now.name())
        .show_ui(ui, |ui| {
            for kind in crate::config::simulation::EngineKind::ALL {
                if ui.selectable_label(kind == now, kind.name()).clicked() {
                    session.set_engine(kind);
                }
            }
        })
        .response
        .on_hover_text("the physics engine: switching rebuilds the world, paused at 0");
}

/// Simulated and real time, steps, step width, speed and frame rate.
fn readout(ui: &mut egui::Ui, session: &SimSession, state: &ToolbarState) {
    let dt = session.simulator.clock().dt;
    ui.monospace(format!(
        "sim {:>8.3} s   real {:>8.3} s   step {:>8}   δ {:.4} s   speed {}   {:>4.1} fps",
        session.sim_time(),
        session.real_time,
        session.steps(),
        dt,
        state
            .meter
            .readout(session.pacing.realtime_factor, session.running),
        state.meter.fps(),
    ));
}

/// The notices (kept tuned values, a halted run, a failed load), floating over the top of
/// the viewer `viewer`: they come and go without moving the toolbar or the panels, so a
/// click aimed at a control lands on it.
pub fn notices(ctx: &egui::Context, viewer: egui::Rect, session: &mut SimSession) {
    if session.tuned.is_none() && session.halt.is_none() && session.error.is_none() {
        return;
    }
    egui::Area::new(egui::Id::new("notices"))
        .order(egui::Order::Foreground)
        // Top right: the robot's readout holds the viewer's top left.
        .pivot(egui::Align2::RIGHT_TOP)
        .fixed_pos(viewer.right_top() + egui::vec2(-8.0, 8.0))
        .show(ctx, |ui| {
            ui.set_max_width((viewer.width() - 16.0).max(200.0));
            egui::Frame::popup(ui.style()).show(ui, |ui| notice_rows(ui, session));
        });
}

/// The notices' rows.
fn notice_rows(ui: &mut egui::Ui, session: &mut SimSession) {
    if session.tuned.is_some() {
        ui.horizontal(|ui| {
            ui.label(
                "Restarted with the file's parameter values; the values you tuned are kept aside.",
            );
            if ui.button("Keep tuned values").clicked() {
                session.keep_tuned();
            }
            if ui.button("Use the file's").clicked() {
                session.tuned = None;
            }
        });
    }
    if let Some(halt) = session.halt.clone() {
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new(halt.message()).strong());
            if !matches!(halt, Halt::Diverged) && ui.button("Continue").clicked() {
                session.continue_run();
            }
            if ui.button("Restart").clicked() {
                session.restart();
            }
        });
    }
    // A failed load or restart: the located error on its own rows (the world shown is the
    // previous one), until dismissed.
    if let Some(e) = session.error.clone() {
        ui.horizontal(|ui| {
            if ui.small_button("Dismiss").clicked() {
                session.error = None;
            }
            ui.add(egui::Label::new(egui::RichText::new(e).color(egui::Color32::LIGHT_RED)).wrap());
        });
    }
}
