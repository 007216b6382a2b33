//! The `suite_file` target (`proleg_fuzz::targets::suite_file`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::suite_file::run(data));
