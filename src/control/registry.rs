//! The registry of actuation-module types, looked up by name. The standard library
//! registers into it; runtime-loaded plugins will too.

use crate::config::xml::read::same_name;
use crate::control::descriptor::ModuleDescriptor;
use crate::control::library;

/// Known module types.
#[derive(Debug, Clone)]
pub struct ModuleRegistry {
    descriptors: Vec<ModuleDescriptor>,
}

impl Default for ModuleRegistry {
    /// The registry with the standard module library.
    fn default() -> Self {
        let mut r = ModuleRegistry::empty();
        for d in library::descriptors() {
            r.register(d);
        }
        r
    }
}

impl ModuleRegistry {
    pub fn empty() -> Self {
        ModuleRegistry {
            descriptors: Vec::new(),
        }
    }

    /// Adds a module type; a later registration under the same name replaces the earlier.
    pub fn register(&mut self, d: ModuleDescriptor) {
        self.descriptors
            .retain(|o| !same_name(o.type_name, d.type_name));
        self.descriptors.push(d);
    }

    /// The type answering to `name` (`Global Adaptive Touch` finds `Global_Adaptive_Touch`).
    pub fn get(&self, name: &str) -> Option<&ModuleDescriptor> {
        self.descriptors
            .iter()
            .find(|d| same_name(d.type_name, name))
    }

    /// Registered type names, in registration order.
    pub fn names(&self) -> Vec<&'static str> {
        self.descriptors.iter().map(|d| d.type_name).collect()
    }
}
