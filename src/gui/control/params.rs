//! Control algorithm properties (thesis 4.5.5): a tab per actuation module with all its
//! parameters, in uniform mode (one slider sets every joint the module drives) or
//! individual mode (a slider per joint). Values are read back from the kernel every frame,
//! so changes made elsewhere (a script, an optimizer, a gamepad) show at once; Reset
//! restores the module's parameters as the configuration built them. Every change goes
//! through [`crate::control::ControlKernel::set_parameter`], the one parameter API.

use std::collections::HashSet;

use bevy::prelude::*;
use bevy_egui::egui;

use crate::config::module_types::ParamDescriptor;
use crate::control::kernel::Actuator;
use crate::gui::control::session::SimSession;

/// The dialog's state: the selected module and which parameters are shown per joint.
#[derive(Resource, Debug, Clone, Default)]
pub struct ParamsState {
    /// The module tab shown.
    pub tab: usize,
    /// (actuator, parameter) pairs in individual mode.
    pub individual: HashSet<(usize, usize)>,
}

/// A parameter change the dialog asks for: one slider moved.
#[derive(Debug, Clone, PartialEq)]
pub struct Change {
    /// The module (kernel actuator index).
    pub actuator: usize,
    /// The parameter.
    pub name: &'static str,
    /// A robot joint (individual mode), or every joint the module drives (uniform mode).
    pub joint: Option<usize>,
    /// The new value.
    pub value: f64,
}

/// Draws the dialog and applies the changes made in it.
pub fn show(ui: &mut egui::Ui, session: &mut SimSession, state: &mut ParamsState) {
    let Ok(kernel) = session.simulator.kernel(0) else {
        ui.label("no robot");
        return;
    };
    let actuators = kernel.actuators();
    if actuators.is_empty() {
        ui.label("This robot has no actuation modules.");
        return;
    }
    state.tab = state.tab.min(actuators.len() - 1);
    ui.horizontal_wrapped(|ui| {
        for (i, a) in actuators.iter().enumerate() {
            let name = a.module.descriptor().type_name;
            ui.selectable_value(&mut state.tab, i, format!("{i}: {name}"));
        }
    });
    ui.separator();
    let a = &actuators[state.tab];
    let d = a.module.descriptor();
    ui.label(egui::RichText::new(d.summary).italics());
    ui.label(format!("joints {:?}", a.joints));
    let mut changes = Vec::new();
    let mut reset = false;
    egui::ScrollArea::vertical().show(ui, |ui| {
        for (pi, desc) in d.parameters.iter().enumerate() {
            parameter_row(ui, state, a, pi, desc, &mut changes);
        }
        ui.separator();
        reset = ui
            .button("Reset")
            .on_hover_text("restore this module's parameters as configured")
            .clicked();
    });
    apply(session, changes, reset.then_some(state.tab));
}

/// One parameter's row: its name, unit and per-joint switch, then one slider for all the
/// module's joints or one per joint; a slider moved is a change.
fn parameter_row(
    ui: &mut egui::Ui,
    state: &mut ParamsState,
    a: &Actuator,
    pi: usize,
    desc: &ParamDescriptor,
    changes: &mut Vec<Change>,
) {
    let p = a.module.parameters();
    let key = (state.tab, pi);
    let mut individual = state.individual.contains(&key);
    ui.horizontal(|ui| {
        ui.strong(desc.name).on_hover_text(desc.help);
        if !desc.unit.is_empty() {
            ui.label(format!("[{}]", desc.unit));
        }
        if ui.checkbox(&mut individual, "per joint").changed() {
            if individual {
                state.individual.insert(key);
            } else {
                state.individual.remove(&key);
            }
        }
    });
    let (lo, hi) = slider_range(desc.min, desc.max, p.row(pi));
    if individual {
        for (local, joint) in a.joints.iter().enumerate() {
            let mut v = p.get(pi, local);
            let r = ui.add(egui::Slider::new(&mut v, lo..=hi).text(format!("J{}", joint + 1)));
            if r.changed() {
                changes.push(Change {
                    actuator: state.tab,
                    name: desc.name,
                    joint: Some(*joint),
                    value: v,
                });
            }
        }
    } else {
        let mut v = p.get(pi, 0);
        let uniform = p.row(pi).iter().all(|x| *x == v);
        let text = if uniform {
            "all joints"
        } else {
            "all joints (differ)"
        };
        if ui
            .add(egui::Slider::new(&mut v, lo..=hi).text(text))
            .changed()
        {
            changes.push(Change {
                actuator: state.tab,
                name: desc.name,
                joint: None,
                value: v,
            });
        }
    }
}

