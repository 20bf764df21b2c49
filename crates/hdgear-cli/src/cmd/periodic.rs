//! `hdgear periodic`: the periodic orbit by shooting, its Floquet multipliers and stability, and
//! optionally the largest Lyapunov exponent.

use crate::sink::{warn, write_records};
use anyhow::Result;
use hdgear::periodic::{
    LyapunovEstimate, Periodic, PeriodicOptions, PeriodicOrbit, burst_verdict, lyapunov_converged,
    shoot,
};
use serde::Serialize;

use crate::args::BurstArgs;
use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `hdgear periodic`.
#[derive(Args, Debug)]
pub struct PeriodicArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
    /// K: look for the orbit of period K·2π/ω.
    #[arg(long, default_value_t = 1)]
    pub subharmonic: u32,
    /// Also compute the largest Lyapunov exponent (Benettin, over 50 forcing periods).
    #[arg(long)]
    pub lyapunov: bool,
    /// Print one JSON document.
    #[arg(long)]
    pub json: bool,
    /// The orbit's samples (t,x,xdot every 0.05 over one period) to a .csv, .json or .parquet file.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The JSON document: the orbit and, when asked, the Lyapunov exponent.
#[derive(Serialize)]
struct Doc<'a, S: Serialize> {
    #[serde(flatten)]
    orbit: &'a hdgear::periodic::PeriodicOrbit<S>,
    /// The burst verdict on the orbit itself.
    bursts: hdgear::burst::Classification,
    lyapunov_exponent: Option<f64>,
    /// The exponent with its standard error and the span it was averaged over.
    #[serde(skip_serializing_if = "Option::is_none")]
    lyapunov: Option<LyapunovEstimate>,
    /// (τ, x, x') every 0.05 over one period.
    samples: &'a [[f64; 3]],
}

/// The relative standard error the Lyapunov exponent is averaged to.
const LYAPUNOV_REL_TOL: f64 = 1e-3;

pub fn run(a: PeriodicArgs) -> Result<()> {
    let (system, warnings) = a.params.resolve_system()?;
    let burst_opts = a.burst.options()?;
    crate::args::check_out(&a.out)?;
    warn(&warnings);
    hdgear::on_subject!(&system, |p| run_on(p, &a, &burst_opts))
}

/// The orbit of the study's set or of a model, its verdict, exports and summary.
fn run_on<S: Periodic>(
    p: &S,
    a: &PeriodicArgs,
    burst_opts: &hdgear::burst::BurstOptions,
) -> Result<()> {
    let opts = PeriodicOptions::default();
    let orbit = shoot(p, a.subharmonic, &opts)?;
    let bursts = burst_verdict(&orbit, burst_opts)?;
    let lyap = if a.lyapunov {
        Some(lyapunov_converged(
            p,
            orbit.start,
            LYAPUNOV_REL_TOL,
            opts.tol,
        )?)
    } else {
        None
    };
    if let Some(out) = &a.out {
        let rows = orbit
            .samples
            .iter()
            .map(|&s| hdgear::simulate::StateSample::from(s));
        write_records(Some(out), &orbit, rows)?;
    }
    if a.json {
        let doc = Doc {
            orbit: &orbit,
            bursts,
            lyapunov_exponent: lyap.map(|l| l.exponent),
            lyapunov: lyap,
            samples: &orbit.samples,
        };
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    print_orbit(&orbit, &bursts, lyap)
}

/// The readable summary of an orbit, its burst verdict and its Lyapunov exponent.
fn print_orbit<S>(
    orbit: &PeriodicOrbit<S>,
    bursts: &hdgear::burst::Classification,
    lyap: Option<LyapunovEstimate>,
) -> Result<()> {
    let m = |k: usize| {
        let q = orbit.multipliers[k];
        if q.log_abs == f64::NEG_INFINITY {
            format!("m{} = 0 (a rest forgets the speed)", k + 1)
        } else {
            format!("ln|m{}| = {:.10}, arg {:.4}", k + 1, q.log_abs, q.arg)
        }
    };
    crate::sink::outln!(
        "periodic orbit of period {} × 2π/ω = {:.6}: starts at (x, x') = ({:.12}, {:.12}) at τ = 0",
        orbit.subharmonic,
        orbit.period,
        orbit.start[0],
        orbit.start[1]
    );
    crate::sink::outln!(
        "  Newton: {} iterations, residual {:.1e}",
        orbit.newton_iterations,
        orbit.residual
    );
    if orbit.minimal_subharmonic < orbit.subharmonic {
        crate::sink::outln!(
            "  its least period is {} × 2π/ω: no subharmonic of order {} here",
            orbit.minimal_subharmonic,
            orbit.subharmonic
        );
    }
    crate::sink::outln!("  Floquet multipliers: {}; {}", m(0), m(1));
    crate::sink::outln!(
        "  Floquet exponents {:.8}, {:.8}: {}",
        orbit.floquet_exponents[0],
        orbit.floquet_exponents[1],
        orbit.stability().name()
    );
    crate::sink::outln!(
        "  x from {:.6} to {:.6} (peak to peak {:.6}), max |x'| {:.6}",
        orbit.x_range[0],
        orbit.x_range[1],
        orbit.peak_to_peak,
        orbit.max_abs_xdot
    );
    if let Some(r) = orbit.rests {
        crate::sink::outln!(
            "  rests per period: {}, {} switches, at rest for {:.6} ({:.1} % of the period)",
            r.rests,
            r.switches,
            r.time_stuck,
            100.0 * r.time_stuck / orbit.period
        );
    }
    crate::sink::outln!(
        "  bursts on the orbit itself: {} (verdict {}, mode {}, mechanism {})",
        if bursts.bursting { "yes" } else { "no" },
        bursts.verdict.name(),
        bursts.mode.name(),
        bursts.mechanism.name()
    );
    if let Some(l) = lyap {
        crate::sink::outln!(
            "  largest Lyapunov exponent (Benettin, over {:.0} time units): {:.8} ± {:.1e}{}",
            l.span,
            l.exponent,
            l.standard_error,
            if l.converged {
                ""
            } else {
                " (not converged to the requested 1e-3 within the span limit)"
            }
        );
    }
    Ok(())
}
