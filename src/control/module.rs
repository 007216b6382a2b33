//! The actuation-module interface (thesis 5.2, listing A.1): plain Rust, free of Bevy, so
//! a module runs the same in the simulation, in a unit test, in the GUI and in a plugin.
//!
//! A module drives a group of joints. Every step it gets a [`StepContext`] and writes one
//! angle (degrees) per connected joint. Its parameters are per joint, uniform or
//! individual ([`Parameters`]); its intermediate values are logged ([`InternalData`]).

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
use crate::control::policy::{NetworkMismatch, PolicyNet};
use crate::rng::SimRng;
use crate::sensing::SensorData;

/// What a module sees in one step.
#[derive(Debug, Clone, Copy)]
pub struct StepContext<'a> {
    /// Simulated time (s) of the step being computed.
    pub time: f64,
    /// Step width δ (s).
    pub dt: f64,
    /// Step counter.
    pub step: u64,
    /// Current measured angles (degrees) of the module's joints, in mask order.
    pub angles: &'a [f64],
    /// Current measured angles (degrees) of every robot joint.
    pub robot_angles: &'a [f64],
    /// The robot's latest sensor readings (for sensing modules).
    pub sensors: &'a SensorData,
    /// The phase (degrees) of each generator of the kernel at its first joint, as of the
    /// previous step: every module with a `Phase` series, in kernel order.
    pub phases: &'a [f64],
}

/// Why a parameter could not be read or changed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// The module has no parameter of that name.
    #[error("module {module} has no parameter \"{name}\"; its parameters: {}", known.join(", "))]
    UnknownParameter {
        /// The module type.
        module: &'static str,
        /// The name asked for.
        name: String,
        /// Its parameters.
        known: Vec<&'static str>,
    },
    /// A joint index beyond the module's joints.
    #[error("joint {joint} is not one of the module's {joints} joints")]
    JointOutOfRange {
        /// The index given.
        joint: usize,
        /// The module's joints.
        joints: usize,
    },
    /// A NaN or infinite value.
    #[error("{name}: {value} is not a finite number")]
    NotFinite {
        /// The parameter.
        name: &'static str,
        /// The value.
        value: f64,
    },
    /// A value outside the parameter's range.
    #[error("{name} = {value} {unit} is outside {min}..{max}")]
    OutOfRange {
        /// The parameter.
        name: &'static str,
        /// The value.
        value: f64,
        /// Lowest allowed.
        min: f64,
        /// Highest allowed.
        max: f64,
        /// The parameter's unit.
        unit: &'static str,
    },
    /// Per-joint values whose count is not the module's joints.
    #[error("{name}: {given} values for {joints} joints")]
    WrongCount {
        /// The parameter.
        name: &'static str,
        /// Values given.
        given: usize,
        /// The module's joints.
        joints: usize,
    },
}

/// A module's parameter values: one value per parameter and connected joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameters {
    module: &'static str,
    descriptors: &'static [ParamDescriptor],
    joints: usize,
    /// Row-major: `values[param * joints + joint]`.
    values: Vec<f64>,
}

impl Parameters {
    /// Every parameter at its default, for `joints` joints.
    pub fn new(descriptor: &ModuleDescriptor, joints: usize) -> Self {
        let values = descriptor
            .parameters
            .iter()
            .flat_map(|p| std::iter::repeat_n(p.default, joints))
            .collect();
        Parameters {
            module: descriptor.type_name,
            descriptors: descriptor.parameters,
            joints,
            values,
        }
    }

    /// Joints the values are kept for.
    pub fn joints(&self) -> usize {
        self.joints
    }

