//! The environment's contact model ([`ContactModel`]) in MuJoCo's terms, in one place:
//! `solref` (time constant, damping ratio) on every geom (MuJoCo keeps time constants of at
//! least two timesteps: below that it stiffens no further), the cone in `<option>`, and the
//! friction rule: MuJoCo takes the larger coefficient of two geoms of equal `priority` and
//! the higher-priority geom's otherwise, so `min` ranks the more slippery geom higher.

use crate::config::contact::{ContactModel, FrictionCombine, FrictionCone};
use crate::sim::engine::LINK_FRICTION;
use crate::sim::engine::mujoco::MujocoError;

/// `solref` of every geom: (time constant s, damping ratio).
pub fn solref(model: &ContactModel) -> [f64; 2] {
    [model.time_constant, model.damping_ratio]
}

/// `<option cone=...>`.
pub fn cone(model: &ContactModel) -> &'static str {
    match model.friction_cone {
        FrictionCone::Elliptic => "elliptic",
        FrictionCone::Pyramidal => "pyramidal",
    }
}

/// The `priority` of a terrain geom of friction `friction` (`terrain`) or of a link:
/// with `min`, the smaller coefficient outranks (a terrain geom below the links' friction
/// outranks them, the links outrank the others); with `max`, all are equal (MuJoCo's own
/// rule). `mean` has no MuJoCo counterpart.
pub fn priority(model: &ContactModel, terrain: Option<f64>) -> Result<u32, MujocoError> {
    match (model.friction_combine, terrain) {
        (FrictionCombine::Min, Some(f)) => Ok(if f < LINK_FRICTION { 2 } else { 0 }),
        (FrictionCombine::Min, None) => Ok(1),
        (FrictionCombine::Max, _) => Ok(0),
        (FrictionCombine::Mean, _) => Err(MujocoError::Unsupported(
            "<frictionCombine>mean</frictionCombine>: MuJoCo combines two geoms' friction by \
             the larger one or by priority (min); use min or max, or rapier"
                .into(),
        )),
    }
}
