//! `hdgear equilibria`: the equilibrium curve, sampled.

use crate::cli::{EquilibriaArgs, check_out, parse_range};
use crate::sink::{warn, warn_range, write_records};
use anyhow::Result;

pub fn run(a: EquilibriaArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let range = parse_range(&a.a_range)?;
    check_out(&a.out)?;
    crate::cli::check_points(a.points)?;
    warn(&warnings);
    warn_range(range);
    let curve = hdgear::fast::curve(&p, range, a.points)?;
    let meta = hdgear::fast::CurveSetup {
        params: p,
        a_range: range,
    };
    write_records(a.out.as_deref(), &meta, curve)
}
