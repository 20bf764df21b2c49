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
    let r = d
        .reduce()
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
    let p = r.params;
    let predicted = if p.omega >= hdgear::physical::design::MIN_SIMULATED_OMEGA {
        let resp = hdgear::burst::response(&p, &opts)?;
        let c = hdgear::burst::classify(&p, &resp);
        serde_json::json!({ "bursting": c.bursting, "verdict": c.verdict, "mode": c.mode, "mechanism": c.mechanism,
            "fast_slow_domain": c.fast_slow_domain, "bursts_per_period": resp.bursts_per_period })
    } else {
        serde_json::json!({ "bursting": hdgear::fast::predict(&p).bursting, "verdict": null, "mode": null,
            "mechanism": null, "note": "reduced omega below 1e-4: not simulated; predicted from the equilibrium curve" })
    };
    let doc = serde_json::json!({
        "drive": d,
        "catalogue": { "name": a.drive, "fit": fit, "assumptions": ASSUMPTIONS },
        "reduced": p,
        "time_scale": r.time_scale,
        "length_scale": r.length_scale,
        "j_eq": r.j_eq,
        "alpha_eps": p.alpha * p.eps,
        "critical_gamma": p.critical_gamma(),
        "gamma_margin": p.gamma - p.critical_gamma(),
        "predicted": predicted,
    });
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
        let meta = serde_json::json!({ "drive": d, "t_end": t_end, "dt": dt });
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
        let f = summary.final_state;
        let doc = serde_json::json!({
            "t_end": summary.t_end,
            "final": {
                "theta": f.theta, "theta_dot": f.theta_dot,
                "theta_in": f.theta_in, "theta_out": f.theta_out,
                "theta_in_dot": summary.final_rates[0], "theta_out_dot": summary.final_rates[1],
            },
            "stats": summary.stats,
            "angle_scale": summary.angle_scale,
        });
        println!("{}", serde_json::to_string_pretty(&doc)?);
    }
    Ok(())
}
