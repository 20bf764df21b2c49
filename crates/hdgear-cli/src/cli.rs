//! Command-line front end: raw clap arguments, checked into ready-to-run settings.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use hdgear::integrate::Options;
use hdgear::params::{Params, Warning};
use hdgear::scenario::Scenario;
use hdgear::simulate::{SimOptions, Start};
use std::path::PathBuf;

pub use crate::cmd::card::CardArgs;
pub use crate::cmd::control::ControlArgs;
pub use crate::cmd::robust::{RobustArgs, RobustOpts};
pub use crate::sources::ParamArgs;

/// hdgear: fast-slow dynamics of harmonic drive gears.
#[derive(Parser, Debug)]
#[command(name = "hdgear", version, about, long_about = None)]
pub struct Cli {
    /// No warnings on stderr.
    #[arg(long, global = true)]
    pub quiet: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Simulate the dimensionless model and write its trajectory (t,a,x,xdot, then a column per
    /// internal state of the model's terms).
    Simulate(SimulateArgs),
    /// The assembled model: its equation (text and LaTeX), states, parameters with values and
    /// domains, and the facts of its fast subsystem derived from its terms.
    Model(ModelArgs),
    /// Sample the fast subsystem's equilibrium curve (a,x,slope,gprime,re1,im1,re2,im2,type,branch).
    Equilibria(EquilibriaArgs),
    /// Analyse the fast subsystem: folds, cusp, steepest point, Hopf, spiking areas.
    Analyze(AnalyzeArgs),
    /// The fold curves in the (a, gamma) plane up to the cusp (gamma,a_lower,x_lower,a_upper,x_upper).
    Bifurcation(BifurcationArgs),
    /// Detect the bursts of a response and list them one per row.
    Bursts(BurstsArgs),
    /// The study's gamma table and parameter-effects table with measured numbers.
    Table(TableArgs),
    /// Sweep one or two parameters over a grid in parallel (resumable, shardable).
    Sweep(SweepArgs),
    /// The periodic response: the orbit by shooting, its Floquet multipliers, the Lyapunov exponent.
    Periodic(PeriodicArgs),
    /// Follow the periodic orbit in a parameter (pseudo-arclength): folds, period doublings,
    /// the doubled branches.
    Continue(ContinueArgs),
    /// Curves of folds or period doublings in two parameters (two-parameter continuation),
    /// with their cusps and generalised period doublings.
    Continue2(crate::cmd::continuation2::Continue2Args),
    /// Boundaries in two parameters as curves: the bursting boundary (predicted and simulated),
    /// the fold set of the fast subsystem, the edge of the fast-slow domain.
    Boundary(crate::cmd::boundary::BoundaryArgs),
    /// The frequency-response curve: response amplitude against omega, stable and unstable
    /// branches, folds (the jumps).
    FrequencyResponse(FrequencyResponseArgs),
    /// The stroboscopic orbit diagram against a parameter, swept up and down (hysteresis), with
    /// the largest Lyapunov exponent on request.
    OrbitDiagram(OrbitDiagramArgs),
    /// The largest Lyapunov exponent over a grid of one or two parameters (a sweep or a map).
    LyapunovMap(LyapunovMapArgs),
    /// Join the shard files of a sweep into the file one machine would have written.
    Merge(MergeArgs),
    /// A physical drive in SI units: reduction, two-inertia simulation, design check.
    Physical(Box<PhysicalArgs>),
    /// Drive cards: a drive's catalogue numbers with their sources (list, show, check, map, new).
    Card(CardArgs),
    /// Feedback laws against the bursts (virtual stiffness and damping, washout, scheduled
    /// stiffness, dither, delay): each tuned to its least gain that removes them, or assessed at
    /// --gain, with what it costs.
    Control(ControlArgs),
    /// The design check under manufacturing spread: P(burst) with its interval, the worst
    /// corner and the margin, which tolerance matters (Sobol indices), the resonance rule.
    Robust(RobustArgs),
    /// Draw one figure: xdot-gamma, x-equilibrium, transformed-phase, phase-plane, slope, sweep,
    /// map, boundary, frequency-response, orbit-diagram, lyapunov-map.
    Plot(PlotArgs),
    /// Run everything on the study's defaults and write a self-contained HTML report.
    Report(ReportArgs),
    /// A live explorer in the browser: move a parameter, see the curve, the response and the
    /// verdict change (serves until Ctrl-C).
    Serve(ServeArgs),
}

impl Command {
    /// Whether the command may create files, so that Ctrl-C and SIGTERM must be watched (an
    /// interrupted run removes its temporaries and says so). `simulate` without `--out` writes
    /// only to stdout: interrupted, it has nothing to remove and ends as the signal's default
    /// action ends it (status 128 + n in the shell), without the watcher's thread, whose start
    /// is a noticeable share of such a short run. Every other command is watched.
    pub fn writes_files(&self) -> bool {
        match self {
            Command::Simulate(a) => a.out.is_some(),
            _ => true,
        }
    }
}

/// Arguments of `hdgear model`.
#[derive(Args, Debug)]
pub struct ModelArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// Also give the quasi-static loading and unloading branches x±(a) of the steady loop under
    /// a ∈ [−1, 1]: breakaways, steepest points (spiking areas), folds; with --json every point.
    #[arg(long)]
    pub branches: bool,
    /// Print JSON (for programs) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `hdgear serve`.
#[derive(Args, Debug)]
pub struct ServeArgs {
    /// Port (0: any free port; the URL is printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Address to listen on. The default, 127.0.0.1, serves this machine only; 0.0.0.0 exposes
    /// the explorer (and its CPU) to everyone who can reach this machine.
    #[arg(long, default_value = "127.0.0.1", value_name = "ADDR")]
    pub bind: String,
    /// Open the page in the desktop's browser.
    #[arg(long)]
    pub open: bool,
}

/// Arguments of `hdgear report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Output directory (index.html, figures/, data/). Files hdgear did not write there are
    /// never overwritten without --force.
    #[arg(long, default_value = "report", value_name = "DIR")]
    pub out: PathBuf,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Overwrite files in DIR that hdgear did not write.
    #[arg(long)]
    pub force: bool,
}

