//! The remote configuration dialog (thesis 4.5.7, fig. 4.22): connected gamepads, each
//! element's live value, the bindings (add, edit, remove), load and save `*.remote.xml`.
//! Each frame, before the simulation steps, the active gamepad's values (and values a
//! script injects, standing in for hardware) pass through the bindings into the robot's
//! kernel — the same `set_parameter` the properties dialog uses, which shows the changes.

use std::path::Path;

use bevy::prelude::*;
use bevy_egui::egui;

use crate::config::error::Pos;
use crate::config::remote::{
    BindMode, BindTarget, Binding, JointSelection, RemoteAction, RemoteFile,
    default_gamepad_bindings, parse_remote_file, write_remote_file,
};
use crate::gui::control::params::reset_actuator;
use crate::gui::control::session::SimSession;
use crate::gui::error::GuiError;
use crate::remote::device::{ElementKind, gamepad_elements};
use crate::remote::gamepad::GamepadRemote;
use crate::remote::{Remote, RemoteData, RemoteMapper};

/// Where the default binding file lives.
pub const DEFAULT_REMOTE_FILE: &str = "configs/remote/default.remote.xml";

/// The "add a binding" form.
#[derive(Debug, Clone)]
struct Form {
    element: String,
    mode: BindMode,
    module: String,
    parameter: String,
    joints: String,
    scale: f64,
}

/// The dialog's state and the resolved bindings.
#[derive(Resource)]
pub struct RemoteView {
    /// Whether the dialog is shown.
    pub open: bool,
    /// Bindings act on the robot.
    pub enabled: bool,
    /// The binding file path typed.
    pub path: String,
    /// The bindings edited and applied.
    pub file: RemoteFile,
    mapper: Option<RemoteMapper>,
    /// (session generation, edit revision) the mapper was built for.
    built_for: Option<(u64, u64)>,
    revision: u64,
    /// The last error (loading, saving, a binding).
    pub error: Option<String>,
    /// Element values set by scripts (over the gamepad's).
    pub injected: RemoteData,
    /// The values applied last frame (the live display).
    pub last: RemoteData,
    /// Actions carried out so far (reset, pause), for the state report.
    pub actions: u64,
    form: Form,
}

impl Default for RemoteView {
    fn default() -> Self {
        let file = if Path::new(DEFAULT_REMOTE_FILE).is_file() {
            std::fs::read_to_string(DEFAULT_REMOTE_FILE)
                .ok()
                .and_then(|t| parse_remote_file(DEFAULT_REMOTE_FILE, &t).ok())
        } else {
            None
        };
        RemoteView {
            open: false,
            enabled: true,
            path: DEFAULT_REMOTE_FILE.into(),
            file: file.unwrap_or_else(default_gamepad_bindings),
            mapper: None,
            built_for: None,
            revision: 0,
            error: None,
            injected: RemoteData::default(),
            last: RemoteData::default(),
            actions: 0,
            form: Form {
                element: "RightStickX".into(),
                mode: BindMode::Rate,
                module: "PatternGenerator_sinusoidal".into(),
                parameter: "Phase_Difference".into(),
                joints: "all".into(),
                scale: 20.0,
            },
        }
    }
}

impl RemoteView {
    /// Loads a binding file (errors name file and line).
    pub fn load(&mut self, path: &Path) -> Result<(), GuiError> {
        let text = std::fs::read_to_string(path).map_err(GuiError::io(path))?;
        self.file = parse_remote_file(&path.display().to_string(), &text)?;
        self.path = path.display().to_string();
        self.edited();
        Ok(())
    }

    /// Writes the bindings.
    pub fn save(&mut self, path: &Path) -> Result<(), GuiError> {
        crate::gui::control::widgets::ensure_parent(path);
        std::fs::write(path, write_remote_file(&self.file)).map_err(GuiError::io(path))?;
        self.path = path.display().to_string();
        Ok(())
    }

