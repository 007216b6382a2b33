//! The optimization page (thesis 4.4.8): module parameters registered for the genetic
//! algorithm, the modified great deluge, CMA-ES or MAP-Elites, each on all or selected
//! joints, uniform (one gene) or individual (one gene per joint), with a value set (a range
//! with an increment, or listed values), and the algorithm settings with the thesis's
//! defaults (tables 6.1 and 6.3), CMA-ES's and MAP-Elites' defaults, a random start, robust
//! fitness, and the morphology ranges of a co-design search (the body evolved with its
//! gait).

use crate::compose::error::ComposeError;
use crate::config::cross_engine::CrossEngine;
use crate::config::error::Pos;
use crate::config::fitness::Fitness;
use crate::config::mask::JointMask;
use crate::config::morphology::Morphology;
use crate::config::optimizer::{
    Algorithm, BoundType, CmaSettings, DEFAULT_CMA_SIGMA, DescriptorSpec, GaSettings, GdSettings,
    GenomeConfig, MapElitesSettings, OptimizerFile, RegisteredParameter,
};
use crate::config::robot_builder::MAX_JOINTS;
use crate::config::robustness::Robustness;

/// The values a registered parameter may take.
#[derive(Debug, Clone, PartialEq)]
pub enum ValueSet {
    /// Values from `lower` to `upper` in steps of `increment`.
    Range {
        /// The first value.
        lower: f64,
        /// The last value.
        upper: f64,
        /// The step between values.
        increment: f64,
    },
    /// An enumerated list of values.
    List(Vec<f64>),
}

/// One parameter registered for optimization.
#[derive(Debug, Clone, PartialEq)]
pub struct Registration {
    /// The module type.
    pub module: String,
    /// The parameter's name.
    pub parameter: String,
    /// Every joint the module drives (`allJoints`), or the joints in `joints`.
    pub all_joints: bool,
    /// The joints optimized, one flag per robot joint (when not all).
    pub joints: Vec<bool>,
    /// One gene for all its joints, or one gene per joint.
    pub uniform: bool,
    /// The values the parameter may take.
    pub values: ValueSet,
}

/// Which optimizer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The genetic algorithm.
    Genetic,
    /// The modified great deluge.
    GreatDeluge,
    /// The covariance matrix adaptation evolution strategy.
    CmaEs,
    /// MAP-Elites: a map of the best candidate per cell of two descriptors.
    MapElites,
}

/// The optimization page's content.
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizationSpec {
    /// Which optimizer.
    pub method: Method,
    /// Genetic-algorithm settings.
    pub ga: GaSettings,
    /// Great-deluge settings.
    pub gd: GdSettings,
    /// CMA-ES settings.
    pub cma: CmaSettings,
    /// MAP-Elites settings.
    pub map_elites: MapElitesSettings,
    /// The bodies a co-design search may build, if the body is searched too.
    pub morphology: Option<Morphology>,
    /// Start from a point drawn from the run's seed.
    pub random_start: bool,
    /// Robust fitness over randomized episodes, if asked for.
    pub robustness: Option<Robustness>,
    /// A task suite's train courses as the episodes' worlds, if asked for (kept as the
    /// file has it; the wizard does not edit it).
    pub courses: Option<crate::config::courses::CoursesSpec>,
    /// Scores on several engines, combined, if asked for.
    pub cross_engine: Option<CrossEngine>,
    /// The registered parameters.
    pub params: Vec<Registration>,
    /// How episodes are scored.
    pub fitness: Fitness,
    /// Evaluation budget, if any.
    pub max_evaluations: Option<u64>,
}

impl OptimizationSpec {
    /// The thesis's settings: GA of table 6.3, great deluge of table 6.1.
    pub fn new(method: Method) -> Self {
        OptimizationSpec {
            method,
            ga: GaSettings {
                popsize: 30,
                pmut: 0.8,
                pcross: 0.2,
                n_convergence: 50,
                p_convergence: 0.99,
                flush_frequency: 1,
                ga_mode: 1,
            },
            gd: GdSettings {
                credits: 10,
                retries: 200,
                initial_water_level: 0.15,
                rain: 0.01,
                confidence: 20,
            },
            cma: CmaSettings {
                popsize: 0,
                sigma: DEFAULT_CMA_SIGMA,
                restarts: 0,
            },
            map_elites: MapElitesSettings {
                initial: 40,
                batch: 10,
                mutation: 0.15,
                descriptors: vec![gene_descriptor(1, 10), gene_descriptor(2, 10)],
            },
            morphology: None,
            random_start: false,
            robustness: None,
            courses: None,
            cross_engine: None,
            params: Vec::new(),
            fitness: Fitness::Displacement,
            max_evaluations: None,
        }
    }

