//! Descriptions of actuation-module types as configurations see them: their parameters
//! (with units, defaults and ranges) and the internal data series they log, and
//! [`ModuleTypes`], the lookup the loader checks actuation and optimizer files against.
//! Plain data: the types themselves (factories, the standard library, plugins) live in
//! `crate::control`, whose registry implements [`ModuleTypes`].

use crate::config::xml::read::same_name;

/// One parameter of a module type.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamDescriptor {
    /// Canonical name, as shown in the GUI and written to files.
    pub name: &'static str,
    /// Other names files may use (the thesis wrote some parameters differently).
    pub aliases: &'static [&'static str],
    /// Unit, for the GUI and messages.
    pub unit: &'static str,
    /// Initial value.
    pub default: f64,
    /// Lowest allowed value.
    pub min: f64,
    /// Highest allowed value.
    pub max: f64,
    /// What it does, for tooltips.
    pub help: &'static str,
}

impl ParamDescriptor {
    /// Whether `name` refers to this parameter (case, spaces, `_`, `-` ignored; aliases too).
    pub fn answers_to(&self, name: &str) -> bool {
        same_name(self.name, name) || self.aliases.iter().any(|a| same_name(a, name))
    }
}

/// The description of a module type.
#[derive(Debug, Clone, PartialEq)]
pub struct ModuleDescriptor {
    /// Registry name (as in actuation files).
    pub type_name: &'static str,
    /// What the module does, in a line.
    pub summary: &'static str,
    /// Its parameters, in order.
    pub parameters: &'static [ParamDescriptor],
    /// Names of the internal data series logged per joint.
    pub series: &'static [&'static str],
    /// Whether the module reads sensors.
    pub sensing: bool,
    /// Whether the module runs a network from a weights file, whose weights an optimizer
    /// searches as the pseudo-parameter [`NETWORK_WEIGHTS`] (one gene per weight).
    pub network: bool,
}

/// The pseudo-parameter an optimizer file registers to search a network's weights and
/// biases: one gene per value, in the network's order (layer by layer, weights then bias).
pub const NETWORK_WEIGHTS: ParamDescriptor = ParamDescriptor {
    name: "Weights",
    aliases: &["Network_Weights"],
    unit: "",
    default: 0.0,
    min: -1.0e6,
    max: 1.0e6,
    help: "the network's weights and biases (searched by an optimizer, one gene each)",
};

impl ModuleDescriptor {
    /// The parameter answering to `name`.
    pub fn parameter(&self, name: &str) -> Option<&ParamDescriptor> {
        self.parameters.iter().find(|p| p.answers_to(name))
    }

    /// Canonical parameter names, for messages.
    pub fn parameter_names(&self) -> Vec<&'static str> {
        self.parameters.iter().map(|p| p.name).collect()
    }
}

/// The module types a configuration may name (the loader's view of a module registry).
pub trait ModuleTypes {
    /// The type answering to `name` (case, spaces, `_` and `-` ignored).
    fn describe(&self, name: &str) -> Option<&ModuleDescriptor>;
    /// Every type name, for messages.
    fn type_names(&self) -> Vec<&'static str>;
}
