//! `proleg data`: inspecting recorded data files (info, export as TSV/CSV).

use std::fmt;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::cli::error::CliError;
use crate::data::export::{SeriesSelector, XAxis, export};
use crate::data::plot::plot;
use crate::data::read::{DataInfo, info};

/// What `proleg data info` found in a data file.
#[derive(Debug, Clone, PartialEq)]
pub struct InfoReport {
    /// The data file.
    pub file: PathBuf,
    /// Its size in bytes, when readable.
    pub size: Option<u64>,
    /// Handlers, series, frames, time span, cut or complete.
    pub info: DataInfo,
}

/// `--series` that names no series.
fn no_series(series: &str) -> CliError {
    CliError::Option {
        option: "--series",
        value: series.to_string(),
        want: "name at least one series, e.g. Robot_Data/y_pos",
    }
}

/// `proleg data info FILE`.
pub fn show_info(file: &Path) -> Result<InfoReport, CliError> {
    Ok(InfoReport {
        file: file.to_path_buf(),
        size: std::fs::metadata(file).ok().map(|m| m.len()),
        info: info(file)?,
    })
}

impl fmt::Display for InfoReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        let i = &self.info;
        writeln!(out, "file      {}", self.file.display())?;
        if let Some(bytes) = self.size {
            writeln!(out, "size      {:.2} MB", bytes as f64 / 1e6)?;
        }
        writeln!(out, "rounds    {}", i.rounds)?;
        match (i.first_simtime_ms, i.last_simtime_ms) {
            (Some(a), Some(b)) => {
                writeln!(out, "simtime   {:.3} s .. {:.3} s", a / 1000.0, b / 1000.0)?
            }
            _ => writeln!(out, "simtime   (no frames)")?,
        }
        if i.cut {
            writeln!(
                out,
                "status    CUT: the file ends before </dataRoot>; complete rounds up to here are readable"
            )?;
        } else {
            writeln!(out, "status    complete")?;
        }
        for w in &i.warnings {
            writeln!(out, "warning   {w}")?;
        }
        for (h, frames) in i.handlers.iter().zip(&i.frames) {
            writeln!(out, "handler   {} ({frames} frames)", h.name)?;
            for (s, p) in h.series.iter().zip(&h.parts) {
                writeln!(out, "  {s} [{p}]")?;
            }
        }
        Ok(())
    }
}

/// `proleg data export FILE --x X --series LIST -o OUT`.
pub fn export_table(file: &Path, x: &str, series: &str, output: &Path) -> Result<String, CliError> {
    let x = XAxis::parse(x)?;
    let wanted = SeriesSelector::parse_list(series)?;
    if wanted.is_empty() {
        return Err(no_series(series));
    }
    let sep = match output.extension().and_then(|e| e.to_str()) {
        Some("csv") => ',',
        _ => '\t',
    };
    let f = File::create(output).map_err(CliError::write(output))?;
    let mut w = BufWriter::new(f);
    let t = Instant::now();
    let stats = export(file, x, &wanted, sep, &mut w)?;
    w.flush().map_err(CliError::write(output))?;
    let mut out = format!(
        "wrote {} rows x {} columns to {} in {:.2} s\n",
        stats.rows,
        stats.columns + 1,
        output.display(),
        t.elapsed().as_secs_f64()
    );
    if stats.info.cut {
        out.push_str("note: the data file is cut; rows end at its last complete round\n");
    }
    for w in &stats.info.warnings {
        out.push_str(&format!("warning: {}: {w}\n", file.display()));
    }
    Ok(out)
}

/// `proleg data plot FILE --x X --series LIST -o OUT.png`.
pub fn plot_png(
    file: &Path,
    x: &str,
    series: &str,
    output: &Path,
    size: (u32, u32),
) -> Result<String, CliError> {
    let x = XAxis::parse(x)?;
    let wanted = SeriesSelector::parse_list(series)?;
    if wanted.is_empty() {
        return Err(no_series(series));
    }
    if size.0 < 200 || size.1 < 150 || size.0 > 10_000 || size.1 > 10_000 {
        return Err(CliError::Option {
            option: "--size",
            value: format!("{}x{}", size.0, size.1),
            want: "give a width of 200..10000 and a height of 150..10000 pixels",
        });
    }
    let t = Instant::now();
    let stats = plot(file, x, &wanted, output, size)?;
    Ok(format!(
        "plotted {} series of {} rows ({} points drawn) to {} ({}x{}) in {:.2} s\n",
        stats.series,
        stats.rows,
        stats.points_drawn,
        output.display(),
        size.0,
        size.1,
        t.elapsed().as_secs_f64()
    ))
}
