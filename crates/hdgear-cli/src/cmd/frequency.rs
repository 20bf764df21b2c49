//! `hdgear frequency-response`: the response amplitude against ω by continuation in ln ω, with
//! its folds (the jumps of a slow up- or down-sweep) and stability along the curve.

use crate::sink::warn;
use anyhow::{Context, Result};
use hdgear::params::Param;
use hdgear::periodic::{BranchRow, ContinuationOptions, Periodic, Special, frequency_response};

use crate::sources::ParamArgs;
use clap::Args;

/// Arguments of `hdgear frequency-response`.
#[derive(Args, Debug)]
pub struct FrequencyResponseArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// LO:HI, the omega range (default: from 1/20 to 3 times the stiffest static frequency).
    #[arg(long = "omega-range", value_name = "LO:HI")]
    pub omega_range: Option<String>,
    #[command(flatten)]
    pub export: crate::export::Export<hdgear::periodic::BranchRow>,
}

pub fn run(a: FrequencyResponseArgs) -> Result<()> {
    let omega = Param::Omega;
    if a.params.given(omega) {
        anyhow::bail!(
            "--{omega} does not apply: the curve varies {omega} itself (see --omega-range)"
        );
    }
    let range = crate::args::parse_frequency_range("--omega-range", a.omega_range.as_deref())?;
    let (system, warnings) = a.params.resolve_system()?;
    a.export.check()?;
    warn(&warnings);
    hdgear::on_subject!(&system, |p| run_on(p, &a, range))
}

/// The curve of the study's set or of a model, exported and summarised.
fn run_on<S: Periodic>(p: &S, a: &FrequencyResponseArgs, range: Option<(f64, f64)>) -> Result<()> {
    let opts = ContinuationOptions::default();
    let b = frequency_response(p, range, &opts).context("frequency-response")?;
    let rows = || b.points.iter().map(|q| BranchRow::new(0, 1, q));
    let figure = || hdgear::figures::frequency_response_figure(p, &b);
    a.export.write(&b.param, rows, figure)?;
    a.export.print(&b, || summary(&b))
}

fn summary<P>(b: &hdgear::periodic::OrbitBranch<P>) -> Result<()> {
    let peak = b.points.iter().max_by(|x, y| {
        x.amplitude
            .peak_to_peak
            .total_cmp(&y.amplitude.peak_to_peak)
    });
    let (lo, hi) = (b.points[0].param, b.points[b.points.len() - 1].param);
    crate::sink::outln!(
        "frequency response over omega {lo:.6} … {hi:.6}: {} points",
        b.points.len()
    );
    if let Some(q) = peak {
        crate::sink::outln!(
            "  largest response: peak-to-peak x {:.6} at omega = {:.6} ({})",
            q.amplitude.peak_to_peak,
            q.param,
            if q.stable { "stable" } else { "unstable" }
        );
    }
    crate::summary::specials(
        b.specials(),
        |q| q.special.map_or("", Special::name),
        |q| {
            format!(
                "omega = {:.10}, peak-to-peak x {:.6}{}",
                q.param,
                q.amplitude.peak_to_peak,
                crate::summary::criticality(q)
            )
        },
        "no fold, no period doubling: the response is single-valued (no jump)",
    )
}
