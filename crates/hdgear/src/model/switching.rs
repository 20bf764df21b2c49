//! Models with switching terms (Coulomb friction's sgn x', the |x'| of LuGre and Bouc–Wen, the
//! |z| of Bouc–Wen's state) integrated piece by piece, sticking included ([`Switching`]).
//!
//! sgn x' is not analytic across x' = 0, so neither a Taylor series nor a Runge–Kutta step may
//! straddle it. A slipping piece fixes sgn x' = s in every switching term, and sgn z of every
//! internal state whose law holds |z| ([`Model::directed`]), which makes the right-hand side
//! analytic on the piece; each step's dense output is watched for s·x' (and each such sgn z·z)
//! falling through 0, and the step is cut at the located root. Where z reaches 0 the next piece
//! takes z's new sign from the direction z leaves 0 in (its first nonzero Taylor row). Where x'
//! reaches 0 the motion is at rest and the rest of the torque, A(t, y) = μ + δ sin ωt −
//! Σ T(x, 0, z) (the sticking terms' sign part left out), decides what follows: |A| ≤ the static
//! band ([`Model::breakaway`], 0 without a sticking term) sticks — x held, x' = 0, until |A|
//! reaches the band, an event located on A itself — and |A| > band slips again in the direction
//! of A (at x' = 0 the acceleration is A − sgn(A)·band, of A's sign). While it sticks, an
//! internal state whose rate vanishes at x' = 0 (a memory term's) is held with x; one that moves
//! on (a wave generator's angle, a washout's filter) is integrated by its own equation with x
//! held ([`Model::held`]), and A, which it enters, is followed along that motion.
//!
//! No regularisation constant enters: the events are located to a bracket of 1e-13·max(1, |t|)
//! ([`refine_root`]). A tangency of x' with 0 inside one eighth of a step, or of |A| with the band
//! inside 1/64 of a forcing period, is not seen (both need the motion to graze rest without
//! crossing it).
//!
//! ```
//! use hdgear::integrate::{Options, Stepper};
//! use hdgear::model::{Model, switching::{Pieces, Switching, SwitchingMode}, terms::AnyTerm};
//! use hdgear::Params;
//! let p = Params { delta: 1.0, omega: 0.5, ..Params::default() };
//! let m = Model::study(&p).with_term(AnyTerm::new("coulomb", &[0.3, 0.4, 0.1, 0.0]).unwrap()).unwrap();
//! let pieces = Pieces::new(&m).unwrap();
//! let mut s = Switching::<2>::new(&pieces, 0.0, [0.0, 0.0], Options::default()).unwrap();
//! let mut stuck = 0.0;
//! while s.t() < 40.0 {
//!     let (t0, was) = (s.t(), s.mode());
//!     s.step(40.0).unwrap();
//!     if was == SwitchingMode::Stuck { stuck += s.t() - t0; }
//! }
//! assert!(stuck > 0.0 && stuck < 40.0);
//! ```
//!
//! **Why one file.** The pieces of a switching model, its modes and its stepper (slip, stick,
//! drift, the switch located between them) are one state machine whose transitions must be read
//! together.

use super::Model;
use super::assembled::MAX_STATES;
use crate::error::{Result, SolverError};
use crate::integrate::events::{Detector, Direction, refine_root};
use crate::integrate::{
    AnyDense, AnyStepper, DenseOutput, Options, Stats, Stepper, System, Taylor, stepper,
};
use serde::Serialize;

/// Sub-intervals per step in which s·x' (and sgn z·z) is sampled for its fall through 0.
const SUBDIVISIONS: usize = 8;
/// Samples of |A(t, y)| − band per forcing period while stuck (and per period of the fastest load
/// that acts whatever the motion, [`Model::load_frequency`], while an internal state moves on).
const STICK_SAMPLES: f64 = 64.0;
/// Switches in a row without the time advancing before the run is refused as chattering.
const MAX_STALLS: u32 = 8;
/// Combinations of the internal states' signs.
const SIGNS: usize = 1 << MAX_STATES;

