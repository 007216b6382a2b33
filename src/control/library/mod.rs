//! The standard actuation-module library.

pub mod adaptive_touch;
pub mod direct;
pub mod sinusoidal;

use crate::control::descriptor::ModuleDescriptor;

/// Descriptors of every standard module type.
pub fn descriptors() -> Vec<ModuleDescriptor> {
    vec![
        direct::descriptor(),
        sinusoidal::descriptor(),
        adaptive_touch::descriptor(),
    ]
}
