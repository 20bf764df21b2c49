//! Identification: a law's parameters fitted to measured data, with intervals that can be
//! trusted and a warning where the data do not determine them.
//!
//! The law is the model's own terms ([`FitLaw`]: Stribeck, sticking Coulomb, LuGre, Dahl,
//! Bouc–Wen, a piecewise or cubic stiffness, in the data's SI units); the data a friction sweep
//! or a quasi-static torque–twist loop ([`Data`]). [`fit`] minimises the weighted output error by
//! Levenberg–Marquardt with the gradients of the forward sensitivities ([`predict`]), from a
//! Sobol design of starts in the bounds, and reports:
//!
//! - each estimate's standard error and 95 % interval from JᵀJ (scaled by the residual noise
//!   estimate, t with n − k degrees of freedom), and the profile-likelihood interval, which is
//!   the one to trust where the two differ;
//! - the correlation matrix;
//! - the parameter combinations the data do not determine, from the small eigenvalues of the
//!   scaled JᵀJ.
//!
//! ```
//! use hdgear::fit::{fit, Data, DataKind, Free, FitLaw, FitOptions};
//! use hdgear::model::terms::AnyTerm;
//! // a Coulomb–Stribeck–viscous law, measured at 40 speeds
//! let truth = AnyTerm::new("coulomb", &[0.5, 0.8, 0.02, 0.3]).unwrap();
//! let v: Vec<f64> = (1..=40).map(|i| 0.002 * 1.15_f64.powi(i)).collect();
//! let tau: Vec<f64> = v.iter().map(|&v| truth.torque(0.0, v, 0.0)).collect();
//! let (data, _) = Data::new(DataKind::Friction, v, tau, None).unwrap();
//! let start = FitLaw::new(vec![AnyTerm::new("coulomb", &[1.0, 1.0, 0.1, 0.0]).unwrap()]).unwrap();
//! let free = ["fc=0:5", "fs=0:5", "vst=1e-4:1", "cv=0:2"].map(|f| f.parse::<Free>().unwrap());
//! let result = fit(&start, &data, &free, &FitOptions::default()).unwrap();
//! assert!((result.estimates[1].value - 0.8).abs() < 1e-9);
//! ```
//!
//! **Why one file.** The fit's steps (multistart design, Levenberg–Marquardt, covariance,
//! identifiability, profiles) all read and fill the one `Fit` it returns; the data, the laws, the
//! solver and the statistics live in their own files.

mod card;
mod data;
mod figure;
mod law;
mod linalg;
mod lm;
mod predict;
mod reference;
mod stats;

pub use card::{citation, fitted_card};
pub use data::{
    Column, Data, DataKind, DataSource, MeasuredQuantity, SPEED, TORQUE, TWIST, units_text,
};
pub use figure::figure;
pub use law::{FitLaw, LawParam};
pub use lm::{Residuals, Stop};
pub use reference::{ERGOCUB_TOML, JointFriction, ergocub};
pub use stats::t_quantile;

use crate::error::{Error, Result};
use crate::robust::sequence::{Points, Sampler};
use lm::Minimum;
use predict::Problem;
use rayon::prelude::*;
use serde::Serialize;

/// The confidence level of the intervals.
pub const LEVEL: f64 = 0.95;
/// An eigenvalue of the scaled JᵀJ (unit diagonal) below this fraction of the largest marks a
/// direction the data do not see at all: J's columns are dependent there to 1e-5 relative, far
/// below any measurement's resolution and far above the 1e-13 to which J is computed.
const NULL_DIRECTION: f64 = 1e-10;
/// A parameter whose full change (100 % of its value) moves the weighted prediction by less
/// than this fraction of the data's norm is one the data do not depend on: rounding in the
/// derivatives is about 1e-16, any measurable effect far above.
const DEAD: f64 = 1e-10;
/// A combination whose standard error exceeds its parameters' bounds is known less well from
/// the data than from the bounds the user gave: warned about (its intervals are wide, and kept).
const WIDER_THAN_BOUNDS: f64 = 1.0;
/// The profile interval is called quadratic where its ends lie within this fraction of the
/// JᵀJ half-width of the JᵀJ interval's: a 10 % wider or narrower interval changes a nominal
/// 95 % coverage by about 2 %, the scale of the coverage test's own sampling error.
const QUADRATIC: f64 = 0.1;

