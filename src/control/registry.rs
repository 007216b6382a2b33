//! The registry of actuation-module types: descriptors looked up by name, and factories
//! that create module instances. The standard library registers into it; runtime-loaded
//! plugins will too.

use std::fmt;

use crate::config::xml::read::same_name;
use crate::control::descriptor::ModuleDescriptor;
use crate::control::library;
use crate::control::module::ActuationModule;

/// Creates a module for a number of connected joints.
pub type ModuleFactory = fn(joints: usize) -> Box<dyn ActuationModule>;

#[derive(Debug, Clone)]
struct Entry {
    descriptor: ModuleDescriptor,
    factory: Option<ModuleFactory>,
}

/// Known module types.
#[derive(Debug, Clone)]
pub struct ModuleRegistry {
    entries: Vec<Entry>,
}

/// Why a module could not be created.
#[derive(Debug, Clone, PartialEq)]
pub enum CreateError {
    Unknown {
        name: String,
        known: Vec<&'static str>,
    },
    NotImplemented {
        name: &'static str,
    },
}

impl fmt::Display for CreateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CreateError::Unknown { name, known } => {
                write!(
                    f,
                    "unknown actuation module \"{name}\"; known modules: {}",
                    known.join(", ")
                )
            }
            CreateError::NotImplemented { name } => {
                write!(
                    f,
                    "actuation module {name} is described but has no implementation yet"
                )
            }
        }
    }
}

impl std::error::Error for CreateError {}

impl Default for ModuleRegistry {
    /// The registry with the standard module library.
    fn default() -> Self {
        let mut r = ModuleRegistry::empty();
        library::register(&mut r);
        r
    }
}

impl ModuleRegistry {
    pub fn empty() -> Self {
        ModuleRegistry {
            entries: Vec::new(),
        }
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
        let factory = entry.factory.ok_or(CreateError::NotImplemented {
            name: entry.descriptor.type_name,
        })?;
        Ok(factory(joints))
    }
}
