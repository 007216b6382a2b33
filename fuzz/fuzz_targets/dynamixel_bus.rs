//! The `dynamixel_bus` target (`proleg_fuzz::targets::dynamixel_bus`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::dynamixel_bus::run(data));
