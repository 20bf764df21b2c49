//! The design check: how far a physical drive is from bursting, and which single change of k1,
//! k2, C, T_am, backlash or T_m moves it across, by how much.
//!
//! "Bursting" is decided as everywhere else: the drive is reduced to dimensionless form, its
//! response simulated and judged by its signatures ([`crate::burst::classify`]). When the reduced
//! ω is below [`MIN_SIMULATED_OMEGA`] (a slow period beyond 63,000 time units, too long to simulate
//! routinely) the prediction from the equilibrium curve ([`crate::fast::predict`]) decides
//! instead, and the result says so.
//!
//! For each parameter the factor f that first flips the verdict is searched on f = 2^k,
//! k = ±1 … ±6 (a change within ×1/64 … ×64; the side nearer to 1 wins), then refined by 12
//! bisections in log f (to 0.02 %). Both ends of the final bracket are reported with their
//! verdicts, so every margin shows the response just inside and just outside. A move that takes
//! the drive out of the fast-slow domain (the reduced ω no longer small against the relaxation
//! rate, or fast motion that never stops) is refused: past it the verdict has no fast-slow
//! meaning, and the margin says so instead of giving a factor.

use super::{DriveParam, PhysicalParams, Reduction};
use crate::burst::{BurstOptions, Verdict, classify, response};
use crate::error::Result;
use crate::fast::predict;
use rayon::prelude::*;
use serde::Serialize;

/// Parameters a designer can change, in the order reported (the mean load t_m too: it sets
/// where on the equilibrium curve the drive operates).
pub const DESIGN_PARAMETERS: [DriveParam; 6] = [
    DriveParam::K1,
    DriveParam::K2,
    DriveParam::CEq,
    DriveParam::TAm,
    DriveParam::Backlash,
    DriveParam::TM,
];

/// How a verdict was reached.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Basis {
    /// Simulated and judged by the signatures.
    Simulation,
    /// Predicted from the equilibrium curve (reduced ω too small to simulate).
    Prediction,
}

/// The verdict on one drive.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Judgement {
    /// Bursting or not.
    pub bursting: bool,
    /// The strongest signature (null when predicted).
    pub verdict: Option<Verdict>,
    /// Whether the drive is in the fast-slow domain.
    pub fast_slow_domain: bool,
    /// How it was decided.
    pub basis: Basis,
}

impl Judgement {
    /// The verdict of a simulated response, as its classification gives it.
    pub fn simulated(c: &crate::burst::Classification) -> Judgement {
        Judgement {
            bursting: c.bursting,
            verdict: Some(c.verdict),
            fast_slow_domain: c.fast_slow_domain,
            basis: Basis::Simulation,
        }
    }

    /// The verdict's name, or `bursting (predicted)` / `no-bursts (predicted)` when predicted.
    pub fn label(&self) -> &'static str {
        match (self.verdict, self.bursting) {
            (Some(v), _) => v.name(),
            (None, true) => "bursting (predicted)",
            (None, false) => "no-bursts (predicted)",
        }
    }
}

/// One end of a margin's final bracket.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BracketEnd {
    /// The factor applied to the parameter.
    pub factor: f64,
    /// The verdict there.
    pub judgement: Judgement,
}

impl std::fmt::Display for BracketEnd {
    /// `×1.2345 overshoot`: the factor and the verdict there.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "×{:.4} {}", self.factor, self.judgement.label())
    }
}

/// How one parameter moves the drive across the bursting boundary. `P` names the parameter: a
/// drive parameter here, a friction parameter in [`super::friction`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Margin<P = DriveParam> {
    /// Parameter name.
    pub parameter: P,
    /// Its current value (SI).
    pub current: f64,
    /// Multiplicative factor that crosses the boundary (null if none within 1/64…64, or refused).
    pub factor: Option<f64>,
    /// The value at the boundary (SI).
    pub boundary_value: Option<f64>,
    /// (factor − 1)·100.
    pub change_percent: Option<f64>,
    /// `enters bursting` or `leaves bursting`.
    pub effect: &'static str,
    /// The end of the bracket with the current verdict.
    pub inside: Option<BracketEnd>,
    /// The end of the bracket with the other verdict.
    pub outside: Option<BracketEnd>,
    /// Why no factor is given although the search went on: the move leaves the fast-slow domain,
    /// or a changed drive could not be judged.
    pub refused: Option<String>,
}

