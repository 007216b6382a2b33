//! An environment file from raw bytes under the demo snake: loaded and, when it loads, run.

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    if let Some(text) = crate::text(data) {
        crate::load_and_run("demo.simulation.xml", "environments/flat.env.xml", text);
    }
}
