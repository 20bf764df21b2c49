//! `hdgear continue2`: the curves of folds (or period doublings) of the periodic response in two
//! parameters, started from the special points a one-parameter continuation finds, with their
//! cusps and generalised period doublings.

use crate::export::Export;
use crate::sink::{outln, warn};
use crate::sources::ParamArgs;
use anyhow::{Context, Result, bail};
use clap::Args;
use hdgear::periodic::{
    Box2, Codim2, ContinuationOptions, Curve2, CurveKind, CurveRow, End, Oscillator, Periodic,
    Range, Scale, continue_curve, curves_at_gpds, curves_from_branch,
};
use serde::Serialize;

/// A plane of two parameters: the set, and `--param` given twice (shared by `continue2` and
/// `boundary`).
#[derive(Args, Debug)]
pub struct PlaneArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// NAME=LO:HI[:log], given twice: the two parameters and the box the curves are followed in.
    #[arg(
        long = "param",
        value_name = "SPEC",
        required = true,
        allow_hyphen_values = true
    )]
    pub ranges: Vec<String>,
}

/// Arguments of `hdgear continue2`.
#[derive(Args, Debug)]
pub struct Continue2Args {
    #[command(flatten)]
    pub plane: PlaneArgs,
    /// fold or period-doubling, optionally :N: the curves through every fold (period doubling)
    /// of the one-parameter branch in the first --param from LO to HI (the second at the set's
    /// value), or through its Nth (from 1) only.
    #[arg(long, default_value = "fold", value_name = "KIND[:N]")]
    pub from: String,
    /// FILE:ROW: follow the one curve through row ROW (from 0) of a `continue2 --out` CSV
    /// file instead, the two --param as in the run that wrote it (its param1 and param2).
    #[arg(long, value_name = "FILE:ROW")]
    pub restart: Option<String>,
    /// K: orbits of period K·2π/ω.
    #[arg(long, default_value_t = 1)]
    pub subharmonic: u32,
    /// Period-doubling curves only: also follow the fold curve of the doubled orbits (period
    /// 2K·2π/ω) born at each generalised period doubling found, switched onto there.
    #[arg(long)]
    pub switch: bool,
    #[command(flatten)]
    pub export: Export<CurveRow>,
}

/// What `--json` prints and `--out` carries as metadata.
#[derive(Serialize)]
#[serde(bound = "")]
struct Doc<'a, S: Periodic> {
    params: S,
    ranges: [Range<S::Param>; 2],
    options: ContinuationOptions,
    curves: &'a [Curve2<S::Param>],
}

/// The checked request: the set (with the first parameter at its start), both ranges.
fn request<S: Periodic>(
    a: &Continue2Args,
    base: S,
    warnings: &[hdgear::params::Warning],
) -> Result<(S, [Range<S::Param>; 2])> {
    let (p, [r1, r2], box2) = a.plane.resolve_on(base)?;
    let at = p.get(r2.param);
    if !(at >= box2.ranges[1].0 && at <= box2.ranges[1].1) {
        bail!(
            "invalid --param {}: the set's {} = {at} is outside it, and the start is found there",
            a.plane.ranges[1],
            r2.param
        );
    }
    a.export.check()?;
    warn(warnings);
    Ok((p, [r1, r2]))
}

/// A system at the first range's start, the two ranges naming its parameters, and their box.
type Plane<S> = (S, [Range<<S as Oscillator>::Param>; 2], Box2);

impl PlaneArgs {
    /// `base` (the study's set or a model) at the first range's start, the two ranges naming
    /// its parameters, and their box: every end of both ranges checked as a value the parameter
    /// may take (the curves are followed up to the box's edges).
    pub(crate) fn resolve_on<S: Periodic>(&self, base: S) -> Result<Plane<S>> {
        let (params, specs) = (&self.params, &self.ranges);
        let ranges: Vec<Range<S::Param>> = specs
            .iter()
            .map(|r| Range::parse_for(r, &base).context("--param"))
            .collect::<Result<_>>()?;
        let [r1, r2] = ranges[..] else {
            bail!(
                "--param is needed exactly twice (NAME=LO:HI[:log] for each of the two parameters), got {}",
                ranges.len()
            );
        };
        if r1.param == r2.param {
            bail!(
                "invalid --param: {} given twice; two different parameters are needed",
                r1.param
            );
        }
        params.not_given(&r1.param.to_string(), "--param sets")?;
        for r in [r1, r2] {
            for end in [r.from, r.to] {
                base.with(r.param, end).context("--param")?;
            }
        }
        let p = base.with(r1.param, r1.from).context("--param")?;
        let box2 = Box2::of([r1, r2]);
        box2.validate().context("--param")?;
        Ok((p, [r1, r2], box2))
    }
}

pub fn run(a: Continue2Args) -> Result<()> {
    if let (Some(spec), Some(out)) = (&a.restart, &a.export.out) {
        let file = spec.rsplit_once(':').map_or(spec.as_str(), |(f, _)| f);
        crate::sink::check_not_input(out, [std::path::Path::new(file)], "the --restart file")?;
    }
    let (kind, nth) = CurveKind::parse_start(&a.from).context("--from")?;
    let (system, warnings) = a.plane.params.resolve_system()?;
    hdgear::on_subject!(system, |s| curves_of(&a, s, kind, nth, &warnings))
}

