//! The morphology space of an optimizer file (our extension): which bodies a co-design
//! search may build, searched with the gait.
//!
//! ```xml
//! <morphology>
//!   <modules min="3" max="10"/>          <!-- modules of the chain (joints = modules - 1) -->
//!   <orientations>pitch yaw</orientations> <!-- the alphabet of joint orientations -->
//!   <motif>2</motif>                     <!-- optional: k orientations repeated along the chain -->
//!   <parts>plain touch</parts>           <!-- the part sets a body may be built of -->
//! </morphology>
//! ```
//!
//! Every body of the space is a valid robot by construction: its module count lies in the
//! range, each joint's orientation is a letter of the alphabet, its parts one of the sets,
//! and the robot builder ([`crate::config::robot_builder`]) makes it.

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::robot_builder::{MAX_JOINTS, Orientation, PartSet};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::XmlWriter;

/// The bodies a co-design search may build.
#[derive(Debug, Clone, PartialEq)]
pub struct Morphology {
    /// Fewest and most modules (a chain of n modules has n - 1 joints).
    pub modules: [u32; 2],
    /// The joint orientations a body may use.
    pub orientations: Vec<Orientation>,
    /// With `Some(k)`, the orientations of k joints repeated along the chain (k genes);
    /// without, one orientation gene per joint.
    pub motif: Option<u32>,
    /// The part sets a body may be built of.
    pub parts: Vec<PartSet>,
    /// Where it was written.
    pub pos: Pos,
}

impl Morphology {
    /// Orientation genes: the motif's length, or one per joint of the longest body.
    pub fn orientation_genes(&self) -> usize {
        match self.motif {
            Some(k) => k as usize,
            None => self.modules[1].saturating_sub(1) as usize,
        }
    }
}

/// Reads `<morphology>`.
pub fn read_morphology(r: &Reader, el: &Element) -> ConfigResult<Morphology> {
    r.only_attrs(el, &[])?;
    r.only_children(el, &["modules", "orientations", "motif", "parts"])?;
    let m = r.required(el, "modules")?;
    r.only_attrs(m, &["min", "max"])?;
    let bound = |name: &str| -> ConfigResult<u32> {
        let a = r.required_attr(m, name)?;
        r.u32_str(&a.value, a.pos, name)
    };
    let modules = [bound("min")?, bound("max")?];
    let most = MAX_JOINTS as u32 + 1;
    if modules[0] < 2 || modules[0] > modules[1] || modules[1] > most {
        return Err(r.err(
            m.pos,
            ErrorKind::OutOfRange,
            format!(
                "modules min=\"{}\" max=\"{}\": a chain has 2 to {most} modules, min <= max",
                modules[0], modules[1]
            ),
        ));
    }
    let o = r.required(el, "orientations")?;
    let orientations = words(
        r,
        o,
        |w| match w.to_ascii_lowercase().as_str() {
            "pitch" | "p" => Some(Orientation::Pitch),
            "yaw" | "y" => Some(Orientation::Yaw),
            _ => None,
        },
        "pitch or yaw",
    )?;
    let p = r.required(el, "parts")?;
    let parts = words(r, p, PartSet::parse, "plain, touch or cube")?;
    let motif = r
        .at_most_one(el, "motif")?
        .map(|k| -> ConfigResult<u32> {
            let v = r.u32(k)?;
            if v == 0 || v > MAX_JOINTS as u32 {
                return Err(r.err(
                    k.text_pos,
                    ErrorKind::OutOfRange,
                    format!("<motif> is {v}; give 1 to {MAX_JOINTS} joints"),
                ));
            }
            Ok(v)
        })
        .transpose()?;
    Ok(Morphology {
        modules,
        orientations,
        motif,
        parts,
        pos: el.pos,
    })
}

/// The distinct words of `el`'s text, each read by `parse`; at least one.
fn words<T: PartialEq>(
    r: &Reader,
    el: &Element,
    parse: impl Fn(&str) -> Option<T>,
    expected: &str,
) -> ConfigResult<Vec<T>> {
    let mut out = Vec::new();
    for w in r.text(el)?.split_whitespace() {
        let v = parse(w).ok_or_else(|| {
            r.err(
                el.text_pos,
                ErrorKind::InvalidValue,
                format!("<{}>: {w:?} is not {expected}", el.name),
            )
        })?;
        if !out.contains(&v) {
            out.push(v);
        }
    }
    if out.is_empty() {
        return Err(r.err(
            el.pos,
            ErrorKind::InvalidValue,
            format!("<{}> names none; give {expected}", el.name),
        ));
    }
    Ok(out)
}

/// Writes `<morphology>`.
pub fn write_morphology(w: &mut XmlWriter, m: &Morphology) {
    w.open("morphology", &[]);
    w.empty(
        "modules",
        &[
            ("min", m.modules[0].to_string()),
            ("max", m.modules[1].to_string()),
        ],
    );
    let o: Vec<&str> = m
        .orientations
        .iter()
        .map(|o| match o {
            Orientation::Pitch => "pitch",
            Orientation::Yaw => "yaw",
        })
        .collect();
    w.leaf("orientations", &o.join(" "));
    if let Some(k) = m.motif {
        w.leaf("motif", &k.to_string());
    }
    let p: Vec<&str> = m.parts.iter().map(|p| p.name()).collect();
    w.leaf("parts", &p.join(" "));
    w.close();
}
