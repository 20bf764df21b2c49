//! `hdgear continue`: a branch of periodic orbits by pseudo-arclength continuation, its special
//! points, and (with --switch) the doubled branches born at its period doublings.

use crate::sink::{warn, write_records};
use anyhow::{Context, Result};
use hdgear::params::{Param, Warning};
use hdgear::periodic::{
    BranchRow, ContinuationOptions, End, OrbitBranch, Periodic, Range, Special,
    continue_with_doubled,
};
use serde::Serialize;

use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `hdgear continue`.
#[derive(Args, Debug)]
pub struct ContinueArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// NAME=FROM:TO[:log]: follow the orbit in NAME from FROM (the parameter is set to it) to TO,
    /// in ln NAME with :log.
    #[arg(long = "param", value_name = "SPEC", allow_hyphen_values = true)]
    pub range: String,
    /// K: follow the orbit of period K·2π/ω.
    #[arg(long, default_value_t = 1)]
    pub subharmonic: u32,
    /// Also follow the doubled branch from every period doubling found (one level).
    #[arg(long)]
    pub switch: bool,
    /// The branch points (branch,subharmonic,param,x0,xdot0,x_min,x_max,…,special) to a .csv,
    /// .json or .parquet file.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON document (the branches with every point).
    #[arg(long)]
    pub json: bool,
}

/// What `--json` prints and `--out` carries as metadata.
#[derive(Serialize)]
struct Doc<'a, S: Periodic> {
    range: Range<S::Param>,
    params: &'a S,
    options: ContinuationOptions,
    branches: &'a [OrbitBranch<S::Param>],
}

pub fn run(a: ContinueArgs) -> Result<()> {
    // a study parameter's flag beside --param naming it would be overwritten
    let name = a.range.split_once('=').map(|(n, _)| n.trim());
    if let Some(q) = name.and_then(|n| n.parse::<Param>().ok())
        && a.params.given(q)
    {
        anyhow::bail!(
            "--{0} does not apply: --param {1} sets {0} itself",
            q,
            a.range
        );
    }
    let (system, warnings) = a.params.resolve_system()?;
    crate::args::check_out(&a.out)?;
    hdgear::on_subject!(&system, |p| run_on(p, &a, &warnings))
}

/// The branches of the study's set or of a model, exported and summarised.
fn run_on<S: Periodic>(p: &S, a: &ContinueArgs, warnings: &[Warning]) -> Result<()> {
    let range = Range::parse_for(&a.range, p).context("--param")?;
    let p = p.with(range.param, range.from).context("--param")?;
    warn(warnings);
    let progress = crate::sink::PointsProgress::new("continue");
    let opts = ContinuationOptions {
        scale: range.scale,
        progress: Some(progress.counter()),
        ..ContinuationOptions::default()
    };
    let branches =
        continue_with_doubled(&p, range.param, a.subharmonic, range.to, a.switch, &opts)?;
    drop(progress);
    let doc = Doc {
        range,
        params: &p,
        options: opts,
        branches: &branches,
    };
    if let Some(out) = &a.out {
        let rows = branches.iter().enumerate().flat_map(|(i, b)| {
            b.points
                .iter()
                .map(move |q| BranchRow::new(i, b.subharmonic, q))
        });
        write_records(Some(out), &doc, rows)?;
    }
    if a.json {
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        print_summary(&branches, range.param)?;
    }
    Ok(())
}

fn print_summary<P: std::fmt::Display>(branches: &[OrbitBranch<P>], param: P) -> Result<()> {
    for (i, b) in branches.iter().enumerate() {
        let (first, last) = (b.points.first(), b.points.last());
        let span = match (first, last) {
            (Some(f), Some(l)) => format!("{param} from {} to {}", f.param, l.param),
            _ => "no points".to_string(),
        };
        let end = match b.end {
            End::Reached => "left the range".to_string(),
            End::MaxPoints => "stopped at the point limit".to_string(),
            End::Closed => "closed on itself (an isola)".to_string(),
            End::Rejoined { param: v } => {
                format!("rejoined the parent branch at the period doubling at {param} = {v}")
            }
            End::StepTooSmall { param: v } => {
                format!("the step fell below its minimum near {param} = {v}")
            }
            End::Switched => "switched onto at its first point".to_string(),
        };
        crate::sink::outln!(
            "branch {i}: period {} × 2π/ω, {} points, {span}; {end}",
            b.subharmonic,
            b.points.len()
        );
        let stable = b.points.iter().filter(|q| q.stable).count();
        crate::sink::outln!("  {stable} stable, {} unstable", b.points.len() - stable);
        for q in b.specials() {
            crate::sink::outln!(
                "  {:<16} {param} = {:<14.10} x0 = {:<12.8} peak-to-peak x {:.6}, max |x'| {:.6}{}",
                q.special.map_or("", Special::name),
                q.param,
                q.start[0],
                q.amplitude.peak_to_peak,
                q.amplitude.max_abs_xdot,
                crate::summary::criticality(q)
            );
        }
    }
    Ok(())
}
