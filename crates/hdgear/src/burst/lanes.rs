//! The burst scan of a batch's [`LANES`] trajectories, one step of all of them at a time: what
//! every step needs (x and x' at the midpoint, the equilibrium followed at the midpoint and the
//! end, the sample's measures) is computed over all lanes at once in vector registers, from the
//! batch's own rows and its carried sin ωt and cos ωt; so is whether a lane's step holds any event
//! at all ([`scan::eventful`]). A step without one changes only a few running maxima, kept over
//! the lanes ([`Quiet`]); a lane with one goes to its [`Scanner`], which locates the events on
//! that lane's step polynomial. A lane whose tracker needs more than two Newton steps (or the
//! exact solve: with three equilibria, or off a stable branch) is sampled by its scanner as in
//! the scan of one trajectory. The steps kept for pulse onsets are one copy of the batch's x' rows
//! per step, with a lower bound of |x'| on each, so the onset search passes over most of them
//! without evaluating them.
//!
//! **Why one file.** The lane scan is the scalar scan (`scan.rs`) over all lanes at once: its
//! samples, trackers and step bookkeeping are one loop's state, read beside each other.

use super::scan::{
    self, Past, Sample, Scan, Scanner, TURN_BACK_MAX, measure, midpoint, onset_in, turn_back,
};
use crate::batch::{LANES, StepLanes, horner_lanes};
use crate::fast::newton;
use crate::integrate::DenseOutput;
use crate::integrate::taylor::{MAX_ORDER, abs_floor, poly};
use crate::params::Params;
use crate::simd::{Simd, dispatched};
use std::collections::VecDeque;

type V = [f64; LANES];

/// The scanners of one chunk of a batch.
pub(crate) struct LaneScan {
    /// One scanner per lane holding a point, until its scan ends (`None` after).
    scanners: Vec<Option<Scanner>>,
    /// Each finished scan.
    done: Vec<Option<Scan>>,
    params: ParamLanes,
    /// Each lane's a-interval with three equilibria (an empty one without folds), where its
    /// tracker solves the cubic.
    multi: [(f64, f64); LANES],
    /// Where each lane's scan ends.
    t_end: V,
    /// How far back each lane's pulse onsets are looked for.
    span: V,
    /// Each lane's equilibrium tracker's warm start, between steps (its scanner's tracker is set
    /// from it whenever the scanner works on the lane).
    trackers: Trackers,
    /// Lanes whose scan is under way.
    active: [bool; LANES],
    /// The latest step's samples.
    mid: Samples,
    end: Samples,
    quiet: Quiet,
    steps: Steps,
    simd: Simd,
}

impl LaneScan {
    /// Scanners for the points of one chunk (at most [`LANES`]), each with where its scan ends and
    /// how far back its pulse onsets are looked for.
    pub(crate) fn new(scanners: Vec<(Scanner, Params, f64, f64)>) -> LaneScan {
        debug_assert!(
            scanners.len() <= LANES,
            "a chunk holds at most LANES points"
        );
        let first = scanners.first().map_or_else(Params::default, |s| s.1);
        let pick = |l: usize| scanners.get(l);
        let params = ParamLanes::new(&std::array::from_fn(|l| pick(l).map_or(first, |s| s.1)));
        let t_end = std::array::from_fn(|l| pick(l).map_or(0.0, |s| s.2));
        let span = std::array::from_fn(|l| pick(l).map_or(0.0, |s| s.3));
        let n = scanners.len();
        let multi = std::array::from_fn(|l| {
            let multi = pick(l).and_then(|s| s.0.follower_ref().multi());
            multi.unwrap_or((f64::INFINITY, f64::NEG_INFINITY))
        });
        let quiet = Quiet::new(&std::array::from_fn(|l| pick(l).map(|s| &s.0)));
        let simd = Simd::detect();
        LaneScan {
            multi,
            scanners: scanners.into_iter().map(|s| Some(s.0)).collect(),
            done: (0..n).map(|_| None).collect(),
            params,
            t_end,
            span,
            trackers: Trackers::default(),
            active: std::array::from_fn(|l| l < n),
            mid: Samples::default(),
            end: Samples::default(),
            quiet,
            steps: Steps::new(simd),
            simd,
        }
    }

