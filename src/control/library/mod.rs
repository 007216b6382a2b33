//! The standard actuation-module library, a file per module type:
//!
//! - [`sinusoidal`]: `PatternGenerator_sinusoidal`, the thesis's sine generator (eq. 3.1)
//! - [`cpg_phase`], [`cpg_matsuoka`]: phase-oscillator and Matsuoka CPGs (3.3.2)
//! - [`adaptive_touch`]: `Global_Adaptive_Touch`, the thesis's sensor-driven module (6.2)
//! - [`direct`]: `DirectJointAccess`, joints held at set angles (listing B.5; the Gymnasium
//!   environment sets them from its actions)
//! - [`learned`]: `Policy`, a learned network ([`crate::control::policy`]) as a module

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
