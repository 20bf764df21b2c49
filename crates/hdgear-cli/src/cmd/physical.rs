//! `hdgear physical`: reduction summary, two-inertia simulation, design check.

use crate::cli::{PhysicalArgs, check_out};
use crate::sink::Sink;
use anyhow::{Context, Result, bail};
use hdgear::output::RecordWriter;
use hdgear::physical::model::{Bearings, Physical};
use hdgear::physical::simulate::{PhysicalSample, simulate_drive};

/// Runs the physical command.
pub fn run(a: PhysicalArgs) -> Result<()> {
    let (d, origin, bearings) = a.drive()?;
    let opts = a.burst.options()?;
    if a.simulate {
        let mut sys = Physical::with_bearings(d, bearings);
        if let Some(text) = &a.twist_friction {
            sys = Bearings::parse_law("twist", text)
                .and_then(|law| sys.with_twist_friction(law))
                .context("--twist-friction")?;
        }
        return simulate(&a, &sys, opts.tol);
    }
    if a.twist_friction.is_some() {
        bail!("--twist-friction acts in the two-inertia model: only --simulate runs it");
    }
    if bearings.any() {
        bail!(
            "friction at the bearings (--output-bearing, --input-bearing or [bearings]) acts on \
             one inertia alone: the reduction to one equation does not hold with it, and only \
             --simulate runs the two-inertia model"
        );
    }
    if a.out.is_some() && !a.frequency_response && !a.robust {
        bail!("--out needs --simulate, --frequency-response or --robust");
    }
    // a drive without a reduction is refused here with the way out
    d.reduce()
        .context("cannot reduce the drive (run it with hdgear physical --simulate)")?;
    if a.frequency_response {
        return frequency_response(&a, &d);
    }
    if a.robust {
        let nominal = hdgear::robust::Nominal::Drive(d);
        let card = crate::cmd::card::load(&a.drive).context("--drive")?;
        return crate::cmd::robust::analyse_and_print(
            nominal,
            Some(&card),
            &a.robust_opts,
            &opts,
            a.out.as_deref(),
            a.json,
        );
    }
    if a.control {
        let card = crate::cmd::card::load(&a.drive).context("--drive")?;
        let c = hdgear::control::ControlOptions {
            spread: Some(0.2),
            ..Default::default()
        };
        let doc = crate::cmd::control::drive_control(&d, &card, &[], &c, &opts)?;
        return crate::cmd::control::print(&doc, a.json, crate::cmd::control::drive_text);
    }
    if a.design {
        let check = hdgear::physical::design::design_check(&d, &opts)?;
        if a.json {
            crate::sink::outln!("{}", serde_json::to_string_pretty(&check)?);
        } else {
            crate::sink::out!("{}", crate::summary::design_text(&check));
        }
        return Ok(());
    }
    let doc = hdgear::physical::design::summarize(&d, origin, &opts)?;
    if a.json {
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        crate::sink::out!("{}", crate::summary::physical_text(&doc));
    }
    Ok(())
}

fn simulate(a: &PhysicalArgs, sys: &Physical, tol: hdgear::integrate::Options) -> Result<()> {
    let d = sys.drive();
    let Some(t_end) = a.t_end else {
        bail!("--simulate needs --t-end T (seconds)");
    };
    if !(t_end.is_finite() && t_end > 0.0) {
        bail!("invalid option --t-end = {t_end:?}: must be finite and > 0");
    }
    let dt = a.dt.unwrap_or(d.j_eq() / d.c_eq / 20.0);
    if !(dt.is_finite() && dt > 0.0) {
        bail!("invalid option --dt = {dt:?}: must be finite and > 0");
    }
    check_out(&a.out)?;
    let samples = t_end / dt;
    if samples > 5e7 && (a.out.is_some() || !a.summary) {
        bail!(
            "--t-end {t_end:?} with --dt {dt:?} would write {samples:.3e} rows: choose a larger --dt"
        );
    }
    let span = t_end / (d.j_eq() / d.c_eq);
    let mut progress = crate::sink::RunProgress::new(span, t_end);
    let summary = if a.summary && a.out.is_none() {
        // no rows are written: sample only the end (progress still advances per step)
        simulate_drive(sys, t_end, t_end, tol, |s| progress.at(s.t))?
    } else {
        let (sink, format) = Sink::open(a.out.as_deref())?;
        let meta = hdgear::physical::simulate::Setup {
            drive: *d,
            bearings: sys.bearings(),
            twist_friction: sys.twist_friction(),
            t_end,
            dt,
        };
        let mut w = RecordWriter::<_, PhysicalSample>::new(sink, format, &meta)?;
        let mut err = None;
        let s = simulate_drive(sys, t_end, dt, tol, |row| {
            progress.at(row.t);
            if err.is_none()
                && let Err(e) = w.row(row)
            {
                err = Some(e);
            }
        })?;
        if let Some(e) = err {
            return Err(e)
                .with_context(|| crate::sink::writing("the trajectory", a.out.as_deref()));
        }
        w.finish()
            .with_context(|| crate::sink::writing("the trajectory", a.out.as_deref()))?
            .commit()?;
        s
    };
    drop(progress);
    if a.summary {
        let doc = summary.report();
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
    }
    Ok(())
}

