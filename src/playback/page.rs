//! The viewer's page: [`standalone`] writes one self-contained HTML file (the viewer, its
//! libraries and the streams inlined; opened from disk, no server, no network), and the
//! dashboard serves the same viewer over HTTP ([`VIEWER_JS`] and the others), its streams
//! fetched. The assets are built into the binary.

use std::path::Path;

use crate::playback::error::PlaybackError;
use crate::playback::stream::PoseStream;

/// The viewer (assets/viewer/viewer.js).
pub const VIEWER_JS: &str = include_str!("../../assets/viewer/viewer.js");
/// The viewer's style.
pub const VIEWER_CSS: &str = include_str!("../../assets/viewer/viewer.css");
/// three.js as the global `THREE`, bundled by scripts/dashboard-assets.
pub const THREE_JS: &str = include_str!("../../assets/viewer/vendor/three.iife.min.js");
/// uPlot, the plots' library (the dashboard's).
pub const UPLOT_JS: &str = include_str!("../../assets/dashboard/vendor/uPlot.iife.min.js");
/// uPlot's style.
pub const UPLOT_CSS: &str = include_str!("../../assets/dashboard/vendor/uPlot.min.css");
/// The self-contained page's template.
const TEMPLATE: &str = include_str!("../../assets/viewer/replay.html");

/// The page with `streams` (one, or two on one timeline) inlined.
pub fn standalone(streams: &[&PoseStream]) -> Result<String, PlaybackError> {
    if !(1..=2).contains(&streams.len()) {
        return Err(PlaybackError::Streams(streams.len()));
    }
    let mut json = String::from("[");
    for (i, s) in streams.iter().enumerate() {
        if i > 0 {
            json.push(',');
        }
        json.push_str(&s.to_json()?);
    }
    json.push(']');
    // In JSON a `<` is only ever inside a string, where `\u003c` reads the same: no
    // `</script>` in a label ends the script element early.
    let json = json.replace('<', "\\u003c");
    // The assets are ours and hold no `</script` or `</style` (a test checks); each
    // placeholder is replaced once, in order, so no inlined text is searched again.
    let mut page = String::with_capacity(TEMPLATE.len() + json.len() + THREE_JS.len() + 200_000);
    let mut rest = TEMPLATE;
    for (mark, text) in [
        ("/*UPLOT_CSS*/", UPLOT_CSS),
        ("/*VIEWER_CSS*/", VIEWER_CSS),
        ("/*STREAMS*/", json.as_str()),
        ("/*UPLOT_JS*/", UPLOT_JS),
        ("/*THREE_JS*/", THREE_JS),
        ("/*VIEWER_JS*/", VIEWER_JS),
    ] {
        let (before, after) = rest.split_once(mark).unwrap_or((rest, ""));
        page.push_str(before);
        page.push_str(text);
        rest = after;
    }
    page.push_str(rest);
    Ok(page)
}

/// Writes [`standalone`]'s page to `path` (beside it first, then renamed: never half a
/// page); returns its size in bytes.
pub fn write_standalone(path: &Path, streams: &[&PoseStream]) -> Result<u64, PlaybackError> {
    let page = standalone(streams)?;
    let write_err = |source| PlaybackError::Write {
        path: path.to_path_buf(),
        source,
    };
    let mut part = path.as_os_str().to_owned();
    part.push(".part");
    let part = std::path::PathBuf::from(part);
    std::fs::write(&part, &page).map_err(write_err)?;
    std::fs::rename(&part, path).map_err(write_err)?;
    Ok(page.len() as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_asset_ends_its_element_early() {
        for (name, text) in [
            ("viewer.js", VIEWER_JS),
            ("three.iife.min.js", THREE_JS),
            ("uPlot.iife.min.js", UPLOT_JS),
            ("viewer.css", VIEWER_CSS),
            ("uPlot.min.css", UPLOT_CSS),
        ] {
            let lower = text.to_ascii_lowercase();
            assert!(
                !lower.contains("</script") && !lower.contains("</style"),
                "{name} holds an end tag"
            );
        }
        for mark in [
            "/*UPLOT_CSS*/",
            "/*VIEWER_CSS*/",
            "/*STREAMS*/",
            "/*UPLOT_JS*/",
            "/*THREE_JS*/",
            "/*VIEWER_JS*/",
        ] {
            assert_eq!(TEMPLATE.matches(mark).count(), 1, "{mark}");
        }
    }
}
