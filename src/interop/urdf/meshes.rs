//! Mesh files named by a URDF (`package://`, `file://` or relative paths; OBJ, STL or
//! COLLADA),
//! scaled and written once each as OBJ next to the imported robot.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::config::mesh::TriMesh;
use crate::interop::urdf::options::ImportOptions;
use crate::interop::{InteropError, write_text};

/// Converts and writes the meshes of one import; each (file, scale) once.
pub struct MeshWriter {
    /// The URDF's folder (relative mesh paths start here).
    urdf_dir: PathBuf,
    /// The output folder (meshes go to its `meshes/`).
    out_dir: PathBuf,
    /// Written meshes by source path and scale: their relative name and vertices.
    written: BTreeMap<String, (String, TriMesh)>,
    /// The URDF file (named in errors).
    urdf: PathBuf,
    /// Where ROS looks for packages (`ROS_PACKAGE_PATH`): folders holding packages, or
    /// packages themselves.
    package_path: Vec<PathBuf>,
    /// Packages given by name, looked up first.
    packages: Vec<(String, PathBuf)>,
}

impl MeshWriter {
    /// A writer for the URDF `urdf` imported into `out_dir`, finding `package://` meshes
    /// also where `opts` says (named packages, ROS's `ROS_PACKAGE_PATH`).
    pub fn new(urdf: &Path, out_dir: &Path, opts: &ImportOptions) -> Self {
        MeshWriter {
            urdf_dir: urdf.parent().unwrap_or(Path::new(".")).to_path_buf(),
            out_dir: out_dir.to_path_buf(),
            written: BTreeMap::new(),
            urdf: urdf.to_path_buf(),
            package_path: opts.package_path.clone(),
            packages: opts.packages.clone(),
        }
    }

    /// The URDF file being imported (named in errors).
    pub fn urdf(&self) -> &Path {
        &self.urdf
    }

    /// How many mesh files were written.
    pub fn count(&self) -> usize {
        self.written.len()
    }

    /// The written mesh named `file` (as returned by [`MeshWriter::convert`]).
    pub fn mesh(&self, file: &str) -> Option<&TriMesh> {
        self.written
            .values()
            .find(|(f, _)| f == file)
            .map(|(_, m)| m)
    }

    /// The OBJ (relative to the output folder) holding `filename` scaled by `scale`;
    /// `None` for a format other than OBJ, STL or COLLADA (DAE).
    pub fn convert(
        &mut self,
        filename: &str,
        scale: [f64; 3],
    ) -> Result<Option<String>, InteropError> {
        let source = self.resolve(filename)?;
        let key = format!("{} {scale:?}", source.display());
        if let Some((file, _)) = self.written.get(&key) {
            return Ok(Some(file.clone()));
        }
        let Some(mut mesh) = read_mesh(&source)? else {
            return Ok(None);
        };
        for v in &mut mesh.vertices {
            for k in 0..3 {
                v[k] *= scale[k];
            }
        }
        let stem = source
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "mesh".into());
        let mut file = format!("meshes/{stem}.obj");
        let mut n = 1;
        while self.written.values().any(|(f, _)| *f == file) {
            n += 1;
            file = format!("meshes/{stem}_{n}.obj");
        }
        write_text(
            &self.out_dir.join(&file),
            &mesh.obj_text("written by proleg import (scaled to metres)"),
        )?;
        self.written.insert(key, (file.clone(), mesh));
        Ok(Some(file))
    }

    /// The file a URDF mesh name points to: `package://NAME/rest` is looked for as
    /// `NAME/rest` or `rest` in the URDF's folder and every folder above it, then in the
    /// package path's folders.
    fn resolve(&self, filename: &str) -> Result<PathBuf, InteropError> {
        if let Some(path) = filename.strip_prefix("file://") {
            return Ok(PathBuf::from(path));
        }
        let Some(rest) = filename.strip_prefix("package://") else {
            return Ok(self.urdf_dir.join(filename));
        };
        let (package, inner) = rest.split_once('/').unwrap_or((rest, ""));
        if let Some((_, dir)) = self.packages.iter().find(|(n, _)| n == package) {
            let inside = dir.join(inner);
            return if inside.is_file() {
                Ok(inside)
            } else {
                Err(InteropError::new(
                    &self.urdf,
                    format!(
                        "mesh {filename}: {} does not exist (package \"{package}\" given as {})",
                        inside.display(),
                        dir.display()
                    ),
                ))
            };
        }
        let above = self.urdf_dir.ancestors().map(Path::to_path_buf);
        for dir in above.chain(self.package_path.iter().cloned()) {
            let inside = dir.join(package).join(inner);
            if inside.is_file() {
                return Ok(inside);
            }
            if dir.file_name().is_some_and(|n| n == package) && dir.join(inner).is_file() {
                return Ok(dir.join(inner));
            }
        }
        Err(InteropError::new(
            &self.urdf,
            format!(
                "mesh {filename}: package \"{package}\" not found in the URDF's folder or above, nor in ROS_PACKAGE_PATH ({}); name it with --package-path NAME=DIR",
                if self.package_path.is_empty() {
                    "not set".to_string()
                } else {
                    self.package_path
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect::<Vec<_>>()
                        .join(":")
                }
            ),
        ))
    }
}

