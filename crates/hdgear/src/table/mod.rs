//! The study's two tables, with measured numbers: the γ table (curve shape, slopes, bursts, mode)
//! and the parameter-effects table (each parameter halved and doubled around the study's point).

pub mod render;

use crate::burst::{BurstOptions, Mechanism, Mode, Verdict, classify, response};
use crate::error::Result;
use crate::fast::analyze;
use crate::params::{Param, Params};
use crate::study::{Case, Study};
use rayon::prelude::*;
use serde::Serialize;

/// The study's γ values and the mode it reports for each.
pub const STUDY_GAMMAS: [(f64, Mode); 4] = [
    (30.0, Mode::Normal),
    (10.0, Mode::Transitional),
    (1.0, Mode::FastSlow),
    (0.1, Mode::PronouncedBursting),
];

/// Words for the curve's shape, derived from its largest |dx/da| on a ∈ [−1, 1] in decades:
/// < 1 "smooth and gradual" (x changes less than a), 1–10 "moderately steep", 10–100 "very steep,
/// sharp turn", ≥ 100 "extremely steep, near-vertical", infinite "folded (hysteresis)".
/// The study's four curves (0.47, 1.50, 15.3, 189.5) land in its four words.
pub fn shape_words(max_slope: f64) -> &'static str {
    if max_slope.is_infinite() {
        "folded (hysteresis)"
    } else if max_slope < 1.0 {
        "smooth and gradual"
    } else if max_slope < 10.0 {
        "moderately steep"
    } else if max_slope < 100.0 {
        "very steep, sharp turn"
    } else {
        "extremely steep, near-vertical"
    }
}

/// One row of the γ table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GammaRow {
    /// γ.
    pub gamma: f64,
    /// Shape words (see [`shape_words`]).
    pub shape: &'static str,
    /// Largest |dx/da| on a ∈ [−1, 1].
    pub max_slope: f64,
    /// dx/da at a = 0.
    pub slope_at_a0: f64,
    /// Bursts per slow period.
    pub bursts_per_period: f64,
    /// Mean spikes per burst.
    pub spikes_per_burst: f64,
    /// Largest |x'|.
    pub peak_abs_xdot: f64,
    /// The strongest signature measured.
    pub verdict: Verdict,
    /// Measured mode.
    pub mode: Mode,
    /// Mechanism.
    pub mechanism: Mechanism,
    /// The study's mode.
    pub study_mode: Mode,
    /// Measured mode equals the study's.
    pub agrees: bool,
}

/// One row of the parameter-effects table: a parameter at half and at twice its study value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EffectRow {
    /// Parameter name.
    pub parameter: &'static str,
    /// Lower value (half the study's).
    pub low: f64,
    /// Upper value (twice the study's).
    pub high: f64,
    /// Burst amplitude (mean peak |x'|) at low, high.
    pub amplitude: [f64; 2],
    /// Spikes per burst at low, high.
    pub spikes: [f64; 2],
    /// Quiescent duration at low, high.
    pub quiescent_duration: [f64; 2],
    /// Centre of the spiking area nearest a = 0 at low, high (NaN without one).
    pub spiking_center: [f64; 2],
    /// What was measured, in words, with the size of the change.
    pub measured: String,
    /// The study's claim.
    pub claim: &'static str,
    /// Whether the measurement supports the claim.
    pub verdict: ClaimVerdict,
}

/// What the measurement says of one of the study's claims.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum ClaimVerdict {
    /// The claim's own metric moves the claimed way (a change under 2 % counts as none).
    #[serde(rename = "agrees")]
    Agrees,
    /// It does not.
    #[serde(rename = "contradicts")]
    Contradicts,
    /// Neither end bursts, so a burst metric does not exist.
    #[serde(rename = "n/a (no bursts at either end)")]
    NoBursts,
    /// One end has no spiking area, so its location does not exist.
    #[serde(rename = "n/a (no spiking area at one end)")]
    NoSpikingArea,
}

impl ClaimVerdict {
    /// The words shown in tables (the serde name).
    pub fn name(self) -> &'static str {
        match self {
            ClaimVerdict::Agrees => "agrees",
            ClaimVerdict::Contradicts => "contradicts",
            ClaimVerdict::NoBursts => "n/a (no bursts at either end)",
            ClaimVerdict::NoSpikingArea => "n/a (no spiking area at one end)",
        }
    }
}

impl std::fmt::Display for ClaimVerdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

/// Both tables.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tables {
    /// The study's point (γ varies in the first table).
    pub base: Params,
    /// The γ table.
    pub gamma_table: Vec<GammaRow>,
    /// The parameter-effects table.
    pub effects_table: Vec<EffectRow>,
}

struct Measured {
    bursting: bool,
    amplitude: f64,
    spikes: f64,
    quiescent: f64,
    center: f64,
}

fn measure(p: &Params, opts: &BurstOptions) -> Result<Measured> {
    let r = response(p, opts)?;
    let an = analyze(p, crate::fast::A_RANGE)?;
    let center = an
        .equilibria
        .spiking_areas
        .iter()
        .map(|s| 0.5 * (s.a_min + s.a_max))
        .min_by(|u, v| u.abs().total_cmp(&v.abs()))
        .unwrap_or(f64::NAN);
    Ok(Measured {
        bursting: classify(p, &r).bursting,
        amplitude: r.rates.burst_amplitude,
        spikes: r.rates.spikes_per_burst,
        quiescent: r.rates.quiescent_duration,
        center,
    })
}