    /// Why the settings cannot be written, if they cannot (the joints are checked
    /// against the robot when the whole simulation is checked).
    pub fn validate(&self) -> Result<(), ComposeError> {
        if self.params.is_empty() {
            return Err(ComposeError::NothingRegistered);
        }
        for (i, p) in self.params.iter().enumerate() {
            let what = |problem| ComposeError::Registration {
                index: i + 1,
                module: p.module.clone(),
                parameter: p.parameter.clone(),
                problem,
            };
            match &p.values {
                ValueSet::Range {
                    lower,
                    upper,
                    increment,
                } => {
                    if ![lower, upper, increment].iter().all(|v| v.is_finite()) {
                        return Err(what("range values must be numbers"));
                    }
                    if lower > upper {
                        return Err(what("the lower bound is above the upper bound"));
                    }
                    if *increment < 0.0 {
                        return Err(what("the increment is negative"));
                    }
                }
                ValueSet::List(v) => {
                    if v.is_empty() || v.iter().any(|x| !x.is_finite()) {
                        return Err(what("list at least one value, all numbers"));
                    }
                }
            }
            if !p.all_joints && !p.joints.iter().any(|b| *b) {
                return Err(what("select at least one joint"));
            }
        }
        if self.method == Method::Genetic && self.ga.popsize < 2 {
            return Err(ComposeError::Popsize);
        }
        if let Some(m) = &self.morphology {
            validate_morphology(m)?;
        }
        if self.method == Method::MapElites {
            if self.map_elites.descriptors.len() != 2 {
                return Err(ComposeError::Descriptors("give two descriptors"));
            }
            if self
                .map_elites
                .descriptors
                .iter()
                .filter_map(|d| d.measured)
                .any(|m| m.range[0] >= m.range[1] || !m.range.iter().all(|v| v.is_finite()))
            {
                return Err(ComposeError::Descriptors(
                    "a measured descriptor's range runs from a lower to a higher value",
                ));
            }
            if self.morphology.is_none() && self.map_elites.descriptors.iter().any(|d| d.yaw_share)
            {
                return Err(ComposeError::Descriptors(
                    "the share of yaw joints describes co-design bodies: evolve the body too",
                ));
            }
            if self.max_evaluations.is_none() {
                return Err(ComposeError::Descriptors(
                    "MAP-Elites runs until its budget: set \"stop after\"",
                ));
            }
        }
        Ok(())
    }

    /// Searches the body too (`Some`) or not: with MAP-Elites, the descriptors become the
    /// module count and the share of yaw joints.
    pub fn set_morphology(&mut self, morphology: Option<Morphology>) {
        if let Some(m) = &morphology {
            let modules = m.modules[1].saturating_sub(m.modules[0]) + 1;
            self.map_elites.descriptors = vec![
                gene_descriptor(1, modules),
                DescriptorSpec {
                    gene: 0,
                    bins: 5,
                    yaw_share: true,
                    measured: None,
                },
            ];
        } else if self.morphology.is_some() {
            self.map_elites.descriptors = vec![gene_descriptor(1, 10), gene_descriptor(2, 10)];
        }
        self.morphology = morphology;
    }

