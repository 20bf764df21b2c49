//! The periodic orbit by shooting: Newton on the stroboscopic map, its amplitudes, whether it
//! bursts, and its least period.

use super::*;
use crate::model::{Model, ModelParam};
use crate::params::Param;

/// A periodic orbit of a forced system `S`: the study's set ([`Params`]) or a model assembled
/// from terms ([`Model`], serialised as its description).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeriodicOrbit<S = Params> {
    /// The system: its parameters.
    pub params: S,
    /// k: the orbit's period is k·2π/ω.
    pub subharmonic: u32,
    /// Its period k·2π/ω.
    pub period: f64,
    /// (x, x') at τ = 0 (the phase where a = sin ωτ = 0, rising).
    pub start: [f64; 2],
    /// |φ(y) − y| at the solution.
    pub residual: f64,
    /// Newton iterations taken.
    pub newton_iterations: usize,
    /// The two Floquet multipliers, the larger first.
    pub multipliers: [Multiplier; 2],
    /// ln|m1|, ln|m2|.
    pub log_abs_multipliers: [f64; 2],
    /// Floquet exponents ln|m|/period.
    pub floquet_exponents: [f64; 2],
    /// Both multipliers inside the unit circle.
    pub stable: bool,
    /// The smallest j dividing k with φ_{j·2π/ω}(start) = start (to 1e-8): 1 when the orbit
    /// asked for as a subharmonic is the period-1 orbit.
    pub minimal_subharmonic: u32,
    /// max |x'| over the orbit (located on the dense output, see [`Amplitude`]).
    pub max_abs_xdot: f64,
    /// Smallest and largest x.
    pub x_range: [f64; 2],
    /// Peak-to-peak amplitude of x.
    pub peak_to_peak: f64,
    /// For a model whose friction sticks: its rests on one period (then a rest forgets the
    /// speed, and the second multiplier is exactly 0, ln|m₂| = −∞, `null` in JSON).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rests: Option<Rests>,
    /// (τ, x, x') every `dt` over one period.
    #[serde(skip)]
    pub samples: Vec<[f64; 3]>,
}

/// How the neighbours of a periodic orbit behave, read from its multipliers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stability {
    /// Both multipliers inside the unit circle: nearby motion settles on the orbit.
    Stable,
    /// A multiplier outside (or on) the unit circle.
    Unstable,
    /// The drive rests all period (a sticking friction holds it): m₁ = 1 exactly, as every x
    /// near the rest, within the sticking band, rests too. Neither attracting nor repelling.
    RestsAllPeriod,
}

impl Stability {
    /// The word the command-line tool and the report print.
    pub fn name(self) -> &'static str {
        match self {
            Stability::Stable => "stable",
            Stability::Unstable => "unstable",
            Stability::RestsAllPeriod => "neutral (at rest all period)",
        }
    }
}

impl<S> PeriodicOrbit<S> {
    /// The orbit's [`Stability`].
    pub fn stability(&self) -> Stability {
        match self.rests {
            Some(r) if r.switches == 0 && r.time_stuck > 0.0 => Stability::RestsAllPeriod,
            _ if self.stable => Stability::Stable,
            _ => Stability::Unstable,
        }
    }
}

/// A converged shooting solution: the start at phase 0 and the flow over k periods from it.
pub(crate) struct Solved {
    pub(crate) y: [f64; 2],
    pub(crate) flow: Flow,
    pub(crate) iterations: usize,
    pub(crate) residual: f64,
}

/// Whether |r| is within Newton's tolerance at y.
pub(crate) fn converged(r: [f64; 2], y: [f64; 2]) -> bool {
    r[0].hypot(r[1]) <= NEWTON_TOL * (1.0 + y[0].hypot(y[1]))
}

