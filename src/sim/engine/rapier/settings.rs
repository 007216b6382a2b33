//! The physics engine's settings for a robot: how finely rapier integrates (substeps, physics
//! steps per simulation step) and its length-dependent tolerances, scaled to the robot's
//! module size rather than rapier's human-sized defaults. Production runs derive them from
//! the robot ([`PhysicsSettings::production_for`]); the convergence check (`proleg bench
//! --convergence`) and the lever measurements override them ([`PhysicsSettings::parse_overrides`]).
//! Each setting's measured effect on speed and accuracy is in docs/MEASUREMENTS.md.

use rapier3d::prelude as rp;

use crate::config::Simulation;
use crate::config::contact::{DEFAULT_CONTACT_DAMPING, DEFAULT_CONTACT_HZ};
use crate::config::environment::Articulation;
use crate::config::resolve::robot::geom_volume;
use crate::sim::engine::rapier::contact::softness;

/// How rapier integrates one simulation step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicsSettings {
    /// rapier's `num_solver_iterations`: solver substeps per physics step.
    pub substeps: usize,
    /// Physics steps per simulation step (the control kernel, sensors and servos run once per
    /// simulation step); more than 1 only for converged references.
    pub steps_per_step: u32,
    /// rapier's `length_unit` (m): scales its tolerances (allowed penetration, speculative
    /// prediction distance, contact recycling distance).
    pub length_unit: f64,
    /// Warm-start joint impulses from the previous step.
    pub warmstart_joints: bool,
    /// Reuse contacts of pairs that moved less than the recycling distance.
    pub contact_recycling: bool,
    /// One Coulomb friction constraint per contact point instead of rapier's simplified
    /// (one per manifold plus twist) model.
    pub coulomb_friction: bool,
    /// rapier's `num_internal_pgs_iterations`: solver iterations per substep.
    pub pgs_iterations: usize,
    /// Natural frequency of every contact's spring (Hz): the environment's contact time
    /// constant converted ([`super::contact`]).
    pub contact_hz: f64,
    /// Damping ratio of every contact's spring: the environment's.
    pub contact_damping: f64,
    /// The floor box as a half-space ([`super::terrain`]); measured slower than the
    /// box, so off in production.
    pub halfspace_floor: bool,
    /// The robot's hinges as rapier multibody (reduced-coordinate) joints instead of
    /// impulse joints: the environment's `<articulation>reduced</articulation>`
    /// ([`Articulation`]), which `proleg import` chooses for robots whose light links under
    /// strong servos shake apart as impulse joints; off by default.
    pub multibody_joints: bool,
}

/// Production substeps: measured against the converged reference (docs/MEASUREMENTS.md).
pub const PRODUCTION_SUBSTEPS: usize = 4;
/// Production solver iterations per substep: the second halves the displacement error of
/// the reference scenario for 5 % more instructions per step (docs/MEASUREMENTS.md).
pub const PRODUCTION_PGS_ITERATIONS: usize = 2;
/// A `--physics key=value,...` override that cannot be applied.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SettingsError {
    /// An item without `=`.
    #[error("physics setting `{item}`: expected key=value")]
    NotKeyValue {
        /// The item as written.
        item: String,
    },
    /// A key that is not a setting.
    #[error("unknown physics setting `{key}` (known: {})", OVERRIDE_KEYS.join(", "))]
    UnknownKey {
        /// The key as written.
        key: String,
    },
    /// A value of the wrong kind.
    #[error("physics setting `{key}`: `{value}` is not {expected}")]
    BadValue {
        /// The setting.
        key: String,
        /// The value as written.
        value: String,
        /// What it must be.
        expected: &'static str,
    },
}

/// The keys `--physics key=value,...` knows: the fields' names.
pub const OVERRIDE_KEYS: [&str; 11] = [
    "substeps",
    "steps_per_step",
    "length_unit",
    "warmstart_joints",
    "contact_recycling",
    "coulomb_friction",
    "pgs_iterations",
    "contact_hz",
    "contact_damping",
    "halfspace_floor",
    "multibody_joints",
];
/// rapier's tolerances are tuned for objects of about this size (m).
pub const RAPIER_REFERENCE_SIZE: f64 = 1.0;

/// Solver substeps of every rung of the reference ladder ([`PhysicsSettings::reference`]).
pub const REFERENCE_SUBSTEPS: usize = 8;