/// A model with switching terms on its pieces: x' > 0 and x' < 0, each for every combination
/// of the switching internal states' signs, and at rest.
#[derive(Clone, Copy, Debug)]
pub struct Pieces {
    free: Model,
    /// `free` with the motion held ([`Model::held`]): the rest of a model whose internal states
    /// move on.
    held: Model,
    /// [x' > 0, x' < 0][bit j set: sgn z_j = −1].
    slipping: [[Model; SIGNS]; 2],
    band: f64,
}

impl Pieces {
    /// The pieces of `model`; `None` when no term switches (every term smooth).
    pub fn new(model: &Model) -> Option<Pieces> {
        if !model.switches() {
            return None;
        }
        let piece = |v: f64, bits: usize| {
            let z = std::array::from_fn(|j| if bits >> j & 1 == 1 { -1.0 } else { 1.0 });
            model.directed(v, z)
        };
        let free = model.directed(0.0, [0.0; MAX_STATES]);
        Some(Pieces {
            free,
            held: free.held(),
            slipping: [
                std::array::from_fn(|b| piece(1.0, b)),
                std::array::from_fn(|b| piece(-1.0, b)),
            ],
            band: model.breakaway().unwrap_or(0.0),
        })
    }

    /// The model, every sign read from the state (0 at 0): right wherever no switching
    /// quantity is 0.
    pub fn model(&self) -> &Model {
        &self.free
    }

    /// Every slipping piece (each sign of x' and of the switching states).
    pub(crate) fn slipping_pieces(&self) -> impl Iterator<Item = &Model> {
        self.slipping.iter().flatten()
    }

    /// The static band: the sum of the sticking terms' breakaway torques (0 without one).
    pub fn band(&self) -> f64 {
        self.band
    }

    /// A(t, y): x'' at rest (y's x' taken as 0) without the sticking terms' sign part, the
    /// torque the static band holds.
    pub fn applied(&self, t: f64, y: &[f64]) -> f64 {
        let mut at_rest = [0.0; 2 + MAX_STATES];
        at_rest[..y.len()].copy_from_slice(y);
        at_rest[1] = 0.0;
        self.free
            .accel_at(self.free.forcing()[2] * t, &at_rest[..y.len()])
    }

    /// |A(t, y)| − band: positive where the motion at rest breaks away.
    fn excess(&self, t: f64, y: &[f64]) -> f64 {
        self.applied(t, y).abs() - self.band
    }

    /// The spacing of the samples of [`Pieces::excess`] while stuck: 1/[`STICK_SAMPLES`] of the
    /// forcing's period, and of the fastest load's where there is one.
    fn stick_spacing(&self) -> f64 {
        let fastest = self.free.load_frequency();
        std::f64::consts::TAU / self.free.forcing()[2].max(fastest) / STICK_SAMPLES
    }

    /// What the motion does from rest at (t, y): sticks while |A| ≤ band, else slips along A.
    pub fn mode_at_rest(&self, t: f64, y: &[f64]) -> SwitchingMode {
        let a = self.applied(t, y);
        if a.abs() <= self.band {
            SwitchingMode::Stuck
        } else {
            SwitchingMode::slipping(a)
        }
    }

    /// What the motion does at the start of a run from rest at (t, y), and the time whose
    /// Taylor rows give the internal states' signs ([`Pieces::signs`]): as
    /// [`Pieces::mode_at_rest`] at t, except where A changes sign within 1/64 of a stick
    /// sample's spacing h (1/4096 of the forcing's period). That is a start on an equilibrium,
    /// where A vanishes to its rounding and its sign says nothing: the motion leaves rest as A
    /// pushes at t + h (before that, the drive moves by at most |A|·h²/2), and a state at 0
    /// leaves it as that push moves it, its signs read at t + h.
    fn mode_leaving_rest(&self, t: f64, y: &[f64]) -> (SwitchingMode, f64) {
        match self.mode_at_rest(t, y) {
            SwitchingMode::Stuck => (SwitchingMode::Stuck, t),
            slipping => {
                let later_t = t + self.stick_spacing() / 64.0;
                let later = self.applied(later_t, y);
                if later * slipping.side() < 0.0 {
                    (SwitchingMode::slipping(later), later_t)
                } else {
                    (slipping, t)
                }
            }
        }
    }

