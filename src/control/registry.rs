//! The registry of actuation-module types: descriptors looked up by name, and factories
//! that create module instances. A registry is a value passed to whoever builds modules
//! (the loader checks files against it, the simulator and the optimizers create modules
//! from it): [`ModuleRegistry::standard`] holds the standard library, and the plugin host
//! builds one that adds the loaded plugins (`crate::plugin_host::PluginHost::registry`).

use std::fmt;
use std::sync::Arc;

use crate::config::module_types::{ModuleDescriptor, ModuleTypes};
use crate::config::xml::read::same_name;
use crate::control::library;
use crate::control::module::ActuationModule;

/// Creates a module for a number of connected joints.
pub type ModuleFactory = Arc<dyn Fn(usize) -> Box<dyn ActuationModule> + Send + Sync>;

/// A factory from a plain function.
pub fn factory(f: fn(usize) -> Box<dyn ActuationModule>) -> Option<ModuleFactory> {
    Some(Arc::new(f))
}

#[derive(Clone)]
struct Entry {
    descriptor: ModuleDescriptor,
    factory: Option<ModuleFactory>,
}

impl fmt::Debug for Entry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Entry")
            .field("descriptor", &self.descriptor.type_name)
            .field("factory", &self.factory.is_some())
            .finish()
    }
}

/// Known module types.
#[derive(Debug, Clone)]
pub struct ModuleRegistry {
    entries: Vec<Entry>,
}

/// Why a module could not be created.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CreateError {
    /// No type answers to the name.
    #[error("unknown actuation module \"{name}\"; known modules: {}", known.join(", "))]
    Unknown {
        /// The name asked for.
        name: String,
        /// The registered names.
        known: Vec<&'static str>,
    },
    /// The type is described but has no factory.
    #[error("actuation module {name} is described but has no implementation yet")]
    NotImplemented {
        /// Its name.
        name: &'static str,
    },
}

impl Default for ModuleRegistry {
    /// The standard module library (plugins are added by whoever loaded them:
    /// `crate::plugin_host::PluginHost::registry`).
    fn default() -> Self {
        ModuleRegistry::standard()
    }
}

impl ModuleTypes for ModuleRegistry {
    fn describe(&self, name: &str) -> Option<&ModuleDescriptor> {
        self.get(name)
    }

    fn type_names(&self) -> Vec<&'static str> {
        self.names()
    }
}

impl ModuleRegistry {
    /// A registry without any type.
    pub fn empty() -> Self {
        ModuleRegistry {
            entries: Vec::new(),
        }
    }

    /// The standard module library only.
    pub fn standard() -> Self {
        let mut r = ModuleRegistry::empty();
        library::register(&mut r);
        r
    }

    /// Adds a module type; a later registration under the same name replaces the earlier.
    /// `factory` is `None` for a type that configurations may name but runs cannot create.
    pub fn register(&mut self, descriptor: ModuleDescriptor, factory: Option<ModuleFactory>) {
        self.entries
            .retain(|e| !same_name(e.descriptor.type_name, descriptor.type_name));
        self.entries.push(Entry {
            descriptor,
            factory,
        });
    }

    /// The type answering to `name` (`Global Adaptive Touch` finds `Global_Adaptive_Touch`).
    pub fn get(&self, name: &str) -> Option<&ModuleDescriptor> {
        self.entry(name).map(|e| &e.descriptor)
    }

    fn entry(&self, name: &str) -> Option<&Entry> {
        self.entries
            .iter()
            .find(|e| same_name(e.descriptor.type_name, name))
    }

    /// Registered type names, in registration order.
    pub fn names(&self) -> Vec<&'static str> {
        self.entries
            .iter()
            .map(|e| e.descriptor.type_name)
            .collect()
    }

    /// A new module of type `name` for `joints` connected joints.
    pub fn create(
        &self,
        name: &str,
        joints: usize,
    ) -> Result<Box<dyn ActuationModule>, CreateError> {
        let entry = self.entry(name).ok_or_else(|| CreateError::Unknown {
            name: name.to_string(),
            known: self.names(),
        })?;
        let factory = entry.factory.as_ref().ok_or(CreateError::NotImplemented {
            name: entry.descriptor.type_name,
        })?;
        Ok(factory(joints))
    }
}
