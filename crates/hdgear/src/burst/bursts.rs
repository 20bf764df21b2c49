//! From located events to bursts: the floors below which an event is noise, the grouping of
//! events into bursts, their signatures, measures and spikes.

use super::*;

/// Integration noise in the state is this many times the tolerance scale atol + rtol·X:
/// smaller swings of x' and lobes of x − x* are truncation error, not motion (see
/// [`swing_floor`]). Measured: at ω = 1e-4 the truncation error of a 3-period run creates false
/// ringing with a factor 10 at rtol = 1e-6 … 1e-8 and none with 100, over the reference cases and
/// a 200-point γ sweep.
pub const NOISE_FACTOR: f64 = 100.0;

fn noise_floor(opts: &BurstOptions, x_extent: f64) -> f64 {
    NOISE_FACTOR * (opts.tol.atol + opts.tol.rtol * x_extent)
}

/// The swing floor of x' actually used: [`BurstOptions::swing_floor`]·ω·X, but never below
/// [`NOISE_FACTOR`]·(atol + rtol·X), the level the integration itself resolves. Without the
/// second term a loose tolerance at small ω turns truncation error into "ringing".
pub fn swing_floor(p: &impl StaticCurve, opts: &BurstOptions, x_extent: f64) -> f64 {
    physical_swing_floor(p, opts, x_extent).max(noise_floor(opts, x_extent))
}

/// The ringing floor the physics sets: [`BurstOptions::swing_floor`]·ω·X.
fn physical_swing_floor(p: &impl StaticCurve, opts: &BurstOptions, x_extent: f64) -> f64 {
    opts.swing_floor * p.omega() * x_extent
}

/// The overshoot floor the physics sets: [`BurstOptions::overshoot_floor`]·X.
fn physical_overshoot_floor(opts: &BurstOptions, x_extent: f64) -> f64 {
    opts.overshoot_floor * x_extent
}

/// The overshoot floor actually used: [`BurstOptions::overshoot_floor`]·X, never below the
/// noise level of [`swing_floor`].
pub fn overshoot_floor(opts: &BurstOptions, x_extent: f64) -> f64 {
    physical_overshoot_floor(opts, x_extent).max(noise_floor(opts, x_extent))
}

/// Where the integration's tolerance, not the physics, decides what counts as motion: its noise
/// floor [`NOISE_FACTOR`]·(atol + rtol·X) lies above the ringing floor
/// [`BurstOptions::swing_floor`]·ω·X or the overshoot floor [`BurstOptions::overshoot_floor`]·X,
/// so swings or lobes between the two are not counted and the verdict may differ from a tighter
/// run's.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ToleranceLimit {
    /// The noise floor in effect.
    pub noise_floor: f64,
    /// The smaller of the ringing and overshoot floors the physics sets.
    pub physical_floor: f64,
    /// The largest rtol (= atol) that puts the noise floor below the physical one: a power of ten.
    pub rtol_needed: f64,
}

impl std::fmt::Display for ToleranceLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the integration's noise floor {:.2e} is above the ringing/overshoot floor {:.2e}: \
             smaller swings are not counted and the verdict may differ at a tighter tolerance; \
             rerun with --rtol {:e} --atol {:e} or smaller",
            self.noise_floor, self.physical_floor, self.rtol_needed, self.rtol_needed
        )
    }
}

/// The [`ToleranceLimit`] of a run with `opts` on `p`, if any.
pub fn tolerance_limit(
    p: &impl StaticCurve,
    opts: &BurstOptions,
    x_extent: f64,
) -> Option<ToleranceLimit> {
    let physical =
        physical_swing_floor(p, opts, x_extent).min(physical_overshoot_floor(opts, x_extent));
    let noise = noise_floor(opts, x_extent);
    (noise > physical).then(|| ToleranceLimit {
        noise_floor: noise,
        physical_floor: physical,
        // NOISE_FACTOR·r·(1 + X) ≤ physical, rounded down to a power of ten
        rtol_needed: 10f64.powf(
            (physical / (NOISE_FACTOR * (1.0 + x_extent)))
                .log10()
                .floor(),
        ),
    })
}

/// One group of events while it is being built.
#[derive(Default)]
struct Group {
    start: f64,
    end: f64,
    pivots: Vec<Pivot>,
    lobes: Vec<f64>,
    jumps: u32,
}

