//! A URDF's structure checked before `urdf-rs` reads it, so that a refusal names the
//! element and its line (serde's messages name neither), and visual details proleg does not
//! use never refuse a robot: textures are dropped, a `<visual>` with a fault is dropped
//! with a warning. The cleaned document is what `urdf-rs` then reads.

use crate::config::xml::dom::{Element, parse};
use crate::config::xml::write::XmlWriter;
use crate::interop::InteropError;

/// Attributes `urdf-rs` requires, per element, and how many numbers each holds (0: text).
const REQUIRED: &[(&str, &[(&str, usize)])] = &[
    ("link", &[("name", 0)]),
    ("joint", &[("name", 0), ("type", 0)]),
    ("parent", &[("link", 0)]),
    ("child", &[("link", 0)]),
    ("mass", &[("value", 1)]),
    (
        "inertia",
        &[
            ("ixx", 1),
            ("ixy", 1),
            ("ixz", 1),
            ("iyy", 1),
            ("iyz", 1),
            ("izz", 1),
        ],
    ),
    ("box", &[("size", 3)]),
    ("cylinder", &[("radius", 1), ("length", 1)]),
    ("capsule", &[("radius", 1), ("length", 1)]),
    ("sphere", &[("radius", 1)]),
    ("mesh", &[("filename", 0)]),
    ("color", &[("rgba", 4)]),
    ("material", &[("name", 0)]),
    ("axis", &[("xyz", 3)]),
    ("limit", &[("velocity", 1)]),
    ("mimic", &[("joint", 0)]),
    ("safety_controller", &[("k_velocity", 1)]),
];

/// Optional numeric attributes, checked when present.
const NUMERIC: &[(&str, &[(&str, usize)])] = &[
    ("origin", &[("xyz", 3), ("rpy", 3)]),
    ("mesh", &[("scale", 3)]),
    ("limit", &[("lower", 1), ("upper", 1), ("effort", 1)]),
    ("dynamics", &[("damping", 1), ("friction", 1)]),
];

/// Joint types a URDF may name.
const JOINT_TYPES: &[&str] = &[
    "revolute",
    "continuous",
    "prismatic",
    "fixed",
    "floating",
    "planar",
    "spherical",
];

/// The elements of URDF inside each element that `urdf-rs` reads (others, such as
/// `<gazebo>` or `<transmission>`, are not URDF's and are not checked).
const STRUCTURE: &[(&str, &[&str])] = &[
    ("robot", &["link", "joint", "material"]),
    ("link", &["inertial", "visual", "collision"]),
    ("inertial", &["origin", "mass", "inertia"]),
    ("visual", &["origin", "geometry", "material"]),
    ("collision", &["origin", "geometry"]),
    ("geometry", &SHAPES),
    ("material", &["color"]),
    (
        "joint",
        &[
            "origin",
            "parent",
            "child",
            "axis",
            "limit",
            "dynamics",
            "mimic",
            "safety_controller",
            "calibration",
        ],
    ),
];

/// The shapes a URDF `<geometry>` may hold.
const SHAPES: [&str; 5] = ["box", "cylinder", "sphere", "capsule", "mesh"];

/// Elements a URDF element holds at most once (`urdf-rs` refuses a second one).
const SINGLE: &[&str] = &[
    "inertial",
    "origin",
    "mass",
    "inertia",
    "geometry",
    "material",
    "color",
    "parent",
    "child",
    "axis",
    "limit",
    "dynamics",
    "mimic",
    "safety_controller",
    "calibration",
];

/// A URDF checked and cleaned.
pub struct Cleaned {
    /// The text for `urdf-rs`.
    pub text: String,
    /// Where each link is written in the file, by name.
    pub lines: std::collections::BTreeMap<String, LinkLines>,
}

/// The lines of one link's elements, in the order `urdf-rs` reads them.
#[derive(Debug, Clone, Default)]
pub struct LinkLines {
    /// The `<link>` element's line.
    pub link: u32,
    /// Each `<collision>`'s line.
    pub collisions: Vec<u32>,
    /// Each `<visual>`'s line (those drawn: a faulty visual is dropped before).
    pub visuals: Vec<u32>,
}

impl LinkLines {
    fn of(link: &Element) -> LinkLines {
        let lines = |tag: &str| link.children_named(tag).map(|c| c.pos.line).collect();
        LinkLines {
            link: link.pos.line,
            collisions: lines("collision"),
            visuals: lines("visual"),
        }
    }
}

