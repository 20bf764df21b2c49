//! Output: atomic files and the CSV/JSON encodings of results.
//!
//! Every file is written to a temporary sibling (`.NAME.tmp-PID`) and renamed over the target
//! only when complete, so a failure never leaves a half-written file behind. Every temporary is
//! also listed in a process-wide registry, so that a program interrupted by a signal can remove
//! them all ([`remove_temporaries`]) before it exits.

#[cfg(feature = "parquet")]
pub mod parquet;
pub mod plot;
pub mod zip;

pub use hdgear_record::Record;

use crate::error::{Error, Result};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// A number as the report and the figures' captions show it: four decimals, or three
/// significant digits in e-notation.
pub(crate) fn num(v: f64) -> String {
    if v.is_infinite() {
        "∞".into()
    } else if v.is_nan() {
        "–".into()
    } else if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e5) {
        format!("{v:.3e}")
    } else {
        format!("{}", (v * 1e4).round() / 1e4)
    }
}

/// The temporaries of this process that are not yet committed or removed, and whether the
/// process is shutting down (then no new temporary may be created).
static TEMPORARIES: Mutex<(Vec<PathBuf>, bool)> = Mutex::new((Vec::new(), false));

fn registry() -> std::sync::MutexGuard<'static, (Vec<PathBuf>, bool)> {
    // a panic while the lock was held cannot leave the list inconsistent: use it anyway
    TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner())
}

fn unregister(tmp: &Path) {
    registry().0.retain(|t| t != tmp);
}

/// Lists a file this process created and must not leave behind if it is interrupted (a lock
/// file, say); [`untrack_temporary`] takes it off again.
pub fn track_temporary(path: &Path) {
    registry().0.push(path.to_path_buf());
}

/// Takes a file off the list of [`track_temporary`].
pub fn untrack_temporary(path: &Path) {
    unregister(path);
}

/// Removes every uncommitted temporary of this process and refuses new ones from then on:
/// for a signal handler that is about to end the process. Returns how many were removed.
pub fn remove_temporaries() -> usize {
    let mut reg = registry();
    reg.1 = true;
    let n = reg.0.len();
    for t in reg.0.drain(..) {
        let _ = std::fs::remove_file(t);
    }
    n
}

/// Whether [`remove_temporaries`] has run: the process is being ended by a signal handler, and
/// an output refused since then is its doing, not the run's own failure.
pub fn interrupting() -> bool {
    registry().1
}

/// Checks that `path` can be an output file before any work is done: not an existing
/// directory, not ending in a separator, and its directory exists.
pub fn check_output_path(path: &Path) -> Result<()> {
    let bad = |reason: &str| {
        Err(Error::InvalidInput {
            what: "output file",
            text: path.display().to_string(),
            reason: reason.into(),
        })
    };
    let text = path.as_os_str().to_string_lossy();
    if text.is_empty() {
        return bad("the path is empty");
    }
    if text.ends_with('/')
        || text.ends_with(std::path::MAIN_SEPARATOR)
        || path.file_name().is_none()
    {
        return bad("names a directory, not a file");
    }
    if path.is_dir() {
        return bad("is an existing directory");
    }
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(d) = dir
        && !d.is_dir()
    {
        return bad("its directory does not exist");
    }
    Ok(())
}

/// Opens an input file for reading, refusing anything but a regular file (or a link to one)
/// before opening it: a FIFO would block the open until some writer appears, a device could be
/// endless. The error is the system's, or "not a regular file".
pub fn open_input(path: &Path) -> std::io::Result<std::fs::File> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        let kind = if meta.is_dir() {
            "a directory"
        } else {
            "not a regular file (a FIFO, socket or device)"
        };
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("is {kind}"),
        ));
    }
    std::fs::File::open(path)
}

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
        check_output_path(path)?;
        let mut reg = registry();
        if reg.1 {
            return Err(Error::Io {
                path: path.to_path_buf(),
                source: std::io::Error::new(
                    std::io::ErrorKind::Interrupted,
                    "the program is being interrupted",
                ),
            });
        }
        let f = File::create(&tmp).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        reg.0.push(tmp.clone());
        drop(reg);
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

    /// Flushes, syncs and renames the temporary onto the target. On any failure the temporary
    /// is removed.
    pub fn commit(mut self) -> Result<()> {
        let Some(w) = self.w.take() else {
            return Ok(());
        };
        let io = |source| Error::Io {
            path: self.path.clone(),
            source,
        };
        let done = w
            .into_inner()
            .map_err(|e| io(e.into_error()))
            .and_then(|f| f.sync_all().map_err(io))
            .and_then(|()| std::fs::rename(&self.tmp, &self.path).map_err(io));
        if done.is_err() {
            let _ = std::fs::remove_file(&self.tmp);
        }
        unregister(&self.tmp);
        done
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self.w.as_mut() {
            Some(w) => w.write(buf),
            None => Err(std::io::Error::other("write after commit")),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match self.w.as_mut() {
            Some(w) => w.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.w.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
            unregister(&self.tmp);
        }
    }
}

/// Reads an f64 that JSON may hold as `null` (serde_json writes NaN and ±∞ so) back as NaN;
/// for `#[serde(deserialize_with = …)]` on fields that are NaN when undefined.
pub fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(<Option<f64> as serde::Deserialize>::deserialize(d)?.unwrap_or(f64::NAN))
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
#[non_exhaustive]
pub enum Format {
    /// Comma-separated values with a header row.
    Csv,
    /// JSON.
    Json,
    /// Apache Parquet (columnar; with the cargo feature `parquet`, on by default).
    Parquet,
}

