//! Behaviour composition (thesis 4.4.5): actuation modules from the registry on groups of
//! joints. "Simple actuation" is one group holding every joint; "grouped actuation" any
//! number of groups (they may overlap: the kernel sums their outputs), each with one or
//! more modules and their parameter values. The result is an ordinary actuation file.

use crate::compose::error::{ComposeError, GroupProblem};
use crate::config::actuation::{ActuationFile, ModuleAssignment, ParamSetting, ParamValue};
use crate::config::error::Pos;
use crate::config::mask::JointMask;
use crate::config::xml::read::same_name;
use crate::control::registry::ModuleRegistry;

/// One module of a group, with the parameter values that differ from its defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct ModuleChoice {
    /// Registry name.
    pub name: String,
    /// Parameter values: uniform, or one per joint of the group.
    pub params: Vec<(String, ParamValue)>,
    /// The weights file of a module that runs a network (as written in the actuation file).
    pub weights: Option<String>,
}

impl ModuleChoice {
    /// A module with every parameter at its registry default.
    pub fn with_defaults(registry: &ModuleRegistry, name: &str) -> Option<ModuleChoice> {
        let d = registry.get(name)?;
        Some(ModuleChoice {
            name: d.type_name.to_string(),
            params: d
                .parameters
                .iter()
                .map(|p| (p.name.to_string(), ParamValue::Uniform(p.default)))
                .collect(),
            weights: None,
        })
    }

    /// Sets one parameter to a uniform value (added when missing).
    pub fn set(&mut self, param: &str, value: f64) {
        self.set_value(param, ParamValue::Uniform(value));
    }

    /// Sets one parameter (added when missing).
    pub fn set_value(&mut self, param: &str, value: ParamValue) {
        match self.params.iter_mut().find(|(n, _)| same_name(n, param)) {
            Some(p) => p.1 = value,
            None => self.params.push((param.to_string(), value)),
        }
    }
}

/// A group of joints and the modules driving it.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// The group's joints, one flag per robot joint.
    pub joints: Vec<bool>,
    /// The modules driving them, each with its parameter values.
    pub modules: Vec<ModuleChoice>,
}

/// Which modules drive which joints.
#[derive(Debug, Clone, PartialEq)]
pub struct BehaviourSpec {
    /// The groups, in actuation-file order.
    pub groups: Vec<Group>,
}

impl BehaviourSpec {
    /// Simple actuation: one module on every joint.
    pub fn simple(joints: usize, module: ModuleChoice) -> Self {
        BehaviourSpec {
            groups: vec![Group {
                joints: vec![true; joints],
                modules: vec![module],
            }],
        }
    }

    /// Keeps the groups when the robot's joint count changes (new joints unassigned,
    /// except in a group that held every joint).
    pub fn resize(&mut self, joints: usize) {
        for g in &mut self.groups {
            let all = g.joints.iter().all(|b| *b);
            g.joints.resize(joints, all);
        }
    }

    /// Why this behaviour cannot drive a robot of `joints` joints, if it cannot.
    pub fn validate(&self, registry: &ModuleRegistry, joints: usize) -> Result<(), ComposeError> {
        if self.groups.is_empty() {
            return Err(ComposeError::NoGroups);
        }
        for (gi, g) in self.groups.iter().enumerate() {
            let fail = |problem| ComposeError::Group {
                group: gi + 1,
                problem,
            };
            if g.joints.len() != joints {
                return Err(fail(GroupProblem::Joints {
                    selected: g.joints.len(),
                    joints,
                }));
            }
            if !g.joints.iter().any(|b| *b) {
                return Err(fail(GroupProblem::NoJoint));
            }
            if g.modules.is_empty() {
                return Err(fail(GroupProblem::NoModule));
            }
            for m in &g.modules {
                let d = registry.get(&m.name).ok_or_else(|| {
                    fail(GroupProblem::UnknownModule {
                        name: m.name.clone(),
                        known: registry.names().join(", "),
                    })
                })?;
                let driven = g.joints.iter().filter(|b| **b).count();
                for (name, value) in &m.params {
                    let p = d.parameter(name).ok_or_else(|| {
                        fail(GroupProblem::UnknownParameter {
                            module: d.type_name.to_string(),
                            parameter: name.clone(),
                            known: d.parameter_names().join(", "),
                        })
                    })?;
                    let values: &[f64] = match value {
                        ParamValue::Uniform(v) => std::slice::from_ref(v),
                        ParamValue::PerJoint(v) => {
                            if v.len() != driven {
                                return Err(fail(GroupProblem::ValueCount {
                                    module: d.type_name.to_string(),
                                    parameter: p.name.to_string(),
                                    values: v.len(),
                                    driven,
                                }));
                            }
                            v
                        }
                    };
                    if let Some(v) = values
                        .iter()
                        .find(|v| !v.is_finite() || **v < p.min || **v > p.max)
                    {
                        return Err(fail(GroupProblem::OutOfRange {
                            module: d.type_name.to_string(),
                            parameter: p.name.to_string(),
                            value: *v,
                            unit: p.unit.to_string(),
                            min: p.min,
                            max: p.max,
                        }));
                    }
                }
            }
        }
        Ok(())
    }

