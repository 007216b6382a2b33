//! A sensor file from raw bytes, the touch snake's pads: loaded and, when it loads, run.

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    if let Some(text) = crate::text(data) {
        crate::load_and_run(crate::TOUCH, "sensors/tactile.sensor.xml", text);
    }
}
