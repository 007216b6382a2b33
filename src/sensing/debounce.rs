//! Debouncing a binary contact signal (the thesis's tactile sensors report debounced
//! collisions, 5.1): a new state is reported once it has lasted `steps` consecutive steps.

/// The debounced state of one pad.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Debounce {
    /// The reported state.
    pub pressed: bool,
    /// Consecutive steps the raw signal has differed from `pressed`.
    pending: u32,
}

impl Debounce {
    /// Feeds one raw sample; returns the (possibly new) reported state. With `steps` 0 or
    /// 1 every change is reported at once.
    pub fn update(&mut self, raw: bool, steps: u32) -> bool {
        if raw == self.pressed {
            self.pending = 0;
        } else {
            self.pending += 1;
            if self.pending >= steps.max(1) {
                self.pressed = raw;
                self.pending = 0;
            }
        }
        self.pressed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flicker_is_suppressed_and_steady_changes_pass() {
        let mut d = Debounce::default();
        // Flicker: on for 2 steps, off, on for 2: never 3 in a row.
        for raw in [true, true, false, true, true, false] {
            assert!(!d.update(raw, 3));
        }
        assert!(!d.update(true, 3));
        assert!(!d.update(true, 3));
        assert!(d.update(true, 3), "three steady steps press it");
        assert!(d.update(false, 3) && d.update(false, 3));
        assert!(!d.update(false, 3), "three steady steps release it");
        assert!(d.update(true, 1), "debounce 1 passes every change");
    }
}
