//! The resolved actuation: module types found in the registry, joint masks checked
//! against the robot, parameter values checked against the module's descriptor.

use std::path::{Path, PathBuf};

use crate::config::actuation::{ActuationFile, ModuleAssignment, ParamValue};
use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::mask::JointMask;
use crate::config::module_types::{ModuleDescriptor, ModuleTypes, ParamDescriptor};
use crate::config::resolve::flatten::find_file;
use crate::config::resolve::robot::RobotModel;
use crate::config::source::FileSource;
use crate::config::xml::read::Reader;

/// A parameter value set in the actuation file, with its canonical name.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamAssignment {
    /// The parameter's canonical name.
    pub name: &'static str,
    /// Its value(s).
    pub value: ParamValue,
}

/// One module instance driving a group of joints.
#[derive(Debug, Clone, PartialEq)]
pub struct ModuleInstance {
    /// The module type.
    pub descriptor: ModuleDescriptor,
    /// The robot joints it drives.
    pub joints: JointMask,
    /// Values from the file; parameters not listed keep their defaults.
    pub params: Vec<ParamAssignment>,
    /// The weights file of a module that runs a network, found relative to the actuation
    /// file and read with the configuration (parsed when the kernel is built).
    pub weights: Option<WeightsFile>,
    /// Where its `<actuationModule>` was written (no position: a module made in the
    /// window), for errors found when the kernel meets the robot.
    pub pos: Pos,
}

/// A weights file's path and bytes, read with the configuration (so a run's stored files
/// carry it to workers on other hosts).
#[derive(Debug, Clone, PartialEq)]
pub struct WeightsFile {
    /// Where it was read.
    pub path: PathBuf,
    /// Its bytes (a safetensors file, parsed by `crate::control::policy`).
    pub bytes: std::sync::Arc<[u8]>,
}

/// The resolved actuation file.
#[derive(Debug, Clone, PartialEq)]
pub struct ActuationModel {
    /// The actuation file.
    pub file: PathBuf,
    /// The modules, in file order.
    pub modules: Vec<ModuleInstance>,
    /// Things that load but look unintended.
    pub warnings: Vec<String>,
}

/// The module type `name` from the registry, or an error listing the known ones.
pub(crate) fn lookup_module<'a>(
    r: &Reader,
    registry: &'a dyn ModuleTypes,
    name: &str,
    pos: Pos,
) -> ConfigResult<&'a ModuleDescriptor> {
    registry.describe(name).ok_or_else(|| {
        r.err(
            pos,
            ErrorKind::UnknownModule,
            format!(
                "unknown actuation module \"{name}\"; known modules: {}",
                registry.type_names().join(", ")
            ),
        )
    })
}

/// The parameter `name` of a module type, or an error listing its parameters.
pub(crate) fn lookup_parameter<'a>(
    r: &Reader,
    module: &'a ModuleDescriptor,
    name: &str,
    pos: Pos,
) -> ConfigResult<&'a ParamDescriptor> {
    module.parameter(name).ok_or_else(|| {
        r.err(
            pos,
            ErrorKind::UnknownReference,
            format!(
                "module {} has no parameter \"{name}\"; its parameters: {}",
                module.type_name,
                module.parameter_names().join(", ")
            ),
        )
    })
}

/// Checks an actuation file against the robot and the registry.
pub fn resolve_actuation(
    src: &dyn FileSource,
    path: &Path,
    file: &ActuationFile,
    robot: &RobotModel,
    registry: &dyn ModuleTypes,
) -> ConfigResult<ActuationModel> {
    let r = Reader::new(path);
    let mut warnings = Vec::new();
    if let Some(valid) = &file.valid_robot {
        let robot_file = robot
            .file
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        if *valid != robot_file && *valid != robot.name {
            warnings.push(format!(
                "{}: made for robot \"{valid}\", used with \"{robot_file}\" (masks match its {} joints)",
                path.display(),
                robot.joints.len()
            ));
        }
    }
    let mut modules = Vec::with_capacity(file.modules.len());
    for m in &file.modules {
        let descriptor = lookup_module(&r, registry, &m.name, m.pos)?;
        m.joints.check_len(
            &r,
            m.mask_pos,
            robot.joints.len(),
            "jointConfiguration joints=",
        )?;
        if m.joints.count() == 0 {
            warnings.push(format!(
                "{}: module {} drives no joint (mask {})",
                path.display(),
                m.name,
                m.joints
            ));
        }
        let params = resolve_params(&r, descriptor, m)?;
        let weights = read_weights(src, path, &r, m.weights.as_ref())?;
        modules.push(ModuleInstance {
            descriptor: descriptor.clone(),
            joints: m.joints.clone(),
            params,
            weights,
            pos: m.pos,
        });
    }
    Ok(ActuationModel {
        file: path.to_path_buf(),
        modules,
        warnings,
    })
}

/// A module's parameter settings, each a parameter of its type, set once, with one value
/// or one per driven joint, in its range.
fn resolve_params(
    r: &Reader,
    descriptor: &ModuleDescriptor,
    m: &ModuleAssignment,
) -> ConfigResult<Vec<ParamAssignment>> {
    let mut params: Vec<ParamAssignment> = Vec::new();
    for p in &m.params {
        let d = lookup_parameter(r, descriptor, &p.name, p.pos)?;
        if params.iter().any(|o| o.name == d.name) {
            return Err(r.err(
                p.pos,
                ErrorKind::InvalidValue,
                format!("parameter {} is set twice", d.name),
            ));
        }
        let values: &[f64] = match &p.value {
            ParamValue::Uniform(v) => std::slice::from_ref(v),
            ParamValue::PerJoint(v) => {
                if v.len() != m.joints.count() {
                    return Err(r.err(
                        p.pos,
                        ErrorKind::InvalidValue,
                        format!(
                            "parameter {} has {} values but the module drives {} joints (mask {}); give one per driven joint",
                            d.name,
                            v.len(),
                            m.joints.count(),
                            m.joints
                        ),
                    ));
                }
                v
            }
        };
        for v in values {
            r.check_range(
                *v,
                d.min,
                d.max,
                p.pos,
                &format!("{} {} ({})", descriptor.type_name, d.name, d.unit),
            )?;
        }
        params.push(ParamAssignment {
            name: d.name,
            value: p.value.clone(),
        });
    }
    Ok(params)
}

/// A module's weights file (`weights="..."`), found like an include and read with the
/// configuration.
fn read_weights(
    src: &dyn FileSource,
    path: &Path,
    r: &Reader,
    weights: Option<&(String, Pos)>,
) -> ConfigResult<Option<WeightsFile>> {
    Ok(match weights {
        Some((file, pos)) => {
            let found = find_file(src, path, file, *pos, "weights")?;
            let bytes = src.read_bytes(&found).map_err(|e| {
                r.err(
                    *pos,
                    ErrorKind::MissingFile,
                    format!("weights file {}: {e}", found.display()),
                )
                .caused_by(e)
            })?;
            Some(WeightsFile {
                path: found,
                bytes: bytes.into(),
            })
        }
        None => None,
    })
}
