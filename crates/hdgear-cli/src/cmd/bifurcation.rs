//! `hdgear bifurcation`: the fold curves up to the cusp.

use crate::cli::{BifurcationArgs, check_out};
use crate::sink::{warn, write_records};
use anyhow::Result;
use hdgear::params::Param;

pub fn run(a: BifurcationArgs) -> Result<()> {
    let gamma = Param::Gamma;
    if a.params.given(gamma) {
        anyhow::bail!(
            "--{gamma} does not apply to bifurcation: it varies {gamma} from --gamma-min to the cusp"
        );
    }
    let (p, warnings) = a.params.resolve()?;
    check_out(&a.out)?;
    crate::cli::check_points(a.points)?;
    warn(&warnings);
    let rows = hdgear::fast::fold_curves(&p, a.gamma_min, a.points)?;
    let meta = hdgear::fast::FoldCurvesSetup {
        params: p,
        cusp: hdgear::fast::cusp(&p),
    };
    write_records(a.out.as_deref(), &meta, rows)
}
