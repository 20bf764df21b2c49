//! The flow of a model whose friction sticks, with its monodromy: the motion integrated switch by
//! switch ([`crate::model::switching`]), Φ and w carried across each switch by its saltation
//! matrix (Aizerman & Gantmacher 1958; Leine & Nijmeijer 2004, ch. 3 and 7).
//!
//! **Why.** A sticking Coulomb law switches the vector field where x' = 0, so the flow is not
//! differentiable through a switch, and the variational equations of either side alone give the
//! wrong monodromy. Between switches the motion is smooth: a slipping piece is the model with
//! sgn x' fixed ([`Model::directed`]), whose Φ and w come from the smooth machinery
//! ([`super::floquet::smooth_flow`]); at rest f = 0 and Φ = I. At a switch where h(s, y) = 0,
//! from the field f⁻ to f⁺ (both in phase time), a perturbation δy before maps to S·δy after,
//!
//!   S = I + (f⁺ − f⁻)·∇hᵀ / (∇h·f⁻ + ∂h/∂s),
//!
//! and the parameter sensitivity jumps as w⁺ = S·w⁻ + (f⁺ − f⁻)·(∂h/∂λ) / (∇h·f⁻ + ∂h/∂s). With
//! A(s, x) = x'' at x' = 0 without the sticking terms' sign part and b the static band:
//! - **slip to slip** (reversal, |A| > b): h = x', S = diag(1, a⁺/a⁻), a± = x'' of each piece
//!   at the reversal;
//! - **slip to stick**: h = x', f⁺ = 0, S = diag(1, 0): a rest forgets the speed, so an orbit
//!   that sticks has a multiplier of exactly 0 (ln |m| = −∞);
//! - **stick to slip** (breakaway in the direction σ): h = σA − b, f⁻ = 0, f⁺ = (0, a⁺/ω),
//!   S₂₁ = a⁺·A_x/(ω·A_s), w₂ jumps by a⁺·(σA_λ − b_λ)/(ω·σA_s). For the Coulomb–Stribeck law
//!   a⁺ = A − σf_s = 0 at the breakaway, so S = I there.
//!
//! The switches are the integration's own, located to 1e-13 ([`crate::model::switching`]); a
//! grazing rest (x' touching 0 without crossing) is a point where the flow is not differentiable
//! and shows as a multiplier that jumps along a continuation.

use super::*;
use crate::integrate::{DenseOutput, Stepper};
use crate::model::ModelParam;
use crate::model::switching::{Pieces, Switch, Switching, SwitchingMode};

/// The flow of the switching model `pieces` are of from phase `s0` and `y0` over `span`:
/// [`super::floquet::flow`] with the saltation matrices (module docs).
pub(crate) fn flow(
    pieces: &Pieces,
    param: Option<ModelParam>,
    s0: f64,
    y0: [f64; 2],
    span: f64,
    tol: Options,
) -> Result<Flow> {
    let omega = pieces.model().forcing()[2];
    let (t0, t1) = (s0 / omega, (s0 + span) / omega);
    let mut run = Switching::<2>::new(pieces, t0, y0, tol)?;
    let mut out = Flow::start(y0);
    if run.mode() == SwitchingMode::Stuck {
        // the run starts at rest: a speed given there dies before it moves x (S of a stick)
        out.then(&stop(y0));
    }
    let mut from = (t0, *run.y(), run.mode());
    while run.t() < t1 {
        run.step(t1)?;
        if let Some(switch) = run.last_switch() {
            segment(pieces, param, from, switch.t, &mut out, tol)?;
            out.then(&saltation(pieces, param, &switch));
            from = (switch.t, *run.y(), switch.to);
        }
    }
    segment(pieces, param, from, t1, &mut out, tol)?;
    out.y = *run.y();
    Ok(out)
}

