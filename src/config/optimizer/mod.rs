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
//! `<engines>`/`<combine>` in its properties ([`crate::config::cross_engine`]) and a
//! `<morphology>` element ([`crate::config::morphology`]).

mod genome;
mod read;
mod write;

pub use read::parse_optimizer_file;
pub use write::write_optimizer_file;

use crate::config::cross_engine::CrossEngine;
use crate::config::error::Pos;
use crate::config::fitness::Fitness;
use crate::config::mask::JointMask;
use crate::config::robustness::Robustness;
use crate::config::xml::write::num;

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

/// OpenAI-ES settings (our extension, for the thousands of weights of a policy network).
#[derive(Debug, Clone, PartialEq)]
pub struct EsSettings {
    /// Candidates per generation: antithetic pairs, so an even number.
    pub popsize: u32,
    /// Perturbation scale, as a fraction of each gene's range.
    pub sigma: f64,
    /// Adam's step size, as a fraction of each gene's range.
    pub learning_rate: f64,
    /// L2 decay of the mean per step (a fraction of the learning rate).
    pub weight_decay: f64,
}

impl Default for EsSettings {
    fn default() -> Self {
        EsSettings {
            popsize: 32,
            sigma: 0.005,
            learning_rate: 0.002,
            weight_decay: 0.005,
        }
    }
}

/// CMA-ES's initial step size unless the file gives one.
pub const DEFAULT_CMA_SIGMA: f64 = 0.3;

/// MAP-Elites settings (our extension).
#[derive(Debug, Clone, PartialEq)]
pub struct MapElitesSettings {
    /// Random candidates before the first mutants (the first round).
    pub initial: u32,
    /// Mutants per round.
    pub batch: u32,
    /// Probability that a mutant redraws a gene (at least one gene is redrawn).
    pub mutation: f64,
    /// The two behaviour descriptors (x, y) of the archive.
    pub descriptors: Vec<DescriptorSpec>,
}

/// A behaviour descriptor: a gene's place in its range (or, in a co-design file, the
/// body's share of yaw joints, or a quantity measured in the episode), cut into cells.
#[derive(Debug, Clone, PartialEq)]
pub struct DescriptorSpec {
    /// The gene, numbered from 1 in genome order (registered parameters in their order,
    /// one gene per value of each; in a co-design file the body genes come first, gene 1
    /// being the module count); 0 with `yaw_share` or `measured`.
    pub gene: u32,
    /// Cells along this axis.
    pub bins: u32,
    /// `name="yaw-share"`: the share of the body's joints that are yaw joints.
    pub yaw_share: bool,
    /// `name="height"` or `name="curvature"` with `min`/`max`: measured in the episode.
    pub measured: Option<Measured>,
}

/// What a measured descriptor measures in each episode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// The body's height: the highest link centre above the lowest, averaged over the
    /// episode (m).
    Height,
    /// The path's turn: the angle between the centre of mass's displacements over the
    /// episode's first and second halves (degrees, 0 straight on, 180 back).
    Curvature,
}

impl Quantity {
    /// The name files use.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Height => "height",
            Quantity::Curvature => "curvature",
        }
    }

    /// What it is, for axis labels.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::Height => "body height (m)",
            Quantity::Curvature => "path curvature (deg)",
        }
    }
}

/// A measured descriptor: the quantity and the range its cells cover (values outside fall
/// into the end cells).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// What is measured.
    pub quantity: Quantity,
    /// The range (min, max) the cells cut.
    pub range: [f64; 2],
}

/// Which optimizer, with its settings.
#[derive(Debug, Clone, PartialEq)]
pub enum Algorithm {
    /// The genetic algorithm (B.7).
    Genetic(GaSettings),
    /// The modified great deluge.
    GreatDeluge(GdSettings),
    /// The covariance matrix adaptation evolution strategy.
    CmaEs(CmaSettings),
    /// MAP-Elites: an archive of the best candidate per cell of two descriptors.
    MapElites(MapElitesSettings),
    /// OpenAI's evolution strategy (antithetic sampling, rank shaping, Adam).
    Es(EsSettings),
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
    /// Our extension `<courses>`: the episodes' worlds are a task suite's train courses.
    pub courses: Option<crate::config::courses::CoursesSpec>,
    /// Our extension `<engines>`/`<combine>`: every candidate scored on several engines.
    pub cross_engine: Option<CrossEngine>,
    /// Our extension `<morphology>`: the bodies a co-design search may build.
    pub morphology: Option<crate::config::morphology::Morphology>,
}

