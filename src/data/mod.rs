//! Recorded data (thesis 4.3.2, 4.5.6, 5.5.2, listing B.8), free of Bevy: what a data
//! handler records ([`HandlerSpec`]), the bounded ring buffers live views read
//! ([`RingBuffer`]), the XML data file written round by round on a background thread
//! ([`store`]), read back as a stream ([`read`]) and exported as TSV/CSV ([`export`]).
//! - [`handler`]: a data handler's shape (its series and units)
//! - [`ring`]: the ring buffer of a handler's latest frames
//! - [`write`], [`store`]: writing the data file (the writer thread)
//! - [`read`]: reading it back as a stream; [`export`]: TSV / CSV; [`plot`]: `proleg data plot`

pub mod export;
pub mod handler;
pub mod plot;
pub mod read;
pub mod ring;
pub mod store;
pub mod write;

pub use handler::{FrameMeta, HandlerSpec};
pub use ring::RingBuffer;
