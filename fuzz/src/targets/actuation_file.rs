//! An actuation file from raw bytes on the demo snake: loaded (module names, masks, parameters, weights files) and, when it loads, run.

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    if let Some(text) = crate::text(data) {
        crate::load_and_run(
            "demo.simulation.xml",
            "actuation/snake5p_sine40.actuation.xml",
            text,
        );
    }
}
