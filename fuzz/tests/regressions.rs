//! Every fixed finding stays fixed: each input under `fuzz/regressions/TARGET/` (named for
//! what it found) is replayed through its target, which panics on a finding. Inputs are
//! added there when a finding is fixed (docs/development.md, "Fuzzing").

use std::path::Path;

use proleg_fuzz::targets::ALL;

#[test]
fn every_fixed_finding_replays_clean() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let mut replayed = 0;
    for entry in std::fs::read_dir(&dir).expect("fuzz/regressions") {
        let target = entry.expect("a folder entry").path();
        let name = target.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let Some((_, run)) = ALL.iter().find(|(n, _)| *n == name) else {
            panic!("{}: no fuzz target of that name", target.display());
        };
        for input in std::fs::read_dir(&target).expect("a target's folder") {
            let input = input.expect("a folder entry").path();
            let bytes = std::fs::read(&input).expect("an input");
            eprintln!("replaying {}", input.display());
            run(&bytes);
            replayed += 1;
        }
    }
    assert!(replayed > 0, "no inputs under {}", dir.display());
}
