//! A `Policy` weights file (safetensors) from raw bytes: read (header, shapes, element
//! types, sizes that lie, NaN), and when it is accepted, one forward pass.

use proleg::control::policy::PolicyNet;

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let Ok(mut net) = PolicyNet::from_bytes(data, std::path::Path::new("fuzz.safetensors")) else {
        return;
    };
    let input = vec![0.5; net.inputs()];
    let mut out = vec![0.0; net.outputs()];
    net.forward(&input, &mut out);
}
