//! The library's error type. Every variant carries what a user needs to fix the problem: the
//! offending name and value, or the time at which an integration failed.

use std::path::PathBuf;

/// Errors of the hdgear library.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A model parameter is out of its domain.
    #[error("invalid parameter {name} = {}: {reason}", shown(*value))]
    InvalidParameter {
        /// Parameter name as the user writes it (e.g. `alpha`, `j_in`).
        name: String,
        /// The rejected value.
        value: f64,
        /// What the value must satisfy.
        reason: &'static str,
    },
    /// A term's parameter that breaks a rule relating it to another of the same term
    /// ([`crate::model::terms::Relation`]).
    #[error(
        "invalid parameter {name} = {}: {reason} (here {other} = {})",
        shown(*value),
        shown(*other_value)
    )]
    RelationBroken {
        /// The parameter the rule bounds, as the user writes it.
        name: String,
        /// Its value.
        value: f64,
        /// The parameter it is bounded by.
        other: String,
        /// That parameter's value.
        other_value: f64,
        /// The rule, and why it holds.
        reason: &'static str,
    },
    /// A numerical or run option is out of its domain.
    #[error("invalid option {name} = {}: {reason}", shown(*value))]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// What the value must satisfy.
        reason: &'static str,
    },
    /// A malformed argument that is not a single number (a range, a parameter name, ...).
    #[error("invalid {what} '{text}': {reason}")]
    InvalidInput {
        /// What was being parsed.
        what: &'static str,
        /// The offending text.
        text: String,
        /// What is expected.
        reason: String,
    },
    /// A report directory that holds files hdgear did not write, which a report would overwrite.
    #[error(
        "invalid report directory '{dir}': holds files hdgear did not write ({}{}): choose another \
         directory, or let the report overwrite them",
        files[..files.len().min(3)].join(", "),
        if files.len() > 3 { ", …" } else { "" }
    )]
    ForeignFiles {
        /// The directory.
        dir: String,
        /// The files in it hdgear did not write, relative to it.
        files: Vec<String>,
    },
    /// A control law that no gain within reach makes remove the bursts (a valid request whose
    /// answer is "none").
    #[error("no gain of {law} removes the bursts: {reason}")]
    NoGain {
        /// The law.
        law: &'static str,
        /// Why: the largest gain tried, or the delay's stability limit.
        reason: String,
    },
    /// A preset name that does not exist.
    #[error("unknown preset '{name}' (known: {known})")]
    UnknownPreset {
        /// The name asked for.
        name: String,
        /// Comma-separated list of valid names.
        known: String,
    },
    /// A drive card name that is not in the file (or among the built-in cards).
    #[error("unknown drive card '{name}' (known: {known})")]
    UnknownCard {
        /// The name asked for.
        name: String,
        /// The names, or the first of them and how to list all.
        known: String,
    },
    /// A drive card with a missing, out-of-range or inconsistent value.
    #[error("card {card}: {field} = {value}: {reason}")]
    Card {
        /// The card's name (empty for the file's own fields).
        card: String,
        /// The quantity, as `section.key`.
        field: String,
        /// The offending value as written.
        value: String,
        /// What it must satisfy.
        reason: &'static str,
    },
    /// A scenario file that cannot be read or parsed, or that has an unknown key.
    #[error("scenario file {}: {message}", path.display())]
    Config {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the key or line.
        message: String,
    },
    /// The integration failed on valid input (the exit code 1 of the command-line tool).
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// A run that would certainly exceed the step budget, refused before any work.
    #[error(
        "the run spans {span:.3e} time units: about {estimated_steps:.1e} integration steps, beyond \
         the budget of {budget:e} steps; shorten it (fewer periods, a shorter --t-end, a smaller --discard)"
    )]
    RunTooLong {
        /// Dimensionless time to integrate.
        span: f64,
        /// Steps it would take at the most optimistic step size.
        estimated_steps: f64,
        /// The budget (`Options::max_steps`).
        budget: f64,
    },
    /// A model whose fastest rate would take more steps than the budget over the run, refused
    /// before any work ([`crate::integrate::check_rate_budget`]).
    #[error(
        "the model's fastest rate, {rate:.3e} per time unit (its {term} term), needs about \
         {estimated_steps:.1e} integration steps over the run's {span:.3e} time units, beyond the \
         budget of {budget:e} steps; lower that term's gain or frequency"
    )]
    RateTooHigh {
        /// The rate: a gain, √stiffness, a state's rate or a load's angular frequency.
        rate: f64,
        /// The kind of the term it comes from.
        term: &'static str,
        /// Dimensionless time to integrate.
        span: f64,
        /// Steps it would take if each crossed a whole turn 2π/rate.
        estimated_steps: f64,
        /// The budget (`Options::max_steps`).
        budget: f64,
    },
    /// An iteration (Newton's method for a periodic orbit) did not converge on valid input.
    #[error("{what} did not converge: residual {residual:e} after {iterations} iterations")]
    NoConvergence {
        /// What was being solved.
        what: &'static str,
        /// Iterations taken.
        iterations: usize,
        /// The last residual.
        residual: f64,
    },
    /// The reduction to dimensionless form does not exist for this drive.
    #[error("no dimensionless reduction: {reason}")]
    NoReduction {
        /// Why, and what to do instead.
        reason: String,
    },
    /// A figure could not be drawn.
    #[error("cannot draw figure {figure}")]
    Plot {
        /// The figure's name.
        figure: String,
        /// The drawing library's error.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// An output file could not be written.
    #[error("cannot write {}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// Failures of an integration on valid input, with the time they happened at.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SolverError {
    /// The adaptive step size fell below the rounding level of t.
    #[error(
        "step size underflow at t = {t:?} (h = {h:e}): the solution is too stiff or singular there"
    )]
    StepSizeTooSmall {
        /// Time reached.
        t: f64,
        /// The step that was too small.
        h: f64,
    },
    /// A state component grew beyond the blow-up threshold.
    #[error("the solution blew up at t = {t:?} (a state component reached {value:e})")]
    BlowUp {
        /// Time of the step that exceeded the threshold.
        t: f64,
        /// The offending value.
        value: f64,
    },
    /// Switches of a non-smooth model accumulate: the time no longer advances between them.
    #[error(
        "{switches} switches of the friction's mode at t = {t:?} without the time advancing: the \
         motion chatters at rest (raise the static friction or regularise the term)"
    )]
    Chattering {
        /// Time reached.
        t: f64,
        /// Switches in a row at that time.
        switches: u32,
    },
    /// The step budget ran out.
    #[error("more than {max_steps} steps were needed before t = {t:?}")]
    TooManySteps {
        /// Time reached.
        t: f64,
        /// The budget.
        max_steps: u64,
    },
    /// The caller's deadline ([`crate::integrate::Options::deadline`]) passed, or its cancel
    /// flag ([`crate::integrate::Options::cancel`]) was set.
    #[error(
        "stopped at t = {t:?}: the result was no longer wanted (its deadline passed or its caller \
         cancelled it)"
    )]
    Deadline {
        /// Time reached.
        t: f64,
    },
}

