//! `hdgear merge SHARD…`: the shard files of a sweep → the file one machine would have written,
//! byte for byte. The files' settings are checked before any row is read (same sweep, every shard
//! once); the rows are then streamed in grid order (row i is the next row of shard i mod N), each
//! checked as it passes, into an atomic output: a failed merge leaves nothing behind.
//!
//! The `--json` summaries of `hdgear robust --shard K/N` (files ending in .json) merge into the
//! whole run's summary: the same space and options checked, every part once, the counts (and the
//! importance sampling's sums) added, the worst case and Sobol indices taken from part 0.

use crate::cmd::sweep::file;
use anyhow::{Context, Result, bail};
use hdgear::output::{Format, RecordWriter};
use std::path::{Path, PathBuf};

use clap::Args;

/// Arguments of `hdgear merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The shard files (FILE.shard-K-of-N.csv), all N of them, in any order.
    #[arg(required = true, value_name = "SHARD")]
    pub shards: Vec<PathBuf>,
    /// The merged file, .csv, .json or .parquet (default: the shards' name without .shard-K-of-N, .csv).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

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

/// A merge error with the flags that rerun or resume the shards it names: the library's message
/// names the shards, the command its own flags.
fn with_flags(e: anyhow::Error) -> anyhow::Error {
    use hdgear::sweep::MergeError;
    let flags = match e.downcast_ref::<MergeError>() {
        Some(MergeError::MissingShards { missing, count }) => missing
            .iter()
            .map(|k| format!("--shard {k}/{count}"))
            .collect::<Vec<_>>()
            .join(", "),
        Some(MergeError::Incomplete { shard, .. }) => format!("--shard {shard} --resume"),
        _ => return e,
    };
    anyhow::anyhow!("{e} ({flags})")
}

/// Runs the merge command.
pub fn run(a: MergeArgs) -> Result<()> {
    if a.shards
        .iter()
        .all(|p| p.extension().is_some_and(|e| e == "json"))
    {
        return robust(&a.shards, a.out.as_deref());
    }
    let out = match a.out {
        Some(o) => o,
        None => default_out(&a.shards[0])?,
    };
    let format = Format::from_path(&out).context("--out")?;
    hdgear::output::check_output_path(&out)?;
    crate::sink::check_not_input(
        &out,
        a.shards.iter().map(PathBuf::as_path),
        "the input shard",
    )?;
    let mut headers = Vec::with_capacity(a.shards.len());
    let mut readers = Vec::with_capacity(a.shards.len());
    for path in &a.shards {
        let (settings, rows) = file::open(path)?;
        headers.push((path.display().to_string(), settings));
        readers.push(rows);
    }
    let plan = hdgear::sweep::plan(headers).map_err(|e| with_flags(e.into()))?;
    let (sink, _) = crate::sink::Sink::open(Some(&out))?;
    let mut w = RecordWriter::new(sink, format, plan.settings())?;
    let mut failed = 0;
    let n = plan
        .merge(readers, |row| {
            failed += usize::from(!row.error.is_empty());
            w.row(&row)
                .with_context(|| format!("writing {}", out.display()))
        })
        .map_err(with_flags)?;
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

/// One part's summary, and the fields merging reads from it.
struct Part {
    doc: serde_json::Value,
    shard: (u64, u64),
    first: u64,
}

fn read_part(path: &Path) -> Result<Part> {
    let what = || format!("reading {}", path.display());
    let file = hdgear::output::open_input(path).with_context(what)?;
    let doc: serde_json::Value =
        serde_json::from_reader(std::io::BufReader::new(file)).with_context(what)?;
    let shard = doc.get("shard").cloned().unwrap_or_default();
    let Ok(shard) = serde_json::from_value::<(u64, u64)>(shard) else {
        bail!(
            "{} is not the --json summary of hdgear robust --shard K/N (no shard)",
            path.display()
        );
    };
    let first = doc.pointer("/sampling/first").and_then(|v| v.as_u64());
    let first = first.with_context(|| format!("{}: no sampling.first", path.display()))?;
    Ok(Part { doc, shard, first })
}

/// The run's settings a part must share with the others: everything but its block.
#[derive(PartialEq)]
struct Settings {
    space: serde_json::Value,
    sampling: serde_json::Map<String, serde_json::Value>,
}

fn settings(doc: &serde_json::Value) -> Settings {
    let mut sampling = doc["sampling"].as_object().cloned().unwrap_or_default();
    sampling.remove("first");
    sampling.remove("samples");
    Settings {
        space: doc["space"].clone(),
        sampling,
    }
}

/// Merges the --json summaries of a sharded `hdgear robust` run.
fn robust(paths: &[PathBuf], out: Option<&Path>) -> Result<()> {
    if let Some(out) = out {
        crate::sink::check_not_input(out, paths.iter().map(PathBuf::as_path), "the input part")?;
    }
    let mut parts = paths
        .iter()
        .map(|p| read_part(p))
        .collect::<Result<Vec<_>>>()?;
    parts.sort_by_key(|p| p.shard.0);
    let n = parts[0].shard.1;
    let ks: Vec<u64> = parts.iter().map(|p| p.shard.0).collect();
    if parts.iter().any(|p| p.shard.1 != n) || ks != (0..n).collect::<Vec<_>>() {
        bail!("the summaries are parts {ks:?} of N = {n}: every part 0 … N−1 once is needed");
    }
    let whole = settings(&parts[0].doc);
    let mut next = 0;
    for (p, path) in parts.iter().zip(paths) {
        if settings(&p.doc) != whole {
            bail!(
                "{} is a part of another run (space or sampling differs)",
                path.display()
            );
        }
        if p.first != next {
            bail!(
                "part {} starts at sample {}, not {next}",
                p.shard.0,
                p.first
            );
        }
        next += p.doc["sampling"]["samples"].as_u64().unwrap_or(0);
    }
    let field = |name: &str| -> Result<Vec<serde_json::Value>> {
        Ok(parts.iter().map(|p| p.doc[name].clone()).collect())
    };
    let probability: Vec<hdgear::robust::Probability> = field("probability")?
        .into_iter()
        .map(serde_json::from_value)
        .collect::<std::result::Result<_, _>>()
        .context("a part's probability")?;
    let probability = hdgear::robust::Probability::merge(&probability)?;
    let importance: Option<Vec<hdgear::robust::Importance>> = field("importance")?
        .into_iter()
        .map(|v| {
            (!v.is_null())
                .then(|| serde_json::from_value(v))
                .transpose()
        })
        .collect::<std::result::Result<_, _>>()
        .context("a part's importance sampling")?;
    let importance = importance
        .map(|i| hdgear::robust::Importance::merge(&i))
        .transpose()?;
    let mut doc = parts.swap_remove(0).doc;
    doc["probability"] = serde_json::to_value(probability)?;
    doc["importance"] = serde_json::to_value(&importance)?;
    doc["sampling"]["samples"] = next.into();
    doc["shard"] = serde_json::Value::Null;
    let text = serde_json::to_string_pretty(&doc)? + "\n";
    match out {
        Some(path) => hdgear::output::write_atomic(path, text.as_bytes())?,
        None => crate::sink::out!("{text}"),
    }
    eprintln!(
        "merged {n} parts: P(burst) = {:.4e} [{:.4e}, {:.4e}] from {} samples",
        probability.p, probability.interval.0, probability.interval.1, probability.samples
    );
    Ok(())
}
