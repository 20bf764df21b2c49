//! # hdgear — fast-slow dynamics of harmonic drive gears
//!
//! hdgear simulates and analyses the harmonic drive model with nonlinear torsional stiffness of
//! Han, Huang, Ding & Bi (2022), in its dimensionless form
//!
//! ```text
//! x'' + x' + α x³ − x² + γ (x − ε) = μ + δ sin(ω τ)
//! ```
//!
//! and its two-inertia physical form ([`physical`]). The slow variable
//! a = sin(ω τ) (ω ≪ 1) sweeps the fast subsystem x'' + x' + g(x) = μ + δ a, g(x) = αx³ − x² + γ(x − ε),
//! through its equilibrium curve; where that curve is steep the state cannot follow and bursts.
//!
//! Principal types:
//! * [`Params`]: the dimensionless parameters, presets and validation ([`params`]).
//! * [`model::Dimensionless`]: the right-hand side and its Taylor coefficients.
//! * [`integrate::Taylor`] (the default) and [`integrate::Dop853`] behind the
//!   [`integrate::Stepper`] seam, with dense output and events; [`batch`] runs 16
//!   parameter sets in SIMD lock-step.
//! * [`simulate::simulate`]: a sampled trajectory with a summary; [`simulate::summarize`], the
//!   summary alone.
//! * [`fast`]: equilibria and stability of the fast subsystem, and [`fast::predict`], bursting
//!   predicted from the equilibrium curve alone.
//! * [`burst::response`] and [`burst::classify`]: bursts judged by their signatures (jump,
//!   overshoot, ringing), modes and mechanisms; [`burst::response_model`] for a model assembled
//!   from terms.
//! * [`control`]: feedback laws as terms, each measured against the open loop and tuned to the
//!   least gain that removes the bursts.
//! * [`physical`]: the drive in SI units, its reduction, simulation and design check.
//! * [`robust`]: the design check under manufacturing spread (P(burst), worst case and margin,
//!   Sobol indices), on the [`distribution`]s of the parameters.
//! * [`study::Study`] and [`report::Report`]: computations done once, then rendered.
//! * [`prelude`]: the names most programs start from, in one `use hdgear::prelude::*`.
//!
//! ```
//! use hdgear::{Params, simulate::{simulate, SimOptions}};
//! let p = Params { gamma: 30.0, ..Params::default() };
//! let opts = SimOptions { t_end: 50.0, ..SimOptions::default() };
//! let run = simulate(&p, &opts, |_t, _y| {}).unwrap();
//! assert!(run.max_abs_xdot < 1.0);
//! ```
#![warn(missing_docs)]

// `#[derive(Record)]` names the crate `::hdgear`, inside it as outside
extern crate self as hdgear;

pub mod batch;
pub mod burst;
pub mod control;
pub mod distribution;
pub mod error;
pub mod explore;
pub mod fast;
pub mod figures;
pub mod fit;
pub mod integrate;
pub mod model;
pub mod output;
pub mod params;
pub mod periodic;
pub mod physical;
pub mod prelude;
pub mod refine;
pub mod report;
pub mod robust;
pub mod roots;
pub mod scenario;
pub mod simd;
pub mod simulate;
pub mod study;
pub mod sweep;
pub mod table;

pub use error::{Error, Result};

/// The user guide's library page (`docs/src/library.md`), compiled and run as doc-tests so its
/// examples cannot drift from the API.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/src/library.md")]
pub struct GuideLibraryPage;

/// The guide's architecture page (`docs/src/architecture.md`): its worked examples compiled and
/// run as doc-tests.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/src/architecture.md")]
pub struct GuideArchitecturePage;
pub use params::Params;