    /// Scans one step of every shown lane: the lanes without events over all lanes at once
    /// ([`Quiet::absorb`]), the others by their own scanner.
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    pub(crate) fn push(&mut self, step: &StepLanes<'_>) {
        // the lanes shown, and among them those on their first step
        let (mut shown, mut fresh) = ([false; LANES], [false; LANES]);
        for l in 0..LANES {
            shown[l] = step.shown[l] & self.active[l];
            fresh[l] = shown[l] & !self.quiet.started[l];
        }
        self.steps.push(step, &shown);
        if fresh.contains(&true) {
            self.start(step, &fresh);
        }
        self.sampled(step, &shown, Point::Mid);
        self.sampled(step, &shown, Point::End);
        let (mid, end) = (&self.mid, &self.end);
        let eventful = absorb(
            self.simd,
            &mut self.quiet,
            &self.params.omega,
            &shown,
            mid,
            end,
        );
        // the lanes with an event, and those whose scan is over with this step
        let (mut over, mut handed) = ([false; LANES], [false; LANES]);
        for l in 0..LANES {
            over[l] = shown[l] & (step.t1[l] >= self.t_end[l]);
            handed[l] = eventful[l] | over[l];
        }
        for l in (0..LANES).filter(|&l| handed[l]) {
            self.scan_lane(step, l, eventful[l], over[l]);
        }
        self.steps.forget(&self.span);
    }

    /// Samples the start of each `fresh` lane (shown on its first step), by its scanner, which
    /// follows the equilibrium there.
    fn start(&mut self, step: &StepLanes<'_>, fresh: &[bool; LANES]) {
        for l in (0..LANES).filter(|&l| fresh[l]) {
            if let Some(s) = self.scanners[l].as_mut() {
                s.start(&LaneDense::new(step, l));
                self.trackers.set(l, s.follower().state());
                if let Some(last) = s.last() {
                    self.quiet.last.set(l, &last);
                }
                self.quiet.started[l] = true;
            }
        }
    }

    /// Hands lane `l` to its scanner: its quiet steps so far, then this step if it has an event
    /// (`eventful`); the scan ends here if the step reaches the lane's end (`over`).
    fn scan_lane(&mut self, step: &StepLanes<'_>, l: usize, eventful: bool, over: bool) {
        let Some(s) = self.scanners[l].as_mut() else {
            return;
        };
        let past = LanePast {
            steps: &self.steps,
            lane: l,
            span: self.span[l],
        };
        self.quiet.hand_over(l, s);
        if eventful {
            let (mid, end) = (self.mid.get(l), self.end.get(l));
            s.follower().set_state(self.trackers.get(l));
            s.push_sampled(&LaneDense::new(step, l), mid, end, &past);
            self.quiet.last.set(l, &end);
        }
        if over {
            // the lane's scan is over: finished now, while its steps are kept
            if let Some(s) = self.scanners[l].take() {
                self.done[l] = Some(s.finish(&past));
                self.active[l] = false;
            }
        }
    }

    /// Each lane's scan (`None` for a lane whose integration failed before its end).
    pub(crate) fn finish(self) -> Vec<Option<Scan>> {
        self.done
    }

    /// The samples at the midpoint or the end of every lane's step (into `mid` or `end`): over all
    /// lanes at once, then the lanes that need more (see the module) by their own scanner.
    fn sampled(&mut self, step: &StepLanes<'_>, shown: &[bool; LANES], at: Point) {
        let trackers = &mut self.trackers;
        let out = match at {
            Point::Mid => &mut self.mid,
            Point::End => &mut self.end,
        };
        let ok = samples_at(
            self.simd,
            &self.params,
            &self.multi,
            step,
            trackers,
            at,
            out,
        );
        for l in (0..LANES).filter(|&l| shown[l] && !ok[l]) {
            let Some(s) = self.scanners[l].as_mut() else {
                continue;
            };
            let d = LaneDense::new(step, l);
            let (t0, t1) = (step.t0[l], step.t1[l]);
            let end_sc = (step.sin_cos.0[l], step.sin_cos.1[l]);
            let (t, y, sc) = match at {
                Point::Mid => {
                    let (tm, sc) = midpoint(self.params.omega[l], t0, t1, end_sc);
                    (tm, d.eval(tm), sc)
                }
                Point::End => (t1, d.end_state(), end_sc),
            };
            s.follower().set_state(trackers.get(l));
            out.set(l, &s.sample_with(t, y, sc.0, sc.1, None));
            trackers.set(l, s.follower().state());
        }
    }
}