    /// The bindings changed: resolve them again.
    pub fn edited(&mut self) {
        self.revision += 1;
    }

    /// Adds a binding of `element` with one target.
    pub fn add_binding(&mut self, element: &str, mode: BindMode, target: BindTarget) {
        self.file.bindings.push(Binding {
            element: element.into(),
            mode,
            dead_zone: crate::config::remote::DEFAULT_DEAD_ZONE,
            action: None,
            targets: vec![target],
            pos: Pos::new(0, 0),
        });
        self.edited();
    }

    /// Removes binding `i`.
    pub fn remove(&mut self, i: usize) -> Result<(), GuiError> {
        if i >= self.file.bindings.len() {
            return Err(GuiError::Missing {
                what: "binding",
                name: format!("{i} (there are {})", self.file.bindings.len()),
            });
        }
        self.file.bindings.remove(i);
        self.edited();
        Ok(())
    }

    /// Whether the bindings fit the robot (resolving them when needed).
    fn ensure_mapper(&mut self, session: &SimSession) {
        let key = (session.generation, self.revision);
        if self.built_for == Some(key) {
            return;
        }
        // Only an edit of the bindings carries element states over; a new world starts
        // from its configured values.
        let same_world = self.built_for.is_some_and(|(g, _)| g == session.generation);
        self.built_for = Some(key);
        let orientations: Vec<_> = session
            .sim
            .robot
            .joints
            .iter()
            .map(|j| j.orientation)
            .collect();
        let built = session
            .simulator
            .kernel(0)
            .map_err(|e| e.to_string())
            .and_then(|k| {
                RemoteMapper::new(&self.file, &self.path, k, &orientations)
                    .map_err(|e| e.to_string())
            });
        match built {
            Ok(mut m) => {
                if let (true, Some(old), Ok(k)) =
                    (same_world, &self.mapper, session.simulator.kernel(0))
                {
                    m.carry_over(old, k);
                }
                self.mapper = Some(m);
                self.error = None;
            }
            Err(e) => {
                self.mapper = None;
                self.error = Some(e);
            }
        }
    }

    /// Applies this frame's values (`dt` seconds since the last frame).
    pub fn apply(&mut self, session: &mut SimSession, remote: &mut GamepadRemote, dt: f64) {
        self.ensure_mapper(session);
        let mut data = remote.read_all();
        for (name, v) in self.injected.iter() {
            data.set(name, v);
        }
        self.last = data.clone();
        if !self.enabled {
            return;
        }
        let Some(mapper) = self.mapper.as_mut() else {
            return;
        };
        let Ok(kernel) = session.simulator.kernel_mut(0) else {
            return;
        };
        let actions = match mapper.apply(&data, dt, kernel) {
            Ok(a) => a,
            Err(e) => {
                self.error = Some(e.to_string());
                return;
            }
        };
        for a in actions {
            self.actions += 1;
            match a {
                RemoteAction::Pause => session.running = !session.running,
                RemoteAction::Reset => {
                    let initial = session.initial_kernel.clone();
                    if let Ok(kernel) = session.simulator.kernel_mut(0) {
                        for i in 0..initial.actuators().len() {
                            if let Err(e) = reset_actuator(kernel, &initial, i) {
                                self.error = Some(e.to_string());
                            }
                        }
                        mapper.rebase(kernel);
                    }
                }
            }
        }
    }
}

/// Applies the remote before the simulation steps (the `Simulate` set).
pub fn apply_remote(
    time: Res<Time>,
    mut session: NonSendMut<SimSession>,
    mut view: ResMut<RemoteView>,
    mut remote: ResMut<GamepadRemote>,
) {
    let dt = time.delta_secs_f64();
    view.apply(&mut session, &mut remote, dt);
}

