//! The control kernel (thesis 4.3.1, fig. 4.4, Algorithm 1): the actuation modules of one
//! robot, each driving a group of joints (groups may overlap); every step it computes each
//! module's angles and sums them joint-wise, clamped to the joint limits.
//!
//! Plain Rust with no Bevy types: the simulation holds one per robot as a component, and
//! real-robot control and the optimizers use the same object. Parameters are read and
//! changed by name between steps (GUI, gamepad, optimizers all go through
//! [`ControlKernel::set_parameter`]). Nothing is allocated per step.

use std::fmt;

use crate::config::actuation::ParamValue;
use crate::config::resolve::ActuationModel;
use crate::control::module::{ActuationModule, ParamError, StepContext};
use crate::control::policy::{NetworkMismatch, PolicyError, PolicyNet};
use crate::control::registry::{CreateError, ModuleRegistry};
use crate::rng::SimRng;
use crate::sensing::SensorData;

/// One module instance and the robot joints it drives.
#[derive(Clone)]
pub struct Actuator {
    /// The module.
    pub module: Box<dyn ActuationModule>,
    /// Robot joint indices, in the module's joint order.
    pub joints: Vec<usize>,
    /// Measured angles of those joints, gathered each step.
    angles: Vec<f64>,
    /// The module's latest output (with the distortion added).
    out: Vec<f64>,
    /// Constant distortion added to each driven joint's output (degrees).
    distortion: Vec<f64>,
    /// Whether any distortion is non-zero (skips the addition otherwise).
    distorted: bool,
}

impl Actuator {
    /// The module's latest output, one angle per driven joint.
    pub fn output(&self) -> &[f64] {
        &self.out
    }

    /// The module-local index of robot joint `joint`.
    pub fn local(&self, joint: usize) -> Option<usize> {
        self.joints.iter().position(|j| *j == joint)
    }

    /// The constant distortion per driven joint (degrees).
    pub fn distortion(&self) -> &[f64] {
        &self.distortion
    }
}

impl fmt::Debug for Actuator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Actuator")
            .field("module", &self.module.descriptor().type_name)
            .field("joints", &self.joints)
            .finish()
    }
}

