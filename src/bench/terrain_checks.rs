//! Physical checks on terrain made of meshes ([`super::physics_checks`] does the box floor):
//! the friction onset of one module on a real slope that is a height field or a triangle
//! mesh (it must start sliding within 1° of atan μ, as on the tilted floor), and a module
//! resting on a height field (penetration, drift, jitter). The terrain is a generated grid
//! (a height map), so both engines read the very same surface.

use std::sync::Arc;

use crate::bench::physics_checks::{
    Check, PhysicsCheckError, friction_probe_angles, half_height, module_scene, rest_figures, world,
};
use crate::config::Simulation;
use crate::config::body::{MeshCollision, Shape};
use crate::config::mesh::TriMesh;
use crate::config::simulation::EngineKind;
use crate::config::transform::Pose;
use crate::control::ModuleRegistry;

/// Grid points along each side of the generated terrain.
const GRID: usize = 11;
/// Half the side of the generated terrain (m).
const HALF_SIDE: f64 = 0.5;

/// A terrain representation checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Terrain {
    /// A height field over the grid.
    HeightField,
    /// The grid's triangles.
    Triangles,
}

impl Terrain {
    fn name(self) -> &'static str {
        match self {
            Terrain::HeightField => "height field",
            Terrain::Triangles => "trimesh",
        }
    }

    fn collision(self) -> MeshCollision {
        match self {
            Terrain::HeightField => MeshCollision::HeightField,
            Terrain::Triangles => MeshCollision::Triangles,
        }
    }
}

/// Thickness of a triangle-mesh slope (m): a slab, so that its convex hull (what MuJoCo
/// collides a mesh as) is the slope's solid.
const SLAB: f64 = 0.05;

/// A height-map grid over ±[`HALF_SIDE`] rising along +y at `theta` degrees; `bump` raises
/// one far corner by that much (a flat height field needs some relief on MuJoCo); with
/// `slab`, the grid again [`SLAB`] lower as the slab's underside.
fn slope_grid(theta_deg: f64, bump: f64, slab: bool) -> TriMesh {
    let slope = theta_deg.to_radians().tan();
    let step = 2.0 * HALF_SIDE / (GRID - 1) as f64;
    let mut vertices = Vec::with_capacity(GRID * GRID);
    for j in 0..GRID {
        for i in 0..GRID {
            let (x, y) = (-HALF_SIDE + i as f64 * step, -HALF_SIDE + j as f64 * step);
            let corner = if i == GRID - 1 && j == GRID - 1 {
                bump
            } else {
                0.0
            };
            vertices.push([x, y, y * slope + corner]);
        }
    }
    let mut triangles = Vec::with_capacity(2 * (GRID - 1) * (GRID - 1));
    for j in 0..GRID - 1 {
        for i in 0..GRID - 1 {
            let v = (j * GRID + i) as u32;
            let g = GRID as u32;
            triangles.push([v, v + 1, v + g + 1]);
            triangles.push([v, v + g + 1, v + g]);
        }
    }
    if slab {
        let (n, top) = (vertices.len() as u32, triangles.len());
        let below: Vec<[f64; 3]> = vertices.iter().map(|v| [v[0], v[1], v[2] - SLAB]).collect();
        vertices.extend(below);
        for k in 0..top {
            let [a, b, c] = triangles[k];
            triangles.push([a + n, c + n, b + n]);
        }
    }
    TriMesh::new(vertices, triangles)
}

/// A slope checked: the module's friction on it, its angle (degrees) and the height of the
/// bumps on it (m).
#[derive(Debug, Clone, Copy)]
struct Slope {
    mu: f64,
    theta_deg: f64,
    bump: f64,
}

