//! The genome configurations of an optimizer file (GAlib's allele sets): reading each
//! `<genomeConfig>` and checking it against the registered parameters.

use crate::config::error::{ConfigResult, ErrorKind};
use crate::config::mask::JointMask;
use crate::config::optimizer::{BoundType, GenomeConfig, RegisteredParameter};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;

fn bound_type(r: &Reader, el: &Element, name: &str) -> ConfigResult<BoundType> {
    match r.at_most_one(el, name)? {
        None => Ok(BoundType::Inclusive),
        Some(c) => match r.u32(c)? {
            0 => Ok(BoundType::None),
            1 => Ok(BoundType::Inclusive),
            2 => Ok(BoundType::Exclusive),
            v => Err(r.err(
                c.text_pos,
                ErrorKind::OutOfRange,
                format!(
                    "<{}> is {v}; expected 0 (none), 1 (inclusive) or 2 (exclusive)",
                    c.name
                ),
            )),
        },
    }
}

fn read_genome(r: &Reader, el: &Element) -> ConfigResult<GenomeConfig> {
    r.only_children(
        el,
        &[
            "upperbounds",
            "lowerbounds",
            "boundsincrements",
            "lowerboundtypes",
            "upperboundtypes",
            "uniform",
            "values",
        ],
    )?;
    r.only_attrs(
        el,
        &[
            "number",
            "alljoints",
            "genometype",
            "valuetype",
            "valuespace",
            "activejoints",
        ],
    )?;
    let attr_u32 = |name: &str, default: u32| -> ConfigResult<u32> {
        el.attr(name)
            .map(|a| r.u32_str(&a.value, a.pos, &format!("{name}=")))
            .transpose()
            .map(|v| v.unwrap_or(default))
    };
    let num_attr = r.required_attr(el, "number")?;
    let mask_attr = r.required_attr(el, "activejoints")?;
    let list = |name: &str| -> ConfigResult<Vec<f64>> {
        match r.at_most_one(el, name)? {
            Some(c) => r.numbers(r.text(c)?, c.text_pos, &format!("<{}>", c.name)),
            None => Ok(Vec::new()),
        }
    };
    let g = GenomeConfig {
        number: r.u32_str(&num_attr.value, num_attr.pos, "number=")?,
        all_joints: el
            .attr("alljoints")
            .map(|a| r.flag_str(&a.value, a.pos, "allJoints="))
            .transpose()?
            .unwrap_or(true),
        genome_type: attr_u32("genometype", 1)?,
        value_type: attr_u32("valuetype", 1)?,
        value_space: attr_u32("valuespace", 1)?,
        active_joints: JointMask::parse(r, &mask_attr.value, mask_attr.pos, "activeJoints=")?,
        upper: list("upperbounds")?,
        lower: list("lowerbounds")?,
        increments: list("boundsincrements")?,
        lower_bound_type: bound_type(r, el, "lowerboundtypes")?,
        upper_bound_type: bound_type(r, el, "upperboundtypes")?,
        values: list("values")?,
        uniform: r
            .at_most_one(el, "uniform")?
            .map(|c| r.flag(c))
            .transpose()?
            .unwrap_or(true),
        pos: el.pos,
        mask_pos: mask_attr.pos,
    };
    check_genome(r, el, &g)?;
    Ok(g)
}

/// Checks a genome configuration on its own (the robot is checked when resolving).
fn check_genome(r: &Reader, el: &Element, g: &GenomeConfig) -> ConfigResult<()> {
    let what = format!("genomeConfig {}", g.number);
    match g.value_space {
        0 => {
            if g.values.is_empty() {
                return Err(r.err(
                    g.pos,
                    ErrorKind::Missing,
                    format!("{what}: valueSpace=\"0\" needs a <values> list"),
                ));
            }
        }
        1 => {
            let per_joint = if g.uniform {
                1
            } else {
                g.active_joints.count()
            };
            for (name, v) in [
                ("upperBounds", &g.upper),
                ("lowerBounds", &g.lower),
                ("boundsIncrements", &g.increments),
            ] {
                let pos = el.child(name).map(|c| c.text_pos).unwrap_or(g.pos);
                if v.is_empty() {
                    return Err(r.err(pos, ErrorKind::Missing, format!("{what} needs <{name}>")));
                }
                if v.len() != 1 && v.len() != per_joint {
                    return Err(r.err(
                        pos,
                        ErrorKind::InvalidValue,
                        format!("{what}: <{name}> has {} values; give 1, or one per active joint ({per_joint})", v.len()),
                    ));
                }
            }
            for i in 0..per_joint {
                let pick = |v: &Vec<f64>| if v.len() == 1 { v[0] } else { v[i] };
                let (lo, hi, inc) = (pick(&g.lower), pick(&g.upper), pick(&g.increments));
                let pos = el.child("lowerbounds").map(|c| c.text_pos).unwrap_or(g.pos);
                if lo > hi {
                    return Err(r.err(
                        pos,
                        ErrorKind::OutOfRange,
                        format!("{what}: lower bound {lo} is greater than upper bound {hi}"),
                    ));
                }
                if inc <= 0.0 {
                    let pos = el
                        .child("boundsincrements")
                        .map(|c| c.text_pos)
                        .unwrap_or(g.pos);
                    return Err(r.err(
                        pos,
                        ErrorKind::OutOfRange,
                        format!("{what}: increment {inc} must be > 0"),
                    ));
                }
            }
        }
        v => {
            let pos = el.attr("valuespace").map(|a| a.pos).unwrap_or(g.pos);
            return Err(r.err(
                pos,
                ErrorKind::OutOfRange,
                format!(
                    "{what}: valueSpace=\"{v}\"; expected 1 (range) or 0 (enumerated <values>)"
                ),
            ));
        }
    }
    Ok(())
}

/// The genome configurations, one per registered parameter.
pub(super) fn read_genomes(
    r: &Reader,
    root: &Element,
    parameters: &[RegisteredParameter],
) -> ConfigResult<Vec<GenomeConfig>> {
    let mut genome: Vec<GenomeConfig> = Vec::new();
    for g in root.children_named("genomeconfig") {
        let cfg = read_genome(r, g)?;
        if genome.iter().any(|o| o.number == cfg.number) {
            return Err(r.err(
                cfg.pos,
                ErrorKind::InvalidValue,
                format!("genomeConfig number {} given twice", cfg.number),
            ));
        }
        if !parameters.iter().any(|p| p.number == cfg.number) {
            return Err(r.err(
                cfg.pos,
                ErrorKind::UnknownReference,
                format!(
                    "genomeConfig number {} belongs to no registered parameter",
                    cfg.number
                ),
            ));
        }
        genome.push(cfg);
    }
    for p in parameters {
        if !genome.iter().any(|g| g.number == p.number) {
            return Err(r.err(
                p.pos,
                ErrorKind::Missing,
                format!(
                    "registered parameter {} ({}) has no <genomeConfig number=\"{}\">",
                    p.number, p.parameter, p.number
                ),
            ));
        }
    }
    Ok(genome)
}
