//! Writing the data file of listing B.8: a header naming every handler's series, then
//! rounds of frames, one block per handler, then the closing tag. Numbers are written in
//! Rust's shortest form that reads back to the same `f64`.

use std::fmt::Write as _;

use crate::data::handler::{FrameMeta, HandlerSpec};

/// The series every frame carries besides a handler's own (B.8's last three types).
pub const STAMPS: [&str; 3] = ["realtime", "simtime", "stepcount"];

/// Frames of one handler in one round: `meta.len()` frames of `spec.width()` values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HandlerFrames {
    /// Stamps of each frame.
    pub meta: Vec<FrameMeta>,
    /// Values of every frame, flat.
    pub values: Vec<f64>,
}

impl HandlerFrames {
    /// Frames held.
    pub fn len(&self) -> usize {
        self.meta.len()
    }

    /// Whether no frame is held.
    pub fn is_empty(&self) -> bool {
        self.meta.is_empty()
    }

    /// Forgets the frames, keeping the memory.
    pub fn clear(&mut self) {
        self.meta.clear();
        self.values.clear();
    }
}

/// Appends `v` in the shortest form that parses back to the same value.
pub fn push_number(out: &mut String, v: f64) {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-5..1e15).contains(&a) {
        let _ = write!(out, "{v}");
    } else {
        let _ = write!(out, "{v:e}");
    }
}

/// The XML declaration, `<dataRoot>` and the header.
pub fn header(handlers: &[HandlerSpec]) -> String {
    let mut out =
        String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<dataRoot>\n  <Header>\n");
    for h in handlers {
        let _ = writeln!(
            out,
            "    <{} types=\"{}\" parts=\"{}\">",
            h.name,
            h.series.len() + STAMPS.len(),
            h.max_parts()
        );
        let names: Vec<&str> = h.series.iter().map(String::as_str).chain(STAMPS).collect();
        let _ = writeln!(out, "      <typeNames>{}</typeNames>", names.join(" "));
        let parts: Vec<String> = h.parts.iter().map(|p| p.to_string()).collect();
        let _ = writeln!(out, "      <typeParts>{}</typeParts>", parts.join(" "));
        let _ = writeln!(out, "    </{}>", h.name);
    }
    out.push_str("  </Header>\n");
    out
}

/// One round: for every handler its frames (`frames[i]` belongs to `handlers[i]`).
pub fn round(out: &mut String, number: u64, handlers: &[HandlerSpec], frames: &[HandlerFrames]) {
    let _ = writeln!(out, "  <round number=\"{number}\">");
    for (h, f) in handlers.iter().zip(frames) {
        if f.is_empty() {
            let _ = writeln!(out, "    <{} />", h.name);
            continue;
        }
        let _ = writeln!(out, "    <{}>", h.name);
        let width = h.width();
        for (k, m) in f.meta.iter().enumerate() {
            let _ = write!(
                out,
                "      <Frame index=\"{}\" realtime=\"{}\" simtime=\"",
                m.index, m.realtime_ms
            );
            push_number(out, m.simtime_ms);
            let _ = writeln!(out, "\" step=\"{}\">", m.step);
            let values = &f.values[k * width..(k + 1) * width];
            let mut at = 0;
            for (name, parts) in h.series.iter().zip(&h.parts) {
                let _ = write!(out, "        <{name}>");
                for (i, v) in values[at..at + parts].iter().enumerate() {
                    if i > 0 {
                        out.push(' ');
                    }
                    push_number(out, *v);
                }
                let _ = writeln!(out, "</{name}>");
                at += parts;
            }
            out.push_str("      </Frame>\n");
        }
        let _ = writeln!(out, "    </{}>", h.name);
    }
    out.push_str("  </round>\n");
}

/// The closing tag.
pub const FOOTER: &str = "</dataRoot>\n";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_exactly() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1,
            -29.297,
            1e-7,
            3.24042e-18,
            1.66857e9,
            1e300,
            f64::INFINITY,
            f64::MIN_POSITIVE,
        ] {
            let mut s = String::new();
            push_number(&mut s, v);
            assert_eq!(s.parse::<f64>().unwrap(), v, "{s}");
        }
    }
}
