//! The layout every generated course shares and the builder the families draw with.
//!
//! A course runs along +y from the robot's start at the origin (the way the shipped robots
//! face): flat ground from [`START_PAD`] behind the start to [`FEATURES_FROM`] ahead of it,
//! the family's ground up to the course's length, then [`END_PAD`] of the same ground's
//! level. Every coordinate is rounded to a micrometre and only arithmetic and square roots
//! (correctly rounded by IEEE 754) make them, so the same seed gives the same geometry on
//! every machine; the geometry is ordinary boxes, cylinders and a height-field mesh, which
//! both engines, the windows, the videos and the MJCF export already know.

use std::sync::Arc;

use crate::config::body::{Body, BodyKind, Geom, MeshCollision, Shape};
use crate::config::error::Pos;
use crate::config::kinbody::KinBody;
use crate::config::mesh::TriMesh;
#[cfg(doc)]
use crate::config::terrain::spec::Family;
use crate::config::terrain::spec::{FIELD_GRID, TerrainSpec};
use crate::config::transform::{Pose, round_to};
use crate::rng::SimRng;

pub use crate::config::terrain::spec::{END_PAD, FEATURES_FROM, START_PAD};

/// Flat floor beside the course (m each side), where a robot that wanders off lands.
pub const SIDE_MARGIN: f64 = 2.0;
/// Prefix of the names of generated meshes (not files: they live in memory).
pub const GENERATED_MESH: &str = "generated:";

/// Coordinates are rounded to 1 µm.
const RESOLUTION: f64 = 1e6;

/// A generated course: static bodies, and the meshes their height fields name.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratedTerrain {
    /// One kinbody of static bodies.
    pub kinbody: KinBody,
    /// The height-field meshes, by the name their geometry gives.
    pub meshes: Vec<(String, Arc<TriMesh>)>,
}

/// What the families draw with: the spec, its random stream, and the bodies so far.
pub struct Course<'a> {
    /// The course being made.
    pub spec: &'a TerrainSpec,
    /// Its random stream (seeded by the spec's seed and family).
    pub rng: SimRng,
    bodies: Vec<Body>,
    meshes: Vec<(String, Arc<TriMesh>)>,
}

/// µm-rounded.
pub fn r6(v: f64) -> f64 {
    round_to(v, RESOLUTION)
}

/// The rotation about z taking +y onto the direction `(dx, dy)`, from the half-angle
/// formula (square roots only).
pub fn yaw_towards(dx: f64, dy: f64) -> [f64; 4] {
    // The angle from +y to (dx, dy): cos = dy / n, sin = -dx / n.
    let n = (dx * dx + dy * dy).sqrt();
    if n == 0.0 {
        return Pose::IDENTITY.rotation;
    }
    let (c, s) = (dy / n, -dx / n);
    if c > -1.0 + 1e-12 {
        let w = 1.0 + c;
        let m = (w * w + s * s).sqrt();
        [w / m, 0.0, 0.0, s / m]
    } else {
        [0.0, 0.0, 0.0, 1.0]
    }
}

/// A yaw drawn by a rational parametrization (`t` in [-1, 1] covers ±90°, all a box
/// needs): no trigonometry, so no platform's libm changes it.
pub fn yaw_of(t: f64) -> [f64; 4] {
    let m = (1.0 + t * t).sqrt();
    [1.0 / m, 0.0, 0.0, t / m]
}

