//! The standard actuation-module library.

pub mod adaptive_touch;
pub mod cpg_matsuoka;
pub mod cpg_phase;
pub mod direct;
pub mod learned;
pub mod sinusoidal;

use crate::control::registry::{ModuleRegistry, factory};

/// Registers every standard module type.
pub fn register(r: &mut ModuleRegistry) {
    r.register(
        direct::descriptor(),
        factory(|n| Box::new(direct::DirectJointAccess::new(n))),
    );
    r.register(
        sinusoidal::descriptor(),
        factory(|n| Box::new(sinusoidal::Sinusoidal::new(n))),
    );
    r.register(
        adaptive_touch::descriptor(),
        factory(|n| Box::new(adaptive_touch::AdaptiveTouch::new(n))),
    );
    r.register(
        cpg_phase::descriptor(),
        factory(|n| Box::new(cpg_phase::CpgPhase::new(n))),
    );
    r.register(
        cpg_matsuoka::descriptor(),
        factory(|n| Box::new(cpg_matsuoka::CpgMatsuoka::new(n))),
    );
    r.register(
        learned::descriptor(),
        factory(|n| Box::new(learned::Policy::new(n))),
    );
}
