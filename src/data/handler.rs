//! A data handler's shape: its name (the XML element, e.g. `Robot_Data`), its series
//! ("types" in B.8, e.g. `x_pos`) and how many values ("parts") each series has per
//! frame, plus the time stamps every frame carries.

/// What one handler records.
#[derive(Debug, Clone, PartialEq)]
pub struct HandlerSpec {
    /// Handler name (a module type, `tactile`, `laser2d`, `Robot_Data`).
    pub name: String,
    /// Series names, in frame order.
    pub series: Vec<String>,
    /// Values per frame of each series (joints, pads, beams, or 1 for a scalar).
    pub parts: Vec<usize>,
}

impl HandlerSpec {
    /// A handler whose series all have `parts` values.
    pub fn uniform(name: &str, series: &[&str], parts: usize) -> Self {
        HandlerSpec {
            name: name.to_string(),
            series: series.iter().map(|s| s.to_string()).collect(),
            parts: vec![parts; series.len()],
        }
    }

    /// Values per frame (all series).
    pub fn width(&self) -> usize {
        self.parts.iter().sum()
    }

    /// Offset of series `i` in a frame's values.
    pub fn offset(&self, i: usize) -> usize {
        self.parts[..i].iter().sum()
    }

    /// The index of the series called `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.series.iter().position(|s| s == name)
    }

    /// The largest part count (the header's `parts`).
    pub fn max_parts(&self) -> usize {
        self.parts.iter().copied().max().unwrap_or(0)
    }
}

/// The time stamps of one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameMeta {
    /// Sample number within the file.
    pub index: u64,
    /// Wall-clock time, milliseconds since the Unix epoch.
    pub realtime_ms: u64,
    /// Simulated time in milliseconds (B.8's `simtime`).
    pub simtime_ms: f64,
    /// Simulation step count.
    pub step: u64,
}

impl FrameMeta {
    /// The stamps of sample `index` taken after step `step` (counted from 0) of `dt`
    /// seconds, at the wall clock's now.
    pub fn after_step(index: u64, step: u64, dt: f64) -> FrameMeta {
        FrameMeta {
            index,
            realtime_ms: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_millis() as u64)
                .unwrap_or(0),
            // Whole steps times the step in ms: exact for millisecond steps.
            simtime_ms: (step + 1) as f64 * (dt * 1000.0),
            step: step + 1,
        }
    }
}
