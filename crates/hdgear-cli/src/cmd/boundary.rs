//! `hdgear boundary`: the bursting boundary (predicted and simulated), the fold set of the fast
//! subsystem and the edge of the fast-slow domain as curves in a plane of two parameters.

use super::two_parameter::PlaneArgs;
use crate::args::BurstArgs;
use crate::export::Export;
use crate::sink::{outln, warn};
use anyhow::{Context, Result};
use clap::Args;
use clap::builder::PossibleValuesParser;
use hdgear::burst::{
    BoundaryKind, BurstOptions, PlaneCurve, PlaneEnd, PlaneOptions, PlaneRow, PlaneSystem,
    plane_boundaries,
};
use hdgear::periodic::{Oscillator, Periodic, Range, Scale};
use serde::Serialize;

/// Arguments of `hdgear boundary`.
#[derive(Args, Debug)]
pub struct BoundaryArgs {
    #[command(flatten)]
    pub plane: PlaneArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
    /// Which boundaries, comma-separated (all without it).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "KIND",
        value_parser = PossibleValuesParser::new(BoundaryKind::ALL.map(BoundaryKind::name))
    )]
    pub kinds: Vec<String>,
    /// Largest step, as a fraction of the box (each axis 1 wide in its scale).
    #[arg(long, default_value_t = PlaneOptions::default().step_max)]
    pub step: f64,
    #[command(flatten)]
    pub export: Export<PlaneRow>,
}

/// What `--json` prints and `--out` carries as metadata.
#[derive(Serialize)]
#[serde(bound = "")]
struct Doc<'a, S: Periodic> {
    params: S,
    ranges: [Range<S::Param>; 2],
    options: PlaneOptions,
    burst: BurstOptions,
    curves: &'a [PlaneCurve<S::Param>],
}

pub fn run(a: BoundaryArgs) -> Result<()> {
    let (system, warnings) = a.plane.params.resolve_system()?;
    hdgear::on_subject!(system, |s| boundaries_of(&a, s, &warnings))
}

/// The boundaries of `base`, the study's set (every kind) or a model (the simulated boundary:
/// the other kinds are the study's closed forms), written and summarised.
fn boundaries_of<S>(a: &BoundaryArgs, base: S, warnings: &[hdgear::params::Warning]) -> Result<()>
where
    S: Periodic + PlaneSystem<Axis = <S as Oscillator>::Param>,
{
    let (p, [r1, r2], box2) = a.plane.resolve_on(base)?;
    a.plane
        .params
        .not_given(&r2.param.to_string(), "--param sets")?;
    let kinds: Vec<BoundaryKind> = if a.kinds.is_empty() {
        BoundaryKind::ALL
            .into_iter()
            .filter(|&k| p.defines(k).is_ok())
            .collect()
    } else {
        a.kinds
            .iter()
            .map(|k| k.parse())
            .collect::<Result<_, _>>()?
    };
    for &k in &kinds {
        p.defines(k).context("--kinds")?;
    }
    let opts = PlaneOptions::with_step(a.step);
    opts.validate()
        .map_err(|e| anyhow::anyhow!("--step: {e}"))?;
    let burst = a.burst.options()?;
    a.export.check()?;
    warn(warnings);
    let params = [r1.param, r2.param];
    let curves = plane_boundaries(&p, params, &box2, &kinds, &opts, &burst)?;
    let doc = Doc {
        params: p,
        ranges: [r1, r2],
        options: opts,
        burst,
        curves: &curves,
    };
    let rows = || {
        curves
            .iter()
            .enumerate()
            .flat_map(|(i, c)| PlaneRow::of(i, c))
    };
    let names = params.map(|q| q.to_string());
    let figure = || {
        let logs = [r1.scale, r2.scale].map(|s| s == Scale::Log);
        hdgear::figures::plane_figure::<S::Param, S::Param>(
            &[],
            &curves,
            [&names[0], &names[1]],
            logs,
        )
    };
    a.export.write(&doc, rows, figure)?;
    a.export
        .print(&doc, || summary(&p, &curves, &kinds, &names))
}

fn summary<S: PlaneSystem>(
    base: &S,
    curves: &[PlaneCurve<S::Axis>],
    kinds: &[BoundaryKind],
    names: &[String; 2],
) -> Result<()> {
    // the kinds not defined for this system, on one line with the reason
    let refused: Vec<(BoundaryKind, hdgear::Error)> = BoundaryKind::ALL
        .into_iter()
        .filter(|k| !kinds.contains(k))
        .filter_map(|k| base.defines(k).err().map(|e| (k, e)))
        .collect();
    if let Some((_, hdgear::Error::InvalidInput { reason, .. })) = refused.first() {
        let names: Vec<&str> = refused.iter().map(|(k, _)| k.name()).collect();
        outln!("{}: not traced: {reason}", names.join(", "));
    }
    for &kind in kinds {
        let n = curves.iter().filter(|c| c.kind == kind).count();
        outln!(
            "{}: {n} curve(s); on one side {}",
            kind.name(),
            kind.inside()
        );
    }
    for (i, c) in curves.iter().enumerate() {
        let extent = |j: usize| {
            super::two_parameter::extent(&names[j], c.points.iter().map(|q| q.params[j]))
        };
        let end = match c.end {
            PlaneEnd::Edge => "edge to edge",
            PlaneEnd::MaxPoints => "stopped at the point limit",
            PlaneEnd::StepTooSmall => "the step fell below its minimum",
        };
        let what = match c.kind {
            BoundaryKind::Simulated => "simulations",
            _ => "verdicts",
        };
        outln!(
            "curve {i}: {}, {} points, {}, {}, {end}; {} {what}, each point to {:e}",
            c.kind.name(),
            c.points.len(),
            extent(0),
            extent(1),
            c.evaluations,
            c.kind.tolerance()
        );
    }
    Ok(())
}
