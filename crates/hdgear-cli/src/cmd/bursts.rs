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
    crate::sink::tolerance_note(&r, &opts.tol);
    let meta = hdgear::burst::BurstsSetup::new(&p, &opts, &r);
    write_records(a.out.as_deref(), &meta, r.bursts)
}
