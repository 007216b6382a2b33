//! Fuzzing the configuration readers: arbitrary bytes, and valid files mutated at random,
//! never panic or hang; every error they produce names a line inside the file.
//!
//! The number of inputs per property is proptest's `PROPTEST_CASES` (256 by default here);
//! run longer with e.g. `PROPTEST_CASES=20000 cargo test --release --test fuzz_config`.

mod common;

use std::path::{Path, PathBuf};

use proleg::config::{ConfigError, MemSource, load_simulation_with};
use proleg::control::ModuleRegistry;
use proptest::prelude::*;

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

/// Every parser, on one text.
fn parse_all(text: &str) {
    use proleg::config::*;
    let _ = simulation::parse_simulation_file("f", text);
    let _ = robot::parse_robot_file("f", text);
    let _ = kinbody::parse_kinbody_file("f", text);
    let _ = sensor::parse_sensor_file("f", text);
    let _ = actuation::parse_actuation_file("f", text);
    let _ = environment::parse_environment_file("f", text);
    let _ = optimizer::parse_optimizer_file("f", text);
    let _ = mesh::parse_obj(Path::new("f"), text);
}

/// The files of one configs/ simulation, relative to the repository root.
fn simulation_files(sim: &str) -> Vec<(PathBuf, String)> {
    let root = common::root();
    let loaded = proleg::control::load_simulation(root.join("configs").join(sim)).unwrap();
    let mut files = vec![loaded.actuation.file.clone()];
    files.extend(loaded.robot.files.iter().cloned());
    files.extend(loaded.environment.files.iter().cloned());
    files.extend(loaded.optimizer.iter().map(|o| o.file.clone()));
    files.sort();
    files.dedup();
    files.insert(0, loaded.file.clone());
    files
        .into_iter()
        .map(|f| {
            let rel = f.strip_prefix(&root).unwrap_or(&f).to_path_buf();
            let text = std::fs::read_to_string(&f).unwrap();
            (rel, text)
        })
        .collect()
}

