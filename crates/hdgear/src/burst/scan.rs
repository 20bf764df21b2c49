//! One streaming pass over the dense output that extracts the raw material of the three
//! signatures: the extrema of x' (pruned to swings above a floor), the lobes of the tracking error
//! e = x − x*(a) on the leading side, and the jumps across the unstable band. Every event is a
//! root located on the step's interpolant, so nothing depends on where the steps land.
//!
//! **Why one file.** The three signatures' raw material comes from one pass over each step, sharing
//! the step's samples and the history of the pass; one scanner keeps them in step with each other.

use crate::fast::{Follower, StaticCurve};
use crate::integrate::DenseOutput;
use crate::integrate::events::refine_root;
use crate::params::Params;
use std::collections::VecDeque;
use std::f64::consts::{FRAC_PI_2, PI};

/// Equal parts each step is split into before sign changes are looked for (as in
/// [`crate::integrate::events::Detector`]): two roots closer than a quarter step can be missed,
/// which only happens for wiggles far below every floor (a step resolves the motion it carries).
/// [`Scanner::push`] samples the midpoint and the end; the onset search uses the same split.
const SUBDIVISIONS: usize = 2;

/// A step's dense output as the scan reads it: x and x' ([`DenseOutput<2>`]) and, for a model
/// with terms beyond the curve it is scanned against, its own x'' (None, the default, for the
/// study's model: x'' is then the curve's forcing − x' − g(x)). Both come from one evaluation.
pub(crate) trait ScanStep: DenseOutput<2> {
    /// (x, x') at t in the step and x'' there where the step knows it.
    fn state_at(&self, t: f64) -> ([f64; 2], Option<f64>) {
        (self.eval(t), None)
    }
    /// The state the step ended on ([`DenseOutput::end_state`]) and x'' there where the step
    /// knows it.
    fn end(&self) -> ([f64; 2], Option<f64>) {
        (self.end_state(), None)
    }
}

impl ScanStep for crate::integrate::AnyDense<2> {}

/// What the scan measures at one time.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sample {
    pub t: f64,
    pub x: f64,
    pub v: f64,
    /// x''.
    pub acc: f64,
    /// sin(ωt): the slow variable a.
    pub s: f64,
    /// cos(ωt): the sign of da/dt.
    pub c: f64,
    /// e = x − x*(a).
    pub e: f64,
    /// e' = x' − dx*/dt.
    pub ed: f64,
}

/// An extremum of x' that survived pruning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Pivot {
    pub t: f64,
    pub v: f64,
    /// Last time before `t` at which |x'| < |v|/2 (the half-height onset of a pulse).
    pub onset: f64,
}

/// A lobe of e on the leading side (e·cos ωt > 0) bounded by zeros of e on both sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lobe {
    pub start: f64,
    pub end: f64,
    /// max |e| over the lobe.
    pub amp: f64,
}

/// Prunes the extrema of x' to the swings of at least `floor` (a ZigZag with hysteresis): an
/// extremum is confirmed when x' has since moved the other way by `floor` or more; smaller
/// retracements are dropped together with the extremum they would have created.
#[derive(Clone, Debug)]
struct ZigZag {
    floor: f64,
    /// The running candidate (t, v, is_max).
    cand: Option<(f64, f64, bool)>,
}

impl ZigZag {
    /// Feeds a raw extremum; returns the candidate it confirms, if any.
    fn push(&mut self, t: f64, v: f64, is_max: bool) -> Option<(f64, f64)> {
        match self.cand {
            None => {
                self.cand = Some((t, v, is_max));
                None
            }
            Some((ct, cv, cmax)) if cmax == is_max => {
                if (is_max && v > cv) || (!is_max && v < cv) {
                    self.cand = Some((t, v, is_max));
                }
                let _ = ct;
                None
            }
            Some((ct, cv, _)) => {
                if (v - cv).abs() >= self.floor {
                    self.cand = Some((t, v, is_max));
                    Some((ct, cv))
                } else {
                    None
                }
            }
        }
    }
}