    /// The piece of a slipping `mode` with the internal states' signs `bits`.
    pub(crate) fn piece(&self, mode: SwitchingMode, bits: usize) -> &Model {
        match mode {
            SwitchingMode::Forward => &self.slipping[0][bits],
            SwitchingMode::Backward => &self.slipping[1][bits],
            SwitchingMode::Stuck => &self.free,
        }
    }

    /// The signs of the switching internal states at (t, y) for a slipping `mode`: each z's own
    /// sign, or where z = 0 the sign of its first nonzero Taylor row on the piece (the direction
    /// it leaves 0 in; the rows below it do not depend on that sign, the |z| parts vanishing at
    /// z = 0 to the order of z's exponent).
    fn signs<const N: usize>(&self, mode: SwitchingMode, t: f64, y: &[f64; N]) -> usize {
        let mut bits = 0;
        let mut rows = None;
        for i in self.free.switching_states() {
            let negative = if y[i] != 0.0 {
                y[i] < 0.0
            } else {
                let c = rows.get_or_insert_with(|| {
                    let mut c = [[0.0; N]; 9];
                    self.piece(mode, 0).taylor(t, y, 8, &mut c);
                    c
                });
                c.iter().map(|r| r[i]).find(|&r| r != 0.0).unwrap_or(0.0) < 0.0
            };
            bits |= usize::from(negative) << (i - 2);
        }
        bits
    }
}

/// The mode of a switching integration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SwitchingMode {
    /// Slipping with x' > 0.
    Forward,
    /// Slipping with x' < 0.
    Backward,
    /// At rest inside the static band.
    Stuck,
}

impl SwitchingMode {
    /// Slipping in the direction of `a` (which is ≠ 0).
    fn slipping(a: f64) -> SwitchingMode {
        if a > 0.0 {
            SwitchingMode::Forward
        } else {
            SwitchingMode::Backward
        }
    }

    /// sgn x' in this mode.
    pub fn side(self) -> f64 {
        match self {
            SwitchingMode::Forward => 1.0,
            SwitchingMode::Backward => -1.0,
            SwitchingMode::Stuck => 0.0,
        }
    }
}

/// A change of mode, located.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Switch {
    /// When.
    pub t: f64,
    /// x there (x' = 0 at every switch).
    pub x: f64,
    /// The mode left.
    pub from: SwitchingMode,
    /// The mode entered.
    pub to: SwitchingMode,
}

/// The dense output of one step of a [`Switching`] integration.
// the slipping variant holds the step polynomial by value: dense outputs are `Copy` and on the
// stack, a box would allocate on every step
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug)]
pub enum SwitchingDense<const N: usize> {
    /// A slipping step, cut at `t_end` where it ended on a switch.
    Slip {
        /// The piece's step.
        inner: AnyDense<N>,
        /// Where the step ends (the switch, or the inner step's end).
        t_end: f64,
        /// The state there.
        y_end: [f64; N],
    },
    /// At rest with internal states that move on: a step of the held model ([`Model::held`]),
    /// cut at `t_end` where the motion breaks away.
    Drift {
        /// The held model's step.
        inner: AnyDense<N>,
        /// Where the step ends (the breakaway, or the inner step's end).
        t_end: f64,
        /// The state there.
        y_end: [f64; N],
    },
    /// At rest: the state held (x' = 0).
    Stuck {
        /// Start.
        t0: f64,
        /// End.
        t1: f64,
        /// The held state.
        y: [f64; N],
    },
}

impl<const N: usize> SwitchingDense<N> {
    /// Whether the motion is at rest on this step (held, or drifting with moving internal
    /// states).
    pub fn is_stuck(&self) -> bool {
        !matches!(self, SwitchingDense::Slip { .. })
    }
}

