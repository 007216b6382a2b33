//! Actuation files (`*.actuation.xml`, thesis listing B.5): which actuation modules drive
//! which groups of joints. Groups may overlap; the control kernel sums their outputs.
//!
//! Extension: parameter values per module, uniform or one per driven joint:
//! `<parameter name="Amplitude" value="40"/>` or
//! `<parameter name="Amplitude" values="40 40 40 40 0"/>`; a module that runs a learned
//! network names its weights file: `<actuationModule name="Policy" weights="w.safetensors">`.

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::mask::JointMask;
use crate::config::xml::read::read_document;
use crate::config::xml::write::{XmlWriter, num, nums};

/// A parameter's value: the same for every driven joint, or one per driven joint.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    /// One value for every joint.
    Uniform(f64),
    /// One value per driven joint.
    PerJoint(Vec<f64>),
}

/// One parameter setting of a module.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamSetting {
    /// The parameter's name as written.
    pub name: String,
    /// Its value(s).
    pub value: ParamValue,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// One actuation module assigned to a group of joints.
#[derive(Debug, Clone, PartialEq)]
pub struct ModuleAssignment {
    /// Registry name of the module type.
    pub name: String,
    /// The joints it drives (`jointConfiguration`).
    pub joints: JointMask,
    /// Its parameter settings.
    pub params: Vec<ParamSetting>,
    /// Where it was written (line, column).
    pub pos: Pos,
    /// Where its joint mask was written.
    pub mask_pos: Pos,
    /// The weights file of a module that runs a network (`weights="crawl.safetensors"`,
    /// relative to the actuation file), and where it was written.
    pub weights: Option<(String, Pos)>,
}

/// An actuation file as written.
#[derive(Debug, Clone, PartialEq)]
pub struct ActuationFile {
    /// The robot file this actuation was made for.
    pub valid_robot: Option<String>,
    /// The modules, in file order.
    pub modules: Vec<ModuleAssignment>,
}

/// Reads an actuation file's text.
pub fn parse_actuation_file(file: &str, text: &str) -> ConfigResult<ActuationFile> {
    let (doc, r) = read_document(file, text, "actuation", "an actuation file")?;
    let root = &doc.root;
    r.only_children(root, &["validrobot", "actuationmodule"])?;
    r.only_attrs(root, &[])?;
    let valid_robot = match r.at_most_one(root, "validrobot")? {
        Some(v) => {
            r.only_attrs(v, &["robotname"])?;
            Some(r.required_attr(v, "robotname")?.value.clone())
        }
        None => None,
    };
    let mut modules = Vec::new();
    for m in root.children_named("actuationmodule") {
        r.only_children(m, &["jointconfiguration", "parameter"])?;
        r.only_attrs(m, &["name", "weights"])?;
        let name = r.required_attr(m, "name")?.value.clone();
        let weights = m.attr("weights").map(|w| (w.value.clone(), w.pos));
        let jc = r.required(m, "jointconfiguration")?;
        r.only_attrs(jc, &["joints"])?;
        let mask_attr = r.required_attr(jc, "joints")?;
        let joints = JointMask::parse(&r, &mask_attr.value, mask_attr.pos, "joints=")?;
        let mut params = Vec::new();
        for p in m.children_named("parameter") {
            r.only_attrs(p, &["name", "value", "values"])?;
            let pname = r.required_attr(p, "name")?.value.clone();
            let what = format!("parameter {pname}");
            let value = match (p.attr("value"), p.attr("values")) {
                (Some(v), None) => ParamValue::Uniform(r.number(&v.value, v.pos, &what)?),
                (None, Some(v)) => ParamValue::PerJoint(r.numbers(&v.value, v.pos, &what)?),
                _ => {
                    return Err(r.err(
                        p.pos,
                        ErrorKind::InvalidValue,
                        format!("{what}: give either value=\"x\" (uniform) or values=\"x y ...\" (one per driven joint)"),
                    ));
                }
            };
            params.push(ParamSetting {
                name: pname,
                value,
                pos: p.pos,
            });
        }
        modules.push(ModuleAssignment {
            name,
            joints,
            params,
            pos: m.pos,
            mask_pos: mask_attr.pos,
            weights,
        });
    }
    Ok(ActuationFile {
        valid_robot,
        modules,
    })
}

/// Writes an actuation file.
pub fn write_actuation_file(a: &ActuationFile) -> String {
    let mut w = XmlWriter::new();
    w.open("actuation", &[]);
    if let Some(v) = &a.valid_robot {
        w.empty("validRobot", &[("robotName", v.clone())]);
    }
    for m in &a.modules {
        let mut attrs = vec![("name", m.name.clone())];
        if let Some((file, _)) = &m.weights {
            attrs.push(("weights", file.clone()));
        }
        w.open("actuationModule", &attrs);
        w.empty("jointConfiguration", &[("joints", m.joints.to_string())]);
        for p in &m.params {
            let attr = match &p.value {
                ParamValue::Uniform(v) => ("value", num(*v)),
                ParamValue::PerJoint(v) => ("values", nums(v)),
            };
            w.empty("parameter", &[("name", p.name.clone()), attr]);
        }
        w.close();
    }
    w.finish()
}