/// How many of the raw extrema `raw` (τ, v, is_max), in order, survive pruning to the swings
/// of at least `floor` (the scan's own pruning of x', [`ZigZag`]).
pub(crate) fn pruned_count(floor: f64, raw: &[(f64, f64, bool)]) -> usize {
    let mut zigzag = ZigZag { floor, cand: None };
    let confirmed = raw
        .iter()
        .filter(|&&(t, v, is_max)| zigzag.push(t, v, is_max).is_some())
        .count();
    confirmed + usize::from(zigzag.cand.is_some())
}

/// Everything the scan found.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scan {
    pub pivots: Vec<Pivot>,
    pub lobes: Vec<Lobe>,
    pub jumps: Vec<f64>,
    /// Largest |x'| inside the window.
    pub peak_abs_xdot: f64,
    /// Largest |e| inside the window.
    pub max_lag: f64,
}

/// The streaming scanner (`Debug` and `Clone` for its tests). Feed it every step's dense output
/// in order with [`Scanner::push`] (or, with the samples measured elsewhere,
/// [`Scanner::push_sampled`]), keeping the steps in a [`Past`] for the pulse onsets.
#[derive(Clone, Debug)]
pub(crate) struct Scanner<C: StaticCurve = Params> {
    p: C,
    follower: C::Follower,
    zigzag: ZigZag,
    /// Lobes smaller than this are not kept (they can never matter; avoids storing rounding).
    lobe_keep: f64,
    band: Option<(f64, f64)>,
    window: (f64, f64),
    last: Option<Sample>,
    side: i8,
    lobe: Option<(f64, bool, f64)>,
    out: Scan,
}

impl<C: StaticCurve> Scanner<C> {
    /// `swing_floor`: the smallest swing of x' that counts; `lobe_keep`: the smallest lobe kept;
    /// `window`: where the window statistics are taken.
    pub(crate) fn new(
        p: &C,
        x0: f64,
        swing_floor: f64,
        lobe_keep: f64,
        window: (f64, f64),
    ) -> Scanner<C> {
        Scanner {
            p: p.clone(),
            follower: p.follower(x0),
            zigzag: ZigZag {
                floor: swing_floor,
                cand: None,
            },
            lobe_keep,
            band: p.fold_band(),
            window,
            last: None,
            side: 0,
            lobe: None,
            out: Scan::default(),
        }
    }

    fn sample(&mut self, t: f64, y: [f64; 2], acc: Option<f64>) -> Sample {
        let (s, c) = (self.p.omega() * t).sin_cos();
        self.sample_with(t, y, s, c, acc)
    }

    /// [`Scanner::sample`] with sin ωt and cos ωt given (`acc`: [`ScanStep::state_at`]'s x'').
    pub(crate) fn sample_with(
        &mut self,
        t: f64,
        y: [f64; 2],
        s: f64,
        c: f64,
        acc: Option<f64>,
    ) -> Sample {
        let xs = self.follower.at(s, y[0]);
        measure(&self.p, t, y, (s, c), xs, acc)
    }

    /// The tracker of the equilibrium (for scanners that follow it elsewhere and hand it back).
    pub(crate) fn follower(&mut self) -> &mut C::Follower {
        &mut self.follower
    }

    /// [`Scanner::follower`], to read.
    pub(crate) fn follower_ref(&self) -> &C::Follower {
        &self.follower
    }

    fn in_window(&self, t: f64) -> bool {
        t >= self.window.0 && t <= self.window.1
    }

    /// Scans one step; `past` holds the steps so far, this one included.
    pub(crate) fn push<D: ScanStep>(&mut self, d: &D, past: &impl Past) {
        let (t0, t1) = (d.t_start(), d.t_end());
        self.start(d);
        // sin and cos of ωt at the step's end, the midpoint's from them: one sine per step
        let (s1, c1) = (self.p.omega() * t1).sin_cos();
        let (tm, (sm, cm)) = midpoint(self.p.omega(), t0, t1, (s1, c1));
        // the step's end: the state the integrator ended on (and starts the next step from)
        let (ym, em) = d.state_at(tm);
        let (y1, e1) = d.end();
        let mid = self.sample_with(tm, ym, sm, cm, em);
        let end = self.sample_with(t1, y1, s1, c1, e1);
        self.push_sampled(d, mid, end, past);
    }