impl<const N: usize> DenseOutput<N> for SwitchingDense<N> {
    fn t_start(&self) -> f64 {
        match self {
            SwitchingDense::Slip { inner, .. } | SwitchingDense::Drift { inner, .. } => {
                inner.t_start()
            }
            SwitchingDense::Stuck { t0, .. } => *t0,
        }
    }
    fn t_end(&self) -> f64 {
        match self {
            SwitchingDense::Slip { t_end, .. } | SwitchingDense::Drift { t_end, .. } => *t_end,
            SwitchingDense::Stuck { t1, .. } => *t1,
        }
    }
    fn eval(&self, t: f64) -> [f64; N] {
        match self {
            SwitchingDense::Slip { inner, .. } | SwitchingDense::Drift { inner, .. } => {
                inner.eval(t)
            }
            SwitchingDense::Stuck { y, .. } => *y,
        }
    }
    fn end_state(&self) -> [f64; N] {
        match self {
            SwitchingDense::Slip { y_end, .. } | SwitchingDense::Drift { y_end, .. } => *y_end,
            SwitchingDense::Stuck { y, .. } => *y,
        }
    }
    /// The inner step's bound (over its whole step, so over the cut one too).
    fn abs_bound(&self, i: usize) -> Option<f64> {
        match self {
            SwitchingDense::Slip { inner, .. } | SwitchingDense::Drift { inner, .. } => {
                inner.abs_bound(i)
            }
            SwitchingDense::Stuck { y, .. } => Some(y.get(i)?.abs()),
        }
    }
    /// The inner step's floor (over its whole step, so over the cut one too).
    fn abs_floor(&self, i: usize) -> Option<f64> {
        match self {
            SwitchingDense::Slip { inner, .. } | SwitchingDense::Drift { inner, .. } => {
                inner.abs_floor(i)
            }
            SwitchingDense::Stuck { y, .. } => Some(y.get(i)?.abs()),
        }
    }
}

/// A [`Stepper`] for a model with switching terms, N = [`Model::dim`]: each slipping piece by
/// the method of `opts` on the piece's analytic model, steps cut at the located switch,
/// sticking held exactly (module docs).
pub struct Switching<'p, const N: usize> {
    pieces: &'p Pieces,
    opts: Options,
    inner: Option<AnyStepper<'p, Model, N>>,
    mode: SwitchingMode,
    /// The switching internal states' signs on the current piece.
    bits: usize,
    t: f64,
    y: [f64; N],
    dense: SwitchingDense<N>,
    /// Work of the finished pieces and the held intervals.
    done: Stats,
    last: Option<Switch>,
    stalls: u32,
}

impl<'p, const N: usize> Switching<'p, N> {
    /// Starts at (t0, y0): slipping along x' if it is ≠ 0, else as [`Pieces::mode_at_rest`]
    /// (the direction of leaving an equilibrium start taken from A a moment later).
    pub fn new(pieces: &'p Pieces, t0: f64, y0: [f64; N], opts: Options) -> Result<Self> {
        opts.validate()?;
        let (mode, signs_at) = if y0[1] == 0.0 {
            pieces.mode_leaving_rest(t0, &y0)
        } else {
            (SwitchingMode::slipping(y0[1]), t0)
        };
        let mut s = Switching {
            pieces,
            opts,
            inner: None,
            mode,
            bits: 0,
            t: t0,
            y: y0,
            dense: SwitchingDense::Stuck { t0, t1: t0, y: y0 },
            done: Stats::default(),
            last: None,
            stalls: 0,
        };
        s.enter_reading_signs_at(mode, signs_at)?;
        Ok(s)
    }

    /// The current mode.
    pub fn mode(&self) -> SwitchingMode {
        self.mode
    }

    /// The switch the last step ended on, if it ended on one.
    pub fn last_switch(&self) -> Option<Switch> {
        self.last
    }

    /// Enters `mode` at the current (t, y): a fresh stepper on its piece when it slips.
    fn enter(&mut self, mode: SwitchingMode) -> Result<()> {
        self.enter_reading_signs_at(mode, self.t)
    }

    /// [`Switching::enter`], the internal states' signs read from the piece's Taylor rows at
    /// `signs_at` (the current t but at an equilibrium start, [`Pieces::mode_leaving_rest`]).
    fn enter_reading_signs_at(&mut self, mode: SwitchingMode, signs_at: f64) -> Result<()> {
        self.mode = mode;
        if let Some(inner) = &self.inner {
            let s = inner.stats();
            self.done.steps += s.steps;
            self.done.rejected += s.rejected;
            self.done.rhs_evals += s.rhs_evals;
        }
        if mode != SwitchingMode::Stuck {
            self.bits = self.pieces.signs(mode, signs_at, &self.y);
            // a Taylor stepper moves to the new piece in place (a new one is a pass and a
            // workspace to fill, at every switch)
            if let Some(AnyStepper::Taylor(t)) = self.inner.as_mut() {
                t.restart(self.pieces.piece(mode, self.bits), self.t, self.y);
                return Ok(());
            }
        }
        self.inner = match mode {
            SwitchingMode::Stuck => {
                self.y[1] = 0.0;
                let p = self.pieces;
                if p.held.moves_at_rest(&self.y) {
                    Some(stepper(&p.held, self.t, self.y, self.opts)?)
                } else {
                    None
                }
            }
            _ => {
                let piece = self.pieces.piece(mode, self.bits);
                Some(stepper(piece, self.t, self.y, self.opts)?)
            }
        };
        Ok(())
    }

