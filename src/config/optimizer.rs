//! Optimizer settings: the genetic algorithm (thesis listing B.7, tables 6.3 and 6.8)
//! and the modified great deluge (tables 6.1 and 6.6), with the same parameter
//! registration and genome configuration.
//!
//! `genomeConfig` follows GAlib's allele sets: `lowerBounds`/`upperBounds` with
//! `boundsIncrements` form a discrete range; with `uniform="0"` each of the three may list
//! one value per active joint. Bound types are GAlib's: 0 none, 1 inclusive, 2 exclusive.
//! `valueSpace` 1 is such a range; 0 an enumerated set given in `<values>`. `genomeType`
//! and `valueType` are kept as written (1 = real-valued genome, as in the thesis).
//! Great-deluge files have the root `<greatDeluge>` and the properties `credits`,
//! `retries`, `initialWaterLevel`, `rain`, `confidence`. CMA-ES files (our extension) have
//! the root `<cmaEvolutionStrategy>` and the optional properties `popsize` (samples per
//! generation; 0 or absent: 4 + 3 ln n) and `sigma` (the initial step size as a fraction of
//! each gene's range, in (0, 1]; default 0.3) and `restarts` (IPOP restarts after
//! convergence, each with twice the population; default 0).
//!
//! Every optimizer file may also have (our extensions) `<randomStart>1</randomStart>` in its
//! properties (the search starts from a point drawn from the run's seed instead of the
//! actuation file's values), a `<robustness>` element ([`crate::config::robustness`]) and
//! `<engines>`/`<combine>` in its properties ([`crate::config::cross_engine`]).

use crate::config::cross_engine::{CrossEngine, read_cross_engine, write_cross_engine};
use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::fitness::Fitness;
use crate::config::mask::JointMask;
use crate::config::robustness::{Robustness, read_robustness, write_robustness};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::{XmlWriter, num};

/// A module parameter registered for optimization.
#[derive(Debug, Clone, PartialEq)]
pub struct RegisteredParameter {
    /// The number its `genomeConfig` refers to.
    pub number: u32,
    /// Module type name, as in the actuation file (`controlAlgorithm=`).
    pub module: String,
    /// The parameter's name.
    pub parameter: String,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// GAlib bound type of an allele range end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundType {
    /// No bound (GAlib 0).
    None = 0,
    /// The bound is a value (GAlib 1).
    Inclusive = 1,
    /// The bound is not a value (GAlib 2).
    Exclusive = 2,
}

/// The allowed values of one registered parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct GenomeConfig {
    /// The registered parameter it configures.
    pub number: u32,
    /// Whether every joint of the module is active.
    pub all_joints: bool,
    /// GAlib genome type, as written.
    pub genome_type: u32,
    /// Value type, as written (1 = real).
    pub value_type: u32,
    /// 0: an enumerated list of values; else a range.
    pub value_space: u32,
    /// The joints optimized.
    pub active_joints: JointMask,
    /// One value, or one per active joint when not uniform.
    pub upper: Vec<f64>,
    /// Lower bounds (one, or one per active joint).
    pub lower: Vec<f64>,
    /// Steps between values (one, or one per active joint).
    pub increments: Vec<f64>,
    /// How the lower bound counts.
    pub lower_bound_type: BoundType,
    /// How the upper bound counts.
    pub upper_bound_type: BoundType,
    /// Enumerated allowed values (`valueSpace="0"`).
    pub values: Vec<f64>,
    /// The same value for every active joint (one gene) or one gene per joint.
    pub uniform: bool,
    /// Where it was written (line, column).
    pub pos: Pos,
    /// Where its joint mask was written.
    pub mask_pos: Pos,
}

/// Genetic algorithm settings.
#[derive(Debug, Clone, PartialEq)]
pub struct GaSettings {
    /// Population size.
    pub popsize: u32,
    /// Mutation probability.
    pub pmut: f64,
    /// Crossover probability.
    pub pcross: f64,
    /// Generations taken into account for the convergence test.
    pub n_convergence: u32,
    /// Convergence ratio (0.99 = 99 %).
    pub p_convergence: f64,
    /// Generations between flushes of scores to disk.
    pub flush_frequency: u32,
    /// GAlib mode (1 = simple GA with elitism).
    pub ga_mode: u32,
}

