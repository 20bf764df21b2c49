//! `hdgear report`: the HTML report.

use anyhow::{Context, Result};

pub fn run(a: crate::cli::ReportArgs) -> Result<()> {
    if a.threads == Some(0) {
        anyhow::bail!("invalid option --threads = 0: must be ≥ 1");
    }
    let opts = hdgear::report::ReportOptions {
        threads: a.threads.unwrap_or(0),
        force: a.force,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let mut step = 0;
    let summary = hdgear::report::build(&a.out, &opts, &mut |stage| {
        step += 1;
        eprintln!("[{step}/8 {:5.1} s] {stage}", start.elapsed().as_secs_f64());
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
