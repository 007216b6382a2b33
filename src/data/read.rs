//! Reading a data file (listing B.8) as a stream: the header, then each complete round's
//! frames handed to a callback, never the whole document in memory. A file whose end is
//! missing (the writer was killed) reads up to its last complete round and is reported
//! as cut. Files without our `typeParts` extension (the thesis's own) take each series'
//! part count from its first frame.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use quick_xml::events::{BytesStart, Event};
use quick_xml::reader::Reader;

use crate::data::handler::{FrameMeta, HandlerSpec};
use crate::data::write::STAMPS;

/// Why a data file could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{}: {}", .file.display(), line_suffix(.line), .message)]
pub struct DataError {
    /// The data file.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

/// `:LINE` when the line is known.
fn line_suffix(line: &Option<usize>) -> String {
    line.map(|l| format!(":{l}")).unwrap_or_default()
}

/// What a file holds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DataInfo {
    /// The handlers the header declares.
    pub handlers: Vec<HandlerSpec>,
    /// Complete frames per handler.
    pub frames: Vec<u64>,
    /// Complete rounds.
    pub rounds: u64,
    /// Simulated time span of the frames read (ms).
    pub first_simtime_ms: Option<f64>,
    /// Simulated time of the last frame (ms).
    pub last_simtime_ms: Option<f64>,
    /// The file ends before `</dataRoot>`: data after the last complete round is lost.
    pub cut: bool,
    /// Stamps that are not numbers, each with its line (`line 12: <Frame> index="x" is not
    /// a number; read as 0`); the frame is kept. At most [`MAX_WARNINGS`], then a count.
    pub warnings: Vec<String>,
}

/// Warnings a read keeps word for word; the rest are counted in the last one.
pub const MAX_WARNINGS: usize = 20;

/// One frame handed to the callback.
pub struct FrameRef<'a> {
    /// Index of the handler.
    pub handler: usize,
    /// Round number.
    pub round: u64,
    /// The frame's stamps.
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

#[derive(PartialEq, Default)]
enum At {
    #[default]
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
    let mut st = Stream::default();
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
                if st.info.rounds > 0 || st.header_done {
                    // A cut in the middle of an element: keep the complete rounds.
                    st.info.cut = true;
                    break;
                }
                return Err(err(&reader, format!("malformed XML: {e}")));
            }
        };
        let step = match event {
            Event::Start(e) | Event::Empty(e) if !st.in_root => st.root(&e),
            Event::Start(e) => st.start(&e),
            Event::Empty(e) => st.empty(&e),
            Event::Text(t) => st.text(&t.xml10_content()),
            Event::End(e) => {
                st.end(e.name().as_ref(), &mut on_event);
                Ok(())
            }
            Event::Eof => break,
            _ => Ok(()),
        };
        step.map_err(|m| err(&reader, m.to_string()))?;
        if !st.bad_stamps.is_empty() {
            let line = line_of(path, reader.buffer_position() as usize);
            for m in st.bad_stamps.drain(..) {
                let w = &mut st.info.warnings;
                if w.len() < MAX_WARNINGS {
                    w.push(match line {
                        Some(l) => format!("line {l}: {m}"),
                        None => m,
                    });
                }
                st.bad_stamp_count += 1;
            }
        }
    }
    if st.bad_stamp_count > MAX_WARNINGS {
        let more = st.bad_stamp_count - MAX_WARNINGS;
        st.info
            .warnings
            .push(format!("... and {more} more stamps that are not numbers"));
    }
    if !st.header_done {
        return Err(DataError {
            file: path.to_path_buf(),
            line: None,
            message: "no <Header>: not a data file, or cut before its header".into(),
        });
    }
    st.info.cut |= !st.closed;
    Ok(st.info)
}

