//! The two-inertia drive as a [`System`], with friction at its bearings ([`Bearings`]).

use crate::error::{Error, Result};
use crate::integrate::System;
use crate::integrate::taylor::{MAX_ORDER, Workspace};
use crate::model::terms::{AnyTerm, Friction, Stribeck, Term};
use serde::Serialize;

/// Friction where the reduction to one equation does not hold: at the output bearing, on the
/// output rate θo', and at the wave generator, on the input rate θi' (torques in N m, rates in
/// rad/s). Such friction acts on one inertia alone, so it moves the rigid-body mode and the twist
/// together: only the two-inertia model ([`Physical`]) carries it. Friction across the
/// compliance, on the twist rate θ', is the reduced model's ([`super::friction`]).
///
/// Each is a term of velocity alone, analytic on the step ([`BEARING_KINDS`]: the smooth
/// Coulomb and the regularised Stribeck laws), with its parameters in SI units.
///
/// ```
/// use hdgear::model::terms::AnyTerm;
/// use hdgear::physical::model::Bearings;
/// // 0.8 N m of Coulomb, 1.2 N m of breakaway friction at the output bearing
/// let output = AnyTerm::new("stribeck", &[0.8, 1.2, 0.05, 0.01, 1e-3]).unwrap();
/// let b = Bearings::new(Some(output), None).unwrap();
/// assert_eq!(b.torques(0.0, 0.0), [0.0, 0.0]);
/// assert!(Bearings::new(None, Some(AnyTerm::new("coulomb", &[0.8, 1.2, 0.05, 0.0]).unwrap())).is_err());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Bearings {
    /// Friction torque on θo', opposing the output's rotation.
    pub output: Option<AnyTerm>,
    /// Friction torque on θi', opposing the input's (the wave generator's) rotation.
    pub input: Option<AnyTerm>,
}

/// The kinds of term a bearing takes: friction laws of the velocity alone, analytic along a
/// step (a switched law's sign would need the piecewise integration of the reduced model).
pub const BEARING_KINDS: [&str; 2] = [Friction::KIND, Stribeck::KIND];

impl Bearings {
    /// Checks that each term is one of [`BEARING_KINDS`].
    pub fn new(output: Option<AnyTerm>, input: Option<AnyTerm>) -> Result<Bearings> {
        for (side, term) in [("output", output), ("input", input)] {
            if let Some(t) = term.filter(|t| !BEARING_KINDS.contains(&t.kind())) {
                return Err(Error::InvalidInput {
                    what: "bearing friction",
                    text: format!("{side}: {}", t.kind()),
                    reason: format!("a bearing takes {}", BEARING_KINDS.join(" or ")),
                });
            }
        }
        Ok(Bearings { output, input })
    }

    /// A bearing's law from its kind (one of [`BEARING_KINDS`]) and its values by name, in SI
    /// units (N m, rad/s, N m s/rad), each of the law's parameters named once: the terms'
    /// defaults are dimensionless and mean nothing here. What a scenario file's
    /// `[bearings.output.stribeck]` table and the CLI's `--output-bearing stribeck:fc=…` give.
    /// Errors name the side, the law and the key; the values' domains are the term's own
    /// ([`AnyTerm::new`]).
    ///
    /// ```
    /// use hdgear::physical::model::Bearings;
    /// let law = Bearings::law("output", "friction", [("fc", 0.8), ("vs", 1e-3)]).unwrap();
    /// assert_eq!(law.kind(), "friction");
    /// // vs missing: no default in SI units
    /// assert!(Bearings::law("output", "friction", [("fc", 0.8)]).is_err());
    /// ```
    pub fn law<'a>(
        side: &str,
        kind: &str,
        named: impl IntoIterator<Item = (&'a str, f64)>,
    ) -> Result<AnyTerm> {
        let invalid = |reason: String| Error::InvalidInput {
            what: "bearing friction",
            text: format!("{side}: {kind}"),
            reason,
        };
        if !BEARING_KINDS.contains(&kind) {
            return Err(invalid(format!(
                "a bearing takes {}",
                BEARING_KINDS.join(" or ")
            )));
        }
        let named: Vec<(&str, f64)> = named.into_iter().collect();
        let (kind, values) = crate::model::terms::term_values(kind, named.iter().copied())
            .map_err(|e| invalid(e.to_string()))?;
        let params = AnyTerm::params_of(kind).unwrap_or_default();
        for p in params {
            match named.iter().filter(|(k, _)| *k == p.name).count() {
                1 => {}
                0 => {
                    return Err(invalid(format!(
                        "{} missing (a bearing's law names all of {}, in SI units)",
                        p.name,
                        params.iter().map(|q| q.name).collect::<Vec<_>>().join(", ")
                    )));
                }
                _ => return Err(invalid(format!("{} given twice", p.name))),
            }
        }
        AnyTerm::new(kind, &values)
    }

