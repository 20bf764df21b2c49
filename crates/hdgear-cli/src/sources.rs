//! The model's sources shared by every dimensionless command: preset, then scenario file, then
//! flags; the study's parameter set, or the model assembled from the file's term tables.

use anyhow::Result;
use clap::Args;
use hdgear::model::Subject;
use hdgear::model::terms::Domain;
use hdgear::params::{self, Param, ParamOverrides, Params, Warning};
use hdgear::scenario::Scenario;
use std::path::PathBuf;

/// The parameter set, the scenario file read (if any) with its path, and the set's warnings.
type Sources<'a> = (Params, Option<(&'a PathBuf, Scenario)>, Vec<Warning>);

/// Model parameters shared by every command: preset, then file, then flags.
#[derive(Args, Debug, Clone)]
pub struct ParamArgs {
    #[arg(long, default_value = ParamArgs::DEFAULT_PRESET, help = preset_help())]
    pub preset: String,
    #[arg(long, value_name = "FILE", help = config_help())]
    pub config: Option<PathBuf>,
    /// One flag per parameter of the study (`--alpha`, …), from the library's list.
    #[command(flatten)]
    pub values: ParamFlags,
}

/// The flags `--alpha`, `--gamma`, … of the study's parameters, one per [`Param`], each with
/// its symbol, domain and meaning from the library's definition ([`hdgear::model::study_param`]).
#[derive(Debug, Clone, Default)]
pub struct ParamFlags(pub ParamOverrides);

impl clap::FromArgMatches for ParamFlags {
    fn from_arg_matches(m: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut o = ParamOverrides::default();
        for q in Param::ALL {
            if let Some(&v) = m.get_one::<f64>(q.name()) {
                o.set(q, v);
            }
        }
        Ok(ParamFlags(o))
    }

    fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

/// What `--card` conflicts with: the preset, the scenario file and every parameter flag.
pub const NOT_WITH_CARD: [&str; 2 + Param::ALL.len()] = {
    let mut names = ["preset", "config", "", "", "", "", "", ""];
    let mut i = 0;
    while i < Param::ALL.len() {
        names[2 + i] = Param::ALL[i].name();
        i += 1;
    }
    names
};

impl Args for ParamFlags {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        Param::ALL.iter().fold(cmd, |cmd, &q| {
            let info = hdgear::model::study_param(q);
            let domain = match info.domain {
                Domain::Any => String::new(),
                rule => format!(" {}", rule.text()),
            };
            cmd.arg(
                clap::Arg::new(q.name())
                    .long(q.name())
                    .value_name(q.name().to_uppercase())
                    .allow_negative_numbers(true)
                    .value_parser(clap::value_parser!(f64))
                    .help(format!("{}{domain}, {}", info.symbol, info.meaning)),
            )
        })
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

/// The commands that run the model a scenario's term tables assemble (the others refuse them).
const MODEL_COMMANDS: &str = "model, simulate, bursts, analyze, equilibria, periodic, continue, \
     frequency-response, orbit-diagram, control, sweep, lyapunov-map, continue2, robust, boundary, \
     report";

/// `--preset`'s help: the library's presets, a name that repeats another's set marked so.
fn preset_help() -> String {
    let names: Vec<String> = params::PRESETS
        .iter()
        .enumerate()
        .map(
            |(i, (name, gamma))| match params::PRESETS[i + 1..].iter().find(|(_, g)| g == gamma) {
                Some((same, _)) => format!("{name} (= {same})"),
                None => name.to_string(),
            },
        )
        .collect();
    format!("Named parameter set: {}", names.join(", "))
}

/// `--config`'s help: the keys of `[params]` and the tables of the extra terms, read from the
/// library's lists.
fn config_help() -> String {
    let keys: Vec<&str> = Param::ALL.iter().map(|q| q.name()).collect();
    let tables: Vec<String> = hdgear::scenario::extra_kinds()
        .map(|kind| format!("[{kind}]"))
        .collect();
    format!(
        "TOML scenario file: a [params] table (keys {}) and, for {MODEL_COMMANDS}, a table per \
         extra term ({})",
        keys.join(", "),
        tables.join(", ")
    )
}

impl ParamArgs {
    /// The preset taken without `--preset`: the study's set.
    pub const DEFAULT_PRESET: &'static str = "paper";

    /// Whether the flag of parameter `param` was given.
    pub fn given(&self, param: Param) -> bool {
        self.values.0.get(param).is_some()
    }

    /// Refuses the flag of the parameter called `name` (a study parameter's; a model's own have
    /// no flag) when it was given: `what` names the option that sets it instead.
    pub fn not_given(&self, name: &str, what: &str) -> Result<()> {
        if name.parse().is_ok_and(|q| self.given(q)) {
            anyhow::bail!("--{name} does not apply: {what} {name} itself");
        }
        Ok(())
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
                 {MODEL_COMMANDS} read (this command runs the study's model)",
                path.display()
            );
        }
        Ok((p, warnings))
    }

    /// The model these sources give: the study's with the parameter set, and a term for each of
    /// the scenario file's term tables (`[friction]`, …), checked.
    pub fn resolve_model(&self) -> Result<(Params, hdgear::model::Model, Vec<Warning>)> {
        let (p, scenario, mut warnings) = self.sources()?;
        let model = match &scenario {
            Some((path, s)) => s.model(&p, path)?,
            None => hdgear::model::Model::study(&p),
        };
        if model.study_set().is_none() {
            // a [spring] table replaced the study's stiffness: its α, γ, ε are not the model's
            for q in [Param::Alpha, Param::Gamma, Param::Eps] {
                if self.given(q) {
                    anyhow::bail!(
                        "--{q} does not apply: the scenario's [spring] table is the model's \
                         stiffness, in place of the study's"
                    );
                }
            }
            warnings.retain(|w| !matches!(w, Warning::AlphaEpsNotOne { .. }));
        }
        Ok((p, model, warnings))
    }

    /// What these sources give to run on ([`Subject`]): the study's set where the assembled
    /// model is the study's, else the model.
    pub fn resolve_system(&self) -> Result<(Subject, Vec<Warning>)> {
        let (_, model, warnings) = self.resolve_model()?;
        Ok((model.subject(), warnings))
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
        let (p, warnings) = params::resolve(
            &self.preset,
            file.as_ref().and_then(|(_, s)| s.params.as_ref()),
            &self.values.0,
        )?;
        Ok((p, file, warnings))
    }
}
