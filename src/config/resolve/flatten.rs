//! Flattens a `<KinBody>` and the part files it includes into one list of bodies, joints
//! and sensors, with names prefixed and poses composed. Detects missing files and
//! include cycles.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::config::body::{Body, Geom, MeshCollision, Shape};
use crate::config::error::{ConfigError, ConfigResult, ErrorKind, Pos};
use crate::config::kinbody::{Include, Joint, KinBody, parse_kinbody_file};
use crate::config::mesh::{Meshes, parse_obj};
use crate::config::sensor::AttachedSensor;
use crate::config::source::{FileSource, resolve_include};
use crate::config::terrain::GENERATED_MESH;
use crate::config::transform::Pose;

/// A body placed in the frame of the flattened kinbody.
#[derive(Debug, Clone)]
pub struct PlacedBody {
    /// The body.
    pub body: Body,
    /// Its placement in the flattened kinbody.
    pub world: Pose,
    /// The file it came from.
    pub file: PathBuf,
}

/// A joint with prefixed body names, and where it was written.
#[derive(Debug, Clone)]
pub struct PlacedJoint {
    /// The joint, names prefixed.
    pub joint: Joint,
    /// The file it came from.
    pub file: PathBuf,
}

/// A sensor with its prefixed link name, and where it was written.
#[derive(Debug, Clone)]
pub struct PlacedSensor {
    /// The sensor, link name prefixed.
    pub sensor: AttachedSensor,
    /// The file it came from.
    pub file: PathBuf,
}

/// Everything a kinbody expands to.
#[derive(Debug, Clone, Default)]
pub struct Flat {
    /// Every body.
    pub bodies: Vec<PlacedBody>,
    /// Every joint.
    pub joints: Vec<PlacedJoint>,
    /// Every sensor.
    pub sensors: Vec<PlacedSensor>,
    /// Every file read (parts, meshes), in order.
    pub files: Vec<PathBuf>,
    /// The meshes of `trimesh` geometries, parsed.
    pub meshes: Meshes,
}

/// Flattens kinbodies, reading included files from a [`FileSource`].
pub struct Flattener<'a> {
    /// Where included files are read from.
    pub src: &'a dyn FileSource,
    stack: Vec<PathBuf>,
    /// What was flattened so far.
    pub out: Flat,
}

impl<'a> Flattener<'a> {
    /// A flattener of the kinbody in `root_file`.
    pub fn new(src: &'a dyn FileSource, root_file: &Path) -> Self {
        Flattener {
            src,
            stack: vec![root_file.to_path_buf()],
            out: Flat::default(),
        }
    }

    /// Adds `kb` (written in `file`) with `prefix`, placed by `placement`.
    pub fn add(
        &mut self,
        kb: &KinBody,
        file: &Path,
        prefix: &str,
        placement: &Pose,
    ) -> ConfigResult<()> {
        let tf = placement.mul(&kb.pose);
        for inc in &kb.includes {
            self.include(inc, file, prefix, &tf)?;
        }
        for b in &kb.bodies {
            let mut body = b.clone();
            body.name = format!("{prefix}{}", b.name);
            if let Some(other) = self.out.bodies.iter().find(|o| o.body.name == body.name) {
                return Err(ConfigError::new(
                    file,
                    b.pos,
                    ErrorKind::InvalidValue,
                    format!(
                        "body name \"{}\" is used twice (also in {}:{}); give the part a different prefix",
                        body.name,
                        other.file.display(),
                        other.body.pos
                    ),
                ));
            }
            for g in &mut body.geoms {
                self.resolve_mesh(g, file)?;
            }
            let world = tf.mul(&b.pose);
            self.out.bodies.push(PlacedBody {
                body,
                world,
                file: file.to_path_buf(),
            });
        }
        for j in &kb.joints {
            let mut joint = j.clone();
            joint.name = format!("{prefix}{}", j.name);
            for b in &mut joint.bodies {
                *b = format!("{prefix}{b}");
            }
            if let Some(o) = &mut joint.offset_from {
                *o = format!("{prefix}{o}");
            }
            self.out.joints.push(PlacedJoint {
                joint,
                file: file.to_path_buf(),
            });
        }
        for s in &kb.sensors {
            let mut sensor = s.clone();
            sensor.name = format!("{prefix}{}", s.name);
            sensor.link = format!("{prefix}{}", s.link);
            self.out.sensors.push(PlacedSensor {
                sensor,
                file: file.to_path_buf(),
            });
        }
        Ok(())
    }