/// The dialog.
pub fn show(
    ctx: &egui::Context,
    view: &mut RemoteView,
    remote: &mut GamepadRemote,
    session: &SimSession,
) {
    let mut open = view.open;
    egui::Window::new("Remote control")
        .open(&mut open)
        .default_size([520.0, 560.0])
        .show(ctx, |ui| {
            ui.horizontal(|ui| {
                ui.label("Gamepads:");
                if remote.pads.is_empty() {
                    ui.label("none connected");
                }
                let pads = remote.pads.clone();
                for (e, name) in pads {
                    if ui.radio(remote.active == Some(e), name).clicked() {
                        remote.active = Some(e);
                    }
                }
            });
            ui.horizontal(|ui| {
                let mut on = remote.is_connected();
                if ui.checkbox(&mut on, "use the gamepad").changed() {
                    if on {
                        if let Err(e) = remote.connect() {
                            view.error = Some(e.to_string());
                        }
                    } else {
                        remote.disconnect();
                    }
                }
                ui.checkbox(&mut view.enabled, "bindings act on the robot");
                if ui.button("rumble").clicked()
                    && let Err(e) = remote.receive_command("rumble 0.6 0.3")
                {
                    view.error = Some(e.to_string());
                }
            });
            ui.separator();
            egui::CollapsingHeader::new("Live values")
                .default_open(true)
                .show(ui, |ui| live_values(ui, &view.last));
            ui.separator();
            bindings(ui, view);
            ui.separator();
            add_form(ui, view, session);
            ui.separator();
            ui.horizontal(|ui| {
                ui.label("file");
                ui.text_edit_singleline(&mut view.path);
            });
            ui.horizontal(|ui| {
                let path = std::path::PathBuf::from(view.path.trim());
                if ui.button("Load").clicked()
                    && let Err(e) = view.load(&path)
                {
                    view.error = Some(e.to_string());
                }
                if ui.button("Save").clicked()
                    && let Err(e) = view.save(&path)
                {
                    view.error = Some(e.to_string());
                }
                if ui.button("Default binding").clicked() {
                    view.file = default_gamepad_bindings();
                    view.edited();
                }
            });
            if let Some(e) = &view.error {
                ui.colored_label(egui::Color32::LIGHT_RED, e);
            }
        });
    view.open = open;
}

fn live_values(ui: &mut egui::Ui, data: &RemoteData) {
    egui::Grid::new("remote values")
        .num_columns(4)
        .show(ui, |ui| {
            for (i, e) in gamepad_elements().iter().enumerate() {
                let v = data.get(&e.name);
                ui.label(&e.name);
                match e.kind {
                    ElementKind::Axis => {
                        ui.add(
                            egui::ProgressBar::new(((v + 1.0) / 2.0) as f32)
                                .desired_width(90.0)
                                .text(format!("{v:+.2}")),
                        );
                    }
                    ElementKind::Button => {
                        ui.label(if v > 0.5 { "● pressed" } else { "○" });
                    }
                }
                if i % 2 == 1 {
                    ui.end_row();
                }
            }
        });
}

fn bindings(ui: &mut egui::Ui, view: &mut RemoteView) {
    ui.strong(format!("Bindings ({})", view.file.name));
    let mut remove = None;
    let mut changed = false;
    egui::Grid::new("remote bindings")
        .striped(true)
        .show(ui, |ui| {
            for (i, b) in view.file.bindings.iter_mut().enumerate() {
                ui.label(&b.element);
                match b.action {
                    Some(a) => {
                        ui.label(format!("action: {}", a.name()));
                    }
                    None => {
                        ui.label(b.mode.name());
                    }
                }
                ui.vertical(|ui| {
                    for t in &mut b.targets {
                        ui.horizontal(|ui| {
                            ui.label(format!(
                                "{} {} [{}]",
                                t.module,
                                t.parameter,
                                t.joints.to_text()
                            ));
                            changed |= ui
                                .add(egui::DragValue::new(&mut t.scale).speed(0.1).prefix("×"))
                                .changed();
                        });
                    }
                    if !b.mode.is_press() && b.action.is_none() {
                        changed |= ui
                            .add(egui::Slider::new(&mut b.dead_zone, 0.0..=0.9).text("dead zone"))
                            .changed();
                    }
                });
                if ui.small_button("remove").clicked() {
                    remove = Some(i);
                }
                ui.end_row();
            }
        });
    if let Some(i) = remove {
        if let Err(e) = view.remove(i) {
            view.error = Some(e.to_string());
        }
    } else if changed {
        view.edited();
    }
}

