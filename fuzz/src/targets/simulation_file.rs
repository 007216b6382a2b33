//! A simulation file from raw bytes, with the demo's robot, control and floor beside it: loaded through the resolver (its includes and paths fuzzed too) and, when it loads, run.

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    if let Some(text) = crate::text(data) {
        crate::load_and_run("demo.simulation.xml", "demo.simulation.xml", text);
    }
}