/// The URDF text `text` of `file`, checked and cleaned for `urdf-rs`; `warn` gets what was
/// dropped. Every structural fault outside a `<visual>` is reported, each with its element
/// and line.
pub fn cleaned(
    file: &std::path::Path,
    text: &str,
    warn: &mut Vec<String>,
) -> Result<Cleaned, InteropError> {
    // A URDF ends at </robot>; what follows (pybullet's humanoid.urdf: a NUL byte) is not
    // the robot's.
    let text = text
        .rfind("</robot>")
        .map_or(text, |end| &text[..end + "</robot>".len()]);
    let doc = parse(&file.display().to_string(), text)
        .map_err(|e| InteropError::new(file, format!("not a valid URDF: {e}")))?;
    let root = &doc.root;
    let mut faults = Vec::new();
    if !root.is("robot") {
        faults.push(format!(
            "line {}: the root element is <{}>, not <robot>",
            root.pos.line, root.name
        ));
    } else if root.child("link").is_none() {
        faults.push(format!("line {}: <robot> has no <link>", root.pos.line));
    }
    if root.is("robot") {
        repeated_names(root, &mut faults);
    }
    let mut out = urdf_only(root, "robot");
    if root.is("robot") {
        for l in out.children.iter_mut().filter(|c| c.is("link")) {
            drop_faulty_visuals(l, warn);
        }
        walk(&out, &mut faults);
    }
    if !faults.is_empty() {
        return Err(InteropError::new(
            file,
            format!("not a valid URDF: {}", faults.join("; ")),
        ));
    }
    let mut w = XmlWriter::new();
    write(&out, &mut w);
    let lines = out
        .children_named("link")
        .filter_map(|l| Some((l.attr("name")?.value.clone(), LinkLines::of(l))))
        .collect();
    Ok(Cleaned {
        text: w.finish(),
        lines,
    })
}

/// A link or joint name used twice (urdf-rs reads both; every link and joint must be
/// unique in a URDF, and the robot file written from it would repeat the name).
fn repeated_names(root: &Element, faults: &mut Vec<String>) {
    for tag in ["link", "joint"] {
        let mut first: std::collections::BTreeMap<&str, u32> = std::collections::BTreeMap::new();
        for el in root.children_named(tag) {
            let Some(name) = el.attr("name") else {
                continue;
            };
            match first.entry(name.value.as_str()) {
                std::collections::btree_map::Entry::Vacant(v) => {
                    v.insert(el.pos.line);
                }
                std::collections::btree_map::Entry::Occupied(o) => faults.push(format!(
                    "line {}: {tag} name \"{}\" is used twice (first on line {})",
                    el.pos.line,
                    name.value,
                    o.get()
                )),
            }
        }
    }
}

/// Whether `child` is URDF inside an element named `parent`.
fn allowed(parent: &str, child: &Element) -> bool {
    // A geometry keeps whatever it holds, for the fault to name it.
    parent == "geometry"
        || STRUCTURE
            .iter()
            .any(|(p, cs)| *p == parent && cs.iter().any(|c| child.is(c)))
}

/// `el` (an element named `kind`) with only the URDF elements inside it, at every depth
/// ([`STRUCTURE`]): `<gazebo>`, `<transmission>`, `<texture>` and the like are not read,
/// and commas between numbers (bike.urdf's "0.07, 0, -0.69") are spaces, as PyBullet reads
/// them.
fn urdf_only(el: &Element, kind: &str) -> Element {
    let mut out = el.clone();
    for a in &mut out.attrs {
        if numeric(kind, &a.name) {
            a.value = a.value.replace(',', " ");
        }
    }
    out.children = el
        .children
        .iter()
        .filter(|c| allowed(kind, c))
        .map(|c| urdf_only(c, &c.name.to_ascii_lowercase()))
        .collect();
    out
}

/// Whether attribute `attr` of an element named `kind` holds numbers.
fn numeric(kind: &str, attr: &str) -> bool {
    REQUIRED
        .iter()
        .chain(NUMERIC)
        .filter(|(n, _)| *n == kind)
        .any(|(_, attrs)| attrs.iter().any(|(a, n)| *a == attr && *n > 0))
}

/// Drops the `<visual>`s of link `l` that hold a fault, with a warning: proleg draws what
/// collides, a visual only lends its colour.
fn drop_faulty_visuals(l: &mut Element, warn: &mut Vec<String>) {
    let name = l.attr("name").map(|a| a.value.clone()).unwrap_or_default();
    l.children.retain(|v| {
        if !v.is("visual") {
            return true;
        }
        let mut inner = Vec::new();
        walk(v, &mut inner);
        if !inner.is_empty() {
            warn.push(format!(
                "link {name}: its <visual> at line {} is not drawn: {}",
                v.pos.line,
                inner.join("; ")
            ));
        }
        inner.is_empty()
    });
}

