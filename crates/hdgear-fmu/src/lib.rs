//! The shared library inside a drive's FMU (FMI 2.0, co-simulation): every `fmi2*` function
//! the standard requires, around [`hdgear::physical::fmu::Instance`], which holds the state
//! machine, the variables and the drive. The drive itself comes from the FMU's
//! `resources/drive.json` ([`hdgear::physical::fmu::Resources`]), so one library serves every
//! card. `hdgear export fmu` packs it.
//!
//! The one module with code outside safe Rust is [`ffi`], each such block with its reason.

pub mod ffi;
