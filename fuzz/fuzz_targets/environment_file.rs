//! An environment file from raw bytes under the demo snake: loaded and, when it loads, run.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(text) = proleg_fuzz::text(data) {
        proleg_fuzz::load_and_run("demo.simulation.xml", "environments/flat.env.xml", text);
    }
});