/// Every fault of `el` and of the elements inside it (all URDF's, see [`urdf_only`]).
fn walk(el: &Element, faults: &mut Vec<String>) {
    check_element(el, faults);
    for c in &el.children {
        walk(c, faults);
    }
}

/// The faults of `el` itself: missing or malformed attributes, an unknown joint type.
fn check_element(el: &Element, faults: &mut Vec<String>) {
    let at = |what: String| format!("line {}: <{}> {what}", el.pos.line, el.name);
    for (name, attrs) in REQUIRED.iter().filter(|(n, _)| el.is(n)) {
        for (attr, numbers) in attrs.iter() {
            match el.attr(attr) {
                None => faults.push(at(format!("has no {attr}=\"...\""))),
                Some(a) => {
                    if let Some(f) = bad_numbers(&a.value, *numbers) {
                        faults.push(at(format!("{attr}=\"{}\": {f}", a.value)));
                    }
                }
            }
        }
        if *name == "joint"
            && let Some(t) = el.attr("type")
            && !JOINT_TYPES.contains(&t.value.as_str())
        {
            faults.push(at(format!(
                "type=\"{}\" is not a joint type ({})",
                t.value,
                JOINT_TYPES.join(", ")
            )));
        }
    }
    if el.is("joint")
        && el
            .attr("type")
            .is_some_and(|t| matches!(t.value.as_str(), "revolute" | "continuous"))
        && let Some(axis) = el.child("axis")
        && let Some(xyz) = axis.attr("xyz")
        && bad_numbers(&xyz.value, 3).is_none()
        && xyz
            .value
            .split_whitespace()
            .map(|v| v.parse::<f64>().map_or(0.0, |v| v * v))
            .sum::<f64>()
            < 1e-12
    {
        faults.push(format!(
            "line {}: <axis> xyz=\"{}\": a hinge's axis needs a direction (length 1e-6 or more)",
            axis.pos.line, xyz.value
        ));
    }
    for (_, attrs) in NUMERIC.iter().filter(|(n, _)| el.is(n)) {
        for (attr, numbers) in attrs.iter() {
            if let Some(a) = el.attr(attr)
                && let Some(f) = bad_numbers(&a.value, *numbers)
            {
                faults.push(at(format!("{attr}=\"{}\": {f}", a.value)));
            }
        }
    }
    for single in SINGLE.iter().filter(|_| !el.is("robot")) {
        if let Some(second) = el.children_named(single).nth(1) {
            faults.push(at(format!(
                "has a second <{single}> (line {})",
                second.pos.line
            )));
        }
    }
    let not_shape = el.children.iter().any(|c| !SHAPES.iter().any(|s| c.is(s)));
    if el.is("geometry") && (el.children.len() != 1 || not_shape) {
        let held: Vec<String> = el
            .children
            .iter()
            .map(|c| format!("<{}>", c.name))
            .collect();
        faults.push(at(format!(
            "must hold one shape (box, cylinder, sphere, capsule, mesh); it holds {}",
            if held.is_empty() {
                "none".to_string()
            } else {
                held.join(", ")
            }
        )));
    }
    if (el.is("inertial") && (el.child("mass").is_none() || el.child("inertia").is_none()))
        || (el.is("visual") || el.is("collision")) && el.child("geometry").is_none()
    {
        faults.push(at("lacks a required child (<inertial> needs <mass> and <inertia>, <visual> and <collision> a <geometry>)".into()));
    }
}

/// Why `value` is not `n` numbers (0: any text), if it is not.
fn bad_numbers(value: &str, n: usize) -> Option<String> {
    if n == 0 {
        return value.trim().is_empty().then(|| "empty".into());
    }
    let parts: Vec<&str> = value.split_whitespace().collect();
    if parts.len() != n {
        return Some(format!("expected {n} number(s), found {}", parts.len()));
    }
    parts
        .iter()
        .find(|p| p.parse::<f64>().is_err())
        .map(|p| format!("\"{p}\" is not a number"))
}

/// Writes `el` back as XML.
fn write(el: &Element, w: &mut XmlWriter) {
    let attrs: Vec<(&str, String)> = el
        .attrs
        .iter()
        .map(|a| (a.name.as_str(), a.value.clone()))
        .collect();
    if el.children.is_empty() && el.text.is_empty() {
        w.empty(&el.name, &attrs);
    } else if el.children.is_empty() {
        w.leaf_attrs(&el.name, &attrs, &el.text);
    } else {
        w.open(&el.name, &attrs);
        for c in &el.children {
            write(c, w);
        }
        w.close();
    }
}