/// The triangles of a mesh file in any format URDFs use: OBJ and COLLADA read by the
/// `mesh-loader` crate (every mesh of the file in one, COLLADA's unit and node transforms
/// applied), STL by `stl_io` (mesh-loader takes a binary STL whose header starts with
/// "solid" for ASCII, as bolt's and solo12's feet are). `None` for another format.
fn read_mesh(path: &Path) -> Result<Option<TriMesh>, InteropError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let loader = mesh_loader::Loader::default();
    let collada = match ext.as_str() {
        "stl" => return read_stl(path).map(Some),
        "obj" => false,
        "dae" => true,
        _ => return Ok(None),
    };
    let load = || {
        if collada {
            loader.load_collada(path)
        } else {
            loader.load_obj(path)
        }
    };
    // mesh-loader 0.1's readers index and unwrap what a malformed file lacks (a COLLADA
    // accessor naming a source that is not there panics): a panic there is this file's
    // error, not the end of the program.
    let scene = std::panic::catch_unwind(std::panic::AssertUnwindSafe(load))
        .map_err(|payload| {
            let why = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            InteropError::new(
                path,
                format!("not a readable {ext} mesh (its reader failed: {why})"),
            )
        })?
        .map_err(|e| InteropError::new(path, format!("not a readable {ext} mesh: {e}")))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for m in &scene.meshes {
        let base = vertices.len() as u32;
        vertices.extend(m.vertices.iter().map(|v| v.map(f64::from)));
        triangles.extend(m.faces.iter().map(|f| f.map(|i| base + i)));
    }
    checked(path, vertices, triangles).map(Some)
}

/// A mesh with faces and finite vertices (random_urdfs/168's OBJ holds `v nan nan nan`).
fn checked(
    path: &Path,
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
) -> Result<TriMesh, InteropError> {
    if triangles.is_empty() {
        return Err(InteropError::new(path, "the mesh has no faces"));
    }
    if let Some(k) = vertices
        .iter()
        .position(|v| !v.iter().all(|c| c.is_finite()))
    {
        return Err(InteropError::new(
            path,
            format!("vertex {} is not finite: {:?}", k + 1, vertices[k]),
        ));
    }
    Ok(TriMesh::new(vertices, triangles))
}

fn read_stl(path: &Path) -> Result<TriMesh, InteropError> {
    let mut file = std::fs::File::open(path)
        .map_err(|e| InteropError::new(path, format!("cannot read the mesh: {e}")))?;
    let stl = stl_io::read_stl(&mut file)
        .map_err(|e| InteropError::new(path, format!("not a readable STL file: {e}")))?;
    let vertices = stl
        .vertices
        .iter()
        .map(|v| [v[0], v[1], v[2]].map(f64::from))
        .collect();
    let triangles = stl
        .faces
        .iter()
        .map(|f| f.vertices.map(|i| i as u32))
        .collect::<Vec<_>>();
    checked(path, vertices, triangles)
}
