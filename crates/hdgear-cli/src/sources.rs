//! The model's sources shared by every dimensionless command: preset, then scenario file, then
//! flags; the study's parameter set, or the model assembled from the file's term tables.

use anyhow::Result;
use clap::Args;
use hdgear::params::{self, ParamOverrides, Params, Warning};
use hdgear::scenario::Scenario;
use std::path::PathBuf;

/// The parameter set, the scenario file read (if any) with its path, and the set's warnings.
type Sources<'a> = (Params, Option<(&'a PathBuf, Scenario)>, Vec<Warning>);

/// Model parameters shared by every command: preset, then file, then flags.
#[derive(Args, Debug, Clone)]
pub struct ParamArgs {
    /// Named parameter set: paper (= paper-g0.1), paper-g30, paper-g10, paper-g1, paper-g0.1.
    #[arg(long, default_value = "paper")]
    pub preset: String,
    #[arg(long, value_name = "FILE", help = config_help())]
    pub config: Option<PathBuf>,
    /// α > 0, cubic stiffness.
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// γ, linear stiffness.
    #[arg(long, allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// ε, backlash offset.
    #[arg(long, allow_negative_numbers = true)]
    pub eps: Option<f64>,
    /// μ, mean load.
    #[arg(long, allow_negative_numbers = true)]
    pub mu: Option<f64>,
    /// δ ≥ 0, amplitude of the slow disturbance.
    #[arg(long, allow_negative_numbers = true)]
    pub delta: Option<f64>,
    /// ω > 0, frequency of the slow disturbance.
    #[arg(long, allow_negative_numbers = true)]
    pub omega: Option<f64>,
}

/// `--config`'s help: the keys of `[params]` and the tables of the extra terms, read from the
/// library's lists.
fn config_help() -> String {
    let keys: Vec<&str> = params::Param::ALL.iter().map(|q| q.name()).collect();
    let tables: Vec<String> = hdgear::model::terms::AnyTerm::KINDS
        .iter()
        .filter(|(kind, ..)| hdgear::model::Model::is_extra_kind(kind))
        .map(|(kind, ..)| format!("[{kind}]"))
        .collect();
    format!(
        "TOML scenario file: a [params] table (keys {}) and, for model and simulate, a table per \
         extra term ({})",
        keys.join(", "),
        tables.join(", ")
    )
}

impl ParamArgs {
    /// Whether the flag of parameter `name` was given.
    pub fn given(&self, name: &str) -> bool {
        match name {
            "alpha" => self.alpha.is_some(),
            "gamma" => self.gamma.is_some(),
            "eps" => self.eps.is_some(),
            "mu" => self.mu.is_some(),
            "delta" => self.delta.is_some(),
            "omega" => self.omega.is_some(),
            _ => false,
        }
    }

    /// The parameter set these sources give, validated, with its warnings. A scenario file with
    /// tables of extra terms is refused: this command runs the study's model.
    pub fn resolve(&self) -> Result<(Params, Vec<Warning>)> {
        let (p, scenario, warnings) = self.sources()?;
        if let Some((path, s)) = &scenario
            && let Some(name) = s.terms.keys().next()
        {
            anyhow::bail!(
                "scenario file {}: its [{name}] table is a term of the model, which only hdgear \
                 model and hdgear simulate read (this command runs the study's model)",
                path.display()
            );
        }
        Ok((p, warnings))
    }

    /// The model these sources give: the study's with the parameter set, and a term for each of
    /// the scenario file's term tables (`[friction]`, …), checked.
    pub fn resolve_model(&self) -> Result<(Params, hdgear::model::Model, Vec<Warning>)> {
        let (p, scenario, warnings) = self.sources()?;
        let model = match &scenario {
            Some((path, s)) => s.model(&p, path)?,
            None => hdgear::model::Model::study(&p),
        };
        Ok((p, model, warnings))
    }

    /// The parameter set and the scenario file it read, if any.
    fn sources(&self) -> Result<Sources<'_>> {
        let file = match &self.config {
            Some(path) => {
                let s = Scenario::load(path)?;
                if s.params.is_none() && !s.has_terms() {
                    anyhow::bail!(
                        "scenario file {} has no [params] table{}",
                        path.display(),
                        if s.physical.is_some() {
                            " (its [physical] table is for hdgear physical)"
                        } else {
                            ""
                        }
                    );
                }
                Some((path, s))
            }
            None => None,
        };
        let flags = ParamOverrides {
            alpha: self.alpha,
            gamma: self.gamma,
            eps: self.eps,
            mu: self.mu,
            delta: self.delta,
            omega: self.omega,
        };
        let (p, warnings) = params::resolve(
            &self.preset,
            file.as_ref().and_then(|(_, s)| s.params.as_ref()),
            &flags,
        )?;
        Ok((p, file, warnings))
    }
}
