//! The native part of the `hdgear` Python package (`hdgear._hdgear`). The Python layer
//! (`python/hdgear/__init__.py`) gives it its documented API; this module turns Python values
//! into the library's checked types, runs the library with the GIL released, and hands back numpy
//! arrays (columns of numbers) or Python objects (dicts and lists of nested results).
//!
//! One module per part of the library: [`params`], [`model`], [`simulate`], [`fast`], [`sweep`],
//! [`drive`], [`periodic`], [`control`], [`robust`]; what they share (errors, conversions, limits, Ctrl-C) in [`convert`].
//!
//! Errors: the library's input errors become `ValueError` with the CLI's message; a failed
//! integration (step-size underflow, blow-up, step budget) a `RuntimeError`; Ctrl-C during a
//! sweep a `KeyboardInterrupt`.

#![forbid(unsafe_code)]

mod control;
mod convert;
mod drive;
mod fast;
mod fit;
mod model;
mod params;
mod periodic;
mod robust;
mod simulate;
mod sweep;

use pyo3::prelude::*;

/// The native module.
#[pymodule]
fn _hdgear(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<params::Params>()?;
    m.add_class::<model::Model>()?;
    m.add_class::<drive::Drive>()?;
    m.add_class::<drive::Bearing>()?;
    for f in [
        wrap_pyfunction!(simulate::simulate, m)?,
        wrap_pyfunction!(simulate::time_simulate_in_rust, m)?,
        wrap_pyfunction!(fast::equilibria, m)?,
        wrap_pyfunction!(fast::curve, m)?,
        wrap_pyfunction!(fast::branches, m)?,
        wrap_pyfunction!(fit::fit, m)?,
        wrap_pyfunction!(fast::analyze, m)?,
        wrap_pyfunction!(sweep::sweep, m)?,
        wrap_pyfunction!(sweep::bursts, m)?,
        wrap_pyfunction!(periodic::periodic, m)?,
        wrap_pyfunction!(periodic::continuation, m)?,
        wrap_pyfunction!(periodic::continuation2, m)?,
        wrap_pyfunction!(periodic::boundary, m)?,
        wrap_pyfunction!(control::control, m)?,
        wrap_pyfunction!(robust::robust, m)?,
    ] {
        m.add_function(f)?;
    }
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
