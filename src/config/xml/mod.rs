//! XML plumbing shared by every format: a positioned element tree, typed reading with
//! located errors, and an indenting writer.

pub mod dom;
pub mod read;
pub mod write;
