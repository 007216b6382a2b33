//! A tactile pad's area on its link, engine-neutral: a box in the link's frame, touched
//! when the bounding box of one contact patch's points (in the pad's frame) overlaps it.
//! Both engines feed it their contact points; the rule is one.

use crate::config::transform::Pose;

/// A pad's area: a box at `pose` in its link's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PadArea {
    /// Centre and orientation in the link's frame.
    pub pose: Pose,
    /// Half extents (m).
    pub half_extents: [f64; 3],
}

impl PadArea {
    /// How far outside the pad's box a contact point still counts (m): the contact solver
    /// keeps points a little off the surface.
    pub fn tolerance(&self) -> f64 {
        0.1 * self
            .half_extents
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether the box spanned by `points` (in the pad's frame) overlaps the pad.
    pub fn touched_by(&self, mut points: impl Iterator<Item = [f64; 3]>) -> bool {
        let Some(first) = points.next() else {
            return false;
        };
        let (lo, hi) = points.fold((first, first), |(mut lo, mut hi), p| {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
            (lo, hi)
        });
        let tol = self.tolerance();
        (0..3).all(|i| {
            let reach = self.half_extents[i] + tol;
            lo[i] <= reach && hi[i] >= -reach
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pad() -> PadArea {
        PadArea {
            pose: Pose::IDENTITY,
            half_extents: [0.012, 0.015, 0.003],
        }
    }

    #[test]
    fn a_patch_wider_than_the_pad_touches_it() {
        // A sole lying flat: contact points at its corners, outside the pad in x.
        let corners = [[-0.022, -0.03, -0.003], [0.022, 0.03, -0.003]];
        assert!(pad().touched_by(corners.into_iter()));
    }

    #[test]
    fn a_patch_beside_the_pad_or_above_it_does_not() {
        let beside = [[-0.022, 0.02, -0.003], [0.022, 0.03, -0.003]];
        assert!(!pad().touched_by(beside.into_iter()));
        let above = [[0.0, 0.0, 0.01]];
        assert!(!pad().touched_by(above.into_iter()));
        assert!(!pad().touched_by(std::iter::empty()));
    }

    #[test]
    fn points_on_the_face_touch_within_the_tolerance() {
        let on_face = [[0.0, 0.0, -0.003 - 0.0002]];
        assert!(pad().touched_by(on_face.into_iter()));
        let below = [[0.0, 0.0, -0.003 - 0.0005]];
        assert!(!pad().touched_by(below.into_iter()));
    }
}
