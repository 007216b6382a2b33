//! Reading a data file (listing B.8) as a stream: the header, then each complete round's
//! frames handed to a callback, never the whole document in memory. A file whose end is
//! missing (the writer was killed) reads up to its last complete round and is reported
//! as cut. Files without our `typeParts` extension (the thesis's own) take each series'
//! part count from its first frame.

use std::fmt;
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use quick_xml::events::{BytesStart, Event};
use quick_xml::reader::Reader;

use crate::data::handler::{FrameMeta, HandlerSpec};
use crate::data::write::STAMPS;

/// Why a data file could not be read.
#[derive(Debug, Clone, PartialEq)]
pub struct DataError {
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for DataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{l}: {}", self.file.display(), self.message),
            None => write!(f, "{}: {}", self.file.display(), self.message),
        }
    }
}

impl std::error::Error for DataError {}

/// What a file holds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DataInfo {
    pub handlers: Vec<HandlerSpec>,
    /// Complete frames per handler.
    pub frames: Vec<u64>,
    /// Complete rounds.
    pub rounds: u64,
    /// Simulated time span of the frames read (ms).
    pub first_simtime_ms: Option<f64>,
    pub last_simtime_ms: Option<f64>,
    /// The file ends before `</dataRoot>`: data after the last complete round is lost.
    pub cut: bool,
}

/// One frame handed to the callback.
pub struct FrameRef<'a> {
    pub handler: usize,
    pub round: u64,
    pub meta: FrameMeta,
    /// `handlers[handler].width()` values.
    pub values: &'a [f64],
}

