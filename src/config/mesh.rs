//! Triangle meshes for `trimesh` and `heightfield` geometries: a small Wavefront OBJ reader
//! (vertices and faces; polygons are fanned into triangles) and writer, and the test that a
//! mesh is a height map.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, OnceLock};

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

    /// Keeps only the meshes whose file name `keep` accepts.
    pub fn retain(&mut self, mut keep: impl FnMut(&str) -> bool) {
        self.0.retain(|file, _| keep(file));
    }

    /// The file names held.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.0.keys().map(String::as_str)
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
            .caused_by(e)
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
    /// [`TriMesh::height_map`], worked out on first use (the load check) and shared by
    /// every world built from the mesh.
    height_map: OnceLock<Result<HeightMap, NotAHeightMap>>,
}

impl TriMesh {
    /// A mesh of these vertices and triangles (indices into `vertices`).
    pub fn new(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Self {
        TriMesh {
            vertices,
            triangles,
            height_map: OnceLock::new(),
        }
    }

    /// The mesh as OBJ text, vertices to 1 µm, under a `# header` comment line.
    pub fn obj_text(&self, header: &str) -> String {
        let vertices = self
            .vertices
            .iter()
            .map(|v| format!("v {:.6} {:.6} {:.6}\n", v[0], v[1], v[2]));
        let faces = self
            .triangles
            .iter()
            .map(|t| format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
        std::iter::once(format!("# {header}\n"))
            .chain(vertices)
            .chain(faces)
            .collect()
    }

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

/// A mesh's top surface sampled on its regular x-y grid (see [`TriMesh::height_map`]).
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    /// Smallest and largest x of the grid.
    pub x: [f64; 2],
    /// Smallest and largest y of the grid.
    pub y: [f64; 2],
    /// Grid nodes along x.
    pub nx: usize,
    /// Grid nodes along y.
    pub ny: usize,
    /// Height of node `(i, j)` (i along x, j along y) at `j * nx + i`: the highest vertex
    /// there.
    pub heights: Vec<f64>,
}

impl HeightMap {
    /// Height of node `i` along x, `j` along y.
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.heights[j * self.nx + i]
    }
}

/// Why a mesh is not a height map.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NotAHeightMap {
    /// All vertices on one row or column.
    #[error("its vertices do not span an x-y grid (one row or column)")]
    OneRow,
    /// Fewer vertices than grid nodes.
    #[error(
        "{vertices} vertices cannot fill its {nx} x {ny} x-y grid: some grid nodes have no vertex"
    )]
    TooFewVertices {
        /// Vertices of the mesh.
        vertices: usize,
        /// Grid nodes along x.
        nx: usize,
        /// Grid nodes along y.
        ny: usize,
    },
    /// A vertex between grid nodes.
    #[error("vertex ({}, {}) is off the evenly spaced x-y grid ({nx} x {ny} nodes)", at[0], at[1])]
    OffGrid {
        /// The vertex's x and y.
        at: [f64; 2],
        /// Grid nodes along x.
        nx: usize,
        /// Grid nodes along y.
        ny: usize,
    },
    /// A grid node without a vertex.
    #[error("grid node ({}, {}) has no vertex", at[0], at[1])]
    EmptyNode {
        /// The node's x and y.
        at: [f64; 2],
    },
}

/// The sorted distinct values of `values`, merged within `eps`.
fn distinct(mut values: Vec<f64>, eps: f64) -> Vec<f64> {
    values.sort_by(f64::total_cmp);
    values.dedup_by(|b, a| (*b - *a).abs() <= eps);
    values
}

/// Index of `v` among `grid` (evenly spaced from `grid[0]` by `step`), if it lies on a node.
fn node(grid: &[f64], step: f64, v: f64, eps: f64) -> Option<usize> {
    let k = ((v - grid[0]) / step).round();
    (k >= 0.0 && (k as usize) < grid.len() && (grid[0] + k * step - v).abs() <= eps)
        .then_some(k as usize)
}

