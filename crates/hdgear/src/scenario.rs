//! Scenario files: one TOML file that can describe both a dimensionless parameter set
//! (`[params]`) and a physical drive (`[physical]`). It sits above [`crate::params`] and
//! [`crate::physical`], which know nothing of files.

use crate::error::{Error, Result};
use crate::params::ParamOverrides;
use crate::physical::PhysicalOverrides;
use serde::Deserialize;
use std::path::Path;

/// A scenario file. Tables: `[params]` (dimensionless) and `[physical]` (a drive in SI units; read
/// by the physical-model commands). Unknown tables or keys are errors that name them.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Dimensionless parameters (the `[params]` table), if the file has one.
    #[serde(default)]
    pub params: Option<ParamOverrides>,
    /// Physical drive parameters in SI units (the `[physical]` table), if the file has one.
    #[serde(default)]
    pub physical: Option<PhysicalOverrides>,
}

impl Scenario {
    /// Parses a scenario from TOML text; `path` is used in error messages.
    pub fn parse(text: &str, path: &Path) -> Result<Scenario> {
        toml::from_str(text).map_err(|e| Error::Config {
            path: path.to_path_buf(),
            message: e.message().to_string()
                + &e.span()
                    .map(|s| {
                        let line = text[..s.start].matches('\n').count() + 1;
                        format!(" (line {line})")
                    })
                    .unwrap_or_default(),
        })
    }

    /// Reads and parses a scenario file (at most [`SCENARIO_MAX_BYTES`]).
    pub fn load(path: &Path) -> Result<Scenario> {
        use std::io::Read;
        let err = |message: String| Error::Config {
            path: path.to_path_buf(),
            message,
        };
        let file = crate::output::open_input(path).map_err(|e| err(e.to_string()))?;
        let mut bytes = Vec::new();
        file.take(SCENARIO_MAX_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| err(e.to_string()))?;
        if bytes.len() as u64 > SCENARIO_MAX_BYTES {
            return Err(err(format!(
                "larger than {SCENARIO_MAX_BYTES} bytes: not a scenario file"
            )));
        }
        let text = String::from_utf8(bytes).map_err(|_| err("not UTF-8 text".into()))?;
        Scenario::parse(&text, path)
    }
}

/// The largest scenario file read (a scenario is a few lines; this only stops `/dev/zero`).
pub const SCENARIO_MAX_BYTES: u64 = 1 << 20;
