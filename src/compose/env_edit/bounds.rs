//! Bounds in the environment editor: axis-aligned boxes of shapes, kinbodies and the
//! robot's links, how deep two overlap, and the scene's mesh files read once for them
//! ([`SceneMeshes`], behind a lock so the editor's queries take `&self`).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, Mutex, PoisonError};

use crate::config::body::{Geom, Shape};
use crate::config::mesh::{Meshes, TriMesh};
use crate::config::source::{FsSource, resolve_include};
use crate::config::transform::Pose;

/// An axis-aligned box in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lowest corner (m).
    pub min: [f64; 3],
    /// Highest corner (m).
    pub max: [f64; 3],
}

impl Aabb {
    pub(super) const EMPTY: Aabb = Aabb {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    pub(super) fn add(&mut self, p: [f64; 3]) {
        for ((lo, hi), v) in self.min.iter_mut().zip(&mut self.max).zip(p) {
            *lo = lo.min(v);
            *hi = hi.max(v);
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.min[0] > self.max[0]
    }

    /// Whether (x, y) lies inside the box's footprint.
    pub fn covers(&self, x: f64, y: f64) -> bool {
        !self.is_empty()
            && x >= self.min[0]
            && x <= self.max[0]
            && y >= self.min[1]
            && y <= self.max[1]
    }

    /// Extent along each axis (m).
    pub fn size(&self) -> [f64; 3] {
        if self.is_empty() {
            return [0.0; 3];
        }
        [0, 1, 2].map(|i| self.max[i] - self.min[i])
    }
}

/// How deep (m) an object's bounds may reach into the robot's before the editor warns (the
/// same depth a co-design search rejects a body at).
pub use crate::config::start_clearance::OVERLAP_TOLERANCE;

/// Bounds of a box, sphere or cylinder in its own frame (meshes: see the callers).
pub(super) fn shape_aabb(shape: &Shape) -> Option<Aabb> {
    match shape {
        Shape::Box { extents } => Some(Aabb {
            min: extents.map(|e| -e),
            max: *extents,
        }),
        Shape::Sphere { radius } => Some(Aabb {
            min: [-radius; 3],
            max: [*radius; 3],
        }),
        Shape::Cylinder { radius, height } => Some(Aabb {
            min: [-radius, -height / 2.0, -radius],
            max: [*radius, height / 2.0, *radius],
        }),
        Shape::Trimesh { .. } => None,
    }
}

/// Grows `out` by geometry `g` of a body at `body` whose own-frame bounds are `local`.
pub(super) fn add_geom(out: &mut Aabb, g: &Geom, body: &Pose, local: Option<Aabb>) {
    let Some(local) = local else {
        return;
    };
    let gp = body.mul(&g.pose);
    if let Shape::Sphere { radius } = &g.shape {
        // Turning a sphere changes nothing.
        let t = gp.translation;
        out.add(t.map(|v| v - radius));
        out.add(t.map(|v| v + radius));
        return;
    }
    for k in 0..8 {
        let c = [0, 1, 2].map(|i| {
            if k >> i & 1 == 0 {
                local.min[i]
            } else {
                local.max[i]
            }
        });
        let r = gp.rotate(c);
        out.add([0, 1, 2].map(|i| r[i] + gp.translation[i]));
    }
}

/// The mesh files a scene names, each read once for its bounds; a file that cannot be
/// found or parsed is remembered with its reason.
#[derive(Debug, Default)]
pub struct SceneMeshes(Mutex<MeshCache>);

#[derive(Debug, Default, Clone)]
struct MeshCache {
    meshes: Meshes,
    errors: BTreeMap<String, MeshError>,
}

/// A mesh file a scene names that cannot be drawn or measured.
#[derive(Debug, Clone, thiserror::Error)]
pub enum MeshError {
    /// The file does not read or parse (its located error).
    #[error("{0}")]
    Load(#[from] crate::config::ConfigError),
    /// No such file beside the scene or in a folder above it.
    #[error("{file}: mesh file not found next to {}", scene.display())]
    NotFound {
        /// The file as the scene names it.
        file: String,
        /// The scene file.
        scene: std::path::PathBuf,
    },
}

impl Clone for SceneMeshes {
    fn clone(&self) -> Self {
        SceneMeshes(Mutex::new(self.cache().clone()))
    }
}

impl SceneMeshes {
    fn cache(&self) -> std::sync::MutexGuard<'_, MeshCache> {
        // The cache holds no invariant a panicking reader could break.
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Mesh `file` as named in a scene saved at `scene` (none when it cannot be read: its
    /// error is kept, [`SceneMeshes::errors`]).
    pub fn mesh(&self, scene: &Path, file: &str) -> Option<Arc<TriMesh>> {
        let mut cache = self.cache();
        if file.starts_with(crate::config::terrain::GENERATED_MESH) {
            return cache.meshes.get(file).cloned();
        }
        let loaded = match resolve_include(&FsSource, scene, file) {
            Some(path) => cache.meshes.load(&path).map_err(MeshError::from),
            None => Err(MeshError::NotFound {
                file: file.to_string(),
                scene: scene.to_path_buf(),
            }),
        };
        match loaded {
            Ok(m) => Some(m),
            Err(e) => {
                cache.errors.insert(file.to_string(), e);
                None
            }
        }
    }

    /// Keeps a generated terrain's height field under the name its geometry gives, and
    /// forgets every other generated one not named in `live` (the scene's terrains now:
    /// a slider dragged through a hundred difficulties leaves one course, not a hundred).
    pub fn add_generated(&self, name: String, mesh: Arc<TriMesh>, live: &[String]) {
        let mut cache = self.cache();
        cache.meshes.retain(|file| {
            !file.starts_with(crate::config::terrain::GENERATED_MESH)
                || live.iter().any(|l| l == file)
        });
        cache.meshes.insert(name, mesh);
    }

    /// How many generated height fields are held.
    pub fn generated_count(&self) -> usize {
        self.cache()
            .meshes
            .names()
            .filter(|f| f.starts_with(crate::config::terrain::GENERATED_MESH))
            .count()
    }

    /// Bounds of mesh `file` scaled by `scale` (none when it cannot be read).
    pub fn aabb(&self, scene: &Path, file: &str, scale: f64) -> Option<Aabb> {
        let (min, max) = self.mesh(scene, file)?.bounds();
        Some(Aabb {
            min: min.map(|v| v * scale),
            max: max.map(|v| v * scale),
        })
    }

    /// The mesh files that could not be read, with the reason (file: line).
    pub fn errors(&self) -> Vec<MeshError> {
        self.cache().errors.values().cloned().collect()
    }
}
