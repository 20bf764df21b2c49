//! `hdgear table`: the study's two tables, measured.

use crate::sink::warn;
use anyhow::Result;

use crate::args::BurstArgs;
use crate::sources::ParamArgs;
use clap::Args;

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

pub fn run(a: TableArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    warn(&warnings);
    let t = hdgear::table::tables(&p, &opts)?;
    let text = if a.json {
        serde_json::to_string_pretty(&t)? + "\n"
    } else if a.csv {
        hdgear::table::render::csv(&t)?
    } else {
        hdgear::table::render::markdown(&t)
    };
    crate::sink::out!("{text}");
    Ok(())
}
