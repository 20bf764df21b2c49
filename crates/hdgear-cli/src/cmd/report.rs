//! `hdgear report`: the HTML report of the study, or of a model (`--config`, `--card`, the
//! study's flags).

use anyhow::{Context, Result};
use hdgear::params::Param;
use hdgear::report::Stage;
use hdgear::report::model::ModelReportOptions;

use crate::sources::ParamArgs;
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
    /// A drive instead of the study: its card (built-in name, FILE.toml or FILE.toml#NAME) with
    /// the documented assumptions for the rest; the report of its reduced model (with the card's
    /// friction) and its design check.
    #[arg(long, value_name = "CARD", conflicts_with_all = crate::sources::NOT_WITH_CARD)]
    pub card: Option<String>,
    /// With --config or any parameter flag, the report of that model instead of the study's.
    #[command(flatten)]
    pub params: ParamArgs,
}

impl ReportArgs {
    /// Whether a model other than the study's defaults was asked for.
    fn model_asked(&self) -> bool {
        self.card.is_some()
            || self.params.config.is_some()
            || self.params.preset != ParamArgs::DEFAULT_PRESET
            || Param::ALL.iter().any(|&q| self.params.given(q))
    }
}

/// A refused directory's remedy in this command's flags: the library's message says to choose
/// another directory or to let the report overwrite the files it did not write.
fn with_flags(e: hdgear::Error) -> anyhow::Error {
    match &e {
        hdgear::Error::ForeignFiles { .. } => anyhow::anyhow!("{e} (--out DIR, or --force)"),
        _ => e.into(),
    }
}

pub fn run(a: ReportArgs) -> Result<()> {
    let threads = crate::args::threads(a.threads)?;
    if a.model_asked() {
        return run_model(&a, threads);
    }
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
    .map_err(with_flags)
    .with_context(|| format!("writing the report to {}", a.out.display()))?;
    done(summary.files.len(), start, &a.out);
    Ok(())
}

/// The report of the model of `--card`, `--config` or the flags.
fn run_model(a: &ReportArgs, threads: usize) -> Result<()> {
    let opts = ModelReportOptions {
        threads,
        force: a.force,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let files = match &a.card {
        Some(spec) => {
            let loaded = crate::cmd::card::load(spec).context("--card")?;
            let built = hdgear::physical::catalogue::assemble(&loaded.card, None, None)
                .context("--card")?;
            let model = hdgear::physical::friction::card_model(&loaded.card, &built.drive)
                .context("--card")?;
            let origin = format!("card {}", loaded.card.name);
            eprintln!("report of {origin}: {}", model.equation());
            let drive = (
                loaded.card.name.as_str(),
                &built.drive,
                built.assumptions.as_slice(),
            );
            hdgear::report::model::build(&a.out, &model, &origin, Some(drive), &opts)
        }
        None => {
            let (p, model, warnings) = a.params.resolve_model()?;
            crate::sink::warn(&warnings);
            let origin = match &a.params.config {
                Some(path) => format!("scenario file {}", path.display()),
                None => format!(
                    "the study's equation at {}",
                    Param::ALL
                        .iter()
                        .map(|&q| format!(
                            "{} = {}",
                            hdgear::model::study_param(q).symbol,
                            p.value(q)
                        ))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            eprintln!("report of {origin}: {}", model.equation());
            hdgear::report::model::build(&a.out, &model, &origin, None, &opts)
        }
    }
    .map_err(with_flags)
    .with_context(|| format!("writing the report to {}", a.out.display()))?;
    done(files.len(), start, &a.out);
    Ok(())
}

/// The closing line: files written, time, where to look.
fn done(files: usize, start: std::time::Instant, out: &std::path::Path) {
    eprintln!(
        "wrote {files} files in {:.1} s; open {}",
        start.elapsed().as_secs_f64(),
        out.join("index.html").display()
    );
}
