//! Procedural terrains and task suites: every family at every tier is the same geometry
//! for the same seed (a committed hash each, so a change is seen) and another for another
//! seed; its heights agree between the engines within 1 mm at probed points; bad
//! `<Terrain>` elements are located errors; `proleg terrain` writes an environment file
//! that loads as the same course. A suite run scores a real gait on held-out courses of
//! both engines, and a run stopped halfway resumes to the same table.

mod common;

use std::path::Path;

use proleg::config::body::Shape;
use proleg::config::environment::parse_environment_file;
use proleg::config::resolve::environment::{EnvironmentModel, resolve_environment};
use proleg::config::simulation::EngineKind;
use proleg::config::terrain::{Family, TerrainSpec, Tier, generate};
use proleg::config::{ErrorKind, FsSource};
use proleg::control::load_simulation;
use proleg::rng::SimRng;
use proleg::sim::{BuildOptions, Simulator};

/// FNV-1a, 64 bits: a stable hash of the geometry's text.
fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The generated geometry as text: every body's name, pose and shape, every mesh vertex.
fn geometry(spec: &TerrainSpec) -> String {
    let g = generate(spec);
    let mut s = String::new();
    for b in &g.kinbody.bodies {
        s += &format!("{} {:?} {:?}", b.name, b.pose.translation, b.pose.rotation);
        for geom in &b.geoms {
            s += &format!(" {:?}\n", geom.shape);
        }
    }
    for (name, mesh) in &g.meshes {
        s += &format!("{name} {:?} {:?}\n", mesh.vertices, mesh.triangles);
    }
    s
}

/// The committed hash of each family at each tier (seed 7, default length and width).
const HASHES: [(Family, [u64; 3]); 8] = [
    (
        Family::Rough,
        [
            7361459346936673502,
            4015004848305314317,
            11610198357934817500,
        ],
    ),
    (
        Family::Hills,
        [
            6420022469669392916,
            15821470917420755618,
            9357538304297069498,
        ],
    ),
    (
        Family::Steps,
        [
            3319183847281464920,
            7084004324654920740,
            4178912158398675724,
        ],
    ),
    (
        Family::Stairs,
        [
            4844076522210976245,
            12259854564017649427,
            11167165999449746553,
        ],
    ),
    (
        Family::Slope,
        [
            2001269423197581060,
            7402555086558825350,
            13435944908705696283,
        ],
    ),
    (
        Family::Pegs,
        [
            8606272208685073068,
            4872360630126739239,
            9625468760372640637,
        ],
    ),
    (
        Family::Channel,
        [
            5833710362737598232,
            11648291089472487310,
            12666442503607631290,
        ],
    ),
    (
        Family::Rubble,
        [
            10023097266276303439,
            3651475563223022539,
            13313966840762958313,
        ],
    ),
];

#[test]
fn the_same_seed_gives_the_same_course_and_its_committed_hash() {
    let mut found = Vec::new();
    for (family, hashes) in HASHES {
        let mut row = [0u64; 3];
        for (k, tier) in Tier::ALL.into_iter().enumerate() {
            let spec = TerrainSpec::new(family, tier.difficulty(), 7);
            let text = geometry(&spec);
            assert_eq!(text, geometry(&spec), "{family} {tier:?} twice");
            let other = TerrainSpec::new(family, tier.difficulty(), 8);
            assert_ne!(
                text,
                geometry(&other),
                "{family} {tier:?}: seed 8 as seed 7"
            );
            row[k] = fnv(&text);
        }
        found.push((family, row, hashes));
    }
    let table: Vec<String> = found
        .iter()
        .map(|(f, row, _)| format!("    (Family::{f:?}, {row:?}),"))
        .collect();
    assert!(
        found.iter().all(|(_, row, hashes)| row == hashes),
        "the generated geometry changed; if that is meant, commit the new hashes:\n{}",
        table.join("\n")
    );
}

