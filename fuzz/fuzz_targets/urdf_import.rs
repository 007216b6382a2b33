//! The `urdf_import` target (`proleg_fuzz::targets::urdf_import`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::urdf_import::run(data));
