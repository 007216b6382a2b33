//! The expert dialog's logic (thesis 4.4.2): a simulation composed from existing robot,
//! actuation, environment and optimizer files — the lists of what the configuration
//! folder and the user's folder hold — checked as one simulation and saved.

use std::path::{Path, PathBuf};

use crate::compose::error::ComposeError;
use crate::compose::paths::{OverlaySource, relative_path};
use crate::config::error::Pos;
use crate::config::resolve::load_simulation_with;
use crate::config::simulation::{
    FileRef, SimulationFile, SimulationProperties, parse_simulation_file, write_simulation_file,
};
use crate::config::source::{normalize, resolve_include};
use crate::control::registry::ModuleRegistry;

/// The kinds of file a simulation is made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// The robot file.
    Robot,
    /// The actuation file.
    Actuation,
    /// The environment file.
    Environment,
    /// The optimizer file.
    Optimizer,
}

impl Part {
    /// Every value, in the order the GUI lists them.
    pub const ALL: [Part; 4] = [
        Part::Robot,
        Part::Actuation,
        Part::Environment,
        Part::Optimizer,
    ];

    /// The name shown to the user.
    pub fn label(self) -> &'static str {
        match self {
            Part::Robot => "Robot",
            Part::Actuation => "Actuation",
            Part::Environment => "Environment",
            Part::Optimizer => "Optimizer",
        }
    }

    fn matches(self, name: &str) -> bool {
        match self {
            Part::Robot => name.ends_with(".robot.xml"),
            Part::Actuation => name.ends_with(".actuation.xml"),
            Part::Environment => name.ends_with(".env.xml"),
            Part::Optimizer => {
                name.ends_with(".ga.xml")
                    || name.ends_with(".gd.xml")
                    || name.ends_with(".optimizer.xml")
            }
        }
    }
}

