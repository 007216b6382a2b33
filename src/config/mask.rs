//! Joint masks: strings of `0` and `1`, one character per robot joint (thesis 5.5.1).
//! `1` at position i means joint i is driven (or optimized) by the owner of the mask.

use std::fmt;

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::xml::read::Reader;

/// Which joints of the robot a module drives, in the robot's joint order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JointMask(pub Vec<bool>);

impl JointMask {
    /// Parses `"01010"`; `what` names the attribute in errors.
    pub fn parse(r: &Reader, s: &str, pos: Pos, what: &str) -> ConfigResult<JointMask> {
        let s = s.trim();
        if s.is_empty() {
            return Err(r.err(
                pos,
                ErrorKind::InvalidValue,
                format!("{what} is empty; expected a string of 0 and 1"),
            ));
        }
        s.chars()
            .enumerate()
            .map(|(i, c)| match c {
                '1' => Ok(true),
                '0' => Ok(false),
                other => Err(r.err(
                    pos,
                    ErrorKind::InvalidValue,
                    format!(
                        "{what}: character {} is '{other}'; a joint mask holds only 0 and 1",
                        i + 1
                    ),
                )),
            })
            .collect::<ConfigResult<_>>()
            .map(JointMask)
    }

    /// A mask of `n` joints, all set.
    pub fn all(n: usize) -> Self {
        JointMask(vec![true; n])
    }

    /// Joints the mask covers.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether it covers no joint.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Number of joints set.
    pub fn count(&self) -> usize {
        self.0.iter().filter(|b| **b).count()
    }

    /// Indices of the joints set.
    pub fn indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.0
            .iter()
            .enumerate()
            .filter(|(_, b)| **b)
            .map(|(i, _)| i)
    }

    /// Fails unless the mask has one character per robot joint.
    pub fn check_len(&self, r: &Reader, pos: Pos, joints: usize, what: &str) -> ConfigResult<()> {
        if self.len() != joints {
            return Err(r.err(
                pos,
                ErrorKind::MaskLength,
                format!(
                    "{what} \"{self}\" has {} characters but the robot has {joints} joints; write one 0/1 per joint",
                    self.len()
                ),
            ));
        }
        Ok(())
    }
}

impl fmt::Display for JointMask {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for b in &self.0 {
            f.write_str(if *b { "1" } else { "0" })?;
        }
        Ok(())
    }
}