/// Modified great deluge settings (thesis 3.4.2).
#[derive(Debug, Clone, PartialEq)]
pub struct GdSettings {
    /// Rounds without improvement before the search stops.
    pub credits: u32,
    /// Neighbours tried per round.
    pub retries: u32,
    /// The water level at the start.
    pub initial_water_level: f64,
    /// How much the level rises per accepted candidate.
    pub rain: f64,
    /// Evaluations averaged per candidate.
    pub confidence: u32,
}

/// CMA-ES settings (our extension).
#[derive(Debug, Clone, PartialEq)]
pub struct CmaSettings {
    /// Samples per generation (0: the default 4 + 3 ln n).
    pub popsize: u32,
    /// Initial step size, as a fraction of each gene's range.
    pub sigma: f64,
    /// IPOP restarts after convergence (each with twice the population; 0: none).
    pub restarts: u32,
}

/// CMA-ES's initial step size unless the file gives one.
pub const DEFAULT_CMA_SIGMA: f64 = 0.3;

/// Which optimizer, with its settings.
#[derive(Debug, Clone, PartialEq)]
pub enum Algorithm {
    /// The genetic algorithm (B.7).
    Genetic(GaSettings),
    /// The modified great deluge.
    GreatDeluge(GdSettings),
    /// The covariance matrix adaptation evolution strategy.
    CmaEs(CmaSettings),
}

/// An optimizer file as written.
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizerFile {
    /// The optimizer and its settings.
    pub algorithm: Algorithm,
    /// The registered parameters.
    pub parameters: Vec<RegisteredParameter>,
    /// One genome configuration per registered parameter.
    pub genome: Vec<GenomeConfig>,
    /// Our extension `<fitness>`: how episodes are scored (default displacement, eq. 3.7).
    pub fitness: Fitness,
    /// Our extension `<maxEvaluations>`: stop after this many evaluations.
    pub max_evaluations: Option<u64>,
    /// Our extension `<randomStart>`: start from a point drawn from the run's seed.
    pub random_start: bool,
    /// Our extension `<robustness>`: K randomized episodes per candidate.
    pub robustness: Option<Robustness>,
    /// Our extension `<engines>`/`<combine>`: every candidate scored on several engines.
    pub cross_engine: Option<CrossEngine>,
}

impl OptimizerFile {
    /// The optimizer's name, for messages.
    pub fn label(&self) -> &'static str {
        match self.algorithm {
            Algorithm::Genetic(_) => "genetic algorithm",
            Algorithm::GreatDeluge(_) => "modified great deluge",
            Algorithm::CmaEs(_) => "CMA-ES",
        }
    }
}

fn prob(r: &Reader, props: &Element, name: &str) -> ConfigResult<f64> {
    r.f64_in(r.required(props, name)?, 0.0, 1.0)
}

