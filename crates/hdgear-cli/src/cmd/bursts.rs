//! `hdgear bursts`: one burst per row.

use crate::cli::{BurstsArgs, check_out};
use crate::sink::{warn, write_records};
use anyhow::Result;

pub fn run(a: BurstsArgs) -> Result<()> {
    let (p, model, warnings) = a.params.resolve_model()?;
    let opts = a.burst.options()?;
    check_out(&a.out)?;
    warn(&warnings);
    // a scenario's terms: the model's verdict, against its equivalent parameter set's curve
    let (p, r) = if model.has_extra_terms() {
        let r = hdgear::burst::response_model(&model, &opts)?;
        let p = model
            .equivalent_params()
            .expect("response_model checked it");
        (p, r)
    } else {
        (p, hdgear::burst::response(&p, &opts)?)
    };
    crate::sink::tolerance_note(&r, &opts.tol);
    let meta = hdgear::burst::BurstsSetup::new(&p, &opts, &r);
    write_records(a.out.as_deref(), &meta, r.bursts)
}
