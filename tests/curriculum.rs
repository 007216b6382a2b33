//! A curriculum (`<courses>` with `<stage>`s): its stages run one after another, each a
//! stored run of its own training on its stage's tasks and starting from the previous
//! stage's best, sharing the budget; a stage that never reaches its `until` ends it; a run
//! killed in a later stage resumes to the same best; the stages are located errors when
//! written wrong, and a curriculum opened as one run is refused.

mod common;

use std::path::{Path, PathBuf};

use common::proleg;
use proleg::config::ErrorKind;
use proleg::config::optimizer::{parse_optimizer_file, write_optimizer_file};
use proleg::control::ModuleRegistry;
use proleg::optimize::error::OptimizeError;
use proleg::optimize::experiment::{Experiment, ExperimentRequest};
use proleg::optimize::store::{Store, StoreLocation};

const OPTIMIZER: &str = "configs/optimizer/suite_curriculum.cmaes.xml";

/// The shipped curriculum in `dir` with its stages' `until`s replaced by `untils` (in
/// order), every path absolute; its simulation file.
fn curriculum(dir: &Path, untils: &[&str]) -> PathBuf {
    let root = common::root();
    let mut opt = std::fs::read_to_string(root.join(OPTIMIZER)).unwrap();
    for (k, until) in untils.iter().enumerate() {
        let old = ["until=\"4\"", "until=\"4\""][k];
        opt = opt.replacen(old, &format!("until=\"{until}\""), 1);
    }
    opt = opt.replace(
        "suite=\"suites/locomotion.suite.xml\"",
        &format!(
            "suite=\"{}\"",
            root.join("configs/suites/locomotion.suite.xml").display()
        ),
    );
    std::fs::write(dir.join("c.cmaes.xml"), opt).unwrap();
    let mut sim =
        std::fs::read_to_string(root.join("configs/suite_curriculum.simulation.xml")).unwrap();
    for (tag, file) in [
        ("robot", "robots/snake5p.robot.xml"),
        ("actuation", "actuation/snake5p_sine40.actuation.xml"),
        ("environment", "environments/flat.env.xml"),
    ] {
        sim = sim.replace(
            &format!("<{tag}>{file}</{tag}>"),
            &format!(
                "<{tag}>{}</{tag}>",
                root.join("configs").join(file).display()
            ),
        );
    }
    sim = sim.replace(
        "optimizer/suite_curriculum.cmaes.xml",
        &dir.join("c.cmaes.xml").display().to_string(),
    );
    let path = dir.join("c.simulation.xml");
    std::fs::write(&path, sim).unwrap();
    path
}

/// `proleg optimize` of `sim` for `evals` evaluations of 2-s episodes into `store`, with
/// `extra` arguments.
fn optimize(sim: &Path, store: &Path, evals: u64, extra: &[&str]) -> (bool, String, String) {
    let evals = evals.to_string();
    let mut args = vec![
        "optimize",
        sim.to_str().unwrap(),
        "--max-evals",
        &evals,
        "--duration",
        "2",
        "--workers",
        "2",
        "--store",
        store.to_str().unwrap(),
    ];
    args.extend(extra);
    proleg(&args)
}

/// The store at `path`, opened.
fn store(path: &Path) -> Store {
    Store::open_existing(&StoreLocation::parse(path.to_str().unwrap()).unwrap()).unwrap()
}

/// The lines that state the result: best score and best values.
fn result_lines(out: &str) -> Vec<String> {
    out.lines()
        .skip_while(|l| !l.starts_with("best score"))
        .map(str::to_string)
        .collect()
}

/// The line of `out` reporting curriculum stage `k`.
fn stage_line(out: &str, k: usize, tasks: &str) -> String {
    let line = format!("curriculum stage {k} of 3 ({tasks}): best ");
    out.lines()
        .find(|l| l.starts_with(&line))
        .unwrap_or_else(|| panic!("no {line:?} in {out}"))
        .to_string()
}

