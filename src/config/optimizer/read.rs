//! Reading an optimizer file: its properties, registered parameters and algorithm.

use crate::config::cross_engine::read_cross_engine;
use crate::config::error::{ConfigResult, ErrorKind};
use crate::config::fitness::Fitness;
use crate::config::optimizer::genome::read_genomes;
use crate::config::optimizer::{
    Algorithm, CmaSettings, DEFAULT_CMA_SIGMA, DescriptorSpec, EsSettings, GaSettings, GdSettings,
    MapElitesSettings, Measured, OptimizerFile, Quantity, RegisteredParameter,
};
use crate::config::robustness::read_robustness;
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;

pub(super) fn prob(r: &Reader, props: &Element, name: &str) -> ConfigResult<f64> {
    r.f64_in(r.required(props, name)?, 0.0, 1.0)
}

pub(super) fn count(r: &Reader, props: &Element, name: &str, min: u32) -> ConfigResult<u32> {
    let c = r.required(props, name)?;
    let v = r.u32(c)?;
    if v < min {
        return Err(r.err(
            c.text_pos,
            ErrorKind::OutOfRange,
            format!("<{}> is {v}; it must be at least {min}", c.name),
        ));
    }
    Ok(v)
}

fn read_parameters(r: &Reader, props: &Element) -> ConfigResult<Vec<RegisteredParameter>> {
    let Some(reg) = r.at_most_one(props, "registeredparameters")? else {
        return Ok(Vec::new());
    };
    r.only_children(reg, &["parameter"])?;
    let mut out: Vec<RegisteredParameter> = Vec::new();
    for p in reg.children_named("parameter") {
        r.only_attrs(p, &["number", "controlalgorithm", "parameter"])?;
        let n = r.required_attr(p, "number")?;
        let number = r.u32_str(&n.value, n.pos, "number=")?;
        if out.iter().any(|o| o.number == number) {
            return Err(r.err(
                n.pos,
                ErrorKind::InvalidValue,
                format!("parameter number {number} is registered twice"),
            ));
        }
        out.push(RegisteredParameter {
            number,
            module: r.required_attr(p, "controlalgorithm")?.value.clone(),
            parameter: r.required_attr(p, "parameter")?.value.clone(),
            pos: p.pos,
        });
    }
    if let Some(c) = r.at_most_one(props, "numofparameterstooptimize")? {
        let n = r.u32(c)? as usize;
        if n != out.len() {
            return Err(r.err(
                c.text_pos,
                ErrorKind::InvalidValue,
                format!(
                    "<numOfParametersToOptimize> is {n} but {} parameters are registered",
                    out.len()
                ),
            ));
        }
    }
    Ok(out)
}

/// Reads an optimizer file (`<geneticAlgorithm>`, `<greatDeluge>` or `<cmaEvolutionStrategy>`).
pub fn parse_optimizer_file(file: &str, text: &str) -> ConfigResult<OptimizerFile> {
    let doc = crate::config::xml::dom::parse(file, text)?;
    let r = Reader::new(file);
    let root = &doc.root;
    r.only_children(
        root,
        &[
            "properties",
            "genomeconfig",
            "robustness",
            "courses",
            "morphology",
        ],
    )?;
    r.only_attrs(root, &[])?;
    let props = r.required(root, "properties")?;
    let algorithm = read_algorithm(&r, root, props)?;
    let parameters = read_parameters(&r, props)?;
    let genome = read_genomes(&r, root, &parameters)?;
    let fitness = match r.at_most_one(props, "fitness")? {
        Some(el) => Fitness::parse(r.text(el)?)
            .map_err(|m| r.err(el.pos, ErrorKind::InvalidValue, m.to_string()))?,
        None => Fitness::Displacement,
    };
    let max_evaluations = r
        .at_most_one(props, "maxevaluations")?
        .map(|el| r.u32(el).map(u64::from))
        .transpose()?;
    let random_start = match r.at_most_one(props, "randomstart")? {
        Some(el) => r.flag(el)?,
        None => false,
    };
    let robustness = r
        .at_most_one(root, "robustness")?
        .map(|el| read_robustness(&r, el))
        .transpose()?;
    let courses = r
        .at_most_one(root, "courses")?
        .map(|el| crate::config::courses::read_courses(&r, el))
        .transpose()?;
    if let (Some(c), Some(_), Some(_)) = (
        &courses,
        &robustness,
        courses.as_ref().and_then(|c| c.episodes),
    ) {
        return Err(r.err(
            c.pos,
            ErrorKind::InvalidValue,
            "<courses episodes> is for a file without <robustness>; with one, its <episodes> is the number of episodes",
        ));
    }
    let cross_engine = read_cross_engine(&r, props)?;
    let morphology = r
        .at_most_one(root, "morphology")?
        .map(|el| crate::config::morphology::read_morphology(&r, el))
        .transpose()?;
    Ok(OptimizerFile {
        morphology,
        algorithm,
        parameters,
        genome,
        fitness,
        max_evaluations,
        random_start,
        robustness,
        courses,
        cross_engine,
    })
}

