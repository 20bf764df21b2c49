//! `hdgear table`: the study's two tables, measured.

use crate::cli::TableArgs;
use crate::sink::warn;
use anyhow::Result;

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
