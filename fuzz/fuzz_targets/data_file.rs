//! A recorded data file (thesis B.8) from raw bytes: read through the header and every
//! round (cut files, corrupted values, counts that lie), each frame visited.
#![no_main]

use libfuzzer_sys::fuzz_target;
use proleg::data::read::{DataEvent, read_stream};

fuzz_target!(|data: &[u8]| {
    let mut values = 0.0_f64;
    let read = read_stream(data, std::path::Path::new("fuzz.data.xml"), |event| {
        if let DataEvent::Frame(frame) = event {
            values += frame.values.iter().sum::<f64>();
        }
    });
    // Read or refused with its line; never a panic.
    std::hint::black_box((read.is_ok(), values));
});
