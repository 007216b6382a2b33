//! Co-design candidates: one genome holds a body and a gait that fits any body. The body
//! genes are the module count, the joint orientations (one per joint, or a motif of k
//! repeated along the chain) and the part set, all from the optimizer file's
//! `<morphology>`; the robot builder makes the body, so every candidate's robot is an
//! ordinary robot file. The control genes do not depend on the joint count: each
//! registered parameter (uniform, of a module the actuation file names) is one gene per
//! orientation of the alphabet, and a body's actuation drives each orientation group (its
//! pitch joints, its yaw joints) with its own copy of the module and that group's values.
//!
//! A body the builder cannot make or whose start pose is
//! blocked (links overlapping each other, or the scenery: [`start_overlaps`]) is a
//! [`Rejection`]: it is not run, scores `-inf` so no optimizer keeps it, and its reason is
//! stored with the evaluation.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::config::actuation::{
    ActuationFile, ModuleAssignment, ParamSetting, ParamValue, write_actuation_file,
};
use crate::config::error::{ConfigResult, Pos};
use crate::config::mask::JointMask;
use crate::config::morphology::Morphology;
use crate::config::resolve::Simulation;
use crate::config::resolve::optimizer::OptimizerModel;
use crate::config::resolve::robot::resolve_robot;
use crate::config::robot::{parse_robot_file, write_robot_file};
use crate::config::robot_builder::{BuildError, Orientation, PartSet, RobotSpec};
use crate::config::simulation::{FileRef, Mode, SimulationFile, write_simulation_file};
use crate::config::source::{FileSource, MemSource, Overlay, relative_path};
use crate::config::start_clearance::{StartOverlap, start_overlaps};
use crate::control::ModuleRegistry;
use crate::optimize::space::{Alleles, Gene, Genome, SearchSpace, alleles_of};

/// Why a candidate is not scored: a co-design body not run, or a module that stopped
/// during its episode.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Rejection {
    /// The robot builder cannot make it.
    #[error("the builder cannot make this body: {0}")]
    Build(#[from] BuildError),
    /// Its start pose is blocked.
    #[error("{0}")]
    Start(#[from] StartOverlap),
    /// A module stopped during the episode (a plugin that panicked, a network with a
    /// non-finite output): the episode did not run the control the file describes, so it
    /// is not scored as if the module were not there.
    #[error("module {module} failed during the episode: {cause}")]
    ModuleFailed {
        /// The module type.
        module: String,
        /// Why it stopped.
        cause: String,
    },
}

/// What a candidate genome becomes.
#[derive(Debug)]
pub enum Candidate {
    /// A simulation to run.
    Run(Box<Simulation>),
    /// A body rejected unrun.
    Rejected(Rejection),
}

/// A co-design run's bodies and gaits, and how a candidate becomes a simulation: its robot
/// and actuation files written by the builder and laid over the run's own files.
pub struct Design {
    /// The genes.
    pub space: DesignSpace,
    /// The run's simulation file (environment, properties).
    base: SimulationFile,
    /// Its folder: the candidate's files are placed there.
    dir: PathBuf,
    /// The folder of the part files (where the run's own robot finds its parts).
    parts: PathBuf,
    /// Where the run's files are read.
    source: Arc<dyn FileSource + Send + Sync>,
}

impl std::fmt::Debug for Design {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Design")
            .field("space", &self.space)
            .field("dir", &self.dir)
            .finish()
    }
}

impl Design {
    /// The design of `sim` when its optimizer file has a `<morphology>`, its files read
    /// from `source`.
    pub fn of(sim: &Simulation, source: Arc<dyn FileSource + Send + Sync>) -> Option<Design> {
        let model = sim.optimizer.as_ref()?;
        let space = DesignSpace::from_model(model)?;
        Some(Design {
            space,
            base: sim.files.simulation.clone(),
            dir: sim.file.parent().map(Path::to_path_buf).unwrap_or_default(),
            parts: parts_folder(sim),
            source,
        })
    }

    /// The candidate's robot file (text), as it is written in `dir` (naming the parts
    /// from there).
    pub fn robot_text(&self, genome: &Genome, dir: &Path) -> String {
        let parts = relative_path(dir, &self.parts);
        write_robot_file(&self.space.body(genome, "design").to_robot_file(&parts))
    }

    /// The candidate's actuation file (text).
    pub fn actuation_text(&self, genome: &Genome) -> String {
        let body = self.space.body(genome, "design");
        write_actuation_file(&self.space.actuation(genome, &body, "design.robot.xml"))
    }