/// The curves of `base`, the study's set or a model, written and summarised.
fn curves_of<S: Periodic>(
    a: &Continue2Args,
    base: S,
    kind: CurveKind,
    nth: Option<usize>,
    warnings: &[hdgear::params::Warning],
) -> Result<()> {
    let (p, [r1, r2]) = request(a, base, warnings)?;
    let progress = crate::sink::PointsProgress::new("continue2");
    let opts = ContinuationOptions {
        progress: Some(progress.counter()),
        ..ContinuationOptions::default()
    };
    let mut curves = match &a.restart {
        Some(spec) => vec![restart(spec, &p, [r1, r2], &opts)?],
        None => curves_from_branch(&p, [r1, r2], kind, nth, a.subharmonic, &opts)
            .with_context(|| format!("--from {}", a.from))?,
    };
    if a.switch {
        let more = curves_at_gpds(&p, [r1, r2], &curves, &opts).context("--switch")?;
        curves.extend(more);
    }
    drop(progress);
    let doc = Doc {
        params: p,
        ranges: [r1, r2],
        options: opts,
        curves: &curves,
    };
    let rows = || {
        curves
            .iter()
            .enumerate()
            .flat_map(|(i, c)| CurveRow::of(i, c))
    };
    let names = [r1.param.to_string(), r2.param.to_string()];
    let figure = || {
        let logs = [r1.scale, r2.scale].map(|s| s == Scale::Log);
        hdgear::figures::plane_figure::<_, S::Param>(&curves, &[], [&names[0], &names[1]], logs)
    };
    a.export.write(&doc, rows, figure)?;
    a.export.print(&doc, || summary(&curves, &names))
}

/// The curve through row ROW of FILE (`--restart FILE:ROW`): its kind, period, parameters and
/// orbit start are the row's; the start is corrected onto the curve and refused with the reason
/// when it is not near one.
fn restart<O: Oscillator>(
    spec: &str,
    p: &O,
    [r1, r2]: [Range<O::Param>; 2],
    opts: &ContinuationOptions,
) -> Result<Curve2<O::Param>> {
    use hdgear::output::Record;
    let bad = |why: String| anyhow::anyhow!("invalid --restart '{spec}': {why}");
    let (path, row) = spec
        .rsplit_once(':')
        .ok_or_else(|| bad("expected FILE:ROW".into()))?;
    let row: usize = row
        .trim()
        .parse()
        .map_err(|_| bad(format!("ROW '{row}' is not a row number (from 0)")))?;
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .map_err(|e| bad(format!("cannot read {path}: {e}")))?;
    let head = rdr.headers().map_err(|e| bad(e.to_string()))?.clone();
    if head.iter().ne(CurveRow::COLUMNS.iter().copied()) {
        return Err(bad(format!(
            "{path} is not a continue2 --out CSV file (its columns differ)"
        )));
    }
    let rec = rdr
        .records()
        .nth(row)
        .ok_or_else(|| bad(format!("{path} has no row {row}")))?
        .map_err(|e| bad(e.to_string()))?;
    let field = |name: &str| {
        let i = head.iter().position(|h| h == name).unwrap_or(0);
        rec.get(i).unwrap_or("")
    };
    let num = |name: &str| {
        field(name).parse::<f64>().map_err(|_| {
            bad(format!(
                "row {row}: {name} '{}' is not a number",
                field(name)
            ))
        })
    };
    let (kind, _) = CurveKind::parse_start(field("kind")).map_err(|e| bad(e.to_string()))?;
    let k: u32 = field("subharmonic")
        .parse()
        .map_err(|_| bad(format!("row {row}: subharmonic '{}'", field("subharmonic"))))?;
    let (v1, v2) = (num("param1")?, num("param2")?);
    let o = p
        .with(r1.param, v1)
        .and_then(|o| o.with(r2.param, v2))
        .map_err(|e| bad(e.to_string()))?;
    let start = [num("x0")?, num("xdot0")?];
    let box2 = Box2::of([r1, r2]);
    continue_curve(&o, [r1.param, r2.param], kind, k, start, &box2, opts)
        .with_context(|| format!("--restart {spec}"))
}

/// `NAME lo … hi`: the range of a curve's values of one parameter (its summary line).
pub(crate) fn extent(name: impl std::fmt::Display, values: impl Iterator<Item = f64>) -> String {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
        (l.min(x), h.max(x))
    });
    format!("{name} {lo:.6} … {hi:.6}")
}

fn end_text(e: End) -> &'static str {
    match e {
        End::Reached => "left the box",
        End::MaxPoints => "stopped at the point limit",
        End::Closed => "closed on itself",
        End::StepTooSmall { .. } => "the step fell below its minimum",
        End::Rejoined { .. } => "at another generalised period doubling",
        End::Switched => "switched onto at a generalised period doubling",
    }
}

fn summary<P>(curves: &[Curve2<P>], names: &[String; 2]) -> Result<()> {
    for (i, c) in curves.iter().enumerate() {
        let extent = |j: usize| extent(&names[j], c.points.iter().map(|q| q.params[j]));
        outln!(
            "curve {i}: {}, period {} × 2π/ω, {} points, {}, {}; ends: {}, {}",
            c.kind.name(),
            c.subharmonic,
            c.points.len(),
            extent(0),
            extent(1),
            end_text(c.ends[0]),
            end_text(c.ends[1])
        );
        let worst = c
            .points
            .iter()
            .map(|q| {
                q.multipliers[0]
                    .log_abs
                    .abs()
                    .min(q.multipliers[1].log_abs.abs())
            })
            .fold(0.0f64, f64::max);
        outln!("  critical multiplier within {worst:.1e} of the unit circle at every point");
        for q in c.points.iter().filter(|q| q.special.is_some()) {
            outln!(
                "  {:<10} {} = {:.10}  {} = {:.10}",
                q.special.map_or("", Codim2::name),
                names[0],
                q.params[0],
                names[1],
                q.params[1]
            );
        }
    }
    Ok(())
}