/// The demo snake on `env_text`'s environment (written to a temporary file).
fn world_on(dir: &Path, env_text: &str) -> proleg::config::Simulation {
    let path = dir.join("course.env.xml");
    std::fs::write(&path, env_text).unwrap();
    let mut sim = load_simulation("configs/demo.simulation.xml").unwrap();
    sim.environment = environment(&path, env_text);
    sim
}

fn environment(path: &Path, text: &str) -> EnvironmentModel {
    let file = parse_environment_file(&path.display().to_string(), text).unwrap();
    resolve_environment(&FsSource, path, &file).unwrap()
}

fn terrain_env(spec: &TerrainSpec) -> String {
    format!(
        "<Environment><Terrain family=\"{}\" difficulty=\"{}\" seed=\"{}\"/></Environment>",
        spec.family, spec.difficulty, spec.seed
    )
}

#[test]
fn heights_agree_between_the_engines_within_a_millimetre() {
    let dir = common::scratch("terrain_heights");
    let mut engines = vec![EngineKind::Rapier];
    if common::mujoco_here("terrain heights on MuJoCo") {
        engines.push(EngineKind::Mujoco);
    }
    for family in Family::ALL {
        for tier in Tier::ALL {
            let spec = TerrainSpec::new(family, tier.difficulty(), 3);
            let sim = world_on(&dir, &terrain_env(&spec));
            let mut rng = SimRng::new(11);
            let mut points: Vec<[f64; 2]> = (0..300)
                .map(|_| [rng.range(-1.4, 1.4), rng.range(2.0, spec.length)])
                .collect();
            // And on the bodies themselves (a sparse peg field is mostly floor).
            let g = generate(&spec);
            let bodies = g
                .kinbody
                .bodies
                .iter()
                .filter(|b| b.name != "terrain_floor");
            points.extend(bodies.take(100).map(|b| {
                let t = b.pose.translation;
                [t[0], t[1]]
            }));
            let mut heights = Vec::new();
            for &engine in &engines {
                let opts = BuildOptions {
                    engine: engine.into(),
                    record: false,
                    ..Default::default()
                };
                let s = Simulator::new(&sim, &opts).unwrap();
                let h: Vec<f64> = points
                    .iter()
                    .map(|p| s.height_below(p[0], p[1]).expect("ground below"))
                    .collect();
                heights.push(h);
            }
            let top = heights[0].iter().cloned().fold(f64::MIN, f64::max);
            assert!(
                top > 0.004,
                "{}: no relief on rapier ({top} m)",
                spec.label()
            );
            if let [rapier, mujoco] = heights.as_slice() {
                let worst = rapier
                    .iter()
                    .zip(mujoco)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(
                    worst < 1e-3,
                    "{}: engines differ by {worst} m",
                    spec.label()
                );
            }
        }
    }
}

/// MuJoCo holds static bodies as geoms of its world body: each still has its id, its pose
/// and its contacts, as on rapier: a snake started on a step touches that step.
#[test]
fn static_bodies_keep_their_ids_poses_and_contacts_on_both_engines() {
    let dir = common::scratch("terrain_static_ids");
    let mut spec = TerrainSpec::new(Family::Steps, 1.0, 5);
    spec.length = 8.0;
    let mut sim = world_on(&dir, &terrain_env(&spec));
    // The snake's links along y at the start, to centre it on the first step.
    let probe = Simulator::new(&sim, &BuildOptions::default()).unwrap();
    let ys: Vec<f64> = probe
        .links(0)
        .unwrap()
        .iter()
        .map(|l| probe.body_position(l.body).unwrap()[1])
        .collect();
    let middle = (ys.iter().cloned().fold(f64::MAX, f64::min)
        + ys.iter().cloned().fold(f64::MIN, f64::max))
        / 2.0;
    let bodies = &sim.environment.bodies;
    let step = bodies
        .iter()
        .position(|b| b.name.starts_with("step"))
        .expect("a step");
    let at = bodies[step].pose.translation;
    let start = &mut sim.environment.robot_pose.translation;
    start[1] += at[1] - middle;
    start[2] += 2.0 * at[2];
    let mut poses = Vec::new();
    for engine in engines_here() {
        let opts = BuildOptions {
            engine: engine.into(),
            record: false,
            ..Default::default()
        };
        let mut s = Simulator::new(&sim, &opts).unwrap();
        s.run_steps(1000);
        let bodies = s.environment_bodies();
        assert_eq!(bodies.len(), sim.environment.bodies.len(), "{engine:?}");
        let states: Vec<_> = bodies
            .iter()
            .map(|b| s.body_state(b.body).expect("a body of the world"))
            .collect();
        assert!(states.iter().all(|b| !b.dynamic), "{engine:?}");
        let touched: std::collections::BTreeSet<usize> = s
            .engine()
            .contacts()
            .iter()
            .filter(|c| c.touching)
            .flat_map(|c| c.bodies)
            .flatten()
            .filter_map(|id| bodies.iter().find(|b| b.body == id).map(|b| b.index))
            .collect();
        assert_eq!(
            touched,
            std::collections::BTreeSet::from([step]),
            "{engine:?}: the snake lies on {}",
            sim.environment.bodies[step].name
        );
        poses.push(
            states
                .iter()
                .map(|b| b.pose.translation)
                .collect::<Vec<_>>(),
        );
    }
    if let [rapier, mujoco] = poses.as_slice() {
        for (a, b) in rapier.iter().zip(mujoco) {
            // Rapier keeps f32 poses: 4 µm at 32 m.
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-5), "{a:?} vs {b:?}");
        }
    }
}

