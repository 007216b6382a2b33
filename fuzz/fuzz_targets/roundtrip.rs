//! The `roundtrip` target (`proleg_fuzz::targets::roundtrip`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::roundtrip::run(data));