/// Files of one kind under the given folders (searched two levels deep), sorted.
pub fn catalog(part: Part, dirs: &[PathBuf]) -> Vec<PathBuf> {
    fn walk(dir: &Path, depth: usize, part: Part, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() && depth > 0 {
                walk(&p, depth - 1, part, out);
            } else if part.matches(&e.file_name().to_string_lossy()) {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    for d in dirs {
        walk(d, 2, part, &mut out);
    }
    out.sort();
    out.dedup();
    out
}

/// A simulation put together from existing files.
#[derive(Debug, Clone, PartialEq)]
pub struct Composition {
    /// The robot file.
    pub robot: PathBuf,
    /// The actuation file.
    pub actuation: PathBuf,
    /// The environment file, if any.
    pub environment: Option<PathBuf>,
    /// The optimizer file, if any.
    pub optimizer: Option<PathBuf>,
    /// The simulation properties.
    pub properties: SimulationProperties,
    /// The simulation's description.
    pub description: String,
}

impl Composition {
    /// The composition an existing simulation file makes (its included files found as a
    /// simulation load finds them).
    pub fn open(path: &Path) -> Result<Composition, ComposeError> {
        let text = std::fs::read_to_string(path).map_err(ComposeError::io(path))?;
        let sim = parse_simulation_file(&path.display().to_string(), &text)?;
        let src = OverlaySource::default();
        let find = |r: &FileRef| {
            resolve_include(&src, path, &r.path).ok_or_else(|| ComposeError::Include {
                file: path.to_path_buf(),
                line: r.pos.line,
                include: r.path.clone(),
            })
        };
        Ok(Composition {
            robot: find(&sim.robot)?,
            actuation: find(&sim.actuation)?,
            environment: sim.environment.as_ref().map(find).transpose()?,
            optimizer: sim.optimizer.as_ref().map(find).transpose()?,
            properties: sim.properties,
            description: sim.description.unwrap_or_default(),
        })
    }

    /// [`Composition::open`] after loading the simulation with everything it includes, as
    /// the control window and `proleg check` do: a broken file gives the same located
    /// error (`file:line:col: cause`).
    pub fn open_checked(
        path: &Path,
        registry: &ModuleRegistry,
    ) -> Result<Composition, ComposeError> {
        crate::control::load_simulation_in(path, registry)?;
        Composition::open(path)
    }

    /// The simulation file, naming its parts relative to `path`'s folder.
    pub fn to_file(&self, path: &Path) -> SimulationFile {
        let dir = path.parent().unwrap_or(Path::new(""));
        let fref = |p: &Path| FileRef {
            path: relative_path(dir, p),
            pos: Pos::new(0, 0),
        };
        SimulationFile {
            description: (!self.description.trim().is_empty())
                .then(|| self.description.trim().to_string()),
            robot: fref(&self.robot),
            actuation: fref(&self.actuation),
            environment: self.environment.as_deref().map(fref),
            optimizer: self.optimizer.as_deref().map(fref),
            properties: self.properties.clone(),
        }
    }

    /// Checks the composition as `proleg check` would, as if saved at `path`, against the
    /// module types of `registry`.
    pub fn check(&self, path: &Path, registry: &ModuleRegistry) -> Result<String, ComposeError> {
        let mut src = OverlaySource::default();
        let path = normalize(path);
        src.unsaved
            .insert(&path, write_simulation_file(&self.to_file(&path)));
        let sim = load_simulation_with(&src, &path, registry)?;
        Ok(format!(
            "{}: {} joints, {} modules, {} environment bodies{}",
            sim.robot.name,
            sim.robot.joints.len(),
            sim.actuation.modules.len(),
            sim.environment.bodies.len(),
            sim.optimizer
                .as_ref()
                .map(|o| format!(", {} ({:.3e} candidates)", o.spec.label(), o.search_space()))
                .unwrap_or_default()
        ))
    }

    /// Checks (against `registry`'s module types) and writes the simulation file.
    pub fn save(&self, path: &Path, registry: &ModuleRegistry) -> Result<(), ComposeError> {
        self.check(path, registry)?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(ComposeError::io(dir))?;
        }
        std::fs::write(path, write_simulation_file(&self.to_file(path)))
            .map_err(ComposeError::io(path))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalog_lists_each_kind() {
        let dirs = [PathBuf::from("configs")];
        assert!(
            catalog(Part::Robot, &dirs)
                .iter()
                .any(|p| p.ends_with("snake5p.robot.xml"))
        );
        assert!(catalog(Part::Optimizer, &dirs).len() >= 4);
        assert!(
            catalog(Part::Environment, &dirs)
                .iter()
                .all(|p| p.to_string_lossy().ends_with(".env.xml"))
        );
    }

    #[test]
    fn recomposed_experiment_checks_and_saves() {
        let mut c =
            Composition::open(Path::new("configs/experiment2_adaptive.simulation.xml")).unwrap();
        c.environment = Some(PathBuf::from("configs/environments/stairs.env.xml"));
        let dir = std::env::temp_dir().join(format!("proleg_expert_{}", std::process::id()));
        let path = dir.join("stairs2.simulation.xml");
        let summary = c.check(&path, &ModuleRegistry::standard()).unwrap();
        assert!(summary.contains("tactile5p"), "{summary}");
        c.save(&path, &ModuleRegistry::standard()).unwrap();
        let back = Composition::open(&path).unwrap();
        assert_eq!(
            normalize(&back.environment.clone().unwrap()),
            normalize(
                &std::env::current_dir()
                    .unwrap()
                    .join("configs/environments/stairs.env.xml")
            )
        );
        // A wrong pairing is refused with the file that does not fit.
        c.actuation = PathBuf::from("configs/actuation/snake8py_sine.actuation.xml");
        let e = c.check(&path, &ModuleRegistry::standard()).unwrap_err();
        let ComposeError::Config(e) = e else {
            panic!("not a configuration error: {e}");
        };
        assert!(
            e.file
                .to_string_lossy()
                .contains("snake8py_sine.actuation.xml"),
            "{e}"
        );
        std::fs::remove_dir_all(dir).ok();
    }
}