/// Newton on P(y) = φ_{2πk}(y) − y (phase time) from `y`.
pub(crate) fn newton<O: Oscillator>(
    o: &O,
    k: u32,
    mut y: [f64; 2],
    opts: &PeriodicOptions,
) -> Result<Solved> {
    let span = std::f64::consts::TAU * f64::from(k);
    let mut iterations = 0;
    loop {
        let f = flow(o, None, 0.0, y, span, opts.tol)?;
        let r = [f.y[0] - y[0], f.y[1] - y[1]];
        let residual = r[0].hypot(r[1]);
        if converged(r, y) {
            return Ok(Solved {
                y,
                flow: f,
                iterations,
                residual,
            });
        }
        if iterations == opts.max_newton || !residual.is_finite() {
            return Err(Error::NoConvergence {
                what: "periodic orbit (Newton on the stroboscopic map)",
                iterations,
                residual,
            });
        }
        let singular = || Error::NoConvergence {
            what: "periodic orbit (a multiplier is 1: a fold of cycles)",
            iterations,
            residual,
        };
        // (M − I) Δ = −r
        let a = f.m_minus_i().ok_or_else(singular)?;
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        if det == 0.0 || !det.is_finite() {
            return Err(singular());
        }
        y = [
            y[0] + (-r[0] * a[1][1] + r[1] * a[0][1]) / det,
            y[1] + (-r[1] * a[0][0] + r[0] * a[1][0]) / det,
        ];
        iterations += 1;
    }
}

/// Extent of a periodic response: extremes of x (at the zeros of x') and the largest |x'| (at a
/// zero of x'' or an end), each located on the integrator's dense output to 1e-12 in phase.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Amplitude {
    /// Smallest x.
    pub x_min: f64,
    /// Largest x.
    pub x_max: f64,
    /// x_max − x_min.
    pub peak_to_peak: f64,
    /// Largest |x'|.
    pub max_abs_xdot: f64,
}

/// The oscillator alone in phase time (for the amplitudes).
pub(crate) struct Plain<'a, O: Oscillator>(pub(crate) &'a O, pub(crate) f64);

impl<O: Oscillator> System<2> for Plain<'_, O> {
    #[inline]
    fn rhs(&self, s: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1] * self.1, self.0.accel(s, y[0], y[1]) * self.1]
    }
    fn taylor(&self, s: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) -> bool {
        self.0.phase_taylor(None, s, y, order, c)
    }
}

/// Sub-intervals of each step searched for sign changes of x' and x''.
const EXTREMUM_PROBES: usize = 6;

/// The [`Amplitude`] of the response through `y0` at phase 0 over `k` forcing periods.
pub fn amplitude<O: Oscillator>(o: &O, y0: [f64; 2], k: u32, tol: Options) -> Result<Amplitude> {
    let end = std::f64::consts::TAU * f64::from(k);
    let mut extent = Extent {
        lo: y0[0],
        hi: y0[0],
        vmax: y0[1].abs(),
    };
    if let Some(pieces) = o.pieces() {
        // switch by switch, in τ: every switch (x' = 0) ends a step, so x's extremes there are
        // step ends
        let omega = o.omega();
        let free = pieces.model();
        super::saltation::motion(&pieces, y0, end, tol, |d| {
            extent.probe(d, |t, y| free.accel(omega * t, y[0], y[1]));
        })?;
    } else {
        let sys = Plain(o, 1.0 / o.omega());
        let mut s = stepper(&sys, 0.0, y0, method_for::<O>(tol))?;
        while s.t() < end {
            s.step(end)?;
            extent.probe(&s.dense(), |t, y| o.accel(t, y[0], y[1]));
        }
    }
    let Extent { lo, hi, vmax } = extent;
    Ok(Amplitude {
        x_min: lo,
        x_max: hi,
        peak_to_peak: hi - lo,
        max_abs_xdot: vmax,
    })
}

/// The extremes of x and |x'| seen so far.
struct Extent {
    lo: f64,
    hi: f64,
    vmax: f64,
}