impl PhysicsSettings {
    /// rapier's own defaults, one physics step per simulation step, with the default
    /// contact model's spring ([`crate::config::contact::ContactModel::default`]); not
    /// what a run uses ([`PhysicsSettings::production_for`]).
    pub fn rapier_defaults() -> Self {
        PhysicsSettings {
            substeps: 4,
            steps_per_step: 1,
            length_unit: 1.0,
            warmstart_joints: false,
            contact_recycling: true,
            coulomb_friction: false,
            pgs_iterations: 1,
            contact_hz: DEFAULT_CONTACT_HZ,
            contact_damping: DEFAULT_CONTACT_DAMPING,
            halfspace_floor: false,
            multibody_joints: false,
        }
    }

    /// The production settings for `sim`'s robot: tolerances scaled to its module size,
    /// contacts and joints as its environment states them.
    pub fn production_for(sim: &Simulation) -> Self {
        let physics = &sim.environment.physics;
        let contact = physics.contact_model();
        PhysicsSettings {
            substeps: PRODUCTION_SUBSTEPS,
            pgs_iterations: PRODUCTION_PGS_ITERATIONS,
            contact_hz: contact.natural_frequency_hz(),
            contact_damping: contact.damping_ratio,
            multibody_joints: physics.articulation == Articulation::Reduced,
            ..PhysicsSettings::rapier_defaults()
        }
        .scaled_to(module_size(sim))
    }

    /// The same settings with rapier's tolerances scaled from its reference object size
    /// ([`RAPIER_REFERENCE_SIZE`]) to modules of `size` metres.
    pub fn scaled_to(self, size: f64) -> Self {
        PhysicsSettings {
            length_unit: size / RAPIER_REFERENCE_SIZE,
            ..self
        }
    }

    /// The first rung of rapier's reference ladder for these production settings: two
    /// physics steps per simulation step, [`REFERENCE_SUBSTEPS`] substeps each, exact
    /// friction, fresh contacts, rapier's widest tolerances (`length_unit` 1 m: speculative
    /// contacts from 2 cm). Only the model (contact stiffness, the floor's shape) is the
    /// production's.
    pub fn reference(self) -> Self {
        PhysicsSettings {
            substeps: REFERENCE_SUBSTEPS.max(self.substeps),
            steps_per_step: self.steps_per_step * 2,
            length_unit: 1.0,
            warmstart_joints: true,
            contact_recycling: false,
            coulomb_friction: true,
            pgs_iterations: self.pgs_iterations.max(1),
            ..self
        }
    }

    /// A refinement of these settings: `factor` times as many physics steps per simulation
    /// step, each as many substeps (a converged reference's ladder).
    pub fn refined(self, factor: u32) -> Self {
        PhysicsSettings {
            steps_per_step: self.steps_per_step * factor,
            ..self
        }
    }

    /// Applies `key=value` overrides separated by commas (`substeps=2,length_unit=0.05`);
    /// keys are the field names ([`OVERRIDE_KEYS`]), booleans `true`/`false`/`1`/`0`.
    pub fn parse_overrides(mut self, text: &str) -> Result<Self, SettingsError> {
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (key, value) = item
                .split_once('=')
                .ok_or_else(|| SettingsError::NotKeyValue {
                    item: item.to_string(),
                })?;
            let (key, value) = (key.trim(), value.trim());
            let bad = |expected: &'static str| SettingsError::BadValue {
                key: key.to_string(),
                value: value.to_string(),
                expected,
            };
            let count = || {
                (value.parse::<u32>().ok().filter(|n| *n > 0))
                    .ok_or_else(|| bad("a positive integer"))
            };
            let real = |what: &'static str| {
                (value
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite() && *v > 0.0))
                .ok_or_else(|| bad(what))
            };
            let flag = || match value {
                "1" | "true" => Ok(true),
                "0" | "false" => Ok(false),
                _ => Err(bad("true or false")),
            };
            match key {
                "substeps" => self.substeps = count()? as usize,
                "steps_per_step" => self.steps_per_step = count()?,
                "pgs_iterations" => self.pgs_iterations = count()? as usize,
                "length_unit" => self.length_unit = real("a positive length in metres")?,
                "contact_hz" => self.contact_hz = real("a positive frequency in Hz")?,
                "contact_damping" => self.contact_damping = real("a positive damping ratio")?,
                "warmstart_joints" => self.warmstart_joints = flag()?,
                "contact_recycling" => self.contact_recycling = flag()?,
                "coulomb_friction" => self.coulomb_friction = flag()?,
                "halfspace_floor" => self.halfspace_floor = flag()?,
                "multibody_joints" => self.multibody_joints = flag()?,
                _ => {
                    return Err(SettingsError::UnknownKey {
                        key: key.to_string(),
                    });
                }
            }
        }
        Ok(self)
    }

    /// The production settings of `sim`'s robot with `overrides` applied (see
    /// [`PhysicsSettings::parse_overrides`]).
    pub fn production_with(sim: &Simulation, overrides: &str) -> Result<Self, SettingsError> {
        PhysicsSettings::production_for(sim).parse_overrides(overrides)
    }

    /// rapier's integration parameters for a simulation step of `dt` seconds.
    pub fn integration_parameters(&self, dt: f64) -> rp::IntegrationParameters {
        rp::IntegrationParameters {
            dt: (dt / self.steps_per_step as f64) as f32,
            num_solver_iterations: self.substeps,
            length_unit: self.length_unit as f32,
            warmstart_joints: self.warmstart_joints,
            contact_recycling: self.contact_recycling,
            num_internal_pgs_iterations: self.pgs_iterations,
            contact_softness: softness(self.contact_hz, self.contact_damping),
            static_contact_softness: softness(self.contact_hz, self.contact_damping),
            friction_model: if self.coulomb_friction {
                rp::FrictionModel::Coulomb
            } else {
                rp::FrictionModel::Simplified
            },
            ..rp::IntegrationParameters::default()
        }
    }
}

