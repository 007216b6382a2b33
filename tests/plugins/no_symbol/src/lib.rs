//! A shared library that is not a proleg plugin.

#[unsafe(no_mangle)]
pub extern "C" fn something_else() -> u32 {
    7
}
