//! What the viewer draws: every shown body (the environment's objects and robot 0's links)
//! with its geometries in its own frame, the meshes and height fields they name, robot 0's
//! pads, its joints' names, and which bodies move (those whose poses every frame holds).
//! Made once, from the loaded simulation and the world built from it.

use std::collections::HashMap;
use std::sync::Arc;

use serde::Serialize;

use crate::config::Simulation;
use crate::config::body::{BodyKind, Geom, MeshCollision, Shape};
use crate::config::mesh::TriMesh;
use crate::config::transform::Pose;
use crate::playback::encode;
use crate::sim::engine::BodyId;
use crate::sim::{SimError, Simulator};

/// The scene of a replay (serialized into the stream as it is).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene {
    /// Every shown body: the environment's, then robot 0's links.
    pub bodies: Vec<ViewBody>,
    /// The triangle meshes geometries name (by index).
    pub meshes: Vec<ViewMesh>,
    /// Robot 0's tactile pads.
    pub pads: Vec<ViewPad>,
    /// Robot 0's joints' names, in joint order.
    pub joints: Vec<String>,
}

/// A pose as the page takes it: translation, then the rotation's x, y, z, w.
pub type PoseArray = [f64; 7];

/// `p` as a [`PoseArray`].
pub fn pose_array(p: &Pose) -> PoseArray {
    let [w, x, y, z] = p.rotation;
    let [tx, ty, tz] = p.translation;
    [tx, ty, tz, x, y, z, w]
}

/// One body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewBody {
    /// Its name in the configuration.
    pub name: String,
    /// Robot 0's link index (`None`: an environment object).
    pub link: Option<usize>,
    /// Its poses are in every frame (links, dynamic objects); else it stays at `pose`.
    pub moves: bool,
    /// Its pose at the start.
    pub pose: PoseArray,
    /// Its visible geometries.
    pub geoms: Vec<ViewGeom>,
}

/// One geometry in its body's frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewGeom {
    /// Its shape.
    #[serde(flatten)]
    pub shape: ViewShape,
    /// Its pose in the body.
    pub pose: PoseArray,
    /// Diffuse colour (RGB 0..1).
    pub color: [f64; 3],
    /// 1 opaque .. 0 invisible.
    pub opacity: f64,
    /// Whether the ground's metre grid is drawn on it (a floor's box).
    pub grid: bool,
}

/// A geometry's shape.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum ViewShape {
    /// Half extents (m).
    Box {
        /// Half extents along x, y, z.
        half: [f64; 3],
    },
    /// A ball.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// Along the local y axis.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Height (m).
        height: f64,
    },
    /// A triangle mesh of [`Scene::meshes`], scaled.
    Mesh {
        /// Index into the scene's meshes.
        mesh: usize,
        /// Uniform scale of its vertices.
        scale: f64,
    },
    /// A height field over an x-y grid (heights quantized, see [`encode::heights`]).
    Heightfield(ViewHeights),
}

/// A height field: node `(i, j)` at `x[0] + i * (x[1] - x[0]) / (nx - 1)`, likewise y,
/// height `low + step * heights[j * nx + i]`, all times `scale`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewHeights {
    /// Smallest and largest x of the grid.
    pub x: [f64; 2],
    /// Smallest and largest y of the grid.
    pub y: [f64; 2],
    /// Nodes along x.
    pub nx: usize,
    /// Nodes along y.
    pub ny: usize,
    /// The lowest height.
    pub low: f64,
    /// Metres per height step.
    pub step: f64,
    /// Base64 of the little-endian `u16` steps.
    pub heights: String,
    /// Uniform scale (the geometry's).
    pub scale: f64,
}

/// A triangle mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewMesh {
    /// Base64 of little-endian `f32` x, y, z per vertex.
    pub vertices: String,
    /// Base64 of little-endian `u32` vertex indices, three per triangle.
    pub triangles: String,
}

/// A tactile pad: a box on a link, lit while pressed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewPad {
    /// Its index among robot 0's pads (the order of its touch readings).
    pub index: usize,
    /// Index of its link's body in [`Scene::bodies`].
    pub body: usize,
    /// Its centre and orientation in the link's frame.
    pub pose: PoseArray,
    /// Half extents (m).
    pub half: [f64; 3],
}

/// Smallest side (m) of a box that gets the metre grid: a floor, not a step or a wall (as
/// in the windows).
const GRID_MIN_SIDE: f64 = 2.0;

/// The scene and the engine bodies of its moving bodies, in the order frames hold them.
pub struct SceneParts {
    /// The scene.
    pub scene: Scene,
    /// The engine body of each body with `moves`, in [`Scene::bodies`] order.
    pub moving: Vec<BodyId>,
}

