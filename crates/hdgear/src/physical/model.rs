//! The two-inertia drive as a [`System`].

use crate::integrate::System;

/// The physical two-inertia drive (guide: the model and its parameters), integrated in well-conditioned coordinates.
///
/// Internal state z = [θ, T_c·θ', θo, T_c·θo'] with physical time t \[s\], where θ = θo − θi/N is
/// the relative torsion and T_c = J_eq/C. Integrating θ rather than θi avoids computing the small
/// torsion as the difference of two large rotations (the rigid-body swing under a slow
/// disturbance can exceed the torsion by many orders of magnitude), and scaling the rates by T_c
/// gives every component the unit of an angle, so one absolute tolerance fits all. The
/// accelerations are the two-inertia equations themselves:
///
/// θo'' = (T_m + T_am sin Ωt − C θ' − K(θ)(θ − φ)) / J_o,
/// θi'' = (−T_m/N + C θ'/N + K(θ)(θ − φ)/N) / J_i,  θ'' = θo'' − θi''/N.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Physical {
    /// The drive.
    pub d: super::PhysicalParams,
    /// T_c = J_eq/C \[s\].
    pub t_c: f64,
}

impl Physical {
    /// Wraps a (validated) drive.
    pub fn new(d: super::PhysicalParams) -> Self {
        Physical {
            t_c: d.j_eq() / d.c_eq,
            d,
        }
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
        let th = z[0];
        let thd = z[1] / self.t_c;
        let spring = d.spring(th);
        let damper = d.c_eq * thd;
        let acc_out = (d.t_m + d.t_am * libm::sin(d.omega * t) - damper - spring) / d.j_out;
        let acc_in = (-d.t_m + damper + spring) / (d.ratio * d.j_in);
        let acc_rel = acc_out - acc_in / d.ratio;
        [
            z[1] / self.t_c,
            self.t_c * acc_rel,
            z[3] / self.t_c,
            self.t_c * acc_out,
        ]
    }

    /// The same equations order by order: the spring's rows ([`super::PhysicalParams::spring_row`]),
    /// the disturbance from the coefficients of sin Ωt.
    fn taylor(&self, t: f64, z: &[f64; 4], order: usize, c: &mut [[f64; 4]]) -> bool {
        use crate::integrate::taylor::{INV, MAX_ORDER, sine_coefficients, square_coefficient};
        let d = &self.d;
        let n = order.min(MAX_ORDER).min(c.len() - 1);
        let (mut th, mut th2, mut s) = (
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
        );
        sine_coefficients(d.omega, t, n, &mut s);
        c[0] = *z;
        th[0] = z[0];
        for k in 0..n {
            th2[k] = square_coefficient(&th, k);
            let first = if k == 0 { 1.0 } else { 0.0 };
            let spring = d.spring_row(&th, &th2, k);
            let damper = d.c_eq * c[k][1] / self.t_c;
            let acc_out = (first * d.t_m + d.t_am * s[k] - damper - spring) / d.j_out;
            let acc_in = (-first * d.t_m + damper + spring) / (d.ratio * d.j_in);
            let acc_rel = acc_out - acc_in / d.ratio;
            c[k + 1] = [
                c[k][1] / self.t_c * INV[k],
                self.t_c * acc_rel * INV[k],
                c[k][3] / self.t_c * INV[k],
                self.t_c * acc_out * INV[k],
            ];
            th[k + 1] = c[k + 1][0];
        }
        true
    }
}