/// What the scan of a step without events changes ([`Scanner::quiet`]: the window statistics and
/// an open lobe's growth), over all lanes at once, with each lane's last sample; handed to the
/// lane's scanner before it next works on the lane ([`Quiet::hand_over`]). Events are rare
/// (about one sub-interval in forty in a (γ, δ) map), so most steps of most lanes end here.
struct Quiet {
    /// Each lane's last sample (the end of its latest step), once `started`.
    last: Samples,
    /// Lanes whose scanner has sampled its start.
    started: [bool; LANES],
    /// Each lane's fold abscissae (NaN without folds) and window.
    band: (V, V),
    window: (V, V),
    /// The window's largest |x'| and |e|, and the largest |e| (an open lobe's growth), since the
    /// lane was last handed over.
    peak: V,
    lag: V,
    lobe: V,
}

impl Quiet {
    fn new(scanners: &[Option<&Scanner>; LANES]) -> Quiet {
        let pick = |f: fn(&Scanner) -> (f64, f64)| {
            let pairs = scanners.map(|s| s.map_or((f64::NAN, f64::NAN), f));
            (pairs.map(|p| p.0), pairs.map(|p| p.1))
        };
        Quiet {
            last: Samples::default(),
            started: [false; LANES],
            band: pick(Scanner::band),
            window: pick(Scanner::window),
            peak: [0.0; LANES],
            lag: [0.0; LANES],
            lobe: [0.0; LANES],
        }
    }

    /// Scans the step from each shown lane's last sample through `mid` to `end` where it has no
    /// event ([`scan::eventful`] false on both halves), whose last sample becomes `end`, and
    /// returns which lanes have one (their last sample is unchanged: their scanner takes it).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    fn absorb(
        &mut self,
        omega: &V,
        shown: &[bool; LANES],
        mid: &Samples,
        end: &Samples,
    ) -> [bool; LANES] {
        let mut eventful = [false; LANES];
        for l in 0..LANES {
            let (a, m, b) = (self.last.get(l), mid.get(l), end.get(l));
            let band = (self.band.0[l], self.band.1[l]);
            let events =
                scan::eventful(omega[l], band, &a, &m) | scan::eventful(omega[l], band, &m, &b);
            eventful[l] = shown[l] & events;
            let quiet = shown[l] & !events;
            let (lo, hi) = (self.window.0[l], self.window.1[l]);
            // the maxima in registers through the three samples, stored once: updated in place,
            // each was stored under a mask and read back at once by the next sample's update,
            // the read waiting on the store
            let (mut peak, mut lag) = (self.peak[l], self.lag[l]);
            for s in [a, m, b] {
                let counted = quiet & (s.t >= lo) & (s.t <= hi);
                let grow = |max: f64, x: f64| if counted { max.max(x.abs()) } else { max };
                peak = grow(peak, s.v);
                lag = grow(lag, s.e);
            }
            (self.peak[l], self.lag[l]) = (peak, lag);
            let grown = self.lobe[l].max(m.e.abs()).max(b.e.abs());
            self.lobe[l] = if quiet { grown } else { self.lobe[l] };
        }
        let mut moved = [false; LANES];
        for l in 0..LANES {
            moved[l] = shown[l] & !eventful[l];
        }
        self.last.select(&moved, end);
        eventful
    }

    /// Hands lane `l`'s quiet steps to its scanner ([`Scanner::resume`]) and starts afresh.
    fn hand_over(&mut self, l: usize, s: &mut Scanner) {
        s.resume(self.last.get(l), self.lobe[l], [self.peak[l], self.lag[l]]);
        (self.peak[l], self.lag[l], self.lobe[l]) = (0.0, 0.0, 0.0);
    }
}

/// The lanes' parameters, structure of arrays.
struct ParamLanes {
    alpha: V,
    gamma: V,
    eps: V,
    mu: V,
    delta: V,
    omega: V,
    /// 1/α (the equilibrium Newton step's scale).
    scale: V,
}

impl ParamLanes {
    fn new(p: &[Params; LANES]) -> ParamLanes {
        ParamLanes {
            alpha: p.map(|p| p.alpha),
            gamma: p.map(|p| p.gamma),
            eps: p.map(|p| p.eps),
            mu: p.map(|p| p.mu),
            delta: p.map(|p| p.delta),
            omega: p.map(|p| p.omega),
            scale: p.map(|p| 1.0 / p.alpha),
        }
    }

    #[inline(always)]
    fn get(&self, l: usize) -> Params {
        Params {
            alpha: self.alpha[l],
            gamma: self.gamma[l],
            eps: self.eps[l],
            mu: self.mu[l],
            delta: self.delta[l],
            omega: self.omega[l],
        }
    }
}

