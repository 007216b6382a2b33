//! A mesh's convex hull dropped on a floor in plain rapier, outside proleg: the
//! reproduction behind docs/MEASUREMENTS.md's note on `random_urdfs/350` (the hull rocks
//! and sinks into the floor where a box of its size rests).
//!
//! ```text
//! cargo run --release --example hull_on_floor -- MESH.obj [SCALE] [SECONDS]
//! cargo run --release --example hull_on_floor -- .../pybullet_data/random_urdfs/350/350.obj 0.015
//! ```
//!
//! The hull of the OBJ's vertices times SCALE (to metres; the URDF's `scale`), 0.1 kg,
//! friction 0.5, dropped 1 mm onto a cuboid floor with proleg's production step (1 ms, 4
//! substeps, 2 PGS iterations, a 60-Hz contact spring of damping ratio 10, tolerances
//! scaled to the hull's size), then a box of its bounding box the same way; every 0.5 s it
//! prints each one's lowest point, speed and spin.

use rapier3d::prelude::*;

/// What stops the run.
#[derive(Debug, thiserror::Error)]
enum ProbeError {
    #[error("usage: hull_on_floor MESH.obj [SCALE] [SECONDS]")]
    Usage,
    #[error("not a number: {0}")]
    Number(String),
    #[error("{0}: {1}")]
    Read(String, std::io::Error),
    #[error("{0}: line {1}: not a vertex of 3 numbers: {2}")]
    Vertex(String, usize, String),
    #[error("{0}: its vertices have no convex hull")]
    NoHull(String),
}

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), ProbeError> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or(ProbeError::Usage)?;
    let mut number = |default: f32| match args.next() {
        Some(s) => s.parse().map_err(|_| ProbeError::Number(s)),
        None => Ok(default),
    };
    let (scale, seconds) = (number(1.0)?, number(8.0)?);
    let text = std::fs::read_to_string(&path).map_err(|e| ProbeError::Read(path.clone(), e))?;
    let points: Vec<Vector> = vertices(&path, &text)?
        .into_iter()
        .map(|p| p * scale)
        .collect();
    let hull = SharedShape::convex_hull(&points).ok_or(ProbeError::NoHull(path.clone()))?;
    let aabb = hull.compute_local_aabb();
    let (lo, hi) = (aabb.mins, aabb.maxs);
    let corners: Vec<Vector> = (0..8)
        .map(|i| {
            let pick = |bit: usize, a: f32, b: f32| if i & bit == 0 { a } else { b };
            Vector::new(
                pick(1, lo.x, hi.x),
                pick(2, lo.y, hi.y),
                pick(4, lo.z, hi.z),
            )
        })
        .collect();
    let half = (hi - lo) / 2.0;
    let the_box = SharedShape::cuboid(half.x, half.y, half.z);
    let centred: Vec<Vector> = corners.iter().map(|c| *c - (lo + half)).collect();
    let size = (hi - lo).element_product().cbrt();
    println!(
        "{path}: the hull of {} mesh vertices, {size:.4} m; then a box of its bounding box",
        points.len()
    );
    let hull_run = settle(hull, &points, size, seconds);
    let box_run = settle(the_box, &centred, size, seconds);
    println!(
        "   t | hull: lowest vertex (m), speed (m/s), spin (rad/s) | box: lowest, speed, spin"
    );
    for (h, b) in hull_run.iter().zip(&box_run) {
        println!(
            "{:4.1} | {:+.5} {:.4} {:.3} | {:+.5} {:.4} {:.3}",
            h[0], h[1], h[2], h[3], b[1], b[2], b[3]
        );
    }
    Ok(())
}

/// `shape` (0.1 kg, its `points` tracked) dropped 1 mm onto the floor and stepped for
/// `seconds`: every 0.5 s the time, the lowest point's height, the speed and the spin.
fn settle(shape: SharedShape, points: &[Vector], size: f32, seconds: f32) -> Vec<[f32; 4]> {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    world.integration_parameters = IntegrationParameters {
        dt: 0.001,
        num_solver_iterations: 4,
        num_internal_pgs_iterations: 2,
        length_unit: size,
        contact_softness: SpringCoefficients::new(60.0, 10.0),
        static_contact_softness: SpringCoefficients::new(60.0, 10.0),
        ..Default::default()
    };
    let lowest = |pose: &Pose| {
        points
            .iter()
            .map(|p| (pose * *p).z)
            .fold(f32::MAX, f32::min)
    };
    let start = Pose::from_translation(Vector::new(0.0, 0.0, 0.001 - lowest(&Pose::IDENTITY)));
    let body = world.bodies.insert(RigidBodyBuilder::dynamic().pose(start));
    let collider = ColliderBuilder::new(shape).mass(0.1).friction(0.5);
    world
        .colliders
        .insert_with_parent(collider, body, &mut world.bodies);
    let floor = world
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.5)));
    world.colliders.insert_with_parent(
        ColliderBuilder::cuboid(50.0, 50.0, 0.5),
        floor,
        &mut world.bodies,
    );
    let mut rows = Vec::new();
    for step in 1..=(seconds * 1000.0) as u32 {
        world.step();
        if step % 500 == 0 {
            let b = &world.bodies[body];
            rows.push([
                step as f32 / 1000.0,
                lowest(b.position()),
                b.linvel().length(),
                b.angvel().length(),
            ]);
        }
    }
    rows
}

/// The `v x y z` lines of the OBJ `path`.
fn vertices(path: &str, text: &str) -> Result<Vec<Vector>, ProbeError> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("v "))
        .map(|(i, l)| {
            let bad = || ProbeError::Vertex(path.to_string(), i + 1, l.to_string());
            let v: Vec<f32> = l
                .split_whitespace()
                .skip(1)
                .take(3)
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| bad())?;
            match v[..] {
                [x, y, z] => Ok(Vector::new(x, y, z)),
                _ => Err(bad()),
            }
        })
        .collect()
}