/// Each stage of the run in the store at `path` is a finished run of its own, named for
/// its stage, whose stored optimizer file trains on its tasks alone (a worker or a replay
/// builds the stage's courses from the store), with the evaluations `counts` gives, starting
/// from the previous stage's best.
fn assert_stages_stored(path: &Path, counts: &[(usize, &str, usize)]) {
    let mut s = store(path);
    let runs = s.runs().unwrap();
    assert_eq!(runs.len(), 3, "a run per stage");
    let mut previous_best: Option<Vec<u32>> = None;
    for (k, run) in runs.iter().enumerate() {
        let (_, tasks, n) = counts[k];
        assert!(
            run.info
                .algorithm
                .ends_with(&format!("curriculum stage {} of 3 ({tasks})", k + 1)),
            "{}",
            run.info.algorithm
        );
        assert!(run.finished);
        let spec = s.run_spec(run.id).unwrap();
        let optimizer = spec
            .files
            .iter()
            .find(|(p, _)| p.ends_with("c.cmaes.xml"))
            .map(|(_, text)| text.clone())
            .unwrap();
        assert!(
            optimizer.contains(&format!("tasks=\"{tasks}\"")),
            "{optimizer}"
        );
        assert!(!optimizer.contains("<stage"), "{optimizer}");
        assert!(
            spec.episodes[0]
                .draws
                .starts_with(&format!("course {tasks} seed 1;")),
            "{:?}",
            spec.episodes[0].draws
        );
        let evals = s.evaluations(run.id).unwrap();
        assert_eq!(evals.len(), n);
        if let Some(best) = &previous_best {
            assert_eq!(
                &evals[0].genome,
                best,
                "stage {} starts from the last best",
                k + 1
            );
        }
        let best = evals
            .iter()
            .fold(&evals[0], |b, e| if e.score > b.score { e } else { b });
        previous_best = Some(best.genome.clone());
    }
    assert_ne!(
        runs[0].best_values, runs[2].best_values,
        "stage 3 searched on"
    );
}

#[test]
fn the_stages_run_in_turn_from_the_last_best_and_a_killed_curriculum_resumes_to_the_same_best() {
    let dir = common::scratch("curriculum");
    // A first stage that never ends, for one generation: the start's score and the best.
    std::fs::create_dir_all(dir.join("probe")).unwrap();
    let probe = curriculum(&dir.join("probe"), &["1000", "-1000"]);
    let (ok, _, err) = optimize(&probe, &dir.join("probe.sqlite"), 9, &["--quiet"]);
    assert!(ok, "{err}");
    let evals = store(&dir.join("probe.sqlite")).evaluations(1).unwrap();
    let (start, best) = (
        evals[0].score,
        evals.iter().map(|e| e.score).fold(f64::MIN, f64::max),
    );
    assert_eq!(evals.len(), 9, "the start alone, then a generation of 8");
    assert!(
        best > start,
        "a generation improves on the start: {start} -> {best}"
    );
    // Stage 1 ends after that generation, stage 2 after its start alone (already past
    // its score), stage 3 has the rest of the 24 evaluations.
    let until = format!("{}", (start + best) / 2.0);
    let sim = curriculum(&dir, &[&until, "-1000"]);
    let whole = dir.join("whole.sqlite");
    let (ok, out, err) = optimize(&sim, &whole, 24, &["--quiet"]);
    assert!(ok, "{err}");
    let counts = [
        (1, "steps-easy", 9),
        (2, "steps-medium", 1),
        (3, "steps-hard", 14),
    ];
    for (k, tasks, n) in counts {
        let line = stage_line(&out, k, tasks);
        assert!(
            line.contains(&format!(" in {n} evaluations ({n} simulated)")),
            "{line}"
        );
    }
    assert_stages_stored(&whole, &counts);

    // Killed in the third stage (after 12 of the 24 evaluations are stored), resumed.
    let killed = dir.join("killed.sqlite");
    let (ok, _, _) = optimize(&sim, &killed, 24, &["--quiet", "--crash-after", "12"]);
    assert!(!ok, "the crash aid aborts the process");
    let (ok, resumed, err) = optimize(&sim, &killed, 24, &["--resume"]);
    assert!(ok, "{err}");
    assert!(
        err.contains("curriculum stage 1 of 3: steps-easy until a best score of")
            && err.contains(", 9 evaluations stored"),
        "{err}"
    );
    let line = stage_line(&resumed, 1, "steps-easy");
    assert!(
        line.contains("in 9 evaluations (0 simulated)"),
        "replayed from the store: {line}"
    );
    let line = stage_line(&resumed, 3, "steps-hard");
    assert!(
        !line.contains("(14 simulated)"),
        "the killed stage goes on: {line}"
    );
    assert_eq!(result_lines(&resumed), result_lines(&out));
}

#[test]
fn a_stage_that_never_reaches_its_score_ends_the_curriculum_with_its_best() {
    let dir = common::scratch("curriculum-unreached");
    let sim = curriculum(&dir, &["1000", "-1000"]);
    let (ok, out, err) = optimize(&sim, &dir.join("s.sqlite"), 17, &["--quiet"]);
    assert!(ok, "{err}");
    let line = stage_line(&out, 1, "steps-easy");
    assert!(
        line.contains("in 17 evaluations (17 simulated), did not reach 1000"),
        "{line}"
    );
    assert!(!out.contains("curriculum stage 2"), "{out}");
    assert!(out.contains("17 evaluations in 3 rounds"), "{out}");
}

