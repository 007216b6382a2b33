//! `proleg terrain FAMILY --difficulty D --seed S -o FILE`: one generated course written out
//! as an ordinary environment file — its boxes and cylinders inline, a height field's OBJ
//! beside it — for whoever wants to edit it by hand; or, with `--element`, the one
//! `<Terrain>` element that regenerates it when the file is loaded.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::config::body::Shape;
use crate::config::environment::{EnvObject, EnvironmentFile, Physics, write_environment_file};
use crate::config::terrain::spec::{DEFAULT_LENGTH, DEFAULT_WIDTH};
use crate::config::terrain::{Family, TerrainError, TerrainSpec, Tier, generate};
use crate::config::transform::Pose;

/// Command-line options of `proleg terrain`.
#[derive(clap::Args)]
pub struct TerrainArgs {
    /// The family: rough, hills, steps, stairs, slope, pegs, channel, rubble.
    pub family: String,
    /// 0 (gentlest) to 1 (hardest), or a tier: easy (0.2), medium (0.5), hard (0.8).
    #[arg(long, default_value = "medium")]
    pub difficulty: String,
    /// The seed of its random sizes and places.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Metres of course ahead of the start.
    #[arg(long, default_value_t = DEFAULT_LENGTH)]
    pub length: f64,
    /// Metres across.
    #[arg(long, default_value_t = DEFAULT_WIDTH)]
    pub width: f64,
    /// The environment file to write (`*.env.xml`).
    #[arg(short = 'o', long = "out")]
    pub out: PathBuf,
    /// Write the `<Terrain>` element instead of its bodies.
    #[arg(long)]
    pub element: bool,
}

/// Why a terrain cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum TerrainCommandError {
    /// A family that is none of the known ones.
    #[error("{0}")]
    Family(#[from] crate::config::error::UnknownName),
    /// A difficulty that is neither a number nor a tier.
    #[error("difficulty {0:?} is neither a number in [0, 1] nor easy, medium or hard")]
    Difficulty(String),
    /// Numbers out of range, or a course too big.
    #[error("{0}")]
    Terrain(#[from] TerrainError),
    /// A file that cannot be written.
    #[error("{0}")]
    Write(#[from] crate::config::bundle::BundleError),
}

/// What was written.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainReport {
    /// The course.
    pub spec: TerrainSpec,
    /// The environment file.
    pub file: PathBuf,
    /// The height field's OBJ, when the course has one and its bodies were written.
    pub mesh: Option<PathBuf>,
    /// Static bodies (0 when the element was written).
    pub bodies: usize,
}

impl fmt::Display for TerrainReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "wrote {}: {} ({} m x {} m",
            self.file.display(),
            self.spec.label(),
            self.spec.length,
            self.spec.width
        )?;
        if self.bodies > 0 {
            write!(f, ", {} static bodies", self.bodies)?;
        }
        writeln!(f, ")")?;
        if let Some(m) = &self.mesh {
            writeln!(f, "wrote {} (its height field)", m.display())?;
        }
        Ok(())
    }
}

/// The spec the options name, checked.
pub fn spec(a: &TerrainArgs) -> Result<TerrainSpec, TerrainCommandError> {
    let family = Family::parse(&a.family)?;
    let difficulty = match Tier::parse(&a.difficulty) {
        Some(t) => t.difficulty(),
        None => a
            .difficulty
            .trim()
            .parse::<f64>()
            .map_err(|_| TerrainCommandError::Difficulty(a.difficulty.clone()))?,
    };
    let spec = TerrainSpec {
        length: a.length,
        width: a.width,
        ..TerrainSpec::new(family, difficulty, a.seed)
    };
    spec.check()?;
    Ok(spec)
}

/// Writes the course the options name.
pub fn run(a: &TerrainArgs) -> Result<TerrainReport, TerrainCommandError> {
    let spec = spec(a)?;
    let mut env = EnvironmentFile {
        physics: Physics {
            self_collision: true,
            ..Physics::default()
        },
        objects: Vec::new(),
        robot_pose: Some(Pose::IDENTITY),
    };
    let mut report = TerrainReport {
        spec: spec.clone(),
        file: a.out.clone(),
        mesh: None,
        bodies: 0,
    };
    if a.element {
        env.objects.push(EnvObject::Terrain(spec));
    } else {
        let mut generated = generate(&spec);
        report.bodies = generated.kinbody.bodies.len();
        if let Some((_, mesh)) = generated.meshes.first() {
            let path = mesh_path(&a.out);
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let header = format!("proleg terrain: {}", spec.label());
            crate::config::bundle::write_file(&path, &mesh.obj_text(&header))?;
            for g in generated
                .kinbody
                .bodies
                .iter_mut()
                .flat_map(|b| &mut b.geoms)
            {
                if let Shape::Trimesh { file, .. } = &mut g.shape {
                    file.clone_from(&name);
                }
            }
            report.mesh = Some(path);
        }
        env.objects.push(EnvObject::Inline(generated.kinbody));
    }
    crate::config::bundle::write_file(&a.out, &write_environment_file(&env))?;
    Ok(report)
}

/// The OBJ beside `out`: `pegs.env.xml` -> `pegs.terrain.obj`.
fn mesh_path(out: &Path) -> PathBuf {
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "terrain".into());
    let stem = name
        .strip_suffix(".env.xml")
        .or_else(|| name.strip_suffix(".xml"))
        .unwrap_or(&name);
    out.with_file_name(format!("{stem}.terrain.obj"))
}