impl OptimizerFile {
    /// The optimizer's name, for messages.
    pub fn label(&self) -> &'static str {
        match self.algorithm {
            Algorithm::Genetic(_) => "genetic algorithm",
            Algorithm::GreatDeluge(_) => "modified great deluge",
            Algorithm::CmaEs(_) => "CMA-ES",
            Algorithm::MapElites(_) => "MAP-Elites",
            Algorithm::Es(_) => "OpenAI-ES",
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
    use crate::config::error::ErrorKind;

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
        let base = include_str!("../../../configs/optimizer/experiment1.ga.xml");
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
    fn map_elites_settings_round_trip_and_are_checked() {
        let base = include_str!("../../../configs/optimizer/experiment1.mapelites.xml");
        let o = parse_optimizer_file("x.mapelites.xml", base).unwrap();
        let Algorithm::MapElites(m) = &o.algorithm else {
            panic!("not MAP-Elites: {:?}", o.algorithm);
        };
        assert_eq!((m.initial, m.batch, m.mutation), (20, 10, 0.2));
        assert_eq!(
            m.descriptors,
            vec![
                DescriptorSpec {
                    gene: 1,
                    bins: 8,
                    yaw_share: false,
                    measured: None,
                },
                DescriptorSpec {
                    gene: 5,
                    bins: 8,
                    yaw_share: false,
                    measured: None,
                }
            ]
        );
        assert_eq!(o.label(), "MAP-Elites");
        let again = parse_optimizer_file("y.xml", &write_optimizer_file(&o)).unwrap();
        assert_eq!(again, o);
        for (bad, says) in [
            ("<descriptor gene=\"5\" bins=\"8\"/>", "two <descriptor"),
            ("<maxEvaluations>300</maxEvaluations>", "<maxEvaluations>"),
            ("<mutation>0.2</mutation>", "mutation"),
        ] {
            let text = base.replacen(bad, "", 1);
            let e = parse_optimizer_file("x.xml", &text)
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("x.xml:") && e.contains(says), "{bad}: {e}");
        }
        let zero = base.replace("gene=\"1\"", "gene=\"0\"");
        let e = parse_optimizer_file("x.xml", &zero)
            .unwrap_err()
            .to_string();
        assert!(e.contains("counts from 1"), "{e}");
    }

    #[test]
    fn cma_es_settings_are_read_with_defaults_and_checked() {
        let base = include_str!("../../../configs/optimizer/experiment1.cmaes.xml");
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

    #[test]
    fn evolution_strategy_settings_are_read_written_and_checked() {
        let base = include_str!("../../../configs/optimizer/demo_policy.es.xml");
        let o = parse_optimizer_file("x.es.xml", base).unwrap();
        assert_eq!(
            o.algorithm,
            Algorithm::Es(EsSettings {
                popsize: 16,
                sigma: 0.0125,
                learning_rate: 0.005,
                weight_decay: 0.005,
            })
        );
        assert_eq!(o.label(), "OpenAI-ES");
        let again = parse_optimizer_file("y.es.xml", &write_optimizer_file(&o)).unwrap();
        assert_eq!(again.algorithm, o.algorithm);
        for (good, bad) in [
            ("<popsize>16</popsize>", "<popsize>15</popsize>"),
            ("<sigma>0.0125</sigma>", "<sigma>0</sigma>"),
            ("<sigma>0.0125</sigma>", "<sigma>2</sigma>"),
        ] {
            let e = parse_optimizer_file("x.es.xml", &base.replace(good, bad)).unwrap_err();
            assert!(e.to_string().starts_with("x.es.xml:"), "{bad}: {e}");
        }
    }
}
