//! Whether a robot's start pose is free: no two of its links that no joint connects
//! overlap, and no link starts inside an object of the environment. A co-design search
//! rejects a body that fails (`optimize::design`), with this module's reason, and the
//! environment editor warns of an object on the robot's start pose with the same
//! measure ([`Boxes`]: the one overlap check).
//!
//! The check is geometry of the configuration, not of an engine, so it means the same on
//! rapier and MuJoCo: every shape is taken as its oriented bounding box (a box as itself,
//! a sphere as its cube, a cylinder as its box, a robot's mesh as its own-frame bounds)
//! and two boxes overlap by the smallest push along the 15 axes of the separating-axis
//! test. The scenery's meshes and height fields are not checked: their bounds say nothing
//! of their surface (a robot on a hill lies inside its hill's box).

use crate::config::body::{Geom, Shape};
use crate::config::mesh::Meshes;
use crate::config::resolve::Simulation;
use crate::config::transform::Pose;

/// How deep (m) two shapes may reach into each other before the start pose counts as
/// blocked (a robot resting on the floor touches it; adjacent parts touch).
pub const OVERLAP_TOLERANCE: f64 = 0.002;

/// What blocks a robot's start pose.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StartOverlap {
    /// Two links that no joint connects overlap.
    #[error(
        "self-intersecting start pose: links {a} and {b} overlap by {:.0} mm",
        depth * 1000.0
    )]
    SelfIntersection {
        /// One link.
        a: String,
        /// The other.
        b: String,
        /// How deep (m).
        depth: f64,
    },
    /// A link starts inside an object of the environment.
    #[error(
        "the body does not fit the world: link {link} starts inside {object} (by {:.0} mm)",
        depth * 1000.0
    )]
    Scenery {
        /// The link.
        link: String,
        /// The environment's body.
        object: String,
        /// How deep (m).
        depth: f64,
    },
}

/// The oriented boxes of some geometries placed in the world: the one measure of how deep
/// shapes reach into each other before anything runs.
#[derive(Debug, Clone, Default)]
pub struct Boxes(Vec<Obb>);

