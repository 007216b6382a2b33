//! A remote-control file (gamepad bindings) and a stream of gamepad snapshots, from the
//! fuzzer's bytes (the file's text, a NUL, then snapshots of 17 bytes: element, value and
//! seconds since the last as little-endian f64, NaN and infinities included): the file
//! parsed and its bindings resolved against the demo's control, then each snapshot applied
//! to the kernel (a value a module refuses is an error, never a panic).

use proleg::config::remote::parse_remote_file;
use proleg::control::ControlKernel;
use proleg::remote::device::{RemoteData, gamepad_elements};
use proleg::remote::mapper::RemoteMapper;

/// Snapshot `chunk`: element index, value, seconds since the last.
fn snapshot(chunk: &[u8]) -> (usize, f64, f64) {
    let f = |at: usize| {
        let mut b = [0_u8; 8];
        b.copy_from_slice(&chunk[at..at + 8]);
        f64::from_le_bytes(b)
    };
    (usize::from(chunk[0]), f(1), f(9))
}

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let split = data.iter().position(|b| *b == 0).unwrap_or(data.len());
    let (text, rest) = data.split_at(split);
    let Some(text) = crate::text(text) else {
        return;
    };
    let Ok(file) = parse_remote_file("fuzz.remote.xml", text) else {
        return;
    };
    let Some(demo) = crate::demo() else {
        return;
    };
    let limits = demo.robot.joints.iter().map(|j| j.limits_deg).collect();
    let Ok(mut kernel) = ControlKernel::from_actuation(&demo.actuation, crate::registry(), limits)
    else {
        return;
    };
    let orientations: Vec<_> = demo.robot.joints.iter().map(|j| j.orientation).collect();
    let Ok(mut mapper) = RemoteMapper::new(&file, "fuzz.remote.xml", &kernel, &orientations) else {
        return;
    };
    let elements = gamepad_elements();
    let mut remote = RemoteData::default();
    for chunk in rest.get(1..).unwrap_or(&[]).chunks_exact(17).take(64) {
        let (element, value, dt) = snapshot(chunk);
        remote.set(&elements[element % elements.len()].name, value);
        if mapper.apply(&remote, dt, &mut kernel).is_err() {
            return;
        }
    }
}
