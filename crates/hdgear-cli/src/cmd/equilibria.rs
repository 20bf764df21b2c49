//! `hdgear equilibria`: the equilibrium curve, sampled.

use crate::args::{check_out, parse_range};
use crate::sink::{warn, warn_range, write_records};
use anyhow::Result;
use hdgear::fast::StaticCurve;
use hdgear::model::AnyCurve;
use hdgear::model::Subject;

use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

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

pub fn run(a: EquilibriaArgs) -> Result<()> {
    let (system, warnings) = a.params.resolve_system()?;
    let range = parse_range(&a.a_range)?;
    check_out(&a.out)?;
    crate::args::check_points(a.points)?;
    warn(&warnings);
    warn_range(range);
    match system {
        Subject::Study(p) => write(&p, p, range, &a),
        Subject::Model(m) => match AnyCurve::of(&m)? {
            AnyCurve::Torque(c) => write(&c, m, range, &a),
            AnyCurve::Scheduled(c) => write(&c, m, range, &a),
        },
    }
}

/// Samples `c` and writes the curve with `params` as its metadata.
fn write<C: StaticCurve, P: serde::Serialize>(
    c: &C,
    params: P,
    range: (f64, f64),
    a: &EquilibriaArgs,
) -> Result<()> {
    let curve = hdgear::fast::curve(c, range, a.points)?;
    let meta = hdgear::fast::CurveSetup {
        params,
        a_range: range,
    };
    write_records(a.out.as_deref(), &meta, curve)
}