    /// The actuation file; `robot` is written as the file's valid robot.
    pub fn to_actuation_file(&self, robot: &str) -> ActuationFile {
        let mut modules = Vec::new();
        for g in &self.groups {
            for m in &g.modules {
                modules.push(ModuleAssignment {
                    name: m.name.clone(),
                    joints: JointMask(g.joints.clone()),
                    params: m
                        .params
                        .iter()
                        .map(|(n, v)| ParamSetting {
                            name: n.clone(),
                            value: v.clone(),
                            pos: Pos::new(0, 0),
                        })
                        .collect(),
                    pos: Pos::new(0, 0),
                    mask_pos: Pos::new(0, 0),
                    weights: m.weights.clone().map(|file| (file, Pos::new(0, 0))),
                });
            }
        }
        ActuationFile {
            valid_robot: Some(robot.to_string()),
            modules,
        }
    }

    /// The groups of an actuation file: modules on the same joints share a group.
    pub fn from_actuation_file(a: &ActuationFile) -> Self {
        let mut groups: Vec<Group> = Vec::new();
        for m in &a.modules {
            let choice = ModuleChoice {
                name: m.name.clone(),
                params: m
                    .params
                    .iter()
                    .map(|p| (p.name.clone(), p.value.clone()))
                    .collect(),
                weights: m.weights.as_ref().map(|(file, _)| file.clone()),
            };
            match groups.iter_mut().find(|g| g.joints == m.joints.0) {
                Some(g) => g.modules.push(choice),
                None => groups.push(Group {
                    joints: m.joints.0.clone(),
                    modules: vec![choice],
                }),
            }
        }
        BehaviourSpec { groups }
    }

    /// Every (module, parameter) pair assigned, for the optimization page.
    pub fn parameters(&self, registry: &ModuleRegistry) -> Vec<(String, String)> {
        let mut out: Vec<(String, String)> = Vec::new();
        for m in self.groups.iter().flat_map(|g| &g.modules) {
            if let Some(d) = registry.get(&m.name) {
                for p in d.parameters {
                    let pair = (d.type_name.to_string(), p.name.to_string());
                    if !out.contains(&pair) {
                        out.push(pair);
                    }
                }
            }
        }
        out
    }

    /// The joints a module type drives (union of its groups).
    pub fn joints_of(&self, module: &str, joints: usize) -> Vec<bool> {
        let mut mask = vec![false; joints];
        for g in self
            .groups
            .iter()
            .filter(|g| g.modules.iter().any(|m| same_name(&m.name, module)))
        {
            for (m, b) in mask.iter_mut().zip(&g.joints) {
                *m |= *b;
            }
        }
        mask
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::actuation::{parse_actuation_file, write_actuation_file};

    fn sine(reg: &ModuleRegistry) -> ModuleChoice {
        ModuleChoice::with_defaults(reg, "PatternGenerator_sinusoidal").unwrap()
    }

    #[test]
    fn grouped_actuation_writes_one_module_per_group_and_round_trips() {
        let reg = ModuleRegistry::default();
        let mut s = sine(&reg);
        s.set("Amplitude", 35.0);
        let direct = ModuleChoice::with_defaults(&reg, "DirectJointAccess").unwrap();
        let b = BehaviourSpec {
            groups: vec![
                Group {
                    joints: vec![true, false, true, false, true],
                    modules: vec![s],
                },
                Group {
                    joints: vec![false, true, false, true, false],
                    modules: vec![direct],
                },
            ],
        };
        b.validate(&reg, 5).unwrap();
        let a = b.to_actuation_file("x.robot.xml");
        assert_eq!(a.modules.len(), 2);
        assert_eq!(a.modules[0].joints.to_string(), "10101");
        let back = parse_actuation_file("a.xml", &write_actuation_file(&a)).unwrap();
        assert_eq!(back, a);
        assert_eq!(
            b.joints_of("DirectJointAccess", 5),
            vec![false, true, false, true, false]
        );
        assert_eq!(BehaviourSpec::from_actuation_file(&back), b);
    }

    #[test]
    fn validation_names_group_module_and_parameter() {
        let reg = ModuleRegistry::default();
        let mut b = BehaviourSpec::simple(5, sine(&reg));
        b.validate(&reg, 5).unwrap();
        let problem = |b: &BehaviourSpec, joints| match b.validate(&reg, joints) {
            Err(ComposeError::Group { group: 1, problem }) => problem,
            other => panic!("not a problem of group 1: {other:?}"),
        };
        assert_eq!(
            problem(&b, 6),
            GroupProblem::Joints {
                selected: 5,
                joints: 6
            }
        );
        b.groups[0].modules[0].set("Amplitude", f64::NAN);
        assert!(matches!(
            problem(&b, 5),
            GroupProblem::OutOfRange { parameter, value, .. } if parameter == "Amplitude" && value.is_nan()
        ));
        b.groups[0].modules[0].set_value("Amplitude", ParamValue::PerJoint(vec![10.0; 4]));
        assert!(matches!(
            problem(&b, 5),
            GroupProblem::ValueCount {
                values: 4,
                driven: 5,
                ..
            }
        ));
        b.groups[0].modules[0].name = "Wobble".into();
        assert!(matches!(
            problem(&b, 5),
            GroupProblem::UnknownModule { name, .. } if name == "Wobble"
        ));
        b.groups[0].joints = vec![false; 5];
        assert_eq!(problem(&b, 5), GroupProblem::NoJoint);
    }

    #[test]
    fn resizing_keeps_the_all_joints_group_whole() {
        let reg = ModuleRegistry::default();
        let mut b = BehaviourSpec::simple(3, sine(&reg));
        b.resize(6);
        assert_eq!(b.groups[0].joints, vec![true; 6]);
    }
}
