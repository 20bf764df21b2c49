//! The catalogue's stiffness law as a term: piecewise linear in the twist, with its kinks located
//! as events by the Taylor steps ([`Piecewise`]).
//!
//! A harmonic drive's catalogue gives its torque–twist curve as three straight segments, K₁ up to
//! T₁, K₂ up to T₂ and K₃ beyond. Such a law is not analytic at a kink: its slope jumps, and no
//! Taylor series (nor a Runge–Kutta step's error estimate) straddles one. On a segment it is
//! linear, so a Taylor step computes its rows with the segment the step starts on and ends where
//! the twist leaves that segment, located on the step's own polynomial
//! ([`Term::step_limit`]); the next step starts on the kink and takes the segment the motion
//! enters. DOP853 steps are not cut: its error control shortens the steps about a kink instead
//! (the tests compare the two).
//!
//! A measured curve has no corners: its knees turn over some twist. With a rounding x_r > 0 the
//! law is P_r(u) = k₃u + ½(k₂ − k₁)(q(u − x₁) − q(u + x₁)) + ½(k₃ − k₂)(q(u − x₂) − q(u + x₂)),
//! q(y) = √(y² + x_r²), x₂ = x₁ + w₂: each kink |y| replaced by a hyperbola, so the law is
//! analytic, within (|k₂ − k₁| + |k₃ − k₂|)·x_r of the sharp one everywhere, and the sharp one
//! itself at x_r = 0 (q(y) = |y|: P on each segment). Its Taylor rows follow from √'s
//! recurrence ([`crate::model::jet::sqrt_coefficient`]) and need no events.
//!
//! ```
//! use hdgear::model::{Model, terms::AnyTerm};
//! use hdgear::simulate::{SimOptions, Start, simulate_model};
//! // a slow load swept across both kinks of a three-segment law (kinks at |x| = 0.5 and 1.5)
//! let law = AnyTerm::new("piecewise", &[1.0, 2.0, 4.0, 0.5, 1.0, 0.0, 0.0]).unwrap();
//! let m = Model::damped(3.0, 2.0, 0.05).with_term(law).unwrap();
//! let opts = SimOptions { t_end: 60.0, dt: 1.0, start: Start::Rest, ..SimOptions::default() };
//! let mut top = 0.0_f64;
//! simulate_model(&m, &opts, |_, y| top = top.max(y[0])).unwrap();
//! // quasi-static at the load's peak 5: P(x) = 0.5 + 2 + 4(x − 1.5) = 5 at x = 2.125
//! assert!(top > 1.5 && top < 2.2);
//! //! ```

use super::term::{Domain, ParamInfo, Scratch, Term};
use serde::Serialize;

/// How near an edge `e` a twist counts as on it (a few rounding errors of e): there the
/// segment is chosen by the direction of motion, and a step that starts that near an edge of its
/// segment, on either side, starts on the segment.
pub(super) fn on_kink(e: f64) -> f64 {
    8.0 * f64::EPSILON * e.abs().max(1.0)
}

/// Piecewise-linear stiffness T(x) = P(x − x₀), P odd, with slope k₁ for |u| ≤ x₁, k₂ for
/// x₁ < |u| ≤ x₁ + w₂ and k₃ beyond (u = x − x₀): the catalogue's three-segment torque–twist
/// curve, continuous, its slope jumping at the kinks |u| = x₁ and |u| = x₁ + w₂; with a knee
/// rounding x_r > 0 the rounded law P_r of the module's text. Its values are
/// [k₁, k₂, k₃, x₁, w₂, x₀, x_r].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Piecewise(pub [f64; 7]);

/// One segment of the law: where it lies and the line on it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Segment {
    /// Its twist interval [lo, hi] in u (±∞ at the ends).
    lo: f64,
    hi: f64,
    /// The slope on it.
    slope: f64,
}

/// q(y) = √(y² + r²): |y| with its corner rounded over r.
fn hyperbola(y: f64, r: f64) -> f64 {
    (y * y + r * r).sqrt()
}

