//! Models with a switching term (Coulomb friction's sgn x') integrated piece by piece, sticking
//! included ([`Switching`]).
//!
//! sgn x' is not analytic across x' = 0, so neither a Taylor series nor a Runge–Kutta step may
//! straddle it. A slipping piece fixes sgn x' = s in every switching term ([`Model::directed`]),
//! which makes the right-hand side analytic on the piece; each step's dense output is watched for
//! s·x' falling through 0, and the step is cut at the located root. There the motion is at rest
//! and the rest of the torque, A(t, x) = μ + δ sin ωt − Σ T(x, 0) (the switching terms' sign part
//! left out), decides what follows: |A| ≤ the static band ([`Model::breakaway`]) sticks — x held,
//! x' = 0, until |A(t, x)| reaches the band, an event located on A itself — and |A| > band slips
//! again in the direction of A (at x' = 0 the acceleration is A − sgn(A)·band, of A's sign).
//!
//! No regularisation constant enters: the events are located to a bracket of 1e-13·max(1, |t|)
//! ([`refine_root`]). A tangency of x' with 0 inside one eighth of a step, or of |A| with the band
//! inside 1/64 of a forcing period, is not seen (both need the motion to graze rest without
//! crossing it).
//!
//! ```
//! use hdgear::integrate::{Options, Stepper};
//! use hdgear::model::{Model, switching::{Mode, Pieces, Switching}, terms::AnyTerm};
//! use hdgear::Params;
//! let p = Params { delta: 1.0, omega: 0.5, ..Params::default() };
//! let m = Model::study(&p).with_term(AnyTerm::new("coulomb", &[0.3, 0.4, 0.1, 0.0]).unwrap()).unwrap();
//! let pieces = Pieces::new(&m).unwrap();
//! let mut s = Switching::new(&pieces, 0.0, [0.0, 0.0], Options::default()).unwrap();
//! let mut stuck = 0.0;
//! while s.t() < 40.0 {
//!     let (t0, was) = (s.t(), s.mode());
//!     s.step(40.0).unwrap();
//!     if was == Mode::Stuck { stuck += s.t() - t0; }
//! }
//! assert!(stuck > 0.0 && stuck < 40.0);
//! ```

use super::Model;
use crate::error::{Result, SolverError};
use crate::integrate::events::{Detector, Direction, refine_root};
use crate::integrate::{AnyDense, AnyStepper, DenseOutput, Options, Stats, Stepper, stepper};
use serde::Serialize;

/// Sub-intervals per step in which s·x' is sampled for its fall through 0.
const SUBDIVISIONS: usize = 8;
/// Samples of |A(t, x)| − band per forcing period while stuck.
const STICK_SAMPLES: f64 = 64.0;
/// Switches in a row without the time advancing before the run is refused as chattering.
const MAX_STALLS: u32 = 8;

/// A model with switching terms on its three pieces: x' > 0, x' < 0 and at rest.
#[derive(Clone, Copy, Debug)]
pub struct Pieces {
    free: Model,
    forward: Model,
    backward: Model,
    band: f64,
}

impl Pieces {
    /// The pieces of `model`; `None` when it has no switching term (every term smooth).
    pub fn new(model: &Model) -> Option<Pieces> {
        let band = model.breakaway()?;
        Some(Pieces {
            free: model.directed(0.0),
            forward: model.directed(1.0),
            backward: model.directed(-1.0),
            band,
        })
    }

    /// The model, sgn x' read from x' (0 at rest): right wherever x' ≠ 0.
    pub fn model(&self) -> &Model {
        &self.free
    }

    /// The static band: the sum of the switching terms' breakaway torques.
    pub fn band(&self) -> f64 {
        self.band
    }

    /// A(t, x): x'' at rest without the switching terms' sign part, the torque the static band
    /// holds.
    pub fn applied(&self, t: f64, x: f64) -> f64 {
        self.free.accel(self.free.forcing()[2] * t, x, 0.0)
    }

    /// What the motion does from rest at (t, x): sticks while |A| ≤ band, else slips along A.
    pub fn mode_at_rest(&self, t: f64, x: f64) -> Mode {
        let a = self.applied(t, x);
        if a.abs() <= self.band {
            Mode::Stuck
        } else {
            Mode::slipping(a)
        }
    }

    fn piece(&self, mode: Mode) -> &Model {
        match mode {
            Mode::Forward => &self.forward,
            Mode::Backward => &self.backward,
            Mode::Stuck => &self.free,
        }
    }
}