/// One point of a drive's frequency-response curve: the columns of `--frequency-response --out`.
#[derive(serde::Serialize)]
struct ResponseRow {
    frequency_hz: f64,
    omega_rad_s: f64,
    twist_min: f64,
    twist_max: f64,
    twist_peak_to_peak: f64,
    max_twist_rate: f64,
    torque_min: f64,
    torque_max: f64,
    stable: bool,
    special: &'static str,
}
hdgear::record!(
    ResponseRow: "frequency_hz", "omega_rad_s", "twist_min", "twist_max", "twist_peak_to_peak",
    "max_twist_rate", "torque_min", "torque_max", "stable", "special"
);

fn frequency_response(a: &PhysicalArgs, d: &hdgear::physical::PhysicalParams) -> Result<()> {
    use hdgear::periodic::{ContinuationOptions, Special, physical_frequency_response};
    let hz = crate::cli::parse_frequency_range("--hz", a.hz.as_deref())?;
    check_out(&a.out)?;
    if let Some(plot) = &a.plot {
        crate::cli::check_plot(plot)?;
    }
    let r = physical_frequency_response(d, hz, &ContinuationOptions::default())
        .context("frequency response")?;
    if let Some(out) = &a.out {
        let rows = r.points.iter().map(|q| ResponseRow {
            frequency_hz: q.frequency_hz,
            omega_rad_s: q.omega_rad_s,
            twist_min: q.twist_range[0],
            twist_max: q.twist_range[1],
            twist_peak_to_peak: q.twist_peak_to_peak,
            max_twist_rate: q.max_twist_rate,
            torque_min: q.torque_range[0],
            torque_max: q.torque_range[1],
            stable: q.stable,
            special: q.special.map_or("", Special::name),
        });
        crate::sink::write_records(Some(out), &r.drive, rows)?;
    }
    if let Some(plot) = &a.plot {
        let f = hdgear::figures::physical_response_figure(&r);
        hdgear::output::plot::write(&f, plot)?;
    }
    if a.json {
        crate::sink::outln!("{}", serde_json::to_string_pretty(&r)?);
        return Ok(());
    }
    let (first, last) = (&r.points[0], &r.points[r.points.len() - 1]);
    crate::sink::outln!(
        "frequency response of the drive from {:.3} Hz to {:.3} Hz: {} points",
        first.frequency_hz,
        last.frequency_hz,
        r.points.len()
    );
    if let Some(q) = r
        .points
        .iter()
        .max_by(|x, y| x.twist_peak_to_peak.total_cmp(&y.twist_peak_to_peak))
    {
        crate::sink::outln!(
            "  largest response at {:.3} Hz: twist {:.4e} … {:.4e} rad ({:.4e} rad peak to peak), \
             elastic torque {:.3} … {:.3} N m",
            q.frequency_hz,
            q.twist_range[0],
            q.twist_range[1],
            q.twist_peak_to_peak,
            q.torque_range[0],
            q.torque_range[1]
        );
    }
    crate::summary::specials(
        r.points.iter().filter(|q| q.special.is_some()),
        |q| q.special.map_or("", Special::name),
        |q| {
            format!(
                "{:.6} Hz, twist {:.4e} rad peak to peak",
                q.frequency_hz, q.twist_peak_to_peak
            )
        },
        "no fold: the response is single-valued, a frequency sweep does not jump",
    )
}
