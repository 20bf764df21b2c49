//! The stroboscopic (Poincaré) orbit diagram: (x, x') at phase 0 of every forcing period after a
//! transient, against a parameter, each value started from the previous value's final state —
//! swept up and then down, so coexisting responses show as hysteresis.

use super::{Oscillator, Plain};
use crate::error::{Error, Result};
use crate::integrate::{Options, Stepper, stepper};
use serde::Serialize;
use std::f64::consts::TAU;

/// Options of the orbit diagram.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DiagramOptions {
    /// Forcing periods discarded at each value before recording. The previous value's state is
    /// close, so the transient is small, but near a fold or period doubling it decays as slowly
    /// as the critical multiplier (critical slowing down): 200 periods.
    pub discard: u32,
    /// Forcing periods recorded at each value.
    pub record: u32,
    /// Integrator tolerances; by default 1e-10 with Taylor's method at order 20, whose longer
    /// steps pay for the tangent's extra work per step ([`Options::order`]).
    pub tol: Options,
    /// Also the largest Lyapunov exponent at each value, averaged over this many forcing periods
    /// after the recorded ones (Benettin's estimate converges like 1/span: over 32 periods of
    /// ω = 6 it wanders by ±0.05 around the exact −1/2 of a focus-type orbit, over 400 by less
    /// than ±0.005).
    pub lyapunov: Option<u32>,
}

impl Default for DiagramOptions {
    fn default() -> Self {
        DiagramOptions {
            discard: 200,
            record: 32,
            tol: Options {
                order: Some(crate::integrate::taylor::MAX_ORDER),
                ..Options::default()
            },
            lyapunov: None,
        }
    }
}

/// The direction of a sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SweepDirection {
    /// Values in increasing order.
    Up,
    /// Values in decreasing order.
    Down,
}

impl SweepDirection {
    /// The name written in tables.
    pub fn name(self) -> &'static str {
        match self {
            SweepDirection::Up => "up",
            SweepDirection::Down => "down",
        }
    }
}

/// The recorded response at one parameter value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DiagramPoint {
    /// The parameter.
    pub param: f64,
    /// The sweep it belongs to.
    pub sweep: SweepDirection,
    /// (x, x') at phase 0 of each recorded period.
    pub section: Vec<[f64; 2]>,
    /// The least j ≤ record/2 with section\[i + j\] = section\[i\] for all i (to 1e-6 relative):
    /// the response's period in forcing periods; None if there is none (no periodic response
    /// within the record: quasi-periodic, chaotic or not settled).
    pub period: Option<u32>,
    /// The largest Lyapunov exponent per unit τ, when asked for.
    pub lyapunov: Option<f64>,
}

/// The most parameter values one orbit diagram takes: each value continues from the previous
/// one's state, so they run one after another on one core, each for 2·(discard + record)
/// forcing periods (420 at the defaults); 10⁵ values are already some 4·10⁷ periods, hours of
/// integration.
pub const MAX_DIAGRAM_VALUES: usize = 100_000;

/// Checks the number of values of an orbit diagram against [`MAX_DIAGRAM_VALUES`], before they are made.
pub fn check_diagram_values(count: usize) -> Result<()> {
    if count > MAX_DIAGRAM_VALUES {
        return Err(Error::InvalidOption {
            name: "values",
            value: count as f64,
            reason: "at most 100000 values (each runs after the previous one, on one core)",
        });
    }
    Ok(())
}

/// Relative tolerance for two section points to count as one.
pub const SAME_POINT: f64 = 1e-6;

fn least_period(section: &[[f64; 2]]) -> Option<u32> {
    let n = section.len();
    (1..=n / 2)
        .find(|&j| {
            (0..n - j).all(|i| {
                let (a, b) = (section[i], section[i + j]);
                (a[0] - b[0]).hypot(a[1] - b[1]) <= SAME_POINT * (1.0 + a[0].hypot(a[1]))
            })
        })
        .map(|j| j as u32)
}

