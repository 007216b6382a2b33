//! Results across engines: an optimizer file with `<engines>rapier mujoco</engines>`
//! scores each candidate on both and stores each engine's score; `proleg results` shows them,
//! a replay on either engine reproduces that engine's stored score; `proleg compare` measures
//! one simulation on both engines; the environment's contact model is read, written and
//! refused where an engine has no counterpart.

mod common;

use proleg::config::contact::{FrictionCombine, FrictionCone};
use proleg::config::cross_engine::Combine;
use proleg::config::environment::{parse_environment_file, write_environment_file};
use proleg::config::optimizer::{parse_optimizer_file, write_optimizer_file};
use proleg::config::simulation::EngineKind;
use proleg::control::{ModuleRegistry, load_simulation};
use proleg::optimize::replay::{Which, replay_from};
use proleg::optimize::store::{Store, StoreLocation};
use proleg::sim::{BuildOptions, Simulator};

const BOTH: &str = "configs/gait_from_scratch_engines.simulation.xml";

#[test]
fn a_cross_engine_run_stores_both_scores_combines_them_by_min_and_replays_each() {
    if !common::mujoco_here("cross-engine optimization") {
        return;
    }
    let dir = common::scratch("cross_engine_run");
    let store = dir.join("runs.sqlite").display().to_string();
    let (ok, out, err) = common::proleg(&[
        "optimize",
        BOTH,
        "--max-evals",
        "12",
        "--duration",
        "2",
        "--store",
        &store,
        "--workers",
        "2",
    ]);
    assert!(ok, "{err}");
    assert!(
        err.contains("rapier+mujoco (min): each candidate scored on every engine"),
        "{err}"
    );
    assert!(
        out.contains("  on rapier ") && out.contains("  on mujoco "),
        "{out}"
    );
    let mut s = Store::open_existing(&StoreLocation::parse(&store).unwrap()).unwrap();
    let runs = s.runs().unwrap();
    assert_eq!(runs[0].info.algorithm, "CMA-ES on rapier+mujoco (min)");
    let evals = s.evaluations(runs[0].id).unwrap();
    assert_eq!(evals.len(), 12);
    for e in &evals {
        let kinds: Vec<EngineKind> = e.engines.iter().map(|(k, _)| *k).collect();
        assert_eq!(kinds, vec![EngineKind::Rapier, EngineKind::Mujoco]);
        let lower = e.engines[0].1.min(e.engines[1].1);
        assert_eq!(e.score, lower, "the score is the lower engine score");
    }
    // The engines disagree on some candidate (else the combination would be moot).
    assert!(evals.iter().any(|e| e.engines[0].1 != e.engines[1].1));
    let (ok, listed, err) = common::proleg(&["results", &store]);
    assert!(ok, "{err}");
    assert!(
        listed.contains("(rapier ") && listed.contains(", mujoco "),
        "{listed}"
    );
    // `robustness --engines` checks the best on each engine in turn.
    let (ok, checked, err) = common::proleg(&[
        "robustness",
        &store,
        "--run",
        &runs[0].id.to_string(),
        "--episodes",
        "2",
        "--engines",
        "rapier,mujoco",
    ]);
    assert!(ok, "{err}");
    assert!(
        checked.contains("on rapier\n") && checked.contains("on mujoco\n"),
        "{checked}"
    );
    assert_eq!(checked.matches("kept ").count(), 2, "{checked}");
    // The best replayed on each engine gives that engine's stored score, step for step.
    let registry = ModuleRegistry::standard();
    let best = replay_from(&store, runs[0].id, Which::Best, None, &registry).unwrap();
    for engine in [EngineKind::Rapier, EngineKind::Mujoco] {
        let r = best.clone().on_engine(engine);
        let stored = r
            .stored_engines
            .iter()
            .find(|(k, _)| *k == engine)
            .map(|(_, s)| *s)
            .unwrap();
        assert_eq!(r.stored_score, stored);
        assert_eq!(r.score().unwrap(), stored, "replay on {engine}");
    }
}

