//! `hdgear fit`: a law's parameters fitted to measured data, with intervals, correlations, the
//! combinations the data do not determine, the residual plot, and a card out.

use crate::sink::{ComputationFailed, check_not_input, note, outln};
use anyhow::{Context, Result, bail};
use clap::Args;
use hdgear::fit::{Column, Data, DataKind, Fit, FitLaw, FitOptions, Free};
use hdgear::model::terms::AnyTerm;
use hdgear::scenario::Scenario;
use std::path::{Path, PathBuf};

/// Arguments of `hdgear fit`.
#[derive(Args, Debug)]
pub struct FitArgs {
    /// The measured data: a CSV file with a header row naming the columns, each with its unit
    /// (`speed [rpm]`, `torque [N m]`); NaN or empty cells leave their row out (with a warning).
    /// An optional column `torque_sd` gives each torque's standard deviation (weights).
    #[arg(long, value_name = "FILE")]
    pub data: PathBuf,
    /// What the data measured: friction (torque against a constant speed; columns speed,
    /// torque) or loop (a quasi-static torque–twist test, rows in the order the twist was
    /// applied; columns twist, torque).
    #[arg(long, value_name = "KIND")]
    pub kind: DataKind,
    /// The law to fit: a scenario file whose term tables ([coulomb], [lugre], [piecewise],
    /// [boucwen], …) give its terms, in the data's SI units, and the start values.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// A term of the law at its default values (repeatable; beside --config's terms).
    #[arg(long = "term", value_name = "KIND")]
    pub terms: Vec<String>,
    /// A parameter to fit, with its bounds: NAME=LO:HI (fs or coulomb.fs; repeatable). The
    /// other parameters are held at their values.
    #[arg(long = "free", value_name = "NAME=LO:HI", required = true)]
    pub free: Vec<Free>,
    /// The column holding a quantity where it is not named after it: QUANTITY=HEADER
    /// (speed, twist or torque; repeatable).
    #[arg(long = "column", value_name = "QUANTITY=HEADER")]
    pub columns: Vec<String>,
    /// A quantity's unit where the header does not give it: QUANTITY=UNIT.
    #[arg(long = "unit", value_name = "QUANTITY=UNIT", help = format!(
        "A quantity's unit where the header does not give it: QUANTITY=UNIT ({})",
        hdgear::fit::units_text()
    ))]
    pub units: Vec<String>,
    /// Starts of the minimisation: the law's values, then a Sobol design in the bounds.
    #[arg(long, default_value_t = 16)]
    pub starts: usize,
    /// Seed of the Sobol design.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Skip the profile-likelihood intervals (they cost a fit per step along each parameter).
    #[arg(long)]
    pub no_profile: bool,
    /// Passes of a loop's twist path run before the compared one, from the virgin state (the
    /// cycles a test runs before recording).
    #[arg(long, default_value_t = 0)]
    pub repeat: usize,
    /// Write the points with the fitted torque and the residual (x,measured,predicted,residual).
    #[arg(long, value_name = "FILE")]
    pub residuals: Option<PathBuf>,
    /// Draw the data with the fitted law, and the residuals (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Write the fitted law as a scenario file's term tables.
    #[arg(long, value_name = "FILE")]
    pub law_out: Option<PathBuf>,
    /// Write a card file: --card's card with the fitted friction or curve, citing the fit; a
    /// fitted curve's standard errors become its tolerance bands k1, k2 for `hdgear robust`.
    #[arg(long, value_name = "FILE", requires = "card")]
    pub card_out: Option<PathBuf>,
    /// The card --card-out starts from: a built-in card, FILE.toml or FILE.toml#NAME.
    #[arg(long, value_name = "CARD")]
    pub card: Option<String>,
    /// Print JSON (for programs) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `QUANTITY=VALUE` pairs of a flag, each naming a quantity of the data's kind.
fn pairs<'a>(flag: &str, list: &'a [String], kind: DataKind) -> Result<Vec<(&'a str, &'a str)>> {
    let known = [kind.abscissa().name, hdgear::fit::TORQUE.name];
    list.iter()
        .map(|p| {
            let (q, v) = p
                .split_once('=')
                .with_context(|| format!("invalid option {flag} '{p}': write QUANTITY=VALUE"))?;
            if !known.contains(&q) {
                bail!(
                    "invalid option {flag} '{p}': {} data have the quantities {}",
                    kind.name(),
                    known.join(", ")
                );
            }
            Ok((q, v))
        })
        .collect()
}

impl FitArgs {
    /// The law from --config and --term.
    fn law(&self) -> Result<FitLaw> {
        let mut terms = Vec::new();
        if let Some(path) = &self.config {
            let scenario = Scenario::load(path)?;
            for (kind, values) in scenario.term_tables(path)? {
                terms.push(AnyTerm::new(kind, &values)?);
            }
        }
        for kind in &self.terms {
            let (kind, values) = hdgear::model::tables::term_values(kind, [])
                .map_err(|e| anyhow::anyhow!("invalid option --term '{kind}': {e}"))?;
            terms.push(AnyTerm::new(kind, &values)?);
        }
        if terms.is_empty() {
            bail!("give the law to fit: --config FILE with its term tables, or --term KIND");
        }
        Ok(FitLaw::new(terms)?)
    }

