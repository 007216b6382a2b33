//! The `policy_weights` target (`proleg_fuzz::targets::policy_weights`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::policy_weights::run(data));