#[test]
fn engines_and_combine_round_trip_and_bad_ones_are_named() {
    let path = common::root().join("configs/optimizer/gait_from_scratch_engines.cmaes.xml");
    let text = std::fs::read_to_string(&path).unwrap();
    let file = parse_optimizer_file("o.xml", &text).unwrap();
    let cross = file.cross_engine.clone().unwrap();
    assert_eq!(cross.engines, vec![EngineKind::Rapier, EngineKind::Mujoco]);
    assert_eq!(cross.combine, Combine::Min);
    let again = parse_optimizer_file("o.xml", &write_optimizer_file(&file)).unwrap();
    assert_eq!(again, file);
    for (bad, says) in [
        ("<engines>rapier</engines>", "two or more engines"),
        (
            "<engines>rapier ode</engines>",
            "unknown physics engine `ode`",
        ),
        ("<engines>rapier rapier</engines>", "names rapier twice"),
        ("<combine>max</combine>", "<combine> is min or mean"),
    ] {
        let broken = text.replace(
            "<engines>rapier mujoco</engines>\n    <combine>min</combine>",
            bad,
        );
        let e = parse_optimizer_file("o.xml", &broken)
            .unwrap_err()
            .to_string();
        assert!(e.contains(says) && e.contains("o.xml:"), "{bad}: {e}");
    }
    let lone = text.replace("<engines>rapier mujoco</engines>\n", "");
    let e = parse_optimizer_file("o.xml", &lone)
        .unwrap_err()
        .to_string();
    assert!(e.contains("<combine> needs <engines>"), "{e}");
}