/// The scanned events (extrema of x', overshoot lobes of at least `floor`, jumps) in groups:
/// events closer than `gap` belong together.
fn group_events(scan: &Scan, floor: f64, gap: f64) -> Vec<Group> {
    // events as (start, end, kind)
    enum Ev {
        Pivot(Pivot),
        Lobe(f64),
        Jump,
    }
    let mut events: Vec<(f64, f64, Ev)> = Vec::new();
    events.extend(scan.pivots.iter().map(|&q| (q.t, q.t, Ev::Pivot(q))));
    events.extend(
        scan.lobes
            .iter()
            .filter(|l| l.amp >= floor)
            .map(|l| (l.start, l.end, Ev::Lobe(l.amp))),
    );
    events.extend(scan.jumps.iter().map(|&t| (t, t, Ev::Jump)));
    events.sort_by(|a, b| a.0.total_cmp(&b.0));

    let mut groups: Vec<Group> = Vec::new();
    for (s, e, ev) in events {
        let join = groups.last().is_some_and(|g| s - g.end < gap);
        if !join {
            groups.push(Group {
                start: s,
                end: e,
                ..Group::default()
            });
        }
        let g = groups.last_mut().expect("a group was just pushed");
        g.end = g.end.max(e);
        match ev {
            Ev::Pivot(q) => g.pivots.push(q),
            Ev::Lobe(a) => g.lobes.push(a),
            Ev::Jump => g.jumps += 1,
        }
    }

    groups
}

/// The extrema of x' in group `g` that are the fast mode's: its pivots less the equilibrium's
/// own speed extrema beyond the first over the group's span (widened by a decay time each way,
/// the lag of x' behind x*), both pruned to swings of `floor`. The ringing rule (three extrema
/// or more) allows the one hump of the equilibrium's speed that a passage of the cubic has; a
/// curve whose speed has several (a scheduled stiffness, stiffest at the soft middle, gives two
/// humps and a dip between) would otherwise count its quasi-static motion as ringing.
fn fast_extrema(p: &impl StaticCurve, g: &Group, floor: f64) -> usize {
    let n = g.pivots.len();
    if n < 3 {
        return n;
    }
    let margin = p.decay_time();
    let raw = p.speed_extrema(g.start - margin, g.end + margin);
    let humps = super::scan::pruned_count(floor, &raw);
    n - humps.saturating_sub(1).min(n)
}

/// The bursts of `groups` with their pulse in the window, and whether any group is continuous
/// fast motion (longer than half a slow period).
fn bursts_of(
    p: &impl StaticCurve,
    opts: &BurstOptions,
    groups: &[Group],
    (t_w0, t_w1): (f64, f64),
    t_scan_end: f64,
    gap: f64,
    x_extent: f64,
) -> (Vec<Burst>, bool) {
    let period = p.slow_period();
    let omega_x = p.omega() * x_extent;
    let mut bursts = Vec::new();
    let mut continuous = false;
    let floor = swing_floor(p, opts, x_extent);
    for g in groups {
        let extrema = fast_extrema(p, g, floor);
        let ringing = extrema >= 3;
        if !(ringing || g.jumps > 0 || !g.lobes.is_empty()) {
            continue;
        }
        let Some((ip, pulse)) = g
            .pivots
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.v.abs().total_cmp(&b.1.v.abs()))
        else {
            continue; // a signature without any extremum of x' cannot be placed; never seen
        };
        if g.end - g.start > 0.5 * period && g.end > t_w0 && g.start < t_w1 {
            continuous = true;
        }
        if !(pulse.t >= t_w0 && pulse.t < t_w1) {
            continue;
        }
        let peak = pulse.v.abs();
        let swing = g.pivots[ip..]
            .windows(2)
            .skip(1)
            .map(|w| (w[1].v - w[0].v).abs())
            .fold(0.0, f64::max);
        let onset = pulse.onset.min(g.start);
        let end = g.end.max(pulse.t);
        bursts.push(Burst {
            onset,
            end,
            a_onset: (p.omega() * onset).sin(),
            duration: end - onset,
            t_peak: pulse.t,
            a_peak: (p.omega() * pulse.t).sin(),
            peak_abs_xdot: peak,
            spikes: spikes(&g.pivots, opts.spike_fraction),
            extrema: extrema as u32,
            ringing_swing: swing / omega_x,
            overshoot: g.lobes.iter().fold(0.0, |m: f64, &a| m.max(a)) / x_extent,
            overshoot_lobes: g.lobes.len() as u32,
            jumps: g.jumps,
            complete: g.end + gap <= t_scan_end,
        });
    }
    (bursts, continuous)
}