/// The module of `base` with friction `mu` on a slope of `theta` degrees made as `terrain`,
/// laid on it 1 mm above its surface (bottom parallel to it), gravity straight down.
fn slope_scene(
    base: &Simulation,
    engine: EngineKind,
    slope: Slope,
    terrain: Terrain,
) -> Result<Simulation, PhysicsCheckError> {
    let Slope {
        mu,
        theta_deg,
        bump,
    } = slope;
    let mut sim = module_scene(base, engine, mu);
    let name = format!("proleg-check:{}:{theta_deg}", terrain.name());
    sim.environment.meshes.insert(
        name.clone(),
        Arc::new(slope_grid(theta_deg, bump, terrain == Terrain::Triangles)),
    );
    let body = sim
        .environment
        .bodies
        .first_mut()
        .ok_or(PhysicsCheckError::Scene("no floor"))?;
    body.pose = Pose::IDENTITY;
    let mut geom = body
        .geoms
        .first()
        .cloned()
        .ok_or(PhysicsCheckError::Scene("the floor has no geometry"))?;
    geom.shape = Shape::Trimesh {
        file: name,
        scale: 1.0,
        collision: terrain.collision(),
    };
    geom.pose = Pose::IDENTITY;
    geom.friction = Some(mu);
    body.geoms = vec![geom];
    sim.environment.bodies.truncate(1);
    // The robot frame turned by theta about x, placed so that the module's box centre is
    // its half height (plus 1 mm) above the surface at the origin, along the normal.
    let link = &sim.robot.links[0];
    let centre = link.geoms.first().map_or(link.pose.translation, |g| {
        link.pose.mul(&g.pose).translation
    });
    let t = theta_deg.to_radians();
    let turn = Pose {
        translation: [0.0; 3],
        rotation: [(t / 2.0).cos(), (t / 2.0).sin(), 0.0, 0.0],
    };
    let lift = half_height(&sim) + 0.001;
    let target = [0.0, -t.sin() * lift, t.cos() * lift];
    let turned = turn.transform_point(centre);
    sim.environment.robot_pose = Pose {
        translation: std::array::from_fn(|k| target[k] - turned[k]),
        rotation: turn.rotation,
    };
    Ok(sim)
}

/// The slope (degrees) from which the module slides on `terrain` with friction `mu`:
/// slopes from atan μ - 4° in 0.5° steps; sliding = more than 5 mm down the slope in 1 s
/// (after 0.2 s to settle).
pub fn slope_onset(
    base: &Simulation,
    engine: EngineKind,
    mu: f64,
    terrain: Terrain,
    registry: &ModuleRegistry,
) -> Result<Check, PhysicsCheckError> {
    let expected = mu.atan().to_degrees();
    let mut onset = f64::NAN;
    for theta in friction_probe_angles(expected) {
        let sim = slope_scene(
            base,
            engine,
            Slope {
                mu,
                theta_deg: theta,
                bump: 0.0,
            },
            terrain,
        )?;
        let mut s = world(&sim, registry)?;
        let settle = (0.2 / s.clock().dt).round() as u64;
        s.run_steps(settle);
        let start = s.com(0)?;
        s.run_steps(5 * settle);
        let end = s.com(0)?;
        let down = ((start[1] - end[1]).powi(2) + (start[2] - end[2]).powi(2)).sqrt();
        if down > 0.005 {
            onset = theta;
            break;
        }
    }
    Ok(Check::within(
        format!("friction onset on a {} slope, mu {mu}", terrain.name()),
        onset,
        expected,
        1.0,
        "deg",
    ))
}

/// A module resting 10 s on a flat height field: penetration, drift and jitter, as on the
/// floor.
pub fn resting_on_height_field(
    base: &Simulation,
    engine: EngineKind,
    registry: &ModuleRegistry,
) -> Result<Vec<Check>, PhysicsCheckError> {
    let sim = slope_scene(
        base,
        engine,
        Slope {
            mu: 0.5,
            theta_deg: 0.0,
            bump: 0.05,
        },
        Terrain::HeightField,
    )?;
    let h = half_height(&sim);
    let s = world(&sim, registry)?;
    rest_figures(s, h, "resting on a height field")
}
