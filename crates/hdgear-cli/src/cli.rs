//! The command line: the list of commands, each naming its argument struct in `cmd/<name>.rs`.

use clap::{Parser, Subcommand};

use crate::cmd::card::CardArgs;
use crate::cmd::control::ControlArgs;
use crate::cmd::robust::RobustArgs;

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
    Simulate(crate::cmd::simulate::SimulateArgs),
    /// The assembled model: its equation (text and LaTeX), states, parameters with values and
    /// domains, and the facts of its fast subsystem derived from its terms.
    Model(crate::cmd::model::ModelArgs),
    /// Sample the fast subsystem's equilibrium curve (a,x,slope,gprime,re1,im1,re2,im2,type,branch).
    Equilibria(crate::cmd::equilibria::EquilibriaArgs),
    /// Analyse the fast subsystem: folds, cusp, steepest point, Hopf, spiking areas.
    Analyze(crate::cmd::analyze::AnalyzeArgs),
    /// The fold curves in the (a, gamma) plane up to the cusp (gamma,a_lower,x_lower,a_upper,x_upper).
    Bifurcation(crate::cmd::bifurcation::BifurcationArgs),
    /// Detect the bursts of a response and list them one per row.
    Bursts(crate::cmd::bursts::BurstsArgs),
    /// The study's gamma table and parameter-effects table with measured numbers.
    Table(crate::cmd::table::TableArgs),
    /// Sweep one or two parameters over a grid in parallel (resumable, shardable).
    Sweep(crate::cmd::sweep::SweepArgs),
    /// The periodic response: the orbit by shooting, its Floquet multipliers, the Lyapunov exponent.
    Periodic(crate::cmd::periodic::PeriodicArgs),
    /// Follow the periodic orbit in a parameter (pseudo-arclength): folds, period doublings,
    /// the doubled branches.
    Continue(crate::cmd::continuation::ContinueArgs),
    /// Curves of folds or period doublings in two parameters (two-parameter continuation),
    /// with their cusps and generalised period doublings.
    Continue2(crate::cmd::two_parameter::Continue2Args),
    /// Boundaries in two parameters as curves: the bursting boundary (predicted and simulated),
    /// the fold set of the fast subsystem, the edge of the fast-slow domain.
    Boundary(crate::cmd::boundary::BoundaryArgs),
    /// The frequency-response curve: response amplitude against omega, stable and unstable
    /// branches, folds (the jumps).
    FrequencyResponse(crate::cmd::frequency::FrequencyResponseArgs),
    /// The stroboscopic orbit diagram against a parameter, swept up and down (hysteresis), with
    /// the largest Lyapunov exponent on request.
    OrbitDiagram(crate::cmd::diagram::OrbitDiagramArgs),
    /// The largest Lyapunov exponent over a grid of one or two parameters (a sweep or a map).
    LyapunovMap(crate::cmd::lyapunov::LyapunovMapArgs),
    /// Join the shard files of a sweep into the file one machine would have written.
    Merge(crate::cmd::merge::MergeArgs),
    /// A physical drive in SI units: reduction, two-inertia simulation, design check.
    Physical(Box<crate::cmd::physical::PhysicalArgs>),
    /// A drive for another tool: an FMI 2.0 co-simulation FMU of the two-inertia model.
    Export(crate::cmd::fmu::ExportArgs),
    /// Fit a law's parameters to measured data (a friction sweep or a torque–twist loop): the
    /// estimates with 95 % intervals (JᵀJ and profile likelihood), correlations, the
    /// combinations the data do not determine, the residual plot, a fitted card.
    Fit(Box<crate::cmd::fit::FitArgs>),
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
    Plot(crate::cmd::plot::PlotArgs),
    /// Run everything on the study's defaults and write a self-contained HTML report.
    Report(crate::cmd::report::ReportArgs),
    /// A live explorer in the browser: move a parameter, see the curve, the response and the
    /// verdict change (serves until Ctrl-C).
    Serve(crate::cmd::serve::ServeArgs),
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
