//! MJCF geometry: shapes, placement, friction and contact filtering of one geom, and the
//! mesh and height-field assets they name.

use std::fmt::Write as _;

use crate::config::Simulation;
use crate::config::body::{Geom, MeshCollision, Shape};
use crate::config::transform::{Pose, round_to};
use crate::config::xml::write::XmlWriter;
use crate::sim::engine::LINK_FRICTION;
use crate::sim::engine::mujoco::MujocoError;
use crate::sim::engine::mujoco::mjcf::contact;

/// Which side of a contact a geom is on.
#[derive(Debug, Clone, Copy)]
pub enum Collision {
    /// Terrain (environment) geometry with its friction.
    Terrain {
        /// Coulomb coefficient.
        friction: f64,
    },
    /// A link of robot `robot` of the batch; with or without collisions among the
    /// robot's links.
    Link {
        /// Index in the batch (its collision bit is `1 << (robot + 1)`).
        robot: usize,
        /// Whether non-neighbouring links collide.
        self_collision: bool,
    },
}

/// The mesh and height-field assets of a model: each file once.
#[derive(Debug, Default)]
pub struct Assets {
    /// `(resolved file, scale, as height field)` in order of first use.
    files: Vec<(String, f64, bool)>,
    /// Where MuJoCo differs by construction.
    pub notes: Vec<String>,
}

impl Assets {
    /// Every mesh and height field the simulation's geometry names.
    pub fn collect(sim: &Simulation) -> Assets {
        let mut a = Assets::default();
        let env = sim
            .environment
            .bodies
            .iter()
            .flat_map(|b| b.geoms.iter().map(|g| (g, true)));
        let links = sim
            .robot
            .links
            .iter()
            .flat_map(|l| l.geoms.iter().map(|g| (g, false)));
        for (g, terrain) in env.chain(links) {
            if let Shape::Trimesh {
                file,
                scale,
                collision,
            } = &g.shape
            {
                let field = *collision == MeshCollision::HeightField && terrain;
                if a.index(file, *scale, field).is_none() {
                    if *collision == MeshCollision::Triangles {
                        a.notes.push(format!(
                            "mesh {file}: MuJoCo collides with its convex hull, proleg with its triangles"
                        ));
                    }
                    a.files.push((file.clone(), *scale, field));
                }
            }
        }
        a
    }

    fn index(&self, file: &str, scale: f64, field: bool) -> Option<usize> {
        self.files
            .iter()
            .position(|(f, s, h)| f == file && *s == scale && *h == field)
    }

    /// How many assets there are.
    pub fn count(&self) -> usize {
        self.files.len()
    }

    /// The `<asset>` section.
    pub fn write(&self, w: &mut XmlWriter, sim: &Simulation) -> Result<(), MujocoError> {
        if self.files.is_empty() {
            return Ok(());
        }
        w.open("asset", &[]);
        for (k, (file, scale, field)) in self.files.iter().enumerate() {
            if *field {
                let map = height_map(sim, file)?;
                let (lo, hi) = min_max(&map.heights);
                // MuJoCo's first elevation row is the field's +y edge (as an image's top
                // row), ours the -y edge: rows go in reverse.
                let mut elevation = String::new();
                for row in map.heights.chunks(map.nx.max(1)).rev() {
                    for h in row {
                        let _ = write!(elevation, "{} ", round_to(h - lo, 1e9));
                    }
                }
                w.empty(
                    "hfield",
                    &[
                        ("name", format!("field{k}")),
                        ("nrow", map.ny.to_string()),
                        ("ncol", map.nx.to_string()),
                        (
                            "size",
                            mj(&[
                                (map.x[1] - map.x[0]) / 2.0 * scale,
                                (map.y[1] - map.y[0]) / 2.0 * scale,
                                ((hi - lo) * scale).max(1e-6),
                                0.1,
                            ]),
                        ),
                        ("elevation", elevation.trim_end().to_string()),
                    ],
                );
            } else {
                w.empty("mesh", &mesh_attrs(sim, k, file, *scale)?);
            }
        }
        w.close();
        Ok(())
    }
}

fn height_map(sim: &Simulation, file: &str) -> Result<crate::config::mesh::HeightMap, MujocoError> {
    let err = |cause: String| MujocoError::Mesh {
        file: file.to_string(),
        cause,
    };
    let mesh = sim
        .mesh(file)
        .ok_or_else(|| err("not among the loaded meshes".into()))?;
    mesh.height_map()
        .cloned()
        .map_err(|why| err(format!("not a height map: {why}")))
}

fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        })
}

/// Numbers for people: rounded to 1e-9 (float noise such as 0.07200000000000001 goes).
pub fn mj(v: &[f64]) -> String {
    let rounded: Vec<f64> = v.iter().map(|x| round_to(*x, 1e9)).collect();
    crate::config::xml::write::nums(&rounded)
}