/// The algorithm's settings, by the root element: GA or great deluge.
fn read_algorithm(r: &Reader, root: &Element, props: &Element) -> ConfigResult<Algorithm> {
    let common = [
        "numofparameterstooptimize",
        "registeredparameters",
        "fitness",
        "maxevaluations",
        "randomstart",
        "engines",
        "combine",
    ];
    Ok(if root.is("geneticalgorithm") {
        let mut allowed = vec![
            "popsize",
            "pmut",
            "pcross",
            "nconvergence",
            "pconvergence",
            "flushfrequency",
            "gamode",
        ];
        allowed.extend(common);
        r.only_children(props, &allowed)?;
        Algorithm::Genetic(GaSettings {
            popsize: count(r, props, "popsize", 2)?,
            pmut: prob(r, props, "pmut")?,
            pcross: prob(r, props, "pcross")?,
            n_convergence: count(r, props, "nconvergence", 1)?,
            p_convergence: prob(r, props, "pconvergence")?,
            flush_frequency: count(r, props, "flushfrequency", 1)?,
            ga_mode: count(r, props, "gamode", 0)?,
        })
    } else if root.is("greatdeluge") {
        let mut allowed = vec![
            "credits",
            "retries",
            "initialwaterlevel",
            "rain",
            "confidence",
        ];
        allowed.extend(common);
        r.only_children(props, &allowed)?;
        let rain = r.required(props, "rain")?;
        Algorithm::GreatDeluge(GdSettings {
            credits: count(r, props, "credits", 0)?,
            retries: count(r, props, "retries", 1)?,
            initial_water_level: r.f64(r.required(props, "initialwaterlevel")?)?,
            rain: r.f64_in(rain, 0.0, f64::INFINITY)?,
            confidence: count(r, props, "confidence", 1)?,
        })
    } else if root.is("cmaevolutionstrategy") {
        let mut allowed = vec!["popsize", "sigma", "restarts"];
        allowed.extend(common);
        r.only_children(props, &allowed)?;
        Algorithm::CmaEs(read_cma(r, props)?)
    } else if root.is("evolutionstrategy") {
        let mut allowed = vec!["popsize", "sigma", "learningrate", "weightdecay"];
        allowed.extend(common);
        r.only_children(props, &allowed)?;
        Algorithm::Es(read_es(r, props)?)
    } else if root.is("mapelites") {
        let mut allowed = vec!["initialsamples", "batch", "mutation", "descriptor"];
        allowed.extend(common);
        r.only_children(props, &allowed)?;
        Algorithm::MapElites(read_map_elites(r, props)?)
    } else {
        return Err(r.err(
            root.pos,
            ErrorKind::UnknownElement,
            format!(
                "an optimizer file starts with <geneticAlgorithm>, <greatDeluge>, <cmaEvolutionStrategy>, <evolutionStrategy> or <mapElites>, not <{}>",
                root.name
            ),
        ));
    })
}

/// MAP-Elites' properties: two descriptors, and `<maxEvaluations>` (the archive fills
/// until the budget; there is no other end).
fn read_map_elites(r: &Reader, props: &Element) -> ConfigResult<MapElitesSettings> {
    let mutation = r.required(props, "mutation")?;
    let mutation = r.f64_in(mutation, 0.0, 1.0)?;
    let mut descriptors = Vec::new();
    for d in props.children_named("descriptor") {
        descriptors.push(read_descriptor(r, d)?);
    }
    if descriptors.len() != 2 {
        return Err(r.err(
            props.pos,
            ErrorKind::InvalidValue,
            format!(
                "MAP-Elites needs two <descriptor gene=\"N\" bins=\"B\"/> elements, found {}",
                descriptors.len()
            ),
        ));
    }
    if r.at_most_one(props, "maxevaluations")?.is_none() {
        return Err(r.err(
            props.pos,
            ErrorKind::Missing,
            "MAP-Elites needs <maxEvaluations>: its archive fills until the budget",
        ));
    }
    Ok(MapElitesSettings {
        initial: count(r, props, "initialsamples", 1)?,
        batch: count(r, props, "batch", 1)?,
        mutation,
        descriptors,
    })
}

