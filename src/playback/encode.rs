//! How the stream's numbers travel: arrays of little-endian numbers in base64 (a page
//! turns one back into a typed array without parsing a number at a time), and the
//! quantizations that keep a body within a micrometre and a thousandth of a degree.

use base64::Engine;
use base64::engine::general_purpose::STANDARD;

/// Scale of a quaternion component stored as an `i16` (a component is within -1..1).
pub const QUATERNION_SCALE: f64 = 32767.0;

/// Hundredths of a degree: a joint angle stored as an `i16` (within ±327.67°).
pub const ANGLE_SCALE: f64 = 100.0;

/// `values` as base64 of their bytes as `bytes` gives them (little-endian).
fn base64_of<T: Copy, const N: usize>(values: &[T], bytes: fn(T) -> [u8; N]) -> String {
    let mut out = Vec::with_capacity(values.len() * N);
    for v in values {
        out.extend_from_slice(&bytes(*v));
    }
    STANDARD.encode(out)
}

/// `values` as base64 of their little-endian bytes.
pub fn f32s(values: &[f32]) -> String {
    base64_of(values, f32::to_le_bytes)
}

/// `values` as base64 of their little-endian bytes.
pub fn i16s(values: &[i16]) -> String {
    base64_of(values, i16::to_le_bytes)
}

/// `values` as base64 of their little-endian bytes.
pub fn u16s(values: &[u16]) -> String {
    base64_of(values, u16::to_le_bytes)
}

/// `values` as base64 of their little-endian bytes.
pub fn u32s(values: &[u32]) -> String {
    base64_of(values, u32::to_le_bytes)
}

/// `bytes` as base64.
pub fn u8s(bytes: &[u8]) -> String {
    STANDARD.encode(bytes)
}

/// A base64 array of `T`s back (the page's reading, for tests): `None` when it is not
/// base64 or not a whole number of `N`-byte values.
pub fn decode<const N: usize, T>(text: &str, from: fn([u8; N]) -> T) -> Option<Vec<T>> {
    let bytes = STANDARD.decode(text).ok()?;
    if !bytes.len().is_multiple_of(N) {
        return None;
    }
    Some(
        bytes
            .chunks_exact(N)
            .map(|c| {
                let mut a = [0u8; N];
                a.copy_from_slice(c);
                from(a)
            })
            .collect(),
    )
}

/// A unit quaternion (x, y, z, w) as four `i16`s, its sign chosen so that w >= 0 (the
/// same rotation; neighbouring frames then interpolate the short way).
pub fn quaternion(q: [f64; 4]) -> [i16; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let s = if n > 0.0 && n.is_finite() {
        q[3].signum() / n
    } else {
        return [0, 0, 0, QUATERNION_SCALE as i16];
    };
    q.map(|c| (c * s * QUATERNION_SCALE).round().clamp(-32767.0, 32767.0) as i16)
}

/// A joint angle (degrees) in hundredths of a degree, clamped to what an `i16` holds.
pub fn angle(degrees: f64) -> i16 {
    if degrees.is_finite() {
        (degrees * ANGLE_SCALE).round().clamp(-32767.0, 32767.0) as i16
    } else {
        0
    }
}

/// Heights quantized onto `u16` steps from their lowest: (lowest, step, steps). The step
/// is the span over 65,535 (at least a micrometre), so a span up to 65 m keeps every
/// height within half a millimetre.
pub fn heights(values: &[f64]) -> (f64, f64, Vec<u16>) {
    let (lo, hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
    if lo > hi {
        return (0.0, 1e-6, vec![0; values.len()]);
    }
    let step = ((hi - lo) / 65535.0).max(1e-6);
    let steps = values
        .iter()
        .map(|v| {
            if v.is_finite() {
                ((v - lo) / step).round().clamp(0.0, 65535.0) as u16
            } else {
                0
            }
        })
        .collect();
    (lo, step, steps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_read_back_as_written() {
        let v = [1.5f32, -2.25, 1e-7, 3.0e7];
        assert_eq!(decode(&f32s(&v), f32::from_le_bytes), Some(v.to_vec()));
        let q = [-32767i16, 0, 5, 32767];
        assert_eq!(decode(&i16s(&q), i16::from_le_bytes), Some(q.to_vec()));
        assert_eq!(decode::<4, f32>("AAA=", f32::from_le_bytes), None);
    }

    #[test]
    fn a_quantized_rotation_is_within_a_hundredth_of_a_degree() {
        // 37° about a slanted axis, given with w < 0 (the same rotation).
        let (half, axis) = (37f64.to_radians() / 2.0, [0.48, -0.6, 0.64]);
        let q = [
            -axis[0] * half.sin(),
            -axis[1] * half.sin(),
            -axis[2] * half.sin(),
            -half.cos(),
        ];
        let back = quaternion(q).map(|c| f64::from(c) / QUATERNION_SCALE);
        assert!(back[3] > 0.0);
        let dot: f64 = (0..4).map(|i| -q[i] * back[i]).sum();
        let n: f64 = back.iter().map(|c| c * c).sum::<f64>().sqrt();
        let angle = 2.0 * (dot / n).clamp(-1.0, 1.0).acos();
        assert!(angle.to_degrees() < 0.01, "{}", angle.to_degrees());
    }

    #[test]
    fn heights_keep_half_a_millimetre() {
        let h = [0.0, 0.013, -0.2, 4.0, 0.5];
        let (lo, step, q) = heights(&h);
        for (v, s) in h.iter().zip(&q) {
            assert!((lo + step * f64::from(*s) - v).abs() < 5e-4);
        }
        assert_eq!(angle(12.345), 1235);
        assert_eq!(angle(f64::NAN), 0);
    }
}
