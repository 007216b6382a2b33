//! The `environment_file` target (`proleg_fuzz::targets::environment_file`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::environment_file::run(data));
