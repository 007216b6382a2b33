//! `DirectJointAccess`: holds its joints at fixed angles (thesis listing B.5).

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::rng::SimRng;

const PARAMETERS: &[ParamDescriptor] = &[ParamDescriptor {
    name: "Angle",
    aliases: &["Position", "Desired angle"],
    unit: "deg",
    default: 0.0,
    min: -90.0,
    max: 90.0,
    help: "angle the joint is held at",
}];

/// The type's descriptor.
pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "DirectJointAccess",
        summary: "fixed joint angles",
        parameters: PARAMETERS,
        series: &["desired_angle"],
        sensing: false,
        network: false,
    }
}

/// Holds each joint at its `Angle`.
#[derive(Debug, Clone)]
pub struct DirectJointAccess {
    core: ModuleCore,
}

impl DirectJointAccess {
    /// A module for `joints` connected joints, its parameters at their defaults.
    pub fn new(joints: usize) -> Self {
        DirectJointAccess {
            core: ModuleCore::new(descriptor(), joints),
        }
    }
}

impl ActuationModule for DirectJointAccess {
    fn core(&self) -> &ModuleCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut ModuleCore {
        &mut self.core
    }

    fn reset(&mut self, _rng: &mut SimRng) {}

    fn compute(&mut self, _ctx: &StepContext, out: &mut [f64]) {
        out.copy_from_slice(self.core.params.row(0));
        self.core.data.series_mut(0).copy_from_slice(out);
    }

    fn clone_box(&self) -> Box<dyn ActuationModule> {
        Box::new(self.clone())
    }
}