impl TriMesh {
    /// The mesh as a height map: every vertex lies on one regular grid in x and y (nodes
    /// evenly spaced along each axis, every node holding a vertex), and the height of a
    /// node is its highest vertex, so walls and a base below the surface are allowed. An
    /// error says why it is not one. Worked out once per mesh.
    pub fn height_map(&self) -> Result<&HeightMap, &NotAHeightMap> {
        self.height_map.get_or_init(|| self.grid_heights()).as_ref()
    }

    /// [`TriMesh::height_map`], worked out.
    fn grid_heights(&self) -> Result<HeightMap, NotAHeightMap> {
        let ([x0, y0, _], [x1, y1, _]) = self.bounds();
        let eps = 1e-5 * (x1 - x0).max(y1 - y0).max(1e-9);
        let xs = distinct(self.vertices.iter().map(|v| v[0]).collect(), eps);
        let ys = distinct(self.vertices.iter().map(|v| v[1]).collect(), eps);
        let (nx, ny) = (xs.len(), ys.len());
        if nx < 2 || ny < 2 {
            return Err(NotAHeightMap::OneRow);
        }
        if nx.saturating_mul(ny) > self.vertices.len() {
            return Err(NotAHeightMap::TooFewVertices {
                vertices: self.vertices.len(),
                nx,
                ny,
            });
        }
        let (dx, dy) = ((x1 - x0) / (nx - 1) as f64, (y1 - y0) / (ny - 1) as f64);
        let mut heights = vec![f64::NEG_INFINITY; nx * ny];
        for v in &self.vertices {
            let (Some(i), Some(j)) = (node(&xs, dx, v[0], eps), node(&ys, dy, v[1], eps)) else {
                return Err(NotAHeightMap::OffGrid {
                    at: [v[0], v[1]],
                    nx,
                    ny,
                });
            };
            let h = &mut heights[j * nx + i];
            *h = h.max(v[2]);
        }
        if let Some(k) = heights.iter().position(|h| h.is_infinite()) {
            return Err(NotAHeightMap::EmptyNode {
                at: [xs[k % nx], ys[k / nx]],
            });
        }
        Ok(HeightMap {
            x: [x0, x1],
            y: [y0, y1],
            nx,
            ny,
            heights,
        })
    }
}

/// Parses OBJ text; errors name the line.
pub fn parse_obj(file: &Path, text: &str) -> ConfigResult<TriMesh> {
    let mut mesh = TriMesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
        height_map: OnceLock::new(),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 x 2 grid (x 0, 0.5, 1; y 2, 3) with heights x + y / 10, walls down to 0 under
    /// the edge nodes.
    fn grid_with_walls() -> TriMesh {
        let mut vertices = Vec::new();
        for y in [2.0, 3.0] {
            for x in [0.0, 0.5, 1.0] {
                vertices.push([x, y, x + y / 10.0]);
                vertices.push([x, y, 0.0]);
            }
        }
        TriMesh {
            vertices,
            triangles: vec![[0, 2, 6]],
            height_map: OnceLock::new(),
        }
    }

    #[test]
    fn a_grid_with_walls_is_a_height_map_of_its_top() {
        let mesh = grid_with_walls();
        let m = mesh.height_map().unwrap();
        assert_eq!((m.nx, m.ny, m.x, m.y), (3, 2, [0.0, 1.0], [2.0, 3.0]));
        assert!((m.at(2, 1) - 1.3).abs() < 1e-12, "{m:?}");
        assert!((m.at(1, 0) - 0.7).abs() < 1e-12, "{m:?}");
    }

    #[test]
    fn uneven_spacing_or_a_missing_node_is_not() {
        let mut uneven = grid_with_walls();
        for v in &mut uneven.vertices {
            if v[0] == 0.5 {
                v[0] = 0.4;
            }
        }
        let e = uneven.height_map().unwrap_err();
        assert!(matches!(e, NotAHeightMap::OffGrid { .. }), "{e}");
        let mut holed = grid_with_walls();
        holed.vertices.retain(|v| !(v[0] == 1.0 && v[1] == 3.0));
        let e = holed.height_map().unwrap_err();
        assert_eq!(e, &NotAHeightMap::EmptyNode { at: [1.0, 3.0] });
    }
}
