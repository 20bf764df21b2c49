//! `--out`, `--plot` and `--json`, written once for every command whose result is rows, a figure
//! and one JSON document (hyperfine's one exporter): the flags, their checks before the run, and
//! the export after it. The `--out` help lists the rows' columns from the row type itself.

use crate::sink::{outln, write_records_and};
use anyhow::Result;
use clap::Args;
use hdgear::output::Record;
use hdgear::output::plot::Figure;
use std::marker::PhantomData;
use std::path::PathBuf;

/// The three output flags of a command whose rows are `R`.
#[derive(Args)]
pub struct Export<R: Record + 'static> {
    #[arg(long, value_name = "FILE", help = out_help(R::COLUMNS))]
    pub out: Option<PathBuf>,
    /// The figure to a .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Print one JSON document (every result in full) instead of the summary.
    #[arg(long)]
    pub json: bool,
    #[arg(skip)]
    rows: PhantomData<fn() -> R>,
}

impl<R: Record> std::fmt::Debug for Export<R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Export")
            .field("out", &self.out)
            .field("plot", &self.plot)
            .field("json", &self.json)
            .finish()
    }
}

/// `--out`'s help: the columns, in order, as the file will have them.
pub fn out_help(columns: &[&str]) -> String {
    format!(
        "The rows ({}) to a .csv, .json or .parquet file",
        columns.join(",")
    )
}

impl<R: Record> Export<R> {
    /// Refuses a bad `--out` or `--plot` path before anything is computed.
    pub fn check(&self) -> Result<()> {
        crate::args::check_out(&self.out)?;
        if let Some(path) = &self.plot {
            crate::args::check_plot(path)?;
        }
        Ok(())
    }

    /// Writes the rows (with `meta`) to `--out` and the figure to `--plot`, each only when asked
    /// for.
    pub fn write<I: IntoIterator<Item = R>>(
        &self,
        meta: &impl serde::Serialize,
        rows: impl FnOnce() -> I,
        figure: impl FnOnce() -> Figure,
    ) -> Result<()> {
        let plot = || match &self.plot {
            Some(path) => Ok(hdgear::output::plot::write(&figure(), path)?),
            None => Ok(()),
        };
        match &self.out {
            // the figure before the rows are made final: where either fails, neither is left
            Some(out) => write_records_and(Some(out), meta, R::COLUMNS.to_vec(), rows(), plot),
            None => plot(),
        }
    }

    /// Prints `doc` as one JSON document with `--json`, the summary without it.
    pub fn print(
        &self,
        doc: &impl serde::Serialize,
        summary: impl FnOnce() -> Result<()>,
    ) -> Result<()> {
        if self.json {
            outln!("{}", serde_json::to_string_pretty(doc)?);
            Ok(())
        } else {
            summary()
        }
    }
}