/// Arguments of `hdgear plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// The figure: xdot-gamma, x-equilibrium, transformed-phase, phase-plane, slope, sweep, map,
    /// boundary, frequency-response, orbit-diagram, lyapunov-map.
    pub kind: String,
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
    /// Output file, .svg or .png.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Worker threads for the sweep and map figures (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Arguments of `hdgear physical`.
#[derive(Args, Debug)]
pub struct PhysicalArgs {
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
    /// Friction at the output bearing, on θo' (with --simulate): LAW:KEY=VALUE,… in SI units,
    /// every key given, LAW friction (fc [N m], vs [rad/s]) or stribeck (fc, fs [N m], vst
    /// [rad/s], cv [N m s/rad], vr [rad/s]); e.g. friction:fc=0.8,vs=1e-3. Replaces the
    /// scenario's [bearings.output] table.
    #[arg(long, value_name = "LAW")]
    pub output_bearing: Option<String>,
    /// Friction at the wave generator, on θi' (with --simulate): LAW:KEY=VALUE,… as
    /// --output-bearing. Replaces the scenario's [bearings.input] table.
    #[arg(long, value_name = "LAW")]
    pub input_bearing: Option<String>,
    /// Friction across the compliance, on the twist rate θ' (with --simulate): LAW:KEY=VALUE,…
    /// as --output-bearing, a torque between the two inertias (the teeth's sliding in mesh).
    #[arg(long, value_name = "LAW")]
    pub twist_friction: Option<String>,
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

impl PhysicalArgs {
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
        use hdgear::physical::model::Bearings;
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
}

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

/// Arguments of `hdgear bursts`.
#[derive(Args, Debug)]
pub struct BurstsArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
    /// Output file, .csv, .json or .parquet (CSV on stdout without it).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Arguments of `hdgear table`.
#[derive(Args, Debug)]
pub struct TableArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
    /// JSON instead of Markdown.
    #[arg(long, conflicts_with = "csv")]
    pub json: bool,
    /// CSV instead of Markdown (the gamma table, a blank line, the effects table).
    #[arg(long)]
    pub csv: bool,
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

/// Arguments of `hdgear sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
    #[command(flatten)]
    pub grid: GridAxes,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output file, .csv, .json or .parquet. Rows stream into FILE.partial as they finish; FILE is written
    /// in grid order at the end.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Continue an interrupted sweep from FILE.partial.
    #[arg(long)]
    pub resume: bool,
    /// Compute only shard K of N (K = 0 … N−1): the grid points i with i mod N = K, written to
    /// DIR/NAME.shard-K-of-N.csv for --out DIR/NAME.EXT. `hdgear merge` joins the shards.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Write SLURM scripts (not submitted): a job array of N shards and a merge job that runs
    /// after them, next to FILE; prints the sbatch command.
    #[arg(long, value_name = "N", conflicts_with_all = ["shard", "resume"])]
    pub slurm: Option<usize>,
    /// SLURM partition of the jobs (with --slurm).
    #[arg(long, requires = "slurm", value_name = "P")]
    pub partition: Option<String>,
    /// SLURM time limit of each shard, e.g. 30:00 or 1-12:00:00 (with --slurm).
    #[arg(long, requires = "slurm", value_name = "T")]
    pub time: Option<String>,
    /// CPUs of each shard, its worker threads (with --slurm; default 1).
    #[arg(long, requires = "slurm", value_name = "C")]
    pub cpus_per_task: Option<usize>,
}

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