/// A parameter to free, with its bounds: `name=lo:hi`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Free {
    /// The parameter's name (`fs` or `coulomb.fs`).
    pub name: String,
    /// Its lower bound.
    pub lo: f64,
    /// Its upper bound.
    pub hi: f64,
}

impl std::str::FromStr for Free {
    type Err = Error;
    fn from_str(s: &str) -> Result<Free> {
        let bad = |reason: &str| Error::InvalidInput {
            what: "free parameter",
            text: s.into(),
            reason: reason.into(),
        };
        let (name, range) = s.split_once('=').ok_or_else(|| bad("write NAME=LO:HI"))?;
        let (lo, hi) = range
            .split_once(':')
            .ok_or_else(|| bad("write NAME=LO:HI"))?;
        let number = |t: &str| {
            t.trim()
                .parse::<f64>()
                .map_err(|_| bad("its bounds must be numbers"))
        };
        let (lo, hi) = (number(lo)?, number(hi)?);
        if !(lo < hi && (hi - lo).is_finite()) {
            return Err(bad(
                "its bounds must be finite with LO < HI (and HI − LO finite)",
            ));
        }
        Ok(Free {
            name: name.trim().into(),
            lo,
            hi,
        })
    }
}

/// How a fit runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FitOptions {
    /// Starts: the law's own values, then a Sobol design in the bounds.
    pub starts: usize,
    /// The Sobol design's seed.
    pub seed: u64,
    /// Whether to compute the profile-likelihood intervals.
    pub profile: bool,
    /// Passes of a loop's measured path run before the compared one (preconditioning, as a
    /// test cycles the drive before recording).
    pub repeat: usize,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            starts: 16,
            seed: 1,
            profile: true,
            repeat: 0,
        }
    }
}

/// The most starts: each is a whole minimisation, and past a thousand Sobol points the design
/// covers bounds of a handful of parameters finer than their minima are apart.
pub const MAX_STARTS: usize = 1024;
/// The most preconditioning passes of a loop's path: a test cycles a drive a few times before
/// recording, and a rate-independent loop settles within a few cycles.
pub const MAX_REPEAT: usize = 1000;

/// A warning about the data or the fit: what it means and what to change.
#[derive(Clone, Debug, PartialEq, Serialize, thiserror::Error)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum FitWarning {
    /// Rows were left out.
    #[error("{count} rows left out ({why}), the first at line {first_line}")]
    DroppedRows {
        /// How many.
        count: usize,
        /// The first one's line in the file (1: the header).
        first_line: usize,
        /// Why.
        why: &'static str,
    },
    /// A parameter combination the data do not determine.
    #[error(
        "the data do not determine {combination} ({why}): fix one of its parameters, or measure where it matters"
    )]
    Undetermined {
        /// The combination, e.g. `0.71·sigma0 − 0.70·sigma1` or `lugre.sigma0`.
        combination: String,
        /// Why: not seen at all, or its relative standard error.
        why: String,
    },
    /// An estimate sits on its bound.
    #[error(
        "{name} = {value:e} sits on its bound: its interval is not valid; widen its free range ({name}=LO:HI) if the law allows"
    )]
    AtBound {
        /// The parameter.
        name: String,
        /// Its estimate.
        value: f64,
    },
    /// The best start did not converge.
    #[error(
        "the fit did not converge in {iterations} iterations: give a start closer to the data (a scenario file with the term's values) or narrower bounds"
    )]
    NotConverged {
        /// Iterations used.
        iterations: usize,
    },
    /// Only one start reached the best minimum.
    #[error(
        "only {at_best} of {starts} starts reached the best fit: the sum of squares has other minima; more starts would show whether a better one exists"
    )]
    FewStartsAtBest {
        /// Starts that reached the best.
        at_best: usize,
        /// Starts run.
        starts: usize,
    },
}

