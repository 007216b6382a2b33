//! The `data_file` target (`proleg_fuzz::targets::data_file`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::data_file::run(data));