#[test]
fn compare_measures_both_engines_and_draws_the_paths() {
    if !common::mujoco_here("proleg compare") {
        return;
    }
    let png = common::scratch("cross_engine_compare").join("demo.png");
    let (ok, out, err) = common::proleg(&[
        "compare",
        "configs/demo.simulation.xml",
        "--duration",
        "3",
        "--plot",
        png.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    for row in [
        "displacement (m)",
        "penetration max (mm)",
        "slip of contacts (m/s)",
        "link 0 in contact (%)",
        "spread: the smallest displacement is",
    ] {
        assert!(out.contains(row), "{row}: {out}");
    }
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    let (ok, _, err) =
        common::proleg(&["compare", "configs/demo.simulation.xml", "--engines", "ode"]);
    assert!(!ok && err.contains("ode"), "{err}");
}

#[test]
fn compare_sees_the_robot_touch_the_ground_and_move_on_rapier() {
    let sim = load_simulation(common::root().join("configs/demo.simulation.xml")).unwrap();
    let c = proleg::bench::compare::compare(
        &sim,
        &[EngineKind::Rapier],
        3.0,
        &ModuleRegistry::standard(),
    )
    .unwrap();
    let r = c.on(EngineKind::Rapier).unwrap();
    assert!(r.displacement > 0.1, "{c}");
    assert_eq!(r.contact_share.len(), sim.robot.links.len());
    assert!(r.contact_share.iter().any(|s| *s > 0.2), "{c}");
    assert!(r.penetration_max > 0.0 && r.penetration_max < 0.005, "{c}");
    assert!(r.slip_mean > 0.0 && r.slip_mean.is_finite(), "{c}");
    assert!(r.path.len() > 100 && r.joints.len() == r.path.len());
}

#[test]
fn the_contact_model_round_trips_and_each_engine_refuses_what_it_lacks() {
    let text = std::fs::read_to_string(common::root().join("configs/environments/flat.env.xml"))
        .unwrap()
        .replace(
            "</odeproperties>",
            "<contact><timeConstant>0.004</timeConstant><dampingRatio>1</dampingRatio>\
             <frictionCombine>mean</frictionCombine><frictionCone>pyramidal</frictionCone>\
             </contact></odeproperties>",
        );
    let env = parse_environment_file("e.env.xml", &text).unwrap();
    let c = env.physics.contact.unwrap();
    assert_eq!((c.time_constant, c.damping_ratio), (0.004, 1.0));
    assert_eq!(c.friction_combine, FrictionCombine::Mean);
    assert_eq!(c.friction_cone, FrictionCone::Pyramidal);
    let again = parse_environment_file("e.env.xml", &write_environment_file(&env)).unwrap();
    assert_eq!(again, env);
    let bad = text.replace(
        "<dampingRatio>1</dampingRatio>",
        "<dampingRatio>-1</dampingRatio>",
    );
    let e = parse_environment_file("e.env.xml", &bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("e.env.xml:"), "{e}");
    // rapier's cone is elliptic; MuJoCo has no mean friction rule.
    let mut sim = load_simulation(common::root().join("configs/demo.simulation.xml")).unwrap();
    sim.environment.physics.contact = Some(c);
    let opts = BuildOptions::default();
    let e = Simulator::new(&sim, &opts).err().unwrap().to_string();
    assert!(
        e.contains("rapier cannot simulate this") && e.contains("pyramidal"),
        "{e}"
    );
    if common::mujoco_here("contact model on MuJoCo") {
        let on_mujoco = sim.clone().with_engine(Some(EngineKind::Mujoco));
        let e = Simulator::new(&on_mujoco, &opts).err().unwrap().to_string();
        assert!(
            e.contains("MuJoCo cannot simulate this") && e.contains("mean"),
            "{e}"
        );
    }
}

#[test]
fn a_stiffer_contact_presses_a_resting_robot_less_into_the_floor() {
    // The contact model reaches the engines: rapier's resting penetration follows its
    // spring (static deflection g tau^2 at damping ratio 1).
    let registry = ModuleRegistry::standard();
    let mut depths = Vec::new();
    for tau in [0.02, 0.005] {
        let mut sim = load_simulation(common::root().join("configs/demo.simulation.xml")).unwrap();
        sim.actuation.modules.clear();
        let mut c = sim.environment.physics.contact_model();
        c.time_constant = tau;
        c.damping_ratio = 1.0;
        sim.environment.physics.contact = Some(c);
        let c =
            proleg::bench::compare::compare(&sim, &[EngineKind::Rapier], 2.0, &registry).unwrap();
        depths.push(c.runs[0].penetration_mean);
    }
    assert!(depths[0] > 4.0 * depths[1], "{depths:?}");
}

/// Every evaluation of a store as its TSV rows without the store's name and wall seconds:
/// number, round, score, best so far, genome, values, engine scores.
fn exported(store: &str, name: &str) -> Vec<String> {
    let tsv = common::scratch(name).join("evaluations.tsv");
    let (ok, _, err) = common::proleg(&["results", store, "--export", tsv.to_str().unwrap()]);
    assert!(ok, "{err}");
    common::table_columns(
        &std::fs::read_to_string(&tsv).unwrap(),
        &[
            "evaluation",
            "round",
            "score",
            "best",
            "genome",
            "values",
            "engine_scores",
        ],
    )
}

#[test]
fn a_killed_cross_engine_run_resumes_with_every_engine_score() {
    if !common::mujoco_here("cross-engine resume") {
        return;
    }
    let dir = common::scratch("cross_engine_resume");
    let run = |extra: &[&str], store: &str| {
        let mut args = vec![
            "optimize",
            BOTH,
            "--max-evals",
            "20",
            "--duration",
            "1",
            "--quiet",
            "--store",
            store,
        ];
        args.extend(extra);
        common::proleg(&args)
    };
    let whole = dir.join("whole.sqlite").display().to_string();
    let (ok, _, err) = run(&[], &whole);
    assert!(ok, "{err}");
    let killed = dir.join("killed.sqlite").display().to_string();
    let (ok, _, _) = run(&["--crash-after", "10"], &killed);
    assert!(!ok, "the crash aid aborts the process");
    let (ok, _, err) = run(&["--resume"], &killed);
    assert!(ok, "{err}");
    let rows = exported(&killed, "cross_engine_resume_killed");
    assert_eq!(rows.len(), 20);
    assert!(
        rows.iter()
            .all(|r| r.contains("rapier=") && r.contains("mujoco="))
    );
    assert_eq!(rows, exported(&whole, "cross_engine_resume_whole"));
}