    /// The columns for the data's quantities.
    fn columns(&self) -> Result<(Column, Column)> {
        let (mut x, mut torque) = (Column::default(), Column::default());
        for (flag, list) in [("--column", &self.columns), ("--unit", &self.units)] {
            for (q, v) in pairs(flag, list, self.kind)? {
                let c = if q == hdgear::fit::TORQUE.name {
                    &mut torque
                } else {
                    &mut x
                };
                let slot = if flag == "--column" {
                    &mut c.name
                } else {
                    &mut c.unit
                };
                *slot = Some(v.to_string());
            }
        }
        Ok((x, torque))
    }

    fn outputs(&self) -> impl Iterator<Item = (&'static str, &Path)> {
        [
            ("--residuals", &self.residuals),
            ("--plot", &self.plot),
            ("--law-out", &self.law_out),
            ("--card-out", &self.card_out),
        ]
        .into_iter()
        .filter_map(|(f, p)| p.as_deref().map(|p| (f, p)))
    }
}

pub fn run(a: FitArgs) -> Result<()> {
    let law = a.law()?;
    for (_, out) in a.outputs() {
        check_not_input(out, [a.data.as_path()], "the data file")?;
    }
    if let Some(p) = &a.plot {
        let ext = p
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("svg" | "png")) {
            bail!(
                "invalid option --plot '{}': the extension must be .svg or .png",
                p.display()
            );
        }
    }
    let card = a
        .card
        .as_deref()
        .map(crate::cmd::card::load)
        .transpose()
        .context("--card")?;
    let (x, torque) = a.columns()?;
    let (data, warnings) = Data::read(&a.data, a.kind, &x, &torque)?;
    let options = FitOptions {
        starts: a.starts,
        seed: a.seed,
        profile: !a.no_profile,
        repeat: a.repeat,
    };
    let fit = hdgear::fit::fit(&law, &data, &a.free, &options)?;
    for w in warnings.iter().chain(&fit.warnings) {
        note(&w.to_string());
    }
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&fit)?);
    } else {
        print(&fit)?;
    }
    if let Some(path) = &a.residuals {
        let mut text = String::from("x,measured,predicted,residual\n");
        for i in 0..fit.x.len() {
            text += &format!(
                "{:?},{:?},{:?},{:?}\n",
                fit.x[i], fit.measured[i], fit.predicted[i], fit.residuals[i]
            );
        }
        hdgear::output::write_atomic(path, text.as_bytes()).context("--residuals")?;
    }
    if let Some(path) = &a.plot {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("fit");
        hdgear::output::plot::write(&hdgear::fit::figure(&fit, stem), path).context("--plot")?;
    }
    if let Some(path) = &a.law_out {
        let text = format!("# {}\n{}", hdgear::fit::citation(&fit), fit.law.to_toml());
        hdgear::output::write_atomic(path, text.as_bytes()).context("--law-out")?;
    }
    if let (Some(path), Some(card)) = (&a.card_out, &card) {
        if !fit.converged() {
            return Err(ComputationFailed(format!(
                "--card-out {}: not written, the fit did not converge",
                path.display()
            ))
            .into());
        }
        let file = hdgear::fit::fitted_card(&card.card, &card.sources, &fit)?;
        hdgear::output::write_atomic(path, file.to_toml().as_bytes()).context("--card-out")?;
    }
    Ok(())
}

/// The text report.
fn print(f: &Fit) -> Result<()> {
    outln!(
        "fit of {} ({} data, {} points, CRC-32 {})",
        f.source.path,
        f.kind.name(),
        f.x.len(),
        f.source.crc32
    );
    outln!(
        "{} starts, {} at the best; {} after {} iterations (stop: {})",
        f.starts,
        f.starts_at_best,
        if f.converged() {
            "converged"
        } else {
            "NOT converged"
        },
        f.iterations,
        f.stop.name()
    );
    outln!(
        "noise {:.4e} (residual RMS, weighted) on {} degrees of freedom; t = {:.4}",
        f.noise,
        f.dof,
        f.t
    );
    outln!();
    outln!(
        "{:<18} {:>13} {:>11}  {:<29} {}",
        "parameter",
        "estimate",
        "std error",
        "95 % from JᵀJ",
        "95 % profile likelihood"
    );
    let interval =
        |i: Option<[f64; 2]>| i.map_or("-".to_string(), |[lo, hi]| format!("[{lo:.5e}, {hi:.5e}]"));
    for e in &f.estimates {
        let profile = e.profile.map(|p| {
            let mut s = interval(Some([p.lo, p.hi]));
            if p.lo_open || p.hi_open {
                s += " (bound)";
            }
            if e.quadratic == Some(false) {
                s += " *";
            }
            s
        });
        outln!(
            "{:<18} {:>13.6e} {:>11}  {:<29} {}",
            e.name,
            e.value,
            e.std_error.map_or("-".into(), |s| format!("{s:.3e}")),
            interval(e.wald),
            profile.unwrap_or_else(|| "-".into())
        );
    }
    if f.estimates.iter().any(|e| e.quadratic == Some(false)) {
        outln!("* the profile is not quadratic: trust its interval, not JᵀJ's");
    }
    if f.estimates.len() > 1 {
        outln!();
        outln!("correlation");
        for (e, row) in f.estimates.iter().zip(&f.correlation) {
            let cells: Vec<String> = row.iter().map(|c| format!("{c:>6.2}")).collect();
            outln!("{:<18} {}", e.name, cells.join(" "));
        }
    }
    outln!();
    outln!("fitted law (SI units of the data):");
    for line in f.law.to_toml().lines() {
        outln!("  {line}");
    }
    Ok(())
}