fn count(r: &Reader, props: &Element, name: &str, min: u32) -> ConfigResult<u32> {
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
    r.only_children(root, &["properties", "genomeconfig", "robustness"])?;
    r.only_attrs(root, &[])?;
    let props = r.required(root, "properties")?;
    let algorithm = read_algorithm(&r, root, props)?;
    let parameters = read_parameters(&r, props)?;
    let genome = read_genomes(&r, root, &parameters)?;
    let fitness = match r.at_most_one(props, "fitness")? {
        Some(el) => {
            Fitness::parse(r.text(el)?).map_err(|m| r.err(el.pos, ErrorKind::InvalidValue, m))?
        }
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
    let cross_engine = read_cross_engine(&r, props)?;
    Ok(OptimizerFile {
        algorithm,
        parameters,
        genome,
        fitness,
        max_evaluations,
        random_start,
        robustness,
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
    } else {
        return Err(r.err(
            root.pos,
            ErrorKind::UnknownElement,
            format!(
                "an optimizer file starts with <geneticAlgorithm>, <greatDeluge> or <cmaEvolutionStrategy>, not <{}>",
                root.name
            ),
        ));
    })
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

/// The genome configurations, one per registered parameter.
fn read_genomes(
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

/// Writes an optimizer file.
pub fn write_optimizer_file(o: &OptimizerFile) -> String {
    let mut w = XmlWriter::new();
    let root = match &o.algorithm {
        Algorithm::Genetic(_) => "geneticAlgorithm",
        Algorithm::GreatDeluge(_) => "greatDeluge",
        Algorithm::CmaEs(_) => "cmaEvolutionStrategy",
    };
    w.open(root, &[]);
    w.open("properties", &[]);
    write_algorithm(&mut w, &o.algorithm);
    if o.fitness != Fitness::Displacement {
        w.leaf("fitness", o.fitness.name());
    }
    if let Some(m) = o.max_evaluations {
        w.leaf("maxEvaluations", &m.to_string());
    }
    if o.random_start {
        w.flag("randomStart", true);
    }
    if let Some(c) = &o.cross_engine {
        write_cross_engine(&mut w, c);
    }
    w.leaf("numOfParametersToOptimize", &o.parameters.len().to_string());
    w.open("registeredParameters", &[]);
    for p in &o.parameters {
        w.empty(
            "parameter",
            &[
                ("number", p.number.to_string()),
                ("controlAlgorithm", p.module.clone()),
                ("parameter", p.parameter.clone()),
            ],
        );
    }
    w.close();
    w.close();
    for g in &o.genome {
        w.open(
            "genomeConfig",
            &[
                ("number", g.number.to_string()),
                ("allJoints", if g.all_joints { "1" } else { "0" }.into()),
                ("genomeType", g.genome_type.to_string()),
                ("valueType", g.value_type.to_string()),
                ("valueSpace", g.value_space.to_string()),
                ("activeJoints", g.active_joints.to_string()),
            ],
        );
        for (name, v) in [
            ("upperBounds", &g.upper),
            ("lowerBounds", &g.lower),
            ("boundsIncrements", &g.increments),
        ] {
            if !v.is_empty() {
                w.nums(name, v);
            }
        }
        w.leaf("lowerBoundTypes", &(g.lower_bound_type as u32).to_string());
        w.leaf("upperBoundTypes", &(g.upper_bound_type as u32).to_string());
        if !g.values.is_empty() {
            w.nums("values", &g.values);
        }
        w.flag("uniform", g.uniform);
        w.close();
    }
    if let Some(rb) = &o.robustness {
        write_robustness(&mut w, rb);
    }
    w.finish()
}

/// The algorithm's own properties.
fn write_algorithm(w: &mut XmlWriter, algorithm: &Algorithm) {
    match algorithm {
        Algorithm::Genetic(g) => {
            w.leaf("popsize", &g.popsize.to_string());
            w.num("pmut", g.pmut);
            w.num("pcross", g.pcross);
            w.leaf("nConvergence", &g.n_convergence.to_string());
            w.num("pConvergence", g.p_convergence);
            w.leaf("flushFrequency", &g.flush_frequency.to_string());
            w.leaf("gaMode", &g.ga_mode.to_string());
        }
        Algorithm::GreatDeluge(g) => {
            w.leaf("credits", &g.credits.to_string());
            w.leaf("retries", &g.retries.to_string());
            w.num("initialWaterLevel", g.initial_water_level);
            w.num("rain", g.rain);
            w.leaf("confidence", &g.confidence.to_string());
        }
        Algorithm::CmaEs(c) => {
            w.leaf("popsize", &c.popsize.to_string());
            w.num("sigma", c.sigma);
            if c.restarts > 0 {
                w.leaf("restarts", &c.restarts.to_string());
            }
        }
    }
}

/// Number of allowed values of one gene with the given range (GAlib discretized allele).
pub fn allele_count(
    lower: f64,
    upper: f64,
    inc: f64,
    lo_type: BoundType,
    hi_type: BoundType,
) -> u64 {
    let steps = ((upper - lower) / inc + 1e-9).floor();
    let mut n = (steps as u64).saturating_add(1);
    if lo_type == BoundType::Exclusive {
        n = n.saturating_sub(1);
    }
    if hi_type == BoundType::Exclusive && (lower + steps * inc - upper).abs() < inc * 1e-6 {
        n = n.saturating_sub(1);
    }
    n
}

/// A short `[lo, hi] step inc` description of a gene's range.
pub fn describe_range(lower: f64, upper: f64, inc: f64) -> String {
    format!("[{}, {}] step {}", num(lower), num(upper), num(inc))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn allele_counts_follow_galib_bound_types() {
        use BoundType::*;
        assert_eq!(allele_count(0.0, 40.0, 0.25, Inclusive, Inclusive), 161);
        assert_eq!(allele_count(50.0, 800.0, 25.0, Exclusive, Exclusive), 29);
        assert_eq!(allele_count(0.1, 1.0, 0.1, Inclusive, Inclusive), 10);
        // A range that does not end on a step keeps its last reachable value.
        assert_eq!(allele_count(0.0, 1.0, 0.3, Inclusive, Exclusive), 4);
        // Absurdly fine steps saturate instead of overflowing.
        assert_eq!(
            allele_count(0.0, 1.0, 1e-320, Inclusive, Inclusive),
            u64::MAX
        );
    }

    #[test]
    fn fitness_and_evaluation_budget_are_read_written_and_checked() {
        let base = include_str!("../../configs/optimizer/experiment1.ga.xml");
        let text = base.replace(
            "<gaMode>1</gaMode>",
            "<gaMode>1</gaMode>\n    <fitness>cost-of-transport</fitness>\n    <maxEvaluations>500</maxEvaluations>",
        );
        let o = parse_optimizer_file("x.ga.xml", &text).unwrap();
        assert_eq!(
            (o.fitness, o.max_evaluations),
            (Fitness::CostOfTransport, Some(500))
        );
        let again = parse_optimizer_file("x.ga.xml", &write_optimizer_file(&o)).unwrap();
        assert_eq!(again, o);
        let plain = parse_optimizer_file("x.ga.xml", base).unwrap();
        assert_eq!(
            (plain.fitness, plain.max_evaluations),
            (Fitness::Displacement, None)
        );
        let bad = base.replace(
            "<gaMode>1</gaMode>",
            "<gaMode>1</gaMode>\n<fitness>fastest</fitness>",
        );
        let e = parse_optimizer_file("x.ga.xml", &bad).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidValue);
        assert!(e.to_string().contains("unknown fitness"), "{e}");
    }

    #[test]
    fn cma_es_settings_are_read_with_defaults_and_checked() {
        let base = include_str!("../../configs/optimizer/experiment1.cmaes.xml");
        let o = parse_optimizer_file("x.cmaes.xml", base).unwrap();
        assert_eq!(
            o.algorithm,
            Algorithm::CmaEs(CmaSettings {
                popsize: 10,
                sigma: 0.25,
                restarts: 0
            })
        );
        assert_eq!(o.label(), "CMA-ES");
        let plain = base
            .replace("    <popsize>10</popsize>\n", "")
            .replace("    <sigma>0.25</sigma>\n", "");
        let o = parse_optimizer_file("x.cmaes.xml", &plain).unwrap();
        assert_eq!(
            o.algorithm,
            Algorithm::CmaEs(CmaSettings {
                popsize: 0,
                sigma: DEFAULT_CMA_SIGMA,
                restarts: 0
            })
        );
        for bad in [
            "<sigma>0</sigma>",
            "<sigma>1.5</sigma>",
            "<credits>3</credits>",
        ] {
            let text = base.replace("<sigma>0.25</sigma>", bad);
            let e = parse_optimizer_file("x.cmaes.xml", &text).unwrap_err();
            assert!(e.to_string().starts_with("x.cmaes.xml:"), "{bad}: {e}");
        }
    }
}
