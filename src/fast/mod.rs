//! The fast subsystem x'' + x' + g(x) = μ + δ a with the slow variable a = sin(ω τ) frozen.
//!
//! Exact facts used throughout (SPEC §3): the Jacobian at an equilibrium is
//! [[0, 1], [−g'(x), −1]], so the trace is −1 for every parameter and every equilibrium: the fast
//! subsystem can never undergo a Hopf bifurcation. Equilibria are stable iff g'(x) > 0; the only
//! bifurcations are folds where g'(x) = 0, which exist iff γ < 1/(3α).

mod equilibria;

pub use equilibria::{
    EqType, Equilibria, Equilibrium, eigenvalues, equilibria, fold_abscissae, stable_equilibrium,
};
