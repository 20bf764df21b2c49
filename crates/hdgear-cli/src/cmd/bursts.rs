//! `hdgear bursts`: one burst per row.

use crate::args::check_out;
use crate::sink::{warn, write_records};
use anyhow::Result;

use crate::args::BurstArgs;
use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

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

pub fn run(a: BurstsArgs) -> Result<()> {
    let (p, model, warnings) = a.params.resolve_model()?;
    let opts = a.burst.options()?;
    check_out(&a.out)?;
    warn(&warnings);
    // a scenario's terms: the model's verdict, against its equivalent parameter set's curve or,
    // where its static torque is no study cubic, its own
    let (r, meta) = if model.has_extra_terms() {
        let r = hdgear::burst::response_model(&model, &opts)?;
        let c = hdgear::burst::classify_model(&model, &r)?;
        let p = model.equivalent_params().unwrap_or(p);
        let meta = hdgear::burst::BurstsSetup::classified(&p, &opts, &r, c);
        (r, meta)
    } else {
        let r = hdgear::burst::response(&p, &opts)?;
        let meta = hdgear::burst::BurstsSetup::new(&p, &opts, &r);
        (r, meta)
    };
    crate::sink::tolerance_note(&r, &opts.tol);
    write_records(a.out.as_deref(), &meta, r.bursts)
}
