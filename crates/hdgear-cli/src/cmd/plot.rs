//! `hdgear plot`: one figure.

use crate::sink::warn;
use anyhow::Result;

use crate::args::BurstArgs;
use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

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

pub fn run(a: PlotArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    let kind: hdgear::figures::FigureKind = a.kind.parse()?;
    crate::args::check_figure_path("--out", &a.out)?;
    // figures that vary a parameter themselves would silently ignore its flag
    for param in kind.varies() {
        if a.params.given(*param) {
            anyhow::bail!(
                "--{param} does not apply to plot {kind}: the figure varies {param} itself"
            );
        }
    }
    let threads = crate::args::threads(a.threads)?;
    warn(&warnings);
    let f = hdgear::figures::by_kind(kind, &p, &opts, threads)?;
    hdgear::output::plot::write(&f, &a.out)?;
    Ok(())
}
