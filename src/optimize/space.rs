//! The search space of an optimization (thesis B.7, eq. 3.3): one gene per registered
//! parameter when uniform, else one per active joint; each gene picks one of a discrete
//! set of values (a range with increment and GAlib bound types, or a list). A genome is
//! the allele index of every gene.

use crate::config::optimizer::{BoundType, GenomeConfig, allele_count};
use crate::config::resolve::OptimizerModel;
use crate::control::ControlKernel;
use crate::control::kernel::KernelError;

/// Allele indices, one per gene.
pub type Genome = Vec<u32>;

/// The values one gene can take.
#[derive(Debug, Clone, PartialEq)]
pub enum Alleles {
    /// `first + k * inc` for `k < count`.
    Range {
        /// The first value.
        first: f64,
        /// The step between values.
        inc: f64,
        /// How many values.
        count: u32,
    },
    /// An enumerated list of values.
    List(Vec<f64>),
}

impl Alleles {
    /// How many values the gene can take.
    pub fn count(&self) -> u32 {
        match self {
            Alleles::Range { count, .. } => *count,
            Alleles::List(v) => v.len() as u32,
        }
    }

    /// Value `k` (clamped to the last).
    pub fn value(&self, k: u32) -> f64 {
        match self {
            Alleles::Range { first, inc, count } => {
                // Rounded to 1e-10 so that 0.1 + 6 * 0.1 reads 0.7, not 0.7000000000000001.
                let v = first + f64::from(k.min(count.saturating_sub(1))) * inc;
                (v * 1e10).round() / 1e10
            }
            Alleles::List(v) => v.get(k as usize).or(v.last()).copied().unwrap_or(0.0),
        }
    }

    /// The allele nearest to `value`.
    pub fn nearest(&self, value: f64) -> u32 {
        match self {
            Alleles::Range { first, inc, count } => {
                let k = ((value - first) / inc).round();
                k.clamp(0.0, f64::from(count.saturating_sub(1))) as u32
            }
            Alleles::List(v) => v
                .iter()
                .enumerate()
                .min_by(|a, b| (a.1 - value).abs().total_cmp(&(b.1 - value).abs()))
                .map(|(i, _)| i as u32)
                .unwrap_or(0),
        }
    }
}

/// One gene: which module parameter at which robot joints, and its values.
#[derive(Debug, Clone, PartialEq)]
pub struct Gene {
    /// Module type name (the kernel's first actuator of that type is set).
    pub module: &'static str,
    /// The parameter's name.
    pub parameter: &'static str,
    /// Robot joints this gene sets (none for a network weight).
    pub joints: Vec<usize>,
    /// The values it takes.
    pub alleles: Alleles,
    /// For a weight of the module's network: its index in the network's parameters.
    pub network: Option<usize>,
}

impl Gene {
    /// `Module.Parameter[j]` (or `[all]` for a uniform gene).
    pub fn label(&self) -> String {
        if let Some(k) = self.network {
            format!("{}.{}[{k}]", self.module, self.parameter)
        } else if self.joints.len() == 1 {
            format!("{}.{}[{}]", self.module, self.parameter, self.joints[0])
        } else {
            format!("{}.{}[all]", self.module, self.parameter)
        }
    }
}

/// Every gene of an optimization.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SearchSpace {
    /// The genes, in genome order.
    pub genes: Vec<Gene>,
}

pub(crate) fn alleles_of(g: &GenomeConfig, i: usize) -> Alleles {
    if g.value_space == 0 {
        return Alleles::List(g.values.clone());
    }
    let pick = |v: &Vec<f64>| {
        if v.len() == 1 {
            v[0]
        } else {
            v.get(i).copied().unwrap_or(0.0)
        }
    };
    let (lo, hi, inc) = (pick(&g.lower), pick(&g.upper), pick(&g.increments));
    let count = allele_count(lo, hi, inc, g.lower_bound_type, g.upper_bound_type)
        .min(u32::MAX as u64) as u32;
    let first = if g.lower_bound_type == BoundType::Exclusive {
        lo + inc
    } else {
        lo
    };
    Alleles::Range { first, inc, count }
}

impl SearchSpace {
    /// The genes of a resolved optimizer file; a network's weights get one gene each, as
    /// many as the network `kernel`'s module of that type runs.
    pub fn from_model(
        model: &OptimizerModel,
        kernel: &ControlKernel,
    ) -> Result<SearchSpace, KernelError> {
        let mut genes = Vec::new();
        for p in &model.parameters {
            if p.network {
                let count = network_of(kernel, p.module)?.parameter_count();
                let alleles = alleles_of(&p.genome, 0);
                genes.extend((0..count).map(|k| Gene {
                    module: p.module,
                    parameter: p.parameter.name,
                    joints: Vec::new(),
                    alleles: alleles.clone(),
                    network: Some(k),
                }));
                continue;
            }
            let active: Vec<usize> = p.genome.active_joints.indices().collect();
            if p.genome.uniform {
                genes.push(Gene {
                    module: p.module,
                    parameter: p.parameter.name,
                    joints: active,
                    alleles: alleles_of(&p.genome, 0),
                    network: None,
                });
            } else {
                for (i, j) in active.into_iter().enumerate() {
                    genes.push(Gene {
                        module: p.module,
                        parameter: p.parameter.name,
                        joints: vec![j],
                        alleles: alleles_of(&p.genome, i),
                        network: None,
                    });
                }
            }
        }
        Ok(SearchSpace { genes })
    }