/// One edit of a text: where (a fraction of its length), what, and with which payload.
#[derive(Debug, Clone)]
enum Edit {
    Insert(f64, String),
    Delete(f64, usize),
    Duplicate(f64, usize),
    ReplaceNumber(f64, &'static str),
}

fn edit_strategy() -> impl Strategy<Value = Edit> {
    let payload = prop_oneof![
        Just("<".to_string()),
        Just(">".to_string()),
        Just("</".to_string()),
        Just("\"".to_string()),
        Just("&".to_string()),
        Just("&#0;".to_string()),
        Just("<!--".to_string()),
        Just("<![CDATA[".to_string()),
        Just("<Body name=\"x\">".to_string()),
        Just("<KinBody file=\"robots/snake5p.robot.xml\"/>".to_string()),
        Just("\u{0}".to_string()),
        "[a-zA-Z0-9 <>/=\"'.-]{0,12}",
    ];
    let numbers = prop_oneof![
        Just("NaN"),
        Just("-1"),
        Just("0"),
        Just("1e309"),
        Just("-inf"),
        Just("99999999999999999999"),
        Just(""),
        Just("0 0"),
        Just("1 2 3 4 5"),
        Just("x"),
        Just("-0"),
        Just("1e-320"),
    ];
    prop_oneof![
        (0.0..1.0f64, payload).prop_map(|(p, s)| Edit::Insert(p, s)),
        (0.0..1.0f64, 1..40usize).prop_map(|(p, n)| Edit::Delete(p, n)),
        (0.0..1.0f64, 1..200usize).prop_map(|(p, n)| Edit::Duplicate(p, n)),
        (0.0..1.0f64, numbers).prop_map(|(p, s)| Edit::ReplaceNumber(p, s)),
    ]
}

fn boundary(text: &str, frac: f64) -> usize {
    let mut i = ((text.len() as f64) * frac) as usize;
    while i > 0 && !text.is_char_boundary(i) {
        i -= 1;
    }
    i.min(text.len())
}

fn apply(text: &str, edit: &Edit) -> String {
    let mut t = text.to_string();
    match edit {
        Edit::Insert(p, s) => t.insert_str(boundary(&t, *p), s),
        Edit::Delete(p, n) => {
            let a = boundary(&t, *p);
            let b = boundary(&t, ((a + n) as f64 / t.len().max(1) as f64).min(1.0));
            t.replace_range(a..b.max(a), "");
        }
        Edit::Duplicate(p, n) => {
            let a = boundary(&t, *p);
            let b = boundary(&t, ((a + n) as f64 / t.len().max(1) as f64).min(1.0)).max(a);
            let piece = t[a..b].to_string();
            t.insert_str(b, &piece);
        }
        Edit::ReplaceNumber(p, s) => {
            // Replace the first number at or after the position.
            let a = boundary(&t, *p);
            if let Some(off) = t[a..].find(|c: char| c.is_ascii_digit()) {
                let start = a + off;
                let end = t[start..]
                    .find(|c: char| !(c.is_ascii_digit() || c == '.'))
                    .map_or(t.len(), |e| start + e);
                t.replace_range(start..end, s);
            }
        }
    }
    t
}

/// An error must point inside the file it names (or at 0:0 for whole-file errors).
fn check_error(e: &ConfigError, files: &[(PathBuf, String)]) {
    let shown = e.to_string();
    assert!(!shown.is_empty());
    if let Some((_, text)) = files.iter().find(|(p, _)| e.file.ends_with(p)) {
        let lines = text.lines().count() as u32 + 1;
        assert!(
            e.pos.line <= lines,
            "line {} beyond the file's {lines} lines: {shown}",
            e.pos.line
        );
    }
}

/// Loads the simulation with one file edited; returns the error kind, if any.
fn load_mutated(
    files: &[(PathBuf, String)],
    which: usize,
    edits: &[Edit],
) -> Option<proleg::config::ErrorKind> {
    let mut src = MemSource::new();
    let mut mutated = files.to_vec();
    let k = which % mutated.len();
    for e in edits {
        mutated[k].1 = apply(&mutated[k].1, e);
    }
    for (p, t) in &mutated {
        src.insert(p, t.clone());
    }
    parse_all(&mutated[k].1);
    let top = &files[0].0;
    match load_simulation_with(&src, top, &ModuleRegistry::default()) {
        Ok(sim) => {
            let _ = proleg::config::summary::summary(&sim);
            None
        }
        Err(e) => {
            check_error(&e, &mutated);
            Some(e.kind)
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        parse_all(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn xml_like_text_never_panics(text in "(<[a-zA-Z]{1,8}( [a-z]{1,6}=\"[0-9a-z. -]{0,8}\")?/?>|</[a-zA-Z]{1,8}>|[0-9. -]{0,10}|<!--[a-z ]{0,5}-->){0,30}") {
        parse_all(&text);
    }

    #[test]
    fn mutated_experiment_2_never_panics(which in 0usize..64, edits in proptest::collection::vec(edit_strategy(), 1..6)) {
        thread_local!(static FILES: Vec<(PathBuf, String)> = simulation_files("experiment2_gd.simulation.xml"));
        FILES.with(|files| { load_mutated(files, which, &edits); });
    }

    #[test]
    fn mutated_experiment_1_never_panics(which in 0usize..64, edits in proptest::collection::vec(edit_strategy(), 1..6)) {
        thread_local!(static FILES: Vec<(PathBuf, String)> = simulation_files("experiment1_ga.simulation.xml"));
        FILES.with(|files| { load_mutated(files, which, &edits); });
    }
}

#[test]
fn unmutated_files_load_from_memory() {
    for sim in [
        "experiment1_ga.simulation.xml",
        "experiment2_gd.simulation.xml",
    ] {
        let files = simulation_files(sim);
        assert!(files[0].0.ends_with(sim), "{:?}", files[0].0);
        assert_eq!(load_mutated(&files, 0, &[]), None);
    }
}

/// The mutations get past the XML syntax into the semantic checks: a fixed, seeded batch
/// reaches many error classes, and some mutated files still load.
#[test]
fn mutations_reach_semantic_checks() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let files = simulation_files("experiment2_gd.simulation.xml");
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    );
    let strategy = (0usize..64, proptest::collection::vec(edit_strategy(), 1..3));
    let mut kinds = std::collections::BTreeMap::new();
    let mut loaded = 0;
    for _ in 0..3000 {
        let (which, edits) = strategy.new_tree(&mut runner).unwrap().current();
        match load_mutated(&files, which, &edits) {
            Some(kind) => *kinds.entry(format!("{kind:?}")).or_insert(0) += 1,
            None => loaded += 1,
        }
    }
    eprintln!("3000 mutated sets: {loaded} loaded, errors by kind: {kinds:?}");
    assert!(loaded > 0, "no mutated set loaded");
    assert!(kinds.len() >= 6, "only {kinds:?}");
}