impl Extent {
    /// Widens by one step's dense output `d`: sampled at [`EXTREMUM_PROBES`] points, x located
    /// at each sign change of x' and |x'| at each of x'' = `acc`(t, y).
    fn probe<D: crate::integrate::DenseOutput<2>>(
        &mut self,
        d: &D,
        acc: impl Fn(f64, [f64; 2]) -> f64,
    ) {
        let (t0, t1) = (d.t_start(), d.t_end());
        let mut prev_t = t0;
        let mut prev = d.eval(t0);
        for j in 1..=EXTREMUM_PROBES {
            let t = t0 + (t1 - t0) * j as f64 / EXTREMUM_PROBES as f64;
            let y = d.eval(t);
            self.lo = self.lo.min(y[0]);
            self.hi = self.hi.max(y[0]);
            self.vmax = self.vmax.max(y[1].abs());
            if (prev[1] > 0.0) != (y[1] > 0.0) {
                let z = d.eval(bisect(prev_t, t, |u| d.eval(u)[1]));
                self.lo = self.lo.min(z[0]);
                self.hi = self.hi.max(z[0]);
            }
            if (acc(prev_t, prev) > 0.0) != (acc(t, y) > 0.0) {
                let z = d.eval(bisect(prev_t, t, |u| acc(u, d.eval(u))));
                self.vmax = self.vmax.max(z[1].abs());
            }
            prev_t = t;
            prev = y;
        }
    }
}

/// A sign change of `f` on [a, b], by bisection to the resolution of f64.
fn bisect(a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let fa = f(a) > 0.0;
    let (a, b) = crate::roots::bisect(a, b, 60, crate::roots::at_resolution, |m| {
        (f(m) > 0.0) == fa
    });
    0.5 * (a + b)
}

/// What shooting, its orbit and the orbit's verdict need of a system beyond [`Oscillator`]:
/// whether the machinery applies, where the default start is, the orbit's samples, and the burst
/// verdict on a response from a given start. The study's set ([`Params`], its closed forms and
/// Taylor recurrence) and a model assembled from terms ([`Model`]) are the two; a command holding
/// a model runs the study's set when the model is the study's ([`Model::equivalent_params`]).
pub trait Periodic: Oscillator<Param: Serialize> + Serialize {
    /// Refuses, in one line naming the term and the reason, a system whose periodic orbits the
    /// plane (x, x') shooting cannot compute.
    fn check_periodic(&self) -> Result<()>;
    /// The default start (x, x') at τ = 0: the lowest stable equilibrium at a = 0, at rest.
    fn default_start(&self) -> Result<[f64; 2]>;
    /// The forcing frequency's parameter (what a frequency response varies).
    fn frequency(&self) -> Self::Param;
    /// The parameter called `name` (an error names it and lists the system's).
    fn param_named(&self, name: &str) -> Result<Self::Param>;
    /// The default ω range of a frequency response ([`super::default_frequency_range`]).
    fn frequency_range(&self) -> (f64, f64);
    /// (τ, x, x') every `opts.dt` over `period` from `y` at τ = 0, by Taylor's method, and for
    /// a system whose friction sticks the rests on that period of the orbit ([`Rests`]).
    fn samples(&self, y: [f64; 2], period: f64, opts: &PeriodicOptions) -> Result<Samples>;
    /// The burst verdict on the response from `start` at τ = 0 measured with `opts`.
    fn verdict_from(
        &self,
        opts: &crate::burst::BurstOptions,
        start: [f64; 2],
    ) -> Result<crate::burst::Classification>;
    /// The system in words for a figure's caption.
    fn caption(&self) -> String;
}

