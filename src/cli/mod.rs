//! The command line's logic, as a library: each subcommand of `proleg` is a function here
//! that takes its parsed options and returns a typed value (a report that prints itself, or
//! the text to print) or the error message. `main.rs` only parses arguments and prints, so
//! tests and other front ends (the GUI) call the same functions.
//!
//! | command | module |
//! |---|---|
//! | `proleg run` | [`run`] ([`run::RunReport`]) |
//! | `proleg optimize` | [`optimize`] |
//! | `proleg results` | [`results`] |
//! | `proleg data info / export / plot` | [`data`] |
//! | `proleg plugin new / build / list` | [`plugin`] |
//! | `proleg robot`, `proleg robot-emulator` | [`robot`] |

pub mod data;
pub mod optimize;
pub mod plugin;
pub mod results;
pub mod robot;
pub mod run;
