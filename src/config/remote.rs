//! Remote binding files (`*.remote.xml`, our extension; thesis 4.5.7, fig. 4.22): which
//! element of a remote (a gamepad's sticks, triggers, buttons, d-pad) changes which
//! module parameters, how strongly, and which buttons reset or pause.
//!
//! ```xml
//! <remote name="default gamepad">
//!   <!-- rate: the parameter changes by value·scale per second while the stick is held -->
//!   <binding element="LeftStickY" mode="rate" deadZone="0.15">
//!     <target module="PatternGenerator_sinusoidal" parameter="Amplitude" joints="pitch" scale="20"/>
//!   </binding>
//!   <!-- absolute: parameter = its value when bound + value·scale -->
//!   <binding element="LeftStickX" mode="absolute" deadZone="0.1">
//!     <target module="PatternGenerator_sinusoidal" parameter="Offset" joints="yaw" scale="-20"/>
//!   </binding>
//!   <!-- increment / decrement: ±scale per press; toggle: between its value and scale -->
//!   <binding element="DPadUp" mode="increment">
//!     <target module="PatternGenerator_sinusoidal" parameter="Frequency" joints="all" scale="0.1"/>
//!   </binding>
//!   <binding element="South" action="reset"/>   <!-- parameters back to the configuration -->
//!   <binding element="Start" action="pause"/>   <!-- pause / resume -->
//! </remote>
//! ```
//!
//! `joints` is `all` (every joint the module drives), `pitch` or `yaw` (those of the
//! module's joints with that orientation), or a mask of 0/1 over the robot's joints.
//! Several bindings may use one element (with different scales); a binding may hold
//! several targets.

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::xml::dom::Element;
use crate::config::xml::read::{Reader, read_document};
use crate::config::xml::write::{XmlWriter, num};

/// Dead zone of bindings that give none.
pub const DEFAULT_DEAD_ZONE: f64 = 0.1;

/// How an element's value changes its targets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BindMode {
    /// Parameter += value · scale per second (axes).
    Rate,
    /// Parameter = value when bound + value · scale (axes).
    Absolute,
    /// Parameter += scale per press (buttons).
    Increment,
    /// Parameter -= scale per press (buttons).
    Decrement,
    /// Each press switches between the value when bound and scale (buttons).
    Toggle,
}

impl BindMode {
    /// Every value, in the order the GUI lists them.
    pub const ALL: [BindMode; 5] = [
        BindMode::Rate,
        BindMode::Absolute,
        BindMode::Increment,
        BindMode::Decrement,
        BindMode::Toggle,
    ];

    /// The name binding files use.
    pub fn name(self) -> &'static str {
        match self {
            BindMode::Rate => "rate",
            BindMode::Absolute => "absolute",
            BindMode::Increment => "increment",
            BindMode::Decrement => "decrement",
            BindMode::Toggle => "toggle",
        }
    }

    /// Reads a name as files, scripts and the command line write it (None: unknown).
    pub fn parse(s: &str) -> Option<BindMode> {
        BindMode::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
    }

    /// Whether the mode reads a button press rather than an axis value.
    pub fn is_press(self) -> bool {
        matches!(
            self,
            BindMode::Increment | BindMode::Decrement | BindMode::Toggle
        )
    }
}

/// What a button does besides changing parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RemoteAction {
    /// Every parameter back to the configuration's values.
    Reset,
    /// Pause or resume the simulation.
    Pause,
}

impl RemoteAction {
    /// The name binding files use.
    pub fn name(self) -> &'static str {
        match self {
            RemoteAction::Reset => "reset",
            RemoteAction::Pause => "pause",
        }
    }
}

/// Which of a module's joints a target changes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JointSelection {
    /// Every joint the module drives.
    All,
    /// Its pitch joints.
    Pitch,
    /// Its yaw joints.
    Yaw,
    /// 0/1 per robot joint.
    Mask(Vec<bool>),
}

impl JointSelection {
    /// Reads a name as files, scripts and the command line write it (None: unknown).
    pub fn parse(s: &str) -> Option<JointSelection> {
        match s.trim().to_ascii_lowercase().as_str() {
            "all" | "" => Some(JointSelection::All),
            "pitch" => Some(JointSelection::Pitch),
            "yaw" => Some(JointSelection::Yaw),
            m if m.chars().all(|c| c == '0' || c == '1') => {
                Some(JointSelection::Mask(m.chars().map(|c| c == '1').collect()))
            }
            _ => None,
        }
    }

    /// As binding files write it.
    pub fn to_text(&self) -> String {
        match self {
            JointSelection::All => "all".into(),
            JointSelection::Pitch => "pitch".into(),
            JointSelection::Yaw => "yaw".into(),
            JointSelection::Mask(m) => m.iter().map(|b| if *b { '1' } else { '0' }).collect(),
        }
    }
}