/// The signatures of the bursts found (and of the scan over the window).
fn signatures(
    bursts: &[Burst],
    scan: &Scan,
    (t_w0, t_w1): (f64, f64),
    n_periods: f64,
    x_extent: f64,
) -> Signatures {
    let jumps_in_window = scan
        .jumps
        .iter()
        .filter(|&&t| t >= t_w0 && t < t_w1)
        .count();
    let max_overshoot = scan
        .lobes
        .iter()
        .filter(|l| l.end >= t_w0 && l.start < t_w1)
        .fold(0.0, |m: f64, l| m.max(l.amp))
        / x_extent;
    Signatures {
        jump: bursts.iter().any(|b| b.jumps > 0),
        overshoot: bursts.iter().any(|b| b.overshoot_lobes > 0),
        ringing: bursts.iter().any(|b| b.extrema >= 3),
        jumps_per_period: jumps_in_window as f64 / n_periods,
        ringing_bursts_per_period: bursts.iter().filter(|b| b.extrema >= 3).count() as f64
            / n_periods,
        max_overshoot,
        max_ringing_swing: bursts.iter().fold(0.0, |m: f64, b| m.max(b.ringing_swing)),
    }
}

/// Groups the scanned events into bursts and computes the response's statistics.
pub(super) fn assemble(
    p: &impl StaticCurve,
    opts: &BurstOptions,
    scan: Scan,
    (t_w0, t_w1): (f64, f64),
    t_scan_end: f64,
    gap: f64,
    x_extent: f64,
) -> Response {
    let period = p.slow_period();
    let groups = group_events(&scan, overshoot_floor(opts, x_extent), gap);
    let (bursts, continuous) = bursts_of(p, opts, &groups, (t_w0, t_w1), t_scan_end, gap, x_extent);
    let n_periods = f64::from(opts.periods);
    let window = t_w1 - t_w0;
    let mean = |f: &dyn Fn(&Burst) -> f64| {
        if bursts.is_empty() {
            0.0
        } else {
            bursts.iter().map(f).sum::<f64>() / bursts.len() as f64
        }
    };
    let busy: f64 = bursts
        .iter()
        .map(|b| (b.end.min(t_w1) - b.onset.max(t_w0)).max(0.0))
        .sum();
    let quiescent_duration = if bursts.is_empty() {
        period
    } else {
        (window - busy) / bursts.len() as f64
    };
    let signatures = signatures(&bursts, &scan, (t_w0, t_w1), n_periods, x_extent);
    let measures = Measures {
        speed_ratio: scan.peak_abs_xdot / p.max_equilibrium_speed(),
        lag_ratio: scan.max_lag / p.max_first_order_lag(),
        relative_lag: scan.max_lag / x_extent,
    };
    Response {
        window_start: t_w0,
        window_end: t_w1,
        rates: Rates {
            bursts_per_period: (!continuous).then(|| bursts.len() as f64 / n_periods),
            spikes_per_burst: mean(&|b| f64::from(b.spikes)),
            burst_amplitude: mean(&|b| b.peak_abs_xdot),
            peak_abs_xdot: scan.peak_abs_xdot,
            quiescent_duration,
            quiescent_fraction: 1.0 - busy / window,
            max_tracking_error: scan.max_lag,
        },
        continuous_fast_motion: continuous,
        tolerance_limited: tolerance_limit(p, opts, x_extent),
        signatures,
        measures,
        x_extent,
        group_gap: gap,
        bursts,
        sticking: None,
    }
}

/// The spikes of a burst: its swings of x' (between consecutive extrema of the burst) of at least
/// `fraction` of its largest swing; at least 1 (the pulse) for any burst.
fn spikes(pivots: &[Pivot], fraction: f64) -> u32 {
    let swings = || pivots.windows(2).map(|w| (w[1].v - w[0].v).abs());
    let top = swings().fold(0.0, f64::max);
    (swings().filter(|&s| s >= fraction * top).count() as u32).max(1)
}
