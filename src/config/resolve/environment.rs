//! The resolved environment: physics properties, every object flattened into placed
//! static or dynamic bodies (a procedural terrain generated into its bodies first), and
//! the robot's start pose.

use std::path::{Path, PathBuf};

use crate::config::body::{BodyKind, Geom};
use crate::config::environment::{EnvObject, EnvironmentFile, Physics};
use crate::config::error::{ConfigError, ConfigResult, ErrorKind};
use crate::config::mesh::Meshes;
use crate::config::resolve::flatten::Flattener;
use crate::config::resolve::robot::{DEFAULT_DENSITY, geom_volume};
use crate::config::source::{FileSource, FsSource};
use crate::config::suite::Task;
use crate::config::transform::Pose;

/// One body of the environment, placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvBody {
    /// The body's name.
    pub name: String,
    /// Static or dynamic.
    pub kind: BodyKind,
    /// Placement in the world.
    pub pose: Pose,
    /// Its geometries.
    pub geoms: Vec<Geom>,
    /// kg; only meaningful for dynamic bodies.
    pub mass: f64,
}

/// An environment ready to be simulated.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvironmentModel {
    /// The environment file, if any.
    pub file: Option<PathBuf>,
    /// Gravity, self-collision, default friction.
    pub physics: Physics,
    /// The bodies.
    pub bodies: Vec<EnvBody>,
    /// The robot's start pose.
    pub robot_pose: Pose,
    /// Every file read to build it.
    pub files: Vec<PathBuf>,
    /// The meshes its `trimesh` geometries name, parsed.
    pub meshes: Meshes,
}

impl EnvironmentModel {
    /// No file: gravity on, nothing to stand on.
    pub fn empty() -> Self {
        EnvironmentModel {
            file: None,
            physics: Physics::default(),
            bodies: Vec::new(),
            robot_pose: Pose::IDENTITY,
            files: Vec::new(),
            meshes: Meshes::default(),
        }
    }
}

/// `task`'s course of terrain seed `seed` as a world with `scenery`'s physics properties
/// and start pose (its objects replaced by the course). `suite` is the suite file (what
/// errors name).
pub fn course_environment(
    task: &Task,
    scenery: &EnvironmentModel,
    seed: u64,
    suite: &Path,
) -> ConfigResult<EnvironmentModel> {
    let env = EnvironmentFile {
        physics: scenery.physics.clone(),
        objects: vec![EnvObject::Terrain(task.course(seed))],
        robot_pose: Some(scenery.robot_pose),
    };
    resolve_environment(&FsSource, suite, &env)
}

/// Builds the environment model from a parsed environment file at `path`.
pub fn resolve_environment(
    src: &dyn FileSource,
    path: &Path,
    file: &EnvironmentFile,
) -> ConfigResult<EnvironmentModel> {
    let mut fl = Flattener::new(src, path);
    fl.out.files.push(path.to_path_buf());
    for o in &file.objects {
        match o {
            EnvObject::Inline(kb) => fl.add(kb, path, "", &Pose::IDENTITY)?,
            EnvObject::Include(inc) => fl.include(inc, path, "", &Pose::IDENTITY)?,
            EnvObject::Terrain(spec) => {
                let generated = crate::config::terrain::generate(spec);
                for (name, mesh) in generated.meshes {
                    fl.out.meshes.insert(name, mesh);
                }
                fl.add(&generated.kinbody, path, "", &Pose::IDENTITY)?
            }
        }
    }
    if let Some(j) = fl.out.joints.first() {
        return Err(ConfigError::new(
            &j.file,
            j.joint.pos,
            ErrorKind::UnknownElement,
            "joints in environment objects are not supported",
        ));
    }
    if let Some(s) = fl.out.sensors.first() {
        return Err(ConfigError::new(
            &s.file,
            s.sensor.pos,
            ErrorKind::UnknownElement,
            "sensors belong to robots, not environments",
        ));
    }
    let bodies = fl
        .out
        .bodies
        .iter()
        .map(|pb| EnvBody {
            name: pb.body.name.clone(),
            kind: pb.body.kind,
            pose: pb.world,
            geoms: pb.body.geoms.clone(),
            mass: pb.body.mass.as_ref().map(|m| m.total).unwrap_or_else(|| {
                pb.body.geoms.iter().map(geom_volume).sum::<f64>().max(1e-6) * DEFAULT_DENSITY
            }),
        })
        .collect();
    let meshes = fl.out.meshes;
    let mut files = fl.out.files;
    files.sort();
    files.dedup();
    Ok(EnvironmentModel {
        file: Some(path.to_path_buf()),
        physics: file.physics.clone(),
        bodies,
        robot_pose: file.robot_pose.unwrap_or(Pose::IDENTITY),
        files,
        meshes,
    })
}