    /// [`Bearings::law`] from the text `kind:key=value,key=value…` (the CLI's
    /// `--output-bearing` and `--input-bearing`).
    ///
    /// ```
    /// use hdgear::physical::model::Bearings;
    /// let law = Bearings::parse_law("input", "stribeck:fc=0.05,fs=0.08,vst=0.5,cv=1e-4,vr=0.01").unwrap();
    /// assert_eq!(law.values(), [0.05, 0.08, 0.5, 1e-4, 0.01]);
    /// assert!(Bearings::parse_law("input", "stribeck:fc=a").is_err());
    /// ```
    pub fn parse_law(side: &str, text: &str) -> Result<AnyTerm> {
        let invalid = |reason: &str| Error::InvalidInput {
            what: "bearing friction",
            text: format!("{side}: {text}"),
            reason: reason.into(),
        };
        let (kind, list) = text
            .split_once(':')
            .ok_or_else(|| invalid("expected LAW:KEY=VALUE,… (e.g. friction:fc=0.5,vs=1e-3)"))?;
        let mut named = Vec::new();
        for pair in list.split(',') {
            let value = pair
                .split_once('=')
                .and_then(|(k, v)| Some((k.trim(), v.trim().parse::<f64>().ok()?)))
                .ok_or_else(|| invalid("each of KEY=VALUE,… a name and a number"))?;
            named.push(value);
        }
        Bearings::law(side, kind.trim(), named)
    }

    /// The friction torques (output, input) at the rates θo', θi'.
    pub fn torques(&self, out_rate: f64, in_rate: f64) -> [f64; 2] {
        let [o, i] = self.sides();
        let at = |t: Option<AnyTerm>, v: f64| t.map_or(0.0, |t| t.torque(0.0, v, 0.0));
        [at(o, out_rate), at(i, in_rate)]
    }

    /// The two laws in the order every pair of this module follows: (output, input), as the
    /// rates (θo', θi'), the inertias (J_o, J_i) and the workspace's rows 0 and 1.
    fn sides(&self) -> [Option<AnyTerm>; 2] {
        [self.output, self.input]
    }

    /// Whether either bearing has a law.
    pub fn any(&self) -> bool {
        self.sides().iter().any(Option::is_some)
    }
}

/// The physical two-inertia drive (guide: the model and its parameters), integrated in well-conditioned coordinates.
///
/// Internal state z = [θ, T_c·θ', θo, T_c·θo'] with physical time t \[s\], where θ = θo − θi/N is
/// the relative torsion and T_c = J_eq/C. Integrating θ rather than θi avoids computing the small
/// torsion as the difference of two large rotations (the rigid-body swing under a slow
/// disturbance can exceed the torsion by many orders of magnitude), and scaling the rates by T_c
/// gives every component the unit of an angle, so one absolute tolerance fits all. The
/// accelerations are the two-inertia equations themselves:
///
/// θo'' = (T_m + T_am sin Ωt − C θ' − K(θ)(θ − φ) − F_o(θo')) / J_o,
/// θi'' = (−T_m/N + C θ'/N + K(θ)(θ − φ)/N − F_i(θi')) / J_i,  θ'' = θo'' − θi''/N,
///
/// F_o and F_i the friction at the bearings ([`Bearings`], none by default). Its fields are
/// read through methods: T_c and the reciprocals are derived from the drive when it is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Physical {
    /// The drive.
    d: super::PhysicalParams,
    /// T_c = J_eq/C \[s\].
    t_c: f64,
    /// Friction at the output bearing and the wave generator.
    bearings: Bearings,
    /// The reciprocals the equations multiply by, so that no division waits on a Taylor row.
    inv: Reciprocals,
}

/// 1/T_c, C/T_c, 1/J_o, 1/J_i, 1/(N·J_i) and 1/N of a drive.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Reciprocals {
    t_c: f64,
    damping: f64,
    j_out: f64,
    j_in: f64,
    n_j_in: f64,
    ratio: f64,
}