impl Periodic for Params {
    fn check_periodic(&self) -> Result<()> {
        self.validate().map(|_| ())
    }
    fn default_start(&self) -> Result<[f64; 2]> {
        Ok(crate::simulate::initial_state(
            self,
            crate::simulate::Start::Equilibrium,
        ))
    }
    fn frequency(&self) -> Param {
        Param::Omega
    }
    fn param_named(&self, name: &str) -> Result<Param> {
        name.parse().map_err(|_| Error::InvalidInput {
            what: "parameter name",
            text: name.to_string(),
            reason: format!(
                "no such parameter; the study's are {}",
                Param::ALL.map(Param::name).join(", ")
            ),
        })
    }
    fn frequency_range(&self) -> (f64, f64) {
        super::default_frequency_range(self)
    }
    fn samples(&self, y: [f64; 2], period: f64, opts: &PeriodicOptions) -> Result<Samples> {
        let sim = sample_options(y, period, opts);
        let (samples, _) = collect(|out| crate::simulate::simulate(self, &sim, |t, s| out(t, s)))?;
        Ok((samples, None))
    }
    fn verdict_from(
        &self,
        opts: &crate::burst::BurstOptions,
        start: [f64; 2],
    ) -> Result<crate::burst::Classification> {
        let r = crate::burst::response_from(self, opts, start)?;
        Ok(crate::burst::classify(self, &r))
    }
    fn caption(&self) -> String {
        format!(
            "α = {}, γ = {}, ε = {}, μ = {}, δ = {}",
            self.alpha, self.gamma, self.eps, self.mu, self.delta
        )
    }
}

/// A model's orbit lives in the plane (x, x'): a model with internal states, a dither (a second,
/// fast period) or a delay (a history, not a point, is the state) is refused, naming the term.
/// Friction that sticks is shot switch by switch, its monodromy carried across each switch by
/// the saltation matrix ([`Oscillator::switching_flow`]).
impl Periodic for Model {
    fn check_periodic(&self) -> Result<()> {
        Oscillator::check(self)?;
        let refuse = |kind: &str, reason: &str| Error::InvalidInput {
            what: "model",
            text: kind.to_string(),
            reason: format!("periodic orbits are not computed for it: {reason}"),
        };
        let has = |what: fn(&crate::model::terms::AnyTerm) -> bool| {
            self.terms().find(|t| what(t)).map(|t| t.kind())
        };
        if let Some(kind) = has(|t| t.dither().is_some()) {
            return Err(refuse(
                kind,
                "a dither is a second forcing period, so no orbit has period k·2π/ω",
            ));
        }
        if let Some(kind) = has(|t| t.delay().is_some()) {
            return Err(refuse(
                kind,
                "with a delay the state is a history, not the point (x, x') shooting solves for",
            ));
        }
        Ok(())
    }
    fn default_start(&self) -> Result<[f64; 2]> {
        Ok([self.stable_equilibrium(0.0)?, self.rest_rate()])
    }
    fn frequency(&self) -> ModelParam {
        self.param(Param::Omega.name())
            .expect("every model has the forcing's omega")
    }
    fn param_named(&self, name: &str) -> Result<ModelParam> {
        self.param(name)
    }
    fn frequency_range(&self) -> (f64, f64) {
        let [mu, delta, _] = self.forcing();
        let stiffest = [mu - delta, mu + delta]
            .iter()
            .flat_map(|&level| self.equilibria_at(level).unwrap_or_default())
            .map(|x| self.static_stiffness(x))
            .fold(self.static_stiffness(0.0).abs(), f64::max);
        let ws = stiffest.sqrt().max(1e-3);
        (ws / 20.0, 3.0 * ws)
    }
    fn samples(&self, y: [f64; 2], period: f64, opts: &PeriodicOptions) -> Result<Samples> {
        let sim = sample_options(y, period, opts);
        let (samples, summary) =
            collect(|out| crate::simulate::simulate_model(self, &sim, |t, s| out(t, s)))?;
        let rests = summary.sticking.map(|s| {
            // a rest that spans τ = 0 and ends within the period is counted at the start and
            // again where the period ends (one that lasts the whole period, once)
            let spans_zero = y[1] == 0.0
                && crate::model::switching::Pieces::new(self).is_some_and(|p| {
                    p.mode_at_rest(0.0, &y) == crate::model::switching::SwitchingMode::Stuck
                });
            Rests {
                rests: s.sticks - u64::from(spans_zero && s.sticks > 1),
                switches: s.switches,
                time_stuck: s.time_stuck,
            }
        });
        Ok((samples, rests))
    }
    fn verdict_from(
        &self,
        opts: &crate::burst::BurstOptions,
        start: [f64; 2],
    ) -> Result<crate::burst::Classification> {
        let r = crate::burst::response_model_from(self, opts, start)?;
        crate::burst::classify_model(self, &r)
    }
    fn caption(&self) -> String {
        self.equation()
    }
}