    /// Counts a cut at `t` (refused as chattering after [`MAX_STALLS`] without progress) and
    /// moves to (t, y).
    fn cut(&mut self, t: f64, y: [f64; N]) -> Result<()> {
        self.stalls = if t > self.t { 0 } else { self.stalls + 1 };
        if self.stalls > MAX_STALLS {
            return Err(SolverError::Chattering {
                t,
                switches: self.stalls,
            }
            .into());
        }
        (self.t, self.y) = (t, y);
        Ok(())
    }

    /// Ends the current mode at (t, y) at rest and enters `to`.
    fn switch(&mut self, t: f64, mut y: [f64; N], to: SwitchingMode) -> Result<()> {
        y[1] = 0.0;
        self.cut(t, y)?;
        self.last = Some(Switch {
            t,
            x: y[0],
            from: self.mode,
            to,
        });
        self.enter(to)
    }

    /// Held at rest from the current t: until |A(t, y)| reaches the band (then slipping along
    /// A) or `t_bound`.
    fn hold(&mut self, t_bound: f64) -> Result<()> {
        let (p, y) = (self.pieces, self.y);
        let [_, delta, _] = p.free.forcing();
        let g = |t: f64| p.excess(t, &y);
        // with δ = 0 the applied torque is constant: stuck for good
        let end = if delta == 0.0 { self.t } else { t_bound };
        let (unstick, samples) = first_rise(g, self.t, end, p.stick_spacing());
        self.done.rhs_evals += samples;
        let t1 = unstick.unwrap_or(t_bound);
        self.done.steps += 1;
        self.dense = SwitchingDense::Stuck { t0: self.t, t1, y };
        self.last = None;
        match unstick {
            Some(t) => self.switch(t, y, SwitchingMode::slipping(p.applied(t, &y))),
            None => {
                self.t = t_bound;
                Ok(())
            }
        }
    }

    /// A step `d` of the held model while stuck ([`Model::held`]), ending at (t1, y1): the stick
    /// ends where |A| reaches the band along it ([`first_rise`]).
    fn drift(&mut self, d: AnyDense<N>, (t1, y1): (f64, [f64; N])) -> Result<()> {
        let p = self.pieces;
        let (unstick, samples) =
            first_rise(|t| p.excess(t, &d.eval(t)), self.t, t1, p.stick_spacing());
        self.done.rhs_evals += samples;
        let (t_end, y_end) = unstick.map_or((t1, y1), |t| (t, d.eval(t)));
        self.dense = SwitchingDense::Drift {
            inner: d,
            t_end,
            y_end,
        };
        self.last = None;
        match unstick {
            Some(t) => self.switch(t, y_end, SwitchingMode::slipping(p.applied(t, &y_end))),
            None => {
                (self.t, self.y) = (t1, y1);
                Ok(())
            }
        }
    }
}

/// The first t in [t0, t1] where g rises above 0 (t0 itself where g(t0) > 0), from samples
/// `spacing` apart, located on g ([`refine_root`]); with the number of samples taken after t0.
fn first_rise(g: impl Fn(f64) -> f64, t0: f64, t1: f64, spacing: f64) -> (Option<f64>, u64) {
    let (mut ta, mut ga) = (t0, g(t0));
    if ga > 0.0 {
        return (Some(t0), 0);
    }
    let mut samples = 0;
    while ta < t1 {
        let tb = (ta + spacing).min(t1);
        let gb = g(tb);
        samples += 1;
        if gb > 0.0 {
            return (Some(refine_root(&g, ta, ga, tb, gb)), samples);
        }
        (ta, ga) = (tb, gb);
    }
    (None, samples)
}

