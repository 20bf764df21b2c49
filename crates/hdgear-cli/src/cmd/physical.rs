//! `hdgear physical`: reduction summary, two-inertia simulation, design check.

use crate::args::check_out;
use crate::sink::Sink;
use anyhow::{Context, Result, bail};
use hdgear::output::RecordWriter;
use hdgear::physical::model::{Bearings, Physical};
use hdgear::physical::simulate::{PhysicalSample, simulate_drive};

use crate::args::BurstArgs;
use crate::cmd::robust::RobustOpts;
use clap::Args;
use hdgear::scenario::Scenario;
use std::path::PathBuf;

/// The drive a command of the two-inertia model runs: its card, a scenario's `[physical]` and
/// `[bearings]` tables, and flags for each value (`hdgear physical`, `hdgear export fmu`).
#[derive(Args, Debug)]
pub struct DriveArgs {
    /// The drive's card for the stiffness (k1, k2 fitted to its curve) with documented
    /// assumptions for the rest: a built-in card (hdgear card list) or a card file
    /// (FILE.toml, or FILE.toml#NAME when it holds several).
    #[arg(long, default_value = "CSF-20-50", value_name = "CARD")]
    pub drive: String,
    /// Torque up to which the catalogue curve is fitted [N m] (default T2).
    #[arg(long, allow_negative_numbers = true)]
    pub fit_torque: Option<f64>,
    /// TOML scenario file with a [physical] table (keys j_in, j_out, ratio, k1, k2, backlash,
    /// c_eq, t_m, t_am, omega).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// J_i, input inertia [kg m^2].
    #[arg(long, allow_negative_numbers = true)]
    pub j_in: Option<f64>,
    /// J_o, output inertia [kg m^2].
    #[arg(long, allow_negative_numbers = true)]
    pub j_out: Option<f64>,
    /// N, reduction ratio.
    #[arg(long, allow_negative_numbers = true)]
    pub ratio: Option<f64>,
    /// k1, linear stiffness [N m/rad].
    #[arg(long, allow_negative_numbers = true)]
    pub k1: Option<f64>,
    /// k2, cubic stiffness [N m/rad^3].
    #[arg(long, allow_negative_numbers = true)]
    pub k2: Option<f64>,
    /// phi, backlash [rad].
    #[arg(long, allow_negative_numbers = true)]
    pub backlash: Option<f64>,
    /// C, equivalent damping [N m s/rad].
    #[arg(long, allow_negative_numbers = true)]
    pub c_eq: Option<f64>,
    /// T_m, mean torque [N m].
    #[arg(long, allow_negative_numbers = true)]
    pub t_m: Option<f64>,
    /// T_am, disturbance amplitude [N m].
    #[arg(long, allow_negative_numbers = true)]
    pub t_am: Option<f64>,
    /// Omega, disturbance frequency [rad/s].
    #[arg(long, allow_negative_numbers = true)]
    pub omega: Option<f64>,
    /// Friction at the output bearing, on θo' (the two-inertia model: --simulate, hdgear export
    /// fmu): LAW:KEY=VALUE,… in SI units, every key given, LAW friction (fc [N m], vs [rad/s])
    /// or stribeck (fc, fs [N m], vst [rad/s], cv [N m s/rad], vr [rad/s]); e.g.
    /// friction:fc=0.8,vs=1e-3. Replaces the scenario's [bearings.output] table.
    #[arg(long, value_name = "LAW")]
    pub output_bearing: Option<String>,
    /// Friction at the wave generator, on θi' (the two-inertia model: --simulate, hdgear export
    /// fmu): LAW:KEY=VALUE,… as --output-bearing. Replaces the scenario's [bearings.input] table.
    #[arg(long, value_name = "LAW")]
    pub input_bearing: Option<String>,
    /// Friction across the compliance, on the twist rate θ' (the two-inertia model: --simulate,
    /// hdgear export fmu): LAW:KEY=VALUE,… as --output-bearing, a torque between the two
    /// inertias (the teeth's sliding in mesh).
    #[arg(long, value_name = "LAW")]
    pub twist_friction: Option<String>,
}

/// Arguments of `hdgear physical`.
#[derive(Args, Debug)]
pub struct PhysicalArgs {
    #[command(flatten)]
    pub spec: DriveArgs,
    /// Print one JSON document (the reduction, or with --design the design check).
    #[arg(long, conflicts_with = "simulate")]
    pub json: bool,
    /// Simulate the two-inertia model from rest instead (SI time).
    #[arg(long)]
    pub simulate: bool,
    /// End time of the simulation [s].
    #[arg(long, requires = "simulate", allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Output spacing [s] (default J_eq/C / 20).
    #[arg(long, requires = "simulate", allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// Trajectory file with --simulate (.csv, .json or .parquet; CSV on stdout without it and
    /// without --summary), the curve with --frequency-response, or the samples with --robust.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The frequency-response curve of the drive (continuation in the disturbance frequency) in
    /// SI units: twist, torque, stability, folds.
    #[arg(long, conflicts_with_all = ["simulate", "design"])]
    pub frequency_response: bool,
    /// LO:HI, the frequency range in Hz of --frequency-response (default: from 1/20 to 3 times
    /// the stiffest static frequency).
    #[arg(long, value_name = "LO:HI", requires = "frequency_response")]
    pub hz: Option<String>,
    /// The figure of --frequency-response to a .svg or .png file.
    #[arg(long, value_name = "FILE", requires = "frequency_response")]
    pub plot: Option<PathBuf>,
    /// Print a JSON summary of the simulation.
    #[arg(long, requires = "simulate")]
    pub summary: bool,
    /// Design check: distance to the bursting regime and the single changes that cross it.
    #[arg(long, conflicts_with = "simulate")]
    pub design: bool,
    /// Burst control: the laws of hdgear control tuned on the drive (±20 % robustness), each
    /// law's torque in N m against the card's ratings.
    #[arg(long, conflicts_with_all = ["simulate", "design", "frequency_response"])]
    pub control: bool,
    /// The design check under manufacturing spread (hdgear robust's analysis of this drive;
    /// its options below).
    #[arg(long, conflicts_with_all = ["simulate", "design", "frequency_response", "control"])]
    pub robust: bool,
    #[command(flatten)]
    pub robust_opts: RobustOpts,
    #[command(flatten)]
    pub burst: BurstArgs,
}