/// Result alias of the library.
pub type Result<T> = std::result::Result<T, Error>;

/// An option's value as an error message echoes it: a whole number as the integer the user
/// wrote (`1000000000000`, not `1000000000000.0`) where f64 holds it exactly (below 2⁵³), every
/// other value as Rust prints it in full (`0.5`, `1e300`, `NaN`).
///
/// ```
/// assert_eq!(hdgear::error::shown(1e12), "1000000000000");
/// assert_eq!(hdgear::error::shown(-0.0), "0");
/// assert_eq!(hdgear::error::shown(0.25), "0.25");
/// assert_eq!(hdgear::error::shown(1.8446744073709552e19), "1.8446744073709552e19");
/// ```
pub fn shown(value: f64) -> String {
    const EXACT: f64 = 9_007_199_254_740_992.0; // 2⁵³
    if value.fract() == 0.0 && value.abs() < EXACT {
        format!("{}", value as i64)
    } else {
        format!("{value:?}")
    }
}

/// An [`Error::InvalidOption`] as an `Err`: how option checks refuse a value.
pub(crate) fn bad_option<T>(name: &'static str, value: f64, reason: &'static str) -> Result<T> {
    Err(Error::InvalidOption {
        name,
        value,
        reason,
    })
}

/// The element of `all` called `text` (by `name`), or an [`Error::InvalidInput`] about `what`
/// that lists the names: how every name-parsed enum (parameters, figure kinds, methods) reads
/// user text.
pub(crate) fn by_name<T: Copy>(
    all: &[T],
    name: fn(T) -> &'static str,
    what: &'static str,
    text: &str,
) -> Result<T> {
    all.iter()
        .copied()
        .find(|&v| name(v) == text)
        .ok_or_else(|| Error::InvalidInput {
            what,
            text: text.to_string(),
            reason: format!(
                "expected one of {}",
                all.iter().map(|&v| name(v)).collect::<Vec<_>>().join(", ")
            ),
        })
}
