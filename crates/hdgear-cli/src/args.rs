//! The argument groups and checks several commands share: burst settings, tolerances, ranges,
//! output paths, thread counts, and the library's refusals told with the user's flags. Commands
//! import from here; nothing here imports a command.

use anyhow::{Context, Result};
use clap::Args;
use hdgear::integrate::Options;
use std::path::PathBuf;

/// Burst-detection settings shared by the commands that measure a response.
#[derive(Args, Debug, Clone)]
pub struct BurstArgs {
    /// Slow periods discarded as transient.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub discard: f64,
    /// Whole slow periods analysed after the transient.
    #[arg(long, default_value_t = 2)]
    pub window_periods: u32,
    #[command(flatten)]
    pub tol: TolArgs,
}

impl BurstArgs {
    /// Checked burst options.
    pub fn options(&self) -> Result<hdgear::burst::BurstOptions> {
        let o = hdgear::burst::BurstOptions {
            discard_periods: self.discard,
            periods: self.window_periods,
            tol: self.tol.options()?,
            ..Default::default()
        };
        o.validate()
            .map_err(|e| as_flag(e, &[("discard", "discard"), ("periods", "window-periods")]))?;
        Ok(o)
    }
}

/// Parses `A0:A1` into a checked range.
pub fn parse_range(text: &str) -> Result<(f64, f64)> {
    parse_pair("--a-range", "A0:A1", text)
}

/// Parses an optional frequency range `LO:HI` (finite, 0 < LO < HI) for option `flag`.
pub fn parse_frequency_range(flag: &str, text: Option<&str>) -> Result<Option<(f64, f64)>> {
    let Some(text) = text else {
        return Ok(None);
    };
    let (lo, hi) = parse_pair(flag, "LO:HI", text)?;
    if lo <= 0.0 {
        anyhow::bail!("invalid {flag} '{text}': frequencies must be > 0");
    }
    Ok(Some((lo, hi)))
}

/// Parses `LO:HI` (finite, LO < HI) for option `flag`.
pub fn parse_pair(flag: &str, form: &str, text: &str) -> Result<(f64, f64)> {
    let bad = || {
        anyhow::anyhow!(
            "invalid {flag} '{text}': expected {form} with finite numbers, the first smaller"
        )
    };
    let (l, r) = text.split_once(':').ok_or_else(bad)?;
    let (l, r): (f64, f64) = (
        l.trim().parse().map_err(|_| bad())?,
        r.trim().parse().map_err(|_| bad())?,
    );
    if !(l.is_finite() && r.is_finite() && l < r) {
        return Err(bad());
    }
    Ok((l, r))
}

/// Checks an optional output path's extension.
pub fn check_out(out: &Option<PathBuf>) -> Result<()> {
    if let Some(out) = out {
        hdgear::output::Format::from_path(out).context("--out")?;
        hdgear::output::check_output_path(out).context("--out")?;
    }
    Ok(())
}

/// Checks a figure's path given with `--plot`: .svg or .png, in an existing directory.
pub fn check_plot(path: &std::path::Path) -> Result<()> {
    check_figure_path("--plot", path)
}

/// Checks a figure's path given with `flag`: .svg or .png, in an existing directory.
pub fn check_figure_path(flag: &'static str, path: &std::path::Path) -> Result<()> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg" | "png") => {}
        _ => anyhow::bail!(
            "{flag} {}: the extension must be .svg or .png",
            path.display()
        ),
    }
    hdgear::output::check_output_path(path).context(flag)
}

/// Integrator tolerances.
#[derive(Args, Debug, Clone)]
pub struct TolArgs {
    /// Relative tolerance (1e-15 … 1).
    #[arg(long, default_value = "1e-10", allow_negative_numbers = true)]
    pub rtol: f64,
    /// Absolute tolerance (> 0).
    #[arg(long, default_value = "1e-10", allow_negative_numbers = true)]
    pub atol: f64,
    /// Integration method: taylor (order from the tolerance, Jorba–Zou steps) or dop853
    /// (Dormand–Prince 8(5,3), the independent cross-check).
    #[arg(long, default_value = "taylor")]
    pub method: hdgear::integrate::Method,
}

impl TolArgs {
    /// Checked integrator options.
    pub fn options(&self) -> Result<Options> {
        let o = Options {
            rtol: self.rtol,
            atol: self.atol,
            method: self.method,
            ..Options::default()
        };
        o.validate()
            .map_err(|e| as_flag(e, &[("rtol", "rtol"), ("atol", "atol")]))?;
        Ok(o)
    }
}

/// The library's refusal of an option, told with the user's flag: `flags` pairs the library's
/// option names with the flags that set them (`periods` is `--window-periods`); any other error
/// passes unchanged, with its exit code.
pub fn as_flag(e: hdgear::Error, flags: &[(&str, &str)]) -> anyhow::Error {
    if let hdgear::Error::InvalidOption {
        name,
        value,
        reason,
    } = &e
        && let Some((_, flag)) = flags.iter().find(|(n, _)| n == name)
    {
        let value = hdgear::error::shown(*value);
        return anyhow::anyhow!("invalid option --{flag} = {value}: {reason}");
    }
    e.into()
}

/// `v` if finite and > 0, else the refusal naming `--name`.
pub fn check_positive(name: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        anyhow::bail!("invalid option --{name} = {v:?}: must be finite and > 0")
    }
}

/// Refuses outputs too large to be meant (more than 10⁸ rows).
pub fn check_rows(rows: f64) -> Result<()> {
    if rows > 1e8 {
        anyhow::bail!(
            "the run would write {rows:.3e} rows (more than 1e8): choose a larger --dt or a shorter run"
        );
    }
    Ok(())
}

/// Refuses point counts too large to be meant (more than [`hdgear::fast::MAX_CURVE_POINTS`]).
pub fn check_points(points: usize) -> Result<()> {
    let max = hdgear::fast::MAX_CURVE_POINTS;
    if points > max {
        anyhow::bail!("invalid option --points = {points}: at most {max}");
    }
    Ok(())
}

/// The worker-thread count of `--threads` (none: 0, one per core or `RAYON_NUM_THREADS`),
/// refusing 0 and more than [`hdgear::sweep::MAX_THREADS`].
pub fn threads(given: Option<usize>) -> Result<usize> {
    let max = hdgear::sweep::MAX_THREADS;
    match given {
        Some(0) => anyhow::bail!("invalid option --threads = 0: must be ≥ 1"),
        Some(n) if n > max => anyhow::bail!("invalid option --threads = {n}: at most {max}"),
        _ => {}
    }
    if given.is_none() {
        // no flag: RAYON_NUM_THREADS, when set, decides the count
        hdgear::sweep::check_threads(0)?;
    }
    Ok(given.unwrap_or(0))
}

/// `v` if finite, else the refusal naming `--name`.
pub fn check_finite(name: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        anyhow::bail!("invalid option --{name} = {v:?}: must be finite")
    }
}

/// The axes of a grid, shared by `sweep` and `lyapunov-map`.
#[derive(Args, Debug)]
pub struct GridAxes {
    /// An axis NAME=START:END:COUNT[:log] (one or two).
    #[arg(
        long = "param",
        value_name = "SPEC",
        required = true,
        allow_hyphen_values = true
    )]
    pub axes: Vec<String>,
}
