//! The contact model of an environment, in physical units (our extension of environment
//! files): one statement both engines convert in one place each
//! (`sim::engine::rapier::contact`, `sim::engine::mujoco::mjcf::contact`).
//!
//! ```xml
//! <physicsengine type="ode">
//!   <odeproperties>
//!     ...
//!     <contact>
//!       <timeConstant>0.00265</timeConstant>   <!-- s: the contact spring's 1/omega -->
//!       <dampingRatio>10</dampingRatio>        <!-- the spring-damper's zeta -->
//!       <frictionCombine>min</frictionCombine> <!-- min, max or mean of the two coefficients -->
//!       <frictionCone>elliptic</frictionCone>  <!-- elliptic or pyramidal -->
//!     </contact>
//!   </odeproperties>
//! </physicsengine>
//! ```
//!
//! A contact is a soft constraint: the overlap of two shapes is pushed out like a
//! spring-damper of natural angular frequency 1/`timeConstant` and damping ratio
//! `dampingRatio` (MuJoCo's `solref`; rapier's contact spring of `1 / (2 pi tau)` Hz). Every
//! element is optional; the defaults ([`ContactModel::default`]) are the stiffness and
//! damping rapier's production settings were validated with (its contacts with fixed
//! bodies: 60 Hz, damping ratio 10), which MuJoCo given the same passes every physical
//! check with (docs/architecture.md, "Two engines behind one interface").

use crate::config::error::{ConfigResult, ErrorKind};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::XmlWriter;

/// How the friction coefficients of two touching geometries make the contact's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrictionCombine {
    /// The smaller one (a slippery surface is slippery whatever touches it).
    #[default]
    Min,
    /// The larger one (MuJoCo's own rule).
    Max,
    /// Their mean (rapier only: MuJoCo has no such rule).
    Mean,
}

/// The shape of the friction cone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrictionCone {
    /// Friction force bounded by a circle: |f_t| <= mu f_n in every direction (Coulomb).
    #[default]
    Elliptic,
    /// Bounded per tangent direction (MuJoCo only: rapier's cone is elliptic).
    Pyramidal,
}

/// The contact model of an environment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactModel {
    /// Time constant of the contact spring-damper (s): 1 / its natural angular frequency.
    pub time_constant: f64,
    /// Damping ratio of the contact spring-damper.
    pub damping_ratio: f64,
    /// How two friction coefficients combine.
    pub friction_combine: FrictionCombine,
    /// The friction cone.
    pub friction_cone: FrictionCone,
}

/// Natural frequency (Hz) of the default contact: rapier's own for contacts with fixed
/// bodies, the stiffness its production settings were measured with.
pub const DEFAULT_CONTACT_HZ: f64 = 60.0;
/// Damping ratio of the default contact: rapier's own.
pub const DEFAULT_CONTACT_DAMPING: f64 = 10.0;

impl Default for ContactModel {
    fn default() -> Self {
        ContactModel {
            time_constant: 1.0 / (2.0 * std::f64::consts::PI * DEFAULT_CONTACT_HZ),
            damping_ratio: DEFAULT_CONTACT_DAMPING,
            friction_combine: FrictionCombine::Min,
            friction_cone: FrictionCone::Elliptic,
        }
    }
}

impl ContactModel {
    /// The contact spring's natural frequency (Hz).
    pub fn natural_frequency_hz(&self) -> f64 {
        1.0 / (2.0 * std::f64::consts::PI * self.time_constant)
    }

    /// One line for reports: `tau 2.65 ms, zeta 10, friction min, elliptic cone`.
    pub fn describe(&self) -> String {
        format!(
            "contact tau {:.3} ms ({:.1} Hz), zeta {}, friction {}, {} cone",
            self.time_constant * 1e3,
            self.natural_frequency_hz(),
            self.damping_ratio,
            combine_name(self.friction_combine),
            cone_name(self.friction_cone)
        )
    }
}

/// The name files use.
pub fn combine_name(c: FrictionCombine) -> &'static str {
    match c {
        FrictionCombine::Min => "min",
        FrictionCombine::Max => "max",
        FrictionCombine::Mean => "mean",
    }
}

/// The name files use.
pub fn cone_name(c: FrictionCone) -> &'static str {
    match c {
        FrictionCone::Elliptic => "elliptic",
        FrictionCone::Pyramidal => "pyramidal",
    }
}

/// Reads `<contact>`.
pub fn read_contact(r: &Reader, el: &Element) -> ConfigResult<ContactModel> {
    r.only_children(
        el,
        &[
            "timeconstant",
            "dampingratio",
            "frictioncombine",
            "frictioncone",
        ],
    )?;
    r.only_attrs(el, &[])?;
    let mut c = ContactModel::default();
    if let Some(t) = r.at_most_one(el, "timeconstant")? {
        c.time_constant = r.positive(t)?;
    }
    if let Some(z) = r.at_most_one(el, "dampingratio")? {
        c.damping_ratio = r.positive(z)?;
    }
    if let Some(f) = r.at_most_one(el, "frictioncombine")? {
        let t = r.text(f)?.trim();
        c.friction_combine = match t.to_ascii_lowercase().as_str() {
            "min" => FrictionCombine::Min,
            "max" => FrictionCombine::Max,
            "mean" => FrictionCombine::Mean,
            _ => {
                return Err(r.err(
                    f.pos,
                    ErrorKind::InvalidValue,
                    format!("<frictionCombine> is min, max or mean, not `{t}`"),
                ));
            }
        };
    }
    if let Some(f) = r.at_most_one(el, "frictioncone")? {
        let t = r.text(f)?.trim();
        c.friction_cone = match t.to_ascii_lowercase().as_str() {
            "elliptic" => FrictionCone::Elliptic,
            "pyramidal" => FrictionCone::Pyramidal,
            _ => {
                return Err(r.err(
                    f.pos,
                    ErrorKind::InvalidValue,
                    format!("<frictionCone> is elliptic or pyramidal, not `{t}`"),
                ));
            }
        };
    }
    Ok(c)
}

/// Writes `<contact>`.
pub fn write_contact(w: &mut XmlWriter, c: &ContactModel) {
    w.open("contact", &[]);
    w.num("timeConstant", c.time_constant);
    w.num("dampingRatio", c.damping_ratio);
    w.leaf("frictionCombine", combine_name(c.friction_combine));
    w.leaf("frictionCone", cone_name(c.friction_cone));
    w.close();
}