/// What the reader hands out, in file order.
pub enum DataEvent<'a> {
    /// Once, before any frame.
    Header(&'a [HandlerSpec]),
    /// Every frame of every complete round.
    Frame(FrameRef<'a>),
}

/// Reads `path`, calling `on_event` with the header and then every frame.
pub fn read_file(path: &Path, on_event: impl FnMut(DataEvent<'_>)) -> Result<DataInfo, DataError> {
    let file = File::open(path).map_err(|e| DataError {
        file: path.to_path_buf(),
        line: None,
        message: format!("cannot open: {e}"),
    })?;
    read_stream(BufReader::new(file), path, on_event)
}

/// Just the summary of `path`.
pub fn info(path: &Path) -> Result<DataInfo, DataError> {
    read_file(path, |_| {})
}

#[derive(PartialEq)]
enum At {
    Top,
    Header,
    HeaderHandler,
    HeaderList(bool),
    Round,
    Handler,
    Frame,
    Series,
}

/// Frames of the current round, emitted when the round closes.
struct Pending {
    handler: usize,
    meta: FrameMeta,
    at: usize,
}

/// [`read_file`] on any buffered reader; `path` names it in errors.
pub fn read_stream<R: BufRead>(
    input: R,
    path: &Path,
    mut on_event: impl FnMut(DataEvent<'_>),
) -> Result<DataInfo, DataError> {
    let mut reader = Reader::from_reader(input);
    reader.config_mut().check_end_names = true;
    let mut buf = Vec::new();
    let mut info = DataInfo::default();
    let mut parts_known: Vec<bool> = Vec::new();
    let mut at = At::Top;
    let mut handler: Option<usize> = None;
    let mut round = 0u64;
    let mut series: usize = 0;
    // The round being read: frame stamps and all values, flat.
    let mut pending: Vec<Pending> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    // The frame being read, per series (reused).
    let mut frame_series: Vec<Vec<f64>> = Vec::new();
    let mut meta = FrameMeta::default();
    let mut closed = false;
    let mut in_root = false;
    let mut header_done = false;
    let err = |reader: &Reader<R>, message: String| DataError {
        file: path.to_path_buf(),
        line: line_of(path, reader.buffer_position() as usize),
        message,
    };
    loop {
        buf.clear();
        let event = match reader.read_event_into(&mut buf) {
            Ok(e) => e,
            Err(e) => {
                if info.rounds > 0 || header_done {
                    // A cut in the middle of an element: keep the complete rounds.
                    info.cut = true;
                    break;
                }
                return Err(err(&reader, format!("malformed XML: {e}")));
            }
        };
        match event {
            Event::Start(e) | Event::Empty(e) if !in_root => {
                let name = tag(&e);
                if name != "dataRoot" {
                    return Err(err(&reader, format!("expected <dataRoot>, found <{name}>")));
                }
                in_root = true;
            }
            Event::Start(e) => {
                let name = tag(&e);
                match at {
                    At::Top if name == "Header" && !header_done => at = At::Header,
                    At::Header => {
                        info.handlers.push(HandlerSpec {
                            name,
                            series: Vec::new(),
                            parts: Vec::new(),
                        });
                        let parts = attr(&e, "parts").and_then(|p| p.parse().ok()).unwrap_or(0);
                        parts_known.push(false);
                        // Provisional part count until typeParts or the first frame says.
                        if let Some(h) = info.handlers.last_mut() {
                            h.parts = vec![parts];
                        }
                        at = At::HeaderHandler;
                    }
                    At::HeaderHandler => at = At::HeaderList(name == "typeParts"),
                    At::Top if name == "round" => {
                        if !header_done {
                            return Err(err(&reader, "a round before the header".into()));
                        }
                        round = attr(&e, "number")
                            .and_then(|n| n.parse().ok())
                            .unwrap_or(round);
                        at = At::Round;
                    }
                    At::Round => {
                        handler = info.handlers.iter().position(|h| h.name == name);
                        if handler.is_none() {
                            return Err(err(
                                &reader,
                                format!("data of <{name}>, which the header does not declare"),
                            ));
                        }
                        at = At::Handler;
                    }
                    At::Handler if name == "Frame" => {
                        let h = handler.unwrap_or(0);
                        meta = FrameMeta {
                            index: attr(&e, "index").and_then(|v| v.parse().ok()).unwrap_or(0),
                            realtime_ms: attr(&e, "realtime")
                                .and_then(|v| v.parse().ok())
                                .unwrap_or(0),
                            simtime_ms: attr(&e, "simtime")
                                .and_then(|v| v.parse().ok())
                                .unwrap_or(f64::NAN),
                            step: attr(&e, "step").and_then(|v| v.parse().ok()).unwrap_or(0),
                        };
                        frame_series.resize_with(info.handlers[h].series.len(), Vec::new);
                        frame_series.iter_mut().for_each(Vec::clear);
                        at = At::Frame;
                    }
                    At::Frame => {
                        let h = &info.handlers[handler.unwrap_or(0)];
                        series = h.find(&name).ok_or_else(|| {
                            err(&reader, format!("<{name}> is not a series of {}", h.name))
                        })?;
                        at = At::Series;
                    }
                    _ => return Err(err(&reader, format!("unexpected <{name}>"))),
                }
            }
            Event::Empty(e) => {
                let name = tag(&e);
                if at == At::Round && !info.handlers.iter().any(|h| h.name == name) {
                    return Err(err(
                        &reader,
                        format!("data of <{name}>, which the header does not declare"),
                    ));
                }
            }
            Event::Text(t) => {
                let text = t.xml10_content();
                match at {
                    At::HeaderList(is_parts) => {
                        let Some(h) = info.handlers.last_mut() else {
                            continue;
                        };
                        if is_parts {
                            let parts: Result<Vec<usize>, _> =
                                text.split_whitespace().map(str::parse).collect();
                            h.parts = parts.map_err(|e| err(&reader, format!("typeParts: {e}")))?;
                            if let Some(k) = parts_known.last_mut() {
                                *k = true;
                            }
                        } else {
                            h.series = text
                                .split_whitespace()
                                .filter(|s| !STAMPS.contains(s))
                                .map(str::to_string)
                                .collect();
                        }
                    }
                    At::Series => {
                        for word in text.split_whitespace() {
                            let v: f64 = word
                                .parse()
                                .map_err(|_| err(&reader, format!("{word:?} is not a number")))?;
                            frame_series[series].push(v);
                        }
                    }
                    _ => {}
                }
            }
            Event::End(e) => {
                let name = e.name().as_ref().to_string();
                match at {
                    At::HeaderList(_) => at = At::HeaderHandler,
                    At::HeaderHandler => {
                        let i = info.handlers.len() - 1;
                        let h = &mut info.handlers[i];
                        if !parts_known[i] || h.parts.len() != h.series.len() {
                            let p = h.parts.first().copied().unwrap_or(0);
                            h.parts = vec![p; h.series.len()];
                        }
                        at = At::Header;
                    }
                    At::Header => {
                        header_done = true;
                        info.frames = vec![0; info.handlers.len()];
                        on_event(DataEvent::Header(&info.handlers));
                        at = At::Top;
                    }
                    At::Series => at = At::Frame,
                    At::Frame => {
                        let h = handler.unwrap_or(0);
                        let spec = &mut info.handlers[h];
                        if !parts_known[h] {
                            spec.parts = frame_series.iter().map(Vec::len).collect();
                            parts_known[h] = true;
                        }
                        pending.push(Pending {
                            handler: h,
                            meta,
                            at: values.len(),
                        });
                        for (got, want) in frame_series.iter().zip(&spec.parts) {
                            values.extend(got.iter().take(*want));
                            values.extend(std::iter::repeat_n(
                                f64::NAN,
                                want.saturating_sub(got.len()),
                            ));
                        }
                        at = At::Handler;
                    }
                    At::Handler => at = At::Round,
                    At::Round => {
                        for (k, p) in pending.iter().enumerate() {
                            let end = pending.get(k + 1).map(|q| q.at).unwrap_or(values.len());
                            on_event(DataEvent::Frame(FrameRef {
                                handler: p.handler,
                                round,
                                meta: p.meta,
                                values: &values[p.at..end],
                            }));
                            info.frames[p.handler] += 1;
                            let t = p.meta.simtime_ms;
                            if t.is_finite() {
                                info.first_simtime_ms.get_or_insert(t);
                                info.last_simtime_ms = Some(t);
                            }
                        }
                        pending.clear();
                        values.clear();
                        info.rounds += 1;
                        round += 1;
                        at = At::Top;
                    }
                    At::Top if name == "dataRoot" => closed = true,
                    _ => {}
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if !header_done {
        return Err(DataError {
            file: path.to_path_buf(),
            line: None,
            message: "no <Header>: not a data file, or cut before its header".into(),
        });
    }
    info.cut |= !closed;
    Ok(info)
}

fn tag(e: &BytesStart<'_>) -> String {
    e.name().as_ref().to_string()
}

fn attr(e: &BytesStart<'_>, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == key)
        .map(|a| a.value.to_string())
}

/// The 1-based line of byte `offset` in `path` (error path only: reads the file again).
fn line_of(path: &Path, offset: usize) -> Option<usize> {
    let bytes = std::fs::read(path).ok()?;
    let end = offset.min(bytes.len());
    Some(bytes[..end].iter().filter(|b| **b == b'\n').count() + 1)
}
