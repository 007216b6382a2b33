//! The resolved optimizer settings: every registered parameter found in a module of the
//! actuation file, active joints checked against the robot and the modules' masks,
//! bounds checked against the parameter's range; the size of the search space
//! (thesis eq. 3.3).

use std::path::{Path, PathBuf};

use crate::config::error::{ConfigResult, ErrorKind};
use crate::config::module_types::{
    ModuleDescriptor, ModuleTypes, NETWORK_WEIGHTS, ParamDescriptor,
};
use crate::config::optimizer::{GenomeConfig, OptimizerFile, allele_count};
use crate::config::resolve::actuation::{
    ActuationModel, ModuleInstance, lookup_module, lookup_parameter,
};
use crate::config::resolve::robot::RobotModel;
use crate::config::xml::read::{Reader, same_name};

/// One registered parameter, resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizedParameter {
    /// Its number in the optimizer file.
    pub number: u32,
    /// The module type.
    pub module: &'static str,
    /// The parameter.
    pub parameter: ParamDescriptor,
    /// Its genome configuration.
    pub genome: GenomeConfig,
    /// Number of genes: 1 when uniform, else one per active joint; for a network's
    /// weights ([`OptimizedParameter::network`]) 0 here: one per weight, counted when the
    /// weights file is read (`crate::optimize::SearchSpace`).
    pub genes: usize,
    /// Allowed values per gene (for a network's weights, of every weight).
    pub alleles: Vec<u64>,
    /// Whether this is the weights of the module's network (the pseudo-parameter
    /// `Weights`).
    pub network: bool,
}

/// The resolved optimizer file.
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizerModel {
    /// The optimizer file.
    pub file: PathBuf,
    /// Its settings.
    pub spec: OptimizerFile,
    /// The optimized parameters.
    pub parameters: Vec<OptimizedParameter>,
    /// The train courses of `<courses>`, generated, one per episode.
    pub courses: Option<crate::config::courses::TrainCourses>,
}

impl OptimizerModel {
    /// Number of candidate solutions (product of allele counts), as f64 (it overflows u64).
    pub fn search_space(&self) -> f64 {
        self.parameters
            .iter()
            .flat_map(|p| p.alleles.iter())
            .map(|n| *n as f64)
            .product()
    }
}

/// Checks an optimizer file against the robot, the actuation and the registry.
pub fn resolve_optimizer(
    path: &Path,
    file: &OptimizerFile,
    robot: &RobotModel,
    actuation: &ActuationModel,
    registry: &dyn ModuleTypes,
) -> ConfigResult<OptimizerModel> {
    let r = Reader::new(path);
    let mut parameters = Vec::new();
    for p in &file.parameters {
        let descriptor = lookup_module(&r, registry, &p.module, p.pos)?;
        let instances: Vec<_> = actuation
            .modules
            .iter()
            .filter(|m| same_name(m.descriptor.type_name, descriptor.type_name))
            .collect();
        if instances.is_empty() {
            let used: Vec<&str> = actuation
                .modules
                .iter()
                .map(|m| m.descriptor.type_name)
                .collect();
            return Err(r.err(
                p.pos,
                ErrorKind::UnknownReference,
                format!(
                    "parameter {} belongs to module {}, which the actuation file does not use; it uses: {}",
                    p.number,
                    descriptor.type_name,
                    used.join(", ")
                ),
            ));
        }
        let network = descriptor.network && NETWORK_WEIGHTS.answers_to(&p.parameter);
        let param = if network {
            if !instances.iter().any(|m| m.weights.is_some()) {
                return Err(r.err(
                    p.pos,
                    ErrorKind::Missing,
                    format!(
                        "parameter {} searches the weights of module {}, but the actuation file gives it no weights file (weights=\"...\"; `proleg policy init` writes one)",
                        p.number, descriptor.type_name
                    ),
                ));
            }
            &NETWORK_WEIGHTS
        } else {
            lookup_parameter(&r, descriptor, &p.parameter, p.pos)?
        };
        // parse_optimizer_file guarantees one genomeConfig per registered parameter.
        let Some(genome) = file.genome.iter().find(|g| g.number == p.number) else {
            return Err(r.err(
                p.pos,
                ErrorKind::Missing,
                format!("parameter {} has no genomeConfig", p.number),
            ));
        };
        let (genes, alleles) = if network {
            (0, vec![alleles_of(&r, genome, param, 0)?])
        } else {
            check_active_joints(&r, genome, robot, &instances, descriptor)?;
            let genes = if genome.uniform {
                1
            } else {
                genome.active_joints.count()
            };
            let alleles = (0..genes)
                .map(|i| alleles_of(&r, genome, param, i))
                .collect::<ConfigResult<Vec<u64>>>()?;
            (genes, alleles)
        };
        parameters.push(OptimizedParameter {
            number: p.number,
            module: descriptor.type_name,
            parameter: param.clone(),
            genome: genome.clone(),
            genes,
            alleles,
            network,
        });
    }
    Ok(OptimizerModel {
        file: path.to_path_buf(),
        spec: file.clone(),
        parameters,
        courses: None,
    })
}

/// Every active joint of a genome configuration must be driven by a module of the type.
fn check_active_joints(
    r: &Reader,
    genome: &GenomeConfig,
    robot: &RobotModel,
    instances: &[&ModuleInstance],
    descriptor: &ModuleDescriptor,
) -> ConfigResult<()> {
    let what = format!("genomeConfig {} activeJoints=", genome.number);
    genome
        .active_joints
        .check_len(r, genome.mask_pos, robot.joints.len(), &what)?;
    for j in genome.active_joints.indices() {
        if !instances.iter().any(|m| m.joints.0[j]) {
            return Err(r.err(
                genome.mask_pos,
                ErrorKind::UnknownReference,
                format!(
                    "{what}: joint {j} ({}) is active, but no {} module drives it",
                    robot.joints[j].name, descriptor.type_name
                ),
            ));
        }
    }
    Ok(())
}

/// How many values gene `i` of a genome configuration takes; its values or bounds must
/// lie in the parameter's range.
fn alleles_of(
    r: &Reader,
    genome: &GenomeConfig,
    param: &ParamDescriptor,
    i: usize,
) -> ConfigResult<u64> {
    if genome.value_space == 0 {
        for v in &genome.values {
            let what = format!("{} value", param.name);
            r.check_range(*v, param.min, param.max, genome.pos, &what)?;
        }
        return Ok(genome.values.len() as u64);
    }
    let pick = |v: &Vec<f64>| if v.len() == 1 { v[0] } else { v[i] };
    let (lo, hi, inc) = (
        pick(&genome.lower),
        pick(&genome.upper),
        pick(&genome.increments),
    );
    let what = format!(
        "genomeConfig {} bounds of {} ({})",
        genome.number, param.name, param.unit
    );
    let (min, max) = (param.min, param.max);
    r.check_range(lo, min, max, genome.pos, &format!("{what}: lower"))?;
    r.check_range(hi, min, max, genome.pos, &format!("{what}: upper"))?;
    Ok(allele_count(
        lo,
        hi,
        inc,
        genome.lower_bound_type,
        genome.upper_bound_type,
    ))
}
