//! `hdgear sweep`: grid → parallel run with a progress bar → rows streamed into FILE.partial →
//! FILE in grid order at the end. `--resume` continues from FILE.partial.

use crate::cli::SweepArgs;
use crate::commands::{warn, write_records};
use anyhow::{Context, Result, bail};
use hdgear::output::Format;
use hdgear::sweep::{Axis, Grid, SweepRow};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::HashSet;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

fn partial_path(out: &Path) -> PathBuf {
    let mut name = out.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    out.with_file_name(name)
}

/// Rows already in the partial file, checked against the grid. A torn last line (a write cut by
/// a kill) is dropped.
fn read_partial(path: &Path, grid: &Grid) -> Result<Vec<SweepRow>> {
    let mut rdr =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut rows = Vec::new();
    for rec in rdr.deserialize::<SweepRow>() {
        let Ok(row) = rec else { break };
        if row.index >= grid.len() {
            bail!(
                "{} belongs to another sweep: row index {} is outside this grid of {} points",
                path.display(),
                row.index,
                grid.len()
            );
        }
        let p = grid.point(row.index);
        let same = [p.alpha, p.gamma, p.eps, p.mu, p.delta, p.omega]
            == [row.alpha, row.gamma, row.eps, row.mu, row.delta, row.omega];
        if !same {
            bail!(
                "{} belongs to another sweep: row {} has parameters {:?}, this grid has {:?} \
                 there (delete it, or run without --resume)",
                path.display(),
                row.index,
                [row.alpha, row.gamma, row.eps, row.mu, row.delta, row.omega],
                [p.alpha, p.gamma, p.eps, p.mu, p.delta, p.omega]
            );
        }
        rows.push(row);
    }
    Ok(rows)
}

/// Runs the sweep command.
pub fn sweep(a: SweepArgs) -> Result<()> {
    let (base, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    let format = Format::from_path(&a.out).context("--out")?;
    let axes = a
        .axes
        .iter()
        .map(|s| Axis::parse(s))
        .collect::<hdgear::Result<Vec<_>>>()?;
    let grid = Grid::new(base, axes)?;
    if a.threads == Some(0) {
        bail!("invalid option --threads = 0: must be ≥ 1");
    }
    warn(&warnings);
    let partial = partial_path(&a.out);
    let mut rows: Vec<SweepRow> = Vec::new();
    if a.resume && partial.exists() {
        rows = read_partial(&partial, &grid)?;
    } else if partial.exists() {
        bail!(
            "{} exists (an interrupted sweep): pass --resume to continue it, or delete it",
            partial.display()
        );
    }
    // (re)write the partial file with the good rows, then append as rows finish
    let file = std::fs::File::create(&partial)
        .with_context(|| format!("cannot write {}", partial.display()))?;
    let mut w = csv::Writer::from_writer(file);
    for r in &rows {
        w.serialize(r)?;
    }
    w.flush()?;
    let done: HashSet<usize> = rows.iter().map(|r| r.index).collect();

    let bar = if std::io::stderr().is_terminal() {
        let b = ProgressBar::new(grid.len() as u64);
        b.set_style(
            ProgressStyle::with_template(
                "{bar:40} {pos}/{len} points  {elapsed} elapsed, eta {eta}",
            )
            .expect("valid template"),
        );
        b
    } else {
        ProgressBar::hidden()
    };
    bar.set_position(done.len() as u64);
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
    let meta = serde_json::json!({ "grid": grid, "options": opts });
    match format {
        Format::Csv | Format::Json => write_records(Some(&a.out), &meta, rows)?,
    }
    std::fs::remove_file(&partial).ok();
    if failed > 0 {
        let _ = writeln!(
            std::io::stderr(),
            "warning: {failed} grid points failed; their rows carry the error"
        );
    }
    Ok(())
}
