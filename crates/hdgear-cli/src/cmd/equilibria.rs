//! `hdgear equilibria`: the equilibrium curve, sampled.

use crate::args::{check_out, parse_range};
use crate::sink::{warn, warn_range, write_records};
use crate::sources::System;
use anyhow::Result;
use hdgear::fast::StaticCurve;
use hdgear::model::{Model, ModelCurve};

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
        System::Study(p) => write(&p, p, range, &a),
        System::Model(m) => match curve_of(&m)? {
            Curve::Torque(c) => write(&c, m, range, &a),
            Curve::Scheduled(c) => write(&c, m, range, &a),
        },
    }
}

/// The equilibrium curve of a model's fast subsystem, at the model's own damping at rest: its
/// static torque's, or the closed loop's of a scheduled stiffness
/// ([`hdgear::model::ModelCurve`]; refused as it says).
pub fn curve_of(m: &Model) -> Result<Curve> {
    Ok(if m.is_scheduled() {
        Curve::Scheduled(ModelCurve::scheduled(m)?)
    } else {
        Curve::Torque(ModelCurve::new(m)?)
    })
}

/// A model's equilibrium curve, of either kind.
pub enum Curve {
    /// Its static torque's.
    Torque(ModelCurve),
    /// The closed loop's of a scheduled stiffness.
    Scheduled(ModelCurve<hdgear::model::ScheduledTorque>),
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
