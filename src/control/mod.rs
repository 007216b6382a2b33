//! The control kernel: the actuation-module interface, module descriptors, the registry
//! of module types, the standard module library, and the joint-wise summation of module
//! outputs (thesis 4.3.1, Algorithm 1).
//!
//! - [`module`]: the actuation-module interface (thesis 5.2, listing A.1)
//! - [`pattern`]: what every pattern generator shares (listing A.2)
//! - [`registry`]: the module types a configuration may name (standard and plugins)
//! - [`library`]: the standard module library
//! - [`kernel`]: the kernel that runs a robot's modules and sums their outputs per joint
//! - [`load`]: loading a configuration against a registry
//! - [`policy`]: a learned policy's network (weights, layers, its file)
//! - [`observation`]: what a policy observes of its robot, in a fixed layout

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