impl Boxes {
    /// Adds the boxes of `geoms` on a body at `body` (a mesh by its own-frame bounds in
    /// `meshes`; without them a mesh is left out, as the scenery's are).
    pub fn add<'a>(
        &mut self,
        geoms: impl IntoIterator<Item = &'a Geom>,
        body: &Pose,
        meshes: Option<&Meshes>,
    ) {
        self.0
            .extend(geoms.into_iter().filter_map(|g| Obb::of(g, body, meshes)));
    }

    /// How deep the deepest pair of boxes, one of each, overlap (<= 0: apart;
    /// `-inf` when either is empty).
    pub fn deepest(&self, other: &Boxes) -> f64 {
        self.0
            .iter()
            .flat_map(|x| other.0.iter().map(move |y| x.overlap(y)))
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// An oriented box: centre and axes in the world, half extents along them.
#[derive(Debug, Clone, Copy)]
struct Obb {
    centre: [f64; 3],
    axes: [[f64; 3]; 3],
    half: [f64; 3],
}

impl Obb {
    /// The box of geometry `g` on a body at `body`, or none for a mesh with no bounds.
    fn of(g: &Geom, body: &Pose, meshes: Option<&Meshes>) -> Option<Obb> {
        let (centre, half) = match &g.shape {
            Shape::Box { extents } => ([0.0; 3], *extents),
            Shape::Sphere { radius } => ([0.0; 3], [*radius; 3]),
            Shape::Cylinder { radius, height } => ([0.0; 3], [*radius, height / 2.0, *radius]),
            Shape::Trimesh { file, scale, .. } => {
                let (lo, hi) = meshes?.get(file)?.bounds();
                (
                    std::array::from_fn(|k| (lo[k] + hi[k]) / 2.0 * scale),
                    std::array::from_fn(|k| (hi[k] - lo[k]) / 2.0 * scale),
                )
            }
        };
        let at = body.mul(&g.pose);
        Some(Obb {
            centre: at.transform_point(centre),
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(|a| at.rotate(a)),
            half,
        })
    }

    /// The box's half width along unit direction `d`.
    fn reach(&self, d: [f64; 3]) -> f64 {
        (0..3)
            .map(|k| self.half[k] * dot(self.axes[k], d).abs())
            .sum()
    }

    /// How deep the boxes overlap: the smallest overlap of their projections onto the
    /// separating-axis test's axes (<= 0: apart).
    fn overlap(&self, other: &Obb) -> f64 {
        let between = sub(other.centre, self.centre);
        let mut deepest = f64::INFINITY;
        let mut test = |d: [f64; 3]| {
            let n = dot(d, d).sqrt();
            if n < 1e-9 {
                return;
            }
            let d = d.map(|v| v / n);
            let o = self.reach(d) + other.reach(d) - dot(between, d).abs();
            deepest = deepest.min(o);
        };
        for a in self.axes.iter().chain(&other.axes) {
            test(*a);
        }
        for a in &self.axes {
            for b in &other.axes {
                test(cross(*a, *b));
            }
        }
        deepest
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// What blocks `sim`'s robot at its start pose (every joint at 0), deepest first; empty
/// when the pose is free.
pub fn start_overlaps(sim: &Simulation) -> Vec<StartOverlap> {
    let start = &sim.environment.robot_pose;
    let links: Vec<Boxes> = sim
        .robot
        .links
        .iter()
        .map(|l| {
            let mut b = Boxes::default();
            b.add(&l.geoms, &start.mul(&l.pose), Some(&sim.robot.meshes));
            b
        })
        .collect();
    let joined = |i: usize, j: usize| {
        sim.robot
            .joints
            .iter()
            .any(|k| (k.parent, k.child) == (i, j) || (k.parent, k.child) == (j, i))
    };
    let mut out = Vec::new();
    for i in 0..links.len() {
        for j in i + 1..links.len() {
            let depth = links[i].deepest(&links[j]);
            if depth > OVERLAP_TOLERANCE && !joined(i, j) {
                out.push(StartOverlap::SelfIntersection {
                    a: sim.robot.links[i].name.clone(),
                    b: sim.robot.links[j].name.clone(),
                    depth,
                });
            }
        }
    }
    for body in &sim.environment.bodies {
        // Meshes of the scenery: their bounds are no guide to their surface.
        let mut boxes = Boxes::default();
        boxes.add(&body.geoms, &body.pose, None);
        for (i, link) in links.iter().enumerate() {
            let depth = boxes.deepest(link);
            if depth > OVERLAP_TOLERANCE {
                out.push(StartOverlap::Scenery {
                    link: sim.robot.links[i].name.clone(),
                    object: body.name.clone(),
                    depth,
                });
            }
        }
    }
    out.sort_by(|a, b| depth_of(b).total_cmp(&depth_of(a)));
    out
}

fn depth_of(o: &StartOverlap) -> f64 {
    match o {
        StartOverlap::SelfIntersection { depth, .. } | StartOverlap::Scenery { depth, .. } => {
            *depth
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(at: [f64; 3], half: f64) -> Obb {
        Obb {
            centre: at,
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            half: [half; 3],
        }
    }

    #[test]
    fn boxes_overlap_by_their_smallest_push() {
        let a = cube([0.0; 3], 0.5);
        assert!((a.overlap(&cube([0.9, 0.0, 0.0], 0.5)) - 0.1).abs() < 1e-12);
        assert!(a.overlap(&cube([1.1, 0.0, 0.0], 0.5)) < 0.0);
        // A box turned 45 degrees about z, its corner 0.1 m short of the other's face:
        // apart, though their axis-aligned bounds overlap.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let turned = Obb {
            centre: [
                0.5 + 0.1 + 0.5 * 2f64.sqrt(),
                0.5 + 0.1 + 0.5 * 2f64.sqrt(),
                0.0,
            ],
            axes: [[s, s, 0.0], [-s, s, 0.0], [0.0, 0.0, 1.0]],
            half: [0.5; 3],
        };
        assert!(a.overlap(&turned) < 0.0);
    }
}