    /// Samples the step's start when the step does not continue the last one (the first step):
    /// a caller that samples the midpoint and end itself ([`Scanner::push_sampled`]) calls this
    /// first, since the samples follow the equilibrium from the start's.
    pub(crate) fn start<D: ScanStep>(&mut self, d: &D) {
        let t0 = d.t_start();
        if self.last.is_some_and(|s| s.t == t0) {
            return;
        }
        let (y0, e0) = d.state_at(t0);
        let s = self.sample(t0, y0, e0);
        if s.e * s.c > 0.0 {
            // a leading lobe already under way: its start is unknown, so it cannot count
            self.lobe = Some((t0, true, s.e.abs()));
        }
        self.side = self.band_side(s.x, 0);
        self.last = Some(s);
    }

    /// [`Scanner::push`] with the step's midpoint and end sampled by the caller (the samples
    /// [`Scanner::sample_with`] gives there, in order, after [`Scanner::start`]).
    pub(crate) fn push_sampled<D: ScanStep>(
        &mut self,
        d: &D,
        mid: Sample,
        end: Sample,
        past: &impl Past,
    ) {
        let Some(prev) = self.last else {
            // (callers sample the start first: see above)
            self.start(d);
            return self.push_sampled(d, mid, end, past);
        };
        self.interval(d, &prev, &mid, past);
        self.interval(d, &mid, &end, past);
        self.last = Some(end);
    }

    fn band_side(&self, x: f64, old: i8) -> i8 {
        match self.band {
            Some((xm, _)) if x < xm => -1,
            Some((_, xp)) if x > xp => 1,
            _ => old,
        }
    }

    /// The fold abscissae bounding the unstable band, as [`eventful`] takes them.
    pub(crate) fn band(&self) -> (f64, f64) {
        self.band.unwrap_or((f64::NAN, f64::NAN))
    }

    /// Where the window statistics are taken.
    pub(crate) fn window(&self) -> (f64, f64) {
        self.window
    }

    /// The last sample (the latest step's end), once the scan has started.
    pub(crate) fn last(&self) -> Option<Sample> {
        self.last
    }

    /// Takes the lane back after steps without events were scanned elsewhere (see
    /// [`Scanner::quiet`]): `last` is the latest of them's end, `lobe_growth` the largest |e| at
    /// their samples (the growth of a lobe open throughout them), and `maxima` the window's
    /// largest |x'| and |e| over them.
    pub(crate) fn resume(&mut self, last: Sample, lobe_growth: f64, maxima: [f64; 2]) {
        self.last = Some(last);
        if let Some(l) = self.lobe.as_mut() {
            l.2 = l.2.max(lobe_growth);
        }
        let o = &mut self.out;
        o.peak_abs_xdot = o.peak_abs_xdot.max(maxima[0]);
        o.max_lag = o.max_lag.max(maxima[1]);
    }

    /// Counts a sample in the window statistics.
    fn window_maxima(&mut self, s: &Sample) {
        if self.in_window(s.t) {
            self.out.peak_abs_xdot = self.out.peak_abs_xdot.max(s.v.abs());
            self.out.max_lag = self.out.max_lag.max(s.e.abs());
        }
    }

    /// A sub-interval without events ([`eventful`] false): all it changes are the window
    /// statistics and the growth of an open lobe. (The scan of a batch makes the same changes over
    /// all its lanes at once.)
    fn quiet(&mut self, a: &Sample, b: &Sample) {
        self.window_maxima(a);
        self.window_maxima(b);
        if let Some(l) = self.lobe.as_mut() {
            l.2 = l.2.max(b.e.abs());
        }
    }

