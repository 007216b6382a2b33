//! A sensor file from raw bytes, the touch snake's pads: loaded and, when it loads, run.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(text) = proleg_fuzz::text(data) {
        proleg_fuzz::load_and_run(proleg_fuzz::TOUCH, "sensors/tactile.sensor.xml", text);
    }
});