/// Carries `out` over [t_a, t_b] in one mode from the state `y_a`: at rest Φ = I and w stays; a
/// slipping piece by its smooth variational equations.
fn segment(
    pieces: &Pieces,
    param: Option<ModelParam>,
    (ta, ya, mode): (f64, [f64; 2], SwitchingMode),
    tb: f64,
    out: &mut Flow,
    tol: Options,
) -> Result<()> {
    if mode == SwitchingMode::Stuck || tb <= ta {
        out.y = ya;
        return Ok(());
    }
    let piece = pieces.piece(mode, 0);
    let omega = piece.forcing()[2];
    let f = smooth_flow(piece, param, ya, (omega * ta, omega * (tb - ta)), tol)?;
    out.then(&f);
    Ok(())
}

/// The saltation matrix of `switch` and the jump of w there, as a linear piece (module docs).
fn saltation(pieces: &Pieces, param: Option<ModelParam>, switch: &Switch) -> Flow {
    let m = pieces.model();
    let omega = m.forcing()[2];
    let phase = omega * switch.t;
    let y = [switch.x, 0.0];
    // x'' of a slipping piece at the switch (no internal state: its signs are bits 0)
    let slope = |mode: SwitchingMode| pieces.piece(mode, 0).accel(phase, switch.x, 0.0);
    match (switch.from, switch.to) {
        (SwitchingMode::Stuck, to) => {
            let sigma = to.side();
            let a_plus = slope(to);
            let a_x = m.accel_gradient(switch.x, 0.0)[0];
            // A_s: only the load μ + δ sin s depends on the phase (a model that switches has
            // no internal state, so no other load)
            let a_s = m.forcing()[1] * libm::cos(phase);
            let den = omega * sigma * a_s;
            let h_lambda = param.map_or(0.0, |q| {
                sigma * m.accel_derivative(q, phase, switch.x, 0.0) - band_derivative(m, q)
            });
            Flow::linear(
                [[1.0, 0.0], [a_plus * a_x / (omega * a_s), 1.0]],
                [0.0, a_plus * h_lambda / den],
                y,
            )
        }
        (_, SwitchingMode::Stuck) => stop(y),
        (from, to) => Flow::linear([[1.0, 0.0], [0.0, slope(to) / slope(from)]], [0.0; 2], y),
    }
}

/// The saltation matrix of a stop at `y`, diag(1, 0): a rest forgets the speed.
fn stop(y: [f64; 2]) -> Flow {
    Flow::linear([[1.0, 0.0], [0.0, 0.0]], [0.0; 2], y)
}

/// ∂b/∂λ of the static band b = Σ f_s: the band is the sum of the sticking terms' breakaway
/// torques, each one of its term's parameters, so it is affine in every parameter and a
/// difference quotient is exact to rounding (taken on the side the parameter's domain allows).
fn band_derivative(m: &crate::model::Model, q: ModelParam) -> f64 {
    let v = m.get(q);
    let h = 1e-6 * v.abs().max(1.0);
    let band = |v: f64| m.with(q, v).ok().map(|m| m.breakaway().unwrap_or(0.0));
    let b0 = m.breakaway().unwrap_or(0.0);
    match (band(v + h), band(v - h)) {
        (Some(b), _) => (b - b0) / h,
        (None, Some(b)) => (b0 - b) / h,
        (None, None) => 0.0,
    }
}

/// Runs the switching motion of `pieces` from phase 0 and `y0` over `span` (phase), showing
/// `each` every step's dense output (in τ); returns the end state.
pub(crate) fn motion(
    pieces: &Pieces,
    y0: [f64; 2],
    span: f64,
    tol: Options,
    mut each: impl FnMut(&crate::model::switching::SwitchingDense<2>),
) -> Result<[f64; 2]> {
    let t1 = span / pieces.model().forcing()[2];
    let mut run = Switching::<2>::new(pieces, 0.0, y0, tol)?;
    while run.t() < t1 {
        run.step(t1)?;
        let d = run.dense();
        if d.t_end() > d.t_start() {
            each(&d);
        }
    }
    Ok(*run.y())
}
