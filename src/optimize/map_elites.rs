//! MAP-Elites (Mouret & Clune 2015; pyribs' `GridArchive` with a random-selection emitter):
//! a grid over two behaviour descriptors keeps, per cell, the best candidate that landed
//! there (its elite). The first round draws `initial` candidates at random; every later
//! round mutates elites picked uniformly from the archive (each gene redrawn with
//! probability `mutation`, at least one gene changed). The result is a map of which
//! designs work where, not one best candidate alone.
//!
//! The descriptors ([`Descriptor`]) are functions of the genome (a gene's place in its
//! range, a body's share of yaw joints) or quantities measured in the episode (body
//! height, path curvature: stored with each evaluation), so the archive is a function of
//! the evaluated candidates, their scores and their measures: a run resumed from the store,
//! or evaluated by workers on other hosts, ends with the same archive. Like the other
//! optimizers it is a deterministic function of seed and scores.

use crate::config::optimizer::{DescriptorSpec, MapElitesSettings, Quantity};
use crate::optimize::Optimizer;
use crate::optimize::design::DesignSpace;
use crate::optimize::error::OptimizeError;
use crate::optimize::space::{Genome, SearchSpace};
use crate::rng::SimRng;

/// One behaviour descriptor: what it measures of a genome, and how many cells its range
/// (0..=1) is cut into.
#[derive(Debug, Clone, PartialEq)]
pub struct Descriptor {
    /// What it measures.
    pub axis: Axis,
    /// Cells along this axis.
    pub bins: usize,
}

/// What a descriptor measures.
#[derive(Debug, Clone, PartialEq)]
pub enum Axis {
    /// A gene's place in its range.
    Gene {
        /// The gene (index into the genome).
        gene: usize,
        /// Its alleles.
        alleles: u32,
    },
    /// A co-design body's share of yaw joints.
    YawShare(std::sync::Arc<DesignSpace>),
    /// A quantity measured in the episode, over the range the cells cut.
    Measured {
        /// Which of the evaluation's measures (in descriptor order).
        index: usize,
        /// What it is.
        quantity: Quantity,
        /// The range (min, max) the cells cut.
        range: [f64; 2],
    },
}

impl Descriptor {
    /// The descriptor of `spec` in `space` (its gene is numbered from 1 in files); a
    /// yaw-share descriptor needs the co-design `design`; a measured one reads the
    /// evaluation's measure `measure_index`.
    pub fn of(
        spec: &DescriptorSpec,
        space: &SearchSpace,
        design: Option<&std::sync::Arc<DesignSpace>>,
        measure_index: usize,
    ) -> Option<Descriptor> {
        let axis = if let Some(m) = spec.measured {
            Axis::Measured {
                index: measure_index,
                quantity: m.quantity,
                range: m.range,
            }
        } else if spec.yaw_share {
            Axis::YawShare(design?.clone())
        } else {
            let gene = (spec.gene as usize).checked_sub(1)?;
            let alleles = space.genes.get(gene)?.alleles.count();
            Axis::Gene { gene, alleles }
        };
        Some(Descriptor {
            axis,
            bins: spec.bins as usize,
        })
    }

    /// The descriptor's value for `genome` with the quantities `measures` measured in its
    /// episode, 0..=1 (a measure outside its range counts at the range's end).
    pub fn value(&self, genome: &Genome, measures: &[f64]) -> f64 {
        match &self.axis {
            Axis::Gene { alleles, .. } if *alleles <= 1 => 0.0,
            Axis::Gene { gene, alleles } => {
                let k = genome.get(*gene).copied().unwrap_or(0);
                f64::from(k) / f64::from(alleles - 1)
            }
            Axis::YawShare(design) => design.yaw_share(genome),
            Axis::Measured { index, range, .. } => {
                let v = measures.get(*index).copied().unwrap_or(f64::NAN);
                let t = (v - range[0]) / (range[1] - range[0]);
                if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) }
            }
        }
    }

    /// What the axis shows, named as `proleg results` names genes.
    pub fn label(&self, space: &SearchSpace) -> String {
        match &self.axis {
            Axis::Gene { gene, .. } => space.genes[*gene].label(),
            Axis::YawShare(_) => "share of yaw joints".into(),
            Axis::Measured { quantity, .. } => quantity.label().into(),
        }
    }

    /// What the axis's 0..1 spans: a gene's or a share's place in its range, or a measured
    /// quantity's range.
    pub fn scale(&self) -> String {
        match &self.axis {
            Axis::Measured { range, .. } => format!("{} to {}", range[0], range[1]),
            _ => "place in its range".into(),
        }
    }

    /// The cell along this axis of a value in 0..=1.
    fn bin(&self, v: f64) -> usize {
        ((v * self.bins as f64) as usize).min(self.bins.saturating_sub(1))
    }
}