    /// Processes the sub-interval between two samples.
    fn interval<D: ScanStep>(&mut self, d: &D, a: &Sample, b: &Sample, past: &impl Past) {
        if !eventful(self.p.omega(), self.band(), a, b) {
            #[cfg(test)]
            tests::check_quiet(self, d, a, b, past);
            return self.quiet(a, b);
        }
        self.events(d, a, b, past);
    }

    /// [`Scanner::interval`] where [`eventful`] found something.
    fn events<D: ScanStep>(&mut self, d: &D, a: &Sample, b: &Sample, past: &impl Past) {
        let p = self.p.clone();
        // sin ωt and cos ωt inside the sub-interval from their values at its end
        let sc = |t: f64| sin_cos_near(p.omega(), t, b.t, (b.s, b.c));
        // --- extrema of x': sign changes of x''
        if (a.acc > 0.0) != (b.acc > 0.0) && a.acc != 0.0 {
            let acc = |t: f64| {
                let (y, acc) = d.state_at(t);
                accel(&p, sc(t).0, y, acc)
            };
            let te = refine_root(acc, a.t, a.acc, b.t, b.acc);
            let ve = d.eval(te)[1];
            if self.in_window(te) {
                self.out.peak_abs_xdot = self.out.peak_abs_xdot.max(ve.abs());
            }
            let is_max = a.acc > 0.0;
            if let Some((tp, vp)) = self.zigzag.push(te, ve, is_max) {
                self.emit_pivot(tp, vp, past);
            }
        }
        self.window_maxima(a);
        self.window_maxima(b);
        // --- jumps across the band between the fold abscissae
        if let Some((xm, xp)) = self.band {
            let side = self.band_side(b.x, self.side);
            if self.side != 0 && side != self.side {
                let far = if side > 0 { xp } else { xm };
                let t = refine_root(|t| d.eval(t)[0] - far, a.t, a.x - far, b.t, b.x - far);
                self.out.jumps.push(t);
            }
            self.side = side;
        }
        self.lobe_marks(d, a, b);
    }

    /// The breakpoints of the leading-side lobes of e in (a.t, b.t]: zeros of e and of cos ωt
    /// (turning points of a), and the extrema of e (zeros of e'), which measure the lobe.
    fn lobe_marks<D: DenseOutput<2>>(&mut self, d: &D, a: &Sample, b: &Sample) {
        let p = self.p.clone();
        let sc = |t: f64| sin_cos_near(p.omega(), t, b.t, (b.s, b.c));
        // extrema of e (zeros of e') measure the lobe
        let mut marks: Vec<(f64, Mark)> = Vec::new();
        if (a.e > 0.0) != (b.e > 0.0) && a.e != 0.0 {
            let mut f = self.follower.clone();
            let e = |t: f64| {
                let y = d.eval(t);
                y[0] - f.at(sc(t).0, y[0])
            };
            marks.push((refine_root(e, a.t, a.e, b.t, b.e), Mark::ZeroOfE));
        }
        // turning points of a in (a.t, b.t]: none when cos ωt has one sign at both ends, well
        // away from zero (its rounding is far below 1e-6, so a zero within rounding of an end
        // cannot hide), and the interval is shorter than the π/ω two zeros would need
        let (ca, cb) = (a.c, b.c);
        let one_sign = (ca > 0.0) == (cb > 0.0) && ca.abs().min(cb.abs()) > 1e-6;
        if !(one_sign && p.omega() * (b.t - a.t) < 1.0) {
            self.turning_points(a.t, b.t, &mut marks);
        }
        if (a.ed > 0.0) != (b.ed > 0.0) && a.ed.is_finite() && b.ed.is_finite() {
            let mut f = self.follower.clone();
            let ed = |t: f64| {
                let y = d.eval(t);
                let (s, c) = sc(t);
                let xs = f.at(s, y[0]);
                y[1] - p.omega() * c * p.delta() / p.g_prime(xs)
            };
            let t = refine_root(ed, a.t, a.ed, b.t, b.ed);
            let y = d.eval(t);
            let mut f = self.follower.clone();
            let e = y[0] - f.at(sc(t).0, y[0]);
            marks.push((t, Mark::ExtremumOfE(e.abs())));
        }
        self.apply_marks(marks, b);
    }