/// Which sample of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Point {
    Mid,
    End,
}

/// The lanes' equilibrium trackers' warm starts (see `EquilibriumTracker::state`), structure of
/// arrays.
#[derive(Default)]
struct Trackers {
    hint: V,
    last_a: V,
    slope: V,
    curvature: V,
}

impl Trackers {
    fn set(&mut self, l: usize, [h, a, s, c]: [f64; 4]) {
        (
            self.hint[l],
            self.last_a[l],
            self.slope[l],
            self.curvature[l],
        ) = (h, a, s, c);
    }

    fn get(&self, l: usize) -> [f64; 4] {
        [
            self.hint[l],
            self.last_a[l],
            self.slope[l],
            self.curvature[l],
        ]
    }
}

/// One sample per lane, structure of arrays.
#[derive(Default)]
struct Samples {
    t: V,
    x: V,
    v: V,
    acc: V,
    s: V,
    c: V,
    e: V,
    ed: V,
}

impl Samples {
    fn get(&self, l: usize) -> Sample {
        Sample {
            t: self.t[l],
            x: self.x[l],
            v: self.v[l],
            acc: self.acc[l],
            s: self.s[l],
            c: self.c[l],
            e: self.e[l],
            ed: self.ed[l],
        }
    }

    fn set(&mut self, l: usize, s: &Sample) {
        (self.t[l], self.x[l], self.v[l], self.acc[l]) = (s.t, s.x, s.v, s.acc);
        (self.s[l], self.c[l], self.e[l], self.ed[l]) = (s.s, s.c, s.e, s.ed);
    }

    /// Takes `other`'s sample in the lanes `which`, by selects over all lanes (stores made lane
    /// by lane under a branch left the next step's vector loads waiting on them).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    fn select(&mut self, which: &[bool; LANES], other: &Samples) {
        let pairs = [
            (&mut self.t, &other.t),
            (&mut self.x, &other.x),
            (&mut self.v, &other.v),
            (&mut self.acc, &other.acc),
            (&mut self.s, &other.s),
            (&mut self.c, &other.c),
            (&mut self.e, &other.e),
            (&mut self.ed, &other.ed),
        ];
        // from copies: on the references themselves (a table of them, whose targets the
        // compiler cannot tell apart) it chose lane by lane, a scalar load and store each, a
        // quarter of `absorb`
        for (mine, theirs) in pairs {
            let (old, new) = (*mine, *theirs);
            for l in 0..LANES {
                mine[l] = if which[l] { new[l] } else { old[l] };
            }
        }
    }
}

dispatched! {
    /// [`samples`] on the widest vector unit.
    fn samples_at(
        params: &ParamLanes,
        multi: &[(f64, f64); LANES],
        step: &StepLanes<'_>,
        trackers: &mut Trackers,
        at: Point,
        out: &mut Samples
    ) -> [bool; LANES] = samples::<FMA>(params, multi, step, trackers, at, out)
}

dispatched! {
    /// [`Quiet::absorb`] on the widest vector unit.
    fn absorb(
        quiet: &mut Quiet,
        omega: &V,
        shown: &[bool; LANES],
        mid: &Samples,
        end: &Samples
    ) -> [bool; LANES] = quiet.absorb(omega, shown, mid, end)
}

