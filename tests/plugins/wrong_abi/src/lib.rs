//! A library that says it speaks plugin ABI version 999.

#[unsafe(no_mangle)]
pub extern "C" fn proleg_plugin_abi_version() -> u32 {
    999
}

#[unsafe(no_mangle)]
pub extern "C" fn proleg_plugin_table() -> *const u8 {
    std::ptr::null()
}