/// What is wrong at a place of a data file (the reader adds the file and line).
#[derive(Debug, thiserror::Error)]
enum Fault {
    /// The root element is not `<dataRoot>`.
    #[error("expected <dataRoot>, found <{0}>")]
    Root(String),
    /// A `<round>` before `<Header>`.
    #[error("a round before the header")]
    RoundBeforeHeader,
    /// A handler the header does not declare.
    #[error("data of <{0}>, which the header does not declare")]
    Undeclared(String),
    /// A series its handler does not have.
    #[error("<{series}> is not a series of {handler}")]
    NoSeries {
        /// The element's name.
        series: String,
        /// The handler.
        handler: String,
    },
    /// An element out of place.
    #[error("unexpected <{0}>")]
    Unexpected(String),
    /// `typeParts` that are not counts.
    #[error("typeParts: {0}")]
    Parts(std::num::ParseIntError),
    /// A value that is not a number.
    #[error("{0:?} is not a number")]
    NotANumber(String),
}

/// The reader's state between events.
#[derive(Default)]
struct Stream {
    info: DataInfo,
    /// Per handler: whether its part counts are known (typeParts or a first frame).
    parts_known: Vec<bool>,
    at: At,
    handler: Option<usize>,
    round: u64,
    series: usize,
    /// The round being read: frame stamps and all values, flat.
    pending: Vec<Pending>,
    values: Vec<f64>,
    /// The frame being read, per series (reused).
    frame_series: Vec<Vec<f64>>,
    meta: FrameMeta,
    closed: bool,
    in_root: bool,
    header_done: bool,
    /// Stamps of the element just read that are not numbers (the caller adds the line).
    bad_stamps: Vec<String>,
    /// All of them so far.
    bad_stamp_count: usize,
}

impl Stream {
    /// The root element.
    fn root(&mut self, e: &BytesStart<'_>) -> Result<(), Fault> {
        let name = tag(e);
        if name != "dataRoot" {
            return Err(Fault::Root(name));
        }
        self.in_root = true;
        Ok(())
    }

    /// An opening tag inside the root.
    fn start(&mut self, e: &BytesStart<'_>) -> Result<(), Fault> {
        let name = tag(e);
        match self.at {
            At::Top if name == "Header" && !self.header_done => self.at = At::Header,
            At::Header => self.header_handler(e, name),
            At::HeaderHandler => self.at = At::HeaderList(name == "typeParts"),
            At::Top if name == "round" => {
                if !self.header_done {
                    return Err(Fault::RoundBeforeHeader);
                }
                self.round = attr(e, "number")
                    .and_then(|n| n.parse().ok())
                    .unwrap_or(self.round);
                self.at = At::Round;
            }
            At::Round => {
                self.handler = self.info.handlers.iter().position(|h| h.name == name);
                if self.handler.is_none() {
                    return Err(Fault::Undeclared(name));
                }
                self.at = At::Handler;
            }
            At::Handler if name == "Frame" => self.frame(e),
            At::Frame => {
                let h = &self.info.handlers[self.handler.unwrap_or(0)];
                self.series = h.find(&name).ok_or_else(|| Fault::NoSeries {
                    series: name.clone(),
                    handler: h.name.clone(),
                })?;
                self.at = At::Series;
            }
            _ => return Err(Fault::Unexpected(name)),
        }
        Ok(())
    }

    /// A handler declared in the header, with a provisional part count until typeParts or
    /// the first frame says.
    fn header_handler(&mut self, e: &BytesStart<'_>, name: String) {
        let parts = attr(e, "parts").and_then(|p| p.parse().ok()).unwrap_or(0);
        self.info.handlers.push(HandlerSpec {
            name,
            series: Vec::new(),
            parts: vec![parts],
        });
        self.parts_known.push(false);
        self.at = At::HeaderHandler;
    }

    /// A frame's stamps.
    fn frame(&mut self, e: &BytesStart<'_>) {
        let h = self.handler.unwrap_or(0);
        self.meta = FrameMeta {
            index: self.stamp(e, "index", 0, "0"),
            realtime_ms: self.stamp(e, "realtime", 0, "0"),
            simtime_ms: self.stamp(e, "simtime", f64::NAN, "unknown"),
            step: self.stamp(e, "step", 0, "0"),
        };
        let series = self.info.handlers[h].series.len();
        self.frame_series.resize_with(series, Vec::new);
        self.frame_series.iter_mut().for_each(Vec::clear);
        self.at = At::Frame;
    }