impl<'a> Course<'a> {
    /// An empty course for `spec`.
    pub fn new(spec: &'a TerrainSpec) -> Self {
        let salt = (spec.family as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        Course {
            spec,
            rng: SimRng::new(spec.seed ^ salt),
            bodies: Vec::new(),
            meshes: Vec::new(),
        }
    }

    /// The course's extent along y: from behind the start to beyond its end.
    pub fn y_range(&self) -> [f64; 2] {
        [-START_PAD, self.spec.length + END_PAD]
    }

    /// Half the course's width.
    pub fn half_width(&self) -> f64 {
        self.spec.width / 2.0
    }

    /// How far along the features `y` is: 0 at [`FEATURES_FROM`], 1 at the course's end.
    pub fn progress(&self, y: f64) -> f64 {
        ((y - FEATURES_FROM) / (self.spec.length - FEATURES_FROM)).clamp(0.0, 1.0)
    }

    /// A static box: centre, half-extents, rotation.
    pub fn add_box(&mut self, name: String, centre: [f64; 3], half: [f64; 3], rot: [f64; 4]) {
        let shape = Shape::Box {
            extents: half.map(r6),
        };
        self.add(name, centre, rot, shape, [0.62, 0.55, 0.45]);
    }

    /// A static vertical cylinder standing on z = 0 (ours stand along y: turned about x).
    pub fn add_peg(&mut self, name: String, at: [f64; 2], radius: f64, height: f64) {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let shape = Shape::Cylinder {
            radius: r6(radius),
            height: r6(height),
        };
        let centre = [at[0], at[1], height / 2.0];
        self.add(name, centre, [h, h, 0.0, 0.0], shape, [0.55, 0.55, 0.62]);
    }

    /// The flat floor with its top at `top`, under the whole course and its margins.
    pub fn add_floor(&mut self, top: f64) {
        let [y0, y1] = self.y_range();
        let half = [
            self.half_width() + SIDE_MARGIN,
            (y1 - y0) / 2.0 + SIDE_MARGIN,
            0.05,
        ];
        let centre = [0.0, (y0 + y1) / 2.0, top - 0.05];
        let shape = Shape::Box {
            extents: half.map(r6),
        };
        self.add(
            "terrain_floor".into(),
            centre,
            Pose::IDENTITY.rotation,
            shape,
            [0.3, 0.8, 0.3],
        );
    }

    /// A height field over the course, of `height(x, y)` sampled every [`Family::grid`] (0 on the
    /// start pad is the caller's business); a floor at its lowest point catches a robot
    /// that leaves it sideways.
    pub fn add_field(&mut self, height: impl Fn(f64, f64) -> f64) {
        let [y0, y1] = self.y_range();
        let grid = FIELD_GRID;
        let nx = (self.spec.width / grid).ceil() as usize + 1;
        let ny = ((y1 - y0) / grid).ceil() as usize + 1;
        let x0 = -grid * (nx - 1) as f64 / 2.0;
        let mut vertices = Vec::with_capacity(nx * ny);
        let mut lowest = 0.0_f64;
        for j in 0..ny {
            let y = r6(y0 + grid * j as f64);
            for i in 0..nx {
                let x = r6(x0 + grid * i as f64);
                let z = r6(height(x, y));
                lowest = lowest.min(z);
                vertices.push([x, y, z]);
            }
        }
        let mut triangles = Vec::with_capacity(2 * (nx - 1) * (ny - 1));
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let a = (j * nx + i) as u32;
                let (b, c, d) = (a + 1, a + nx as u32, a + nx as u32 + 1);
                triangles.push([a, b, d]);
                triangles.push([a, d, c]);
            }
        }
        let name = self.spec.mesh_name();
        self.meshes
            .push((name.clone(), Arc::new(TriMesh::new(vertices, triangles))));
        let shape = Shape::Trimesh {
            file: name,
            scale: 1.0,
            collision: MeshCollision::HeightField,
        };
        let rot = Pose::IDENTITY.rotation;
        self.add(
            "terrain_field".into(),
            [0.0; 3],
            rot,
            shape,
            [0.6, 0.45, 0.3],
        );
        self.add_floor(lowest - 0.001);
    }

    fn add(&mut self, name: String, at: [f64; 3], rot: [f64; 4], shape: Shape, colour: [f64; 3]) {
        let pos = self.spec.pos;
        let geom = Geom {
            shape,
            pose: Pose::IDENTITY,
            diffuse_color: Some(colour),
            ambient_color: None,
            transparency: None,
            friction: None,
            visible: true,
            pos,
        };
        self.bodies.push(Body {
            name,
            kind: BodyKind::Static,
            pose: Pose {
                translation: at.map(r6),
                rotation: rot.map(|q| round_to(q, 1e12)),
            },
            geoms: vec![geom],
            mass: None,
            pos,
        });
    }

    /// The course made.
    pub fn finish(self) -> GeneratedTerrain {
        let pos: Pos = self.spec.pos;
        GeneratedTerrain {
            kinbody: KinBody {
                name: Some(format!("terrain_{}", self.spec.family)),
                pose: self.spec.pose,
                includes: Vec::new(),
                bodies: self.bodies,
                joints: Vec::new(),
                sensors: Vec::new(),
                pos,
            },
            meshes: self.meshes,
        }
    }
}