    /// Number of candidates (eq. 3.3; f64 because it overflows integers).
    pub fn size(&self) -> f64 {
        self.genes
            .iter()
            .map(|g| f64::from(g.alleles.count()))
            .product()
    }

    /// Whether `genome` is a candidate of this space: a gene each, every allele in range.
    pub fn contains(&self, genome: &[u32]) -> bool {
        genome.len() == self.genes.len()
            && self
                .genes
                .iter()
                .zip(genome)
                .all(|(g, k)| *k < g.alleles.count())
    }

    /// Parameter values of a genome, one per gene.
    pub fn decode(&self, genome: &[u32]) -> Vec<f64> {
        self.genes
            .iter()
            .zip(genome)
            .map(|(g, k)| g.alleles.value(*k))
            .collect()
    }

    /// The genome nearest to the values `kernel` holds now (the configured start).
    pub fn encode_kernel(&self, kernel: &ControlKernel) -> Genome {
        let weights: Vec<(&'static str, Vec<f64>)> = self
            .network_modules()
            .filter_map(|m| network_in(kernel, m).map(|n| (m, n.parameters())))
            .collect();
        self.genes
            .iter()
            .map(|g| {
                if let Some(k) = g.network {
                    let v = weights
                        .iter()
                        .find(|(m, _)| *m == g.module)
                        .and_then(|(_, w)| w.get(k).copied())
                        .unwrap_or(0.0);
                    return g.alleles.nearest(v);
                }
                let v = kernel
                    .find(g.module)
                    .and_then(|a| {
                        kernel
                            .parameter(a, g.parameter, g.joints.first().copied())
                            .ok()
                    })
                    .unwrap_or_else(|| g.alleles.value(0));
                g.alleles.nearest(v)
            })
            .collect()
    }

    /// Sets the genome's values in `kernel`.
    pub fn apply(&self, genome: &[u32], kernel: &mut ControlKernel) -> Result<(), KernelError> {
        for module in self.network_modules() {
            let values: Vec<f64> = self
                .genes
                .iter()
                .zip(genome)
                .filter(|(g, _)| g.network.is_some() && g.module == module)
                .map(|(g, k)| g.alleles.value(*k))
                .collect();
            if let Some(a) = kernel.find(module) {
                kernel.set_network_parameters(a, &values)?;
            }
        }
        for (g, k) in self.genes.iter().zip(genome) {
            if g.network.is_some() {
                continue;
            }
            let value = g.alleles.value(*k);
            let Some(a) = kernel.find(g.module) else {
                continue;
            };
            for j in &g.joints {
                kernel.set_parameter(a, g.parameter, Some(*j), value)?;
            }
        }
        Ok(())
    }

    /// The module types whose network weights are genes, each once.
    pub fn network_modules(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.genes
            .iter()
            .enumerate()
            .filter(|(i, g)| {
                g.network.is_some()
                    && !self.genes[..*i]
                        .iter()
                        .any(|o| o.network.is_some() && o.module == g.module)
            })
            .map(|(_, g)| g.module)
    }

    /// A uniformly random genome.
    pub fn random(&self, rng: &mut crate::rng::SimRng) -> Genome {
        self.genes
            .iter()
            .map(|g| (rng.next_u64() % u64::from(g.alleles.count().max(1))) as u32)
            .collect()
    }
}

/// The network of `kernel`'s first module of type `module`, if it runs one.
fn network_in<'a>(
    kernel: &'a ControlKernel,
    module: &str,
) -> Option<&'a crate::control::policy::PolicyNet> {
    kernel
        .find(module)
        .and_then(|a| kernel.actuators()[a].module.network())
}

/// The network of `kernel`'s first module of type `module`, or why there is none.
fn network_of<'a>(
    kernel: &'a ControlKernel,
    module: &'static str,
) -> Result<&'a crate::control::policy::PolicyNet, KernelError> {
    network_in(kernel, module).ok_or(KernelError::NoNetwork { module })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alleles_decode_and_encode_back() {
        let a = Alleles::Range {
            first: 0.0,
            inc: 0.25,
            count: 161,
        };
        for k in [0, 1, 80, 160] {
            assert_eq!(a.nearest(a.value(k)), k);
        }
        assert_eq!(a.value(160), 40.0);
        assert_eq!(a.nearest(99.0), 160);
        let c = Alleles::Range {
            first: 0.1,
            inc: 0.1,
            count: 10,
        };
        assert_eq!(c.value(6).to_string(), "0.7");
        let l = Alleles::List(vec![1.0, 5.0, 2.0]);
        assert_eq!((l.nearest(4.0), l.value(2)), (1, 2.0));
    }
}