/// The mode of a switching integration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// Slipping with x' > 0.
    Forward,
    /// Slipping with x' < 0.
    Backward,
    /// At rest inside the static band.
    Stuck,
}

impl Mode {
    /// Slipping in the direction of `a` (which is ≠ 0).
    fn slipping(a: f64) -> Mode {
        if a > 0.0 {
            Mode::Forward
        } else {
            Mode::Backward
        }
    }

    /// sgn x' in this mode.
    pub fn side(self) -> f64 {
        match self {
            Mode::Forward => 1.0,
            Mode::Backward => -1.0,
            Mode::Stuck => 0.0,
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
    pub from: Mode,
    /// The mode entered.
    pub to: Mode,
}

/// The dense output of one step of a [`Switching`] integration.
// the slipping variant holds the step polynomial by value: dense outputs are `Copy` and on the
// stack, a box would allocate on every step
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug)]
pub enum SwitchingDense {
    /// A slipping step, cut at `t_end` where it ended on a switch.
    Slip {
        /// The piece's step.
        inner: AnyDense<2>,
        /// Where the step ends (the switch, or the inner step's end).
        t_end: f64,
        /// The state there.
        y_end: [f64; 2],
    },
    /// At rest: x held, x' = 0.
    Stuck {
        /// Start.
        t0: f64,
        /// End.
        t1: f64,
        /// The held x.
        x: f64,
    },
}

impl DenseOutput<2> for SwitchingDense {
    fn t_start(&self) -> f64 {
        match self {
            SwitchingDense::Slip { inner, .. } => inner.t_start(),
            SwitchingDense::Stuck { t0, .. } => *t0,
        }
    }
    fn t_end(&self) -> f64 {
        match self {
            SwitchingDense::Slip { t_end, .. } => *t_end,
            SwitchingDense::Stuck { t1, .. } => *t1,
        }
    }
    fn eval(&self, t: f64) -> [f64; 2] {
        match self {
            SwitchingDense::Slip { inner, .. } => inner.eval(t),
            SwitchingDense::Stuck { x, .. } => [*x, 0.0],
        }
    }
    fn end_state(&self) -> [f64; 2] {
        match self {
            SwitchingDense::Slip { y_end, .. } => *y_end,
            SwitchingDense::Stuck { x, .. } => [*x, 0.0],
        }
    }
    /// The inner step's bound (over its whole step, so over the cut one too).
    fn abs_bound(&self, i: usize) -> Option<f64> {
        match self {
            SwitchingDense::Slip { inner, .. } => inner.abs_bound(i),
            SwitchingDense::Stuck { x, .. } => Some([x.abs(), 0.0].get(i).copied()?),
        }
    }
    /// The inner step's floor (over its whole step, so over the cut one too).
    fn abs_floor(&self, i: usize) -> Option<f64> {
        match self {
            SwitchingDense::Slip { inner, .. } => inner.abs_floor(i),
            SwitchingDense::Stuck { x, .. } => Some([x.abs(), 0.0].get(i).copied()?),
        }
    }
}

/// A [`Stepper`] for a model with switching terms: each slipping piece by the method of
/// `opts` on the piece's analytic model, steps cut at the located switch, sticking held exactly
/// (module docs).
pub struct Switching<'p> {
    pieces: &'p Pieces,
    opts: Options,
    inner: Option<AnyStepper<'p, Model, 2>>,
    mode: Mode,
    t: f64,
    y: [f64; 2],
    dense: SwitchingDense,
    /// Work of the finished pieces and the held intervals.
    done: Stats,
    last: Option<Switch>,
    stalls: u32,
}

