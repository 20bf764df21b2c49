//! `hdgear report`: the HTML report.

use anyhow::{Context, Result};
use hdgear::report::Stage;

use clap::Args;
use std::path::PathBuf;

/// Arguments of `hdgear report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Output directory (index.html, figures/, data/). Files hdgear did not write there are
    /// never overwritten without --force.
    #[arg(long, default_value = "report", value_name = "DIR")]
    pub out: PathBuf,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Overwrite files in DIR that hdgear did not write.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: ReportArgs) -> Result<()> {
    let threads = crate::args::threads(a.threads)?;
    let opts = hdgear::report::ReportOptions {
        threads,
        force: a.force,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let stages = Stage::ALL.len();
    let summary = hdgear::report::build(&a.out, &opts, &mut |stage: Stage| {
        let step = stage as usize + 1;
        eprintln!(
            "[{step}/{stages} {:5.1} s] {}",
            start.elapsed().as_secs_f64(),
            stage.describe(&opts)
        );
    })
    .with_context(|| format!("writing the report to {}", a.out.display()))?;
    eprintln!(
        "wrote {} files in {:.1} s; open {}",
        summary.files.len(),
        start.elapsed().as_secs_f64(),
        a.out.join("index.html").display()
    );
    Ok(())
}
