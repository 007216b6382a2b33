//! Exporting chosen series of a data file as a table (TSV or CSV with a header row; loads
//! with pandas `read_csv(sep="\t")`), streaming round by round. Series are chosen as
//! `Handler/series`, `Handler/series[k]` or `Handler/series[a..b]` (parts a to b,
//! inclusive); rows are the samples, the first column the chosen x.

use std::io::Write;
use std::path::Path;

use crate::data::handler::{FrameMeta, HandlerSpec};
use crate::data::read::{DataError, DataEvent, DataInfo, read_file};
use crate::data::write::push_number;

/// The x column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum XAxis {
    /// Simulated time, seconds.
    SimTime,
    /// Wall-clock seconds since the first frame.
    RealTime,
    /// The step counter.
    StepCount,
    /// The sample's index.
    Index,
}

impl XAxis {
    /// The names `--x` accepts.
    pub const NAMES: [&'static str; 4] = ["simtime", "realtime", "stepcount", "index"];

    /// Reads an x-axis name (see [`XAxis::NAMES`]).
    pub fn parse(s: &str) -> Result<XAxis, UnknownAxis> {
        match s {
            "simtime" => Ok(XAxis::SimTime),
            "realtime" => Ok(XAxis::RealTime),
            "stepcount" | "step" => Ok(XAxis::StepCount),
            "index" | "count" => Ok(XAxis::Index),
            _ => Err(UnknownAxis(s.to_string())),
        }
    }

    /// Column title with its unit.
    pub fn title(self) -> &'static str {
        match self {
            XAxis::SimTime => "simtime_s",
            XAxis::RealTime => "realtime_s",
            XAxis::StepCount => "stepcount",
            XAxis::Index => "index",
        }
    }

    fn value(self, m: &FrameMeta, first_realtime: u64) -> f64 {
        match self {
            XAxis::SimTime => m.simtime_ms / 1000.0,
            XAxis::RealTime => m.realtime_ms.saturating_sub(first_realtime) as f64 / 1000.0,
            XAxis::StepCount => m.step as f64,
            XAxis::Index => m.index as f64,
        }
    }
}

/// A requested series, before it is checked against a file's header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SeriesSelector {
    /// The handler's name.
    pub handler: String,
    /// The series' name.
    pub series: String,
    /// Inclusive part range; `None` = every part.
    pub parts: Option<(usize, usize)>,
}

impl SeriesSelector {
    /// Parses `Handler/series`, `Handler/series[k]` or `Handler/series[a..b]`.
    pub fn parse(s: &str) -> Result<SeriesSelector, SelectError> {
        let s = s.trim();
        let (handler, rest) = s
            .split_once('/')
            .ok_or_else(|| SelectError::Shape(s.to_string()))?;
        let (series, parts) = match rest.split_once('[') {
            None => (rest, None),
            Some((name, range)) => {
                let range = range
                    .strip_suffix(']')
                    .ok_or_else(|| SelectError::Bracket(s.to_string()))?;
                let num = |t: &str| {
                    t.trim().parse::<usize>().map_err(|_| SelectError::Part {
                        text: s.to_string(),
                        part: t.to_string(),
                    })
                };
                let (a, b) = match range.split_once("..") {
                    Some((a, b)) => (num(a)?, num(b)?),
                    None => (num(range)?, num(range)?),
                };
                if a > b {
                    return Err(SelectError::EmptyRange {
                        text: s.to_string(),
                        range: [a, b],
                    });
                }
                (name, Some((a, b)))
            }
        };
        if handler.is_empty() || series.is_empty() {
            return Err(SelectError::Shape(s.to_string()));
        }
        Ok(SeriesSelector {
            handler: handler.to_string(),
            series: series.to_string(),
            parts,
        })
    }

    /// Parses a comma-separated list.
    pub fn parse_list(s: &str) -> Result<Vec<SeriesSelector>, SelectError> {
        s.split(',')
            .filter(|t| !t.trim().is_empty())
            .map(SeriesSelector::parse)
            .collect()
    }
}