/// A profile-likelihood interval.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Profile {
    /// Its lower end.
    pub lo: f64,
    /// Its upper end.
    pub hi: f64,
    /// Whether the lower end is the bound (the profile did not rise enough before it).
    pub lo_open: bool,
    /// Whether the upper end is the bound.
    pub hi_open: bool,
}

/// One fitted parameter.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Estimate {
    /// `kind.name`.
    pub name: String,
    /// The estimate.
    pub value: f64,
    /// Its standard error from JᵀJ (None where the data do not determine it).
    pub std_error: Option<f64>,
    /// value ± t·std_error.
    pub wald: Option<[f64; 2]>,
    /// The profile-likelihood interval, if computed.
    pub profile: Option<Profile>,
    /// Whether the profile agrees with the JᵀJ interval (within 10 % of its half-width).
    pub quadratic: Option<bool>,
}

impl Estimate {
    /// The interval to report: the profile's where computed, else the JᵀJ one.
    pub fn interval(&self) -> Option<[f64; 2]> {
        self.profile.map(|p| [p.lo, p.hi]).or(self.wald)
    }
}

/// A fit's result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fit {
    /// The kind of data fitted.
    pub kind: DataKind,
    /// Where the data come from.
    pub source: DataSource,
    /// The fitted law.
    pub law: FitLaw,
    /// The free parameters' estimates, in the order given.
    pub estimates: Vec<Estimate>,
    /// Their covariance (NaN where undetermined).
    pub covariance: Vec<Vec<f64>>,
    /// Their correlation.
    pub correlation: Vec<Vec<f64>>,
    /// The eigenvalues of JᵀJ scaled to a unit diagonal, ascending: the data's view of each
    /// direction in the parameters (near 0: a direction they do not see).
    pub spectrum: Vec<f64>,
    /// The data's abscissa (speed or twist, SI).
    pub x: Vec<f64>,
    /// The measured torques.
    pub measured: Vec<f64>,
    /// The fitted law's torques.
    pub predicted: Vec<f64>,
    /// Weighted residuals (predicted − measured)/sd.
    pub residuals: Vec<f64>,
    /// Their sum of squares.
    pub ssr: f64,
    /// Degrees of freedom n − k.
    pub dof: usize,
    /// The noise estimate √(SSR/(n − k)) in the residuals' units (N m where unweighted; about 1
    /// where the file's standard deviations are right).
    pub noise: f64,
    /// t for the 95 % intervals.
    pub t: f64,
    /// Starts run.
    pub starts: usize,
    /// Starts whose minimum equals the best to 1e-6 of its sum of squares.
    pub starts_at_best: usize,
    /// The best start's iterations.
    pub iterations: usize,
    /// Why the best minimisation stopped.
    pub stop: Stop,
    /// What to know before using the result.
    pub warnings: Vec<FitWarning>,
}

impl Fit {
    /// Whether the best minimisation converged.
    pub fn converged(&self) -> bool {
        self.stop != Stop::Iterations
    }
}

/// The torques `law` gives on the speeds or twists `x` of a kind of data (a loop's path run
/// `repeat` times first): what a fit compares with the measurements, and how synthetic data are
/// made.
pub fn predict(law: &FitLaw, kind: DataKind, x: &[f64], repeat: usize) -> Result<Vec<f64>> {
    Ok(evaluate(law, kind, x, &[], repeat)?.0)
}

/// ∂torque/∂p of [`predict`] for the parameters `names` (row-major, a row per point): the
/// forward sensitivities a fit's steps use.
pub fn jacobian(
    law: &FitLaw,
    kind: DataKind,
    x: &[f64],
    names: &[&str],
    repeat: usize,
) -> Result<Vec<f64>> {
    Ok(evaluate(law, kind, x, names, repeat)?.1)
}