impl std::fmt::Display for PhysicsSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "substeps={},steps_per_step={},length_unit={},warmstart_joints={},contact_recycling={},coulomb_friction={},pgs_iterations={},contact_hz={},contact_damping={},halfspace_floor={},multibody_joints={}",
            self.substeps,
            self.steps_per_step,
            self.length_unit,
            self.warmstart_joints,
            self.contact_recycling,
            self.coulomb_friction,
            self.pgs_iterations,
            self.contact_hz,
            self.contact_damping,
            self.halfspace_floor,
            self.multibody_joints
        )
    }
}

/// The robot's module size (m): the cube root of its links' mean volume.
pub fn module_size(sim: &Simulation) -> f64 {
    let links = &sim.robot.links;
    if links.is_empty() {
        return RAPIER_REFERENCE_SIZE;
    }
    let volume: f64 = links
        .iter()
        .map(|l| l.geoms.iter().map(|g| size_volume(sim, g)).sum::<f64>())
        .sum::<f64>()
        / links.len() as f64;
    if volume > 0.0 {
        volume.cbrt()
    } else {
        RAPIER_REFERENCE_SIZE
    }
}

/// The volume (m³) a geometry counts with for the module size: a mesh's bounding box
/// (its mass-giving volume, [`geom_volume`], is a nominal 1 cm³, which made every imported
/// mesh robot a 1 cm module: a 3 cm object rolled slowly through the floor, a kuka arm sank
/// 6 cm), any other shape's own.
fn size_volume(sim: &Simulation, g: &crate::config::body::Geom) -> f64 {
    match &g.shape {
        crate::config::body::Shape::Trimesh { file, scale, .. } => sim
            .mesh(file)
            .map(|m| {
                let (lo, hi) = m.bounds();
                (0..3).map(|k| (hi[k] - lo[k]) * scale).product::<f64>()
            })
            .filter(|v| *v > 0.0)
            .unwrap_or_else(|| geom_volume(g)),
        _ => geom_volume(g),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_parse_and_name_the_bad_one() {
        let s = PhysicsSettings::rapier_defaults()
            .parse_overrides("substeps=2, length_unit=0.05,warmstart_joints=true")
            .unwrap();
        assert_eq!(
            (s.substeps, s.length_unit, s.warmstart_joints),
            (2, 0.05, true)
        );
        let e = PhysicsSettings::rapier_defaults()
            .parse_overrides("substep=2")
            .unwrap_err();
        assert_eq!(
            e,
            SettingsError::UnknownKey {
                key: "substep".into()
            }
        );
        let e = PhysicsSettings::rapier_defaults()
            .parse_overrides("length_unit=NaN")
            .unwrap_err();
        assert!(
            matches!(&e, SettingsError::BadValue { key, expected, .. }
                if key == "length_unit" && expected.contains("positive length")),
            "{e}"
        );
        let e = PhysicsSettings::rapier_defaults()
            .parse_overrides("substeps=0")
            .unwrap_err();
        assert!(
            matches!(
                &e,
                SettingsError::BadValue {
                    expected: "a positive integer",
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn display_round_trips() {
        let s = PhysicsSettings::rapier_defaults()
            .parse_overrides("substeps=3,coulomb_friction=1,contact_recycling=0")
            .unwrap();
        assert_eq!(
            PhysicsSettings::rapier_defaults().parse_overrides(&s.to_string()),
            Ok(s)
        );
    }

    #[test]
    fn refinement_multiplies_physics_steps() {
        let s = PhysicsSettings::rapier_defaults().refined(2).refined(4);
        assert_eq!(s.steps_per_step, 8);
        let p = s.integration_parameters(0.001);
        assert!((p.dt - 0.000125).abs() < 1e-9);
    }
}