    /// The turning points of a (zeros of cos ωt) in (t0, t1].
    fn turning_points(&self, t0: f64, t1: f64, marks: &mut Vec<(f64, Mark)>) {
        let omega = self.p.omega();
        let mut k = ((omega * t0 - FRAC_PI_2) / PI).floor() + 1.0;
        loop {
            let tk = (FRAC_PI_2 + k * PI) / omega;
            if tk > t1 || !tk.is_finite() {
                break;
            }
            if tk > t0 {
                marks.push((tk, Mark::Turn));
            }
            k += 1.0;
        }
    }

    /// Opens, grows and closes lobes at the breakpoints `marks` of one sub-interval ending at `b`.
    fn apply_marks(&mut self, mut marks: Vec<(f64, Mark)>, b: &Sample) {
        marks.sort_by(|x, y| x.0.total_cmp(&y.0));
        for (t, m) in marks {
            match m {
                Mark::ExtremumOfE(amp) => {
                    if let Some(l) = self.lobe.as_mut() {
                        l.2 = l.2.max(amp);
                    }
                    if self.in_window(t) {
                        self.out.max_lag = self.out.max_lag.max(amp);
                    }
                }
                Mark::ZeroOfE | Mark::Turn => {
                    let turn = matches!(m, Mark::Turn);
                    match self.lobe.take() {
                        Some((start, start_turn, amp)) => {
                            if !start_turn && !turn && amp >= self.lobe_keep {
                                self.out.lobes.push(Lobe { start, end: t, amp });
                            }
                        }
                        None => self.lobe = Some((t, turn, 0.0)),
                    }
                }
            }
        }
        if let Some(l) = self.lobe.as_mut() {
            l.2 = l.2.max(b.e.abs());
        }
    }

    /// A raw extremum of x' at `t` that the sign test on x'' cannot see: a rest of a model with
    /// sticking friction (x' = x'' = 0 throughout it) which the motion leaves in the direction it
    /// came from, a minimum of |x'| at 0.
    pub(crate) fn extremum(&mut self, t: f64, v: f64, is_max: bool, past: &impl Past) {
        if let Some((tp, vp)) = self.zigzag.push(t, v, is_max) {
            self.emit_pivot(tp, vp, past);
        }
    }

    fn emit_pivot(&mut self, t: f64, v: f64, past: &impl Past) {
        let onset = past.onset(t, v.abs());
        self.out.pivots.push(Pivot { t, v, onset });
    }

    /// Ends the scan: the last candidate extremum is confirmed.
    pub(crate) fn finish(mut self, past: &impl Past) -> Scan {
        if let Some((t, v, _)) = self.zigzag.cand.take() {
            self.emit_pivot(t, v, past);
        }
        self.out
    }
}

/// Whether [`Scanner::interval`] has anything to locate between samples `a` and `b` (of a model
/// with forcing frequency `omega` and fold abscissae `band`, NaN without folds): a sign change of
/// x'' (an extremum of x'), of e or of e' (a lobe's end or extremum), a crossing of either fold
/// abscissa (a jump, or the side of the band the state is on changing), or a turning point of a
/// that the cheap test cannot rule out. Each test is the one `interval` and its helpers make (the
/// side: after `a` it is the side `a` is on, so it changes only if x crosses an abscissa), written
/// with `|` and `&` so that the scan of a batch evaluates it over all lanes at once.
#[inline(always)]
pub(crate) fn eventful(omega: f64, (xm, xp): (f64, f64), a: &Sample, b: &Sample) -> bool {
    let acc = ((a.acc > 0.0) != (b.acc > 0.0)) & (a.acc != 0.0);
    let side = ((a.x < xm) != (b.x < xm)) | ((a.x > xp) != (b.x > xp));
    let e = ((a.e > 0.0) != (b.e > 0.0)) & (a.e != 0.0);
    let one_sign = ((a.c > 0.0) == (b.c > 0.0)) & (a.c.abs().min(b.c.abs()) > 1e-6);
    let turn = !(one_sign & (omega * (b.t - a.t) < 1.0));
    let ed = ((a.ed > 0.0) != (b.ed > 0.0)) & a.ed.is_finite() & b.ed.is_finite();
    acc | side | e | turn | ed
}