/// A slider range: the descriptor's, narrowed to something draggable when it is unbounded.
fn slider_range(min: f64, max: f64, values: &[f64]) -> (f64, f64) {
    let biggest = values.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    let lo = if min.is_finite() {
        min
    } else {
        -10.0 * biggest
    };
    let hi = if max.is_finite() { max } else { 10.0 * biggest };
    (lo, hi.max(lo + f64::EPSILON))
}

/// Applies the dialog's changes, and a reset of one actuator's parameters (errors go to
/// the toolbar's message).
pub fn apply(session: &mut SimSession, changes: Vec<Change>, reset: Option<usize>) {
    let initial = session.initial_kernel.clone();
    let Ok(kernel) = session.simulator.kernel_mut(0) else {
        return;
    };
    for c in changes {
        if let Err(e) = kernel.set_parameter(c.actuator, c.name, c.joint, c.value) {
            session.error = Some(e.to_string());
            return;
        }
    }
    if let Some(a) = reset
        && let Err(e) = reset_actuator(kernel, &initial, a)
    {
        session.error = Some(e.to_string());
    }
}

/// Sets every parameter of actuator `a` back to its value in `initial`.
pub fn reset_actuator(
    kernel: &mut crate::control::ControlKernel,
    initial: &crate::control::ControlKernel,
    a: usize,
) -> Result<(), crate::gui::error::GuiError> {
    let Some(init) = initial.actuators().get(a) else {
        return Err(crate::gui::error::GuiError::Missing {
            what: "module tab",
            name: a.to_string(),
        });
    };
    let d = init.module.descriptor();
    let p = init.module.parameters();
    for (pi, desc) in d.parameters.iter().enumerate() {
        for (local, joint) in init.joints.iter().enumerate() {
            kernel.set_parameter(a, desc.name, Some(*joint), p.get(pi, local))?;
        }
    }
    Ok(())
}

/// The control algorithms' properties and the module assignment form.
pub struct ParamsPlugin;

impl Plugin for ParamsPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<ParamsState>()
            .init_resource::<crate::gui::control::assign_view::AssignState>();
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn demo() -> SimSession {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        SimSession::open(
            &root.join("configs/demo.simulation.xml"),
            None,
            &crate::control::ModuleRegistry::standard(),
        )
        .expect("demo loads")
    }

    fn amplitudes(s: &SimSession) -> Vec<f64> {
        let k = s.simulator.kernel(0).expect("kernel");
        let a = &k.actuators()[0];
        let p = a.module.parameters();
        p.row(p.index("Amplitude").expect("amplitude")).to_vec()
    }

    fn change(joint: Option<usize>, value: f64) -> Change {
        Change {
            actuator: 0,
            name: "Amplitude",
            joint,
            value,
        }
    }

    /// Runs `seconds` and returns how far the centre of mass moved in the ground plane.
    fn crawl(s: &mut SimSession, seconds: f64) -> f64 {
        s.simulator.run_for(seconds).displacement
    }

    #[test]
    fn uniform_and_individual_sliders_set_the_kernel_and_reset_restores() {
        let mut s = demo();
        assert_eq!(amplitudes(&s), vec![40.0; 5]);
        apply(&mut s, vec![change(None, 25.0)], None);
        assert_eq!(amplitudes(&s), vec![25.0; 5]);
        apply(&mut s, vec![change(Some(3), 10.0)], None);
        assert_eq!(amplitudes(&s), vec![25.0, 25.0, 25.0, 10.0, 25.0]);
        apply(&mut s, vec![], Some(0));
        assert_eq!(amplitudes(&s), vec![40.0; 5]);
        assert!(s.error.is_none());
        // A value outside the parameter's range is refused with a message, not applied.
        apply(&mut s, vec![change(None, f64::NAN)], None);
        assert!(s.error.is_some());
        assert_eq!(amplitudes(&s), vec![40.0; 5]);
    }

    #[test]
    fn the_dialog_changes_how_the_robot_moves() {
        // Amplitude 0 from the dialog: the snake lies still; back to 40: it crawls.
        let mut s = demo();
        apply(&mut s, vec![change(None, 0.0)], None);
        let still = crawl(&mut s, 3.0);
        apply(&mut s, vec![], Some(0));
        let moving = crawl(&mut s, 3.0);
        assert!(still < 0.01, "moved {still} m with amplitude 0");
        assert!(moving > 0.1, "moved only {moving} m with amplitude 40");
    }
}
