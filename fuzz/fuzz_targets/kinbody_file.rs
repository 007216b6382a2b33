//! A part (kinbody) file from raw bytes, the demo robot's middle module: loaded and, when it loads, run.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(text) = proleg_fuzz::text(data) {
        proleg_fuzz::load_and_run("demo.simulation.xml", "parts/PP.kinbody.xml", text);
    }
});