/// Every lane's sample at `at`, following each lane's equilibrium by at most two Newton steps
/// from the tracker's prediction (what `EquilibriumTracker::at` does on a branch alone); `false`
/// for a lane that needs more (its tracker state is then unchanged). The same arithmetic as the
/// scan of one trajectory, lane by lane, so the loop vectorises.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
fn samples<const FMA: bool>(
    params: &ParamLanes,
    multi: &[(f64, f64); LANES],
    step: &StepLanes<'_>,
    tr: &mut Trackers,
    at: Point,
    out: &mut Samples,
) -> [bool; LANES] {
    let mut ok = [false; LANES];
    let mut turned = [true; LANES];
    // x and x' (the end: the state the lane ended on) and sin ωt, cos ωt there
    let (t, x, v, s, c) = match at {
        Point::End => (
            *step.t1,
            *step.end.0,
            *step.end.1,
            *step.sin_cos.0,
            *step.sin_cos.1,
        ),
        Point::Mid => {
            let p = step.order;
            let (mut t, mut h) = ([0.0; LANES], [0.0; LANES]);
            for l in 0..LANES {
                t[l] = 0.5 * (step.t0[l] + step.t1[l]);
                h[l] = t[l] - step.t0[l];
            }
            // h as the compiler cannot see through: read back from memory it is one vector;
            // seen through, the compiler took each lane's h from where its computation left it
            // and split the sums (lanes 0 and 3 scalar, 1–2, 4–7 and 8–15 in three widths)
            let h = std::hint::black_box(h);
            let (x, v) = horner_lanes::<FMA>(&step.x[..=p], &step.v[..=p], &h);
            let (mut s, mut c) = ([0.0; LANES], [0.0; LANES]);
            // (`midpoint` without its branch to the library's sine: lanes past the series'
            // range are sampled on their own)
            for l in 0..LANES {
                let delta = params.omega[l] * (step.t1[l] - t[l]);
                turned[l] = delta.abs() <= TURN_BACK_MAX;
                (s[l], c[l]) = turn_back(step.sin_cos.0[l], step.sin_cos.1[l], delta);
            }
            (t, x, v, s, c)
        }
    };
    // the first Newton step of every lane from the tracker's prediction
    let (mut y, mut slope, mut curvature) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
    let (mut rhs, mut on_branch, mut settled) = ([0.0; LANES], [false; LANES], [false; LANES]);
    let mut again = false;
    for l in 0..LANES {
        let p = &params.get(l);
        let a = s[l];
        rhs[l] = p.forcing(a);
        let da = a - tr.last_a[l];
        let y0 = tr.hint[l] + da * (tr.slope[l] + 0.5 * tr.curvature[l] * da);
        let n = newton(p, params.scale[l], y0, rhs[l]);
        (y[l], slope[l], curvature[l]) = (n.y, n.slope, n.curvature);
        on_branch[l] = n.on_branch;
        settled[l] = n.on_branch & n.done;
        // (`|` and `&`, not `||` and `&&`: no branches, so the loop vectorises)
        again |= n.on_branch & !n.done;
    }
    // the second where a lane on its branch is not done after the first (where none is, as on
    // most steps, its result would be used nowhere: a lane off its branch is not kept, and its
    // sample is taken again by its scanner)
    if again {
        for l in 0..LANES {
            let p = &params.get(l);
            let n = newton(p, params.scale[l], y[l], rhs[l]);
            let first = settled[l];
            (y[l], slope[l], curvature[l]) = if first {
                (y[l], slope[l], curvature[l])
            } else {
                (n.y, n.slope, n.curvature)
            };
            settled[l] = first | (on_branch[l] & n.on_branch & n.done);
        }
    }
    for l in 0..LANES {
        let p = &params.get(l);
        let a = s[l];
        let (lo, hi) = multi[l];
        let unique = (a < lo) | (a > hi);
        let keep = unique & turned[l] & settled[l];
        ok[l] = keep;
        let pick = |new: f64, old: f64| if keep { new } else { old };
        tr.hint[l] = pick(y[l], tr.hint[l]);
        tr.last_a[l] = pick(a, tr.last_a[l]);
        tr.slope[l] = pick(slope[l], tr.slope[l]);
        tr.curvature[l] = pick(curvature[l], tr.curvature[l]);
        out.set(l, &measure(p, t[l], [x[l], v[l]], (s[l], c[l]), y[l], None));
    }
    ok
}

/// Lane `l`'s step as a [`DenseOutput`], evaluated on the batch's rows where they are: the same
/// arithmetic as the [`TaylorDense`](crate::integrate::taylor::TaylorDense) the batch shows, so
/// the same values, without gathering the lane's coefficients into one first (a copy on every
/// eventful step of a map).
struct LaneDense<'a, 'b> {
    step: &'a StepLanes<'b>,
    lane: usize,
}

impl<'a, 'b> LaneDense<'a, 'b> {
    fn new(step: &'a StepLanes<'b>, lane: usize) -> Self {
        LaneDense { step, lane }
    }
}

impl super::scan::ScanStep for LaneDense<'_, '_> {}

impl DenseOutput<2> for LaneDense<'_, '_> {
    fn t_start(&self) -> f64 {
        self.step.t0[self.lane]
    }
    fn t_end(&self) -> f64 {
        self.step.t1[self.lane]
    }
    fn eval(&self, t: f64) -> [f64; 2] {
        let (s, l) = (self.step, self.lane);
        let h = t - s.t0[l];
        [
            poly(|k| s.x[k][l], s.order, h),
            poly(|k| s.v[k][l], s.order, h),
        ]
    }
    fn end_state(&self) -> [f64; 2] {
        [self.step.end.0[self.lane], self.step.end.1[self.lane]]
    }
}