    /// The candidate's three files (robot, actuation, simulation: the run's, with the
    /// candidate's robot and actuation, in the single-run mode) as they lie in `dir`.
    pub fn files(&self, genome: &Genome, dir: &Path) -> [(PathBuf, String); 3] {
        let mut file = self.base.clone();
        let here = |path: &str| FileRef {
            path: path.to_string(),
            pos: Pos::new(0, 0),
        };
        file.robot = here("design.robot.xml");
        file.actuation = here("design.actuation.xml");
        file.optimizer = None;
        file.properties.mode = Mode::SingleRun;
        [
            (dir.join("design.robot.xml"), self.robot_text(genome, dir)),
            (
                dir.join("design.actuation.xml"),
                self.actuation_text(genome),
            ),
            (
                dir.join("design.simulation.xml"),
                write_simulation_file(&file),
            ),
        ]
    }

    /// The candidate's simulation, or why its body is rejected: the builder refuses it, or
    /// its start pose is blocked. A file that does not load (a part missing) is an error of
    /// the run's configuration, not of the body.
    pub fn candidate(&self, genome: &Genome, registry: &ModuleRegistry) -> ConfigResult<Candidate> {
        if let Err(e) = self.space.body(genome, "design").validate() {
            return Ok(Candidate::Rejected(e.into()));
        }
        let sim = self.simulation(genome, registry)?;
        Ok(match start_overlaps(&sim).into_iter().next() {
            Some(blocked) => Candidate::Rejected(blocked.into()),
            None => Candidate::Run(Box::new(sim)),
        })
    }

    /// The candidate's simulation ([`Design::files`] beside the run's simulation file).
    pub fn simulation(
        &self,
        genome: &Genome,
        registry: &ModuleRegistry,
    ) -> ConfigResult<Simulation> {
        let mut top = MemSource::new();
        let [robot, actuation, (path, text)] = self.files(genome, &self.dir);
        for (p, t) in [robot, actuation] {
            top.insert(p, t);
        }
        top.insert(&path, text);
        let source = Overlay {
            top,
            base: &*self.source,
        };
        crate::config::resolve::load_simulation_with(&source, &path, registry)
    }
}

/// What the body genes and the control genes of a co-design genome are.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignSpace {
    /// The bodies allowed.
    pub morphology: Morphology,
    /// The control parameters: module type, parameter and values, one gene per
    /// orientation of the alphabet each.
    pub controls: Vec<(&'static str, &'static str, Alleles)>,
}

/// A body gene's name (`Gene::module` of body genes).
pub const BODY: &str = "body";

impl DesignSpace {
    /// The design space of an optimizer file with a `<morphology>`: its registered
    /// parameters are the control genes (their first value range; one gene per
    /// orientation each).
    pub fn from_model(model: &OptimizerModel) -> Option<DesignSpace> {
        let morphology = model.spec.morphology.clone()?;
        let controls = model
            .parameters
            .iter()
            .map(|p| (p.module, p.parameter.name, alleles_of(&p.genome, 0)))
            .collect();
        Some(DesignSpace {
            morphology,
            controls,
        })
    }

    /// Body genes: modules, orientations, parts.
    pub fn body_genes(&self) -> usize {
        2 + self.morphology.orientation_genes()
    }

    /// Every gene, body genes first (module count, orientations, parts), then the control
    /// genes grouped by orientation.
    pub fn search_space(&self) -> SearchSpace {
        let m = &self.morphology;
        let list = |n: usize| Alleles::List((0..n).map(|k| k as f64).collect());
        let mut genes = vec![Gene {
            module: BODY,
            parameter: "modules",
            joints: Vec::new(),
            alleles: Alleles::Range {
                first: f64::from(m.modules[0]),
                inc: 1.0,
                count: m.modules[1] - m.modules[0] + 1,
            },
            network: None,
        }];
        for j in 0..m.orientation_genes() {
            genes.push(Gene {
                module: BODY,
                parameter: "orientation",
                joints: vec![j],
                alleles: list(m.orientations.len()),
                network: None,
            });
        }
        genes.push(Gene {
            module: BODY,
            parameter: "parts",
            joints: Vec::new(),
            alleles: list(m.parts.len()),
            network: None,
        });
        for g in 0..m.orientations.len() {
            for (module, parameter, alleles) in &self.controls {
                genes.push(Gene {
                    module,
                    parameter,
                    joints: vec![g],
                    alleles: alleles.clone(),
                    network: None,
                });
            }
        }
        SearchSpace { genes }
    }