impl Format {
    /// `.csv`, `.json` or `.parquet` (case-insensitive); anything else is an error naming the
    /// path, as is `.parquet` in a build without the `parquet` feature.
    pub fn from_path(path: &Path) -> Result<Format> {
        let bad = |reason: &str| {
            Err(Error::InvalidInput {
                what: "output file",
                text: path.display().to_string(),
                reason: reason.into(),
            })
        };
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("csv") => Ok(Format::Csv),
            Some("json") => Ok(Format::Json),
            Some("parquet") if cfg!(feature = "parquet") => Ok(Format::Parquet),
            Some("parquet") => bad("this hdgear was built without Parquet (cargo feature parquet)"),
            _ => bad("the extension must be .csv, .json or .parquet"),
        }
    }
}

/// A row type of a table: a `Serialize` struct with scalar fields, and its column names, so that
/// a CSV with no rows still has its header. `#[derive(Record)]` writes them from the fields serde
/// writes (a nested record's columns in its place, `#[record(nested)]`); a test holds them to
/// serde's header.
///
/// ```
/// use hdgear::output::Record;
/// #[derive(serde::Serialize, Record)]
/// struct Row {
///     t: f64,
///     #[serde(rename = "xdot")]
///     v: f64,
///     #[record(nested)]
///     params: hdgear::Params,
/// }
/// assert_eq!(Row::COLUMNS, ["t", "xdot", "alpha", "gamma", "eps", "mu", "delta", "omega"]);
/// ```
pub trait Record: serde::Serialize {
    /// Column names, in field order.
    const COLUMNS: &'static [&'static str];
}

/// Streams records as CSV with a header row, as JSON `{"meta": …, "rows": [{…}, …]}`, row by
/// row, or as Parquet a row group at a time ([`parquet`]), so memory stays flat however long the
/// output.
pub struct RecordWriter<W: Write + Send, T: serde::Serialize> {
    inner: Inner<W>,
    rows: u64,
    _t: std::marker::PhantomData<fn(&T)>,
}

enum Inner<W: Write + Send> {
    Csv(Box<csv::Writer<W>>),
    Json(W),
    #[cfg(feature = "parquet")]
    Parquet(Box<parquet::ParquetWriter<W>>),
}

fn csv_io(e: csv::Error) -> std::io::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(io) => io,
        other => std::io::Error::other(format!("{other:?}")),
    }
}

impl<W: Write + Send, T: Record> RecordWriter<W, T> {
    /// Starts the output (the CSV header is written at once). `meta` (the parameters and options
    /// that produced the rows) goes into JSON and Parquet output only.
    pub fn new(
        w: W,
        format: Format,
        meta: &(impl serde::Serialize + ?Sized),
    ) -> std::io::Result<Self> {
        Self::with_columns(w, format, meta, T::COLUMNS.to_vec())
    }
}

impl<W: Write + Send, T: serde::Serialize> RecordWriter<W, T> {
    /// As [`RecordWriter::new`], for a row type whose columns are known only at run time (a
    /// trajectory with one column per state of its model): `columns` names the fields `T`
    /// writes, in order.
    pub fn with_columns(
        mut w: W,
        format: Format,
        meta: &(impl serde::Serialize + ?Sized),
        columns: Vec<&'static str>,
    ) -> std::io::Result<Self> {
        let inner = match format {
            Format::Csv => {
                let mut c = csv::WriterBuilder::new().has_headers(false).from_writer(w);
                c.write_record(&columns).map_err(csv_io)?;
                Inner::Csv(Box::new(c))
            }
            Format::Json => {
                w.write_all(b"{\"meta\":")?;
                serde_json::to_writer(&mut w, meta)?;
                w.write_all(b",\"rows\":[")?;
                Inner::Json(w)
            }
            #[cfg(feature = "parquet")]
            Format::Parquet => Inner::Parquet(Box::new(parquet::ParquetWriter::new(
                w,
                columns,
                serde_json::to_string(meta)?,
            ))),
            #[cfg(not(feature = "parquet"))]
            Format::Parquet => {
                return Err(std::io::Error::other(
                    "this hdgear was built without Parquet (cargo feature parquet)",
                ));
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
            #[cfg(feature = "parquet")]
            Inner::Parquet(p) => p.row(record)?,
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
            #[cfg(feature = "parquet")]
            Inner::Parquet(p) => p.finish(),
        }
    }
}

/// The column names of `parts`, in order, as one array of `N` names (`N` their total count,
/// [`column_count`]): how `#[derive(Record)]` splices its fields and nested records into a row's columns at compile
/// time.
pub const fn join_columns<const N: usize>(parts: &[&[&'static str]]) -> [&'static str; N] {
    let mut out = [""; N];
    let (mut k, mut p) = (0, 0);
    while p < parts.len() {
        let mut i = 0;
        while i < parts[p].len() {
            out[k] = parts[p][i];
            (k, i) = (k + 1, i + 1);
        }
        p += 1;
    }
    assert!(k == N, "N must be the parts' total count");
    out
}

/// The total count of the column names in `parts`.
pub const fn column_count(parts: &[&[&str]]) -> usize {
    let (mut n, mut p) = (0, 0);
    while p < parts.len() {
        n += parts[p].len();
        p += 1;
    }
    n
}
