//! `hdgear sweep`: grid → parallel run with a progress bar → each row, in grid order, appended to
//! FILE.partial and streamed into FILE (a temporary put in place when the sweep is done), so
//! memory stays flat however large the grid. `--resume` continues from FILE.partial (its rows
//! are held while the rest is computed); `--shard K/N` computes
//! one interleaved part of the grid into FILE's name with `.shard-K-of-N.csv` (joined by
//! `hdgear merge`); `--slurm N` writes the job scripts that run N shards on a cluster.
//!
//! A lock on FILE.lock (holding the owner's pid) keeps a second sweep off the same file while one
//! runs. The row files' format is in [`file`].

pub mod file;
mod slurm;

use crate::sink::warn;
use anyhow::{Context, Result, anyhow, bail};
use file::sibling;
use hdgear::burst::BurstOptions;
use hdgear::model::Subject;
use hdgear::output::Format;
use hdgear::params::{Params, Warning};
use hdgear::sweep::{Axis, Grid, Settings, Shard, Sweep, SweepRow};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::HashSet;
use std::fs::{File, OpenOptions};
use std::io::{IsTerminal, Read, Seek, Write};
use std::path::{Path, PathBuf};

use crate::args::{BurstArgs, GridAxes};
use crate::sources::ParamArgs;
use clap::Args;

/// Arguments of `hdgear sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
    #[command(flatten)]
    pub grid: GridAxes,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output file, .csv, .json or .parquet. Rows stream into FILE.partial as they finish; FILE is written
    /// in grid order at the end.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Continue an interrupted sweep from FILE.partial.
    #[arg(long)]
    pub resume: bool,
    /// Compute only shard K of N (K = 0 … N−1): the grid points i with i mod N = K, written to
    /// DIR/NAME.shard-K-of-N.csv for --out DIR/NAME.EXT. `hdgear merge` joins the shards.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Write SLURM scripts (not submitted): a job array of N shards and a merge job that runs
    /// after them, next to FILE; prints the sbatch command.
    #[arg(long, value_name = "N", conflicts_with_all = ["shard", "resume"])]
    pub slurm: Option<usize>,
    /// SLURM partition of the jobs (with --slurm).
    #[arg(long, requires = "slurm", value_name = "P")]
    pub partition: Option<String>,
    /// SLURM time limit of each shard, e.g. 30:00 or 1-12:00:00 (with --slurm).
    #[arg(long, requires = "slurm", value_name = "T")]
    pub time: Option<String>,
    /// CPUs of each shard, its worker threads (with --slurm; default 1).
    #[arg(long, requires = "slurm", value_name = "C")]
    pub cpus_per_task: Option<usize>,
}