    /// The body of `genome`: module count, orientations and parts decoded, built by the
    /// robot builder as robot `name`.
    pub fn body(&self, genome: &Genome, name: &str) -> RobotSpec {
        let m = &self.morphology;
        let at = |i: usize| genome.get(i).copied().unwrap_or(0) as usize;
        let modules = (m.modules[0] as usize + at(0)).min(m.modules[1] as usize);
        let genes = m.orientation_genes().max(1);
        let joints = (0..modules - 1)
            .map(|j| {
                let k = at(1 + j % genes);
                m.orientations[k.min(m.orientations.len() - 1)]
            })
            .collect();
        let parts = m.parts[at(1 + m.orientation_genes()).min(m.parts.len() - 1)];
        RobotSpec {
            name: name.to_string(),
            joints,
            parts,
        }
    }

    /// The gait of `genome` for `body`: per orientation group present, each control
    /// module on the group's joints with the group's values (`robot` is written as the
    /// file's valid robot).
    pub fn actuation(&self, genome: &Genome, body: &RobotSpec, robot: &str) -> ActuationFile {
        let first = self.body_genes();
        let mut modules: Vec<ModuleAssignment> = Vec::new();
        for (g, o) in self.morphology.orientations.iter().enumerate() {
            let mask: Vec<bool> = body.joints.iter().map(|j| j == o).collect();
            if !mask.contains(&true) {
                continue;
            }
            for (c, (module, parameter, alleles)) in self.controls.iter().enumerate() {
                let i = first + g * self.controls.len() + c;
                let value = alleles.value(genome.get(i).copied().unwrap_or(0));
                let setting = ParamSetting {
                    name: parameter.to_string(),
                    value: ParamValue::Uniform(value),
                    pos: Pos::new(0, 0),
                };
                match modules
                    .iter_mut()
                    .find(|m| m.name == *module && m.joints.0 == mask)
                {
                    Some(m) => m.params.push(setting),
                    None => modules.push(ModuleAssignment {
                        name: module.to_string(),
                        joints: JointMask(mask.clone()),
                        params: vec![setting],
                        pos: Pos::new(0, 0),
                        mask_pos: Pos::new(0, 0),
                        weights: None,
                    }),
                }
            }
        }
        ActuationFile {
            valid_robot: Some(robot.to_string()),
            modules,
        }
    }

    /// Bodies that together use every part of this space: per part set, a chain whose
    /// joints hold every pair of orientations of the alphabet in a row.
    pub fn sample_bodies(&self) -> Vec<RobotSpec> {
        let alphabet = &self.morphology.orientations;
        self.morphology
            .parts
            .iter()
            .map(|&parts| {
                let joints = match parts {
                    PartSet::Plain => alphabet
                        .iter()
                        .flat_map(|a| alphabet.iter().flat_map(move |b| [*a, *b]))
                        .collect(),
                    PartSet::Touch | PartSet::Cube => vec![Orientation::Pitch; 2],
                };
                RobotSpec {
                    name: "sample".into(),
                    joints,
                    parts,
                }
            })
            .collect()
    }

    /// The share of a body's joints that are yaw joints (a behaviour descriptor).
    pub fn yaw_share(&self, genome: &Genome) -> f64 {
        let body = self.body(genome, "d");
        let yaw = body
            .joints
            .iter()
            .filter(|o| **o == Orientation::Yaw)
            .count();
        yaw as f64 / body.joints.len().max(1) as f64
    }
}

/// The folder of `sim`'s part files: where its own robot's parts lie (a `parts` folder
/// holding a kinbody file it read), else `parts` beside the simulation file. Co-design
/// bodies are built of the parts there, wherever their files are written.
pub fn parts_folder(sim: &Simulation) -> PathBuf {
    sim.robot
        .files
        .iter()
        .filter(|f| f.to_string_lossy().ends_with(".kinbody.xml"))
        .filter_map(|f| f.parent())
        .find(|d| d.file_name().is_some_and(|n| n == "parts"))
        .map(Path::to_path_buf)
        .unwrap_or_else(|| {
            sim.file
                .parent()
                .map(|d| d.join("parts"))
                .unwrap_or_else(|| PathBuf::from("parts"))
        })
}