/// A name that is no x axis.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown x series {name:?}; expected one of {}", XAxis::NAMES.join(", "), name = .0)]
pub struct UnknownAxis(pub String);

/// A series selection that is malformed or not in a file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SelectError {
    /// Not `Handler/series[...]`.
    #[error("{0:?}: expected Handler/series, e.g. Robot_Data/x_pos")]
    Shape(String),
    /// A `[` without its `]`.
    #[error("{0:?}: missing ']'")]
    Bracket(String),
    /// A part that is not a number.
    #[error("{text:?}: {part:?} is not a part number")]
    Part {
        /// The selector.
        text: String,
        /// The part given.
        part: String,
    },
    /// `[a..b]` with a > b.
    #[error("{text:?}: empty part range {}..{}", range[0], range[1])]
    EmptyRange {
        /// The selector.
        text: String,
        /// The range given.
        range: [usize; 2],
    },
    /// A handler the file does not have.
    #[error("no handler {handler:?}; the file has {}", known.join(", "))]
    NoHandler {
        /// The handler asked for.
        handler: String,
        /// The file's handlers.
        known: Vec<String>,
    },
    /// A series the handler does not have.
    #[error("{handler} has no series {series:?}; it has {}", known.join(", "))]
    NoSeries {
        /// The handler.
        handler: String,
        /// The series asked for.
        series: String,
        /// The handler's series.
        known: Vec<String>,
    },
    /// A part beyond the series' parts.
    #[error("{handler}/{series} has {parts} parts (0..{}); asked for part {asked}", parts.saturating_sub(1))]
    NoPart {
        /// The handler.
        handler: String,
        /// The series.
        series: String,
        /// Its parts.
        parts: usize,
        /// The part asked for.
        asked: usize,
    },
}

/// One output column: handler index and value index within its frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Column title (`Handler/series[part]`).
    pub title: String,
    /// Index of the handler.
    pub handler: usize,
    /// Index of the value within the handler's frame.
    pub value: usize,
}

/// Resolves selectors against a header.
pub fn resolve(
    handlers: &[HandlerSpec],
    wanted: &[SeriesSelector],
) -> Result<Vec<Column>, SelectError> {
    let mut cols = Vec::new();
    for w in wanted {
        let h = handlers
            .iter()
            .position(|h| h.name == w.handler)
            .ok_or_else(|| SelectError::NoHandler {
                handler: w.handler.clone(),
                known: handlers.iter().map(|h| h.name.clone()).collect(),
            })?;
        let spec = &handlers[h];
        let s = spec.find(&w.series).ok_or_else(|| SelectError::NoSeries {
            handler: spec.name.clone(),
            series: w.series.clone(),
            known: spec.series.clone(),
        })?;
        let n = spec.parts[s];
        let (a, b) = w.parts.unwrap_or((0, n.saturating_sub(1)));
        if b >= n {
            return Err(SelectError::NoPart {
                handler: spec.name.clone(),
                series: spec.series[s].clone(),
                parts: n,
                asked: b,
            });
        }
        for k in a..=b {
            cols.push(Column {
                title: if n == 1 {
                    format!("{}/{}", spec.name, spec.series[s])
                } else {
                    format!("{}/{}[{k}]", spec.name, spec.series[s])
                },
                handler: h,
                value: spec.offset(s) + k,
            });
        }
    }
    Ok(cols)
}

/// What an export wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportStats {
    /// Rows written.
    pub rows: u64,
    /// Columns per row (x included).
    pub columns: usize,
    /// What the file holds.
    pub info: DataInfo,
}