impl Piecewise {
    /// The knee rounding x_r when the knees are rounded.
    fn rounding(&self) -> Option<f64> {
        (self.0[6] > 0.0).then_some(self.0[6])
    }

    /// The rounded law's two knees: each kink c ∈ {x₁, x₂} with its weight ½Δk, the slope
    /// change there halved.
    fn knee_weights(&self) -> [(f64, f64); 2] {
        let [k1, k2, k3, ..] = self.0;
        let [a, b] = self.kinks();
        [(a, 0.5 * (k2 - k1)), (b, 0.5 * (k3 - k2))]
    }

    /// The rounded law's four hyperbolas, each (c, w) standing for w·q(u − c): q(u − x₁) and
    /// q(u + x₁) with weights ±½(k₂ − k₁), then the same at x₂ with ±½(k₃ − k₂), in the order
    /// of the scratch's rows 1 to 4.
    fn hyperbolas(&self) -> [(f64, f64); 4] {
        let [(a, wa), (b, wb)] = self.knee_weights();
        [(a, wa), (-a, -wa), (b, wb), (-b, -wb)]
    }

    /// [`Piecewise::knee_weights`] with (q(u − c), q(u + c)) at u.
    fn knees(&self, u: f64, r: f64) -> [(f64, f64, f64, f64); 2] {
        self.knee_weights()
            .map(|(c, w)| (c, w, hyperbola(u - c, r), hyperbola(u + c, r)))
    }

    /// P_r(u) and its slope.
    fn rounded(&self, u: f64, r: f64) -> (f64, f64) {
        let k3 = self.0[2];
        self.knees(u, r)
            .iter()
            .fold((k3 * u, k3), |(value, slope), &(c, w, minus, plus)| {
                (
                    value + w * (minus - plus),
                    slope + w * ((u - c) / minus - (u + c) / plus),
                )
            })
    }

    /// ∂P_r/∂(x₁, w₂, x_r): a kink's place moves q(u − c) − q(u + c) by
    /// −(u − c)/q(u − c) − (u + c)/q(u + c) per unit of c, and the rounding by r/q each.
    fn rounded_shape_derivatives(&self, u: f64, r: f64) -> [f64; 3] {
        let [(a, wa, ma, pa), (b, wb, mb, pb)] = self.knees(u, r);
        let along = |m: f64, p: f64, c: f64| -(u - c) / m - (u + c) / p;
        let (da, db) = (wa * along(ma, pa, a), wb * along(mb, pb, b));
        [da + db, db, wa * (r / ma - r / pa) + wb * (r / mb - r / pb)]
    }

    /// The kinks in u ≥ 0: x₁ and x₁ + w₂.
    fn kinks(&self) -> [f64; 2] {
        let [_, _, _, x1, w2, ..] = self.0;
        [x1, x1 + w2]
    }

    /// The twist w ≥ 0 spends on each segment: P(w) = k₁·s₁ + k₂·s₂ + k₃·s₃ with [s₁, s₂, s₃]
    /// these, so they are also ∂P/∂k_i.
    fn spans(&self, w: f64) -> [f64; 3] {
        let [a, b] = self.kinks();
        [w.min(a), (w - a).clamp(0.0, b - a), (w - b).max(0.0)]
    }

    /// The segment holding u; on a kink (to a few rounding errors) the one `direction` points
    /// into (its sign; 0 takes the segment below).
    fn segment(&self, u: f64, direction: f64) -> Segment {
        let [k1, k2, k3, ..] = self.0;
        let [a, b] = self.kinks();
        let edges = [-b, -a, a, b];
        let slopes = [k3, k2, k1, k2, k3];
        let on = |e: f64| (u - e).abs() <= on_kink(e);
        // the number of edges below u, an edge u sits on counting as below when moving up
        let i = edges
            .iter()
            .filter(|&&e| if on(e) { direction > 0.0 } else { e < u })
            .count();
        let lo = if i == 0 {
            f64::NEG_INFINITY
        } else {
            edges[i - 1]
        };
        let hi = if i == 4 { f64::INFINITY } else { edges[i] };
        Segment {
            lo,
            hi,
            slope: slopes[i],
        }
    }
}

