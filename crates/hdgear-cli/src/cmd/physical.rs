//! `hdgear physical`: reduction summary, two-inertia simulation, design check.

use crate::cli::{PhysicalArgs, check_out};
use crate::sink::Sink;
use anyhow::{Context, Result, bail};
use hdgear::output::RecordWriter;
use hdgear::physical::catalogue::ASSUMPTIONS;
use hdgear::physical::simulate::{PhysicalSample, simulate_physical};

/// Runs the physical command.
pub fn run(a: PhysicalArgs) -> Result<()> {
    let (d, fit) = a.drive()?;
    let opts = a.burst.options()?;
    if a.simulate {
        return simulate(&a, &d, opts.tol);
    }
    // a drive without a reduction is refused here with the way out
    d.reduce()
        .context("cannot reduce the drive (run it with hdgear physical --simulate)")?;
    if a.design {
        let check = hdgear::physical::design::design_check(&d, &opts)?;
        if a.json {
            println!("{}", serde_json::to_string_pretty(&check)?);
        } else {
            print!("{}", crate::summary::design_text(&check));
        }
        return Ok(());
    }
    let origin = hdgear::physical::design::CatalogueOrigin {
        name: a.drive.clone(),
        fit,
        assumptions: &ASSUMPTIONS,
    };
    let doc = hdgear::physical::design::summarize(&d, origin, &opts)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        print!("{}", crate::summary::physical_text(&doc));
    }
    Ok(())
}

fn simulate(
    a: &PhysicalArgs,
    d: &hdgear::physical::PhysicalParams,
    tol: hdgear::integrate::Options,
) -> Result<()> {
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
        simulate_physical(d, t_end, t_end, tol, |s| progress.at(s.t))?
    } else {
        let (sink, format) = Sink::open(a.out.as_deref())?;
        let meta = hdgear::physical::simulate::Setup {
            drive: *d,
            t_end,
            dt,
        };
        let mut w = RecordWriter::<_, PhysicalSample>::new(sink, format, &meta)?;
        let mut err = None;
        let s = simulate_physical(d, t_end, dt, tol, |row| {
            progress.at(row.t);
            if err.is_none()
                && let Err(e) = w.row(row)
            {
                err = Some(e);
            }
        })?;
        if let Some(e) = err {
            return Err(e).context("writing the trajectory");
        }
        w.finish().context("writing the trajectory")?.commit()?;
        s
    };
    drop(progress);
    if a.summary {
        let doc = summary.report();
        println!("{}", serde_json::to_string_pretty(&doc)?);
    }
    Ok(())
}