/// The orbit diagram of `o` against `param` over `values` (increasing), swept up from the state
/// after `discard` periods from rest at the first value, then down from the last state. `each`
/// sees every point as it is computed (2 × values.len() calls), in groups of
/// [`LANES`](crate::batch::LANES) when Lyapunov exponents are asked for: those feed nothing
/// back, so a group's are computed together ([`Oscillator::lyapunov_each`]).
pub fn orbit_diagram<O: Oscillator>(
    o: &O,
    param: O::Param,
    values: &[f64],
    opts: &DiagramOptions,
    mut each: impl FnMut(DiagramPoint),
) -> Result<()> {
    opts.tol.validate()?;
    check_diagram_values(values.len())?;
    if opts.record < 2 {
        return Err(Error::InvalidOption {
            name: "record",
            value: f64::from(opts.record),
            reason: "must be ≥ 2 periods",
        });
    }
    if let Some(w) = values
        .windows(2)
        .find(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(Error::InvalidOption {
            name: "values",
            value: w[1],
            reason: "must increase",
        });
    }
    let tol = super::method_for::<O>(opts.tol);
    let mut oscillators = Vec::with_capacity(values.len());
    for &v in values {
        let q = o.with(param, v)?;
        crate::integrate::check_budget(
            TAU * f64::from(opts.discard + opts.record) / q.omega(),
            &tol,
        )?;
        oscillators.push(q);
    }
    let mut y = [0.0, 0.0];
    let order: Vec<(usize, SweepDirection)> = (0..values.len())
        .map(|i| (i, SweepDirection::Up))
        .chain((0..values.len()).rev().map(|i| (i, SweepDirection::Down)))
        .collect();
    // the values one after the other (each from the previous one's state), their Lyapunov
    // exponents (which feed nothing back) [`LANES`](crate::batch::LANES) values at a time;
    // without them each point goes out as soon as it is computed
    let group = if opts.lyapunov.is_some() {
        crate::batch::LANES
    } else {
        1
    };
    for group in order.chunks(group) {
        let mut points = Vec::with_capacity(group.len());
        let mut lyapunov_items = Vec::with_capacity(group.len());
        for &(i, sweep) in group {
            let q = &oscillators[i];
            y = advance(q, y, opts.discard, tol)?;
            let mut section = Vec::with_capacity(opts.record as usize);
            for _ in 0..opts.record {
                section.push(y);
                y = advance(q, y, 1, tol)?;
            }
            if let Some(periods) = opts.lyapunov {
                let t = TAU / q.omega();
                lyapunov_items.push((*q, y, (t, f64::from(periods.max(1)) * t)));
            }
            points.push(DiagramPoint {
                param: values[i],
                sweep,
                period: least_period(&section),
                section,
                lyapunov: None,
            });
        }
        if opts.lyapunov.is_some() {
            for (point, l) in points
                .iter_mut()
                .zip(O::lyapunov_each(&lyapunov_items, tol)?)
            {
                point.lyapunov = Some(l?);
            }
        }
        points.into_iter().for_each(&mut each);
    }
    Ok(())
}

/// The state at phase 0 after `periods` forcing periods from `y` at phase 0.
fn advance<O: Oscillator>(o: &O, y: [f64; 2], periods: u32, tol: Options) -> Result<[f64; 2]> {
    if periods == 0 {
        return Ok(y);
    }
    let end = TAU * f64::from(periods);
    if let Some(pieces) = o.pieces() {
        return super::saltation::motion(&pieces, y, end, tol, |_| {});
    }
    let sys = Plain(o, 1.0 / o.omega());
    let mut s = stepper(&sys, 0.0, y, super::method_for::<O>(tol))?;
    while s.t() < end {
        s.step(end)?;
    }
    Ok(*s.y())
}

/// One point of a Lyapunov map (`hdgear lyapunov-map`).
#[derive(Clone, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct LyapunovRow<V = crate::params::Params> {
    /// Grid index (first axis fastest).
    pub index: usize,
    /// The point's parameters (the study's six; a model's swept ones,
    /// [`crate::sweep::Values`]).
    #[record(nested)]
    pub params: V,
    /// The largest Lyapunov exponent per unit τ (NaN when the point failed).
    pub lyapunov: f64,
    /// The response's period in forcing periods (see [`DiagramPoint::period`]).
    pub period: Option<u32>,
    /// Empty, or the error that stopped this point.
    pub error: String,
}

/// The largest Lyapunov exponent at one parameter set: from the default start (the stable
/// equilibrium at a = 0, at rest), `opts.discard` periods settle, `opts.record` periods give the
/// period, then Benettin over `opts.lyapunov` periods (400 when None).
pub fn lyapunov_point(
    index: usize,
    p: &crate::params::Params,
    opts: &DiagramOptions,
) -> LyapunovRow {
    LyapunovRow::new(index, *p, lyapunov_of(p, opts).map_err(|e| e.to_string()))
}

/// The largest Lyapunov exponent of any system whose orbits the shooting computes (the study's
/// set, a smooth model) and the period of its response, as [`lyapunov_point`] measures them.
pub fn lyapunov_of<S: super::Periodic>(p: &S, opts: &DiagramOptions) -> Result<(f64, Option<u32>)> {
    p.check_periodic()?;
    let tol = super::method_for::<S>(opts.tol);
    let periods = opts.lyapunov.unwrap_or(400).max(1);
    let t = TAU / p.omega();
    crate::integrate::check_budget(t * f64::from(opts.discard + opts.record + periods), &tol)?;
    let start = p.default_start()?;
    let mut y = advance(p, start, opts.discard, tol)?;
    let mut section = Vec::with_capacity(opts.record as usize);
    for _ in 0..opts.record {
        section.push(y);
        y = advance(p, y, 1, tol)?;
    }
    let l = super::lyapunov(p, y, t, f64::from(periods) * t, tol)?;
    Ok((l, least_period(&section)))
}