    /// Stamp `key` of `e`: `absent` when the file has none (older files lack some), and
    /// `absent` with a warning ([`DataInfo::warnings`]) when it is not a number.
    fn stamp<T: std::str::FromStr>(
        &mut self,
        e: &BytesStart<'_>,
        key: &str,
        absent: T,
        shown: &str,
    ) -> T {
        let Some(v) = attr(e, key) else {
            return absent;
        };
        v.trim().parse().unwrap_or_else(|_| {
            self.bad_stamps.push(format!(
                "<{}> {key}=\"{v}\" is not a number; read as {shown}",
                tag(e)
            ));
            absent
        })
    }

    /// An empty element: in a round, it must be a declared handler.
    fn empty(&mut self, e: &BytesStart<'_>) -> Result<(), Fault> {
        let name = tag(e);
        if self.at == At::Round && !self.info.handlers.iter().any(|h| h.name == name) {
            return Err(Fault::Undeclared(name));
        }
        Ok(())
    }

    /// Text: the header's series names or part counts, or a series' values.
    fn text(&mut self, text: &str) -> Result<(), Fault> {
        match self.at {
            At::HeaderList(is_parts) => {
                let Some(h) = self.info.handlers.last_mut() else {
                    return Ok(());
                };
                if is_parts {
                    let parts: Result<Vec<usize>, _> =
                        text.split_whitespace().map(str::parse).collect();
                    h.parts = parts.map_err(Fault::Parts)?;
                    if let Some(k) = self.parts_known.last_mut() {
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
                        .map_err(|_| Fault::NotANumber(word.to_string()))?;
                    self.frame_series[self.series].push(v);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// A closing tag: finishes a header handler, the header, a frame or a round.
    fn end(&mut self, name: &str, on_event: &mut impl FnMut(DataEvent<'_>)) {
        match self.at {
            At::HeaderList(_) => self.at = At::HeaderHandler,
            At::HeaderHandler => {
                let i = self.info.handlers.len() - 1;
                let h = &mut self.info.handlers[i];
                if !self.parts_known[i] || h.parts.len() != h.series.len() {
                    let p = h.parts.first().copied().unwrap_or(0);
                    h.parts = vec![p; h.series.len()];
                }
                self.at = At::Header;
            }
            At::Header => {
                self.header_done = true;
                self.info.frames = vec![0; self.info.handlers.len()];
                on_event(DataEvent::Header(&self.info.handlers));
                self.at = At::Top;
            }
            At::Series => self.at = At::Frame,
            At::Frame => self.end_frame(),
            At::Handler => self.at = At::Round,
            At::Round => self.end_round(on_event),
            At::Top if name == "dataRoot" => self.closed = true,
            _ => {}
        }
    }

    /// Keeps a frame's values (padded or cut to the part counts) for its round.
    fn end_frame(&mut self) {
        let h = self.handler.unwrap_or(0);
        let spec = &mut self.info.handlers[h];
        if !self.parts_known[h] {
            spec.parts = self.frame_series.iter().map(Vec::len).collect();
            self.parts_known[h] = true;
        }
        self.pending.push(Pending {
            handler: h,
            meta: self.meta,
            at: self.values.len(),
        });
        for (got, want) in self.frame_series.iter().zip(&spec.parts) {
            self.values.extend(got.iter().take(*want));
            self.values.extend(std::iter::repeat_n(
                f64::NAN,
                want.saturating_sub(got.len()),
            ));
        }
        self.at = At::Handler;
    }

    /// A complete round: hands out its frames.
    fn end_round(&mut self, on_event: &mut impl FnMut(DataEvent<'_>)) {
        for (k, p) in self.pending.iter().enumerate() {
            let end = self
                .pending
                .get(k + 1)
                .map(|q| q.at)
                .unwrap_or(self.values.len());
            on_event(DataEvent::Frame(FrameRef {
                handler: p.handler,
                round: self.round,
                meta: p.meta,
                values: &self.values[p.at..end],
            }));
            self.info.frames[p.handler] += 1;
            let t = p.meta.simtime_ms;
            if t.is_finite() {
                self.info.first_simtime_ms.get_or_insert(t);
                self.info.last_simtime_ms = Some(t);
            }
        }
        self.pending.clear();
        self.values.clear();
        self.info.rounds += 1;
        self.round += 1;
        self.at = At::Top;
    }
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