impl Physical {
    /// Wraps a (validated) drive.
    pub fn new(d: super::PhysicalParams) -> Self {
        let t_c = d.j_eq() / d.c_eq;
        Physical {
            t_c,
            d,
            bearings: Bearings::default(),
            inv: Reciprocals {
                t_c: 1.0 / t_c,
                damping: d.c_eq / t_c,
                j_out: 1.0 / d.j_out,
                j_in: 1.0 / d.j_in,
                n_j_in: 1.0 / (d.ratio * d.j_in),
                ratio: 1.0 / d.ratio,
            },
        }
    }

    /// The drive with friction at its bearings.
    pub fn with_bearings(d: super::PhysicalParams, bearings: Bearings) -> Self {
        Physical {
            bearings,
            ..Physical::new(d)
        }
    }

    /// The drive.
    pub fn drive(&self) -> &super::PhysicalParams {
        &self.d
    }

    /// T_c = J_eq/C \[s\], the time unit of the reduced model.
    pub fn t_c(&self) -> f64 {
        self.t_c
    }

    /// Friction at the output bearing and the wave generator.
    pub fn bearings(&self) -> Bearings {
        self.bearings
    }

    /// (θo', θi') from the internal state's scaled rates z₁ = T_c·θ', z₃ = T_c·θo' (or from
    /// their Taylor rows): θi' = N(θo' − θ').
    #[inline(always)]
    fn rates(&self, z1: f64, z3: f64) -> (f64, f64) {
        (z3 * self.inv.t_c, self.d.ratio * (z3 - z1) * self.inv.t_c)
    }

    /// The two-inertia equations, written once for the right-hand side and for the Taylor rows
    /// (row k of each torque gives row k of each acceleration): (θ'', θo'') from the mean torque
    /// `load` (on both inertias), the disturbance on the output, the torque `twist` = Cθ' +
    /// K(θ)(θ − φ) across the compliance and the bearings' friction (output, input).
    #[inline(always)]
    fn accelerations(
        &self,
        load: f64,
        disturbance: f64,
        twist: f64,
        [f_out, f_in]: [f64; 2],
    ) -> [f64; 2] {
        let inv = &self.inv;
        let acc_out = (load + disturbance - twist - f_out) * inv.j_out;
        let acc_in = (twist - load) * inv.n_j_in - f_in * inv.j_in;
        [acc_out - acc_in * inv.ratio, acc_out]
    }

    /// Internal state from (θi, θi', θo, θo').
    pub fn to_internal(
        &self,
        theta_in: f64,
        theta_in_dot: f64,
        theta_out: f64,
        theta_out_dot: f64,
    ) -> [f64; 4] {
        let n = self.d.ratio;
        [
            theta_out - theta_in / n,
            self.t_c * (theta_out_dot - theta_in_dot / n),
            theta_out,
            self.t_c * theta_out_dot,
        ]
    }

    /// (θi, θi', θo, θo', θ, θ') from the internal state.
    pub fn from_internal(&self, z: &[f64; 4]) -> [f64; 6] {
        let n = self.d.ratio;
        let (th, thd, to, tod) = (z[0], z[1] / self.t_c, z[2], z[3] / self.t_c);
        [n * (to - th), n * (tod - thd), to, tod, th, thd]
    }
}

impl System<4> for Physical {
    #[inline(always)]
    fn rhs(&self, t: f64, z: &[f64; 4]) -> [f64; 4] {
        let d = &self.d;
        let twist = self.inv.damping * z[1] + d.spring(z[0]);
        let friction = if self.bearings.any() {
            let (v_out, v_in) = self.rates(z[1], z[3]);
            self.bearings.torques(v_out, v_in)
        } else {
            [0.0; 2]
        };
        let disturbance = d.t_am * libm::sin(d.omega * t);
        let [acc_rel, acc_out] = self.accelerations(d.t_m, disturbance, twist, friction);
        [
            z[1] * self.inv.t_c,
            self.t_c * acc_rel,
            z[3] * self.inv.t_c,
            self.t_c * acc_out,
        ]
    }

    /// The same equations order by order: the spring's rows ([`super::PhysicalParams::spring_row`]),
    /// the disturbance from the coefficients of sin Ωt.
    fn taylor(&self, t: f64, z: &[f64; 4], order: usize, c: &mut [[f64; 4]]) -> bool {
        let mut work = [crate::integrate::Scratch::default(); 2];
        self.rows(t, z, order, c, &mut work);
        true
    }