fn evaluate(
    law: &FitLaw,
    kind: DataKind,
    x: &[f64],
    names: &[&str],
    repeat: usize,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let free: Vec<LawParam> = names.iter().map(|n| law.param(n)).collect::<Result<_>>()?;
    let data = Data {
        kind,
        x: x.to_vec(),
        torque: vec![0.0; x.len()],
        sd: None,
        source: DataSource {
            path: "(predicted)".into(),
            crc32: String::new(),
            rows: x.len(),
        },
    };
    let problem = Problem {
        law,
        free: &free,
        data: &data,
        repeat,
    };
    problem.check()?;
    let mut out = vec![0.0; x.len()];
    let mut jac = vec![0.0; x.len() * free.len()];
    problem.predict(law, &mut out, &mut jac)?;
    Ok((out, jac))
}

/// Fits `free`'s parameters of `law` (its other values held, its values the first start) to
/// `data`. Refused: unknown or repeated parameters, a start outside the bounds, fewer points
/// than free parameters + 1, a law the kind of data cannot determine.
pub fn fit(law: &FitLaw, data: &Data, free: &[Free], options: &FitOptions) -> Result<Fit> {
    let qs: Vec<LawParam> = free
        .iter()
        .map(|f| law.param(&f.name))
        .collect::<Result<_>>()?;
    for (i, q) in qs.iter().enumerate() {
        if qs[..i].contains(q) {
            return Err(Error::InvalidInput {
                what: "free parameter",
                text: free[i].name.clone(),
                reason: "given twice".into(),
            });
        }
    }
    let k = qs.len();
    if k == 0 {
        return Err(Error::InvalidInput {
            what: "free parameters",
            text: "(none)".into(),
            reason: "give at least one parameter to fit (NAME=LO:HI)".into(),
        });
    }
    if data.len() <= k {
        return Err(Error::InvalidInput {
            what: "data",
            text: data.source.path.clone(),
            reason: format!(
                "{} usable points for {k} free parameters: a fit needs at least {} (and many more for honest intervals)",
                data.len(),
                k + 1
            ),
        });
    }
    for (what, value, max) in [
        ("starts", options.starts, MAX_STARTS),
        ("repeat", options.repeat, MAX_REPEAT),
    ] {
        if value > max || (what == "starts" && value == 0) {
            return Err(Error::InvalidInput {
                what,
                text: value.to_string(),
                reason: format!("must be from {} to {max}", usize::from(what == "starts")),
            });
        }
    }
    let problem = Problem {
        law,
        free: &qs,
        data,
        repeat: options.repeat,
    };
    problem.check()?;
    let bounds: Vec<(f64, f64)> = free.iter().map(|f| (f.lo, f.hi)).collect();
    let starts = design(law, &qs, &bounds, options)?;
    let active: Vec<usize> = (0..k).collect();
    let minima: Vec<Result<Minimum>> = starts
        .par_iter()
        .map(|p0| lm::minimise(&problem, p0, &bounds, &active))
        .collect();
    // a start whose law is refused (a relation broken at the start) drops out
    let minima: Vec<Minimum> = minima.into_iter().filter_map(|m| m.ok()).collect();
    let best = minima
        .iter()
        .min_by(|a, b| a.ssr.total_cmp(&b.ssr))
        .ok_or_else(|| Error::InvalidInput {
            what: "fitted law",
            text: law.to_toml().replace('\n', " "),
            reason:
                "no start gave a valid law: check the bounds against the terms' rules (f_s ≥ f_c)"
                    .into(),
        })?
        .clone();
    let at_best = minima
        .iter()
        .filter(|m| m.ssr <= best.ssr * (1.0 + 1e-6) + 1e-300)
        .count();
    report(&problem, &bounds, best, (minima.len(), at_best), options)
}

/// The starts: the law's values (clamped into the bounds), then the first Sobol points the law
/// accepts (a relation such as f_s ≥ f_c rules some out; at most 64 tried per start wanted),
/// uniform in each bound, or log-uniform where the bounds are positive and span a decade or
/// more (a Stribeck speed, a stiffness).
fn design(
    law: &FitLaw,
    qs: &[LawParam],
    bounds: &[(f64, f64)],
    options: &FitOptions,
) -> Result<Vec<Vec<f64>>> {
    let first: Vec<f64> = qs
        .iter()
        .zip(bounds)
        .map(|(q, &(lo, hi))| law.get(q).clamp(lo, hi))
        .collect();
    let points = Points::new(Sampler::Sobol, options.seed, qs.len())?;
    let mut starts = vec![first];
    let mut u = vec![0.0; qs.len()];
    let tries = 64 * options.starts as u64;
    for i in 1..=tries {
        if starts.len() >= options.starts {
            break;
        }
        points.point(i, &mut u);
        let p: Vec<f64> = u
            .iter()
            .zip(bounds)
            .map(|(&u, &(lo, hi))| {
                if lo > 0.0 && hi >= 10.0 * lo {
                    lo * (hi / lo).powf(u)
                } else {
                    lo + (hi - lo) * u
                }
            })
            .collect();
        if law.with(qs, &p).is_ok() {
            starts.push(p);
        }
    }
    Ok(starts)
}