/// The design check of a drive.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignCheck {
    /// The reduction.
    pub reduced: Reduction,
    /// γ − 1/(3α) at the reduced point.
    pub gamma_margin: f64,
    /// a at the steepest point of the equilibrium curve, x = 1/(3α) (the slow variable covers
    /// [−1, 1]; the further outside, the further the drive is from the steep part).
    pub steepest_point_a: f64,
    /// max(0, |steepest_point_a| − 1): how far the slow variable would have to go beyond its
    /// range to reach the steep part (0 when it is reached).
    pub distance_in_a: f64,
    /// The prediction from the equilibrium curve.
    pub prediction: crate::fast::Prediction,
    /// The verdict on the drive as it is.
    pub judgement: Judgement,
    /// Predicted mode (null when not simulated).
    pub mode: Option<crate::burst::Mode>,
    /// Predicted mechanism (null when not simulated).
    pub mechanism: Option<crate::burst::Mechanism>,
    /// One entry per changeable parameter.
    pub margins: Vec<Margin>,
}

/// Below this reduced ω the prediction replaces simulation.
pub const MIN_SIMULATED_OMEGA: f64 = 1e-4;

/// Step budget of one simulated verdict in the search (a scaled drive can need very small
/// steps, e.g. C/64 makes the reduced γ 4096 times larger); past it the prediction decides.
pub const SEARCH_MAX_STEPS: u64 = 2_000_000;

/// Judges one drive (see the module docs).
pub fn judge(d: &PhysicalParams, opts: &BurstOptions) -> Result<Judgement> {
    Ok(judge_classified(d, opts)?.0)
}

/// [`judge`] for many drives at once, each verdict the one `judge` gives: the responses run as
/// batches of sixteen lanes ([`crate::burst::responses`]), the batches on all cores.
pub fn judge_many(ds: &[PhysicalParams], opts: &BurstOptions) -> Result<Vec<Judgement>> {
    judge_many_by(ds, PhysicalParams::reduce, opts)
}

/// [`judge_many`] with each wave generator held ([`PhysicalParams::reduce_held`]).
pub fn judge_many_held(ds: &[PhysicalParams], opts: &BurstOptions) -> Result<Vec<Judgement>> {
    judge_many_by(ds, PhysicalParams::reduce_held, opts)
}

/// The verdicts on many drives, each reduced by `reduce` (free or held input).
fn judge_many_by(
    ds: &[PhysicalParams],
    reduce: fn(&PhysicalParams) -> Result<Reduction>,
    opts: &BurstOptions,
) -> Result<Vec<Judgement>> {
    let reduced: Vec<crate::Params> = ds
        .iter()
        .map(|d| Ok(reduce(d)?.params))
        .collect::<Result<_>>()?;
    judge_sets(&reduced, opts)
}

/// The verdicts on many reduced sets, each the one [`judge`] gives its drive.
fn judge_sets(reduced: &[crate::Params], opts: &BurstOptions) -> Result<Vec<Judgement>> {
    let o = search_options(opts);
    // in order of ω: the lanes of a batch then run for about the same time (a run lasts a few
    // slow periods, 2π/ω each, and a batch as long as its longest lane)
    let mut simulated: Vec<usize> = (0..reduced.len())
        .filter(|&i| reduced[i].omega >= MIN_SIMULATED_OMEGA)
        .collect();
    simulated.sort_by(|&i, &j| reduced[i].omega.total_cmp(&reduced[j].omega));
    let points: Vec<crate::Params> = simulated.iter().map(|&i| reduced[i]).collect();
    // a few batches per task: enough tasks for the cores, whole batches for the lanes
    let responses: Vec<Result<crate::burst::Response>> = points
        .par_chunks(4 * crate::batch::LANES)
        .flat_map_iter(|chunk| crate::burst::responses(chunk, &o))
        .collect();
    let mut slots: Vec<Option<Result<crate::burst::Response>>> =
        (0..reduced.len()).map(|_| None).collect();
    for (i, r) in simulated.into_iter().zip(responses) {
        slots[i] = Some(r);
    }
    reduced
        .par_iter()
        .zip(slots)
        .map(|(p, s)| Ok(decide(p, s)?.0))
        .collect()
}

/// [`judge`], with the classification of the simulated response when there was one.
fn judge_classified(
    d: &PhysicalParams,
    opts: &BurstOptions,
) -> Result<(Judgement, Option<crate::burst::Classification>)> {
    judge_set(&d.reduce()?.params, opts)
}

