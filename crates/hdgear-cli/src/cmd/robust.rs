//! `hdgear robust` (and `hdgear physical --robust`): the design check under manufacturing
//! spread, P(burst) with its interval, the worst corner and margin, the Sobol indices, the
//! catalogue's resonance rule; the samples streamed to a file.
//!
//! **Why one file.** A command owns its arguments, checks and output in its own file; `robust`
//! prints five analyses (probability, worst case, importance, Sobol indices, the catalogue's
//! resonance rule) from one run.

use crate::args::{BurstArgs, check_out};
use crate::cmd::card::Loaded;
use crate::sink::{Sink, out, warn};
use crate::sources::ParamArgs;
use anyhow::{Context, Result, bail};
use clap::Args;
use hdgear::model::Subject;
use hdgear::output::RecordWriter;
use hdgear::robust::{
    APPLICATIONS, AnalysisOptions, McOptions, Measure, ModelSampleRow, Nominal, RobustAnalysis,
    Sample, SampleRow, Sampler, Space, analyse,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The options of the analysis, shared by `hdgear robust` and `hdgear physical --robust`.
#[derive(Args, Debug, Clone)]
pub struct RobustOpts {
    /// A parameter's spread, NAME=SPEC (repeatable; NAME a drive's, the study's or any of a
    /// scenario model's parameters, coulomb.fs): ±X% or ±X (uniform band), LO..HI,
    /// normal:SD (SD in % or absolute), lognormal:S% (σ of ln), tnormal:SD:±X (truncated).
    /// A drive without any takes its card's bands ([card.tolerance]) and documented default
    /// bands for the rest, marked as assumptions.
    #[arg(long = "tolerance", value_name = "NAME=SPEC")]
    pub tolerances: Vec<String>,
    /// Samples of P(burst).
    #[arg(long, default_value_t = 4096)]
    pub samples: u64,
    /// sobol (quasi-Monte Carlo, digitally shifted) or random (Monte Carlo).
    #[arg(long, default_value = "sobol")]
    pub sampler: String,
    /// Seed of the samples (the same seed, the same bytes).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Confidence of P(burst)'s Wilson interval.
    #[arg(long, default_value_t = 0.95, allow_negative_numbers = true)]
    pub level: f64,
    /// Interval width whose sample count is reported.
    #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
    pub width: f64,
    /// Sobol indices of the burst indicator and the measures from a Saltelli design of N rows
    /// (N·(k + 2) runs for k tolerances; a power of two suits the Sobol points).
    #[arg(long, value_name = "N")]
    pub sobol: Option<usize>,
    /// P(burst) also by importance sampling from N samples drawn around the predicted boundary
    /// and weighted back (for a small P: the variance reduction is reported).
    #[arg(long, value_name = "N")]
    pub importance: Option<u64>,
    /// Skip the worst corner and margin (2^k rays for k tolerances).
    #[arg(long)]
    pub no_worst: bool,
    /// The tolerance cloud to a .svg or .png file: the first 4096 samples in the reduced
    /// (γ, δ) plane coloured by verdict, with the predicted boundary.
    #[arg(long, value_name = "FILE")]
    pub cloud: Option<PathBuf>,
    /// The Sobol bars to a .svg or .png file (needs --sobol): each tolerance's total and
    /// first-order index of the burst indicator.
    #[arg(long, value_name = "FILE", requires = "sobol")]
    pub bars: Option<PathBuf>,
    /// P(burst) at 1/4 … 2 times the load amplitude (13 loads) (T_am, or δ for a parameter set), --samples
    /// each, on the page and as a figure in this .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub load_curve: Option<PathBuf>,
    /// K/N: compute only part K (0 … N−1) of the samples, a contiguous block (the samples are
    /// the same as in the whole run); part 0 also computes the worst case and the Sobol indices.
    /// hdgear merge joins the parts' --json summaries.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
}

/// Arguments of `hdgear robust`.
#[derive(Args, Debug)]
pub struct RobustArgs {
    /// A drive instead of a parameter set: its card (built-in name, FILE.toml or FILE.toml#NAME)
    /// with the documented assumptions for the rest (hdgear physical --robust changes them).
    #[arg(long, value_name = "CARD", conflicts_with_all = crate::sources::NOT_WITH_CARD)]
    pub card: Option<String>,
    /// The samples, one row each (.csv, .json or .parquet).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub robust: RobustOpts,
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
}

impl RobustOpts {
    /// The checked options of the analysis.
    fn options(&self) -> Result<AnalysisOptions> {
        let sampler: Sampler = self.sampler.parse().context("--sampler")?;
        let part = self.shard.as_deref().map(shard).transpose()?;
        let block = |total: u64| match part {
            None => 0..total,
            Some((k, n)) => total * k / n..total * (k + 1) / n,
        };
        let plain = block(self.samples);
        let (first, samples) = (plain.start, plain.end - plain.start);
        // the worst case and the Sobol indices are not sampled: shard 0 computes them whole
        let lead = part.is_none_or(|(k, _)| k == 0);
        let mc = McOptions {
            samples,
            first,
            sampler,
            seed: self.seed,
            level: self.level,
            width: self.width,
        };
        mc.validate()?;
        if self.sobol.is_some_and(|n| n < 2) {
            bail!(
                "invalid option --sobol = {}: at least 2 rows",
                self.sobol.unwrap_or(0)
            );
        }
        if self.importance == Some(0) {
            bail!("invalid option --importance = 0: at least 1 sample");
        }
        Ok(AnalysisOptions {
            mc,
            worst: !self.no_worst && lead,
            sobol: self.sobol.filter(|_| lead),
            importance: self.importance.map(block),
            load_curve: self
                .load_curve
                .as_ref()
                .filter(|_| lead)
                .map(|_| self.samples),
            shard: part,
        })
    }

    /// The space: the user's tolerances, or a drive's card's bands and the defaults.
    fn space(&self, nominal: Nominal, card: Option<&Loaded>) -> Result<Space> {
        let tolerances = if self.tolerances.is_empty() {
            match (nominal, card) {
                (Nominal::Drive(d), Some(c)) => Space::card_tolerances(&d, &c.card, &c.sources)
                    .context("the card's tolerances")?,
                (Nominal::Drive(d), None) => Space::drive_defaults(&d),
                (Nominal::Study(_), _) => bail!(
                    "a parameter set needs its spreads: --tolerance NAME=SPEC (gamma=±10%); a \
                     drive (--card) has default bands"
                ),
                (Nominal::Model(_), _) => bail!(
                    "a model needs its spreads: --tolerance NAME=SPEC, any of its parameters \
                     (coulomb.fs=±20%, delta=±10%); a drive (--card) has default bands"
                ),
            }
        } else {
            self.tolerances
                .iter()
                .map(|t| Space::parse_tolerance(&nominal, t).context("--tolerance"))
                .collect::<Result<_>>()?
        };
        Ok(Space::new(nominal, tolerances)?)
    }
}

/// The samples file: a study set's or a drive's rows carry the reduced set, a model's the
/// toleranced values under their names ([`ModelSampleRow`]).
enum Rows {
    Reduced(RecordWriter<Sink, SampleRow>),
    Model(RecordWriter<Sink, ModelSampleRow>),
}

impl Rows {
    fn open(path: &Path, space: &Space) -> Result<Rows> {
        let (sink, format) = Sink::open(Some(path))?;
        Ok(match space.nominal {
            Nominal::Model(_) => Rows::Model(RecordWriter::with_columns(
                sink,
                format,
                space,
                ModelSampleRow::columns(space),
            )?),
            _ => Rows::Reduced(RecordWriter::new(sink, format, space)?),
        })
    }

    fn write(&mut self, space: &Space, samples: &[Sample]) -> std::io::Result<()> {
        match self {
            Rows::Reduced(w) => samples.iter().try_for_each(|s| w.row(&SampleRow::from(s))),
            Rows::Model(w) => samples
                .iter()
                .try_for_each(|s| w.row(&ModelSampleRow::of(space, s))),
        }
    }

    fn finish(self, path: &Path) -> Result<()> {
        let done = match self {
            Rows::Reduced(w) => w.finish(),
            Rows::Model(w) => w.finish(),
        };
        done.with_context(|| format!("writing {}", path.display()))?
            .commit()?;
        Ok(())
    }
}

/// `K/N` with N ≥ 1 and K < N.
fn shard(text: &str) -> Result<(u64, u64)> {
    let parsed = text
        .split_once('/')
        .and_then(|(k, n)| Some((k.trim().parse::<u64>().ok()?, n.trim().parse::<u64>().ok()?)));
    match parsed {
        Some((k, n)) if n >= 1 && k < n => Ok((k, n)),
        _ => bail!("invalid --shard '{text}': expected K/N with 0 <= K < N"),
    }
}

/// Runs `hdgear robust`.
pub fn run(a: RobustArgs) -> Result<()> {
    let opts = a.burst.options()?;
    let (nominal, card) = match &a.card {
        Some(card) => {
            let loaded = crate::cmd::card::load(card).context("--card")?;
            let built = hdgear::physical::catalogue::assemble(&loaded.card, None, None)
                .context("--card")?;
            (Nominal::Drive(built.drive), Some(loaded))
        }
        None => {
            let (system, warnings) = a.params.resolve_system()?;
            warn(&warnings);
            match system {
                Subject::Study(p) => (Nominal::Study(p), None),
                Subject::Model(m) => (Nominal::Model(m), None),
            }
        }
    };
    analyse_and_print(
        nominal,
        card.as_ref(),
        &a.robust,
        &opts,
        a.out.as_deref(),
        a.json,
    )
}

/// The analysis of `nominal` (a drive with its `card`'s tolerances), its samples to `out`, its
/// page (or JSON) to stdout.
pub fn analyse_and_print(
    nominal: Nominal,
    card: Option<&Loaded>,
    r: &RobustOpts,
    opts: &hdgear::burst::BurstOptions,
    out_path: Option<&Path>,
    json: bool,
) -> Result<()> {
    let space = r.space(nominal, card)?;
    let options = r.options()?;
    check_out(&out_path.map(Path::to_path_buf))?;
    for (flag, path) in [
        ("--cloud", &r.cloud),
        ("--bars", &r.bars),
        ("--load-curve", &r.load_curve),
    ] {
        if let Some(path) = path {
            crate::args::check_figure_path(flag, path)?;
        }
    }
    if let (Nominal::Model(m), Some(path)) = (&space.nominal, &r.cloud) {
        bail!(
            "invalid --cloud '{}': the cloud is drawn in the reduced (γ, δ) plane against the \
             predicted boundary, and {} has neither (its samples go to --out)",
            path.display(),
            m.equation()
        );
    }
    let mut cloud: Vec<(f64, f64, bool)> = Vec::new();
    let mut writer = out_path.map(|path| Rows::open(path, &space)).transpose()?;
    let mut analysis = analyse(&space, opts, &options, |samples| {
        for s in samples {
            if let (Some(p), Ok(o)) = (s.reduced, &s.outcome)
                && cloud.len() < hdgear::figures::CLOUD_POINTS
            {
                cloud.push((p.gamma, p.delta, o.bursting));
            }
        }
        if let Some(w) = writer.as_mut() {
            w.write(&space, samples)
                .map_err(|source| hdgear::Error::Io {
                    path: out_path.unwrap_or(Path::new("-")).to_path_buf(),
                    source,
                })?;
        }
        Ok(())
    })?;
    if let (Some(w), Some(path)) = (writer, out_path) {
        w.finish(path)?;
    }
    if let Some(path) = &r.cloud {
        let figure = hdgear::figures::cloud_figure(&space.nominal.reduced()?, &cloud);
        hdgear::output::plot::write(&figure, path)?;
    }
    if let (Some(path), Some(sens)) = (&r.bars, &analysis.sensitivity) {
        match hdgear::figures::sobol_figure(sens) {
            Some(figure) => hdgear::output::plot::write(&figure, path)?,
            None => eprintln!("no Sobol bars: neither the verdict nor the peak |x'| varies"),
        }
    }
    if let (Some(path), Some(points)) = (&r.load_curve, &analysis.load_curve) {
        let load = match space.nominal {
            Nominal::Drive(_) => "T_am [N m]",
            Nominal::Study(_) | Nominal::Model(_) => "δ",
        };
        hdgear::output::plot::write(&hdgear::figures::load_figure(points, load), path)?;
    }
    if let (Some(r), Some(c)) = (analysis.resonance.as_mut(), card) {
        r.required_hz = c
            .card
            .application
            .as_ref()
            .and_then(|a| a.resonance_required);
    }
    if json {
        crate::sink::outln!("{}", serde_json::to_string_pretty(&analysis)?);
    } else {
        out!("{}", text(&analysis));
    }
    Ok(())
}

/// The one page: what spreads, P(burst), worst case and margin, which tolerance matters, the
/// resonance rule.
pub fn text(a: &RobustAnalysis) -> String {
    let mut s = String::new();
    match &a.space.nominal {
        Nominal::Drive(d) => s.push_str(&crate::summary::drive_line(d)),
        Nominal::Model(m) => {
            let _ = writeln!(s, "model: {}", m.equation());
        }
        Nominal::Study(p) => {
            let values: Vec<String> = hdgear::params::Param::ALL
                .iter()
                .map(|&q| format!("{q} = {}", p.value(q)))
                .collect();
            let _ = writeln!(s, "parameter set: {}", values.join(", "));
        }
    }
    let _ = writeln!(s, "tolerances:");
    for t in &a.space.tolerances {
        let _ = writeln!(
            s,
            "  {:<9} {}  ({})",
            t.target.name(),
            t.distribution,
            t.source
        );
    }
    let p = &a.probability;
    let _ = writeln!(
        s,
        "P(burst) = {} [{}, {}] ({:.0} % Wilson) from {} {} samples from index {} \
         (seed {}): {} judged, {} of them predicted; {} outside the domain, {} failed",
        probability(p.p),
        probability(p.interval.0),
        probability(p.interval.1),
        100.0 * p.level,
        p.samples,
        a.sampling.sampler.name(),
        a.sampling.first,
        a.sampling.seed,
        p.judged,
        p.predicted,
        p.outside_domain,
        p.failed
    );
    let _ = writeln!(
        s,
        "  an interval {} wide needs {} samples at this P",
        p.width, p.needed_for_width
    );
    if let Some(i) = &a.importance {
        importance_text(&mut s, a, i);
    } else if p.bursting < 10 && p.judged > 0 {
        let _ = writeln!(
            s,
            "  few bursting samples: --importance N estimates a small P from samples drawn near \
             the predicted boundary"
        );
    }
    if let Some(w) = &a.worst {
        worst_text(&mut s, a, w);
    }
    if let Some(sens) = &a.sensitivity {
        sobol_text(&mut s, sens);
    }
    if let Some(points) = &a.load_curve {
        load_text(&mut s, a, points);
    }
    if let Some(r) = &a.resonance {
        resonance_text(&mut s, r);
    }
    s
}

fn load_text(s: &mut String, a: &RobustAnalysis, points: &[hdgear::robust::LoadPoint]) {
    let _ = writeln!(
        s,
        "P(burst) against the load amplitude ({}, {} samples each):",
        hdgear::robust::load_target(&a.space.nominal).name(),
        points.first().map_or(0, |q| q.probability.samples)
    );
    for q in points {
        let p = &q.probability;
        let _ = writeln!(
            s,
            "  {:>5.3} x  {:>10.4}  {} [{}, {}]",
            q.factor,
            q.load,
            probability(p.p),
            probability(p.interval.0),
            probability(p.interval.1)
        );
    }
}

fn resonance_text(s: &mut String, r: &hdgear::robust::Resonance) {
    let rule: Vec<String> = APPLICATIONS
        .iter()
        .map(|&(name, hz)| {
            let ok = if r.lowest_hz >= hz { "pass" } else { "FAIL" };
            format!("{name} (>= {hz} Hz) {ok}")
        })
        .collect();
    let _ = writeln!(
        s,
        "resonance (selection rule f_n = sqrt(k1/J_o)/2pi): nominal {:.2} Hz, lowest over the \
         box {:.2} Hz: {}",
        r.nominal_hz,
        r.lowest_hz,
        rule.join(", ")
    );
    if let Some(req) = r.required_hz {
        let ok = if r.lowest_hz >= req { "pass" } else { "FAIL" };
        let _ = writeln!(s, "  the card's application needs {req} Hz: {ok}");
    }
}

/// A probability with four decimals, or four significant digits below 1e-3.
fn probability(p: f64) -> String {
    if p == 0.0 || p >= 1e-3 {
        format!("{p:.4}")
    } else {
        format!("{p:.3e}")
    }
}

fn importance_text(s: &mut String, a: &RobustAnalysis, i: &hdgear::robust::Importance) {
    let names: Vec<&str> = a.space.tolerances.iter().map(|t| t.target.name()).collect();
    match (&i.design, &i.note) {
        (Some(d), _) => {
            let at: Vec<String> = names
                .iter()
                .zip(&d.values)
                .map(|(n, v)| format!("{n} = {v:.5}"))
                .collect();
            let _ = writeln!(
                s,
                "importance sampling: design point (nearest predicted bursting, {} rays) at beta = \
                 {:.4} standard deviations, {}; first-order P = {}",
                d.rays,
                d.beta,
                at.join(", "),
                probability(d.first_order_p)
            );
        }
        (None, Some(note)) => {
            let _ = writeln!(s, "importance sampling: {note}");
        }
        (None, None) => {}
    }
    let _ = writeln!(
        s,
        "  P(burst) = {} [{}, {}] ({:.0} %) from {} samples, {:.0} % of them around the design \
         point: {} bursting, {} excluded",
        probability(i.p),
        probability(i.interval.0),
        probability(i.interval.1),
        100.0 * i.level,
        i.samples,
        100.0 * i.share,
        i.bursting,
        i.excluded
    );
    if i.variance_reduction.is_finite() {
        let _ = writeln!(
            s,
            "  variance reduction {:.3e}: as precise as {:.3e} plain samples",
            i.variance_reduction, i.equivalent_plain_samples
        );
    }
    if i.bursting < 10 {
        let _ = writeln!(
            s,
            "  fewer than 10 bursting samples, so the interval's normal approximation is not \
             reliable; P <= {} holds without it",
            probability(i.upper_bound)
        );
    }
}

fn worst_text(s: &mut String, a: &RobustAnalysis, w: &hdgear::robust::WorstCase) {
    let names: Vec<&str> = a.space.tolerances.iter().map(|t| t.target.name()).collect();
    let nominal = if w.nominal.bursting {
        "bursts"
    } else {
        "is burst-free"
    };
    let _ = writeln!(
        s,
        "worst case ({} corners; the nominal set {nominal}):",
        w.corners.len()
    );
    let c = &w.corners[w.worst];
    let signs: Vec<String> = names
        .iter()
        .zip(&c.signs)
        .map(|(n, &g)| format!("{n} {}", if g > 0 { "high" } else { "low" }))
        .collect();
    let kind = if w.nominal.bursting {
        "furthest into bursting"
    } else {
        "closest to bursting"
    };
    match &c.crossing {
        Some(x) => {
            let _ = writeln!(
                s,
                "  {kind}: {}; the verdict changes between {:.5} and {:.5} of the way to it \
                 ({} inside, {} outside)",
                signs.join(", "),
                x.inside,
                x.outside,
                x.inside_outcome.label(),
                x.outside_outcome.label()
            );
        }
        None => {
            let _ = writeln!(
                s,
                "  {kind}: {}; no change of verdict up to {} times the box",
                signs.join(", "),
                c.reach
            );
        }
    }
    let bands: Vec<String> = names
        .iter()
        .zip(&w.margin_percent)
        .map(|(n, (lo, hi))| format!("{n} {lo:+.2} % … {hi:+.2} %"))
        .collect();
    let what = if w.nominal.bursting {
        "bursting"
    } else {
        "burst-free"
    };
    match w.margin {
        Some(m) => {
            let _ = writeln!(
                s,
                "  margin: {what} with every parameter within {} (the box scaled by {m:.4})",
                bands.join(", ")
            );
        }
        None => {
            let _ = writeln!(
                s,
                "  margin: {what} with every parameter within {} (the reach of the search, {} \
                 times the box)",
                bands.join(", "),
                w.reach
            );
        }
    }
    let _ = writeln!(
        s,
        "  checked inside that box: {} points, {} with another verdict",
        w.interior_checked, w.interior_differing
    );
}

fn sobol_text(s: &mut String, sens: &hdgear::robust::Sensitivity) {
    let runs = sens.n * (sens.parameters.len() + 2);
    let _ = writeln!(
        s,
        "which tolerance matters (Sobol indices, N = {}, {runs} runs, 95 % bootstrap intervals):",
        sens.n
    );
    for (measure, ix) in &sens.measures {
        let Some(ix) = ix else {
            let _ = writeln!(
                s,
                "  {:<17} not every run has it (failed or predicted)",
                measure.name()
            );
            continue;
        };
        if ix.variance == 0.0 {
            let _ = writeln!(
                s,
                "  {:<17} does not vary (mean {:.4e})",
                measure.name(),
                ix.mean
            );
            continue;
        }
        let what = if *measure == Measure::Burst {
            " (mean = P(burst))"
        } else {
            ""
        };
        let _ = writeln!(s, "  {}{what}: mean {:.4e}", measure.name(), ix.mean);
        let interval = |e: hdgear::robust::sobol::BootstrapEstimate| {
            if e.replicates == 0 {
                format!("{:>7.4} [no resample varies]", e.value)
            } else {
                format!("{:>7.4} [{:>7.4}, {:>7.4}]", e.value, e.lo, e.hi)
            }
        };
        for (i, name) in sens.parameters.iter().enumerate() {
            let (f, t) = (ix.first[i], ix.total[i]);
            let _ = writeln!(
                s,
                "    {name:<9} first {}  total {}",
                interval(f),
                interval(t)
            );
        }
        let fewest = ix.first.iter().chain(&ix.total).map(|e| e.replicates).min();
        if let Some(k) = fewest.filter(|&k| k < hdgear::robust::sobol::BOOTSTRAP) {
            let _ = writeln!(
                s,
                "    (intervals from as few as {k} of {} resamples: the others do not vary)",
                hdgear::robust::sobol::BOOTSTRAP
            );
        }
    }
}