/// The grid of elites.
#[derive(Debug, Clone, PartialEq)]
pub struct Archive {
    /// The two descriptors (x, y).
    pub axes: [Descriptor; 2],
    /// Per cell (row-major, x fastest): the elite and its score.
    pub cells: Vec<Option<(Genome, f64)>>,
}

impl Archive {
    /// An empty archive over `axes`.
    pub fn new(axes: [Descriptor; 2]) -> Self {
        let n = axes[0].bins * axes[1].bins;
        Archive {
            axes,
            cells: vec![None; n],
        }
    }

    /// The cell of `genome` with its measured quantities `measures`.
    pub fn cell(&self, genome: &Genome, measures: &[f64]) -> usize {
        let [x, y] = &self.axes;
        y.bin(y.value(genome, measures)) * x.bins + x.bin(x.value(genome, measures))
    }

    /// Offers a scored candidate with its measured quantities; true when it became its
    /// cell's elite (a first, or a better score; a score that is not a number never
    /// enters).
    pub fn offer(&mut self, genome: &Genome, measures: &[f64], score: f64) -> bool {
        if score.is_nan() || score == f64::NEG_INFINITY {
            return false;
        }
        let c = self.cell(genome, measures);
        match &self.cells[c] {
            Some((_, s)) if *s >= score => false,
            _ => {
                self.cells[c] = Some((genome.clone(), score));
                true
            }
        }
    }

    /// The share of cells holding an elite, 0..=1.
    pub fn coverage(&self) -> f64 {
        let filled = self.cells.iter().filter(|c| c.is_some()).count();
        filled as f64 / self.cells.len().max(1) as f64
    }

    /// The QD-score: the sum over filled cells of the elite's score above `floor` (pyribs'
    /// offset, so that every elite adds).
    pub fn qd_score(&self, floor: f64) -> f64 {
        self.cells
            .iter()
            .flatten()
            .map(|(_, s)| (s - floor).max(0.0))
            .sum()
    }

    /// The best elite.
    pub fn best(&self) -> Option<(&Genome, f64)> {
        self.cells
            .iter()
            .flatten()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(g, s)| (g, *s))
    }

    /// The archive the scored candidates `evaluations` (genome, measures, score) make, in
    /// order: how a stored run's archive is rebuilt.
    pub fn replayed<'a>(
        axes: [Descriptor; 2],
        evaluations: impl IntoIterator<Item = (&'a Genome, &'a [f64], f64)>,
    ) -> Self {
        let mut a = Archive::new(axes);
        for (g, m, s) in evaluations {
            a.offer(g, m, s);
        }
        a
    }
}

/// The MAP-Elites search.
pub struct MapElites {
    space: SearchSpace,
    settings: MapElitesSettings,
    archive: Archive,
    rng: SimRng,
    pending: Vec<Genome>,
    evaluations: u64,
    max_evaluations: u64,
}

impl MapElites {
    /// MAP-Elites over `space` with `axes`, until `max_evaluations`; `start` is the first
    /// candidate of the random round.
    pub fn new(
        space: SearchSpace,
        settings: MapElitesSettings,
        axes: [Descriptor; 2],
        start: Genome,
        seed: u64,
        max_evaluations: u64,
    ) -> Self {
        let mut me = MapElites {
            space,
            settings,
            archive: Archive::new(axes),
            rng: SimRng::new(seed),
            pending: Vec::new(),
            evaluations: 0,
            max_evaluations,
        };
        me.pending.push(start);
        me
    }

    /// The archive so far.
    pub fn archive(&self) -> &Archive {
        &self.archive
    }