/// The verdict on a drive's reduced set `p` (its free or its held reduction), with the
/// classification of the simulated response when there was one.
fn judge_set(
    p: &crate::Params,
    opts: &BurstOptions,
) -> Result<(Judgement, Option<crate::burst::Classification>)> {
    let o = search_options(opts);
    let simulated = (p.omega >= MIN_SIMULATED_OMEGA).then(|| response(p, &o));
    let (j, c, _) = decide(p, simulated)?;
    Ok((j, c))
}

/// The verdict on a drive's reduced set `p` as a [`DriveVerdict`] ([`judge`] on a reduction the
/// caller chose: [`PhysicalParams::reduce_held`]'s for a held wave generator).
pub fn outcome_of(p: &crate::Params, opts: &BurstOptions) -> Result<DriveVerdict> {
    let (judgement, c) = judge_set(p, opts)?;
    Ok(DriveVerdict {
        judgement,
        mode: c.map(|c| c.mode),
        mechanism: c.map(|c| c.mechanism),
    })
}

/// The options of one verdict: the step budget capped at [`SEARCH_MAX_STEPS`].
pub(crate) fn search_options(opts: &BurstOptions) -> BurstOptions {
    let mut o = *opts;
    o.tol.max_steps = o.tol.max_steps.min(SEARCH_MAX_STEPS);
    o
}

/// The simulated verdict on a drive's reduced model `m` with terms beyond the study's, and its
/// response; `None` when its load frequency is below [`MIN_SIMULATED_OMEGA`] (no
/// equilibrium-curve prediction covers such a model) or the response needs more steps than a
/// search allows ([`search_options`]).
pub(crate) fn judge_model(
    m: &crate::model::Model,
    opts: &BurstOptions,
) -> Result<Option<(DriveVerdict, crate::burst::Response)>> {
    if m.forcing()[2] < MIN_SIMULATED_OMEGA {
        return Ok(None);
    }
    let resp = match crate::burst::response_model(m, &search_options(opts)) {
        Ok(resp) => resp,
        Err(crate::Error::Solver(crate::error::SolverError::TooManySteps { .. })) => {
            return Ok(None);
        }
        Err(e) => return Err(e),
    };
    let c = crate::burst::classify_model(m, &resp)?;
    let outcome = DriveVerdict {
        judgement: Judgement::simulated(&c),
        mode: Some(c.mode),
        mechanism: Some(c.mechanism),
    };
    Ok(Some((outcome, resp)))
}

/// A verdict, its classification and its response (when simulated).
pub(crate) type Judged = (
    Judgement,
    Option<crate::burst::Classification>,
    Option<crate::burst::Response>,
);

/// The rule of the module docs for a reduced set `p` given its simulated response (None when ω
/// is below [`MIN_SIMULATED_OMEGA`]): the signatures decide, or the prediction when the response
/// was not simulated or ran out of steps.
fn decide(p: &crate::Params, simulated: Option<Result<crate::burst::Response>>) -> Result<Judged> {
    match simulated {
        Some(Ok(resp)) => {
            let c = classify(p, &resp);
            return Ok((Judgement::simulated(&c), Some(c), Some(resp)));
        }
        Some(Err(crate::Error::Solver(crate::error::SolverError::TooManySteps { .. }))) | None => {}
        Some(Err(e)) => return Err(e),
    }
    let j = Judgement {
        bursting: predict(p).bursting,
        verdict: None,
        fast_slow_domain: p.omega <= crate::burst::fast_slow_omega_max(p),
        basis: Basis::Prediction,
    };
    Ok((j, None, None))
}

/// [`judge`] of many reduced sets at once: the simulated ones on the sixteen-lane batches
/// ([`crate::burst::responses`]), in the order given.
pub(crate) fn judge_reduced(points: &[crate::Params], opts: &BurstOptions) -> Vec<Result<Judged>> {
    let o = search_options(opts);
    let simulate: Vec<crate::Params> = points
        .iter()
        .copied()
        .filter(|p| p.omega >= MIN_SIMULATED_OMEGA)
        .collect();
    let mut simulated = crate::burst::responses(&simulate, &o).into_iter();
    points
        .iter()
        .map(|p| {
            let r = (p.omega >= MIN_SIMULATED_OMEGA)
                .then(|| simulated.next())
                .flatten();
            decide(p, r)
        })
        .collect()
}