impl Scene {
    /// The scene of `sim` built into `simulator` (robot 0 shown).
    pub fn of(sim: &Simulation, simulator: &Simulator) -> Result<SceneParts, SimError> {
        let mut meshes = MeshTable::default();
        let mut bodies = Vec::new();
        let mut moving = Vec::new();
        for obj in simulator.environment_bodies() {
            let Some(body) = sim.environment.bodies.get(obj.index) else {
                continue;
            };
            let moves = body.kind == BodyKind::Dynamic;
            let pose = simulator.body_state(obj.body).map_or(body.pose, |s| s.pose);
            if moves {
                moving.push(obj.body);
            }
            bodies.push(ViewBody {
                name: body.name.clone(),
                link: None,
                moves,
                pose: pose_array(&pose),
                geoms: view_geoms(sim, &body.geoms, &mut meshes, !moves),
            });
        }
        let mut link_rows = HashMap::new();
        for l in simulator.links(0)? {
            let Some(link) = sim.robot.links.get(l.index) else {
                continue;
            };
            let pose = simulator.body_state(l.body).map_or(link.pose, |s| s.pose);
            link_rows.insert(l.body, bodies.len());
            moving.push(l.body);
            bodies.push(ViewBody {
                name: link.name.clone(),
                link: Some(l.index),
                moves: true,
                pose: pose_array(&pose),
                geoms: view_geoms(sim, &link.geoms, &mut meshes, false),
            });
        }
        let pads = simulator
            .tactile_pads(0)?
            .into_iter()
            .filter_map(|p| {
                Some(ViewPad {
                    index: p.index,
                    body: *link_rows.get(&p.link)?,
                    pose: pose_array(&p.area.pose),
                    half: p.area.half_extents,
                })
            })
            .collect();
        let joints = sim.robot.joints.iter().map(|j| j.name.clone()).collect();
        Ok(SceneParts {
            scene: Scene {
                bodies,
                meshes: meshes.meshes,
                pads,
                joints,
            },
            moving,
        })
    }
}

/// The meshes met so far, each encoded once.
#[derive(Default)]
struct MeshTable {
    meshes: Vec<ViewMesh>,
    index: HashMap<*const TriMesh, usize>,
}

impl MeshTable {
    /// The index of `mesh`, encoding it the first time.
    fn of(&mut self, mesh: &Arc<TriMesh>) -> usize {
        let key = Arc::as_ptr(mesh);
        if let Some(i) = self.index.get(&key) {
            return *i;
        }
        let vertices: Vec<f32> = mesh
            .vertices
            .iter()
            .flat_map(|v| v.map(|c| c as f32))
            .collect();
        let triangles: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        self.meshes.push(ViewMesh {
            vertices: encode::f32s(&vertices),
            triangles: encode::u32s(&triangles),
        });
        self.index.insert(key, self.meshes.len() - 1);
        self.meshes.len() - 1
    }
}

/// The visible geometries of a body (`ground`: a fixed body, whose floors get the grid).
fn view_geoms(
    sim: &Simulation,
    geoms: &[Geom],
    meshes: &mut MeshTable,
    ground: bool,
) -> Vec<ViewGeom> {
    geoms
        .iter()
        .filter(|g| g.visible)
        .filter_map(|g| {
            let shape = view_shape(sim, &g.shape, meshes)?;
            let grid = ground
                && matches!(g.shape, Shape::Box { extents: [x, y, _] }
                    if 2.0 * x >= GRID_MIN_SIDE && 2.0 * y >= GRID_MIN_SIDE);
            Some(ViewGeom {
                shape,
                pose: pose_array(&g.pose),
                color: g.diffuse_color.unwrap_or([0.7, 0.7, 0.7]),
                opacity: 1.0 - g.transparency.unwrap_or(0.0).clamp(0.0, 1.0),
                grid,
            })
        })
        .collect()
}

/// A shape as the page draws it (`None`: a mesh that did not load, already reported).
fn view_shape(sim: &Simulation, shape: &Shape, meshes: &mut MeshTable) -> Option<ViewShape> {
    Some(match *shape {
        Shape::Box { extents } => ViewShape::Box { half: extents },
        Shape::Sphere { radius } => ViewShape::Sphere { radius },
        Shape::Cylinder { radius, height } => ViewShape::Cylinder { radius, height },
        Shape::Trimesh {
            ref file,
            scale,
            collision,
        } => {
            let mesh = sim.mesh(file)?;
            match (collision, mesh.height_map()) {
                (MeshCollision::HeightField, Ok(map)) => {
                    let (low, step, steps) = encode::heights(&map.heights);
                    ViewShape::Heightfield(ViewHeights {
                        x: map.x,
                        y: map.y,
                        nx: map.nx,
                        ny: map.ny,
                        low,
                        step,
                        heights: encode::u16s(&steps),
                        scale,
                    })
                }
                _ => ViewShape::Mesh {
                    mesh: meshes.of(mesh),
                    scale,
                },
            }
        }
    })
}
