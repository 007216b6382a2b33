//! Faults of the line between the emulated servos and the host (a loose cable, a noisy
//! adapter), applied to the bus's answers in turn: an answer dropped, cut short, with a
//! byte changed, sent twice, split across two writes, or after noise. The tests and the
//! `dynamixel_bus` fuzz target set them ([`super::EmulatedBus::set_faults`]).

use std::collections::VecDeque;
use std::io::Write;
use std::time::Duration;

/// What happens to one answer on its way to the host.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LineFault {
    /// It arrives as sent.
    Pass,
    /// It never arrives.
    Drop,
    /// Only its first bytes arrive.
    Truncate(usize),
    /// Byte `at` (modulo its length) arrives XOR `xor`.
    Corrupt {
        /// Which byte.
        at: usize,
        /// The bits flipped.
        xor: u8,
    },
    /// It arrives twice.
    Repeat,
    /// Its first bytes, a millisecond's pause, then the rest.
    Split(usize),
    /// These bytes arrive before it.
    Noise(Vec<u8>),
}

/// The pause inside a split answer: long enough for the host to read the first part alone.
const SPLIT_PAUSE: Duration = Duration::from_millis(1);

impl LineFault {
    /// Faults from bytes, three each (kind, two parameters), as the fuzz target draws them.
    pub fn from_bytes(bytes: &[u8]) -> VecDeque<LineFault> {
        bytes
            .chunks_exact(3)
            .map(|c| {
                let (a, b) = (usize::from(c[1]), c[2]);
                match c[0] % 7 {
                    0 => LineFault::Pass,
                    1 => LineFault::Drop,
                    2 => LineFault::Truncate(a),
                    3 => LineFault::Corrupt { at: a, xor: b | 1 },
                    4 => LineFault::Repeat,
                    5 => LineFault::Split(a),
                    _ => LineFault::Noise(vec![b; a % 16 + 1]),
                }
            })
            .collect()
    }

    /// Writes `answer` to `line` as this fault has it.
    pub fn send(&self, answer: &[u8], line: &mut impl Write) -> std::io::Result<()> {
        match self {
            LineFault::Pass => line.write_all(answer),
            LineFault::Drop => Ok(()),
            LineFault::Truncate(n) => line.write_all(&answer[..(*n).min(answer.len())]),
            LineFault::Corrupt { at, xor } => {
                let mut changed = answer.to_vec();
                if !changed.is_empty() {
                    let i = at % changed.len();
                    changed[i] ^= xor;
                }
                line.write_all(&changed)
            }
            LineFault::Repeat => {
                line.write_all(answer)?;
                line.write_all(answer)
            }
            LineFault::Split(n) => {
                let (first, rest) = answer.split_at((*n).min(answer.len()));
                line.write_all(first)?;
                std::thread::sleep(SPLIT_PAUSE);
                line.write_all(rest)
            }
            LineFault::Noise(noise) => {
                line.write_all(noise)?;
                line.write_all(answer)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_fault_changes_the_bytes_as_it_says() {
        let answer = [1, 2, 3, 4];
        let sent = |f: LineFault| {
            let mut out = Vec::new();
            f.send(&answer, &mut out).unwrap();
            out
        };
        assert_eq!(sent(LineFault::Pass), answer);
        assert!(sent(LineFault::Drop).is_empty());
        assert_eq!(sent(LineFault::Truncate(2)), [1, 2]);
        assert_eq!(sent(LineFault::Corrupt { at: 5, xor: 8 }), [1, 10, 3, 4]);
        assert_eq!(sent(LineFault::Repeat), [1, 2, 3, 4, 1, 2, 3, 4]);
        assert_eq!(sent(LineFault::Split(9)), answer);
        assert_eq!(sent(LineFault::Noise(vec![0xFF])), [0xFF, 1, 2, 3, 4]);
        let drawn = LineFault::from_bytes(&[2, 7, 0, 3, 0, 0, 6, 1, 9, 99]);
        assert_eq!(
            drawn,
            [
                LineFault::Truncate(7),
                LineFault::Corrupt { at: 0, xor: 1 },
                LineFault::Noise(vec![9, 9])
            ]
        );
    }
}