/// The result at the best minimum: covariance, intervals, identifiability.
fn report(
    problem: &Problem,
    bounds: &[(f64, f64)],
    best: Minimum,
    (starts, at_best): (usize, usize),
    options: &FitOptions,
) -> Result<Fit> {
    let (n, k) = (problem.data.len(), problem.free.len());
    let dof = n - k;
    let s2 = best.ssr / dof as f64;
    let t = t_quantile(LEVEL, dof as u64);
    let names: Vec<String> = problem.free.iter().map(|q| q.name.clone()).collect();
    let mut warnings = Vec::new();
    let (covariance, undetermined, spectrum) =
        identify(problem, bounds, &best, s2, &names, &mut warnings);
    let mut estimates: Vec<Estimate> = (0..k)
        .map(|j| {
            let var = covariance[j][j];
            let se = (!undetermined[j] && var.is_finite()).then(|| var.sqrt());
            Estimate {
                name: names[j].clone(),
                value: best.p[j],
                std_error: se,
                wald: se.map(|se| [best.p[j] - t * se, best.p[j] + t * se]),
                profile: None,
                quadratic: None,
            }
        })
        .collect();
    warnings.extend(estimates.iter().zip(bounds).filter_map(|(e, &(lo, hi))| {
        let on =
            (e.value - lo).abs() <= 1e-9 * (hi - lo) || (hi - e.value).abs() <= 1e-9 * (hi - lo);
        on.then(|| FitWarning::AtBound {
            name: e.name.clone(),
            value: e.value,
        })
    }));
    if options.profile && best.ssr > 0.0 {
        add_profiles(problem, bounds, &best, t, &mut estimates);
    }
    if best.stop == Stop::Iterations {
        warnings.push(FitWarning::NotConverged {
            iterations: best.iterations,
        });
    }
    // one start alone at the best: another region of the bounds may hold a better minimum
    if at_best == 1 && starts > 1 {
        warnings.push(FitWarning::FewStartsAtBest { at_best, starts });
    }
    let correlation = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| covariance[i][j] / (covariance[i][i] * covariance[j][j]).sqrt())
                .collect()
        })
        .collect();
    let law = problem.law.with(problem.free, &best.p)?;
    let mut predicted = vec![0.0; n];
    let mut scratch = vec![0.0; n * k];
    problem.predict(&law, &mut predicted, &mut scratch)?;
    Ok(Fit {
        kind: problem.data.kind,
        source: problem.data.source.clone(),
        law,
        estimates,
        covariance,
        correlation,
        spectrum,
        x: problem.data.x.clone(),
        measured: problem.data.torque.clone(),
        predicted,
        residuals: best.r,
        ssr: best.ssr,
        dof,
        noise: s2.sqrt(),
        t,
        starts,
        starts_at_best: at_best,
        iterations: best.iterations,
        stop: best.stop,
        warnings,
    })
}

/// [`covariance`] at the best minimum, with the parameters' sizes (their values, or their
/// bounds' width at 0) and the weighted data's norm it measures against.
fn identify(
    problem: &Problem,
    bounds: &[(f64, f64)],
    best: &Minimum,
    s2: f64,
    names: &[String],
    warnings: &mut Vec<FitWarning>,
) -> (Vec<Vec<f64>>, Vec<bool>, Vec<f64>) {
    let k = names.len();
    let (a, _) = linalg::normal_equations(&best.jac, &best.r, k);
    let widths: Vec<f64> = bounds.iter().map(|(lo, hi)| hi - lo).collect();
    let scales: Vec<f64> = best
        .p
        .iter()
        .zip(&widths)
        .map(|(p, w)| if *p != 0.0 { p.abs() } else { *w })
        .collect();
    let size = (0..problem.data.len())
        .map(|i| (problem.data.torque[i] / problem.weight(i)).powi(2))
        .sum::<f64>()
        .sqrt();
    covariance(&a, s2, &scales, &widths, size, names, warnings)
}

