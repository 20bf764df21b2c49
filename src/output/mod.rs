//! Output: atomic files and the CSV/JSON encodings of results.
//!
//! Every file is written to a temporary sibling (`.NAME.tmp-PID`) and renamed over the target
//! only when complete, so a failure never leaves a half-written file behind.

pub mod plot;
pub mod tables;

use crate::error::{Error, Result};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file that appears at its path only when [`AtomicFile::commit`] is called; dropped
/// uncommitted, it removes its temporary.
pub struct AtomicFile {
    path: PathBuf,
    tmp: PathBuf,
    w: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Creates the temporary beside `path`.
    pub fn create(path: &Path) -> Result<AtomicFile> {
        let name = path
            .file_name()
            .ok_or_else(|| Error::Io {
                path: path.to_path_buf(),
                source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
            })?
            .to_string_lossy()
            .into_owned();
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
        let tmp_name = format!(".{name}.tmp-{}", std::process::id());
        let tmp = match dir {
            Some(d) => d.join(tmp_name),
            None => PathBuf::from(tmp_name),
        };
        let f = File::create(&tmp).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(AtomicFile {
            path: path.to_path_buf(),
            tmp,
            w: Some(BufWriter::new(f)),
        })
    }

    /// The target path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes, syncs and renames the temporary onto the target.
    pub fn commit(mut self) -> Result<()> {
        let w = self.w.take().expect("not yet committed");
        let io = |source| Error::Io {
            path: self.path.clone(),
            source,
        };
        let f = w.into_inner().map_err(|e| io(e.into_error()))?;
        f.sync_all().map_err(io)?;
        drop(f);
        std::fs::rename(&self.tmp, &self.path).map_err(io)?;
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.w.as_mut().expect("not yet committed").write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.w.as_mut().expect("not yet committed").flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.w.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    f.commit()
}

/// Output format chosen from a file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated values with a header row.
    Csv,
    /// JSON.
    Json,
}

impl Format {
    /// `.csv` or `.json` (case-insensitive); anything else is an error naming the path.
    pub fn from_path(path: &Path) -> Result<Format> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("csv") => Ok(Format::Csv),
            Some("json") => Ok(Format::Json),
            _ => Err(Error::InvalidInput {
                what: "output file",
                text: path.display().to_string(),
                reason: "the extension must be .csv or .json".into(),
            }),
        }
    }
}

/// A row type of a table: a `Serialize` struct with scalar fields, and its column names (the
/// field names, in order; a test checks they match what serde writes), so that a CSV with no
/// rows still has its header.
pub trait Record: serde::Serialize {
    /// Column names, in field order.
    const COLUMNS: &'static [&'static str];
}

/// Streams records as CSV with a header row, or as JSON `{"meta": …, "rows": [{…}, …]}`, row by
/// row, so a late failure loses nothing already computed and memory stays flat however long the
/// output.
pub struct RecordWriter<W: Write, T: Record> {
    inner: Inner<W>,
    rows: u64,
    _t: std::marker::PhantomData<fn(&T)>,
}

enum Inner<W: Write> {
    Csv(Box<csv::Writer<W>>),
    Json(W),
}

fn csv_io(e: csv::Error) -> std::io::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(io) => io,
        other => std::io::Error::other(format!("{other:?}")),
    }
}

impl<W: Write, T: Record> RecordWriter<W, T> {
    /// Starts the output (the CSV header is written at once). `meta` (the parameters and options
    /// that produced the rows) goes into JSON output only.
    pub fn new(mut w: W, format: Format, meta: &serde_json::Value) -> std::io::Result<Self> {
        let inner = match format {
            Format::Csv => {
                let mut c = csv::WriterBuilder::new().has_headers(false).from_writer(w);
                c.write_record(T::COLUMNS).map_err(csv_io)?;
                Inner::Csv(Box::new(c))
            }
            Format::Json => {
                w.write_all(b"{\"meta\":")?;
                serde_json::to_writer(&mut w, meta)?;
                w.write_all(b",\"rows\":[")?;
                Inner::Json(w)
            }
        };
        Ok(RecordWriter {
            inner,
            rows: 0,
            _t: std::marker::PhantomData,
        })
    }

    /// Appends one record.
    pub fn row(&mut self, record: &T) -> std::io::Result<()> {
        match &mut self.inner {
            Inner::Csv(c) => c.serialize(record).map_err(csv_io)?,
            Inner::Json(w) => {
                if self.rows > 0 {
                    w.write_all(b",\n")?;
                }
                serde_json::to_writer(&mut *w, record)?;
            }
        }
        self.rows += 1;
        Ok(())
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Finishes the output and returns the writer.
    pub fn finish(self) -> std::io::Result<W> {
        match self.inner {
            Inner::Csv(c) => c.into_inner().map_err(|e| e.into_error()),
            Inner::Json(mut w) => {
                w.write_all(b"]}\n")?;
                w.flush()?;
                Ok(w)
            }
        }
    }
}

/// Implements [`Record`] for a type with the given column names.
#[macro_export]
macro_rules! record {
    ($t:ty: $($c:literal),+ $(,)?) => {
        impl $crate::output::Record for $t {
            const COLUMNS: &'static [&'static str] = &[$($c),+];
        }
    };
}

record!(crate::fast::CurvePoint: "a", "x", "slope", "gprime", "re1", "im1", "re2", "im2", "type", "branch");
record!(crate::fast::FoldRow: "gamma", "a_lower", "x_lower", "a_upper", "x_upper");
record!(crate::burst::Burst: "onset", "end", "a_onset", "duration", "t_peak", "a_peak", "peak_abs_xdot", "spikes", "extrema", "ringing_swing", "overshoot", "overshoot_lobes", "jumps", "complete");
record!(crate::sweep::SweepRow: "index", "alpha", "gamma", "eps", "mu", "delta", "omega", "mode", "mechanism", "bursts_per_period", "spikes_per_burst", "burst_amplitude", "peak_abs_xdot", "quiescent_duration", "quiescent_fraction", "max_tracking_error", "max_slope", "error");
