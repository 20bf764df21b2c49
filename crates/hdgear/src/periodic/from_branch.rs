//! Two-parameter curves started from a one-parameter branch: the special points a continuation
//! in the first parameter finds are the starts of the curves ([`curves_from_branch`]), and the
//! generalised period doublings on period-doubling curves those of the doubled orbits' fold
//! curves ([`curves_at_gpds`]): what `hdgear continue2` and Python's `continuation2` run.

use super::{
    Box2, Codim2, ContinuationOptions, Curve2, CurveKind, Oscillator, Range, continue_curve,
};
use crate::error::{Error, Result};

/// The curves of `kind` through the special points of that kind (every one, or only the `nth`,
/// counted from one) of the one-parameter branch of `p` in the first range's parameter from its
/// `from` to its `to` (the second parameter at its value in `p`), each curve once: a special
/// point on a curve already traced is skipped (the curve's crossings of the line λ₂ = p's value
/// are corrected onto it and compared, to 1e-6). `p` is the study's set or any smooth model
/// ([`Oscillator`]), its parameters named by the ranges.
pub fn curves_from_branch<O: Oscillator>(
    p: &O,
    [r1, r2]: [Range<O::Param>; 2],
    kind: CurveKind,
    nth: Option<usize>,
    k: u32,
    opts: &ContinuationOptions,
) -> Result<Vec<Curve2<O::Param>>> {
    use super::{Special, continue_orbit};
    let start = p.with(r1.param, r1.from)?;
    let box2 = Box2::of([r1, r2]);
    box2.validate()?;
    super::check_orbit_length(p, [r1.param, r2.param], k, &box2)?;
    let at = start.get(r2.param);
    let one = ContinuationOptions {
        scale: r1.scale,
        ..*opts
    };
    let branch = continue_orbit(&start, r1.param, k, None, r1.to, &one)?;
    let want = match kind {
        CurveKind::Fold => Special::Fold,
        CurveKind::PeriodDoubling => Special::PeriodDoubling,
    };
    let all: Vec<_> = branch
        .specials()
        .filter(|q| q.special == Some(want))
        .collect();
    let bad = |text: String, reason: String| Error::InvalidInput {
        what: "start",
        text,
        reason,
    };
    let starts = match nth {
        None => all,
        Some(n) => match all.get(n.wrapping_sub(1)) {
            Some(q) => vec![*q],
            None => {
                let reason = format!(
                    "the branch in {} has {} {}s",
                    r1.param,
                    all.len(),
                    kind.name()
                );
                return Err(bad(format!("{}:{n}", kind.name()), reason));
            }
        },
    };
    if starts.is_empty() {
        let reason = format!(
            "no {} on the branch in {} from {} to {} at {} = {at}: nothing to continue (try \
             another range or start)",
            kind.name(),
            r1.param,
            r1.from,
            r1.to,
            r2.param
        );
        return Err(bad(kind.name().to_string(), reason));
    }
    let mut curves: Vec<Curve2<O::Param>> = Vec::new();
    for s in starts {
        let mut seen = false;
        for c in &curves {
            let xs = c.crossings(&start, (1, at), &box2, opts)?;
            seen |= xs
                .iter()
                .any(|x| (x.params[0] - s.param).abs() <= 1e-6 * (1.0 + s.param.abs()));
        }
        if !seen {
            let o = start.with(r1.param, s.param)?;
            let params = [r1.param, r2.param];
            curves.push(continue_curve(&o, params, kind, k, s.start, &box2, opts)?);
        }
    }
    Ok(curves)
}

/// The fold curves of the doubled orbits born at the generalised period doublings of the
/// period-doubling curves `pd` of `p` (in the box of `ranges`, as from [`curves_from_branch`]),
/// switched onto at each GPD ([`switch_at_gpd`](super::switch_at_gpd)), each curve once: a GPD
/// where a curve already traced ends is skipped. Fold curves in `pd` are refused.
pub fn curves_at_gpds<O: Oscillator>(
    p: &O,
    ranges: [Range<O::Param>; 2],
    pd: &[Curve2<O::Param>],
    opts: &ContinuationOptions,
) -> Result<Vec<Curve2<O::Param>>> {
    if let Some(c) = pd.iter().find(|c| c.kind != CurveKind::PeriodDoubling) {
        return Err(Error::InvalidInput {
            what: "switch",
            text: c.kind.name().to_string(),
            reason: "switching is at generalised period doublings: period-doubling curves only"
                .into(),
        });
    }
    let box2 = Box2::of(ranges);
    let mut curves: Vec<Curve2<O::Param>> = Vec::new();
    for c in pd {
        for g in c
            .points
            .iter()
            .filter(|q| q.special == Some(Codim2::GeneralisedPeriodDoubling))
        {
            let same = |q: &super::CurvePoint2| {
                (0..2)
                    .all(|i| (q.params[i] - g.params[i]).abs() <= 1e-9 * (1.0 + g.params[i].abs()))
            };
            let seen = curves
                .iter()
                .any(|l| l.points.first().is_some_and(same) || l.points.last().is_some_and(same));
            if !seen {
                curves.push(super::switch_at_gpd(p, c, g, &box2, opts)?);
            }
        }
    }
    Ok(curves)
}

impl Box2 {
    /// The box of two continuation ranges (each from its lower end to its upper one).
    pub fn of<P>(ranges: [Range<P>; 2]) -> Box2 {
        Box2 {
            ranges: [0, 1].map(|i| {
                let r = &ranges[i];
                (r.from.min(r.to), r.from.max(r.to))
            }),
            scales: [0, 1].map(|i| ranges[i].scale),
        }
    }
}
