//! A `Policy` weights file (safetensors) from raw bytes: read (header, shapes, element
//! types, sizes that lie, NaN), and when it is accepted, one forward pass.
#![no_main]

use libfuzzer_sys::fuzz_target;
use proleg::control::policy::PolicyNet;

fuzz_target!(|data: &[u8]| {
    let Ok(mut net) = PolicyNet::from_bytes(data, std::path::Path::new("fuzz.safetensors")) else {
        return;
    };
    let input = vec![0.5; net.inputs()];
    let mut out = vec![0.0; net.outputs()];
    net.forward(&input, &mut out);
});