#[test]
fn the_tiers_grow_what_makes_the_ground_hard() {
    // Relief of height fields, bodies' heights and counts: hard above easy in each family.
    for family in Family::ALL {
        let measure = |tier: Tier| {
            let g = generate(&TerrainSpec::new(family, tier.difficulty(), 5));
            let field: f64 = g
                .meshes
                .iter()
                .flat_map(|(_, m)| m.vertices.iter().map(|v| v[2].abs()))
                .fold(0.0, f64::max);
            let solids = g.kinbody.bodies.len() as f64;
            let tallest = g
                .kinbody
                .bodies
                .iter()
                .filter(|b| b.name != "terrain_floor")
                .flat_map(|b| &b.geoms)
                .map(|geom| match geom.shape {
                    Shape::Box { extents } => extents[2].min(extents[0]),
                    Shape::Cylinder { radius, .. } => radius,
                    _ => 0.0,
                })
                .fold(0.0, f64::max);
            (field, solids, tallest)
        };
        let (easy, hard) = (measure(Tier::Easy), measure(Tier::Hard));
        let harder = match family {
            Family::Rough | Family::Hills | Family::Slope => hard.0 > easy.0,
            Family::Steps | Family::Stairs => hard.2 > easy.2,
            Family::Pegs | Family::Rubble => hard.1 > easy.1 && hard.2 > easy.2,
            // Narrower: the walls' pieces stand closer; the same count, straighter or not.
            Family::Channel => hard.1 >= easy.1,
        };
        assert!(harder, "{family}: easy {easy:?}, hard {hard:?}");
    }
}

#[test]
fn bad_terrain_elements_are_located_errors() {
    let cases = [
        (
            r#"<Terrain family="lava" difficulty="0.5"/>"#,
            ErrorKind::UnknownReference,
            "lava",
        ),
        (
            r#"<Terrain family="pegs" difficulty="1.5"/>"#,
            ErrorKind::OutOfRange,
            "difficulty",
        ),
        (
            r#"<Terrain family="pegs" difficulty="NaN"/>"#,
            ErrorKind::InvalidValue,
            "difficulty",
        ),
        (
            r#"<Terrain family="pegs"/>"#,
            ErrorKind::Missing,
            "difficulty",
        ),
        (
            r#"<Terrain family="pegs" difficulty="hard" seed="-1"/>"#,
            ErrorKind::InvalidValue,
            "seed",
        ),
        (
            r#"<Terrain family="rough" difficulty="easy" length="500" width="40"/>"#,
            ErrorKind::OutOfRange,
            "height-field nodes",
        ),
        (
            r#"<Terrain family="rubble" difficulty="1" length="500" width="50"/>"#,
            ErrorKind::OutOfRange,
            "bodies",
        ),
        (
            r#"<Terrain family="pegs" difficulty="easy" colour="red"/>"#,
            ErrorKind::UnknownElement,
            "colour",
        ),
    ];
    for (element, kind, says) in cases {
        let text = format!("<Environment>\n  {element}\n</Environment>");
        let e = parse_environment_file("bad.env.xml", &text).unwrap_err();
        assert_eq!(e.kind, kind, "{element}: {e}");
        assert_eq!(e.pos.line, 2, "{element}: {e}");
        assert!(e.to_string().contains(says), "{element}: {e}");
    }
}

