//! The `dashboard_request` target (`proleg_fuzz::targets::dashboard_request`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::dashboard_request::run(data));