/// A mesh path MuJoCo finds wherever the model is opened from.
/// A `<mesh>` asset: the OBJ file it was read from, or for a mesh made in memory (no such
/// file: the terrain of a physical check) its vertices and faces inline.
fn mesh_attrs(
    sim: &Simulation,
    k: usize,
    file: &str,
    scale: f64,
) -> Result<Vec<(&'static str, String)>, MujocoError> {
    let mut a = vec![("name", format!("mesh{k}")), ("scale", mj(&[scale; 3]))];
    if std::path::Path::new(file).is_file() {
        a.push(("file", absolute(file)));
        return Ok(a);
    }
    let mesh = sim.mesh(file).ok_or_else(|| MujocoError::Mesh {
        file: file.to_string(),
        cause: "neither a file nor among the loaded meshes".into(),
    })?;
    let vertices: Vec<f64> = mesh.vertices.iter().flatten().copied().collect();
    let faces: Vec<String> = mesh
        .triangles
        .iter()
        .flatten()
        .map(u32::to_string)
        .collect();
    a.push(("vertex", mj(&vertices)));
    a.push(("face", faces.join(" ")));
    Ok(a)
}

fn absolute(file: &str) -> String {
    std::path::absolute(file)
        .map(|p| p.display().to_string())
        .unwrap_or_else(|_| file.to_string())
}

/// `pos` and `quat` of a pose (MuJoCo's quaternions are `w x y z`, as ours).
pub fn pose_attrs(p: &Pose) -> Vec<(&'static str, String)> {
    vec![("pos", mj(&p.translation)), ("quat", mj(&p.rotation))]
}

/// A geom's contact attributes: friction, priority and its collision bits. Terrain is
/// collision bit 1, robot r of a batch bit 1 << (r + 1): MuJoCo pairs two geoms when one's
/// contype meets the other's conaffinity, so every robot meets the terrain, none meets
/// another robot, and a robot meets itself only with self-collision.
fn contact_attrs(
    sim: &Simulation,
    collision: Collision,
) -> Result<Vec<(&'static str, String)>, MujocoError> {
    let model = sim.environment.physics.contact_model();
    let (friction, priority, contype, conaffinity) = match collision {
        Collision::Terrain { friction } => {
            (friction, contact::priority(&model, Some(friction))?, 1, 1)
        }
        Collision::Link {
            robot,
            self_collision,
        } => {
            let bit = 1u32 << (robot + 1);
            (
                LINK_FRICTION,
                contact::priority(&model, None)?,
                bit,
                if self_collision { 1 | bit } else { 1 },
            )
        }
    };
    Ok(vec![
        ("friction", mj(&[friction, 0.005, 0.0001])),
        ("priority", priority.to_string()),
        ("contype", contype.to_string()),
        ("conaffinity", conaffinity.to_string()),
    ])
}

/// The attributes of one geom; `mass` when the body's mass is spread over its geometry.
pub fn geom_attrs(
    g: &Geom,
    sim: &Simulation,
    assets: &Assets,
    collision: Collision,
    mass: Option<f64>,
) -> Result<Vec<(&'static str, String)>, MujocoError> {
    let mut at = g.pose;
    let mut a: Vec<(&'static str, String)> = Vec::new();
    match &g.shape {
        Shape::Box { extents } => {
            a.push(("type", "box".into()));
            a.push(("size", mj(extents)));
        }
        Shape::Sphere { radius } => {
            a.push(("type", "sphere".into()));
            a.push(("size", mj(&[*radius])));
        }
        Shape::Cylinder { radius, height } => {
            // Ours stand along y, MuJoCo's along z: turn z onto y (-90 degrees about x).
            let half = std::f64::consts::FRAC_PI_4;
            let turn = Pose {
                translation: [0.0; 3],
                rotation: [half.cos(), -half.sin(), 0.0, 0.0],
            };
            at = g.pose.mul(&turn);
            a.push(("type", "cylinder".into()));
            a.push(("size", mj(&[*radius, height / 2.0])));
        }
        Shape::Trimesh {
            file,
            scale,
            collision: kind,
        } => {
            let field = *kind == MeshCollision::HeightField
                && matches!(collision, Collision::Terrain { .. });
            let k = assets
                .index(file, *scale, field)
                .ok_or_else(|| MujocoError::Mesh {
                    file: file.clone(),
                    cause: "asset not collected".into(),
                })?;
            if field {
                let map = height_map(sim, file)?;
                let (lo, _) = min_max(&map.heights);
                let centre = [
                    (map.x[0] + map.x[1]) / 2.0 * scale,
                    (map.y[0] + map.y[1]) / 2.0 * scale,
                    lo * scale,
                ];
                at = g.pose.mul(&Pose::from_translation(centre));
                a.push(("type", "hfield".into()));
                a.push(("hfield", format!("field{k}")));
            } else {
                a.push(("type", "mesh".into()));
                a.push(("mesh", format!("mesh{k}")));
            }
        }
    }
    a.extend(pose_attrs(&at));
    a.extend(contact_attrs(sim, collision)?);
    if let Some(m) = mass {
        a.push(("mass", mj(&[m])));
    }
    if let Some(c) = g.diffuse_color {
        let alpha = 1.0 - g.transparency.unwrap_or(0.0);
        a.push(("rgba", mj(&[c[0], c[1], c[2], alpha])));
    }
    Ok(a)
}