/// x'' at the state `y` = (x, x') with sin ωt = `s`: the step's own `acc`
/// ([`ScanStep::state_at`]) where it has one, else the curve's.
#[inline(always)]
fn accel<C: StaticCurve>(p: &C, s: f64, y: [f64; 2], acc: Option<f64>) -> f64 {
    match acc {
        Some(acc) => acc,
        // the fast subsystem x'' = μ + δa − c·x' − g(x) at the curve's damping c (1.0 for the
        // study's set, so c·x' is x' to the bit)
        None => p.forcing(s) - p.damping() * y[1] - p.g(y[0]),
    }
}

/// The measures of a sample at time `t`, state `y`, (sin ωt, cos ωt) = `(s, c)`, from the
/// equilibrium `xs` the state follows there and the step's own x'' `acc` ([`ScanStep::state_at`])
/// (one function for the scanners of one step and of many).
#[inline(always)]
pub(crate) fn measure<C: StaticCurve>(
    p: &C,
    t: f64,
    y: [f64; 2],
    (s, c): (f64, f64),
    xs: f64,
    acc: Option<f64>,
) -> Sample {
    let acc = accel(p, s, y, acc);
    let xs_dot = p.omega() * c * p.delta() / p.g_prime(xs);
    Sample {
        t,
        x: y[0],
        v: y[1],
        acc,
        s,
        c,
        e: y[0] - xs,
        ed: y[1] - xs_dot,
    }
}

/// The steps a scan has seen, for the onset of a pulse: the last time before a pulse's peak at
/// which |x'| was below half of it.
pub(crate) trait Past {
    /// The last time before `t` at which |x'| < `peak`/2, searched back through the steps kept
    /// (the start of the oldest when |x'| stayed above half the peak throughout).
    fn onset(&self, t: f64, peak: f64) -> f64;
}

/// One scan's steps over the last `span` of time.
pub(crate) struct History<D> {
    steps: VecDeque<D>,
    span: f64,
}

impl<D: DenseOutput<2>> History<D> {
    /// Keeps the steps ending within `span` of the latest.
    pub(crate) fn new(span: f64) -> History<D> {
        History {
            steps: VecDeque::new(),
            span,
        }
    }

    /// Adds the latest step and forgets those ending more than the span before it.
    pub(crate) fn push(&mut self, d: D) {
        let t_end = d.t_end();
        self.steps.push_back(d);
        while let Some(f) = self.steps.front() {
            if f.t_end() < t_end - self.span {
                self.steps.pop_front();
            } else {
                break;
            }
        }
    }

    /// The latest step (the one pushed last), where it is kept: scanned in place rather than
    /// from a copy of its own (a Taylor step's polynomial is ~370 bytes).
    pub(crate) fn latest(&self) -> Option<&D> {
        self.steps.back()
    }
}

impl<D: DenseOutput<2>> Past for History<D> {
    fn onset(&self, t: f64, peak: f64) -> f64 {
        onset_in(
            self.steps.iter().rev().map(|d| (d.t_start(), d.t_end(), d)),
            t,
            peak,
            |d, s| d.eval(s)[1],
            |d| d.abs_floor(1).unwrap_or(f64::NEG_INFINITY),
        )
    }
}

