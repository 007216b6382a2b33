//! XML plumbing shared by every format: a positioned element tree, typed reading with
//! located errors, and an indenting writer.
//! - [`dom`]: the element tree with source positions (read with quick-xml)
//! - [`read`]: typed reading of text and attributes, with positioned errors
//! - [`write`]: the indenting writer

pub mod dom;
pub mod read;
pub mod write;
