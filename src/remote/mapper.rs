//! Applies remote bindings to a control kernel (thesis 4.5.7): each frame the remote's
//! values pass through the bindings — dead zones, rate or absolute axes, button steps and
//! toggles on press — and change module parameters through
//! [`ControlKernel::set_parameter`], clamped to each parameter's range. Reset and pause
//! buttons come back as [`RemoteAction`]s for the application to carry out.

use crate::config::remote::{BindMode, BindTarget, JointSelection, RemoteAction, RemoteFile};
use crate::config::resolve::robot::JointOrientation;
use crate::control::ControlKernel;
use crate::remote::device::RemoteData;

/// One parameter of one module instance, on some of its joints.
#[derive(Debug, Clone)]
struct Target {
    actuator: usize,
    param: &'static str,
    /// Robot joint indices.
    joints: Vec<usize>,
    min: f64,
    max: f64,
    scale: f64,
    /// Values when bound (absolute axes and toggles return to them).
    base: Vec<f64>,
    toggled: bool,
}

#[derive(Debug, Clone)]
struct Bound {
    element: String,
    mode: BindMode,
    dead_zone: f64,
    action: Option<RemoteAction>,
    targets: Vec<Target>,
    pressed: bool,
    /// The last axis value written (absolute axes write only on change).
    last: f64,
}

/// Remote bindings resolved against one robot's kernel.
#[derive(Debug, Clone)]
pub struct RemoteMapper {
    bound: Vec<Bound>,
}

/// An axis value with the dead zone removed and the rest rescaled to 0..1.
pub fn dead_zone(v: f64, dz: f64) -> f64 {
    let v = if v.is_finite() {
        v.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    if v.abs() <= dz {
        0.0
    } else {
        v.signum() * (v.abs() - dz) / (1.0 - dz)
    }
}

/// A binding of a remote file that does not fit the robot, located at its line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: {element} -> {module}: {fault}")]
pub struct BindingError {
    /// The remote file.
    pub file: String,
    /// The binding target's line.
    pub line: u32,
    /// The bound element.
    pub element: String,
    /// The target module.
    pub module: String,
    /// What does not fit.
    pub fault: BindingFault,
}

/// What of a binding does not fit the robot.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BindingFault {
    /// A joint mask of another length than the robot's joints.
    #[error("joints=\"{mask}\" has {} characters; the robot has {joints} joints", mask.len())]
    MaskLength {
        /// The mask.
        mask: String,
        /// The robot's joints.
        joints: usize,
    },
    /// A parameter the module does not have.
    #[error("the module has no parameter \"{parameter}\"; its parameters: {known}")]
    NoParameter {
        /// The parameter named.
        parameter: String,
        /// The module's parameters.
        known: String,
    },
    /// A module the actuation does not have.
    #[error("the robot's actuation has no such module")]
    NoModule,
    /// The module drives none of the selected joints.
    #[error("it drives none of the joints \"{joints}\"")]
    DrivesNone {
        /// The selection.
        joints: String,
    },
}

impl RemoteMapper {
    /// Resolves `file`'s bindings against `kernel`; `orientations` are the robot's joints'
    /// (for `pitch` / `yaw` selections). Errors name the file line of the binding.
    pub fn new(
        file: &RemoteFile,
        file_name: &str,
        kernel: &ControlKernel,
        orientations: &[JointOrientation],
    ) -> Result<Self, Box<BindingError>> {
        let mut bound = Vec::new();
        for b in &file.bindings {
            let mut targets = Vec::new();
            for t in &b.targets {
                let at = |fault| {
                    Box::new(BindingError {
                        file: file_name.to_string(),
                        line: t.pos.line,
                        element: b.element.clone(),
                        module: t.module.clone(),
                        fault,
                    })
                };
                targets.extend(targets_of(t, kernel, orientations, &at)?);
                if !targets.iter().any(|x| {
                    crate::config::xml::read::same_name(
                        kernel.actuators()[x.actuator].module.descriptor().type_name,
                        &t.module,
                    )
                }) {
                    return Err(at(BindingFault::DrivesNone {
                        joints: t.joints.to_text(),
                    }));
                }
            }
            bound.push(Bound {
                element: b.element.clone(),
                mode: b.mode,
                dead_zone: b.dead_zone,
                action: b.action,
                targets,
                pressed: false,
                last: 0.0,
            });
        }
        let mut m = RemoteMapper { bound };
        m.rebase(kernel);
        Ok(m)
    }

