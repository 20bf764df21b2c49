//! `hdgear bifurcation`: the fold curves up to the cusp.

use crate::args::check_out;
use crate::sink::{warn, write_records};
use anyhow::Result;
use hdgear::params::Param;

use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

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

pub fn run(a: BifurcationArgs) -> Result<()> {
    let gamma = Param::Gamma;
    if a.params.given(gamma) {
        anyhow::bail!(
            "--{gamma} does not apply to bifurcation: it varies {gamma} from --gamma-min to the cusp"
        );
    }
    let (p, warnings) = a.params.resolve()?;
    check_out(&a.out)?;
    crate::args::check_points(a.points)?;
    warn(&warnings);
    let rows = hdgear::fast::fold_curves(&p, a.gamma_min, a.points)?;
    let meta = hdgear::fast::FoldCurvesSetup {
        params: p,
        cusp: hdgear::fast::cusp(&p),
    };
    write_records(a.out.as_deref(), &meta, rows)
}
