//! The command's integration tests, one binary (ripgrep style): one module per capability. The
//! library tests itself in `crates/hdgear/tests/`.

mod common;

mod bearings;
mod cards;
mod cli;
mod control;
mod docs;
mod edges;
mod fit;
mod fmu;
mod hardening;
mod hostile;
mod interrupted;
mod model;
mod model_report;
mod output;
mod periodic;
mod pipes;
mod report;
mod robust;
mod serve;
mod shard;
