//! `hdgear merge SHARD…`: the shard files of a sweep → the file one machine would have written,
//! byte for byte. The files' settings are checked before any row is read (same sweep, every shard
//! once); the rows are then streamed in grid order (row i is the next row of shard i mod N), each
//! checked as it passes, into an atomic output: a failed merge leaves nothing behind.

use crate::cli::MergeArgs;
use crate::cmd::sweep::file;
use anyhow::{Context, Result, bail};
use hdgear::output::{Format, RecordWriter};
use std::path::{Path, PathBuf};

/// `DIR/NAME.csv` for `DIR/NAME.shard-K-of-N.csv`.
fn default_out(shard: &Path) -> Result<PathBuf> {
    let name = shard.file_name().unwrap_or_default().to_string_lossy();
    let stem = name.strip_suffix(".csv").and_then(|s| {
        let (stem, tail) = s.rsplit_once(".shard-")?;
        let (k, n) = tail.split_once("-of-")?;
        let whole = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
        (whole(k) && whole(n)).then_some(stem)
    });
    match stem {
        Some(stem) => Ok(shard.with_file_name(format!("{stem}.csv"))),
        None => bail!(
            "cannot tell the merged file's name from '{}' (not NAME.shard-K-of-N.csv): give --out",
            shard.display()
        ),
    }
}

/// Runs the merge command.
pub fn run(a: MergeArgs) -> Result<()> {
    let out = match a.out {
        Some(o) => o,
        None => default_out(&a.shards[0])?,
    };
    let format = Format::from_path(&out).context("--out")?;
    hdgear::output::check_output_path(&out)?;
    // (an --out that does not exist yet cannot be an input)
    let target = std::fs::canonicalize(&out).ok();
    let same = |p: &Path| target.is_some() && std::fs::canonicalize(p).ok() == target;
    if let Some(shard) = a.shards.iter().find(|p| same(p)) {
        bail!(
            "invalid option --out '{}': it is the input shard {}; write the merged file elsewhere",
            out.display(),
            shard.display()
        );
    }
    let mut headers = Vec::with_capacity(a.shards.len());
    let mut readers = Vec::with_capacity(a.shards.len());
    for path in &a.shards {
        let (settings, rows) = file::open(path)?;
        headers.push((path.display().to_string(), settings));
        readers.push(rows);
    }
    let plan = hdgear::sweep::plan(headers)?;
    let (sink, _) = crate::sink::Sink::open(Some(&out))?;
    let mut w = RecordWriter::new(sink, format, plan.settings())?;
    let mut failed = 0;
    let n = plan.merge(readers, |row| {
        failed += usize::from(!row.error.is_empty());
        w.row(&row)
            .with_context(|| format!("writing {}", out.display()))
    })?;
    w.finish()
        .with_context(|| format!("writing {}", out.display()))?
        .commit()?;
    eprintln!(
        "wrote {}: {n} rows from {} shards, {failed} failed",
        out.display(),
        a.shards.len()
    );
    crate::cmd::sweep::all_failed(n, failed)
}