/// The binding's target: a module of the robot's kernel and one of its parameters.
fn target_pickers(ui: &mut egui::Ui, f: &mut Form, session: &SimSession) {
    let modules: Vec<&'static str> = session
        .simulator
        .kernel(0)
        .map(|k| {
            k.actuators()
                .iter()
                .map(|a| a.module.descriptor().type_name)
                .collect()
        })
        .unwrap_or_default();
    ui.horizontal(|ui| {
        egui::ComboBox::from_id_salt("remote module")
            .selected_text(f.module.clone())
            .show_ui(ui, |ui| {
                for m in &modules {
                    ui.selectable_value(&mut f.module, m.to_string(), *m);
                }
            });
        let params: Vec<&'static str> = session
            .simulator
            .kernel(0)
            .ok()
            .and_then(|k| {
                k.actuators()
                    .iter()
                    .find(|a| a.module.descriptor().type_name == f.module)
                    .map(|a| a.module.descriptor().parameter_names())
            })
            .unwrap_or_default();
        egui::ComboBox::from_id_salt("remote parameter")
            .selected_text(f.parameter.clone())
            .show_ui(ui, |ui| {
                for p in params {
                    ui.selectable_value(&mut f.parameter, p.to_string(), p);
                }
            });
    });
}

/// The form that adds a binding: the gamepad element and mode, the target, the joints and
/// the scale.
fn add_form(ui: &mut egui::Ui, view: &mut RemoteView, session: &SimSession) {
    ui.strong("Add a binding");
    let f = &mut view.form;
    ui.horizontal(|ui| {
        egui::ComboBox::from_id_salt("remote element")
            .selected_text(f.element.clone())
            .show_ui(ui, |ui| {
                for e in gamepad_elements() {
                    let name = e.name.clone();
                    ui.selectable_value(&mut f.element, name.clone(), name);
                }
            });
        egui::ComboBox::from_id_salt("remote mode")
            .selected_text(f.mode.name())
            .show_ui(ui, |ui| {
                for m in BindMode::ALL {
                    ui.selectable_value(&mut f.mode, m, m.name());
                }
            });
    });
    target_pickers(ui, f, session);
    let mut add = false;
    ui.horizontal(|ui| {
        ui.label("joints");
        ui.add(egui::TextEdit::singleline(&mut f.joints).desired_width(80.0))
            .on_hover_text("all, pitch, yaw, or a 0/1 mask over the robot's joints");
        ui.add(
            egui::DragValue::new(&mut f.scale)
                .speed(0.1)
                .prefix("scale "),
        );
        add = ui.button("Add").clicked();
    });
    if add {
        let f = view.form.clone();
        match JointSelection::parse(&f.joints) {
            Some(joints) => view.add_binding(
                &f.element,
                f.mode,
                BindTarget {
                    module: f.module,
                    parameter: f.parameter,
                    joints,
                    scale: f.scale,
                    pos: Pos::new(0, 0),
                },
            ),
            None => {
                view.error = Some(format!(
                    "joints \"{}\": all, pitch, yaw or a 0/1 mask",
                    f.joints
                ))
            }
        }
    }
}

/// The remote-control dialog and the gamepad's bindings applied each frame.
pub struct RemoteViewPlugin;

impl Plugin for RemoteViewPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(crate::remote::gamepad::GamepadRemotePlugin)
            .init_resource::<RemoteView>()
            .add_systems(
                Update,
                apply_remote.in_set(crate::gui::control::schedule::GuiSystems::Gamepad),
            );
    }
}