    /// The parameters' descriptions, in order.
    pub fn descriptors(&self) -> &'static [ParamDescriptor] {
        self.descriptors
    }

    /// The index of the parameter answering to `name`.
    pub fn index(&self, name: &str) -> Result<usize, ParamError> {
        self.descriptors
            .iter()
            .position(|d| d.answers_to(name))
            .ok_or_else(|| ParamError::UnknownParameter {
                module: self.module,
                name: name.to_string(),
                known: self.descriptors.iter().map(|d| d.name).collect(),
            })
    }

    /// The value of parameter `param` at `joint` (no bounds check beyond the slice's).
    #[inline]
    pub fn get(&self, param: usize, joint: usize) -> f64 {
        self.values[param * self.joints + joint]
    }

    /// Every value, row-major (`values[param * joints + joint]`).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Whether `other` holds values of the same module's parameters for as many joints.
    pub fn same_shape(&self, other: &Parameters) -> bool {
        self.module == other.module
            && self.joints == other.joints
            && self.values.len() == other.values.len()
    }

    /// All joints' values of one parameter.
    pub fn row(&self, param: usize) -> &[f64] {
        &self.values[param * self.joints..(param + 1) * self.joints]
    }

    fn check(&self, param: usize, value: f64) -> Result<(), ParamError> {
        let d = &self.descriptors[param];
        if !value.is_finite() {
            return Err(ParamError::NotFinite {
                name: d.name,
                value,
            });
        }
        if value < d.min || value > d.max {
            return Err(ParamError::OutOfRange {
                name: d.name,
                value,
                min: d.min,
                max: d.max,
                unit: d.unit,
            });
        }
        Ok(())
    }

    /// Sets one joint's value, or every joint's when `joint` is `None`.
    pub fn set(
        &mut self,
        param: usize,
        joint: Option<usize>,
        value: f64,
    ) -> Result<(), ParamError> {
        self.check(param, value)?;
        match joint {
            Some(j) if j >= self.joints => Err(ParamError::JointOutOfRange {
                joint: j,
                joints: self.joints,
            }),
            Some(j) => {
                self.values[param * self.joints + j] = value;
                Ok(())
            }
            None => {
                self.values[param * self.joints..(param + 1) * self.joints].fill(value);
                Ok(())
            }
        }
    }

    /// Sets one value per joint.
    pub fn set_all(&mut self, param: usize, values: &[f64]) -> Result<(), ParamError> {
        if values.len() != self.joints {
            return Err(ParamError::WrongCount {
                name: self.descriptors[param].name,
                given: values.len(),
                joints: self.joints,
            });
        }
        for v in values {
            self.check(param, *v)?;
        }
        self.values[param * self.joints..(param + 1) * self.joints].copy_from_slice(values);
        Ok(())
    }
}

/// A module's logged intermediate values: the latest value of each series per joint.
#[derive(Debug, Clone, PartialEq)]
pub struct InternalData {
    names: &'static [&'static str],
    joints: usize,
    values: Vec<f64>,
}

impl InternalData {
    /// Series `names`, each with one value per joint, all 0.
    pub fn new(names: &'static [&'static str], joints: usize) -> Self {
        InternalData {
            names,
            joints,
            values: vec![0.0; names.len() * joints],
        }
    }

    /// The series' names.
    pub fn names(&self) -> &'static [&'static str] {
        self.names
    }

    /// The latest values of series `series`, one per joint.
    pub fn series(&self, series: usize) -> &[f64] {
        &self.values[series * self.joints..(series + 1) * self.joints]
    }

    /// Every value, row-major (`values[series * joints + joint]`), for the owning module.
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// Mutable access for the module that owns it.
    #[inline]
    pub fn series_mut(&mut self, series: usize) -> &mut [f64] {
        &mut self.values[series * self.joints..(series + 1) * self.joints]
    }
}

/// What every module holds: its description, parameter values and logged data.
#[derive(Debug, Clone)]
pub struct ModuleCore {
    /// Type name, parameters, logged series.
    pub descriptor: ModuleDescriptor,
    /// Current parameter values.
    pub params: Parameters,
    /// Latest internal data.
    pub data: InternalData,
}