/// Each estimate's profile-likelihood interval ([`profile`], in parallel) and whether it agrees
/// with JᵀJ's ([`QUADRATIC`]).
fn add_profiles(
    problem: &Problem,
    bounds: &[(f64, f64)],
    best: &Minimum,
    t: f64,
    estimates: &mut [Estimate],
) {
    let dof = (problem.data.len() - estimates.len()) as f64;
    let threshold = best.ssr * (1.0 + t * t / dof);
    let profiles: Vec<Option<Profile>> = (0..estimates.len())
        .into_par_iter()
        .map(|j| {
            let step = estimates[j].std_error?;
            profile(problem, bounds, best, j, step, threshold)
        })
        .collect();
    for (e, p) in estimates.iter_mut().zip(profiles) {
        e.profile = p;
        e.quadratic = match (p, e.wald, e.std_error) {
            (Some(p), Some([lo, hi]), Some(se)) => {
                Some((p.lo - lo).abs().max((p.hi - hi).abs()) <= QUADRATIC * t * se)
            }
            _ => None,
        };
    }
}

/// The covariance s²(JᵀJ)⁻¹, through the eigendecomposition of JᵀJ scaled to a unit diagonal,
/// with what the data do not determine warned about: a parameter they do not depend on
/// ([`DEAD`]) and a direction they do not see ([`NULL_DIRECTION`]) have no interval; a direction
/// known less well than the bounds already say ([`WIDER_THAN_BOUNDS`]) keeps its (wide)
/// intervals. `scales` are the parameters' sizes (their values, or their bounds' width at 0),
/// `size` the weighted data's norm.
fn covariance(
    a: &[f64],
    s2: f64,
    scales: &[f64],
    widths: &[f64],
    size: f64,
    names: &[String],
    warnings: &mut Vec<FitWarning>,
) -> (Vec<Vec<f64>>, Vec<bool>, Vec<f64>) {
    let k = scales.len();
    let mut undetermined = vec![false; k];
    let diag: Vec<f64> = (0..k).map(|i| a[i * k + i]).collect();
    let (seen, dead): (Vec<usize>, Vec<usize>) =
        (0..k).partition(|&i| diag[i].sqrt() * scales[i] > DEAD * size);
    for &i in &dead {
        undetermined[i] = true;
        warnings.push(FitWarning::Undetermined {
            combination: names[i].clone(),
            why: "the data do not depend on it".into(),
        });
    }
    let m = seen.len();
    let scaled: Vec<f64> = (0..m * m)
        .map(|idx| {
            let (i, j) = (seen[idx / m], seen[idx % m]);
            a[i * k + j] / (diag[i] * diag[j]).sqrt()
        })
        .collect();
    let (values, vectors) = linalg::symmetric_eigen(&scaled, m);
    let largest = values.last().copied().unwrap_or(0.0);
    let mut cov = vec![vec![f64::NAN; k]; k];
    let mut inverse = vec![0.0; m * m];
    for (mu, v) in values.iter().zip(&vectors) {
        let null = *mu <= NULL_DIRECTION * largest;
        // one standard error along it, against each main parameter's bounds: the largest share
        let spread = (0..m)
            .filter(|&i| v[i].abs() > 0.1)
            .map(|i| (s2 / mu).sqrt() * (v[i] / diag[seen[i]].sqrt()).abs() / widths[seen[i]])
            .fold(0.0, f64::max);
        if null || spread > WIDER_THAN_BOUNDS {
            let combination = combination(v, &seen, names);
            let why = if null {
                "the data do not see this combination".to_string()
            } else {
                format!(
                    "its standard error is {:.0} % of the bounds' width",
                    100.0 * spread
                )
            };
            warnings.push(FitWarning::Undetermined { combination, why });
        }
        if null {
            (0..m)
                .filter(|&i| v[i].abs() > 0.1)
                .for_each(|i| undetermined[seen[i]] = true);
            continue;
        }
        for i in 0..m {
            for j in 0..m {
                inverse[i * m + j] += v[i] * v[j] / mu;
            }
        }
    }
    for i in 0..m {
        for j in 0..m {
            let (pi, pj) = (seen[i], seen[j]);
            cov[pi][pj] = s2 * inverse[i * m + j] / (diag[pi] * diag[pj]).sqrt();
        }
    }
    (cov, undetermined, values)
}