#[test]
fn a_curriculum_opened_as_one_run_is_refused_naming_its_optimizer_file() {
    let dir = common::scratch("curriculum-one-run");
    let sim = curriculum(&dir, &["4", "4"]);
    let request = ExperimentRequest {
        config: sim,
        store: Some(dir.join("s.sqlite").display().to_string()),
        ..ExperimentRequest::default()
    };
    let e = Experiment::open(&request, &ModuleRegistry::standard())
        .err()
        .expect("refused");
    assert!(matches!(e, OptimizeError::CurriculumAsOneRun { .. }), "{e}");
    assert!(e.to_string().contains("c.cmaes.xml"), "{e}");
    assert!(
        !dir.join("s.sqlite").exists(),
        "refused before the store is made"
    );
}

#[test]
fn stages_written_wrong_are_located_errors_and_the_stages_round_trip() {
    let text = std::fs::read_to_string(common::root().join(OPTIMIZER)).unwrap();
    let file = parse_optimizer_file("c.cmaes.xml", &text).unwrap();
    let courses = file.courses.clone().unwrap();
    let tasks: Vec<&[String]> = courses.stages.iter().map(|s| &s.tasks[..]).collect();
    assert_eq!(tasks, [["steps-easy"], ["steps-medium"], ["steps-hard"]]);
    let untils: Vec<Option<f64>> = courses.stages.iter().map(|s| s.until).collect();
    assert_eq!(untils, [Some(4.0), Some(4.0), None]);
    let again = parse_optimizer_file("c.cmaes.xml", &write_optimizer_file(&file)).unwrap();
    assert_eq!(again.courses, file.courses);

    let line_of = |needle: &str| text.lines().position(|l| l.contains(needle)).unwrap() as u32 + 1;
    let bad = |from: &str, to: &str| {
        assert!(text.contains(from), "{from}");
        parse_optimizer_file("c.cmaes.xml", &text.replacen(from, to, 1)).unwrap_err()
    };
    let e = bad(
        "<stage tasks=\"steps-medium\" until=\"4\"/>",
        "<stage tasks=\"steps-medium\"/>",
    );
    assert_eq!(
        (e.pos.line, e.kind),
        (line_of("tasks=\"steps-medium\""), ErrorKind::Missing),
        "{e}"
    );
    assert!(e.to_string().contains("stage 2 of 3 needs `until`"), "{e}");
    let e = bad(
        "<stage tasks=\"steps-hard\"/>",
        "<stage tasks=\"steps-hard\" until=\"4\"/>",
    );
    assert_eq!(e.pos.line, line_of("tasks=\"steps-hard\""), "{e}");
    assert!(
        e.to_string().contains("the last stage has no `until`"),
        "{e}"
    );
    let e = bad("until=\"4\"", "until=\"NaN\"");
    assert!(
        e.to_string().contains("until: expected a finite number"),
        "{e}"
    );
    let e = bad("episodes=\"2\">", "episodes=\"2\" tasks=\"pegs-easy\">");
    assert!(e.to_string().contains("not both"), "{e}");
    let e = bad("<stage tasks=\"steps-easy\"", "<stage tasks=\" \"");
    assert!(e.to_string().contains("names no task"), "{e}");
    let e = bad(
        "<stage tasks=\"steps-easy\"",
        "<stage tasks=\"steps-easy\" level=\"2\"",
    );
    assert_eq!(e.kind, ErrorKind::UnknownElement, "{e}");
}

#[test]
fn a_stage_naming_an_unknown_or_held_out_task_is_a_located_error_on_loading() {
    let dir = common::scratch("curriculum-names");
    let sim = curriculum(&dir, &["4", "4"]);
    let opt = dir.join("c.cmaes.xml");
    let text = std::fs::read_to_string(&opt).unwrap();
    for (to, says) in [
        ("steps-lava", "has no task \"steps-lava\""),
        ("rubble-hard", "\"rubble-hard\" is held out"),
    ] {
        std::fs::write(&opt, text.replace("\"steps-hard\"", &format!("\"{to}\""))).unwrap();
        let e = proleg::control::load_simulation(&sim).unwrap_err();
        let line = text
            .lines()
            .position(|l| l.contains("steps-hard\"/>"))
            .unwrap()
            + 1;
        assert!(e.to_string().contains(says), "{e}");
        assert!(
            e.to_string().contains(&format!("c.cmaes.xml:{line}:")),
            "names the third stage's line: {e}"
        );
    }
}