    /// The optimizer file; `module_joints(module)` gives the joints a module drives (for
    /// registrations on all of them).
    pub fn to_optimizer_file(&self, module_joints: &dyn Fn(&str) -> Vec<bool>) -> OptimizerFile {
        let parameters = self
            .params
            .iter()
            .enumerate()
            .map(|(i, p)| RegisteredParameter {
                number: i as u32,
                module: p.module.clone(),
                parameter: p.parameter.clone(),
                pos: Pos::new(0, 0),
            })
            .collect();
        let genome = self
            .params
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mask = if p.all_joints {
                    module_joints(&p.module)
                } else {
                    p.joints.clone()
                };
                let (lower, upper, increments, values, space) = match &p.values {
                    ValueSet::Range {
                        lower,
                        upper,
                        increment,
                    } => (vec![*lower], vec![*upper], vec![*increment], Vec::new(), 1),
                    ValueSet::List(v) => (Vec::new(), Vec::new(), Vec::new(), v.clone(), 0),
                };
                GenomeConfig {
                    number: i as u32,
                    all_joints: p.all_joints,
                    genome_type: 1,
                    value_type: 1,
                    value_space: space,
                    active_joints: JointMask(mask),
                    upper,
                    lower,
                    increments,
                    lower_bound_type: BoundType::Inclusive,
                    upper_bound_type: BoundType::Inclusive,
                    values,
                    uniform: p.uniform,
                    pos: Pos::new(0, 0),
                    mask_pos: Pos::new(0, 0),
                }
            })
            .collect();
        OptimizerFile {
            morphology: self.morphology.clone(),
            algorithm: match self.method {
                Method::Genetic => Algorithm::Genetic(self.ga.clone()),
                Method::GreatDeluge => Algorithm::GreatDeluge(self.gd.clone()),
                Method::CmaEs => Algorithm::CmaEs(self.cma.clone()),
                Method::MapElites => Algorithm::MapElites(self.map_elites.clone()),
            },
            parameters,
            genome,
            fitness: self.fitness,
            max_evaluations: self.max_evaluations,
            random_start: self.random_start,
            robustness: self.robustness,
            courses: self.courses.clone(),
            cross_engine: self.cross_engine.clone(),
        }
    }
}

/// A descriptor over gene `gene` (from 1) cut into `bins` cells.
fn gene_descriptor(gene: u32, bins: u32) -> DescriptorSpec {
    DescriptorSpec {
        gene,
        bins,
        yaw_share: false,
        measured: None,
    }
}

/// The morphology page's ranges: a chain of 2 to MAX_JOINTS + 1 modules, min <= max, at
/// least one orientation and one part set, touch parts only with pitch joints.
fn validate_morphology(m: &Morphology) -> Result<(), ComposeError> {
    let most = MAX_JOINTS as u32 + 1;
    if m.modules[0] < 2 || m.modules[0] > m.modules[1] || m.modules[1] > most {
        return Err(ComposeError::ModuleRange {
            range: m.modules,
            most,
        });
    }
    if m.orientations.is_empty() {
        return Err(ComposeError::Morphology("choose pitch, yaw or both"));
    }
    if m.parts.is_empty() {
        return Err(ComposeError::Morphology("choose at least one part set"));
    }
    if m.motif == Some(0) {
        return Err(ComposeError::Morphology("a motif has at least one joint"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::optimizer::{parse_optimizer_file, write_optimizer_file};

    #[test]
    fn experiment_one_registration_round_trips() {
        let mut s = OptimizationSpec::new(Method::GreatDeluge);
        assert!(matches!(s.validate(), Err(ComposeError::NothingRegistered)));
        s.params.push(Registration {
            module: "PatternGenerator_sinusoidal".into(),
            parameter: "Amplitude".into(),
            all_joints: true,
            joints: Vec::new(),
            uniform: false,
            values: ValueSet::Range {
                lower: 0.0,
                upper: 40.0,
                increment: 0.25,
            },
        });
        s.validate().unwrap();
        let f = s.to_optimizer_file(&|_| vec![true; 5]);
        assert_eq!(f.genome[0].active_joints.to_string(), "11111");
        let text = write_optimizer_file(&f);
        let back = parse_optimizer_file("o.xml", &text).unwrap();
        assert_eq!(back, f);
        // The same settings as the hand-written experiment-1 file.
        let hand = parse_optimizer_file(
            "e.xml",
            &std::fs::read_to_string("configs/optimizer/experiment1.gd.xml").unwrap(),
        )
        .unwrap();
        assert_eq!(back.algorithm, hand.algorithm);
        assert_eq!(back.genome, hand.genome);
        s.params[0].values = ValueSet::Range {
            lower: 5.0,
            upper: 1.0,
            increment: 0.1,
        };
        assert!(matches!(
            s.validate(),
            Err(ComposeError::Registration {
                index: 1,
                problem: "the lower bound is above the upper bound",
                ..
            })
        ));
    }
}