/// The file a shard of a sweep into `out` is written to: `DIR/NAME.shard-K-of-N.csv` for
/// `DIR/NAME.EXT` (always CSV: see [`file`]).
pub fn shard_path(out: &Path, shard: Shard) -> PathBuf {
    let stem = out.file_stem().unwrap_or_default().to_string_lossy();
    out.with_file_name(format!(
        "{stem}.shard-{}-of-{}.csv",
        shard.index, shard.count
    ))
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

/// A checked sweep: what to compute and where it goes.
pub struct Job<S: Sweep = Params> {
    /// Everything that changes a row (with the shard, when one).
    pub settings: Settings<S>,
    /// The user's --out.
    pub out: PathBuf,
    /// Where this run writes: `out`, or the shard's file.
    pub file: PathBuf,
    /// Worker threads (0: one per core).
    pub threads: usize,
    /// Continue from the partial file.
    pub resume: bool,
}

/// Arguments → a checked job of the study's model (every grid point validated before any work):
/// what `--slurm` writes and checks its scripts against.
pub fn check(a: &SweepArgs) -> Result<Job> {
    let (base, warnings) = a.params.resolve()?;
    check_on(a, base, &warnings)
}

/// Arguments → a checked job on `base`, the study's set or a model, whose parameters the axes
/// name.
fn check_on<S: Sweep>(a: &SweepArgs, base: S, warnings: &[Warning]) -> Result<Job<S>> {
    let opts: BurstOptions = a.burst.options()?;
    Format::from_path(&a.out).context("--out")?;
    let axes = a
        .grid
        .axes
        .iter()
        .map(|s| Axis::parse_for(s, &base))
        .collect::<hdgear::Result<Vec<_>>>()
        .context("--param")?;
    let grid = Grid::new(base, axes)?;
    let threads = crate::args::threads(a.threads)?;
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    if let Some(s) = shard.filter(|s| s.count > grid.len()) {
        bail!(
            "invalid shard '{s}': {} shards of a grid of {} points would leave some empty",
            s.count,
            grid.len()
        );
    }
    let file = shard.map_or_else(|| a.out.clone(), |s| shard_path(&a.out, s));
    hdgear::output::check_output_path(&file)?;
    warn(warnings);
    Ok(Job {
        settings: Settings::new(&grid, &opts).with_shard(shard),
        out: a.out.clone(),
        file,
        threads,
        resume: a.resume,
    })
}

/// Runs the sweep command: writes the SLURM scripts, or computes, on the study's set or the
/// scenario's model.
pub fn run(a: SweepArgs) -> Result<()> {
    let (system, warnings) = a.params.resolve_system()?;
    match system {
        Subject::Study(p) => {
            let cluster = a.slurm.map(|n| slurm::Cluster::check(&a, n)).transpose()?;
            let job = check_on(&a, p, &warnings)?;
            match cluster {
                Some(c) => slurm::write(&job, &c),
                None => compute(&job),
            }
        }
        Subject::Model(m) => {
            if let Some(flag) = [
                ("--shard", a.shard.is_some()),
                ("--slurm", a.slurm.is_some()),
            ]
            .iter()
            .find_map(|(flag, given)| given.then_some(flag))
            {
                bail!(
                    "{flag}: a sweep of a model with term tables runs on one machine (its \
                     shards' settings name the model, which hdgear merge does not read back)"
                );
            }
            compute(&check_on(&a, m, &warnings)?)
        }
    }
}

/// Where a sweep's rows end up, written in grid order as they come.
enum Output<P: serde::Serialize> {
    /// A whole sweep: FILE in the format of its extension.
    Records(hdgear::output::RecordWriter<crate::sink::Sink, SweepRow<P>>),
    /// A shard: its row file.
    Shard(Box<file::RowFile>),
}

impl<P: serde::Serialize> Output<P> {
    fn open<S: Sweep<Point = P>>(job: &Job<S>) -> Result<Output<P>> {
        Ok(match job.settings.shard {
            None => {
                let (sink, format) = crate::sink::Sink::open(Some(&job.file))?;
                let columns = hdgear::sweep::columns::<S, SweepRow>(&job.settings.grid.axes);
                Output::Records(hdgear::output::RecordWriter::with_columns(
                    sink,
                    format,
                    &job.settings,
                    columns,
                )?)
            }
            Some(_) => Output::Shard(Box::new(file::RowFile::create(&job.file, &job.settings)?)),
        })
    }

    fn row(&mut self, r: &SweepRow<P>) -> Result<()> {
        match self {
            Output::Records(w) => Ok(w.row(r)?),
            Output::Shard(f) => f.row(r),
        }
    }

    fn commit(self) -> Result<()> {
        match self {
            Output::Records(w) => w.finish()?.commit(),
            Output::Shard(f) => f.commit(),
        }
    }
}

/// Computes a checked job.
fn compute<S: Sweep>(job: &Job<S>) -> Result<()>
where
    S::Param: 'static,
    S::Point: 'static,
{
    let settings = &job.settings;
    let grid = &settings.grid;
    let _lock = Lock::acquire(&job.file)?;
    let partial = sibling(&job.file, ".partial");
    // the output first: if it cannot be started, no partial file is left behind (a failure
    // after this drops it, which removes its temporary)
    let context = || format!("writing {}", job.file.display());
    let mut out = Output::open(job).with_context(context)?;
    let (finished, mut w) = open_partial(job, &partial)?;
    let done: HashSet<usize> = finished.iter().map(|r| r.index).collect();
    let todo: Vec<usize> = settings
        .indices()
        .into_iter()
        .filter(|i| !done.contains(i))
        .collect();
    drop(done);

    let bar = progress_bar(todo.len() + finished.len(), finished.len())?;
    // the rows come in grid order; a resumed sweep's finished rows (in grid order too) are
    // merged in before the first new row after them
    let mut finished = finished.into_iter().peekable();
    let (mut n, mut failed) = (0usize, 0usize);
    let mut put = |out: &mut Output<S::Point>, row: &SweepRow<S::Point>| {
        n += 1;
        failed += usize::from(!row.error.is_empty());
        out.row(row).with_context(context)
    };
    let mut io_err: Option<anyhow::Error> = None;
    hdgear::sweep::run(grid, &settings.options, &todo, job.threads, |row| {
        if io_err.is_none() {
            let res = w
                .serialize(&row)
                .map_err(anyhow::Error::from)
                .and_then(|_| w.flush().map_err(anyhow::Error::from))
                .with_context(|| format!("writing {}", partial.display()))
                .and_then(|()| {
                    while let Some(old) = finished.next_if(|f| f.index < row.index) {
                        put(&mut out, &old)?;
                    }
                    put(&mut out, &row)
                });
            io_err = res.err();
        }
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    if let Some(e) = io_err {
        // what failed first, then what to do about it
        return Err(anyhow::anyhow!("{e:#}; {}", resume_hint(&partial)));
    }
    for old in finished {
        put(&mut out, &old)?;
    }
    drop(w);
    out.commit().with_context(context)?;
    std::fs::remove_file(&partial).ok();
    written(job, n, failed)
}

/// FILE.partial started afresh, or for `--resume` with the rows it holds (returned, in grid
/// order); then opened for appending.
type Partial<P> = (Vec<SweepRow<P>>, csv::Writer<File>);

fn open_partial<S: Sweep>(job: &Job<S>, partial: &Path) -> Result<Partial<S::Point>>
where
    S::Param: 'static,
    S::Point: 'static,
{
    let mut finished: Vec<SweepRow<S::Point>> = Vec::new();
    if job.resume && partial.exists() {
        finished = file::read_partial(partial, &job.settings)?;
    } else if partial.exists() {
        bail!(
            "{} exists (an interrupted sweep): pass --resume to continue it, or delete it",
            partial.display()
        );
    }
    file::write(partial, &job.settings, &finished)?;
    let w = file::append(partial)?;
    crate::signals::set_hint(resume_hint(partial));
    Ok((finished, w))
}

/// What a sweep that stopped early (a signal, a full disk) tells the user.
fn resume_hint(partial: &Path) -> String {
    format!(
        "the finished rows are kept in {}: rerun the same command with --resume",
        partial.display()
    )
}

/// Says what was written; exit code 1 when every point of a whole sweep failed.
fn written<S: Sweep>(job: &Job<S>, n: usize, failed: usize) -> Result<()> {
    let settings = &job.settings;
    match settings.shard {
        None => eprintln!("wrote {}: {n} rows, {failed} failed", job.file.display()),
        Some(s) => {
            // the shard files as a glob, each part quoted for a shell (a pasted path with a space
            // or a `$(…)` stays a path)
            let first = shard_path(
                &job.out,
                Shard {
                    index: 0,
                    count: s.count,
                },
            );
            let text = first.display().to_string();
            let (head, tail) = text.split_once(".shard-0-of-").unwrap_or((&text, ""));
            let glob = format!(
                "{}*{}",
                slurm::shell_word(&format!("{head}.shard-")),
                slurm::shell_word(&format!("-of-{tail}"))
            );
            eprintln!(
                "wrote {}: shard {s}, {n} rows, {failed} failed; when all {} shards are done: \
                 hdgear merge {glob} --out {}",
                job.file.display(),
                s.count,
                slurm::shell_word(&job.out.display().to_string())
            )
        }
    }
    // a shard whose points all failed is still a complete shard: the merge judges the sweep
    if settings.shard.is_none() {
        all_failed(n, failed)?;
    }
    Ok(())
}

/// Exit code 1 when every one of `n > 0` points failed (the rows are written: they say why).
pub fn all_failed(n: usize, failed: usize) -> Result<()> {
    if n > 0 && failed == n {
        return Err(crate::sink::ComputationFailed(
            "every grid point failed (their rows carry the error)".into(),
        )
        .into());
    }
    Ok(())
}