impl ModuleCore {
    /// Parameters at their defaults and zeroed data, for `joints` connected joints.
    pub fn new(descriptor: ModuleDescriptor, joints: usize) -> Self {
        ModuleCore {
            params: Parameters::new(&descriptor, joints),
            data: InternalData::new(descriptor.series, joints),
            descriptor,
        }
    }
}

/// An actuation module (thesis listing A.1).
pub trait ActuationModule: Send + Sync {
    /// The module's descriptor, parameters and logged data.
    fn core(&self) -> &ModuleCore;
    /// The module's descriptor, parameters and logged data, to change.
    fn core_mut(&mut self) -> &mut ModuleCore;
    /// Back to the start state (called before a run; `rng` is the module's own stream).
    fn reset(&mut self, rng: &mut SimRng);
    /// One angle (degrees) per connected joint into `out` (`out.len()` = joints).
    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]);
    /// A copy in the same state (for parallel evaluation).
    fn clone_box(&self) -> Box<dyn ActuationModule>;

    /// Type name, parameters, logged series.
    fn descriptor(&self) -> &ModuleDescriptor {
        &self.core().descriptor
    }
    /// Current parameter values.
    fn parameters(&self) -> &Parameters {
        &self.core().params
    }
    /// Current parameter values, to change (checked by [`Parameters`]).
    fn parameters_mut(&mut self) -> &mut Parameters {
        &mut self.core_mut().params
    }
    /// The latest value of each logged series per joint.
    fn internal_data(&self) -> &InternalData {
        &self.core().data
    }
    /// A one-off disturbance of joint `joint`'s internal state by `amount` (the module's
    /// own unit, e.g. degrees of phase), to study how the module recovers (thesis 5.2.1,
    /// `setDistortion`). Returns false when the module has no state to disturb; a
    /// constant output distortion works for every module (see
    /// [`crate::control::ControlKernel::set_distortion`]).
    fn perturb(&mut self, _joint: usize, _amount: f64) -> bool {
        false
    }
    /// Why the module stopped working, when it did (a plugin that panicked or produced a
    /// non-finite angle): it then outputs 0 for its joints until it is rebuilt.
    fn failure(&self) -> Option<&str> {
        None
    }
    /// The network the module runs (the `Policy` module), if any.
    fn network(&self) -> Option<&PolicyNet> {
        None
    }
    /// Whether the module can run on a robot of `joints` joints whose sensors read into
    /// `sensors` (sized as the robot's) with `phases` generators beside it: a `Policy`
    /// checks that its network reads the observation its switches select; other modules
    /// have nothing to check. Called before a run, so a mismatch is refused, not run.
    fn check_observation(
        &self,
        _joints: usize,
        _sensors: &SensorData,
        _phases: usize,
    ) -> Result<(), NetworkMismatch> {
        Ok(())
    }
    /// Gives the module a network to run; modules that run none refuse it.
    fn set_network(&mut self, _net: PolicyNet) -> Result<(), NetworkMismatch> {
        Err(NetworkMismatch::NotAPolicy {
            module: self.descriptor().type_name,
        })
    }
}

impl Clone for Box<dyn ActuationModule> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// Test helper: runs `module` for `steps` steps of `dt` from step `from` (joint angles 0, no
/// sensors) and returns every output.
#[cfg(test)]
pub(crate) fn drive(
    module: &mut dyn ActuationModule,
    from: usize,
    steps: usize,
    dt: f64,
) -> Vec<Vec<f64>> {
    let n = module.parameters().joints();
    let angles = vec![0.0; n];
    let sensors = SensorData::default();
    let mut out = vec![0.0; n];
    (from..from + steps)
        .map(|k| {
            let ctx = StepContext {
                time: k as f64 * dt,
                dt,
                step: k as u64,
                angles: &angles,
                robot_angles: &angles,
                sensors: &sensors,
                phases: &[],
            };
            module.compute(&ctx, &mut out);
            out.clone()
        })
        .collect()
}
