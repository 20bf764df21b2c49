//! The one integration-test binary (ripgrep style): one module per capability.

mod common;

mod burst;
mod cli;
mod fast;
mod hardening;
mod integrate;
mod output;
mod periodic;
mod physical;
mod reference;
mod report;
mod serve;
mod shard;