    /// A mutant of `parent`: each gene redrawn with probability `mutation`, at least one.
    fn mutant(&mut self, parent: &Genome) -> Genome {
        let mut g = parent.clone();
        let n = g.len();
        let forced = (self.rng.next_u64() % n.max(1) as u64) as usize;
        for (i, k) in g.iter_mut().enumerate() {
            let alleles = u64::from(self.space.genes[i].alleles.count().max(1));
            if i == forced || self.rng.uniform() < self.settings.mutation {
                *k = (self.rng.next_u64() % alleles) as u32;
            }
        }
        g
    }

    /// One round's candidates: the random round, then mutants of uniformly picked elites.
    fn round(&mut self, n: usize) -> Vec<Genome> {
        let elites: Vec<Genome> = self
            .archive
            .cells
            .iter()
            .flatten()
            .map(|(g, _)| g.clone())
            .collect();
        let mut out = std::mem::take(&mut self.pending);
        while out.len() < n {
            if elites.is_empty() || self.evaluations + (out.len() as u64) < self.initial() {
                out.push(self.space.random(&mut self.rng));
            } else {
                let parent = elites[(self.rng.next_u64() % elites.len() as u64) as usize].clone();
                out.push(self.mutant(&parent));
            }
        }
        out.truncate(n);
        out
    }

    /// Random candidates before any mutation.
    fn initial(&self) -> u64 {
        u64::from(self.settings.initial.max(1))
    }
}

impl Optimizer for MapElites {
    fn ask(&mut self) -> Vec<Genome> {
        let budget = self.max_evaluations.saturating_sub(self.evaluations);
        if budget == 0 {
            return Vec::new();
        }
        let n = if self.evaluations == 0 {
            self.initial()
        } else {
            u64::from(self.settings.batch.max(1))
        };
        let asked = self.round(n.min(budget) as usize);
        self.pending = asked.clone();
        asked
    }

    fn tell(&mut self, scores: &[f64]) {
        self.tell_measured(scores, &[]);
    }

    fn tell_measured(&mut self, scores: &[f64], measures: &[Vec<f64>]) {
        let asked = std::mem::take(&mut self.pending);
        for (i, (g, s)) in asked.iter().zip(scores).enumerate() {
            let m = measures.get(i).map_or(&[][..], Vec::as_slice);
            self.archive.offer(g, m, *s);
        }
        self.evaluations += scores.len() as u64;
    }

    fn finished(&self) -> bool {
        self.evaluations >= self.max_evaluations
    }

    fn best(&self) -> Option<(&Genome, f64)> {
        self.archive.best()
    }
}

