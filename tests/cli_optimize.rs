//! `proleg optimize` and `proleg results` from the command line: a run killed in the middle
//! and resumed from its store ends with the same best candidate as an uninterrupted run.

mod common;

use common::proleg;

/// The lines that state the result: best score and best values.
fn result_lines(out: &str) -> Vec<String> {
    out.lines()
        .skip_while(|l| !l.starts_with("best score"))
        .take_while(|l| !l.starts_with("best actuation"))
        .map(str::to_string)
        .collect()
}

/// The first number on the line of `out` that starts with `prefix`.
fn number_after(out: &str, prefix: &str) -> f64 {
    out.lines()
        .find_map(|l| l.strip_prefix(prefix))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no {prefix:?} in {out}"))
}

#[test]
fn a_killed_run_resumes_to_the_same_best() {
    let dir = common::scratch("cli_optimize");
    let whole = dir.join("whole.sqlite");
    let killed = dir.join("killed.sqlite");
    let common_args = [
        "optimize",
        "configs/experiment1_ga.simulation.xml",
        "--max-evals",
        "75",
        "--duration",
        "1",
        "--quiet",
        "--store",
    ];
    let mut args = common_args.to_vec();
    args.push(whole.to_str().unwrap());
    let (ok, full, err) = proleg(&args);
    assert!(ok, "{err}");
    assert!(
        full.contains("75 evaluations in 3 rounds (75 simulated"),
        "{full}"
    );
    let expected = result_lines(&full);
    assert!(expected.len() == 6, "{full}");

    // Killed in the middle of the second generation (after a batch is stored).
    let mut args = common_args.to_vec();
    args.extend([killed.to_str().unwrap(), "--crash-after", "40"]);
    let (ok, _, _) = proleg(&args);
    assert!(!ok, "the crash aid aborts the process");
    let (ok, listing, err) = proleg(&["results", killed.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(listing.contains("(unfinished"), "{listing}");

    let mut args = common_args.to_vec();
    args.extend([killed.to_str().unwrap(), "--resume"]);
    args.retain(|a| *a != "--quiet");
    let (ok, resumed, err) = proleg(&args);
    assert!(ok, "{err}");
    let stored: u64 = err
        .lines()
        .filter(|l| l.contains("evaluations stored"))
        .find_map(|l| {
            l.split("evaluations stored")
                .next()?
                .rsplit(' ')
                .nth(1)?
                .parse()
                .ok()
        })
        .unwrap_or_else(|| panic!("no resume line in {err}"));
    assert!((40..75).contains(&stored), "{err}");
    assert_eq!(result_lines(&resumed), expected);
    assert!(
        resumed.contains(&format!("({} simulated", 75 - stored)),
        "only the missing evaluations run: {resumed}"
    );

    // The store lists the finished run, draws its curve and exports every evaluation.
    let png = dir.join("curve.png");
    let tsv = dir.join("evals.tsv");
    let (ok, listing, err) = proleg(&[
        "results",
        killed.to_str().unwrap(),
        "--curve",
        png.to_str().unwrap(),
        "--export",
        tsv.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        listing.contains("75 evaluations") && !listing.contains("unfinished"),
        "{listing}"
    );
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    assert_eq!(std::fs::read_to_string(&tsv).unwrap().lines().count(), 76);
}

#[test]
fn a_killed_cma_es_run_resumes_to_the_same_best_and_improves_on_its_start() {
    let dir = common::scratch("cli_optimize_cma");
    let args = |store: &str| {
        vec![
            "optimize".to_string(),
            "configs/experiment1_cmaes.simulation.xml".into(),
            "--max-evals".into(),
            "61".into(),
            "--duration".into(),
            "3".into(),
            "--quiet".into(),
            "--store".into(),
            store.into(),
        ]
    };
    let run = |extra: &[&str], store: &str| {
        let mut a = args(store);
        a.extend(extra.iter().map(|s| s.to_string()));
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        proleg(&a)
    };
    let whole = dir.join("whole.sqlite");
    let (ok, full, err) = run(&[], whole.to_str().unwrap());
    assert!(ok, "{err}");
    // The start alone, then 6 generations of 10.
    assert!(full.contains("61 evaluations in 7 rounds"), "{full}");
    let expected = result_lines(&full);
    let start = number_after(&full, "start score ");
    let best: f64 = expected[0]
        .split_whitespace()
        .nth(2)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no best score in {full}"));
    assert!(
        best > start,
        "CMA-ES improved on its start: {start} -> {best}"
    );

    let killed = dir.join("killed.sqlite");
    let (ok, _, _) = run(&["--crash-after", "25"], killed.to_str().unwrap());
    assert!(!ok, "the crash aid aborts the process");
    let (ok, resumed, err) = run(&["--resume"], killed.to_str().unwrap());
    assert!(ok, "{err}");
    assert_eq!(result_lines(&resumed), expected);

    // Two runs of one optimizer on one configuration draw as a band.
    let png = dir.join("band.png");
    let (ok, _, err) = proleg(&[
        "results",
        whole.to_str().unwrap(),
        killed.to_str().unwrap(),
        "--curve",
        png.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
}

#[test]
fn the_demo_s_gait_from_scratch_improves_on_its_start_by_more_than_a_fifth() {
    let dir = common::scratch("cli_optimize_scratch");
    let store = dir.join("s.sqlite");
    let (ok, out, err) = proleg(&[
        "optimize",
        "configs/gait_from_scratch_cmaes.simulation.xml",
        "--max-evals",
        "31",
        "--duration",
        "5",
        "--quiet",
        "--store",
        store.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let gain: f64 = out
        .lines()
        .find_map(|l| l.split('(').nth(1)?.strip_suffix("% over the start)"))
        .and_then(|g| g.trim_start_matches('+').parse().ok())
        .unwrap_or_else(|| panic!("no gain in {out}"));
    assert!(gain >= 20.0, "{out}");
}

#[test]
fn optimize_refuses_a_single_run_configuration() {
    let dir = common::scratch("cli_optimize_refuse");
    let store = dir.join("s.sqlite");
    let (ok, _, err) = proleg(&[
        "optimize",
        "configs/demo.simulation.xml",
        "--store",
        store.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("no optimizer file"), "{err}");
    let (ok, _, err) = proleg(&["results", "missing.sqlite"]);
    assert!(!ok);
    assert!(err.contains("no such store"), "{err}");
}

#[test]
fn a_new_store_in_a_folder_not_made_yet_gets_its_folder() {
    let dir = common::scratch("cli_optimize_new_folder");
    let store = dir.join("out").join("runs.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/experiment1_ga.simulation.xml",
        ("30", "0.5"),
        &store,
        &[],
    );
    assert!(ok, "{err}");
    let (ok, out, err) = proleg(&["results", store.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(out.contains("30 evaluations"), "{out}");
}

#[test]
fn a_killed_map_elites_run_resumes_to_the_same_archive_and_maps_it() {
    let dir = common::scratch("cli_optimize_map");
    let run = |extra: &[&str], store: &std::path::Path| {
        common::optimize(
            "configs/experiment1_mapelites.simulation.xml",
            ("60", "2"),
            store,
            extra,
        )
    };
    let whole = dir.join("whole.sqlite");
    let (ok, full, err) = run(&[], &whole);
    assert!(ok, "{err}");
    // 20 random candidates, then 4 rounds of 10 mutants.
    assert!(full.contains("60 evaluations in 5 rounds"), "{full}");
    let archive = common::archive_line(&whole);
    // 60 candidates over 8 x 8 cells: several cells, not all.
    let filled: usize = archive
        .split(" archive: ")
        .nth(1)
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no cell count in {archive}"));
    assert!((10..64).contains(&filled), "{archive}");

    let killed = dir.join("killed.sqlite");
    let (ok, _, _) = run(&["--crash-after", "35"], &killed);
    assert!(!ok, "the crash aid aborts the process");
    let (ok, resumed, err) = run(&["--resume"], &killed);
    assert!(ok, "{err}");
    assert_eq!(result_lines(&resumed), result_lines(&full));
    assert_eq!(common::archive_line(&killed), archive);

    let png = dir.join("map.png");
    let (ok, out, err) = proleg(&[
        "results",
        whole.to_str().unwrap(),
        "--map",
        png.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("archive map written to"), "{out}");
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    // A run of another optimizer has no archive to map.
    let cma = dir.join("cma.sqlite");
    let (ok, _, err) = proleg(&[
        "optimize",
        "configs/experiment1_cmaes.simulation.xml",
        "--max-evals",
        "3",
        "--duration",
        "1",
        "--quiet",
        "--store",
        cma.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let (ok, _, err) = proleg(&[
        "results",
        cma.to_str().unwrap(),
        "--map",
        png.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("--map"), "{err}");
}

#[test]
fn a_killed_es_run_resumes_to_the_same_weights_and_improves_on_its_start() {
    // OpenAI-ES over the 197 weights of the demo's Policy module: the start, then 3
    // generations of 16; killed after 20 evaluations and resumed, the same best weights
    // file as the uninterrupted run, and better than the sine alone.
    let dir = common::scratch("cli_optimize_es");
    let run = |extra: &[&str], name: &str| {
        let store = dir.join(format!("{name}.sqlite")).display().to_string();
        let out = dir
            .join(format!("{name}.actuation.xml"))
            .display()
            .to_string();
        let mut a = vec![
            "optimize",
            "configs/demo_policy_es.simulation.xml",
            "--max-evals",
            "49",
            "--duration",
            "2",
            "--quiet",
            "--store",
            &store,
            "--out",
            &out,
        ];
        a.extend_from_slice(extra);
        proleg(&a)
    };
    let (ok, full, err) = run(&[], "whole");
    assert!(ok, "{err}");
    assert!(full.contains("49 evaluations in 4 rounds"), "{full}");
    let start = number_after(&full, "start score ");
    let best = number_after(&full, "best score ");
    assert!(
        best > start,
        "the strategy improved on its start: {start} -> {best}"
    );
    let weights = |name: &str| {
        std::fs::read(dir.join(format!("{name}.Policy.safetensors"))).expect("best weights")
    };
    let (ok, _, _) = run(&["--crash-after", "20"], "killed");
    assert!(!ok, "the crash aid aborts the process");
    let (ok, resumed, err) = run(&["--resume"], "killed");
    assert!(ok, "{err}");
    assert_eq!(result_lines(&resumed), result_lines(&full));
    assert_eq!(weights("killed"), weights("whole"));
    // The best actuation file names its weights file, and a run of it scores what the
    // optimizer stored (the weights are written as scored, F64).
    let (ok, shown, err) = proleg(&[
        "policy",
        "show",
        dir.join("whole.Policy.safetensors").to_str().unwrap(),
    ]);
    assert!(
        ok && shown.contains("18 -> 8 -> 5 (tanh), 197 weights"),
        "{shown}{err}"
    );
    let configs = common::root().join("configs");
    let sim = dir.join("best.simulation.xml");
    let text = std::fs::read_to_string(configs.join("demo.simulation.xml"))
        .unwrap()
        .replace("robots/", &format!("{}/robots/", configs.display()))
        .replace(
            "environments/",
            &format!("{}/environments/", configs.display()),
        )
        .replace(
            "actuation/snake5p_sine40.actuation.xml",
            dir.join("whole.actuation.xml").to_str().unwrap(),
        );
    std::fs::write(&sim, text).unwrap();
    let (ok, ran, err) = proleg(&["run", sim.to_str().unwrap(), "--duration", "2"]);
    assert!(ok, "{err}");
    let displacement = number_after(&ran, "displacement    ");
    assert!(
        (displacement - best).abs() < 5e-5,
        "{displacement} against {best}"
    );
}
