//! Dynamixel servos (Protocol 2.0, X series control table): [`table`] holds the register
//! addresses and unit conversions shared by the [`driver`] and the emulator.

pub mod driver;
pub mod table;

pub use driver::DynamixelChain;