/// The archive's two axes of a MAP-Elites file in `space`; a descriptor naming a gene the
/// space does not have is an error naming both.
pub fn map_axes(
    m: &crate::config::optimizer::MapElitesSettings,
    space: &SearchSpace,
    design: Option<DesignSpace>,
) -> Result<[Descriptor; 2], OptimizeError> {
    let design = design.map(std::sync::Arc::new);
    let axis = |k: usize| {
        let spec = m.descriptors.get(k).ok_or(OptimizeError::Descriptor {
            gene: 0,
            genes: space.genes.len(),
        })?;
        // Measured descriptors read the evaluation's measures in descriptor order.
        let index = m.descriptors[..k]
            .iter()
            .filter(|d| d.measured.is_some())
            .count();
        Descriptor::of(spec, space, design.as_ref(), index).ok_or(OptimizeError::Descriptor {
            gene: spec.gene,
            genes: space.genes.len(),
        })
    };
    Ok([axis(0)?, axis(1)?])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::space::{Alleles, Gene};

    /// Four genes of 21 alleles each on 0..1.
    fn space() -> SearchSpace {
        SearchSpace {
            genes: (0..4)
                .map(|_| Gene {
                    module: "M",
                    parameter: "p",
                    joints: vec![0],
                    alleles: Alleles::Range {
                        first: 0.0,
                        inc: 0.05,
                        count: 21,
                    },
                    network: None,
                })
                .collect(),
        }
    }

    fn axes(space: &SearchSpace) -> [Descriptor; 2] {
        [1, 2].map(|gene| {
            let spec = DescriptorSpec {
                gene,
                bins: 10,
                yaw_share: false,
                measured: None,
            };
            Descriptor::of(&spec, space, None, 0).unwrap()
        })
    }

    /// The toy problem: genes 0 and 1 place the candidate in the map; the score is best
    /// (1) when genes 2 and 3 sit at 0.5, whatever the cell.
    fn score(space: &SearchSpace, g: &Genome) -> f64 {
        let v: Vec<f64> = space.decode(g);
        1.0 - (v[2] - 0.5).powi(2) - (v[3] - 0.5).powi(2)
    }

    fn run(seed: u64, evaluations: u64) -> MapElites {
        let s = space();
        let settings = MapElitesSettings {
            initial: 50,
            batch: 10,
            mutation: 0.25,
            descriptors: Vec::new(),
        };
        let mut me = MapElites::new(s.clone(), settings, axes(&s), vec![0; 4], seed, evaluations);
        while !me.finished() {
            let asked = me.ask();
            let scores: Vec<f64> = asked.iter().map(|g| score(&s, g)).collect();
            me.tell(&scores);
        }
        me
    }

    #[test]
    fn fills_the_toy_archive_with_good_elites() {
        let me = run(7, 2000);
        let a = me.archive();
        // 100 cells; 2000 evaluations fill nearly all of them.
        assert!(a.coverage() >= 0.95, "coverage {}", a.coverage());
        // Every elite is at most 1 - 0.5 = 0.5 from the optimum 1; a filled archive of
        // good elites scores close to 100 (the QD-score above 0).
        let qd = a.qd_score(0.0);
        assert!(qd >= 0.95 * 95.0, "QD-score {qd}");
        let (_, best) = a.best().unwrap();
        assert!((best - 1.0).abs() < 1e-12, "best {best}");
        // Random search with the same budget fills less well: MAP-Elites' mutants of
        // elites improve every cell.
        let random = {
            let s = space();
            let mut rng = SimRng::new(7);
            let mut arch = Archive::new(axes(&s));
            for _ in 0..2000 {
                let g = s.random(&mut rng);
                arch.offer(&g, &[], score(&s, &g));
            }
            arch
        };
        assert!(
            qd > random.qd_score(0.0),
            "{qd} vs random {}",
            random.qd_score(0.0)
        );
    }

    #[test]
    fn the_archive_is_a_function_of_seed_and_scores() {
        let a = run(3, 600);
        let b = run(3, 600);
        assert_eq!(a.archive(), b.archive());
        assert_ne!(a.archive(), run(4, 600).archive());
    }

    #[test]
    fn a_replayed_archive_equals_the_searched_one() {
        let s = space();
        let settings = MapElitesSettings {
            initial: 20,
            batch: 5,
            mutation: 0.3,
            descriptors: Vec::new(),
        };
        let mut me = MapElites::new(s.clone(), settings, axes(&s), vec![0; 4], 11, 300);
        let mut seen = Vec::new();
        while !me.finished() {
            let asked = me.ask();
            let scores: Vec<f64> = asked.iter().map(|g| score(&s, g)).collect();
            me.tell(&scores);
            seen.extend(asked.into_iter().zip(scores));
        }
        let replayed = Archive::replayed(axes(&s), seen.iter().map(|(g, s)| (g, &[][..], *s)));
        assert_eq!(&replayed, me.archive());
    }

    #[test]
    fn a_descriptor_beyond_the_genes_is_named() {
        let settings = MapElitesSettings {
            initial: 1,
            batch: 1,
            mutation: 0.1,
            descriptors: vec![
                DescriptorSpec {
                    gene: 1,
                    bins: 4,
                    yaw_share: false,
                    measured: None,
                },
                DescriptorSpec {
                    gene: 9,
                    bins: 4,
                    yaw_share: false,
                    measured: None,
                },
            ],
        };
        let e = map_axes(&settings, &space(), None).unwrap_err();
        assert!(
            matches!(
                e,
                crate::optimize::error::OptimizeError::Descriptor { gene: 9, genes: 4 }
            ),
            "{e}"
        );
    }

    #[test]
    fn scores_that_are_not_numbers_never_become_elites() {
        let s = space();
        let mut a = Archive::new(axes(&s));
        assert!(!a.offer(&vec![0; 4], &[], f64::NAN));
        assert!(!a.offer(&vec![0; 4], &[], f64::NEG_INFINITY));
        assert!(a.offer(&vec![0; 4], &[], -5.0));
        assert!(
            !a.offer(&vec![0, 0, 1, 1], &[], -6.0),
            "a worse score keeps the elite"
        );
        assert_eq!(a.coverage(), 0.01);
    }
}