impl<V> LyapunovRow<V> {
    /// The row of point `index` recorded as `point` from its (exponent, period) or the error
    /// that stopped it.
    pub(crate) fn new(
        index: usize,
        point: V,
        result: std::result::Result<(f64, Option<u32>), String>,
    ) -> LyapunovRow<V> {
        let (lyapunov, period, error) = match result {
            Ok((l, k)) => (l, k, String::new()),
            Err(e) => (f64::NAN, None, e),
        };
        LyapunovRow {
            index,
            params: point,
            lyapunov,
            period,
            error,
        }
    }
}

/// [`lyapunov_point`] for several (index, parameters) pairs at once: with Taylor's method
/// through the batch integrator ([`LANES`](crate::batch::LANES) points in lock-step: the settling
/// periods, each recorded period, then [`super::lyapunov_many`]), otherwise point by point. A
/// row does not depend on the points computed with it; it equals [`lyapunov_point`]'s up to the
/// integration's error (test `batched_lyapunov_rows_equal_one_by_one_rows`).
pub fn lyapunov_points(
    points: &[(usize, crate::params::Params)],
    opts: &DiagramOptions,
) -> Vec<LyapunovRow> {
    if opts.tol.method != crate::integrate::Method::Taylor {
        return points
            .iter()
            .map(|(i, p)| lyapunov_point(*i, p, opts))
            .collect();
    }
    let periods = opts.lyapunov.unwrap_or(400).max(1);
    // the points that can run; the others keep their error
    let checks: Vec<Result<()>> = points
        .iter()
        .map(|(_, p)| {
            p.validate()?;
            let span = TAU / p.omega * f64::from(opts.discard + opts.record + periods);
            crate::integrate::check_budget(span, &opts.tol)
        })
        .collect();
    let live: Vec<crate::params::Params> = points
        .iter()
        .zip(&checks)
        .filter(|(_, c)| c.is_ok())
        .map(|((_, p), _)| *p)
        .collect();
    // (fails as a whole only on bad input, which the checks above rule out)
    let measured = measure_batch(&live, opts, periods);
    let mut measured = match measured {
        Ok(m) => m
            .into_iter()
            .map(|r| r.map_err(|e| e.to_string()))
            .collect(),
        Err(e) => vec![Err(e.to_string()); live.len()],
    }
    .into_iter();
    points
        .iter()
        .zip(checks)
        .map(|((index, p), check)| {
            let result = match check {
                Ok(()) => measured
                    .next()
                    .unwrap_or_else(|| Err("no result for this point".into())),
                Err(e) => Err(e.to_string()),
            };
            LyapunovRow::new(*index, *p, result)
        })
        .collect()
}

/// One point's Lyapunov exponent and the period of its response.
type Measured = (f64, Option<u32>);

/// The settling periods, the recorded periods (each from phase 0) and Benettin's exponent of
/// every point, through the batch integrator: (exponent, the response's period) each.
fn measure_batch(
    points: &[crate::params::Params],
    opts: &DiagramOptions,
    periods: u32,
) -> Result<Vec<Result<Measured>>> {
    use crate::batch::integrate_batch_observed;
    let period = |p: &crate::params::Params| TAU / p.omega;
    let start = |p| crate::simulate::initial_state(p, crate::simulate::Start::Equilibrium);
    let mut state: Vec<Result<[f64; 2]>> = points.iter().map(|p| Ok(start(p))).collect();
    let mut sections = vec![Vec::with_capacity(opts.record as usize); points.len()];
    let current = |state: &[Result<[f64; 2]>]| -> Vec<[f64; 2]> {
        state
            .iter()
            .map(|y| *y.as_ref().unwrap_or(&[0.0; 2]))
            .collect()
    };
    // `discard` periods, then one period at a time for the record (a point that failed keeps
    // its error and is carried along from a dummy state)
    let legs = std::iter::once(opts.discard).chain((0..opts.record).map(|_| 1));
    for (leg, n) in legs.enumerate() {
        if leg > 0 {
            for (section, y) in sections.iter_mut().zip(&state) {
                if let Ok(y) = y {
                    section.push(*y);
                }
            }
        }
        if n == 0 {
            continue;
        }
        let spans: Vec<(f64, f64)> = points
            .iter()
            .map(|p| (f64::from(n) * period(p), f64::from(n) * period(p)))
            .collect();
        let ends = integrate_batch_observed(points, &current(&state), &spans, opts.tol, |_, _| {})?;
        for (y, end) in state.iter_mut().zip(ends) {
            if y.is_ok() {
                *y = end.map(|r| r.y);
            }
        }
    }
    let spans: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (period(p), f64::from(periods) * period(p)))
        .collect();
    let exponents = super::lyapunov_many(points, &current(&state), &spans, opts.tol)?;
    Ok(state
        .into_iter()
        .zip(exponents)
        .zip(sections)
        .map(|((y, l), section)| Ok((y.and(l)?, least_period(&section))))
        .collect())
}
