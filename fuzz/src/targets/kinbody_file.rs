//! A part (kinbody) file from raw bytes, the demo robot's middle module: loaded and, when it loads, run.

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    if let Some(text) = crate::text(data) {
        crate::load_and_run("demo.simulation.xml", "parts/PP.kinbody.xml", text);
    }
}