fn scaled(d: &PhysicalParams, param: DriveParam, f: f64) -> PhysicalParams {
    d.with(param, d.value(param) * f)
}

/// The margin of one parameter.
fn margin(
    d: &PhysicalParams,
    param: DriveParam,
    now: Judgement,
    opts: &BurstOptions,
) -> Result<Margin> {
    search_margin(param, d.value(param), now, |f| {
        judge(&scaled(d, param, f), opts).map(Some)
    })
}

/// The two ends of a search's bracket, each as (log2 of the factor, its verdict): the last one
/// with the drive's verdict and the first one with the other.
type Bracket = [(f64, Judgement); 2];

/// A search's bracket (`None`: no crossing), and why it stopped short.
type Crossing = (Option<Bracket>, Option<String>);

/// Why a factor has no verdict.
fn unjudged(f: f64) -> String {
    format!("x{f} cannot be judged (its response needs more steps than a search allows)")
}

/// The first f = 2^k, k = ±1 … ±6 (nearer to 1 first), whose verdict differs from `now`, with
/// the last f before it on that side (f = 1 is `now` itself) — or none, with why the search
/// stopped on a side (the first such reason).
fn first_crossing(
    now: Judgement,
    at_log: impl Fn(f64) -> Result<Option<Judgement>>,
) -> Result<Crossing> {
    let mut refused: Option<String> = None;
    let mut blocked = [false, false];
    let mut inside = [(0.0, now); 2];
    for k in 1..=6 {
        for (i, sign) in [-1.0, 1.0].into_iter().enumerate() {
            if blocked[i] {
                continue;
            }
            let lf = sign * f64::from(k);
            let Some(j) = at_log(lf)? else {
                blocked[i] = true;
                refused.get_or_insert_with(|| unjudged(lf.exp2()));
                continue;
            };
            if !j.fast_slow_domain {
                blocked[i] = true;
                refused.get_or_insert_with(|| {
                    format!(
                        "x{} leaves the fast-slow domain before the verdict changes",
                        lf.exp2()
                    )
                });
                continue;
            }
            if j.bursting != now.bursting {
                return Ok((Some([inside[i], (lf, j)]), None));
            }
            inside[i] = (lf, j);
        }
    }
    Ok((None, refused))
}

/// The margin of `parameter`, now `current` with verdict `now`, where `at(f)` judges the drive
/// with the parameter ×f (`None`: it cannot be judged, which stops the search on that side):
/// the search of the module docs, on f = 2^k, k = ±1 … ±6, then 12 bisections in log f.
pub(crate) fn search_margin<P>(
    parameter: P,
    current: f64,
    now: Judgement,
    at: impl Fn(f64) -> Result<Option<Judgement>>,
) -> Result<Margin<P>> {
    let at_log = |lf: f64| at(lf.exp2());
    let (found, refused) = if current == 0.0 {
        (None, Some("it is 0, which no factor changes".to_string()))
    } else {
        first_crossing(now, at_log)?
    };
    let mut margin = Margin {
        parameter,
        current,
        factor: None,
        boundary_value: None,
        change_percent: None,
        effect: if now.bursting {
            "leaves bursting"
        } else {
            "enters bursting"
        },
        inside: None,
        outside: None,
        refused: None,
    };
    let Some([(a, mut ja), (b, mut jb)]) = found else {
        margin.refused = refused;
        return Ok(margin);
    };
    // the bracket's ends were judged in the search; a point between them that cannot be judged
    // ends the margin without a factor (`Err(None)` below), as an unjudged end would
    let judged = |lf: f64| -> std::result::Result<Judgement, Option<crate::Error>> {
        at_log(lf).map_err(Some)?.ok_or(None)
    };
    let mut last = b;
    // twelve halvings in log2 of the factor: the bracket's ends are simulated and kept
    let bracket = crate::roots::try_bisect(a, b, 12, crate::roots::all_rounds, |m| {
        last = m;
        let j = judged(m)?;
        let same = j.bursting == now.bursting;
        if same {
            ja = j
        } else {
            jb = j
        }
        Ok(same)
    });
    let (a, b) = match bracket {
        Ok(ab) => ab,
        Err(Some(e)) => return Err(e),
        Err(None) => {
            margin.refused = Some(unjudged(last.exp2()));
            return Ok(margin);
        }
    };
    let f = (0.5 * (a + b)).exp2();
    margin.factor = Some(f);
    margin.boundary_value = Some(f * current);
    margin.change_percent = Some(100.0 * (f - 1.0));
    margin.inside = Some(BracketEnd {
        factor: a.exp2(),
        judgement: ja,
    });
    margin.outside = Some(BracketEnd {
        factor: b.exp2(),
        judgement: jb,
    });
    Ok(margin)
}

