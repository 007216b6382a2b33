//! Co-design: a genome's body is the robot the builder makes, it loads and runs like any
//! robot, the same candidate scores the same every time, a killed co-design run resumes
//! to the same archive, a stored body replays to its stored score, invalid bodies are
//! rejected unrun with their reason, robust fitness and measured descriptors work with
//! bodies, and the genetic algorithm searches bodies and gaits together.

mod common;

use std::sync::Arc;

use proleg::config::fitness::Fitness;
use proleg::config::resolve::robot::JointOrientation;
use proleg::config::source::FsSource;
use proleg::control::{ModuleRegistry, load_simulation_in};
use proleg::optimize::design::{Design, DesignSpace};
use proleg::optimize::evaluate::Evaluator;
use proleg::optimize::replay::{Which, replay_from};
use proleg::optimize::run::prepare;

const CONFIG: &str = "configs/codesign_flat.simulation.xml";

#[test]
fn a_genome_builds_a_body_that_loads_and_crawls_the_same_every_time() {
    let registry = ModuleRegistry::standard();
    let sim = load_simulation_in(common::root().join(CONFIG), &registry).unwrap();
    let (space, start) = prepare(&sim, &registry).unwrap();
    let model = sim.optimizer.as_ref().unwrap();
    let design_space = DesignSpace::from_model(model).unwrap();
    assert_eq!(space, design_space.search_space());
    // modules, 8 orientation genes, parts, 2 orientations x 3 gait parameters.
    assert_eq!(space.genes.len(), 1 + 8 + 1 + 6);
    // 7 modules: joints y y p y p p (two yaw joints in a row need the YY part).
    let mut genome = start.clone();
    genome[0] = 4;
    genome[1..9].copy_from_slice(&[1, 1, 0, 1, 0, 0, 0, 0]);
    let design = Design::of(&sim, Arc::new(FsSource)).unwrap();
    let body = design.simulation(&genome, &registry).unwrap();
    let kinds: Vec<JointOrientation> = body.robot.joints.iter().map(|j| j.orientation).collect();
    use JointOrientation::{Pitch as P, Yaw as Y};
    assert_eq!(kinds, vec![Y, Y, P, Y, P, P]);
    assert_eq!(
        body.actuation.modules.len(),
        2,
        "one sine per orientation group"
    );

    // A 6-module pitch snake with the demo's wave: amplitude 40, phase difference 60,
    // 1 Hz (the pitch group's genes; the yaw group's are unused).
    let mut snake = start.clone();
    snake[0] = 3;
    snake[1..9].copy_from_slice(&[0; 8]);
    snake[10..13].copy_from_slice(&[8, 16, 3]);
    let evaluator = Evaluator::new(&sim, &registry, &space, Fitness::Displacement, 3.0, 1);
    let genomes = vec![snake.clone(), genome.clone(), snake];
    let scores = evaluator.evaluate(&genomes).unwrap();
    assert!(scores.iter().all(|s| s.is_finite()), "{scores:?}");
    assert_eq!(scores[0], scores[2], "the same candidate scores the same");
    assert_ne!(scores[0], scores[1], "another body moves otherwise");
    assert!(scores[0] > 0.1, "the pitch snake crawls: {scores:?}");
}

