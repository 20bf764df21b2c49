//! `hdgear plot`: one figure.

use crate::sink::warn;
use anyhow::Result;

pub fn run(a: crate::cli::PlotArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    let kind: hdgear::figures::FigureKind = a.kind.parse()?;
    crate::cli::check_figure_path("--out", &a.out)?;
    // figures that vary a parameter themselves would silently ignore its flag
    for param in kind.varies() {
        if a.params.given(*param) {
            anyhow::bail!(
                "--{param} does not apply to plot {kind}: the figure varies {param} itself"
            );
        }
    }
    let threads = crate::cli::threads(a.threads)?;
    warn(&warnings);
    let f = hdgear::figures::by_kind(kind, &p, &opts, threads)?;
    hdgear::output::plot::write(&f, &a.out)?;
    Ok(())
}