/// Every file the bodies of `sim`'s co-design space may read besides the run's own (their
/// parts, and the sensors and meshes those include), through `source`: each of
/// [`DesignSpace::sample_bodies`] is resolved beside the simulation file. A co-design run
/// stores them, so a worker builds the bodies from the store alone. Empty without a
/// `<morphology>`.
pub fn body_files(sim: &Simulation, source: &dyn FileSource) -> ConfigResult<Vec<PathBuf>> {
    let Some(space) = sim.optimizer.as_ref().and_then(DesignSpace::from_model) else {
        return Ok(Vec::new());
    };
    let dir = sim.file.parent().unwrap_or(Path::new(""));
    let parts = relative_path(dir, &parts_folder(sim));
    let path = dir.join("design.robot.xml");
    let mut files = Vec::new();
    for body in space.sample_bodies() {
        let text = write_robot_file(&body.to_robot_file(&parts));
        let mut top = MemSource::new();
        top.insert(&path, text.clone());
        let overlay = Overlay { top, base: source };
        let file = parse_robot_file(&path.display().to_string(), &text)?;
        let model = resolve_robot(&overlay, &path, &file)?;
        files.extend(model.files.into_iter().filter(|f| *f != path));
    }
    files.sort();
    files.dedup();
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::robot::write_robot_file;
    use crate::config::robot_builder::PartSet;

    fn space(motif: Option<u32>) -> DesignSpace {
        DesignSpace {
            morphology: Morphology {
                modules: [3, 9],
                orientations: vec![Orientation::Pitch, Orientation::Yaw],
                motif,
                parts: vec![PartSet::Plain, PartSet::Touch],
                pos: Pos::new(0, 0),
            },
            controls: vec![
                (
                    "PatternGenerator_sinusoidal",
                    "Amplitude",
                    Alleles::Range {
                        first: 0.0,
                        inc: 5.0,
                        count: 9,
                    },
                ),
                (
                    "PatternGenerator_sinusoidal",
                    "Phase_Difference",
                    Alleles::Range {
                        first: 0.0,
                        inc: 30.0,
                        count: 7,
                    },
                ),
            ],
        }
    }

    #[test]
    fn a_genome_is_the_builders_robot() {
        let d = space(None);
        let s = d.search_space();
        // modules, 8 orientations, parts, 2 orientations x 2 parameters.
        assert_eq!(s.genes.len(), 1 + 8 + 1 + 4);
        // 6 modules, joints p y p p y, touch parts (the rest of the orientations unused).
        let genome: Genome = vec![3, 0, 1, 0, 0, 1, 1, 1, 1, 1, 8, 2, 4, 5];
        let body = d.body(&genome, "design");
        let built = RobotSpec {
            name: "design".into(),
            joints: crate::config::robot_builder::parse_topology("pypPy").unwrap(),
            parts: PartSet::Touch,
        };
        assert_eq!(body, built);
        assert_eq!(
            write_robot_file(&body.to_robot_file("../parts")),
            write_robot_file(&built.to_robot_file("../parts"))
        );
        assert_eq!(d.yaw_share(&genome), 2.0 / 5.0);
    }

    #[test]
    fn a_motif_repeats_along_the_chain() {
        let d = space(Some(2));
        let genome: Genome = vec![6, 0, 1, 0, 1, 1, 1, 1];
        let body = d.body(&genome, "m");
        assert_eq!(
            crate::config::robot_builder::topology_string(&body.joints),
            "pypypypy"
        );
    }

    #[test]
    fn each_orientation_group_gets_its_own_gait() {
        let d = space(None);
        let genome: Genome = vec![3, 0, 1, 0, 0, 1, 1, 1, 1, 0, 8, 2, 4, 5];
        let body = d.body(&genome, "design");
        let a = d.actuation(&genome, &body, "design.robot.xml");
        assert_eq!(a.modules.len(), 2, "{a:?}");
        assert_eq!(a.modules[0].joints.0, vec![true, false, true, true, false]);
        assert_eq!(a.modules[1].joints.0, vec![false, true, false, false, true]);
        let values = |m: &ModuleAssignment| -> Vec<f64> {
            m.params
                .iter()
                .map(|p| match p.value {
                    ParamValue::Uniform(v) => v,
                    ParamValue::PerJoint(_) => f64::NAN,
                })
                .collect()
        };
        // Pitch: amplitude 40, phase difference 60; yaw: 20, 150.
        assert_eq!(values(&a.modules[0]), vec![40.0, 60.0]);
        assert_eq!(values(&a.modules[1]), vec![20.0, 150.0]);
        // A body of pitch joints only has no yaw group.
        let pitch_only: Genome = vec![0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 8, 2, 4, 5];
        let body = d.body(&pitch_only, "p");
        assert_eq!(d.actuation(&pitch_only, &body, "p").modules.len(), 1);
    }
}