/// Runs the design check.
pub fn design_check(d: &PhysicalParams, opts: &BurstOptions) -> Result<DesignCheck> {
    let r = d.reduce()?;
    let p = r.params;
    // the drive as it is is simulated once: its judgement and its classification together
    let (judgement, classification) = judge_classified(d, opts)?;
    let (mode, mechanism) = (
        classification.map(|c| c.mode),
        classification.map(|c| c.mechanism),
    );
    // the parameters' searches are independent: side by side on the current thread pool (the
    // margins, and the first error if any, in DESIGN_PARAMETERS order whatever the thread count)
    let margins = DESIGN_PARAMETERS
        .par_iter()
        .map(|&name| margin(d, name, judgement, opts))
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
    let x0 = 1.0 / (3.0 * p.alpha);
    let steepest_point_a = p.a_at(x0);
    Ok(DesignCheck {
        reduced: r,
        steepest_point_a,
        distance_in_a: (steepest_point_a.abs() - 1.0).max(0.0),
        gamma_margin: p.gamma - p.critical_gamma(),
        prediction: predict(&p),
        judgement,
        mode,
        mechanism,
        margins,
    })
}

/// The catalogue entry a drive was built from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CatalogueOrigin {
    /// Catalogue name.
    pub name: String,
    /// The stiffness fit.
    pub fit: super::catalogue::CubicFit,
    /// What the preset assumes beyond the catalogue.
    pub assumptions: Vec<&'static str>,
}

/// The verdict on a drive as it is, with the mode and mechanism when it was simulated.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DriveVerdict {
    /// The verdict (its fields at the top level).
    #[serde(flatten)]
    pub judgement: Judgement,
    /// The mode (`None` when predicted).
    pub mode: Option<crate::burst::Mode>,
    /// The mechanism (`None` when predicted).
    pub mechanism: Option<crate::burst::Mechanism>,
}

/// What `hdgear physical` reports for a drive: the drive, where it came from, its reduction and
/// the verdict on it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DriveSummary {
    /// The drive.
    pub drive: PhysicalParams,
    /// Its catalogue origin.
    pub catalogue: CatalogueOrigin,
    /// The reduced dimensionless parameters.
    pub reduced: crate::params::Params,
    /// T = J/C \[s\].
    pub time_scale: f64,
    /// L \[rad\].
    pub length_scale: f64,
    /// J_eq \[kg m²\].
    pub j_eq: f64,
    /// α·ε of the reduced set (1 up to rounding).
    pub alpha_eps: f64,
    /// 1/(3α).
    pub critical_gamma: f64,
    /// γ − 1/(3α).
    pub gamma_margin: f64,
    /// ζ = C/(2√(k1 J_eq)): the damping ratio of the linear torsional mode (γ = 1/(4ζ²)).
    pub zeta: f64,
    /// 3αγ = 3k1/(k2φ²): the fast subsystem has folds iff it is below 1, whatever the damping.
    pub three_alpha_gamma: f64,
    /// The verdict.
    pub predicted: DriveVerdict,
}

/// The summary of drive `d` from `catalogue` (simulated when its reduced ω allows, see
/// [`judge`]).
pub fn summarize(
    d: &PhysicalParams,
    catalogue: CatalogueOrigin,
    opts: &BurstOptions,
) -> Result<DriveSummary> {
    let r = d.reduce()?;
    let p = r.params;
    let predicted = outcome_of(&p, opts)?;
    Ok(DriveSummary {
        drive: *d,
        catalogue,
        reduced: p,
        time_scale: r.time_scale,
        length_scale: r.length_scale,
        j_eq: r.j_eq,
        alpha_eps: p.alpha * p.eps,
        critical_gamma: p.critical_gamma(),
        gamma_margin: p.gamma - p.critical_gamma(),
        zeta: d.zeta_on(r.j_eq),
        three_alpha_gamma: 3.0 * p.alpha * p.gamma,
        predicted,
    })
}