/// One step of every lane as kept for pulse onsets: start, end, which lanes it belongs to, x''s
/// rows and a lower bound of |x'| over the step ([`abs_floor`]). Kept boxed: the queue moves
/// pointers.
struct Kept {
    t0: V,
    t1: V,
    floor: V,
    shown: [bool; LANES],
    order: usize,
    v: [V; MAX_ORDER + 1],
}

/// The steps kept, oldest first, and the latest end of each lane (with whether the latest step
/// showed the lane).
struct Steps {
    kept: VecDeque<Box<Kept>>,
    /// Storage of forgotten steps, reused (boxed: moved in and out of the queue as pointers).
    #[allow(clippy::vec_box)]
    spare: Vec<Box<Kept>>,
    latest: V,
    live: [bool; LANES],
    simd: Simd,
}

impl Steps {
    fn new(simd: Simd) -> Steps {
        Steps {
            kept: VecDeque::new(),
            spare: Vec::new(),
            latest: [0.0; LANES],
            live: [false; LANES],
            simd,
        }
    }

    fn push(&mut self, step: &StepLanes<'_>, shown: &[bool; LANES]) {
        let mut k = self.spare.pop().unwrap_or_else(|| {
            Box::new(Kept {
                t0: [0.0; LANES],
                t1: [0.0; LANES],
                floor: [0.0; LANES],
                shown: [false; LANES],
                order: 0,
                v: [[0.0; LANES]; MAX_ORDER + 1],
            })
        });
        (k.t0, k.t1, k.shown, k.order) = (*step.t0, *step.t1, *shown, step.order);
        k.v[..=step.order].copy_from_slice(step.v);
        k.floor = floors(self.simd, step.v, step.t0, step.t1);
        self.kept.push_back(k);
        self.latest = *step.t1;
        self.live = *shown;
    }

    /// Forgets the oldest steps no lane can look back to: for each lane shown in the latest
    /// step, those ending more than its span before its latest end (the scan of one trajectory
    /// forgets the same ones); the others' scans are over.
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    fn forget(&mut self, span: &V) {
        while let Some(f) = self.kept.front() {
            // (`|` and `&` over all lanes, not `any`: no branch per lane)
            let mut needed = false;
            for l in 0..LANES {
                needed |= self.live[l] & f.shown[l] & (f.t1[l] >= self.latest[l] - span[l]);
            }
            if needed {
                break;
            }
            if let Some(k) = self.kept.pop_front() {
                self.spare.push(k);
            }
        }
    }
}

dispatched! {
    /// [`floors_of`] on the widest vector unit.
    fn floors(v: &[V], t0: &V, t1: &V) -> V = floors_of(v, t0, t1)
}

/// Each lane's lower bound of |x'| over its step from `t0` to `t1`, x''s coefficient rows `v`
/// ([`abs_floor`], as `TaylorDense::abs_floor` computes it).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
fn floors_of(v: &[V], t0: &V, t1: &V) -> V {
    let mut h = [0.0; LANES];
    for l in 0..LANES {
        h[l] = t1[l] - t0[l];
    }
    let Some((first, higher)) = v.split_first() else {
        return [f64::NEG_INFINITY; LANES];
    };
    let mut rest = [0.0; LANES];
    for row in higher.iter().rev() {
        for l in 0..LANES {
            rest[l] = rest[l] * h[l] + row[l].abs();
        }
    }
    let mut out = [0.0; LANES];
    for l in 0..LANES {
        out[l] = abs_floor(first[l].abs(), rest[l] * h[l]);
    }
    out
}

/// Lane `lane`'s kept steps, for [`Scanner`]'s onsets.
struct LanePast<'a> {
    steps: &'a Steps,
    lane: usize,
    span: f64,
}

impl Past for LanePast<'_> {
    fn onset(&self, t: f64, peak: f64) -> f64 {
        let l = self.lane;
        let from = self.steps.latest[l] - self.span;
        // the lane's steps ending within its span of its latest (the ones `History` keeps)
        let own = self
            .steps
            .kept
            .iter()
            .rev()
            .filter(|k| k.shown[l])
            .take_while(|k| k.t1[l] >= from)
            .map(|k| (k.t0[l], k.t1[l], &**k));
        let xdot = |k: &&Kept, s: f64| poly(|j| k.v[j][l], k.order, s - k.t0[l]);
        onset_in(own, t, peak, xdot, |k| k.floor[l])
    }
}
