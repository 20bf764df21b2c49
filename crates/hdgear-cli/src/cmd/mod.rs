//! One module per command, each turning its checked settings into a run and its export
//! (ripgrep/hyperfine style: arguments → checked settings → run → export).

pub mod analyze;
pub mod bifurcation;
pub mod boundary;
pub mod bursts;
pub mod card;
pub mod continuation;
pub mod control;
pub mod diagram;
pub mod equilibria;
pub mod fit;
pub mod fmu;
pub mod frequency;
pub mod lyapunov;
pub mod merge;
pub mod model;
pub mod periodic;
pub mod physical;
pub mod plot;
pub mod report;
pub mod robust;
pub mod serve;
pub mod simulate;
pub mod sweep;
pub mod table;
pub mod two_parameter;

use crate::cli::{Cli, Command};
use anyhow::Result;

/// Dispatches a parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Simulate(a) => simulate::run(a.check()?),
        Command::Model(a) => model::run(a),
        Command::Equilibria(a) => equilibria::run(a),
        Command::Analyze(a) => analyze::run(a),
        Command::Bifurcation(a) => bifurcation::run(a),
        Command::Bursts(a) => bursts::run(a),
        Command::Table(a) => table::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Merge(a) => merge::run(a),
        Command::Continue(a) => continuation::run(a),
        Command::Continue2(a) => two_parameter::run(a),
        Command::Boundary(a) => boundary::run(a),
        Command::FrequencyResponse(a) => frequency::run(a),
        Command::OrbitDiagram(a) => diagram::run(a),
        Command::LyapunovMap(a) => lyapunov::run(a),
        Command::Periodic(a) => periodic::run(a),
        Command::Physical(a) => physical::run(*a),
        Command::Export(a) => fmu::run(a),
        Command::Fit(a) => fit::run(*a),
        Command::Card(a) => card::run(a),
        Command::Control(a) => control::run(a),
        Command::Robust(a) => robust::run(a),
        Command::Plot(a) => plot::run(a),
        Command::Report(a) => report::run(a),
        Command::Serve(a) => serve::run(a),
    }
}
