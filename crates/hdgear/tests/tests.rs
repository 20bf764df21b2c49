//! The library's integration tests, one binary (ripgrep style): one module per capability.
//! Everything they read is in this crate (`tests/data/`), so `cargo test` needs nothing beside
//! the checkout.

mod common;

mod bearings;
mod branches;
mod burst;
mod card_curve_law;
mod card_friction;
mod cards;
mod control;
mod cosim;
mod delay;
mod den_hartog;
mod dither;
mod domain;
mod dop853_terms;
mod fast;
mod fit;
mod friction;
mod friction_reference;
mod house;
mod integrate;
mod kinematic;
mod law;
mod memory;
mod mesh_loss;
mod model;
mod model_batch;
mod normal_form;
mod one_model;
mod output;
mod periodic;
mod physical;
mod piecewise;
mod plane;
mod reference;
mod relations;
mod robust;
mod robust_model;
mod schedule;
mod simd;
mod static_curve;
mod stick_slip;
mod sweep_model;
mod switching_batch;
mod two_parameter;
