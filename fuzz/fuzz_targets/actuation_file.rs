//! An actuation file from raw bytes on the demo snake: loaded (module names, masks, parameters, weights files) and, when it loads, run.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(text) = proleg_fuzz::text(data) {
        proleg_fuzz::load_and_run(
            "demo.simulation.xml",
            "actuation/snake5p_sine40.actuation.xml",
            text,
        );
    }
});