/// Arguments of `hdgear continue`.
#[derive(Args, Debug)]
pub struct ContinueArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// NAME=FROM:TO[:log]: follow the orbit in NAME from FROM (the parameter is set to it) to TO,
    /// in ln NAME with :log.
    #[arg(long = "param", value_name = "SPEC", allow_hyphen_values = true)]
    pub range: String,
    /// K: follow the orbit of period K·2π/ω.
    #[arg(long, default_value_t = 1)]
    pub subharmonic: u32,
    /// Also follow the doubled branch from every period doubling found (one level).
    #[arg(long)]
    pub switch: bool,
    /// The branch points (branch,subharmonic,param,x0,xdot0,x_min,x_max,…,special) to a .csv,
    /// .json or .parquet file.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON document (the branches with every point).
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `hdgear frequency-response`.
#[derive(Args, Debug)]
pub struct FrequencyResponseArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// LO:HI, the omega range (default: from 1/20 to 3 times the stiffest static frequency).
    #[arg(long = "omega-range", value_name = "LO:HI")]
    pub omega_range: Option<String>,
    #[command(flatten)]
    pub export: crate::export::Export<hdgear::periodic::BranchRow>,
}

/// Arguments of `hdgear orbit-diagram`.
#[derive(Args, Debug)]
pub struct OrbitDiagramArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// NAME=START:END:COUNT[:log]: the parameter values, swept up then down.
    #[arg(long = "param", value_name = "SPEC", allow_hyphen_values = true)]
    pub axis: String,
    /// Forcing periods discarded at each value.
    #[arg(long, default_value_t = 200)]
    pub discard: u32,
    /// Forcing periods recorded at each value.
    #[arg(long, default_value_t = 32)]
    pub record: u32,
    /// Also the largest Lyapunov exponent at each value, averaged over N forcing periods after
    /// the recorded ones (Benettin).
    #[arg(long, value_name = "N", num_args = 0..=1, default_missing_value = "400")]
    pub lyapunov: Option<u32>,
    /// The section points (sweep,param,period,lyapunov,x,xdot) to a .csv, .json or .parquet file
    /// (CSV on stdout without it).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The figure to a .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// Arguments of `hdgear lyapunov-map`.
#[derive(Args, Debug)]
pub struct LyapunovMapArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub grid: GridAxes,
    /// Forcing periods discarded at each point (from the default start).
    #[arg(long, default_value_t = 200)]
    pub discard: u32,
    /// Forcing periods recorded to find the response's period.
    #[arg(long, default_value_t = 32)]
    pub record: u32,
    /// Forcing periods Benettin's average runs over.
    #[arg(long, default_value_t = 400)]
    pub periods: u32,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// The rows (index,alpha,…,omega,lyapunov,period,error), in grid order, to a .csv, .json or
    /// .parquet file.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// The figure (a map for two axes, a curve for one) to a .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// Arguments of `hdgear merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The shard files (FILE.shard-K-of-N.csv), all N of them, in any order.
    #[arg(required = true, value_name = "SHARD")]
    pub shards: Vec<PathBuf>,
    /// The merged file, .csv, .json or .parquet (default: the shards' name without .shard-K-of-N, .csv).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
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

/// Arguments of `hdgear equilibria`.
#[derive(Args, Debug)]
pub struct EquilibriaArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// Number of curve points (≥ 2), spread uniformly in arc length.
    #[arg(long, default_value_t = 1001)]
    pub points: usize,
    /// Range of the slow variable a, as A0:A1.
    #[arg(long, default_value = "-1:1", allow_hyphen_values = true)]
    pub a_range: String,
    /// Output file, .csv, .json or .parquet (CSV on stdout without it).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Arguments of `hdgear analyze`.
