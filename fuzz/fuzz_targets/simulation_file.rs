//! The `simulation_file` target (`proleg_fuzz::targets::simulation_file`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::simulation_file::run(data));