/// Calls `on_row` with the x value and the chosen columns of every sample of `path`, in
/// order, holding only one round in memory; returns the rows, the file summary and the
/// resolved columns.
pub fn for_each_row(
    path: &Path,
    x: XAxis,
    wanted: &[SeriesSelector],
    mut on_row: impl FnMut(&[Column], f64, &[f64]) -> std::io::Result<()>,
) -> Result<(u64, DataInfo, Vec<Column>), DataError> {
    let fail = |message: String| DataError {
        file: path.to_path_buf(),
        line: None,
        message,
    };
    let mut cols: Vec<Column> = Vec::new();
    let mut problem: Option<SelectError> = None;
    let mut io_error: Option<std::io::Error> = None;
    // Rows of the current round: stamps and one value per column.
    let mut rows: Vec<(FrameMeta, Vec<f64>)> = Vec::new();
    let mut used = 0usize;
    let mut seen: Vec<usize> = Vec::new();
    let mut round = u64::MAX;
    let mut first_realtime: Option<u64> = None;
    let mut written = 0u64;
    let mut flush = |rows: &mut Vec<(FrameMeta, Vec<f64>)>,
                     used: &mut usize,
                     cols: &[Column],
                     first: u64|
     -> std::io::Result<()> {
        for (m, v) in &rows[..*used] {
            on_row(cols, x.value(m, first), v)?;
            written += 1;
        }
        *used = 0;
        Ok(())
    };
    let info = read_file(path, |event| match event {
        DataEvent::Header(handlers) => match resolve(handlers, wanted) {
            Ok(c) => {
                seen = vec![0; handlers.len()];
                cols = c;
            }
            Err(e) => problem = Some(e),
        },
        DataEvent::Frame(f) => {
            if problem.is_some() || io_error.is_some() {
                return;
            }
            if f.round != round {
                let first = first_realtime.unwrap_or(0);
                if let Err(e) = flush(&mut rows, &mut used, &cols, first) {
                    io_error = Some(e);
                }
                round = f.round;
                seen.iter_mut().for_each(|s| *s = 0);
            }
            first_realtime.get_or_insert(f.meta.realtime_ms);
            let k = seen[f.handler];
            seen[f.handler] += 1;
            if k >= used {
                // Reuse row buffers from earlier rounds.
                if used == rows.len() {
                    rows.push((f.meta, vec![f64::NAN; cols.len()]));
                } else {
                    rows[used].0 = f.meta;
                    rows[used].1.fill(f64::NAN);
                }
                used += 1;
            }
            for (c, slot) in cols.iter().zip(rows[k].1.iter_mut()) {
                if c.handler == f.handler {
                    *slot = f.values.get(c.value).copied().unwrap_or(f64::NAN);
                }
            }
        }
    })?;
    if let Some(p) = problem {
        return Err(fail(p.to_string()));
    }
    if io_error.is_none()
        && let Err(e) = flush(&mut rows, &mut used, &cols, first_realtime.unwrap_or(0))
    {
        io_error = Some(e);
    }
    if let Some(e) = io_error {
        return Err(fail(format!("cannot write: {e}")));
    }
    Ok((written, info, cols))
}

/// Writes the chosen columns of `path` to `out`, separated by `sep` (`'\t'` or `','`).
pub fn export(
    path: &Path,
    x: XAxis,
    wanted: &[SeriesSelector],
    sep: char,
    out: &mut dyn Write,
) -> Result<ExportStats, DataError> {
    let mut titled = false;
    let mut line = String::new();
    let (rows, info, cols) = for_each_row(path, x, wanted, |cols, xv, values| {
        if !titled {
            titled = true;
            write_titles(out, x, cols, sep)?;
        }
        line.clear();
        push_number(&mut line, xv);
        for v in values {
            line.push(sep);
            push_number(&mut line, *v);
        }
        line.push('\n');
        out.write_all(line.as_bytes())
    })?;
    if !titled {
        write_titles(out, x, &cols, sep).map_err(|e| DataError {
            file: path.to_path_buf(),
            line: None,
            message: format!("cannot write: {e}"),
        })?;
    }
    Ok(ExportStats {
        rows,
        columns: cols.len(),
        info,
    })
}

fn write_titles(out: &mut dyn Write, x: XAxis, cols: &[Column], sep: char) -> std::io::Result<()> {
    let titles: Vec<&str> = std::iter::once(x.title())
        .chain(cols.iter().map(|c| c.title.as_str()))
        .collect();
    writeln!(out, "{}", titles.join(&sep.to_string()))
}