    /// Takes the kernel's current values as the base of absolute axes and toggles (after
    /// a reset): a held stick applies again from there.
    pub fn rebase(&mut self, kernel: &ControlKernel) {
        for b in &mut self.bound {
            b.last = 0.0;
            for t in &mut b.targets {
                t.toggled = false;
                t.base = t
                    .joints
                    .iter()
                    .map(|j| {
                        kernel
                            .parameter(t.actuator, t.param, Some(*j))
                            .unwrap_or(0.0)
                    })
                    .collect();
            }
        }
    }

    /// Takes over the element states of `old` (the bindings before an edit): a stick
    /// held during the edit keeps its effect instead of being applied twice.
    pub fn carry_over(&mut self, old: &RemoteMapper, kernel: &ControlKernel) {
        for b in &mut self.bound {
            let Some(o) = old
                .bound
                .iter()
                .find(|o| o.element == b.element && o.mode == b.mode)
            else {
                continue;
            };
            b.last = o.last;
            b.pressed = o.pressed;
            if b.mode == BindMode::Absolute {
                for t in &mut b.targets {
                    for (k, j) in t.joints.iter().enumerate() {
                        let now = kernel
                            .parameter(t.actuator, t.param, Some(*j))
                            .unwrap_or(0.0);
                        if let Some(base) = t.base.get_mut(k) {
                            *base = now - b.last * t.scale;
                        }
                    }
                }
            }
        }
    }

    /// Elements the bindings read.
    pub fn elements(&self) -> Vec<&str> {
        self.bound.iter().map(|b| b.element.as_str()).collect()
    }

    /// Applies one snapshot of the remote, `dt` seconds after the last; returns the
    /// actions of buttons pressed now.
    pub fn apply(
        &mut self,
        data: &RemoteData,
        dt: f64,
        kernel: &mut ControlKernel,
    ) -> Result<Vec<RemoteAction>, crate::control::kernel::KernelError> {
        let dt = if dt.is_finite() {
            dt.clamp(0.0, 0.5)
        } else {
            0.0
        };
        let mut actions = Vec::new();
        for b in &mut self.bound {
            let raw = data.get(&b.element);
            let press = raw > 0.5;
            let edge = press && !b.pressed;
            b.pressed = press;
            if b.action.is_some() || b.mode.is_press() {
                if !edge {
                    continue;
                }
                if let Some(a) = b.action {
                    actions.push(a);
                    continue;
                }
            }
            let v = dead_zone(raw, b.dead_zone);
            match b.mode {
                BindMode::Rate if v == 0.0 => continue,
                BindMode::Absolute if v == b.last => continue,
                _ => {}
            }
            b.last = v;
            for t in &mut b.targets {
                if b.mode == BindMode::Toggle {
                    t.toggled = !t.toggled;
                }
                for (k, j) in t.joints.iter().enumerate() {
                    let now = kernel.parameter(t.actuator, t.param, Some(*j))?;
                    let base = t.base.get(k).copied().unwrap_or(now);
                    let want = match b.mode {
                        BindMode::Rate => now + v * t.scale * dt,
                        BindMode::Absolute => base + v * t.scale,
                        BindMode::Increment => now + t.scale,
                        BindMode::Decrement => now - t.scale,
                        BindMode::Toggle if t.toggled => t.scale,
                        BindMode::Toggle => base,
                    };
                    let value = want.clamp(t.min, t.max);
                    if value != now {
                        kernel.set_parameter(t.actuator, t.param, Some(*j), value)?;
                    }
                }
            }
        }
        Ok(actions)
    }
}

