//! Triangle meshes for `trimesh` geometries: a small Wavefront OBJ reader (vertices and
//! faces; polygons are fanned into triangles).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use crate::config::error::{ConfigError, ConfigResult, ErrorKind, Pos};

/// The meshes a loaded configuration uses, parsed once at load time and shared (by
/// reference count) by the physics, the viewer and the editor; keyed by the resolved path
/// that `trimesh` geometries name after loading.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Meshes(BTreeMap<String, Arc<TriMesh>>);

impl Meshes {
    /// The mesh of a resolved `trimesh` file name.
    pub fn get(&self, file: &str) -> Option<&Arc<TriMesh>> {
        self.0.get(file)
    }

    /// Adds (or replaces) the mesh read from `file`.
    pub fn insert(&mut self, file: String, mesh: Arc<TriMesh>) {
        self.0.insert(file, mesh);
    }

    /// Adds every mesh of `other` not known yet.
    pub fn extend(&mut self, other: &Meshes) {
        for (k, v) in &other.0 {
            self.0.entry(k.clone()).or_insert_with(|| v.clone());
        }
    }

    /// Reads and parses `path` unless it is known; errors name the file and line.
    pub fn load(&mut self, path: &Path) -> ConfigResult<Arc<TriMesh>> {
        let key = path.display().to_string();
        if let Some(m) = self.0.get(&key) {
            return Ok(m.clone());
        }
        let text = std::fs::read_to_string(path).map_err(|e| {
            ConfigError::new(
                path,
                Pos::new(0, 0),
                ErrorKind::MissingFile,
                format!("cannot read the mesh: {e}"),
            )
        })?;
        let mesh = Arc::new(parse_obj(path, &text)?);
        self.0.insert(key, mesh.clone());
        Ok(mesh)
    }
}

/// A triangle mesh in the units of its file.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in &self.vertices {
            for i in 0..3 {
                lo[i] = lo[i].min(v[i]);
                hi[i] = hi[i].max(v[i]);
            }
        }
        (lo, hi)
    }
}

/// Parses OBJ text; errors name the line.
pub fn parse_obj(file: &Path, text: &str) -> ConfigResult<TriMesh> {
    let mut mesh = TriMesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    let err = |line: usize, msg: String| {
        ConfigError::new(
            file,
            Pos::new(line as u32 + 1, 1),
            ErrorKind::InvalidValue,
            msg,
        )
    };
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let v: Vec<f64> = words
                    .take(3)
                    .map(|w| w.parse::<f64>().ok().filter(|x| x.is_finite()))
                    .collect::<Option<_>>()
                    .ok_or_else(|| err(i, "vertex: expected 3 finite numbers".into()))?;
                let v: [f64; 3] = v
                    .try_into()
                    .map_err(|_| err(i, "vertex: expected 3 numbers".into()))?;
                mesh.vertices.push(v);
            }
            Some("f") => {
                let idx: Vec<u32> = words
                    .map(|w| {
                        let first = w.split('/').next().unwrap_or("");
                        let n: i64 = first
                            .parse()
                            .map_err(|_| err(i, format!("face: bad vertex index \"{w}\"")))?;
                        let count = mesh.vertices.len() as i64;
                        let k = if n < 0 { count + n } else { n - 1 };
                        if k < 0 || k >= count {
                            return Err(err(
                                i,
                                format!("face: vertex index {n} out of range (1..{count})"),
                            ));
                        }
                        Ok(k as u32)
                    })
                    .collect::<ConfigResult<_>>()?;
                if idx.len() < 3 {
                    return Err(err(i, "face: needs at least 3 vertices".into()));
                }
                for k in 1..idx.len() - 1 {
                    mesh.triangles.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if mesh.triangles.is_empty() {
        return Err(ConfigError::new(
            file,
            Pos::new(1, 1),
            ErrorKind::InvalidValue,
            "the mesh has no faces",
        ));
    }
    Ok(mesh)
}