/// One module parameter an element changes.
#[derive(Debug, Clone, PartialEq)]
pub struct BindTarget {
    /// The module type.
    pub module: String,
    /// The parameter.
    pub parameter: String,
    /// Which of its joints.
    pub joints: JointSelection,
    /// Parameter change per unit of the element.
    pub scale: f64,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// One binding of an element.
#[derive(Debug, Clone, PartialEq)]
pub struct Binding {
    /// The element's name as the remote lists it (`LeftStickX`, `South`, `DPadUp`, ...).
    pub element: String,
    /// How the element's value changes the parameter.
    pub mode: BindMode,
    /// Axis values below this magnitude count as 0; the rest is rescaled to 0..1.
    pub dead_zone: f64,
    /// A simulation action instead of (or besides) parameters.
    pub action: Option<RemoteAction>,
    /// The parameters it changes.
    pub targets: Vec<BindTarget>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// A remote binding file.
#[derive(Debug, Clone, PartialEq)]
pub struct RemoteFile {
    /// The binding set's name.
    pub name: String,
    /// Its bindings.
    pub bindings: Vec<Binding>,
}

/// Reads a remote binding file's text.
pub fn parse_remote_file(file: &str, text: &str) -> ConfigResult<RemoteFile> {
    let (doc, r) = read_document(file, text, "remote", "a remote binding file")?;
    let root = &doc.root;
    r.only_children(root, &["binding"])?;
    r.only_attrs(root, &["name"])?;
    let mut bindings = Vec::new();
    for b in &root.children {
        bindings.push(read_binding(&r, b)?);
    }
    Ok(RemoteFile {
        name: root
            .attr("name")
            .map(|a| a.value.clone())
            .unwrap_or_default(),
        bindings,
    })
}

/// One `<binding>`: the remote's element, its mode, dead zone, action and targets.
fn read_binding(r: &Reader, b: &Element) -> ConfigResult<Binding> {
    r.only_children(b, &["target"])?;
    r.only_attrs(b, &["element", "mode", "deadzone", "action"])?;
    let element = r.required_attr(b, "element")?;
    if element.value.trim().is_empty() {
        return Err(r.err(
            element.pos,
            ErrorKind::InvalidValue,
            "element=\"\": name the remote's element",
        ));
    }
    let action = match b.attr("action") {
        None => None,
        Some(a) => Some(match a.value.trim().to_ascii_lowercase().as_str() {
            "reset" => RemoteAction::Reset,
            "pause" => RemoteAction::Pause,
            other => {
                return Err(r.err(
                    a.pos,
                    ErrorKind::InvalidValue,
                    format!("action \"{other}\": expected reset or pause"),
                ));
            }
        }),
    };
    let mode = match b.attr("mode") {
        Some(m) => BindMode::parse(&m.value).ok_or_else(|| {
            r.err(
                m.pos,
                ErrorKind::InvalidValue,
                format!(
                    "mode \"{}\": expected one of {}",
                    m.value,
                    BindMode::ALL.map(|m| m.name()).join(", ")
                ),
            )
        })?,
        None if action.is_some() => BindMode::Increment,
        None => BindMode::Rate,
    };
    let dead_zone = match b.attr("deadzone") {
        Some(d) => {
            let v = r.number(&d.value, d.pos, "deadZone=")?;
            r.check_range(v, 0.0, 0.95, d.pos, "deadZone=")?;
            v
        }
        None => DEFAULT_DEAD_ZONE,
    };
    let targets = b
        .children
        .iter()
        .map(|t| read_target(r, t))
        .collect::<ConfigResult<Vec<_>>>()?;
    if targets.is_empty() && action.is_none() {
        return Err(r.err(
            b.pos,
            ErrorKind::Missing,
            format!(
                "binding of {}: give <target> elements or action=\"reset|pause\"",
                element.value
            ),
        ));
    }
    Ok(Binding {
        element: element.value.trim().to_string(),
        mode,
        dead_zone,
        action,
        targets,
        pos: b.pos,
    })
}

/// One `<target>` of a binding: the module parameter, the joints and the scale.
fn read_target(r: &Reader, t: &Element) -> ConfigResult<BindTarget> {
    r.only_attrs(t, &["module", "parameter", "joints", "scale"])?;
    let joints = match t.attr("joints") {
        Some(j) => JointSelection::parse(&j.value).ok_or_else(|| {
            r.err(
                j.pos,
                ErrorKind::InvalidValue,
                format!(
                    "joints=\"{}\": expected all, pitch, yaw or a 0/1 mask over the robot's joints",
                    j.value
                ),
            )
        })?,
        None => JointSelection::All,
    };
    let scale = r.required_attr(t, "scale")?;
    Ok(BindTarget {
        module: r.required_attr(t, "module")?.value.clone(),
        parameter: r.required_attr(t, "parameter")?.value.clone(),
        joints,
        scale: r.number(&scale.value, scale.pos, "scale=")?,
        pos: t.pos,
    })
}

/// Writes a remote binding file.
pub fn write_remote_file(f: &RemoteFile) -> String {
    let mut w = XmlWriter::new();
    w.open("remote", &[("name", f.name.clone())]);
    for b in &f.bindings {
        let mut attrs = vec![("element", b.element.clone())];
        // An action's binding says its mode and dead zone only when not the defaults
        // (press: increment); any other binding always says them.
        if let Some(a) = b.action {
            attrs.push(("action", a.name().to_string()));
        }
        if b.action.is_none() || b.mode != BindMode::Increment {
            attrs.push(("mode", b.mode.name().to_string()));
        }
        if b.action.is_none() || b.dead_zone != DEFAULT_DEAD_ZONE {
            attrs.push(("deadZone", num(b.dead_zone)));
        }
        if b.targets.is_empty() {
            w.empty("binding", &attrs);
            continue;
        }
        w.open("binding", &attrs);
        for t in &b.targets {
            w.empty(
                "target",
                &[
                    ("module", t.module.clone()),
                    ("parameter", t.parameter.clone()),
                    ("joints", t.joints.to_text()),
                    ("scale", num(t.scale)),
                ],
            );
        }
        w.close();
    }
    w.finish()
}

/// The default gamepad binding (as the thesis's Wiimote example, fig. 4.22): left stick
/// up/down changes the sine generator's amplitude on the pitch joints, left stick
/// left/right bends the yaw joints (steering right with the stick right), right stick
/// up/down changes the frequency, the d-pad steps the amplitude, South (A / cross)
/// resets, Start pauses.
pub fn default_gamepad_bindings() -> RemoteFile {
    let sine = "PatternGenerator_sinusoidal";
    let target = |parameter: &str, joints: JointSelection, scale: f64| BindTarget {
        module: sine.into(),
        parameter: parameter.into(),
        joints,
        scale,
        pos: Pos::new(0, 0),
    };
    let bind = |element: &str, mode: BindMode, targets: Vec<BindTarget>| Binding {
        element: element.into(),
        mode,
        dead_zone: 0.12,
        action: None,
        targets,
        pos: Pos::new(0, 0),
    };
    let action = |element: &str, a: RemoteAction| Binding {
        element: element.into(),
        mode: BindMode::Increment,
        dead_zone: DEFAULT_DEAD_ZONE,
        action: Some(a),
        targets: Vec::new(),
        pos: Pos::new(0, 0),
    };
    RemoteFile {
        name: "default gamepad".into(),
        bindings: vec![
            bind(
                "LeftStickY",
                BindMode::Rate,
                vec![target("Amplitude", JointSelection::Pitch, 20.0)],
            ),
            bind(
                "LeftStickX",
                BindMode::Absolute,
                vec![target("Offset", JointSelection::Yaw, -20.0)],
            ),
            bind(
                "RightStickY",
                BindMode::Rate,
                vec![target("Frequency", JointSelection::All, 0.5)],
            ),
            bind(
                "DPadUp",
                BindMode::Increment,
                vec![target("Amplitude", JointSelection::Pitch, 5.0)],
            ),
            bind(
                "DPadDown",
                BindMode::Decrement,
                vec![target("Amplitude", JointSelection::Pitch, 5.0)],
            ),
            action("South", RemoteAction::Reset),
            action("Start", RemoteAction::Pause),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_bindings_round_trip_through_the_file() {
        let d = default_gamepad_bindings();
        let text = write_remote_file(&d);
        assert_eq!(parse_remote_file("d.remote.xml", &text).unwrap(), d);
    }

    #[test]
    fn the_shipped_default_file_is_the_default_binding() {
        let path = "configs/remote/default.remote.xml";
        let f = parse_remote_file(path, &std::fs::read_to_string(path).unwrap()).unwrap();
        assert_eq!(f, default_gamepad_bindings());
    }

    #[test]
    fn bad_bindings_name_line_and_cause() {
        let e = parse_remote_file(
            "b.remote.xml",
            "<remote>\n  <binding element=\"LeftStickX\" mode=\"wobble\">\n    <target module=\"M\" parameter=\"P\" scale=\"1\"/>\n  </binding>\n</remote>\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("b.remote.xml:2:") && e.contains("wobble"), "{e}");
        let e = parse_remote_file(
            "b.remote.xml",
            "<remote>\n  <binding element=\"South\">\n    <target module=\"M\" parameter=\"P\" joints=\"left\" scale=\"1\"/>\n  </binding>\n</remote>\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains(":3:") && e.contains("left"), "{e}");
        let e = parse_remote_file(
            "b.remote.xml",
            "<remote>\n<binding element=\"South\" mode=\"rate\">\n<target module=\"M\" parameter=\"P\" scale=\"NaN\"/>\n</binding>\n</remote>",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("scale=") && e.contains("NaN"), "{e}");
        let e = parse_remote_file("b.remote.xml", "<remote><binding element=\"A\"/></remote>")
            .unwrap_err()
            .to_string();
        assert!(e.contains("target"), "{e}");
    }
}