/// An orbit's samples (τ, x, x') over one period, with its rests where its friction sticks.
pub type Samples = (Vec<[f64; 3]>, Option<Rests>);

/// The rests of a periodic orbit whose friction sticks, over one period.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Rests {
    /// How many times the motion comes to rest and sticks (a rest that spans τ = 0 once).
    pub rests: u64,
    /// Changes of mode (slip → stick, stick → slip, reversals at rest).
    pub switches: u64,
    /// The time at rest.
    pub time_stuck: f64,
}

/// The samples (τ, x, x') a run shows its output callback, and the run's summary.
fn collect(
    run: impl FnOnce(&mut dyn FnMut(f64, &[f64])) -> Result<crate::simulate::SimSummary>,
) -> Result<(Vec<[f64; 3]>, crate::simulate::SimSummary)> {
    let mut samples = Vec::new();
    let summary = run(&mut |t, s| samples.push([t, s[0], s[1]]))?;
    Ok((samples, summary))
}

/// The run that samples an orbit: from `y` over `period`, by Taylor's method.
fn sample_options(y: [f64; 2], period: f64, opts: &PeriodicOptions) -> crate::simulate::SimOptions {
    crate::simulate::SimOptions {
        t_end: period,
        dt: opts.dt,
        start: crate::simulate::Start::Given { x0: y[0], v0: y[1] },
        tol: Options {
            method: Method::Taylor,
            ..opts.tol
        },
    }
}

/// Finds the periodic orbit of period k·2π/ω by shooting from the settled default start, for
/// the study's set or any smooth model in the plane ([`Periodic`]).
///
/// ```
/// use hdgear::{Params, model::{Model, terms::AnyTerm}, periodic::{PeriodicOptions, shoot}};
/// // smooth friction f_c·tanh(x'/v_s) adds damping: the orbit stays stable
/// let m = Model::study(&Params { gamma: 1.0, ..Params::default() })
///     .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
///     .unwrap();
/// let orbit = shoot(&m, 1, &PeriodicOptions::default()).unwrap();
/// assert!(orbit.stable && orbit.residual < 1e-10);
/// ```
pub fn shoot<S: Periodic>(s: &S, k: u32, opts: &PeriodicOptions) -> Result<PeriodicOrbit<S>> {
    s.check_periodic()?;
    if k == 0 {
        return Err(Error::InvalidOption {
            name: "subharmonic",
            value: 0.0,
            reason: "must be ≥ 1",
        });
    }
    let t_forcing = std::f64::consts::TAU / s.omega();
    let period = f64::from(k) * t_forcing;
    crate::integrate::check_budget(t_forcing * settle_periods(s) + 2.0 * period, &opts.tol)?;
    let y0 = s.default_start()?;
    let solved = settle_and_solve(s, k, y0, opts)?;
    orbit(s, k, period, &solved, opts)
}

/// Whole forcing periods covering [`SETTLE_TIME`] (at least one).
fn settle_periods<O: Oscillator>(o: &O) -> f64 {
    (SETTLE_TIME * o.omega() / std::f64::consts::TAU)
        .ceil()
        .max(1.0)
}

