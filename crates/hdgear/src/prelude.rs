//! The names most programs start from, in one `use`: the study's parameters and an assembled
//! model, the integrator's options, a trajectory, a response and its verdict, a periodic orbit,
//! the drive in SI units, a table writer, and the library's error.
//!
//! ```
//! use hdgear::prelude::*;
//!
//! // the study's set with γ = 30, and the same set with friction in its twist
//! let p = Params { gamma: 30.0, ..Params::default() };
//! let m = Model::study(&p).with_term(AnyTerm::new("friction", &[0.05, 0.05])?)?;
//! let opts = BurstOptions::default();
//! let verdict = classify(&p, &response(&p, &opts)?).verdict;
//! assert_eq!(verdict, Verdict::NoBursts);
//! let run = simulate_model(&m, &SimOptions { t_end: 20.0, ..SimOptions::default() }, |_, _| {})?;
//! assert!(run.max_abs_xdot.is_finite());
//! # Ok::<(), hdgear::Error>(())
//! ```

pub use crate::burst::{BurstOptions, Mode, Verdict, classify, response, response_model};
pub use crate::error::{Error, Result};
pub use crate::integrate::Options;
pub use crate::model::{Model, Subject, terms::AnyTerm};
pub use crate::output::{Format, Record, RecordWriter};
pub use crate::params::{Param, Params};
pub use crate::periodic::{ContinuationOptions, PeriodicOptions, continue_orbit, shoot};
pub use crate::physical::PhysicalParams;
pub use crate::simulate::{SimOptions, simulate, simulate_model};
pub use crate::sweep::Axis;
