//! The environment's contact model ([`ContactModel`]) in rapier's terms, in one place: the
//! contact spring of every pair (moving or fixed) at `1 / (2 pi tau)` Hz with damping ratio
//! zeta (rapier's soft constraints are such springs), the friction combine rule, and the
//! cone (rapier's is elliptic: it caps the tangent impulse's magnitude).

use rapier3d::prelude as rp;

use crate::config::contact::{ContactModel, FrictionCombine, FrictionCone};
use crate::config::simulation::EngineKind;
use crate::sim::error::SimError;

/// rapier's spring of a contact of natural frequency `hz` and damping ratio `zeta`.
pub fn softness(hz: f64, zeta: f64) -> rp::SpringCoefficients<f32> {
    rp::SpringCoefficients::new(hz as f32, zeta as f32)
}

/// rapier's rule for combining two friction coefficients.
pub fn combine_rule(model: &ContactModel) -> rp::CoefficientCombineRule {
    match model.friction_combine {
        FrictionCombine::Min => rp::CoefficientCombineRule::Min,
        FrictionCombine::Max => rp::CoefficientCombineRule::Max,
        FrictionCombine::Mean => rp::CoefficientCombineRule::Average,
    }
}

/// Refuses what rapier cannot do: a pyramidal friction cone.
pub fn check(model: &ContactModel) -> Result<(), SimError> {
    match model.friction_cone {
        FrictionCone::Elliptic => Ok(()),
        FrictionCone::Pyramidal => Err(SimError::Unsupported {
            engine: EngineKind::Rapier,
            what: "<frictionCone>pyramidal</frictionCone>: rapier's friction cone is elliptic \
                   (it caps the tangent impulse's magnitude); use elliptic, or MuJoCo"
                .into(),
        }),
    }
}