/// The targets one `<target>` of a binding resolves to: each actuator of its module type
/// with its parameter, on the joints its selection keeps (none kept: no target).
fn targets_of(
    t: &BindTarget,
    kernel: &ControlKernel,
    orientations: &[JointOrientation],
    at: &dyn Fn(BindingFault) -> Box<BindingError>,
) -> Result<Vec<Target>, Box<BindingError>> {
    let mut targets = Vec::new();
    if let JointSelection::Mask(m) = &t.joints
        && m.len() != kernel.joints()
    {
        return Err(at(BindingFault::MaskLength {
            mask: t.joints.to_text(),
            joints: kernel.joints(),
        }));
    }
    let mut found_module = false;
    for (ai, a) in kernel.actuators().iter().enumerate() {
        let d = a.module.descriptor();
        if !crate::config::xml::read::same_name(d.type_name, &t.module) {
            continue;
        }
        found_module = true;
        let p = d.parameter(&t.parameter).ok_or_else(|| {
            at(BindingFault::NoParameter {
                parameter: t.parameter.clone(),
                known: d.parameter_names().join(", "),
            })
        })?;
        let joints: Vec<usize> = a
            .joints
            .iter()
            .copied()
            .filter(|j| match &t.joints {
                JointSelection::All => true,
                JointSelection::Pitch => orientations.get(*j) == Some(&JointOrientation::Pitch),
                JointSelection::Yaw => orientations.get(*j) == Some(&JointOrientation::Yaw),
                JointSelection::Mask(m) => m.get(*j).copied().unwrap_or(false),
            })
            .collect();
        if joints.is_empty() {
            continue;
        }
        targets.push(Target {
            actuator: ai,
            param: p.name,
            joints,
            min: p.min,
            max: p.max,
            scale: t.scale,
            base: Vec::new(),
            toggled: false,
        });
    }
    if !found_module {
        return Err(at(BindingFault::NoModule));
    }
    Ok(targets)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::remote::{default_gamepad_bindings, parse_remote_file};
    use crate::control::ModuleRegistry;

    /// The 8-module pitch-yaw robot with the sine generator on every joint.
    fn kernel() -> (ControlKernel, Vec<JointOrientation>) {
        let sim =
            crate::control::load_simulation("configs/snake8py_remote.simulation.xml").unwrap();
        let limits = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
        let k = ControlKernel::from_actuation(&sim.actuation, &ModuleRegistry::default(), limits)
            .unwrap();
        let o = sim.robot.joints.iter().map(|j| j.orientation).collect();
        (k, o)
    }

    fn values(k: &ControlKernel, p: &str) -> Vec<f64> {
        (0..7)
            .map(|j| k.parameter(0, p, Some(j)).unwrap())
            .collect()
    }

    #[test]
    fn default_binding_changes_amplitude_offsets_and_frequency() {
        let (mut k, o) = kernel();
        let mut m = RemoteMapper::new(&default_gamepad_bindings(), "default", &k, &o).unwrap();
        let amp0 = values(&k, "Amplitude");
        let mut d = RemoteData::default();
        // Inside the dead zone nothing moves.
        d.set("LeftStickY", 0.05);
        m.apply(&d, 0.1, &mut k).unwrap();
        assert_eq!(values(&k, "Amplitude"), amp0);
        // Full up for 0.5 s: +10 deg on the pitch joints only.
        d.set("LeftStickY", 1.0);
        for _ in 0..5 {
            m.apply(&d, 0.1, &mut k).unwrap();
        }
        let amp = values(&k, "Amplitude");
        for j in 0..7 {
            let want = if j % 2 == 0 { amp0[j] + 10.0 } else { amp0[j] };
            assert!(
                (amp[j] - want).abs() < 1e-9,
                "joint {j}: {} vs {want}",
                amp[j]
            );
        }
        // Held long enough it stops at the parameter's limit.
        for _ in 0..200 {
            m.apply(&d, 0.1, &mut k).unwrap();
        }
        let max = values(&k, "Amplitude")[0];
        assert_eq!(max, 90.0, "amplitude clamps at its limit");
        // Steering: stick right bends the yaw joints negative, back to centre restores.
        d.set("LeftStickY", 0.0);
        d.set("LeftStickX", 1.0);
        m.apply(&d, 0.1, &mut k).unwrap();
        let off = values(&k, "Offset");
        assert_eq!(off, vec![0.0, -20.0, 0.0, -20.0, 0.0, -20.0, 0.0]);
        d.set("LeftStickX", 0.0);
        m.apply(&d, 0.1, &mut k).unwrap();
        assert!(values(&k, "Offset").iter().all(|v| *v == 0.0));
        // Frequency follows the right stick; a press of South asks for a reset, once.
        d.set("RightStickY", -1.0);
        let f0 = values(&k, "Frequency")[0];
        m.apply(&d, 0.2, &mut k).unwrap();
        assert!((values(&k, "Frequency")[0] - (f0 - 0.1)).abs() < 1e-9);
        d.set("South", 1.0);
        assert_eq!(m.apply(&d, 0.1, &mut k).unwrap(), vec![RemoteAction::Reset]);
        assert!(
            m.apply(&d, 0.1, &mut k).unwrap().is_empty(),
            "held: no repeat"
        );
        // Bindings rebuilt while the stick is held right keep the offset at -20.
        d.set("LeftStickX", 1.0);
        m.apply(&d, 0.1, &mut k).unwrap();
        let mut again = RemoteMapper::new(&default_gamepad_bindings(), "default", &k, &o).unwrap();
        again.carry_over(&m, &k);
        again.apply(&d, 0.1, &mut k).unwrap();
        assert_eq!(values(&k, "Offset")[1], -20.0);
        d.set("LeftStickX", 0.0);
        again.apply(&d, 0.1, &mut k).unwrap();
        assert_eq!(values(&k, "Offset")[1], 0.0);
    }

    #[test]
    fn buttons_step_and_toggle_and_bad_targets_are_refused() {
        let (mut k, o) = kernel();
        let file = parse_remote_file(
            "t.remote.xml",
            "<remote>\n<binding element=\"North\" mode=\"toggle\">\n<target module=\"PatternGenerator_sinusoidal\" parameter=\"Frequency\" joints=\"all\" scale=\"2\"/>\n</binding>\n<binding element=\"DPadDown\" mode=\"decrement\">\n<target module=\"PatternGenerator_sinusoidal\" parameter=\"Amplitude\" joints=\"1000000\" scale=\"50\"/>\n</binding>\n</remote>",
        )
        .unwrap();
        let mut m = RemoteMapper::new(&file, "t.remote.xml", &k, &o).unwrap();
        let f0 = values(&k, "Frequency")[0];
        let mut d = RemoteData::default();
        d.set("North", 1.0);
        m.apply(&d, 0.1, &mut k).unwrap();
        assert_eq!(values(&k, "Frequency")[3], 2.0);
        d.set("North", 0.0);
        m.apply(&d, 0.1, &mut k).unwrap();
        d.set("North", 1.0);
        m.apply(&d, 0.1, &mut k).unwrap();
        assert_eq!(values(&k, "Frequency")[3], f0, "second press toggles back");
        d.set("DPadDown", 1.0);
        m.apply(&d, 0.1, &mut k).unwrap();
        assert_eq!(
            values(&k, "Amplitude")[0],
            0.0,
            "clamped at the lower limit"
        );
        assert_eq!(values(&k, "Amplitude")[2], 35.0, "other joints untouched");

        let bad = |text: &str| {
            let f = parse_remote_file("b.remote.xml", text).unwrap();
            RemoteMapper::new(&f, "b.remote.xml", &k, &o).unwrap_err()
        };
        let e = bad(
            "<remote>\n<binding element=\"A\">\n<target module=\"Wobble\" parameter=\"P\" scale=\"1\"/>\n</binding>\n</remote>",
        );
        assert_eq!(
            (e.file.as_str(), e.line, e.module.as_str()),
            ("b.remote.xml", 3, "Wobble")
        );
        assert_eq!(e.fault, BindingFault::NoModule);
        let e = bad(
            "<remote>\n<binding element=\"A\">\n<target module=\"PatternGenerator_sinusoidal\" parameter=\"Speed\" scale=\"1\"/>\n</binding>\n</remote>",
        );
        assert!(
            matches!(
                &e.fault,
                BindingFault::NoParameter { parameter, known } if parameter == "Speed" && known.contains("Amplitude")
            ),
            "{e}"
        );
        let e = bad(
            "<remote>\n<binding element=\"A\">\n<target module=\"PatternGenerator_sinusoidal\" parameter=\"Offset\" joints=\"101\" scale=\"1\"/>\n</binding>\n</remote>",
        );
        assert!(
            matches!(e.fault, BindingFault::MaskLength { joints: 7, .. }),
            "{e}"
        );
    }

    #[test]
    fn dead_zone_rescales_the_rest() {
        assert_eq!(dead_zone(0.1, 0.2), 0.0);
        assert!((dead_zone(0.6, 0.2) - 0.5).abs() < 1e-12);
        assert_eq!(dead_zone(-1.0, 0.2), -1.0);
        assert_eq!(dead_zone(f64::NAN, 0.2), 0.0);
        assert_eq!(dead_zone(3.0, 0.0), 1.0);
    }
}