#[test]
fn a_killed_co_design_run_resumes_to_the_same_archive() {
    let dir = common::scratch("codesign_resume");
    let run = |extra: &[&str], store: &std::path::Path| {
        common::optimize(CONFIG, ("60", "1"), store, extra)
    };
    let whole = dir.join("whole.sqlite");
    let (ok, full, err) = run(&[], &whole);
    assert!(ok, "{err}");
    let archive = common::archive_line(&whole);
    assert!(archive.contains("share of yaw joints"), "{archive}");
    let killed = dir.join("killed.sqlite");
    let (ok, _, _) = run(&["--crash-after", "45"], &killed);
    assert!(!ok, "the crash aid aborts the process");
    let (ok, resumed, err) = run(&["--resume"], &killed);
    assert!(ok, "{err}");
    let best = |out: &str| -> Vec<String> {
        out.lines()
            .skip_while(|l| !l.starts_with("best score"))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(best(&resumed), best(&full));
    assert_eq!(common::archive_line(&killed), archive);
    // A stored body replays to its stored score: the best, and one from the middle.
    let registry = ModuleRegistry::standard();
    for which in [Which::Best, Which::Number(30)] {
        let r = replay_from(whole.to_str().unwrap(), 1, which, None, &registry).unwrap();
        assert_eq!(r.score().unwrap(), r.stored_score, "{}", r.label);
    }
}

/// The flat co-design set-up copied into `dir`, its optimizer file and environment
/// changed by `optimizer` and `environment`; the simulation file's path.
fn setup_in(
    dir: &std::path::Path,
    optimizer: impl Fn(String) -> String,
    environment: impl Fn(String) -> String,
) -> std::path::PathBuf {
    let configs = common::root().join("configs");
    let copy = |from: &str| {
        let to = dir.join(from);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(configs.join(from), to).unwrap();
    };
    for folder in ["parts", "sensors"] {
        for file in std::fs::read_dir(configs.join(folder)).unwrap() {
            let name = file.unwrap().file_name();
            copy(&format!("{folder}/{}", name.to_string_lossy()));
        }
    }
    copy("robots/snake5p.robot.xml");
    copy("actuation/snake5p_sine40.actuation.xml");
    let write = |to: &str, text: String| {
        std::fs::create_dir_all(dir.join(to).parent().unwrap()).unwrap();
        std::fs::write(dir.join(to), text).unwrap();
    };
    let read = |from: &str| std::fs::read_to_string(configs.join(from)).unwrap();
    write(
        "optimizer/codesign.mapelites.xml",
        optimizer(read("optimizer/codesign.mapelites.xml")),
    );
    write(
        "environments/flat.env.xml",
        environment(read("environments/flat.env.xml")),
    );
    write(
        "codesign.simulation.xml",
        read("codesign_flat.simulation.xml"),
    );
    dir.join("codesign.simulation.xml")
}

/// The flat co-design set-up in `dir`, with touch parts allowed and a wall across the floor
/// 0.4 m ahead of the tail, where only bodies of 7 or more modules reach.
fn walled_setup(dir: &std::path::Path) -> std::path::PathBuf {
    setup_in(
        dir,
        |o| o.replace("<parts>plain</parts>", "<parts>plain touch</parts>"),
        |e| {
            e.replace(
                "</Environment>",
                r#"<KinBody name="wall"><Body type="static"><Translation>0 0.45 0.1</Translation>
  <Geom type="box"><extents>1 0.05 0.1</extents></Geom></Body></KinBody>
</Environment>"#,
            )
        },
    )
}

#[test]
fn robust_co_design_scores_each_body_over_its_own_randomized_episodes() {
    use proleg::optimize::robust::combine;
    let dir = common::scratch("codesign_robust");
    let config = setup_in(
        &dir,
        |o| {
            o.replace(
                "<morphology>",
                "<robustness><episodes>3</episodes><friction>30</friction><mass>10</mass>\
                 <heading>20</heading></robustness>\n  <morphology>",
            )
        },
        |e| e,
    );
    let store = dir.join("robust.sqlite");
    let (ok, _, err) = common::optimize(config.to_str().unwrap(), ("12", "1"), &store, &[]);
    assert!(ok, "{err}");
    let registry = ModuleRegistry::standard();
    let location = store.to_str().unwrap();
    let mut opened = proleg::optimize::store::Store::open_existing(
        &proleg::optimize::store::StoreLocation::parse(location).unwrap(),
    )
    .unwrap();
    let mut bodies = std::collections::BTreeSet::new();
    for e in opened.evaluations(1).unwrap() {
        // Each episode replays with the evaluation's own body; their mean is the score.
        let scores: Vec<f64> = (0..3)
            .map(|k| {
                let r = proleg::optimize::replay::load_replay(
                    &mut opened,
                    1,
                    e.number,
                    Some(k),
                    &registry,
                )
                .unwrap();
                bodies.insert(r.sim.robot.joints.len());
                r.score().unwrap()
            })
            .collect();
        assert_eq!(combine(&scores, None), e.score, "evaluation {}", e.number);
        assert_ne!(scores[0], scores[1], "the episodes differ: {scores:?}");
    }
    assert!(bodies.len() > 1, "bodies of several lengths: {bodies:?}");
}

#[test]
fn invalid_bodies_are_rejected_unrun_with_their_reason() {
    use proleg::optimize::design::{Candidate, Rejection};
    let dir = common::scratch("codesign_rejects");
    let config = walled_setup(&dir);
    let registry = ModuleRegistry::standard();
    let sim = load_simulation_in(&config, &registry).unwrap();
    let (space, start) = prepare(&sim, &registry).unwrap();
    let design = Design::of(&sim, Arc::new(FsSource)).unwrap();
    // Genes: modules (from 3), 8 orientations, parts (plain, touch), the gait.
    let body = |modules: u32, orientations: [u32; 8], parts: u32| {
        let mut g = start.clone();
        g[0] = modules - 3;
        g[1..9].copy_from_slice(&orientations);
        g[9] = parts;
        g
    };
    let short = body(3, [0; 8], 0);
    let long = body(9, [0; 8], 0);
    let touch = body(4, [0, 1, 0, 0, 0, 0, 0, 0], 1);
    let verdict = |g| match design.candidate(g, &registry).unwrap() {
        Candidate::Run(_) => None,
        Candidate::Rejected(why) => Some(why),
    };
    assert_eq!(verdict(&short), None);
    assert_eq!(verdict(&touch), None, "touch parts, their sensors found");
    let wall = verdict(&long).expect("the long body starts inside the wall");
    assert!(matches!(&wall, Rejection::Start(_)), "{wall:?}");
    assert!(wall.to_string().contains("wall"), "{wall}");

    // Rejected bodies score -inf with their reason; the others run.
    let evaluator = Evaluator::new(&sim, &registry, &space, Fitness::Displacement, 1.0, 1);
    let scored = evaluator
        .evaluate_with(&[short, long, touch], |_, _, _| {})
        .unwrap();
    assert!(scored[0].score.is_finite() && scored[0].rejected.is_none());
    assert_eq!(scored[1].score, f64::NEG_INFINITY);
    assert_eq!(scored[1].rejected, Some(wall));
    assert!(scored[2].score.is_finite() && scored[2].rejected.is_none());

    // A run stores each rejected body's reason, counts them, and keeps none in its archive.
    let store = dir.join("run.sqlite");
    let (ok, _, err) = common::optimize(config.to_str().unwrap(), ("60", "1"), &store, &[]);
    assert!(ok, "{err}");
    let location = proleg::optimize::store::StoreLocation::parse(store.to_str().unwrap()).unwrap();
    let mut opened = proleg::optimize::store::Store::open_existing(&location).unwrap();
    let evals = opened.evaluations(1).unwrap();
    let reasons: Vec<&str> = evals.iter().filter_map(|e| e.rejected.as_deref()).collect();
    assert!(
        reasons.iter().any(|r| r.contains("inside wall")),
        "{reasons:?}"
    );
    for e in evals.iter().filter(|e| e.rejected.is_some()) {
        assert_eq!(e.score, f64::NEG_INFINITY, "evaluation {}", e.number);
    }
    let (ok, out, err) = common::proleg(&["results", store.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(
        out.contains(&format!("{} candidates rejected", reasons.len())),
        "{out}"
    );
}

#[test]
fn a_self_intersecting_start_pose_names_its_links() {
    use proleg::config::start_clearance::{StartOverlap, start_overlaps};
    let dir = common::scratch("start_overlap");
    let body = |name: &str, y: f64| {
        format!(
            "<Body name=\"{name}\" type=\"dynamic\"><Translation>0 {y} 0.03</Translation>\
             <Geom type=\"box\"><extents>0.03 0.03 0.03</extents></Geom></Body>\n"
        )
    };
    let joint = |name: &str, a: &str, b: &str| {
        format!(
            "<Joint type=\"hinge\" name=\"{name}\"><Body>{a}</Body><Body>{b}</Body>\
             <offsetfrom>{b}</offsetfrom><axis>1 0 0</axis></Joint>\n"
        )
    };
    let write = |c: f64| {
        let robot = format!(
            "<Robot name=\"fold\"><KinBody name=\"fold\">\n{}{}{}{}{}</KinBody></Robot>\n",
            body("a", 0.0),
            body("b", 0.06),
            body("c", c),
            joint("j1", "a", "b"),
            joint("j2", "b", "c")
        );
        std::fs::write(dir.join("fold.robot.xml"), robot).unwrap();
        std::fs::write(
            dir.join("fold.actuation.xml"),
            "<actuation><validRobot robotName=\"fold.robot.xml\"/></actuation>",
        )
        .unwrap();
        let sim = dir.join("fold.simulation.xml");
        std::fs::write(
            &sim,
            "<simulation><robot>fold.robot.xml</robot><actuation>fold.actuation.xml</actuation>\
             <simulationProperties><stepWidth>0.001</stepWidth><duration>1</duration>\
             </simulationProperties></simulation>",
        )
        .unwrap();
        load_simulation_in(&sim, &ModuleRegistry::standard()).unwrap()
    };
    // Link c folded back 2 cm into link a (which no joint connects to it); the touching
    // neighbours a-b and b-c do not count.
    let folded = start_overlaps(&write(0.04));
    assert_eq!(folded.len(), 1, "{folded:?}");
    let StartOverlap::SelfIntersection { a, b, depth } = &folded[0] else {
        panic!("{folded:?}")
    };
    assert_eq!((a.as_str(), b.as_str()), ("a", "c"));
    assert!((depth - 0.02).abs() < 1e-9, "{depth}");
    assert!(folded[0].to_string().contains("self-intersecting"));
    // Laid out straight, nothing overlaps.
    assert_eq!(start_overlaps(&write(0.12)), Vec::new());
}

#[test]
fn measured_descriptors_map_bodies_by_how_they_move_and_resume_to_the_same_archive() {
    use proleg::config::optimizer::Quantity;
    use proleg::optimize::store::{Store, StoreLocation};
    let dir = common::scratch("codesign_measured");
    let config = setup_in(
        &dir,
        |o| {
            o.replace(
                r#"<descriptor gene="1" bins="7"/>
    <descriptor name="yaw-share" bins="5"/>"#,
                r#"<descriptor name="height" min="0" max="0.06" bins="4"/>
    <descriptor name="curvature" min="0" max="90" bins="3"/>"#,
            )
        },
        |e| e,
    );
    let registry = ModuleRegistry::standard();
    let sim = load_simulation_in(&config, &registry).unwrap();
    let (space, start) = prepare(&sim, &registry).unwrap();
    let evaluator = Evaluator::new(&sim, &registry, &space, Fitness::Displacement, 3.0, 1);
    assert_eq!(evaluator.measures, [Quantity::Height, Quantity::Curvature]);
    // A 6-module pitch snake lying still is flat; waving at 40 degrees it arches, and it
    // crawls straight on.
    let snake = |amplitude: u32| {
        let mut g = start.clone();
        g[0] = 3;
        g[1..9].copy_from_slice(&[0; 8]);
        g[10..13].copy_from_slice(&[amplitude, 16, 3]);
        g
    };
    let scored = evaluator
        .evaluate_with(&[snake(0), snake(8)], |_, _, _| {})
        .unwrap();
    let (still, waving) = (&scored[0].measures, &scored[1].measures);
    assert!(still[0] < 0.002, "a still snake is flat: {still:?}");
    assert!(waving[0] > still[0] + 0.005, "waving arches it: {waving:?}");
    assert!(
        waving[1] < 30.0,
        "a pitch snake crawls straight on: {waving:?}"
    );

    // A run stores every evaluation's measures; its archive places each elite by them;
    // killed and resumed, it ends with the same archive.
    let run = |extra: &[&str], store: &std::path::Path| {
        common::optimize(config.to_str().unwrap(), ("40", "2"), store, extra)
    };
    let whole = dir.join("whole.sqlite");
    let (ok, _, err) = run(&[], &whole);
    assert!(ok, "{err}");
    let archive = common::archive_line(&whole);
    assert!(
        archive.contains("over body height (m) x path curvature (deg)"),
        "{archive}"
    );
    let killed = dir.join("killed.sqlite");
    let (ok, _, _) = run(&["--crash-after", "25"], &killed);
    assert!(!ok, "the crash aid aborts the process");
    let (ok, _, err) = run(&["--resume"], &killed);
    assert!(ok, "{err}");
    assert_eq!(common::archive_line(&killed), archive);
    let mut store =
        Store::open_existing(&StoreLocation::parse(whole.to_str().unwrap()).unwrap()).unwrap();
    let evals = store.evaluations(1).unwrap();
    assert!(
        evals.iter().all(|e| e.measures.len() == 2),
        "{:?}",
        evals[0]
    );
    let heights: Vec<f64> = evals.iter().map(|e| e.measures[0]).collect();
    assert!(
        heights.iter().any(|h| (h - heights[0]).abs() > 1e-3),
        "bodies differ in height: {heights:?}"
    );
    let stored = proleg::optimize::archive::stored_archive(&mut store, 1, &registry)
        .unwrap()
        .unwrap();
    for (cell, elite) in stored.archive.cells.iter().enumerate() {
        let Some((genome, score)) = elite else {
            continue;
        };
        let e = evals
            .iter()
            .find(|e| &e.genome == genome && e.score == *score)
            .unwrap();
        assert_eq!(stored.archive.cell(genome, &e.measures), cell);
    }
}

#[test]
fn the_genetic_algorithm_searches_bodies_and_gaits_together() {
    use std::collections::BTreeSet;
    let dir = common::scratch("codesign_ga");
    let config = setup_in(
        &dir,
        |o| {
            o.replace("<mapElites>", "<geneticAlgorithm>")
                .replace("</mapElites>", "</geneticAlgorithm>")
                .replace(
                    r#"<initialSamples>40</initialSamples>
    <batch>10</batch>
    <mutation>0.15</mutation>
    <descriptor gene="1" bins="7"/>
    <descriptor name="yaw-share" bins="5"/>"#,
                    "<popsize>10</popsize><pmut>0.3</pmut><pcross>0.6</pcross>\
                     <nConvergence>50</nConvergence><pConvergence>0.99</pConvergence>\
                     <flushFrequency>1</flushFrequency><gaMode>1</gaMode>",
                )
        },
        |e| e,
    );
    let sim_text = std::fs::read_to_string(&config)
        .unwrap()
        .replace("MAP-Elites optimization", "GA optimization");
    std::fs::write(&config, sim_text).unwrap();
    let registry = ModuleRegistry::standard();
    let sim = load_simulation_in(&config, &registry).unwrap();
    let design = Design::of(&sim, Arc::new(FsSource)).unwrap();
    let choices = proleg::optimize::settings::RunChoices {
        max_evaluations: Some(40),
        duration: Some(1.0),
        workers: Some(2),
        ..Default::default()
    };
    let settings = proleg::optimize::settings::RunSettings::of(&sim, &choices).unwrap();
    let mut seen = Vec::new();
    let outcome =
        proleg::optimize::run::optimize(&sim, &settings, &registry, None, |e| seen.push(e.clone()))
            .unwrap();
    assert_eq!(seen.len(), 40);
    // Every genome the GA makes, by mutation or crossover, is a body that builds and
    // runs; later generations hold bodies the first did not.
    let body = |g: &Vec<u32>| design.space.body(g, "b").summary();
    for e in &seen {
        assert!(e.score.is_finite(), "evaluation {}: {}", e.number, e.score);
        assert!(design.simulation(&e.genome, &registry).is_ok());
    }
    let first: BTreeSet<String> = seen
        .iter()
        .filter(|e| e.round == 0)
        .map(|e| body(&e.genome))
        .collect();
    let later: BTreeSet<String> = seen
        .iter()
        .filter(|e| e.round > 0)
        .map(|e| body(&e.genome))
        .collect();
    assert!(later.difference(&first).count() > 0, "{first:?} {later:?}");
    assert!(
        outcome.best_score
            >= seen[..10]
                .iter()
                .map(|e| e.score)
                .fold(f64::NEG_INFINITY, f64::max)
    );
}
