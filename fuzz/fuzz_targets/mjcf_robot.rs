//! The `mjcf_robot` target (`proleg_fuzz::targets::mjcf_robot`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::mjcf_robot::run(data));