#[derive(Args, Debug)]
pub struct AnalyzeArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// Range of the slow variable a, as A0:A1.
    #[arg(long, default_value = "-1:1", allow_hyphen_values = true)]
    pub a_range: String,
    /// Print one JSON document instead of the readable summary.
    #[arg(long)]
    pub json: bool,
    /// Skip the simulated response and its classification (fast-subsystem analysis only).
    #[arg(long)]
    pub no_response: bool,
    /// Also locate the simulated bursting boundaries in gamma and omega through this point, where
    /// the simulated verdict switches, from the predicted ones (under a second at the study's
    /// point; longer at small omega, which is slow to simulate).
    #[arg(long)]
    pub simulated_boundaries: bool,
    #[command(flatten)]
    pub burst: BurstArgs,
}

/// Arguments of `hdgear bifurcation`.
#[derive(Args, Debug)]
pub struct BifurcationArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// Smallest gamma (must be below the critical 1/(3 alpha)).
    #[arg(long, allow_negative_numbers = true)]
    pub gamma_min: f64,
    /// Number of rows (≥ 2), equally spaced in gamma, the last at the cusp.
    #[arg(long, default_value_t = 200)]
    pub points: usize,
    /// Output file, .csv, .json or .parquet (CSV on stdout without it).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
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

/// Arguments of `hdgear simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub tol: TolArgs,
    /// Duration in slow periods 2π/ω.
    #[arg(
        long,
        default_value_t = 3.0,
        conflicts_with = "t_end",
        allow_negative_numbers = true
    )]
    pub periods: f64,
    /// Duration in dimensionless time (instead of --periods).
    #[arg(long, allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Initial x (default: the stable equilibrium at a = 0).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "from_rest")]
    pub x0: Option<f64>,
    /// Initial x' (default: at rest, 0; with a kinematic error e, −e'(0), the total twist at rest).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "from_rest")]
    pub v0: Option<f64>,
    /// Start at rest at x0 = 0 (x' as --v0's default).
    #[arg(long)]
    pub from_rest: bool,
    /// Output spacing (sampled from dense output).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub dt: f64,
    /// Output file, .csv, .json or .parquet (CSV on stdout without it).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON summary object to stdout instead of the trajectory.
    #[arg(long)]
    pub summary: bool,
}

/// `hdgear simulate`, checked.
pub struct SimulateRun {
    pub params: Params,
    /// The assembled model when the scenario adds terms to the study's (`[friction]`, …).
    pub model: Option<hdgear::model::Model>,
    pub warnings: Vec<Warning>,
    pub opts: SimOptions,
    pub out: Option<PathBuf>,
    pub summary: bool,
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

fn check_positive(name: &str, v: f64) -> Result<f64> {
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

fn check_finite(name: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        anyhow::bail!("invalid option --{name} = {v:?}: must be finite")
    }
}

impl SimulateArgs {
    /// Checks every value and resolves the parameters.
    pub fn check(&self) -> Result<SimulateRun> {
        let (params, model, warnings) = self.params.resolve_model()?;
        let model = model.has_extra_terms().then_some(model);
        let tol = self.tol.options()?;
        let t_end = match self.t_end {
            Some(t) => check_positive("t-end", t)?,
            None => check_positive("periods", self.periods)? * params.slow_period(),
        };
        let mut dt = check_positive("dt", self.dt)?;
        if self.summary {
            // no rows are written: no output grid to fill
            dt = t_end;
        } else {
            check_rows(t_end / dt)?;
        }
        let start = if self.from_rest {
            Start::Rest
        } else {
            match (self.x0, self.v0) {
                (None, None) => Start::Equilibrium,
                (x0, v0) => {
                    let x0 = match x0 {
                        Some(x) => check_finite("x0", x)?,
                        None => match &model {
                            Some(m) => m.stable_equilibrium(0.0)?,
                            None => hdgear::fast::stable_equilibrium(&params, 0.0),
                        },
                    };
                    let rest = model.as_ref().map_or(0.0, |m| m.rest_rate());
                    let v0 = check_finite("v0", v0.unwrap_or(rest))?;
                    Start::Given { x0, v0 }
                }
            }
        };
        check_out(&self.out)?;
        Ok(SimulateRun {
            params,
            model,
            warnings,
            opts: SimOptions {
                t_end,
                dt,
                start,
                tol,
            },
            out: self.out.clone(),
            summary: self.summary,
        })
    }
}
