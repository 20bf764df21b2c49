//! `hdgear sweep`: grid → parallel run with a progress bar → rows streamed into FILE.partial →
//! FILE in grid order at the end. `--resume` continues from FILE.partial.
//!
//! FILE.partial starts with a comment line `# hdgear-sweep {settings}` holding everything that
//! changes a row (the grid, every detection option and tolerance, the hdgear version), so a
//! resume with other settings is refused, naming the first difference. A lock on FILE.lock
//! (holding the owner's pid) keeps a second sweep off the same FILE while one runs.

use crate::cli::SweepArgs;
use crate::sink::{warn, write_records};
use anyhow::{Context, Result, anyhow, bail};
use hdgear::output::Format;
use hdgear::sweep::{Axis, Grid, SweepRow};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::{BTreeMap, HashSet};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, IsTerminal, Read, Seek, Write};
use std::path::{Path, PathBuf};

const HEADER_TAG: &str = "# hdgear-sweep ";

fn sibling(out: &Path, suffix: &str) -> PathBuf {
    let mut name = out.file_name().unwrap_or_default().to_os_string();
    name.push(suffix);
    out.with_file_name(name)
}

/// The advisory lock on FILE.lock, released (and the file removed) on drop.
struct Lock {
    path: PathBuf,
    _file: File,
}

impl Lock {
    fn acquire(out: &Path) -> Result<Lock> {
        let path = sibling(out, ".lock");
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        if file.try_lock().is_err() {
            let mut pid = String::new();
            let _ = file.read_to_string(&mut pid);
            bail!(
                "another hdgear sweep is writing {} (pid {}): wait for it, or stop it first",
                out.display(),
                pid.trim()
            );
        }
        file.set_len(0)?;
        file.rewind()?;
        write!(file, "{}", std::process::id())?;
        hdgear::output::track_temporary(&path);
        Ok(Lock { path, _file: file })
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
        hdgear::output::untrack_temporary(&self.path);
    }
}

/// A progress bar on a terminal (hidden otherwise) at `done` of `len` points.
fn progress_bar(len: usize, done: usize) -> Result<ProgressBar> {
    let bar = if std::io::stderr().is_terminal() {
        let b = ProgressBar::new(len as u64);
        b.set_style(
            ProgressStyle::with_template(
                "{bar:40} {pos}/{len} points  {elapsed} elapsed, eta {eta}",
            )
            .map_err(|e| anyhow!("progress template: {e}"))?,
        );
        b
    } else {
        ProgressBar::hidden()
    };
    bar.set_position(done as u64);
    Ok(bar)
}

/// Everything that changes a row ([`hdgear::sweep::Settings`]) as JSON.
fn settings(grid: &Grid, opts: &hdgear::burst::BurstOptions) -> Result<serde_json::Value> {
    Ok(serde_json::to_value(hdgear::sweep::Settings::new(
        grid, opts,
    ))?)
}

fn flatten(prefix: &str, v: &serde_json::Value, out: &mut BTreeMap<String, String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&key, x, out);
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                flatten(&format!("{prefix}[{i}]"), x, out);
            }
        }
        other => {
            out.insert(prefix.to_string(), other.to_string());
        }
    }
}

/// The first setting in which `old` and `new` differ, as a readable sentence.
fn first_difference(old: &serde_json::Value, new: &serde_json::Value) -> Option<String> {
    let (mut a, mut b) = (BTreeMap::new(), BTreeMap::new());
    flatten("", old, &mut a);
    flatten("", new, &mut b);
    let keys: std::collections::BTreeSet<&String> = a.keys().chain(b.keys()).collect();
    keys.into_iter().find_map(|k| {
        let (x, y) = (a.get(k), b.get(k));
        (x != y).then(|| {
            format!(
                "{k} was {} there and is {} now",
                x.map_or("absent", |s| s.as_str()),
                y.map_or("absent", |s| s.as_str())
            )
        })
    })
}