/// Settles from `y0` for [`SETTLE_TIME`] (whole periods, so the phase stays 0) and shoots;
/// if Newton does not converge from there (a weakly damped oscillator, a slow transient), settles
/// ten times longer and shoots once more.
pub(crate) fn settle_and_solve<O: Oscillator>(
    o: &O,
    k: u32,
    y0: [f64; 2],
    opts: &PeriodicOptions,
) -> Result<Solved> {
    let span = std::f64::consts::TAU * settle_periods(o);
    let y = flow(o, None, 0.0, y0, span, opts.tol)?.y;
    match newton(o, k, y, opts) {
        Err(Error::NoConvergence { .. }) => {
            crate::integrate::check_budget(10.0 * span / o.omega(), &opts.tol)?;
            let y = flow(o, None, 0.0, y, 10.0 * span, opts.tol)?.y;
            newton(o, k, y, opts)
        }
        other => other,
    }
}

/// Assembles the orbit: multipliers, samples, amplitudes.
fn orbit<S: Periodic>(
    p: &S,
    k: u32,
    period: f64,
    solved: &Solved,
    opts: &PeriodicOptions,
) -> Result<PeriodicOrbit<S>> {
    let y = solved.y;
    let multipliers = multipliers(&solved.flow);
    let log_abs = [multipliers[0].log_abs, multipliers[1].log_abs];
    let (samples, rests) = p.samples(y, period, opts)?;
    let amp = amplitude(p, y, k, opts.tol)?;
    Ok(PeriodicOrbit {
        params: *p,
        subharmonic: k,
        period,
        start: y,
        residual: solved.residual,
        newton_iterations: solved.iterations,
        multipliers,
        log_abs_multipliers: log_abs,
        floquet_exponents: log_abs.map(|l| l / period),
        stable: log_abs.iter().all(|&l| l < 0.0),
        minimal_subharmonic: minimal_subharmonic(p, y, k, opts.tol)?,
        max_abs_xdot: amp.max_abs_xdot,
        x_range: [amp.x_min, amp.x_max],
        peak_to_peak: amp.peak_to_peak,
        rests,
        samples,
    })
}

/// The burst verdict on the periodic orbit itself: the response from the orbit's start at τ = 0
/// measured with `opts` but no transient discarded (the orbit has none), over
/// max(`opts.periods`, k) slow periods.
///
/// ```
/// use hdgear::{Params, burst::{BurstOptions, Verdict}, periodic::{PeriodicOptions, burst_verdict, shoot}};
/// let p = Params::default(); // γ = 0.1: overshoot bursts
/// let orbit = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
/// let c = burst_verdict(&orbit, &BurstOptions::default()).unwrap();
/// assert_eq!(c.verdict, Verdict::Overshoot);
/// ```
pub fn burst_verdict<S: Periodic>(
    orbit: &PeriodicOrbit<S>,
    opts: &crate::burst::BurstOptions,
) -> Result<crate::burst::Classification> {
    let opts = crate::burst::BurstOptions {
        discard_periods: 0.0,
        periods: opts.periods.max(orbit.subharmonic),
        ..*opts
    };
    orbit.params.verdict_from(&opts, orbit.start)
}

/// The smallest j dividing k with φ_{2πj}(y) = y to 1e-8 (relative to 1 + |y|).
pub(crate) fn minimal_subharmonic<O: Oscillator>(
    o: &O,
    y: [f64; 2],
    k: u32,
    tol: Options,
) -> Result<u32> {
    for j in (1..k).filter(|j| k.is_multiple_of(*j)) {
        let z = flow(o, None, 0.0, y, std::f64::consts::TAU * f64::from(j), tol)?.y;
        if (z[0] - y[0]).hypot(z[1] - y[1]) <= 1e-8 * (1.0 + y[0].hypot(y[1])) {
            return Ok(j);
        }
    }
    Ok(k)
}
