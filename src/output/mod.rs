//! Output: atomic files and the CSV/JSON encodings of results.
//!
//! Every file is written to a temporary sibling (`.NAME.tmp-PID`) and renamed over the target
//! only when complete, so a failure never leaves a half-written file behind.

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

/// Streams a table of f64 columns as CSV or as JSON (an object of column arrays, plus a
/// `meta` object), row by row.
pub struct TableWriter<W: Write> {
    w: W,
    format: Format,
    columns: Vec<&'static str>,
    rows: u64,
    json_cols: Vec<Vec<f64>>,
    meta: serde_json::Value,
}

impl<W: Write> TableWriter<W> {
    /// Starts a table with the given columns. `meta` is written into JSON output only.
    pub fn new(
        mut w: W,
        format: Format,
        columns: &[&'static str],
        meta: serde_json::Value,
    ) -> std::io::Result<Self> {
        if format == Format::Csv {
            writeln!(w, "{}", columns.join(","))?;
        }
        Ok(TableWriter {
            w,
            format,
            columns: columns.to_vec(),
            rows: 0,
            json_cols: vec![
                Vec::new();
                if format == Format::Json {
                    columns.len()
                } else {
                    0
                }
            ],
            meta,
        })
    }

    /// Appends one row (its length must equal the number of columns).
    pub fn row(&mut self, values: &[f64]) -> std::io::Result<()> {
        debug_assert_eq!(values.len(), self.columns.len());
        self.rows += 1;
        match self.format {
            Format::Csv => {
                let mut first = true;
                for v in values {
                    if !first {
                        self.w.write_all(b",")?;
                    }
                    first = false;
                    write!(self.w, "{v}")?;
                }
                self.w.write_all(b"\n")
            }
            Format::Json => {
                for (c, v) in self.json_cols.iter_mut().zip(values) {
                    c.push(*v);
                }
                Ok(())
            }
        }
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Finishes the table and returns the writer.
    pub fn finish(mut self) -> std::io::Result<W> {
        if self.format == Format::Json {
            let mut obj = serde_json::Map::new();
            obj.insert("meta".into(), self.meta.take());
            obj.insert("columns".into(), serde_json::json!(self.columns));
            for (name, col) in self.columns.iter().zip(&self.json_cols) {
                obj.insert((*name).into(), serde_json::json!(col));
            }
            serde_json::to_writer(&mut self.w, &obj)?;
            self.w.write_all(b"\n")?;
        }
        self.w.flush()?;
        Ok(self.w)
    }
}
