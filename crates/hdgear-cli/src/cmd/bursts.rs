//! `hdgear bursts`: one burst per row.

use crate::cli::{BurstsArgs, check_out};
use crate::sink::{warn, write_records};
use anyhow::Result;

pub fn run(a: BurstsArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    check_out(&a.out)?;
    warn(&warnings);
    let r = hdgear::burst::response(&p, &opts)?;
    let c = hdgear::burst::classify(&p, &r);
    let meta = serde_json::json!({
        "params": p,
        "options": opts,
        "classification": c,
        "bursts_per_period": r.bursts_per_period,
        "window": [r.window_start, r.window_end],
    });
    write_records(a.out.as_deref(), &meta, r.bursts)
}
