//! A recorded data file (thesis B.8) from raw bytes: read through the header and every
//! round (cut files, corrupted values, counts that lie), each frame visited.

use proleg::data::read::{DataEvent, read_stream};

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let mut values = 0.0_f64;
    let read = read_stream(data, std::path::Path::new("fuzz.data.xml"), |event| {
        if let DataEvent::Frame(frame) = event {
            values += frame.values.iter().sum::<f64>();
        }
    });
    // Read or refused with its line; never a panic.
    std::hint::black_box((read.is_ok(), values));
}
