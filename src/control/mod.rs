//! The control kernel's vocabulary: module descriptors, the registry of module types,
//! and the standard module library.

pub mod descriptor;
pub mod library;
pub mod registry;

pub use descriptor::{ModuleDescriptor, ParamDescriptor};
pub use registry::ModuleRegistry;