impl<const N: usize> Stepper<N> for Switching<'_, N> {
    type Dense = SwitchingDense<N>;
    fn t(&self) -> f64 {
        self.t
    }
    fn y(&self) -> &[f64; N] {
        &self.y
    }
    fn step(&mut self, t_bound: f64) -> Result<()> {
        if let Some(e) = self.spent() {
            return Err(e.into());
        }
        let Some(inner) = self.inner.as_mut() else {
            return self.hold(t_bound);
        };
        inner.step(t_bound)?;
        self.after_inner_step()
    }
    fn dense(&mut self) -> SwitchingDense<N> {
        self.dense
    }
    fn stats(&self) -> Stats {
        let mut s = self.done;
        if let Some(inner) = &self.inner {
            let i = inner.stats();
            s.steps += i.steps;
            s.rejected += i.rejected;
            s.rhs_evals += i.rhs_evals;
        }
        s
    }
}

impl<'p, const N: usize> Switching<'p, N> {
    /// The error of a spent budget of steps or time, checked before every step.
    pub(crate) fn spent(&self) -> Option<SolverError> {
        self.opts.spent(self.stats().steps, self.t)
    }

    /// The Taylor stepper of the current slipping piece ([`Switching::piece`]): what a batch on vector
    /// lanes steps ([`super::integrate_switching_models`]), followed by
    /// [`Switching::after_inner_step`]. `None` at rest, or when the pieces run another method.
    pub(crate) fn on_piece(&mut self) -> Option<&mut Taylor<'p, Model, N>> {
        if self.mode == SwitchingMode::Stuck {
            return None;
        }
        match self.inner.as_mut() {
            Some(AnyStepper::Taylor(t)) => Some(t),
            _ => None,
        }
    }

    /// The current piece: the slipping one, or at rest the model with every sign read from the
    /// state.
    pub(crate) fn piece(&self) -> &'p Model {
        self.pieces.piece(self.mode, self.bits)
    }

    /// The rest of a step once the inner stepper has taken its own: the step cut at the first
    /// switch located on it, and the mode or piece that follows.
    pub(crate) fn after_inner_step(&mut self) -> Result<()> {
        let Some(inner) = self.inner.as_mut() else {
            return Ok(());
        };
        let d = inner.dense();
        if self.mode == SwitchingMode::Stuck {
            let end = (inner.t(), *inner.y());
            return self.drift(d, end);
        }
        // the first fall through 0 of s·x' (i = 1) or of a switching state's sgn z·z
        let mut first: Option<(usize, crate::integrate::events::Crossing<N>)> = None;
        let watched = std::iter::once((1, self.mode.side())).chain(
            self.pieces.free.switching_states().map(|i| {
                let negative = self.bits >> (i - 2) & 1 == 1;
                (i, if negative { -1.0 } else { 1.0 })
            }),
        );
        for (i, sign) in watched {
            // |y_i| > 0 across the whole step: no switch of it in the step
            if d.abs_floor(i).is_some_and(|f| f > 0.0) {
                continue;
            }
            let mut falls = Detector::new(|_, y: &[f64; N]| sign * y[i], Direction::Falling);
            falls.subdivisions = SUBDIVISIONS;
            let mut found = None;
            falls.scan(&d, |c| {
                found.get_or_insert(c);
            });
            if let Some(c) = found.filter(|c| first.is_none_or(|(_, f)| c.t < f.t)) {
                first = Some((i, c));
            }
        }
        let Some((i, c)) = first else {
            (self.t, self.y) = (inner.t(), *inner.y());
            self.dense = SwitchingDense::Slip {
                inner: d,
                t_end: self.t,
                y_end: self.y,
            };
            self.last = None;
            return Ok(());
        };
        let mut y = c.y;
        y[i] = 0.0;
        self.dense = SwitchingDense::Slip {
            inner: d,
            t_end: c.t,
            y_end: y,
        };
        if i == 1 {
            let to = self.pieces.mode_at_rest(c.t, &y);
            self.switch(c.t, y, to)
        } else {
            // an internal state through 0: the same motion on the piece of z's new sign
            self.cut(c.t, y)?;
            self.last = None;
            self.enter(self.mode)
        }
    }
}
