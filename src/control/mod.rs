//! The control kernel: the actuation-module interface, module descriptors, the registry
//! of module types, the standard module library, and the joint-wise summation of module
//! outputs (thesis 4.3.1, Algorithm 1).

pub mod kernel;
pub mod library;
pub mod load;
pub mod module;
pub mod observation;
pub mod pattern;
pub mod policy;
pub mod registry;

pub use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
pub use kernel::{Actuator, ControlKernel};
pub use load::{load_simulation, load_simulation_in};
pub use module::{ActuationModule, InternalData, ModuleCore, ParamError, Parameters, StepContext};
pub use registry::{CreateError, ModuleRegistry};
