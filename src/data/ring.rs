//! A bounded ring buffer of the latest frames of one handler, for live plots: fixed
//! memory, pushing a frame copies its values into place and never allocates.

use crate::data::handler::FrameMeta;

/// The latest `capacity` frames of `width` values each.
#[derive(Debug, Clone, PartialEq)]
pub struct RingBuffer {
    width: usize,
    capacity: usize,
    values: Vec<f64>,
    meta: Vec<FrameMeta>,
    /// Slot the next frame goes to.
    next: usize,
    len: usize,
}

impl RingBuffer {
    /// A buffer of `capacity` frames of `width` values, allocated now.
    pub fn new(width: usize, capacity: usize) -> Self {
        let capacity = capacity.max(1);
        RingBuffer {
            width,
            capacity,
            values: vec![0.0; width * capacity],
            meta: vec![FrameMeta::default(); capacity],
            next: 0,
            len: 0,
        }
    }

    /// Values per frame.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Frames kept at most.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Frames kept now.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no frame is kept.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Appends a frame, dropping the oldest when full. `values` longer than the width are
    /// cut, shorter ones leave the rest of the slot at 0.
    pub fn push(&mut self, meta: FrameMeta, values: &[f64]) {
        let slot = &mut self.values[self.next * self.width..(self.next + 1) * self.width];
        let n = values.len().min(self.width);
        slot[..n].copy_from_slice(&values[..n]);
        slot[n..].fill(0.0);
        self.meta[self.next] = meta;
        self.next = (self.next + 1) % self.capacity;
        self.len = (self.len + 1).min(self.capacity);
    }

    /// Frame `i`, oldest first (`i < len`).
    pub fn get(&self, i: usize) -> Option<(FrameMeta, &[f64])> {
        if i >= self.len {
            return None;
        }
        let slot = (self.next + self.capacity - self.len + i) % self.capacity;
        Some((
            self.meta[slot],
            &self.values[slot * self.width..(slot + 1) * self.width],
        ))
    }

    /// Frames oldest first.
    pub fn iter(&self) -> impl Iterator<Item = (FrameMeta, &[f64])> {
        (0..self.len).filter_map(|i| self.get(i))
    }

    /// Forgets every frame.
    pub fn clear(&mut self) {
        self.next = 0;
        self.len = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta(index: u64) -> FrameMeta {
        FrameMeta {
            index,
            ..FrameMeta::default()
        }
    }

    #[test]
    fn keeps_the_latest_frames_in_order() {
        let mut r = RingBuffer::new(2, 3);
        for k in 0..5 {
            r.push(meta(k), &[k as f64, -(k as f64)]);
        }
        assert_eq!(r.len(), 3);
        let got: Vec<(u64, Vec<f64>)> = r.iter().map(|(m, v)| (m.index, v.to_vec())).collect();
        assert_eq!(
            got,
            vec![
                (2, vec![2.0, -2.0]),
                (3, vec![3.0, -3.0]),
                (4, vec![4.0, -4.0])
            ]
        );
        assert!(r.get(3).is_none());
        r.clear();
        assert!(r.is_empty());
    }
}