fn change(lo: f64, hi: f64) -> (&'static str, f64) {
    let rel = if lo != 0.0 { (hi - lo) / lo.abs() } else { 0.0 };
    if (hi - lo).abs() <= 0.02 * lo.abs().max(hi.abs()) {
        ("unchanged", rel)
    } else if hi > lo {
        ("increases", rel)
    } else {
        ("decreases", rel)
    }
}

/// Computes both tables at `base` (the study's point: `Params::default()`).
pub fn tables(base: &Params, opts: &BurstOptions) -> Result<Tables> {
    let mut study = Study::new(*opts, *opts, 0, 0, (0, 0));
    tables_in(&mut study, base)
}

/// Both tables at `base`, the γ table from (and into) `study`'s cases.
pub fn tables_in(study: &mut Study, base: &Params) -> Result<Tables> {
    base.validate()?;
    let points = STUDY_GAMMAS.map(|(gamma, _)| Params { gamma, ..*base });
    let opts = study.opts;
    let (cases, effects_table) =
        rayon::join(|| study.cases(&points), || effects_table(base, &opts));
    let gamma_table = cases?
        .into_iter()
        .zip(STUDY_GAMMAS)
        .map(|(c, (_, study_mode))| gamma_row(c, study_mode))
        .collect();
    Ok(Tables {
        base: *base,
        gamma_table,
        effects_table: effects_table?,
    })
}

/// The γ table's row of one case, against the mode the study reports.
pub fn gamma_row(case: &Case, study_mode: Mode) -> GammaRow {
    let (e, r, c) = (
        &case.analysis.equilibria,
        &case.response,
        &case.classification,
    );
    GammaRow {
        gamma: case.params.gamma,
        shape: shape_words(e.max_slope.value),
        max_slope: e.max_slope.value,
        slope_at_a0: e.slope_at_a0.unwrap_or(f64::NAN),
        bursts_per_period: r.rates.bursts_per_period.unwrap_or(f64::NAN),
        spikes_per_burst: r.rates.spikes_per_burst,
        peak_abs_xdot: r.rates.peak_abs_xdot,
        mode: c.mode,
        verdict: c.verdict,
        mechanism: c.mechanism,
        study_mode,
        agrees: c.mode == study_mode,
    }
}

/// The parameter-effects table: each parameter the study makes a claim about, halved and
/// doubled around `base`.
pub fn effects_table(base: &Params, opts: &BurstOptions) -> Result<Vec<EffectRow>> {
    let specs: [(Param, &'static str); 5] = [
        (
            Param::Gamma,
            "decreasing gamma gives steeper curves and stronger bursts",
        ),
        (
            Param::Alpha,
            "higher alpha strengthens the cubic term, possibly larger bursts",
        ),
        (
            Param::Delta,
            "larger delta makes the bursts more pronounced",
        ),
        (Param::Omega, "smaller omega lengthens the quiescent phases"),
        (
            Param::Eps,
            "increasing eps shifts the location of the spiking area",
        ),
    ];
    specs
        .par_iter()
        .map(|&(param, claim)| {
            let name = param.name();
            let v = base.value(param);
            let (low, high) = (0.5 * v, 2.0 * v);
            let (pl, ph) = (base.with(param, low), base.with(param, high));
            let (ml, mh) = (measure(&pl, opts)?, measure(&ph, opts)?);
            let (amp_dir, amp_rel) = change(ml.amplitude, mh.amplitude);
            let (spk_dir, _) = change(ml.spikes, mh.spikes);
            let (q_dir, q_rel) = change(ml.quiescent, mh.quiescent);
            let shift = mh.center - ml.center;
            let any_bursts = ml.bursting || mh.bursting;
            let shift_text = if shift.is_finite() {
                format!("moves by {shift:+.4} in a")
            } else {
                "n/a (no spiking area at one end)".to_string()
            };
            let measured = if any_bursts {
                format!(
                    "from {name} = {low} to {high}: burst amplitude {amp_dir} ({:+.1} %), spikes per \
                     burst {spk_dir} ({} to {}), quiescent duration {q_dir} ({:+.1} %), spiking-area \
                     centre {shift_text}",
                    100.0 * amp_rel,
                    ml.spikes,
                    mh.spikes,
                    100.0 * q_rel,
                )
            } else {
                format!(
                    "from {name} = {low} to {high}: no bursts at either end; spiking-area centre \
                     {shift_text}"
                )
            };
            // the claimed metric, in the claimed direction; None where it does not exist
            let holds = match param {
                Param::Gamma => any_bursts.then_some(amp_dir == "decreases"),
                Param::Alpha | Param::Delta => any_bursts.then_some(amp_dir == "increases"),
                Param::Omega => any_bursts.then_some(q_dir == "decreases"),
                Param::Eps | Param::Mu => shift.is_finite().then_some(shift.abs() > 1e-3),
            };
            Ok(EffectRow {
                parameter: name,
                low,
                high,
                amplitude: [ml.amplitude, mh.amplitude],
                spikes: [ml.spikes, mh.spikes],
                quiescent_duration: [ml.quiescent, mh.quiescent],
                spiking_center: [ml.center, mh.center],
                measured,
                claim,
                verdict: match holds {
                    Some(true) => ClaimVerdict::Agrees,
                    Some(false) => ClaimVerdict::Contradicts,
                    None if param == Param::Eps => ClaimVerdict::NoSpikingArea,
                    None => ClaimVerdict::NoBursts,
                },
            })
        })
        .collect()
}