impl<'p> Switching<'p> {
    /// Starts at (t0, y0): slipping along x' if it is ≠ 0, else as [`Pieces::mode_at_rest`].
    pub fn new(pieces: &'p Pieces, t0: f64, y0: [f64; 2], opts: Options) -> Result<Self> {
        opts.validate()?;
        let mode = if y0[1] == 0.0 {
            pieces.mode_at_rest(t0, y0[0])
        } else {
            Mode::slipping(y0[1])
        };
        let mut s = Switching {
            pieces,
            opts,
            inner: None,
            mode,
            t: t0,
            y: y0,
            dense: SwitchingDense::Stuck {
                t0,
                t1: t0,
                x: y0[0],
            },
            done: Stats::default(),
            last: None,
            stalls: 0,
        };
        s.enter(mode)?;
        Ok(s)
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The switch the last step ended on, if it ended on one.
    pub fn last_switch(&self) -> Option<Switch> {
        self.last
    }

    /// Enters `mode` at the current (t, y): a fresh stepper on its piece when it slips.
    fn enter(&mut self, mode: Mode) -> Result<()> {
        self.mode = mode;
        self.inner = match mode {
            Mode::Stuck => {
                self.y[1] = 0.0;
                None
            }
            _ => Some(stepper(self.pieces.piece(mode), self.t, self.y, self.opts)?),
        };
        Ok(())
    }

    /// Ends the current mode at (t, x) at rest and enters `to`.
    fn switch(&mut self, t: f64, x: f64, to: Mode) -> Result<()> {
        self.stalls = if t > self.t { 0 } else { self.stalls + 1 };
        if self.stalls > MAX_STALLS {
            return Err(SolverError::Chattering {
                t,
                switches: self.stalls,
            }
            .into());
        }
        if let Some(inner) = self.inner.take() {
            let s = inner.stats();
            self.done.steps += s.steps;
            self.done.rejected += s.rejected;
            self.done.rhs_evals += s.rhs_evals;
        }
        self.last = Some(Switch {
            t,
            x,
            from: self.mode,
            to,
        });
        (self.t, self.y) = (t, [x, 0.0]);
        self.enter(to)
    }

    /// Held at rest from the current t: until |A(t, x)| reaches the band (then slipping along
    /// A) or `t_bound`.
    fn hold(&mut self, t_bound: f64) -> Result<()> {
        let (p, x) = (self.pieces, self.y[0]);
        let [_, delta, omega] = p.free.forcing();
        let g = |t: f64| p.applied(t, x).abs() - p.band;
        let spacing = std::f64::consts::TAU / omega / STICK_SAMPLES;
        let (mut ta, mut ga) = (self.t, g(self.t));
        let mut unstick = (ga > 0.0).then_some(ta);
        // with δ = 0 the applied torque is constant: stuck for good
        while unstick.is_none() && delta != 0.0 && ta < t_bound {
            let tb = (ta + spacing).min(t_bound);
            let gb = g(tb);
            self.done.rhs_evals += 1;
            if gb > 0.0 {
                unstick = Some(refine_root(g, ta, ga, tb, gb));
            }
            (ta, ga) = (tb, gb);
        }
        let t1 = unstick.unwrap_or(t_bound);
        self.done.steps += 1;
        self.dense = SwitchingDense::Stuck { t0: self.t, t1, x };
        self.last = None;
        match unstick {
            Some(t) => self.switch(t, x, Mode::slipping(p.applied(t, x))),
            None => {
                self.t = t_bound;
                Ok(())
            }
        }
    }
}

impl Stepper<2> for Switching<'_> {
    type Dense = SwitchingDense;
    fn t(&self) -> f64 {
        self.t
    }
    fn y(&self) -> &[f64; 2] {
        &self.y
    }
    fn step(&mut self, t_bound: f64) -> Result<()> {
        let steps = self.stats().steps;
        if steps >= self.opts.max_steps {
            return Err(SolverError::TooManySteps {
                t: self.t,
                max_steps: self.opts.max_steps,
            }
            .into());
        }
        let side = self.mode.side();
        let Some(inner) = self.inner.as_mut() else {
            return self.hold(t_bound);
        };
        inner.step(t_bound)?;
        let d = inner.dense();
        // s·x' > 0 across the whole step: no switch in it
        let cut = if d.abs_floor(1).is_some_and(|f| f > 0.0) {
            None
        } else {
            let mut falls = Detector::new(|_, y: &[f64; 2]| side * y[1], Direction::Falling);
            falls.subdivisions = SUBDIVISIONS;
            let mut first = None;
            falls.scan(&d, |c| {
                first.get_or_insert(c);
            });
            first
        };
        match cut {
            None => {
                (self.t, self.y) = (inner.t(), *inner.y());
                self.dense = SwitchingDense::Slip {
                    inner: d,
                    t_end: self.t,
                    y_end: self.y,
                };
                self.last = None;
                Ok(())
            }
            Some(c) => {
                let (t, x) = (c.t, c.y[0]);
                self.dense = SwitchingDense::Slip {
                    inner: d,
                    t_end: t,
                    y_end: [x, 0.0],
                };
                let to = self.pieces.mode_at_rest(t, x);
                self.switch(t, x, to)
            }
        }
    }
    fn dense(&mut self) -> SwitchingDense {
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