impl Term for Piecewise {
    const KIND: &'static str = "piecewise";
    const ABOUT: &'static str = "piecewise-linear stiffness of the catalogue: slopes k₁, k₂, k₃ \
         with kinks at |x − x₀| = x₁ and x₁ + w₂, located as events, or rounded over x_r";
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "k1",
            symbol: "k₁",
            latex: "k_1",
            meaning: "stiffness of the first segment (|x − x₀| ≤ x₁)",
            domain: Domain::Positive,
            default: 1.0,
            si: "K₁·J_eq/C² (a stiffness on γ's scale)",
        },
        ParamInfo {
            name: "k2",
            symbol: "k₂",
            latex: "k_2",
            meaning: "stiffness of the second segment",
            domain: Domain::Positive,
            default: 1.5,
            si: "K₂·J_eq/C²",
        },
        ParamInfo {
            name: "k3",
            symbol: "k₃",
            latex: "k_3",
            meaning: "stiffness beyond the second kink",
            domain: Domain::Positive,
            default: 2.0,
            si: "K₃·J_eq/C²",
        },
        ParamInfo {
            name: "x1",
            symbol: "x₁",
            latex: "x_1",
            meaning: "twist at the first kink (T₁/K₁ on x's scale)",
            domain: Domain::Positive,
            default: 0.5,
            si: "θ₁/L (L = C²/(J_eq·k2·φ), x's length scale)",
        },
        ParamInfo {
            name: "w2",
            symbol: "w₂",
            latex: "w_2",
            meaning: "twist width of the second segment ((T₂ − T₁)/K₂ on x's scale)",
            domain: Domain::Positive,
            default: 1.0,
            si: "(θ₂ − θ₁)/L",
        },
        ParamInfo {
            name: "x0",
            symbol: "x₀",
            latex: "x_0",
            meaning: "twist at zero torque (an offset such as the study's backlash ε)",
            domain: Domain::Any,
            default: 0.0,
            si: "θ₀/L",
        },
        ParamInfo {
            name: "xr",
            symbol: "x_r",
            latex: "x_r",
            meaning: "knee rounding: the twist over which each kink turns (0: sharp kinks, \
                      located as events)",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "θ_r/L",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Piecewise([v[0], v[1], v[2], v[3], v[4], v[5], v[6]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, _z: f64) -> f64 {
        let u = x - self.0[5];
        if let Some(r) = self.rounding() {
            return self.rounded(u, r).0;
        }
        let [k1, k2, k3, ..] = self.0;
        let [s1, s2, s3] = self.spans(u.abs());
        u.signum() * (k1 * s1 + k2 * s2 + k3 * s3)
    }
    /// The slope of the segment holding x (at a kink, the one below in |x − x₀|); the rounded
    /// law's slope with rounded knees.
    fn gradient(&self, x: f64, _v: f64, _z: f64) -> [f64; 3] {
        let u = x - self.0[5];
        let slope = match self.rounding() {
            Some(r) => self.rounded(u, r).1,
            None => self.segment(u, -u.signum()).slope,
        };
        [slope, 0.0, 0.0]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, _z: f64) -> f64 {
        let [k1, k2, k3, ..] = self.0;
        let u = x - self.0[5];
        if let Some(r) = self.rounding() {
            let [(_, _, ma, pa), (_, _, mb, pb)] = self.knees(u, r);
            let (da, db) = (ma - pa, mb - pb);
            return match i {
                0 => -0.5 * da,
                1 => 0.5 * (da - db),
                2 => u + 0.5 * db,
                3..=4 => self.rounded_shape_derivatives(u, r)[i - 3],
                5 => -self.rounded(u, r).1,
                _ => self.rounded_shape_derivatives(u, r)[2],
            };
        }
        if i == 6 {
            // |y| + r²/(2|y|) off the kinks: flat in r at r = 0
            return 0.0;
        }
        let (sign, w) = (u.signum(), u.abs());
        let spans = self.spans(w);
        let [a, b] = self.kinks();
        // moving a kink out moves the twist beyond it from the outer slope to the inner one
        let (beyond_a, beyond_b) = (f64::from(u8::from(w > a)), f64::from(u8::from(w > b)));
        match i {
            0..=2 => sign * spans[i],
            // x₁ moves both kinks, w₂ the second
            3 => sign * ((k1 - k2) * beyond_a + (k2 - k3) * beyond_b),
            4 => sign * (k2 - k3) * beyond_b,
            // ∂/∂x₀ = −P'(u)
            _ => -self.gradient(x, 0.0, 0.0)[0],
        }
    }
    /// Row 0 is P at the step's start; rows k ≥ 1 are the slope of the segment the motion is on
    /// times x's rows (chosen at row 1, on a kink by x' or, at rest, by x''). Keeps x's rows and
    /// the segment for [`Term::step_limit`]. With rounded knees: x's rows (row 0 of the scratch,
    /// for [`Term::step_limit`]) and the rows of the four square roots
    /// (rows 1 to 4: q(u ∓ x₁), then q(u ∓ x₂)), each (u ∓ c)² + x_r² formed row by row from
    /// y = u ∓ c itself: y₀² + x_r² at row 0 and 2y₀·x_k + Σ_{0<i<k} x_i·x_{k−i} beyond (not
    /// as x² + 2d·x + d², whose rounding errors of order ε·x² swamp an x_r² far below them).
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], v: &[f64], _z: &[f64], rows: &mut Scratch) -> f64 {
        if let Some(r) = self.rounding() {
            let [xs, roots @ ..] = &mut rows.0;
            xs[k] = x[k];
            let [_, _, k3, _, _, x0, _] = self.0;
            let u = x[0] - x0;
            let mut t = if k == 0 { k3 * u } else { k3 * x[k] };
            // the part of y²'s row k that does not hold y₀: the same for every knee
            let inner = if k >= 2 {
                super::jet::square_coefficient(&x[1..], k - 2)
            } else {
                0.0
            };
            for (root, (c, weight)) in roots.iter_mut().zip(self.hyperbolas()) {
                let y0 = u - c;
                let w = if k == 0 {
                    y0 * y0 + r * r
                } else {
                    2.0 * y0 * x[k] + inner
                };
                root[k] = super::jet::sqrt_coefficient(w, root, k);
                t += weight * root[k];
            }
            return t;
        }
        let [xs, seg, ..] = &mut rows.0;
        xs[k] = x[k];
        match k {
            0 => self.torque(x[0], 0.0, 0.0),
            _ => {
                if k == 1 {
                    let direction = if x[1] != 0.0 { x[1] } else { v[1] };
                    let s = self.segment(x[0] - self.0[5], direction);
                    seg[..3].copy_from_slice(&[s.lo, s.hi, s.slope]);
                }
                seg[2] * x[k]
            }
        }
    }
    const LIMITS_STEPS: bool = true;
    /// The step ends where the twist leaves the segment it started on, located on x's polynomial
    /// ([`super::jet::exit_from`]): the next step starts on the kink or just past it, and its
    /// segment follows from where x is.
    /// With rounded knees the step stays within each hyperbola's radius of convergence
    /// ([`super::jet::hyperbola_step_limit`]).
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        let [xs, seg, ..] = &rows.0;
        if order == 0 {
            return h;
        }
        if let Some(r) = self.rounding() {
            let u = xs[0] - self.0[5];
            return self.hyperbolas().into_iter().fold(h, |h, (c, w)| {
                super::jet::hyperbola_step_limit(u - c, xs, r, order, h, w.abs(), negligible)
            });
        }
        // widened as `segment` reads an edge: a start a rounding error past one is on it
        let (lo, hi) = (
            seg[0] - on_kink(seg[0]) + self.0[5],
            seg[1] + on_kink(seg[1]) + self.0[5],
        );
        super::jet::exit_from(xs, order, h, (lo, hi))
    }
    fn text(&self) -> String {
        " + P(x − x₀)".into()
    }
    fn latex(&self) -> String {
        r" + P(x - x_0)".into()
    }
}