impl DriveArgs {
    /// The drive: its card, then file, then flags; validated. With it, the card's name, the
    /// stiffness fit and what was assumed, and the friction at its bearings (the file's
    /// `[bearings]` tables, each side replaced by its flag where given).
    pub fn drive(
        &self,
    ) -> Result<(
        hdgear::physical::PhysicalParams,
        hdgear::physical::design::CatalogueOrigin,
        hdgear::physical::model::Bearings,
    )> {
        let card = crate::cmd::card::load(&self.drive).context("--drive")?;
        let built = hdgear::physical::catalogue::assemble(&card.card, self.fit_torque, None)
            .context("--drive / --fit-torque")?;
        let mut d = built.drive;
        let origin = hdgear::physical::design::CatalogueOrigin {
            name: card.card.name,
            fit: built.fit,
            assumptions: built.assumptions,
        };
        let mut from_file = Bearings::default();
        if let Some(path) = &self.config {
            let s = Scenario::load(path)?;
            from_file = s.bearings(path)?;
            if let Some(name) = s.terms.keys().next() {
                anyhow::bail!(
                    "scenario file {}: its [{name}] table is a term of the dimensionless model \
                     (hdgear model, hdgear simulate), not of the physical drive",
                    path.display()
                );
            }
            match s.physical {
                Some(ph) => ph.apply(&mut d),
                // the drive's friction alone
                None if s.bearings.is_some() => {}
                None => anyhow::bail!(
                    "scenario file {} has no [physical] table{}",
                    path.display(),
                    if s.params.is_some() {
                        " (its [params] table is for the dimensionless commands)"
                    } else {
                        ""
                    }
                ),
            }
        }
        hdgear::physical::PhysicalOverrides {
            j_in: self.j_in,
            j_out: self.j_out,
            ratio: self.ratio,
            k1: self.k1,
            k2: self.k2,
            backlash: self.backlash,
            c_eq: self.c_eq,
            t_m: self.t_m,
            t_am: self.t_am,
            omega: self.omega,
        }
        .apply(&mut d);
        d.validate()?;
        let side = |flag: &str, text: &Option<String>, file| match text {
            Some(text) => Bearings::parse_law(flag, text)
                .map(Some)
                .with_context(|| format!("--{flag}-bearing")),
            None => Ok(file),
        };
        let bearings = Bearings::new(
            side("output", &self.output_bearing, from_file.output)?,
            side("input", &self.input_bearing, from_file.input)?,
        )?;
        Ok((d, origin, bearings))
    }

    /// The two-inertia model: the drive with its bearings and the friction across its
    /// compliance; with it, the card's name and what was assumed.
    pub fn system(&self) -> Result<(Physical, hdgear::physical::design::CatalogueOrigin)> {
        let (d, origin, bearings) = self.drive()?;
        let mut sys = Physical::with_bearings(d, bearings);
        if let Some(text) = &self.twist_friction {
            sys = Bearings::parse_law("twist", text)
                .and_then(|law| sys.with_twist_friction(law))
                .context("--twist-friction")?;
        }
        Ok((sys, origin))
    }
}

/// Runs the physical command.
pub fn run(a: PhysicalArgs) -> Result<()> {
    if a.simulate {
        let (sys, _) = a.spec.system()?;
        return simulate(&a, &sys, a.burst.options()?.tol);
    }
    let (d, origin, bearings) = a.spec.drive()?;
    let opts = a.burst.options()?;
    if a.spec.twist_friction.is_some() {
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
        let card = crate::cmd::card::load(&a.spec.drive).context("--drive")?;
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
        let card = crate::cmd::card::load(&a.spec.drive).context("--drive")?;
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
        let meta = hdgear::physical::simulate::PhysicalSetup {
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
#[derive(serde::Serialize, hdgear::output::Record)]
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

fn frequency_response(a: &PhysicalArgs, d: &hdgear::physical::PhysicalParams) -> Result<()> {
    use hdgear::periodic::{ContinuationOptions, Special, physical_frequency_response};
    let hz = crate::args::parse_frequency_range("--hz", a.hz.as_deref())?;
    check_out(&a.out)?;
    if let Some(plot) = &a.plot {
        crate::args::check_plot(plot)?;
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