/// A unit direction of the scaled parameters as text: its components above 0.1, largest first.
fn combination(v: &[f64], seen: &[usize], names: &[String]) -> String {
    let mut parts: Vec<(f64, &str)> = v
        .iter()
        .zip(seen)
        .filter(|(c, _)| c.abs() > 0.1)
        .map(|(&c, &i)| (c, names[i].as_str()))
        .collect();
    parts.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
    if parts.len() == 1 {
        return parts[0].1.to_string();
    }
    let sign = if parts[0].0 < 0.0 { -1.0 } else { 1.0 };
    parts
        .iter()
        .enumerate()
        .map(|(i, (c, name))| {
            let c = c * sign;
            let op = if i == 0 {
                ""
            } else if c < 0.0 {
                " − "
            } else {
                " + "
            };
            format!("{op}{:.2}·{name}", if i == 0 { c } else { c.abs() })
        })
        .collect()
}

/// The profile-likelihood interval of parameter j: where the sum of squares minimised over the
/// others reaches `threshold` = SSR·(1 + t²/(n − k)) on each side (the F-test of one parameter),
/// found by doubling steps of `step` from the estimate, then regula falsi (to 1e-4 of `step`).
fn profile(
    problem: &Problem,
    bounds: &[(f64, f64)],
    best: &Minimum,
    j: usize,
    step: f64,
    threshold: f64,
) -> Option<Profile> {
    let k = best.p.len();
    let others: Vec<usize> = (0..k).filter(|&i| i != j).collect();
    let ssr_at = |value: f64, from: &[f64]| -> Option<(f64, Vec<f64>)> {
        let mut p0 = from.to_vec();
        p0[j] = value;
        let m = lm::minimise(problem, &p0, bounds, &others).ok()?;
        Some((m.ssr, m.p))
    };
    // g = √(SSR − SSR_min) − √(threshold − SSR_min): linear in the parameter where the profile
    // is quadratic, so regula falsi (Illinois) meets its root in a few fits
    let root = (threshold - best.ssr).sqrt();
    let g = |ssr: f64| (ssr - best.ssr).max(0.0).sqrt() - root;
    let end = |dir: f64| -> Option<(f64, bool)> {
        let bound = if dir > 0.0 { bounds[j].1 } else { bounds[j].0 };
        let (mut inside, mut from) = ((best.p[j], -root), best.p.clone());
        let mut width = step;
        loop {
            let trial = best.p[j] + dir * width;
            let at_bound = (trial - bound) * dir >= 0.0;
            let trial = if at_bound { bound } else { trial };
            let (ssr, p) = ssr_at(trial, &from)?;
            if ssr >= threshold {
                let done = |v: f64, w: f64| v.abs() <= 1e-6 * root || w <= 1e-4 * step;
                let found =
                    crate::roots::illinois::<_, ()>(inside, (trial, g(ssr)), 60, done, |x| {
                        Ok(ssr_at(x, &from).map(|(s, _)| (g(s), ())))
                    })
                    .ok()??;
                return Some((found.0, false));
            }
            if at_bound {
                return Some((bound, true));
            }
            inside = (trial, g(ssr));
            from = p;
            width *= 2.0;
        }
    };
    let (lo, lo_open) = end(-1.0)?;
    let (hi, hi_open) = end(1.0)?;
    Some(Profile {
        lo,
        hi,
        lo_open,
        hi_open,
    })
}
