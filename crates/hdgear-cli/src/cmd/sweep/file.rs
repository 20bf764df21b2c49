//! The row files of a sweep: FILE.partial while a sweep runs, and the shard files of a sharded
//! sweep. Both are CSV with one extra first line, `# hdgear-sweep {settings}`, holding everything
//! that changes a row ([`hdgear::sweep::Settings`]: the grid, every detection option and
//! tolerance, the hdgear version, the shard), so that resuming and merging can refuse rows of
//! another sweep. CSV because it is lossless here (JSON writes NaN and ∞ both as null), can be
//! appended to row by row, and reads back bit for bit.

use anyhow::{Context, Result, bail};
use hdgear::params::Params;
use hdgear::sweep::{Settings, Sweep, SweepRow};
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{BufRead, Read, Write};
use std::path::{Path, PathBuf};

const HEADER_TAG: &str = "# hdgear-sweep ";

/// `out` with `suffix` appended to its file name.
pub fn sibling(out: &Path, suffix: &str) -> PathBuf {
    let mut name = out.file_name().unwrap_or_default().to_os_string();
    name.push(suffix);
    out.with_file_name(name)
}

/// A row file being written: the settings line and the column names first, then rows one at a
/// time; nothing is at its path until [`RowFile::commit`] (a temporary until then, removed on
/// an error, a drop or a signal).
pub struct RowFile(csv::Writer<hdgear::output::AtomicFile>);

impl RowFile {
    /// Starts the row file of `settings` at `path`.
    pub fn create<S: Sweep>(path: &Path, settings: &Settings<S>) -> Result<RowFile> {
        let mut f = hdgear::output::AtomicFile::create(path)?;
        writeln!(f, "{HEADER_TAG}{}", serde_json::to_string(settings)?)?;
        // the header by hand: csv cannot name the columns of nested structs itself
        let mut w = csv::WriterBuilder::new().has_headers(false).from_writer(f);
        w.write_record(hdgear::sweep::columns::<S, SweepRow>(&settings.grid.axes))?;
        Ok(RowFile(w))
    }

    /// Adds a row.
    pub fn row(&mut self, r: &(impl serde::Serialize + ?Sized)) -> Result<()> {
        Ok(self.0.serialize(r)?)
    }

    /// Puts the file in place.
    pub fn commit(self) -> Result<()> {
        let f = self
            .0
            .into_inner()
            .map_err(|e| anyhow::Error::from(e.into_error()))?;
        Ok(f.commit()?)
    }
}

/// Writes a row file afresh, atomically: the settings line, the column names and `rows`.
pub fn write<S: Sweep>(
    path: &Path,
    settings: &Settings<S>,
    rows: &[SweepRow<S::Point>],
) -> Result<()> {
    let mut f = RowFile::create(path, settings)?;
    for r in rows {
        f.row(r)?;
    }
    f.commit()
}

/// Opens a row file for appending rows.
pub fn append(path: &Path) -> Result<csv::Writer<File>> {
    let file = OpenOptions::new()
        .append(true)
        .open(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(file))
}

/// The rows of a row file, in file order, each a parse result.
pub type Rows<P = Params> = Box<dyn Iterator<Item = Result<SweepRow<P>>>>;

/// Opens a study sweep's row file: its settings, and its rows as they are read.
pub fn open(path: &Path) -> Result<(Settings, Rows)> {
    let json = settings_line(path)?;
    let settings: Settings = serde_json::from_value(json)
        .with_context(|| format!("{}: unreadable settings line", path.display()))?;
    let rows = rows::<Params>(path, &settings.grid.axes)?;
    Ok((settings, rows))
}

/// The settings line of a row file, as JSON.
fn settings_line(path: &Path) -> Result<serde_json::Value> {
    let file = hdgear::output::open_input(path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let mut first = String::new();
    std::io::BufReader::new(&file)
        .take(1 << 20)
        .read_line(&mut first)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let Some(json) = first.trim_end().strip_prefix(HEADER_TAG) else {
        bail!(
            "{} is not a sweep's row file: it has no '{}' settings line (a finished sweep's \
             output, or written by an older hdgear?)",
            path.display(),
            HEADER_TAG.trim()
        );
    };
    serde_json::from_str(json)
        .with_context(|| format!("{}: unreadable settings line", path.display()))
}

/// The rows of the row file at `path` of a grid over `axes`, as they are read.
fn rows<S: Sweep>(path: &Path, axes: &[hdgear::sweep::Axis<S::Param>]) -> Result<Rows<S::Point>>
where
    S::Param: 'static,
    S::Point: 'static,
{
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    if rdr
        .headers()?
        .iter()
        .ne(hdgear::sweep::columns::<S, SweepRow>(axes))
    {
        bail!(
            "{} has other columns than this hdgear writes: delete it to start over",
            path.display()
        );
    }
    let name = path.display().to_string();
    let axes = axes.to_vec();
    // by position: the row's nested parameters and statistics are flat columns
    let rows = rdr.into_records().enumerate().map(move |(n, rec)| {
        rec.and_then(|r| S::read_row(&r, &axes))
            .with_context(|| format!("{name}: row {} is unreadable", n + 1))
    });
    Ok(Box::new(rows))
}

/// Rows already in a partial file, checked against the settings `want`: a resume. A torn last
/// line (a write cut by a kill) ends the rows kept; identical duplicates are dropped; conflicting
/// ones are refused.
pub fn read_partial<S: Sweep>(path: &Path, want: &Settings<S>) -> Result<Vec<SweepRow<S::Point>>>
where
    S::Param: 'static,
    S::Point: 'static,
{
    let have = settings_line(path)?;
    if let Some(d) = hdgear::sweep::first_difference(&have, &serde_json::to_value(want)?) {
        bail!(
            "--resume: {} was computed with other settings ({} was {} there and is {} now): \
             rerun with the same settings, or delete it to start over",
            path.display(),
            d.key,
            d.here,
            d.there
        );
    }
    let mut kept: BTreeMap<usize, SweepRow<S::Point>> = BTreeMap::new();
    for row in rows::<S>(path, &want.grid.axes)?.map_while(Result::ok) {
        want.check_row(&row)
            .with_context(|| format!("{} belongs to another sweep", path.display()))?;
        if let Some(prev) = kept.get(&row.index) {
            let ser = |r: &SweepRow<S::Point>| serde_json::to_string(r).unwrap_or_default();
            if ser(prev) != ser(&row) {
                bail!(
                    "{} holds two different rows for grid point {}: it was written by two runs \
                     at once; delete it to start over",
                    path.display(),
                    row.index
                );
            }
            continue;
        }
        kept.insert(row.index, row);
    }
    Ok(kept.into_values().collect())
}
