//! The `obj_mesh` target (`proleg_fuzz::targets::obj_mesh`) under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| proleg_fuzz::targets::obj_mesh::run(data));