    fn taylor_in(
        &self,
        t: f64,
        z: &[f64; 4],
        order: usize,
        c: &mut [[f64; 4]],
        work: &mut Workspace,
    ) -> bool {
        self.rows(t, z, order, c, work);
        true
    }

    fn taylor_limits_steps(&self) -> bool {
        self.bearings
            .sides()
            .iter()
            .flatten()
            .any(|t| t.limits_steps())
    }

    /// The rows and the step rule's step, shortened where a bearing's friction law needs it
    /// ([`AnyTerm::step_limit`]): a torque F on inertia J moves the scaled rate T_c·θ' by
    /// T_c·F/J per second, so the torque negligible over a step h is atol·J/(T_c·h) (h at least
    /// T_c, the time over which the damping forgets).
    fn taylor_step<F: FnOnce(&[[f64; 4]]) -> f64>(
        &self,
        t: f64,
        z: &[f64; 4],
        order: usize,
        c: &mut [[f64; 4]],
        atol: f64,
        work: &mut Workspace,
        step: F,
    ) -> Option<f64> {
        let n = self.rows(t, z, order, c, work);
        let mut h = step(c);
        let d = &self.d;
        let sides = self.bearings.sides();
        for ((term, rows), j) in sides.iter().zip(work.iter()).zip([d.j_out, d.j_in]) {
            if let Some(term) = term {
                let negligible = atol * j / (self.t_c * h.max(self.t_c));
                h = term.step_limit(rows, n, h, negligible);
            }
        }
        Some(h)
    }
}

impl Physical {
    /// Rows 0..=order (capped at the integrator's) of the Taylor coefficients through (t, z)
    /// into `c`, the bearings' own rows into `work[0]` (output) and `work[1]` (input); returns
    /// the order reached.
    fn rows(
        &self,
        t: f64,
        z: &[f64; 4],
        order: usize,
        c: &mut [[f64; 4]],
        work: &mut [crate::integrate::Scratch],
    ) -> usize {
        use crate::integrate::taylor::{INV, sine_coefficients, square_coefficient};
        let d = &self.d;
        let n = order.min(MAX_ORDER).min(c.len() - 1);
        let (mut th, mut th2, mut s) = (
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
        );
        // the bearings' rates θo', θi', row by row
        let bearings = self.bearings.any();
        let mut v = [[0.0; MAX_ORDER + 1]; 2];
        sine_coefficients(d.omega, t, n, &mut s);
        c[0] = *z;
        th[0] = z[0];
        for k in 0..n {
            th2[k] = square_coefficient(&th, k);
            let load = if k == 0 { d.t_m } else { 0.0 };
            let twist = self.inv.damping * c[k][1] + d.spring_row(&th, &th2, k);
            let friction = if bearings {
                self.bearing_rows(k, &c[k], &mut v, work)
            } else {
                [0.0; 2]
            };
            let [acc_rel, acc_out] = self.accelerations(load, d.t_am * s[k], twist, friction);
            c[k + 1] = [
                c[k][1] * self.inv.t_c * INV[k],
                self.t_c * acc_rel * INV[k],
                c[k][3] * self.inv.t_c * INV[k],
                self.t_c * acc_out * INV[k],
            ];
            th[k + 1] = c[k + 1][0];
        }
        if bearings {
            // the step limits read the bearings' rows at order n too
            self.bearing_rows(n, &c[n], &mut v, work);
        }
        n
    }

    /// Row k of the bearings' torques (output, input) from the state's row k, keeping the
    /// rates' rows in `v` and each law's own rows in `work[0]` and `work[1]`.
    #[inline(always)]
    fn bearing_rows(
        &self,
        k: usize,
        c_k: &[f64; 4],
        v: &mut [[f64; MAX_ORDER + 1]; 2],
        work: &mut [crate::integrate::Scratch],
    ) -> [f64; 2] {
        const NONE: [f64; MAX_ORDER + 1] = [0.0; MAX_ORDER + 1];
        (v[0][k], v[1][k]) = self.rates(c_k[1], c_k[3]);
        let mut f = [0.0; 2];
        let sides = self.bearings.sides();
        for (((term, v), rows), f) in sides.iter().zip(v.iter()).zip(work).zip(&mut f) {
            if let Some(term) = term {
                *f = term.taylor(k, &NONE, v, &NONE, rows);
            }
        }
        f
    }
}
