//! Poses in configuration files: a translation and a rotation quaternion.
//!
//! OpenRAVE files write rotations as `<RotationAxis>x y z angle_deg</RotationAxis>`
//! (repeatable, applied in order), `<quat>w x y z</quat>` or `<RotationMat>` (9 numbers,
//! row-major). All become one unit quaternion; the writer emits `<quat>`.
//! Coordinates are OpenRAVE's: metres, z up.

use crate::config::error::ConfigResult;
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::XmlWriter;

/// A rigid transform: translate after rotating.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Translation (m).
    pub translation: [f64; 3],
    /// Unit quaternion `[w, x, y, z]`.
    pub rotation: [f64; 4],
}

impl Default for Pose {
    fn default() -> Self {
        Pose::IDENTITY
    }
}

/// Names of the pose elements a container may hold.
pub const POSE_ELEMENTS: [&str; 4] = ["translation", "rotationaxis", "quat", "rotationmat"];

impl Pose {
    /// No translation, no rotation.
    pub const IDENTITY: Pose = Pose {
        translation: [0.0; 3],
        rotation: [1.0, 0.0, 0.0, 0.0],
    };

    /// A pure translation.
    pub fn from_translation(t: [f64; 3]) -> Self {
        Pose {
            translation: t,
            rotation: Pose::IDENTITY.rotation,
        }
    }

    /// Whether this is exactly the identity.
    pub fn is_identity(&self) -> bool {
        *self == Pose::IDENTITY
    }

    /// `self * other`: first `other`, then `self`.
    pub fn mul(&self, other: &Pose) -> Pose {
        let t = self.rotate(other.translation);
        Pose {
            translation: [
                t[0] + self.translation[0],
                t[1] + self.translation[1],
                t[2] + self.translation[2],
            ],
            rotation: quat_mul(self.rotation, other.rotation),
        }
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Pose {
        let [w, x, y, z] = self.rotation;
        let conj = Pose {
            translation: [0.0; 3],
            rotation: [w, -x, -y, -z],
        };
        let t = conj.rotate(self.translation);
        Pose {
            translation: [-t[0], -t[1], -t[2]],
            rotation: conj.rotation,
        }
    }

    /// A point of this frame in the outer frame.
    pub fn transform_point(&self, p: [f64; 3]) -> [f64; 3] {
        let r = self.rotate(p);
        [
            r[0] + self.translation[0],
            r[1] + self.translation[1],
            r[2] + self.translation[2],
        ]
    }

    /// Rotates a vector by this transform's rotation.
    pub fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        let [w, x, y, z] = self.rotation;
        let u = [x, y, z];
        let uv = cross(u, v);
        let uuv = cross(u, uv);
        [
            v[0] + 2.0 * (w * uv[0] + uuv[0]),
            v[1] + 2.0 * (w * uv[1] + uuv[1]),
            v[2] + 2.0 * (w * uv[2] + uuv[2]),
        ]
    }

    /// Reads the pose elements among `el`'s children (other children are left alone).
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<Pose> {
        let mut tf = Pose::IDENTITY;
        for c in &el.children {
            if c.is("translation") {
                let t = r.array::<3>(c)?;
                tf.translation = [
                    tf.translation[0] + t[0],
                    tf.translation[1] + t[1],
                    tf.translation[2] + t[2],
                ];
            } else if c.is("rotationaxis") {
                let [x, y, z, deg] = r.array::<4>(c)?;
                let q = axis_angle(r, c, [x, y, z], deg)?;
                tf.rotation = quat_mul(q, tf.rotation);
            } else if c.is("quat") {
                let q = r.array::<4>(c)?;
                tf.rotation = quat_mul(normalized_quat(r, c, q)?, tf.rotation);
            } else if c.is("rotationmat") {
                let m = r.array::<9>(c)?;
                let q = normalized_quat(r, c, mat_to_quat(m))?;
                tf.rotation = quat_mul(q, tf.rotation);
            }
        }
        Ok(tf)
    }