#[test]
fn a_terrain_round_trips_through_its_file() {
    let mut spec = TerrainSpec::new(Family::Channel, 0.35, 12);
    spec.length = 40.0;
    let text = terrain_env(&spec).replace("/>", " length=\"40\"/>");
    let file = parse_environment_file("t.env.xml", &text).unwrap();
    let written = proleg::config::environment::write_environment_file(&file);
    let again = parse_environment_file("t.env.xml", &written).unwrap();
    assert_eq!(file.objects, again.objects);
    let proleg::config::environment::EnvObject::Terrain(read) = &again.objects[0] else {
        panic!("not a terrain: {written}");
    };
    assert_eq!(read.length, 40.0);
    assert_eq!(geometry(read), geometry(&spec));
}

#[test]
fn proleg_terrain_writes_a_course_that_loads_as_the_element_does() {
    let dir = common::scratch("terrain_command");
    for family in [Family::Rough, Family::Pegs] {
        let out = dir.join(format!("{family}.env.xml"));
        let args = proleg::cli::terrain::TerrainArgs {
            family: family.name().into(),
            difficulty: "hard".into(),
            seed: 4,
            length: 10.0,
            width: 2.0,
            out: out.clone(),
            element: false,
        };
        let report = proleg::cli::terrain::run(&args).unwrap();
        assert_eq!(report.mesh.is_some(), family.is_field(), "{report}");
        let text = std::fs::read_to_string(&out).unwrap();
        let written = environment(&out, &text);
        let spec = proleg::cli::terrain::spec(&args).unwrap();
        let element = format!(
            "<Environment><Terrain family=\"{family}\" difficulty=\"hard\" seed=\"4\" length=\"10\" width=\"2\"/></Environment>"
        );
        let generated = environment(&dir.join("g.env.xml"), &element);
        assert_eq!(
            written.bodies.len(),
            generated.bodies.len(),
            "{}",
            spec.label()
        );
        for (a, b) in written.bodies.iter().zip(&generated.bodies) {
            let d: f64 = (0..3)
                .map(|i| (a.pose.translation[i] - b.pose.translation[i]).abs())
                .fold(0.0, f64::max);
            assert!(
                d < 1e-4,
                "{} moved {d} m on the way through the file",
                a.name
            );
        }
    }
    let bad = proleg::cli::terrain::TerrainArgs {
        family: "pegs".into(),
        difficulty: "2".into(),
        seed: 1,
        length: 30.0,
        width: 3.0,
        out: dir.join("x.env.xml"),
        element: false,
    };
    let e = proleg::cli::terrain::run(&bad).unwrap_err();
    assert!(
        matches!(
            e,
            proleg::cli::terrain::TerrainCommandError::Terrain(
                proleg::config::terrain::TerrainError::Difficulty(_)
            )
        ),
        "{e}"
    );
    assert!(!dir.join("x.env.xml").exists());
}

/// A small suite: two tasks, two test courses each, short episodes.
const SMALL_SUITE: &str = r#"<Suite name="small">
  <Task name="rough-easy" family="rough" difficulty="easy" duration="6" goal="0.3" train="1-4" test="101-102"/>
  <Task name="pegs-hard" family="pegs" difficulty="hard" duration="6" goal="0.3" test="101-102"/>
</Suite>"#;

fn engines_here() -> Vec<EngineKind> {
    let mut engines = vec![EngineKind::Rapier];
    if common::mujoco_here("suite on MuJoCo") {
        engines.push(EngineKind::Mujoco);
    }
    engines
}