/// Rows already in the partial file, checked against the settings and the grid. A torn last
/// line (a write cut by a kill) is dropped; identical duplicates are dropped; conflicting ones
/// are refused.
fn read_partial(path: &Path, grid: &Grid, want: &serde_json::Value) -> Result<Vec<SweepRow>> {
    let file = File::open(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut first = String::new();
    std::io::BufReader::new(&file)
        .take(1 << 20)
        .read_line(&mut first)?;
    let Some(json) = first.trim_end().strip_prefix(HEADER_TAG) else {
        bail!(
            "{} has no settings line (written by an older hdgear?): delete it to start over",
            path.display()
        );
    };
    let have: serde_json::Value = serde_json::from_str(json)
        .with_context(|| format!("{}: unreadable settings line", path.display()))?;
    if let Some(d) = first_difference(&have, want) {
        bail!(
            "--resume: {} was computed with other settings ({d}): rerun with the same settings, \
             or delete it to start over",
            path.display()
        );
    }
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let columns = <SweepRow as hdgear::output::Record>::COLUMNS;
    if rdr.headers()?.iter().ne(columns.iter().copied()) {
        bail!(
            "{} has other columns than this hdgear writes: delete it to start over",
            path.display()
        );
    }
    let mut rows: BTreeMap<usize, SweepRow> = BTreeMap::new();
    // by position: the row's nested parameters and statistics are flat columns
    for rec in rdr.records() {
        let Ok(row) = rec.and_then(|r| r.deserialize::<SweepRow>(None)) else {
            break;
        };
        if row.index >= grid.len() {
            bail!(
                "{} belongs to another sweep: row index {} is outside this grid of {} points",
                path.display(),
                row.index,
                grid.len()
            );
        }
        let p = grid.point(row.index);
        if p != row.params {
            bail!(
                "{} belongs to another sweep: row {} has parameters {:?}, this grid has {:?} \
                 there (delete it, or run without --resume)",
                path.display(),
                row.index,
                row.params,
                p
            );
        }
        if let Some(prev) = rows.get(&row.index) {
            let ser = |r: &SweepRow| serde_json::to_string(r).unwrap_or_default();
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
        rows.insert(row.index, row);
    }
    Ok(rows.into_values().collect())
}

/// Writes the partial file afresh (atomically: settings line and the rows kept) and opens it
/// for appending.
fn start_partial(
    path: &Path,
    settings: &serde_json::Value,
    rows: &[SweepRow],
) -> Result<csv::Writer<File>> {
    let mut f = hdgear::output::AtomicFile::create(path)?;
    writeln!(f, "{HEADER_TAG}{settings}")?;
    {
        // the header by hand: csv cannot name the columns of nested structs itself
        let mut w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(&mut f);
        w.write_record(<SweepRow as hdgear::output::Record>::COLUMNS)?;
        for r in rows {
            w.serialize(r)?;
        }
        w.flush()?;
    }
    f.commit()?;
    let file = OpenOptions::new()
        .append(true)
        .open(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(file))
}

/// Runs the sweep command.
pub fn run(a: SweepArgs) -> Result<()> {
    let (base, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    let format = Format::from_path(&a.out).context("--out")?;
    hdgear::output::check_output_path(&a.out)?;
    let axes = a
        .axes
        .iter()
        .map(|s| Axis::parse(s))
        .collect::<hdgear::Result<Vec<_>>>()
        .context("--param")?;
    let grid = Grid::new(base, axes)?;
    if a.threads == Some(0) {
        bail!("invalid option --threads = 0: must be ≥ 1");
    }
    warn(&warnings);
    let _lock = Lock::acquire(&a.out)?;
    let partial = sibling(&a.out, ".partial");
    let want = settings(&grid, &opts)?;
    let mut rows: Vec<SweepRow> = Vec::new();
    if a.resume && partial.exists() {
        rows = read_partial(&partial, &grid, &want)?;
    } else if partial.exists() {
        bail!(
            "{} exists (an interrupted sweep): pass --resume to continue it, or delete it",
            partial.display()
        );
    }
    let mut w = start_partial(&partial, &want, &rows)?;
    crate::signals::set_hint(format!(
        "the finished rows are kept in {}: rerun the same command with --resume",
        partial.display()
    ));
    let done: HashSet<usize> = rows.iter().map(|r| r.index).collect();

    let bar = progress_bar(grid.len(), done.len())?;
    let mut io_err: Option<anyhow::Error> = None;
    hdgear::sweep::run(&grid, &opts, &done, a.threads.unwrap_or(0), |row| {
        if io_err.is_none() {
            let res = w
                .serialize(&row)
                .map_err(anyhow::Error::from)
                .and_then(|_| w.flush().map_err(anyhow::Error::from));
            if let Err(e) = res {
                io_err = Some(e.context(format!("writing {}", partial.display())));
            }
        }
        rows.push(row);
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    if let Some(e) = io_err {
        return Err(e);
    }
    drop(w);
    rows.sort_by_key(|r| r.index);
    let failed = rows.iter().filter(|r| !r.error.is_empty()).count();
    let n = rows.len();
    let meta = hdgear::sweep::Settings::new(&grid, &opts);
    match format {
        Format::Csv | Format::Json => write_records(Some(&a.out), &meta, rows)?,
    }
    std::fs::remove_file(&partial).ok();
    eprintln!("wrote {}: {n} rows, {failed} failed", a.out.display());
    if n > 0 && failed == n {
        return Err(crate::sink::ComputationFailed(
            "every grid point failed (their rows carry the error)".into(),
        )
        .into());
    }
    Ok(())
}
