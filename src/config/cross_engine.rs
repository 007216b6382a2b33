//! Our extension of optimizer files: score every candidate on several physics engines and
//! combine the scores, so that the optimizer prefers gaits that hold on all of them.
//!
//! ```xml
//! <properties>
//!   ...
//!   <engines>rapier mujoco</engines>  <!-- two or more engines, each once -->
//!   <combine>min</combine>            <!-- min (default) or mean of the engines' scores -->
//! </properties>
//! ```
//!
//! Without `<engines>` a candidate is scored on the simulation's own engine
//! (`<physicsEngine>`); `<combine>` needs `<engines>`.

use crate::config::error::{ConfigResult, ErrorKind};
use crate::config::simulation::EngineKind;
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::XmlWriter;

/// How the engines' scores of one candidate become its score.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Combine {
    /// The lowest engine score: a gait counts as good as it is on its worst engine.
    #[default]
    Min,
    /// The engines' mean score.
    Mean,
}

impl Combine {
    /// The name files use.
    pub fn name(self) -> &'static str {
        match self {
            Combine::Min => "min",
            Combine::Mean => "mean",
        }
    }

    /// The combined score of one candidate's engine scores (`-inf` when one is `-inf`, a
    /// blow-up on any engine; NaN when one is NaN, a failed episode).
    pub fn apply(self, scores: &[f64]) -> f64 {
        if scores.is_empty() {
            return f64::NAN;
        }
        if scores.iter().any(|s| s.is_nan()) {
            return f64::NAN;
        }
        match self {
            Combine::Min => scores.iter().copied().fold(f64::INFINITY, f64::min),
            Combine::Mean => scores.iter().sum::<f64>() / scores.len() as f64,
        }
    }
}

/// The engines every candidate is scored on, and how their scores combine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CrossEngine {
    /// Two or more engines, each once, in the order written.
    pub engines: Vec<EngineKind>,
    /// How their scores combine.
    pub combine: Combine,
}

impl CrossEngine {
    /// The run's name for it, e.g. `rapier+mujoco (min)`.
    pub fn describe(&self) -> String {
        let names: Vec<&str> = self.engines.iter().map(|e| e.name()).collect();
        format!("{} ({})", names.join("+"), self.combine.name())
    }
}

/// `<engines>` and `<combine>` of an optimizer file's properties, when given.
pub fn read_cross_engine(r: &Reader, props: &Element) -> ConfigResult<Option<CrossEngine>> {
    let combine = r
        .at_most_one(props, "combine")?
        .map(|el| {
            let t = r.text(el)?.trim();
            match t.to_ascii_lowercase().as_str() {
                "min" => Ok(Combine::Min),
                "mean" => Ok(Combine::Mean),
                _ => Err(r.err(
                    el.pos,
                    ErrorKind::InvalidValue,
                    format!("<combine> is min or mean, not `{t}`"),
                )),
            }
        })
        .transpose()?;
    let Some(el) = r.at_most_one(props, "engines")? else {
        if let Some(c) = r.at_most_one(props, "combine")? {
            return Err(r.err(
                c.pos,
                ErrorKind::InvalidValue,
                "<combine> needs <engines>: the engines whose scores it combines",
            ));
        }
        return Ok(None);
    };
    let mut engines = Vec::new();
    for name in r.text(el)?.split_whitespace() {
        let kind = EngineKind::parse(name).ok_or_else(|| {
            r.err(
                el.pos,
                ErrorKind::InvalidValue,
                format!("unknown physics engine `{name}` in <engines> (known: rapier, mujoco)"),
            )
        })?;
        if engines.contains(&kind) {
            return Err(r.err(
                el.pos,
                ErrorKind::InvalidValue,
                format!("<engines> names {kind} twice"),
            ));
        }
        engines.push(kind);
    }
    if engines.len() < 2 {
        return Err(r.err(
            el.pos,
            ErrorKind::InvalidValue,
            "<engines> names two or more engines (one engine is the simulation's <physicsEngine>)",
        ));
    }
    Ok(Some(CrossEngine {
        engines,
        combine: combine.unwrap_or_default(),
    }))
}

/// Writes `<engines>` and `<combine>` into an optimizer file's properties.
pub fn write_cross_engine(w: &mut XmlWriter, c: &CrossEngine) {
    let names: Vec<&str> = c.engines.iter().map(|e| e.name()).collect();
    w.leaf("engines", &names.join(" "));
    w.leaf("combine", c.combine.name());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_is_the_worst_engine_and_mean_the_average() {
        assert_eq!(Combine::Min.apply(&[1.0, 0.25]), 0.25);
        assert_eq!(Combine::Mean.apply(&[1.0, 0.25]), 0.625);
        assert_eq!(
            Combine::Mean.apply(&[1.0, f64::NEG_INFINITY]),
            f64::NEG_INFINITY
        );
        assert!(Combine::Min.apply(&[1.0, f64::NAN]).is_nan());
        assert!(Combine::Min.apply(&[]).is_nan());
    }
}