/// The onset search over steps `(t_start, t_end, step)` from the latest back, x' of a step at a
/// time by `xdot`: each step split in [`SUBDIVISIONS`] parts, the crossing of half the peak
/// refined on the polynomial. `floor` bounds |x'| over a step from below as `xdot` computes it
/// (−∞ where unknown): a step whose bound is at least half the peak cannot hold the crossing and
/// is passed over without evaluating x' (what the search would find there: |x'| ≥ half at each
/// point it looks at), so the result is the same as without it.
pub(crate) fn onset_in<S>(
    steps: impl Iterator<Item = (f64, f64, S)>,
    t: f64,
    peak: f64,
    xdot: impl Fn(&S, f64) -> f64,
    floor: impl Fn(&S) -> f64,
) -> f64 {
    let half = 0.5 * peak;
    let mut earliest = t;
    for (t0, t1, d) in steps {
        if t0 >= t {
            continue;
        }
        let hi = t1.min(t);
        let lo = t0;
        earliest = lo;
        if floor(&d) >= half {
            continue;
        }
        let f = |s: f64| xdot(&d, s).abs() - half;
        let mut tb = hi;
        let mut fb = f(tb);
        for j in (0..SUBDIVISIONS).rev() {
            let ta = lo + (hi - lo) * j as f64 / SUBDIVISIONS as f64;
            let fa = f(ta);
            if fa < 0.0 && fb >= 0.0 {
                return refine_root(f, ta, fa, tb, fb);
            }
            if fa < 0.0 {
                // already below half at the right end: the pulse rises after tb
                return tb;
            }
            tb = ta;
            fb = fa;
        }
    }
    earliest
}

/// The midpoint tm of a step from `t0` to `t1`, with sin ωtm and cos ωtm from their values
/// `(s1, c1)` at `t1`: turned back through δ = ω(t1 − tm) ([`turn_back`], a short series exact
/// to rounding for |δ| ≤ [`TURN_BACK_MAX`]), else by the library's sine.
pub(crate) fn midpoint(omega: f64, t0: f64, t1: f64, (s1, c1): (f64, f64)) -> (f64, (f64, f64)) {
    let tm = 0.5 * (t0 + t1);
    (tm, sin_cos_near(omega, tm, t1, (s1, c1)))
}

/// sin ωt and cos ωt from their values `(s1, c1)` at a time `t1` near `t` ([`turn_back`] when
/// ω·|t1 − t| ≤ [`TURN_BACK_MAX`], else the library's): for the points of a step, from its end's.
#[inline(always)]
pub(crate) fn sin_cos_near(omega: f64, t: f64, t1: f64, (s1, c1): (f64, f64)) -> (f64, f64) {
    let delta = omega * (t1 - t);
    if delta.abs() <= TURN_BACK_MAX {
        turn_back(s1, c1, delta)
    } else {
        (omega * t).sin_cos()
    }
}

/// The largest |δ| [`turn_back`] is used for.
pub(crate) const TURN_BACK_MAX: f64 = 1e-2;

/// sin(θ − δ) and cos(θ − δ) from sin θ, cos θ for |δ| ≤ 1e-2: cos δ and sin δ by their series to
/// δ⁸ and δ⁹ (remainders below 1e-21), then the addition theorems.
///
/// The series' coefficients are constants (1/4!, 1/6!, …, each within half an ulp), so that every
/// operation is a multiply or an add: written as divisions by 12, 30, 56, … they were seven
/// divisions per call, 30 % of the batched sampling of a (γ, δ) map (a vector division is
/// several times slower than a multiplication and is not turned into one, being inexact).
#[inline(always)]
pub(crate) fn turn_back(s: f64, c: f64, delta: f64) -> (f64, f64) {
    // 1/k! for k = 2…9
    const F2: f64 = 1.0 / 2.0;
    const F3: f64 = 1.0 / 6.0;
    const F4: f64 = 1.0 / 24.0;
    const F5: f64 = 1.0 / 120.0;
    const F6: f64 = 1.0 / 720.0;
    const F7: f64 = 1.0 / 5040.0;
    const F8: f64 = 1.0 / 40320.0;
    const F9: f64 = 1.0 / 362_880.0;
    let d2 = delta * delta;
    let cos_d = 1.0 - d2 * (F2 - d2 * (F4 - d2 * (F6 - d2 * F8)));
    let sin_d = delta * (1.0 - d2 * (F3 - d2 * (F5 - d2 * (F7 - d2 * F9))));
    (s * cos_d - c * sin_d, c * cos_d + s * sin_d)
}