fn small_run<'a>(
    suite: &'a proleg::config::suite::SuiteFile,
    controller: &'a proleg::config::Simulation,
    journal: std::path::PathBuf,
) -> proleg::suite::SuiteRun<'a> {
    proleg::suite::SuiteRun {
        path: "small.suite.xml".into(),
        suite,
        controller,
        label: "demo".into(),
        engines: engines_here(),
        tasks: vec![0, 1],
        threads: 2,
        journal,
        shared: None,
    }
}

#[test]
fn a_suite_run_stopped_halfway_resumes_to_the_same_table() {
    let dir = common::scratch("suite_resume");
    let suite = proleg::config::suite::parse_suite_file("small.suite.xml", SMALL_SUITE).unwrap();
    let demo = load_simulation("configs/demo.simulation.xml").unwrap();
    let registry = proleg::control::ModuleRegistry::standard();
    let quiet = |_: &proleg::sim::episode::course::EpisodeResult, _: usize, _: usize| {};
    let whole = small_run(&suite, &demo, dir.join("whole.csv"))
        .run(&registry, None, &quiet)
        .unwrap();
    assert_eq!(whole.tasks.len(), 2, "{whole}");
    assert!(
        whole.tasks[0].mean > 0.1,
        "the sine crawls ahead on easy ground:\n{whole}"
    );
    assert_eq!(
        whole.aggregates.len(),
        3,
        "all, trained, held out:\n{whole}"
    );
    // The chart draws a bar of each colour (trained, held out).
    let png = dir.join("suite.png");
    proleg::suite::chart::plot(&whole, &[0.3, 0.3], &png, (800, 450)).unwrap();
    let (pixels, w, h, bpp) = common::window::png_pixels(&png);
    assert_eq!((w, h), (800, 450));
    let count = |rgb: [u8; 3]| pixels.chunks(bpp).filter(|p| p[..3] == rgb).count();
    assert!(count([70, 110, 200]) > 500, "no trained task's bar");
    assert!(count([220, 120, 40]) > 500, "no held-out task's bar");
    // Stopped after two episodes: the rest is abandoned, the two are in the journal.
    let stop = proleg::signal::StopFlag::default();
    let raise = |_: &proleg::sim::episode::course::EpisodeResult, done: usize, _: usize| {
        if done >= 2 {
            stop.stop();
        }
    };
    let journal = dir.join("stopped.csv");
    let e = small_run(&suite, &demo, journal.clone())
        .run(&registry, Some(&stop), &raise)
        .unwrap_err();
    let proleg::suite::SuiteError::Stopped { done, total } = e else {
        panic!("{e}");
    };
    assert!(done >= 2 && done < total, "{done} of {total}");
    let resumed = small_run(&suite, &demo, journal.clone())
        .run(&registry, None, &quiet)
        .unwrap();
    assert_eq!(resumed, whole, "resumed:\n{resumed}\nwhole:\n{whole}");
    // A journal of another controller is refused, not mixed in.
    let mut other = demo.clone();
    other.files.simulation.properties.seed += 1;
    let e = small_run(&suite, &other, journal)
        .run(&registry, None, &quiet)
        .unwrap_err();
    assert!(e.to_string().contains("another run"), "{e}");
}

#[test]
fn the_shipped_suite_holds_out_two_families_and_names_unknown_tasks() {
    let path = common::root().join("configs/suites/locomotion.suite.xml");
    let suite = proleg::config::suite::load_suite(&FsSource, &path).unwrap();
    assert_eq!(suite.tasks.len(), Family::ALL.len() * Tier::ALL.len());
    assert!(suite.held_out_families().len() >= 2);
    for t in &suite.tasks {
        assert!(
            t.terrain.length >= 30.0,
            "{}: the course ends too soon",
            t.name
        );
    }
    let e =
        proleg::suite::SuiteRun::select(&suite, &["pegs-easy".into(), "lava".into()]).unwrap_err();
    assert!(
        matches!(&e, proleg::suite::SuiteError::UnknownTask { name, .. } if name == "lava"),
        "{e}"
    );
}