    /// Writes `<translation>` and `<quat>` as they are (each only when not neutral), so a
    /// file read and written reads back equal; producers of computed poses round them first
    /// (`for_people`).
    pub fn write(&self, w: &mut XmlWriter) {
        if self.translation != [0.0; 3] {
            w.nums("translation", &self.translation);
        }
        if self.rotation != Pose::IDENTITY.rotation {
            w.nums("quat", &self.rotation);
        }
    }

    /// The pose as files written for people hold it: the translation rounded to 0.1 mm
    /// (not float noise such as `-0.1559227705001831`), the rotation as it is.
    pub fn for_people(&self) -> Pose {
        Pose {
            translation: self.translation.map(|v| round_to(v, 1e4)),
            rotation: self.rotation,
        }
    }
}

/// `v` rounded to `1 / scale` (a plain `0` for a negative zero).
pub fn round_to(v: f64, scale: f64) -> f64 {
    (v * scale).round() / scale + 0.0
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Hamilton product `a * b`.
pub fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}

fn axis_angle(r: &Reader, el: &Element, axis: [f64; 3], deg: f64) -> ConfigResult<[f64; 4]> {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    if deg == 0.0 {
        return Ok(Pose::IDENTITY.rotation);
    }
    if n < 1e-12 {
        return Err(r.err(
            el.text_pos,
            crate::config::error::ErrorKind::InvalidValue,
            format!("<{}>: the rotation axis is zero", el.name),
        ));
    }
    let half = deg.to_radians() / 2.0;
    let s = half.sin() / n;
    Ok([half.cos(), axis[0] * s, axis[1] * s, axis[2] * s])
}

/// Normalizes a quaternion; an all-zero one (as OpenRAVE writes for "no rotation") is identity.
pub fn normalized_quat(r: &Reader, el: &Element, q: [f64; 4]) -> ConfigResult<[f64; 4]> {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if n == 0.0 {
        return Ok(Pose::IDENTITY.rotation);
    }
    if !n.is_finite() {
        return Err(r.err(
            el.text_pos,
            crate::config::error::ErrorKind::InvalidValue,
            format!("<{}>: the rotation is not finite", el.name),
        ));
    }
    if (n - 1.0).abs() < 1e-12 {
        return Ok(q);
    }
    Ok([q[0] / n, q[1] / n, q[2] / n, q[3] / n])
}

fn mat_to_quat(m: [f64; 9]) -> [f64; 4] {
    let [m00, m01, m02, m10, m11, m12, m20, m21, m22] = m;
    let tr = m00 + m11 + m22;
    if tr > 0.0 {
        let s = (tr + 1.0).sqrt() * 2.0;
        [0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s]
    } else if m00 > m11 && m00 > m22 {
        let s = (1.0 + m00 - m11 - m22).sqrt() * 2.0;
        [(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s]
    } else if m11 > m22 {
        let s = (1.0 + m11 - m00 - m22).sqrt() * 2.0;
        [(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s]
    } else {
        let s = (1.0 + m22 - m00 - m11).sqrt() * 2.0;
        [(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_about_z_turns_x_into_y() {
        let r = Reader::new("t.xml");
        let doc =
            crate::config::xml::dom::parse("t.xml", "<b><rotationaxis>0 0 1 90</rotationaxis></b>")
                .unwrap();
        let tf = Pose::read(&r, &doc.root).unwrap();
        let v = tf.rotate([1.0, 0.0, 0.0]);
        assert!((v[0]).abs() < 1e-12 && (v[1] - 1.0).abs() < 1e-12, "{v:?}");
    }

    #[test]
    fn composition_applies_inner_first() {
        let a = Pose::from_translation([1.0, 0.0, 0.0]);
        let b = Pose::from_translation([0.0, 2.0, 0.0]);
        assert_eq!(a.mul(&b).translation, [1.0, 2.0, 0.0]);
    }
}