#[derive(Clone, Copy, Debug)]
enum Mark {
    ZeroOfE,
    Turn,
    ExtremumOfE(f64),
}

#[cfg(test)]
mod tests {
    use super::{Past, Sample, ScanStep, Scanner};
    use crate::Params;
    use std::cell::Cell;

    thread_local! {
        /// Sub-intervals checked by [`check_quiet`] on this thread.
        static CHECKED: Cell<usize> = const { Cell::new(0) };
    }

    /// Called by [`Scanner::interval`] (in this crate's unit tests) on each sub-interval it
    /// treats as quiet: the full treatment changes the scanner exactly as the quiet one does.
    pub(super) fn check_quiet<C: crate::fast::StaticCurve, D: ScanStep>(
        s: &Scanner<C>,
        d: &D,
        a: &Sample,
        b: &Sample,
        past: &impl Past,
    ) {
        let (mut full, mut quiet) = (s.clone(), s.clone());
        full.events(d, a, b, past);
        quiet.quiet(a, b);
        assert_eq!(format!("{full:?}"), format!("{quiet:?}"), "{a:?} to {b:?}");
        CHECKED.with(|c| c.set(c.get() + 1));
    }

    /// The quiet treatment of a sub-interval without events (what [`super::eventful`] lets
    /// [`Scanner::interval`] skip to, and the scan of a batch does over its lanes at once) is
    /// the full one: checked on every such sub-interval of the scans of five regimes (folds;
    /// the study's bursts; the smooth case; a faster and a slower drive), with the pivots, lobes
    /// and jumps the full treatment found elsewhere (so the test is not a scan without events).
    #[test]
    fn quiet_sub_intervals_are_treated_as_the_full_treatment_would() {
        use crate::burst::{BurstOptions, response};
        for (gamma, omega) in [
            (0.01, 0.01),
            (0.1, 0.01),
            (30.0, 0.01),
            (0.1, 0.05),
            (0.3, 1e-3),
        ] {
            let p = Params {
                gamma,
                omega,
                ..Params::default()
            };
            let before = CHECKED.with(Cell::get);
            let r = response(&p, &BurstOptions::default()).unwrap();
            let checked = CHECKED.with(Cell::get) - before;
            assert!(
                checked > 1000,
                "γ = {gamma}, ω = {omega}: {checked} checked"
            );
            if gamma < 1.0 {
                assert!(!r.bursts.is_empty(), "γ = {gamma}, ω = {omega}: no bursts");
            }
        }
    }
    /// Turning back by a small angle agrees with the library's sine and cosine to rounding: a
    /// few units in the last place of the values, plus the rounding of θ − δ itself (an ulp of
    /// θ, which is what the arguments ω·t_mid and ω·t_end − δ differ by in the scanner too).
    #[test]
    fn turning_back_matches_sin_cos() {
        for &theta in &[0.0, 0.3, 1.7, -2.9, 123.456, 1e4] {
            let (s, c) = f64::sin_cos(theta);
            for &delta in &[1e-2, -1e-2, 3e-3, 1e-6, 0.0] {
                let (st, ct) = super::turn_back(s, c, delta);
                let (se, ce) = f64::sin_cos(theta - delta);
                let tol = 4e-16 + 2.0 * f64::EPSILON * f64::abs(theta);
                assert!(
                    (st - se).abs() <= tol && (ct - ce).abs() <= tol,
                    "{theta} {delta}"
                );
            }
        }
    }
}
