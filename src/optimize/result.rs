//! Turning a candidate back into configuration: the actuation file with the candidate's
//! values written in, ready for `proleg run`, and the networks whose weights it holds
//! (written as weights files the actuation file names).

use crate::config::Simulation;
use crate::config::actuation::{ActuationFile, ParamSetting, ParamValue};
use crate::config::error::Pos;
use crate::config::xml::read::same_name;
use crate::control::kernel::KernelError;
use crate::control::policy::PolicyNet;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::optimize::space::SearchSpace;

/// The simulation's actuation file with `genome`'s values set.
pub fn actuation_with(sim: &Simulation, space: &SearchSpace, genome: &[u32]) -> ActuationFile {
    let mut file = sim.files.actuation.clone();
    for (gene, k) in space.genes.iter().zip(genome) {
        if gene.network.is_some() {
            continue;
        }
        let value = gene.alleles.value(*k);
        let Some(m) = file
            .modules
            .iter_mut()
            .find(|m| same_name(&m.name, gene.module))
        else {
            continue;
        };
        let driven: Vec<usize> = m.joints.indices().collect();
        let default = sim
            .actuation
            .modules
            .iter()
            .find(|x| same_name(x.descriptor.type_name, gene.module))
            .and_then(|x| {
                x.descriptor
                    .parameters
                    .iter()
                    .find(|p| p.name == gene.parameter)
            })
            .map(|p| p.default)
            .unwrap_or(0.0);
        let setting = match m
            .params
            .iter()
            .position(|p| same_name(&p.name, gene.parameter))
        {
            Some(i) => &mut m.params[i],
            None => {
                m.params.push(ParamSetting {
                    name: gene.parameter.to_string(),
                    value: ParamValue::Uniform(default),
                    pos: Pos::new(0, 0),
                });
                let last = m.params.len() - 1;
                &mut m.params[last]
            }
        };
        let all = driven.iter().all(|j| gene.joints.contains(j));
        if all {
            setting.value = ParamValue::Uniform(value);
            continue;
        }
        let mut values = match &setting.value {
            ParamValue::Uniform(v) => vec![*v; driven.len()],
            ParamValue::PerJoint(v) => v.clone(),
        };
        values.resize(driven.len(), default);
        for j in &gene.joints {
            if let Some(local) = driven.iter().position(|d| d == j) {
                values[local] = value;
            }
        }
        setting.value = ParamValue::PerJoint(values);
    }
    file
}

/// The networks `genome` gives the modules whose weights are genes: (module type, network),
/// in gene order.
pub fn networks_with(
    sim: &Simulation,
    space: &SearchSpace,
    genome: &[u32],
    registry: &ModuleRegistry,
) -> Result<Vec<(&'static str, PolicyNet)>, KernelError> {
    let modules: Vec<&'static str> = space.network_modules().collect();
    if modules.is_empty() {
        return Ok(Vec::new());
    }
    let limits = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let mut kernel = ControlKernel::from_actuation(&sim.actuation, registry, limits)?;
    space.apply(genome, &mut kernel)?;
    modules
        .into_iter()
        .map(|m| {
            kernel
                .find(m)
                .and_then(|a| kernel.actuators()[a].module.network().cloned())
                .map(|net| (m, net))
                .ok_or(KernelError::NoNetwork { module: m })
        })
        .collect()
}

/// The actuation file of `genome` for writing at `path`, the networks whose weights it
/// holds written beside it as `NAME.MODULE.safetensors` (F64, exactly the weights scored)
/// and named in it.
pub fn write_candidate(
    path: &std::path::Path,
    sim: &Simulation,
    space: &SearchSpace,
    registry: &ModuleRegistry,
    genome: &[u32],
) -> Result<ActuationFile, crate::optimize::error::OptimizeError> {
    let mut file = actuation_with(sim, space, genome);
    let name = path.file_name().map_or_else(
        || "candidate".to_string(),
        |n| {
            n.to_string_lossy()
                .trim_end_matches(".xml")
                .trim_end_matches(".actuation")
                .to_string()
        },
    );
    for (module, net) in networks_with(sim, space, genome, registry)? {
        let weights = path.with_file_name(format!("{name}.{module}.safetensors"));
        net.write_exact(&weights)
            .map_err(|e| crate::optimize::error::OptimizeError::Policy(Box::new(e)))?;
        let written = weights
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        for m in file
            .modules
            .iter_mut()
            .filter(|m| same_name(&m.name, module))
        {
            m.weights = Some((written.clone(), Pos::new(0, 0)));
        }
    }
    Ok(file)
}