/// Why a kernel could not be built or changed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KernelError {
    /// A module could not be created.
    #[error("{0}")]
    Create(#[source] CreateError),
    /// A module refused a parameter value.
    #[error("{module}: {error}")]
    Param {
        /// The module type.
        module: &'static str,
        /// Why.
        #[source]
        error: ParamError,
    },
    /// A robot joint index beyond the robot's joints.
    #[error("joint {joint} out of range: the robot has {joints} joints")]
    JointOutOfRange {
        /// The index given.
        joint: usize,
        /// The robot's joints.
        joints: usize,
    },
    /// An actuator index beyond the kernel's actuators.
    #[error("no actuator {index}: the kernel has {count}")]
    NoSuchActuator {
        /// The index given.
        index: usize,
        /// The kernel's actuators.
        count: usize,
    },
    /// The module does not drive that joint.
    #[error("module {module} does not drive joint {joint}")]
    NotDriven {
        /// The module type.
        module: &'static str,
        /// The robot joint.
        joint: usize,
    },
    /// A NaN or infinite value.
    #[error("{what} must be a finite number, got {value}")]
    NotFinite {
        /// What it was for.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A module's weights file could not be read or does not fit the module.
    #[error("{0}")]
    Policy(#[source] std::sync::Arc<PolicyError>),
    /// A module has no network to change.
    #[error("module {module} has no network (give it a weights file)")]
    NoNetwork {
        /// The module type.
        module: &'static str,
    },
    /// A module refused a network or its parameters.
    #[error("{module}: {cause}")]
    Network {
        /// The module type.
        module: &'static str,
        /// Why.
        #[source]
        cause: NetworkMismatch,
    },
    /// A module cannot run on the robot's observation (a network's inputs).
    #[error("{module} (module {number} of the actuation file): {cause}")]
    Observation {
        /// The actuator's place in the file, from 1.
        number: usize,
        /// The module type.
        module: &'static str,
        /// Why.
        #[source]
        cause: NetworkMismatch,
    },
}

/// Reads weights file `file` and gives the network to `module`.
fn load_network(
    module: &mut dyn ActuationModule,
    file: &std::path::Path,
) -> Result<(), KernelError> {
    let net = PolicyNet::read(file).map_err(|e| KernelError::Policy(e.into()))?;
    give_network(module, net, file)
}

/// Gives `net`, read from `file`, to `module`.
fn give_network(
    module: &mut dyn ActuationModule,
    net: PolicyNet,
    file: &std::path::Path,
) -> Result<(), KernelError> {
    let tensor = format!("layers.{}.weight", net.layers.len().saturating_sub(1));
    module.set_network(net).map_err(|cause| {
        KernelError::Policy(
            PolicyError::Mismatch {
                file: file.to_path_buf(),
                tensor,
                cause,
            }
            .into(),
        )
    })
}

/// Each generator's phase at its first joint (degrees) into `out`.
fn gather_phases(actuators: &[Actuator], generators: &[(usize, usize)], out: &mut [f64]) {
    for (slot, (a, series)) in out.iter_mut().zip(generators) {
        *slot = actuators
            .get(*a)
            .and_then(|a| a.module.internal_data().series(*series).first().copied())
            .unwrap_or(0.0);
    }
}

/// The control kernel of one robot.
#[derive(Debug, Clone)]
pub struct ControlKernel {
    actuators: Vec<Actuator>,
    /// Joint limits in degrees, per robot joint.
    limits: Vec<[f64; 2]>,
    /// The summed, clamped output per robot joint.
    desired: Vec<f64>,
    /// The generators: (actuator, index of its `Phase` series), in actuator order.
    generators: Vec<(usize, usize)>,
    /// Each generator's phase at its first joint (degrees), gathered before every step.
    phases: Vec<f64>,
}

impl ControlKernel {
    /// An empty kernel for a robot with these joint limits (degrees).
    pub fn new(limits: Vec<[f64; 2]>) -> Self {
        let n = limits.len();
        ControlKernel {
            actuators: Vec::new(),
            limits,
            desired: vec![0.0; n],
            generators: Vec::new(),
            phases: Vec::new(),
        }
    }

    /// Builds the kernel of an actuation file: one module per assignment, parameters set.
    pub fn from_actuation(
        model: &ActuationModel,
        registry: &ModuleRegistry,
        limits: Vec<[f64; 2]>,
    ) -> Result<Self, KernelError> {
        let mut k = ControlKernel::new(limits);
        for m in &model.modules {
            let joints: Vec<usize> = m.joints.indices().collect();
            let mut module = registry
                .create(m.descriptor.type_name, joints.len())
                .map_err(KernelError::Create)?;
            let name = module.descriptor().type_name;
            for p in &m.params {
                let params = module.parameters_mut();
                let idx = params.index(p.name).map_err(|error| KernelError::Param {
                    module: name,
                    error,
                })?;
                match &p.value {
                    ParamValue::Uniform(v) => params.set(idx, None, *v),
                    ParamValue::PerJoint(v) => params.set_all(idx, v),
                }
                .map_err(|error| KernelError::Param {
                    module: name,
                    error,
                })?;
            }
            if let Some(w) = &m.weights {
                let net = PolicyNet::from_bytes(&w.bytes, &w.path)
                    .map_err(|e| KernelError::Policy(e.into()))?;
                give_network(module.as_mut(), net, &w.path)?;
            }
            k.add(module, joints)?;
        }
        Ok(k)
    }

    /// Reads weights file `file` into the network of actuator `index` (a `Policy`).
    pub fn load_network(
        &mut self,
        index: usize,
        file: &std::path::Path,
    ) -> Result<(), KernelError> {
        let a = self.actuator_mut(index)?;
        load_network(a.module.as_mut(), file)
    }

    /// Sets the flat parameters (see [`PolicyNet::parameters`]) of actuator `index`'s
    /// network.
    pub fn set_network_parameters(
        &mut self,
        index: usize,
        values: &[f64],
    ) -> Result<(), KernelError> {
        let a = self.actuator_mut(index)?;
        let module = a.module.descriptor().type_name;
        let mut net = a
            .module
            .network()
            .cloned()
            .ok_or(KernelError::NoNetwork { module })?;
        let refused = |cause| KernelError::Network { module, cause };
        net.set_parameters(values).map_err(refused)?;
        a.module.set_network(net).map_err(refused)
    }

    /// Adds a module driving `joints` (robot joint indices); returns its actuator index.
    pub fn add(
        &mut self,
        module: Box<dyn ActuationModule>,
        joints: Vec<usize>,
    ) -> Result<usize, KernelError> {
        if let Some(j) = joints.iter().find(|j| **j >= self.limits.len()) {
            return Err(KernelError::JointOutOfRange {
                joint: *j,
                joints: self.limits.len(),
            });
        }
        let n = joints.len();
        self.actuators.push(Actuator {
            module,
            joints,
            angles: vec![0.0; n],
            out: vec![0.0; n],
            distortion: vec![0.0; n],
            distorted: false,
        });
        let index = self.actuators.len() - 1;
        if let Some(series) = self.actuators[index]
            .module
            .internal_data()
            .names()
            .iter()
            .position(|n| *n == "Phase")
        {
            self.generators.push((index, series));
            self.phases.push(0.0);
        }
        Ok(index)
    }

    /// The generators whose phases modules and observations see: (actuator, index of its
    /// `Phase` series), in actuator order.
    pub fn generators(&self) -> &[(usize, usize)] {
        &self.generators
    }

    /// Each generator's current phase at its first joint (degrees) into `out` (one per
    /// [`ControlKernel::generators`]).
    pub fn phases_into(&self, out: &mut [f64]) {
        gather_phases(&self.actuators, &self.generators, out);
    }

    /// The kernel's actuators, in actuation-file order.
    pub fn actuators(&self) -> &[Actuator] {
        &self.actuators
    }

    /// Every actuator's parameter values (a copy), in actuator order.
    pub fn parameter_values(&self) -> Vec<crate::control::module::Parameters> {
        self.actuators
            .iter()
            .map(|a| a.module.parameters().clone())
            .collect()
    }

    /// Puts parameter values taken with [`ControlKernel::parameter_values`] back, for the
    /// actuators whose module and joints still match (the modules' own state stays);
    /// returns how many actuators took them.
    pub fn restore_parameter_values(
        &mut self,
        values: &[crate::control::module::Parameters],
    ) -> usize {
        let mut restored = 0;
        for (a, v) in self.actuators.iter_mut().zip(values) {
            let p = a.module.parameters_mut();
            if p.same_shape(v) {
                *p = v.clone();
                restored += 1;
            }
        }
        restored
    }

    /// Modules that stopped working (a plugin that panicked): type name and cause.
    pub fn failures(&self) -> impl Iterator<Item = (&'static str, &str)> {
        self.actuators.iter().filter_map(|a| {
            a.module
                .failure()
                .map(|f| (a.module.descriptor().type_name, f))
        })
    }

    /// Checks every module against the robot's observation before a run: `sensors` sized
    /// as the robot's sensors ([`crate::control::ActuationModule::check_observation`]).
    pub fn check_observation(&self, sensors: &SensorData) -> Result<(), KernelError> {
        let phases = self.generators.len();
        for (index, a) in self.actuators.iter().enumerate() {
            a.module
                .check_observation(self.joints(), sensors, phases)
                .map_err(|cause| KernelError::Observation {
                    number: index + 1,
                    module: a.module.descriptor().type_name,
                    cause,
                })?;
        }
        Ok(())
    }

    /// Number of robot joints.
    pub fn joints(&self) -> usize {
        self.limits.len()
    }

    /// Each robot joint's limits (degrees).
    pub fn limits(&self) -> &[[f64; 2]] {
        &self.limits
    }

    /// An empty kernel for the same robot (its joint limits): where a policy replaces the
    /// file's modules.
    pub fn emptied(&self) -> ControlKernel {
        ControlKernel::new(self.limits.clone())
    }

    /// The first actuator whose module type answers to `type_name`.
    pub fn find(&self, type_name: &str) -> Option<usize> {
        self.actuators.iter().position(|a| {
            crate::config::xml::read::same_name(a.module.descriptor().type_name, type_name)
        })
    }

    /// Resets every module; module `i` draws from its own stream of `rng`.
    pub fn reset(&mut self, rng: &mut SimRng) {
        for (i, a) in self.actuators.iter_mut().enumerate() {
            let mut stream = rng.fork(i as u64);
            a.module.reset(&mut stream);
            a.out.fill(0.0);
        }
        self.desired.fill(0.0);
    }

    /// Algorithm 1 for a robot without sensors: every module computes, outputs are summed
    /// per joint and clamped to the joint limits. `measured` holds the current angle
    /// (degrees) of every robot joint.
    pub fn compute(&mut self, time: f64, dt: f64, step: u64, measured: &[f64]) -> &[f64] {
        self.compute_modules(time, dt, step, measured, &SensorData::default());
        self.sum()
    }

    /// The first half of [`ControlKernel::compute`]: every module computes its output.
    pub fn compute_modules(
        &mut self,
        time: f64,
        dt: f64,
        step: u64,
        measured: &[f64],
        sensors: &SensorData,
    ) {
        gather_phases(&self.actuators, &self.generators, &mut self.phases);
        for a in &mut self.actuators {
            for (slot, j) in a.angles.iter_mut().zip(&a.joints) {
                *slot = measured.get(*j).copied().unwrap_or(0.0);
            }
            let ctx = StepContext {
                time,
                dt,
                step,
                angles: &a.angles,
                robot_angles: measured,
                sensors,
                phases: &self.phases,
            };
            a.module.compute(&ctx, &mut a.out);
            if a.distorted {
                for (o, d) in a.out.iter_mut().zip(&a.distortion) {
                    *o += d;
                }
            }
        }
    }

    /// The second half: the outputs summed per joint, clamped to the joint limits.
    pub fn sum(&mut self) -> &[f64] {
        self.desired.fill(0.0);
        for a in &self.actuators {
            for (v, j) in a.out.iter().zip(&a.joints) {
                self.desired[*j] += v;
            }
        }
        for (d, [lo, hi]) in self.desired.iter_mut().zip(&self.limits) {
            *d = d.clamp(*lo, *hi);
        }
        &self.desired
    }

    /// The latest summed output per robot joint (degrees).
    pub fn desired(&self) -> &[f64] {
        &self.desired
    }

    fn actuator_mut(&mut self, index: usize) -> Result<&mut Actuator, KernelError> {
        let count = self.actuators.len();
        self.actuators
            .get_mut(index)
            .ok_or(KernelError::NoSuchActuator { index, count })
    }

    fn finite(what: &'static str, value: f64) -> Result<f64, KernelError> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(KernelError::NotFinite { what, value })
        }
    }

    fn actuator(&self, index: usize) -> Result<&Actuator, KernelError> {
        self.actuators
            .get(index)
            .ok_or(KernelError::NoSuchActuator {
                index,
                count: self.actuators.len(),
            })
    }

    /// The local joint index of robot joint `joint` in actuator `a`, if given.
    fn local_joint(a: &Actuator, joint: Option<usize>) -> Result<Option<usize>, KernelError> {
        joint
            .map(|j| {
                a.local(j).ok_or(KernelError::NotDriven {
                    module: a.module.descriptor().type_name,
                    joint: j,
                })
            })
            .transpose()
    }

    /// Reads parameter `name` of actuator `index` at robot joint `joint` (the first driven
    /// joint when `None`).
    pub fn parameter(
        &self,
        index: usize,
        name: &str,
        joint: Option<usize>,
    ) -> Result<f64, KernelError> {
        let a = self.actuator(index)?;
        let module = a.module.descriptor().type_name;
        let p = a.module.parameters();
        let idx = p
            .index(name)
            .map_err(|error| KernelError::Param { module, error })?;
        let local = Self::local_joint(a, joint)?.unwrap_or(0);
        if local >= p.joints() {
            return Err(KernelError::NotDriven {
                module,
                joint: joint.unwrap_or(0),
            });
        }
        Ok(p.get(idx, local))
    }

    /// Changes parameter `name` of actuator `index` at robot joint `joint`, or at every
    /// joint it drives when `None`. Takes effect at the next step.
    pub fn set_parameter(
        &mut self,
        index: usize,
        name: &str,
        joint: Option<usize>,
        value: f64,
    ) -> Result<(), KernelError> {
        self.change_parameter(index, name, joint, |p, idx, local| p.set(idx, local, value))
    }

    /// Sets parameter `name` of actuator `index` to one value per driven joint, in the
    /// module's joint order (checked like [`ControlKernel::set_parameter`]; nothing is
    /// allocated): a policy's targets every control period.
    pub fn set_parameter_values(
        &mut self,
        index: usize,
        name: &str,
        values: &[f64],
    ) -> Result<(), KernelError> {
        self.change_parameter(index, name, None, |p, idx, _| p.set_all(idx, values))
    }

    /// Finds parameter `name` of actuator `index` (and robot joint `joint` among its
    /// joints) and hands its values, its index and the joint's local index to `change`.
    fn change_parameter(
        &mut self,
        index: usize,
        name: &str,
        joint: Option<usize>,
        change: impl FnOnce(
            &mut crate::control::module::Parameters,
            usize,
            Option<usize>,
        ) -> Result<(), ParamError>,
    ) -> Result<(), KernelError> {
        let a = self.actuator_mut(index)?;
        let local = Self::local_joint(a, joint)?;
        let module = a.module.descriptor().type_name;
        let p = a.module.parameters_mut();
        let idx = p
            .index(name)
            .map_err(|error| KernelError::Param { module, error })?;
        change(p, idx, local).map_err(|error| KernelError::Param { module, error })
    }

    /// Adds a constant `degrees` to actuator `index`'s output at robot joint `joint`, or at
    /// every joint it drives when `None`, from the next step on (thesis 4.5.2, the
    /// distortion frame); 0 removes it. The module's own state is untouched.
    pub fn set_distortion(
        &mut self,
        index: usize,
        joint: Option<usize>,
        degrees: f64,
    ) -> Result<(), KernelError> {
        let degrees = Self::finite("distortion", degrees)?;
        let a = self.actuator_mut(index)?;
        match Self::local_joint(a, joint)? {
            Some(l) => a.distortion[l] = degrees,
            None => a.distortion.fill(degrees),
        }
        a.distorted = a.distortion.iter().any(|d| *d != 0.0);
        Ok(())
    }

    /// Disturbs the internal state of actuator `index` at robot joint `joint` once by
    /// `amount` (see [`ActuationModule::perturb`]); returns whether the module has such
    /// state.
    pub fn perturb(
        &mut self,
        index: usize,
        joint: usize,
        amount: f64,
    ) -> Result<bool, KernelError> {
        let amount = Self::finite("perturbation", amount)?;
        let a = self.actuator_mut(index)?;
        let local = Self::local_joint(a, Some(joint))?.unwrap_or(0);
        Ok(a.module.perturb(local, amount))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kernel() -> ControlKernel {
        let r = ModuleRegistry::default();
        let mut k = ControlKernel::new(vec![[-90.0, 90.0]; 3]);
        let mut direct = r.create("DirectJointAccess", 2).unwrap();
        direct.parameters_mut().set(0, None, 10.0).unwrap();
        k.add(direct, vec![0, 1]).unwrap();
        let mut direct2 = r.create("DirectJointAccess", 2).unwrap();
        direct2.parameters_mut().set(0, None, 85.0).unwrap();
        k.add(direct2, vec![1, 2]).unwrap();
        k
    }

    #[test]
    fn overlapping_groups_sum_and_clamp() {
        let mut k = kernel();
        let out = k.compute(0.0, 0.001, 0, &[0.0; 3]).to_vec();
        assert_eq!(
            out,
            [10.0, 90.0, 85.0],
            "joint 1 gets 10 + 85, clamped to 90"
        );
    }

    #[test]
    fn parameters_by_name_between_steps() {
        let mut k = kernel();
        k.set_parameter(0, "Angle", Some(1), -20.0).unwrap();
        assert_eq!(k.parameter(0, "angle", Some(1)).unwrap(), -20.0);
        assert_eq!(k.parameter(0, "Angle", Some(0)).unwrap(), 10.0);
        assert_eq!(k.compute(0.0, 0.001, 0, &[0.0; 3]), [10.0, 65.0, 85.0]);
        assert!(matches!(
            k.set_parameter(0, "Angle", Some(2), 1.0),
            Err(KernelError::NotDriven { joint: 2, .. })
        ));
        assert!(matches!(
            k.set_parameter(0, "Angel", None, 1.0),
            Err(KernelError::Param { .. })
        ));
        assert!(matches!(
            k.set_parameter(0, "Angle", None, f64::NAN),
            Err(KernelError::Param { .. })
        ));
        assert!(matches!(
            k.set_parameter(5, "Angle", None, 1.0),
            Err(KernelError::NoSuchActuator { .. })
        ));
        assert_eq!(k.find("directjointaccess"), Some(0));
    }

    #[test]
    fn a_constant_distortion_is_added_until_removed() {
        let mut k = kernel();
        k.set_distortion(0, Some(0), -4.0).unwrap();
        assert_eq!(k.compute(0.0, 0.001, 0, &[0.0; 3]), [6.0, 90.0, 85.0]);
        assert_eq!(k.actuators()[0].distortion(), [-4.0, 0.0]);
        k.set_distortion(1, None, -10.0).unwrap();
        assert_eq!(k.compute(0.0, 0.001, 1, &[0.0; 3]), [6.0, 85.0, 75.0]);
        k.set_distortion(0, None, 0.0).unwrap();
        k.set_distortion(1, None, 0.0).unwrap();
        assert_eq!(k.compute(0.0, 0.001, 2, &[0.0; 3]), [10.0, 90.0, 85.0]);
        assert!(matches!(
            k.set_distortion(0, None, f64::INFINITY),
            Err(KernelError::NotFinite { .. })
        ));
        assert!(matches!(
            k.set_distortion(0, Some(2), 1.0),
            Err(KernelError::NotDriven { joint: 2, .. })
        ));
        // Direct joint access has no state to disturb; a phase oscillator has.
        assert_eq!(k.perturb(0, 1, 5.0), Ok(false));
        let mut k = ControlKernel::new(vec![[-90.0, 90.0]; 3]);
        let sine = ModuleRegistry::default()
            .create("PatternGenerator_sinusoidal", 3)
            .unwrap();
        k.add(sine, vec![0, 1, 2]).unwrap();
        let before = k.compute(0.0, 0.001, 0, &[0.0; 3]).to_vec();
        let mut other = k.clone();
        assert_eq!(k.perturb(0, 2, 90.0), Ok(true));
        let kicked = k.compute(0.001, 0.001, 1, &[0.0; 3]).to_vec();
        let plain = other.compute(0.001, 0.001, 1, &[0.0; 3]).to_vec();
        assert_eq!(kicked[..2], plain[..2]);
        assert!(
            (kicked[2] - plain[2]).abs() > 1.0,
            "{before:?} {kicked:?} {plain:?}"
        );
    }

    #[test]
    fn out_of_range_joint_is_refused() {
        let r = ModuleRegistry::default();
        let mut k = ControlKernel::new(vec![[-90.0, 90.0]; 2]);
        let m = r.create("DirectJointAccess", 1).unwrap();
        assert!(matches!(
            k.add(m, vec![2]),
            Err(KernelError::JointOutOfRange { .. })
        ));
        let mut described_only = ModuleRegistry::empty();
        described_only.register(crate::control::library::direct::descriptor(), None);
        assert!(matches!(
            described_only.create("DirectJointAccess", 5),
            Err(CreateError::NotImplemented { .. })
        ));
        assert!(matches!(
            r.create("Nope", 5),
            Err(CreateError::Unknown { .. })
        ));
    }
}