    /// Reads an included part file and adds it.
    pub fn include(
        &mut self,
        inc: &Include,
        file: &Path,
        prefix: &str,
        placement: &Pose,
    ) -> ConfigResult<()> {
        let path = find_file(self.src, file, &inc.file, inc.pos, "kinbody part")?;
        if let Some(i) = self.stack.iter().position(|p| *p == path) {
            let chain: Vec<String> = self.stack[i..]
                .iter()
                .chain([&path])
                .map(|p| p.display().to_string())
                .collect();
            return Err(ConfigError::new(
                file,
                inc.pos,
                ErrorKind::IncludeCycle,
                format!("include cycle: {}", chain.join(" -> ")),
            ));
        }
        let text = read_file(self.src, &path, file, inc.pos)?;
        let part = parse_kinbody_file(&path.display().to_string(), &text)
            .map_err(|e| e.included_from(file, inc.pos))?;
        self.stack.push(path.clone());
        self.out.files.push(path.clone());
        let tf = placement.mul(&inc.pose);
        let result = self.add(&part, &path, &format!("{prefix}{}", inc.prefix), &tf);
        self.stack.pop();
        result.map_err(|e| e.included_from(file, inc.pos))
    }

    /// Replaces a mesh's file name by the resolved path and keeps the parsed mesh; a
    /// heightfield's mesh must be a height map.
    fn resolve_mesh(&mut self, g: &mut Geom, file: &Path) -> ConfigResult<()> {
        if let Shape::Trimesh {
            file: mesh,
            collision,
            ..
        } = &mut g.shape
        {
            if mesh.starts_with(GENERATED_MESH) && self.out.meshes.get(mesh).is_some() {
                // A generated terrain's height field: in memory, a height map by making.
                return Ok(());
            }
            let path = find_file(self.src, file, mesh, g.pos, "mesh")?;
            let key = path.display().to_string();
            if self.out.meshes.get(&key).is_none() {
                let text = read_file(self.src, &path, file, g.pos)?;
                let parsed = parse_obj(&path, &text).map_err(|e| e.included_from(file, g.pos))?;
                self.out.meshes.insert(key.clone(), Arc::new(parsed));
            }
            if *collision == MeshCollision::HeightField
                && let Some(Err(why)) = self.out.meshes.get(&key).map(|m| m.height_map())
            {
                return Err(ConfigError::new(
                    file,
                    g.pos,
                    ErrorKind::InvalidValue,
                    format!("{} cannot be a heightfield: {why}", path.display()),
                ));
            }
            *mesh = key;
            self.out.files.push(path);
        }
        Ok(())
    }
}

/// Resolves an included path or fails with a missing-file error at `pos` of `from`.
pub fn find_file(
    src: &dyn FileSource,
    from: &Path,
    written: &str,
    pos: Pos,
    what: &str,
) -> ConfigResult<PathBuf> {
    if written.trim().is_empty() {
        return Err(ConfigError::new(
            from,
            pos,
            ErrorKind::Missing,
            format!("the {what} file name is empty"),
        ));
    }
    resolve_include(src, from, written).ok_or_else(|| {
        let dir = from
            .parent()
            .map(|d| d.display().to_string())
            .unwrap_or_default();
        ConfigError::new(
            from,
            pos,
            ErrorKind::MissingFile,
            format!(
                "{what} file \"{written}\" not found (looked in {dir} and the folders above it)"
            ),
        )
    })
}

/// Reads a file, or fails with a missing-file error at `pos` of `from`.
pub fn read_file(src: &dyn FileSource, path: &Path, from: &Path, pos: Pos) -> ConfigResult<String> {
    src.read(path).map_err(|e| {
        ConfigError::new(
            from,
            pos,
            ErrorKind::MissingFile,
            format!("cannot read {}: {e}", path.display()),
        )
        .caused_by(e)
    })
}
