//! A simulation file from raw bytes, with the demo's robot, control and floor beside it: loaded through the resolver (its includes and paths fuzzed too) and, when it loads, run.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(text) = proleg_fuzz::text(data) {
        proleg_fuzz::load_and_run("demo.simulation.xml", "demo.simulation.xml", text);
    }
});