/// One MAP-Elites `<descriptor>`: a gene's place in its range, the body's yaw share, or a
/// quantity measured in the episode (with its range).
fn read_descriptor(r: &Reader, d: &Element) -> ConfigResult<DescriptorSpec> {
    r.only_attrs(d, &["gene", "name", "bins", "min", "max"])?;
    let bins = r.required_attr(d, "bins")?;
    let bins = r.u32_str(&bins.value, bins.pos, "bins=")?;
    let spec = match d.attr("name") {
        Some(n) if n.value == "yaw-share" => DescriptorSpec {
            gene: 0,
            bins,
            yaw_share: true,
            measured: None,
        },
        Some(n) => {
            let quantity = match n.value.as_str() {
                "height" => Quantity::Height,
                "curvature" => Quantity::Curvature,
                _ => {
                    return Err(r.err(
                        n.pos,
                        ErrorKind::InvalidValue,
                        format!(
                            "descriptor name={:?}: the named descriptors are yaw-share, height and curvature",
                            n.value
                        ),
                    ));
                }
            };
            DescriptorSpec {
                gene: 0,
                bins,
                yaw_share: false,
                measured: Some(Measured {
                    quantity,
                    range: measured_range(r, d)?,
                }),
            }
        }
        None => {
            let gene = r.required_attr(d, "gene")?;
            DescriptorSpec {
                gene: r.u32_str(&gene.value, gene.pos, "gene=")?,
                bins,
                yaw_share: false,
                measured: None,
            }
        }
    };
    let named = spec.yaw_share || spec.measured.is_some();
    if (spec.gene == 0 && !named) || spec.bins == 0 || spec.bins > 1000 {
        return Err(r.err(
            d.pos,
            ErrorKind::OutOfRange,
            "a descriptor's gene counts from 1 and its bins lie in 1..=1000",
        ));
    }
    Ok(spec)
}

/// A measured descriptor's `min` and `max`: numbers, min below max.
fn measured_range(r: &Reader, d: &Element) -> ConfigResult<[f64; 2]> {
    let bound = |name: &str| -> ConfigResult<f64> {
        let a = r.required_attr(d, name)?;
        r.number(&a.value, a.pos, name)
    };

    let range = [bound("min")?, bound("max")?];
    if range[0] >= range[1] {
        return Err(r.err(
            d.pos,
            ErrorKind::OutOfRange,
            format!(
                "descriptor min=\"{}\" max=\"{}\": min must lie below max",
                range[0], range[1]
            ),
        ));
    }
    Ok(range)
}

/// OpenAI-ES's properties, with their defaults.
fn read_es(r: &Reader, props: &Element) -> ConfigResult<EsSettings> {
    let mut es = EsSettings::default();
    if let Some(el) = r.at_most_one(props, "popsize")? {
        es.popsize = r.u32(el)?;
        if es.popsize < 2 || es.popsize % 2 == 1 {
            return Err(r.err(
                el.pos,
                ErrorKind::InvalidValue,
                "popsize must be an even number of at least 2 (antithetic pairs)",
            ));
        }
    }
    let fraction = |name: &str, default: f64| -> ConfigResult<f64> {
        match r.at_most_one(props, name)? {
            Some(el) if r.f64(el)? <= 0.0 => Err(r.err(
                el.pos,
                ErrorKind::InvalidValue,
                format!("{name} must be > 0 (a fraction of each gene's range)"),
            )),
            Some(el) => r.f64_in(el, 0.0, 1.0),
            None => Ok(default),
        }
    };
    es.sigma = fraction("sigma", es.sigma)?;
    es.learning_rate = fraction("learningrate", es.learning_rate)?;
    if let Some(el) = r.at_most_one(props, "weightdecay")? {
        es.weight_decay = r.f64_in(el, 0.0, 1.0)?;
    }
    Ok(es)
}

/// CMA-ES's properties, with their defaults.
fn read_cma(r: &Reader, props: &Element) -> ConfigResult<CmaSettings> {
    let popsize = match r.at_most_one(props, "popsize")? {
        Some(el) => r.u32(el)?,
        None => 0,
    };
    let sigma = match r.at_most_one(props, "sigma")? {
        Some(el) if r.f64(el)? <= 0.0 => {
            return Err(r.err(
                el.pos,
                ErrorKind::InvalidValue,
                "sigma must be > 0 (a fraction of each gene's range)",
            ));
        }
        Some(el) => r.f64_in(el, 0.0, 1.0)?,
        None => DEFAULT_CMA_SIGMA,
    };
    let restarts = match r.at_most_one(props, "restarts")? {
        Some(el) => r.u32(el)?,
        None => 0,
    };
    Ok(CmaSettings {
        popsize,
        sigma,
        restarts,
    })
}
