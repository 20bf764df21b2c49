//! `hdgear card`: list, show, check and write drive cards.
//!
//! **Why one file.** A command owns its arguments, checks and output in its own file; `card` has
//! five actions (list, show, new, check, map) that share the card loader and the check's text.

use crate::args::{BurstArgs, as_flag};
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use hdgear::output::Record;
use hdgear::physical::card::{self, Card, CardFile, Source};
use hdgear::physical::check::{CardCheck, DampingChoice, MapGrid, check_card, load_map};
use hdgear::physical::design::Judgement;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::{Read, Write};
use std::path::Path;
use std::path::PathBuf;

/// Arguments of `hdgear card`.
#[derive(Args, Debug)]
pub struct CardArgs {
    /// What to do with cards.
    #[command(subcommand)]
    pub action: CardAction,
}

/// The `hdgear card` actions. CARD is a built-in card's name (hdgear card list) or a card file
/// (FILE.toml, or FILE.toml#NAME when it holds several cards).
#[derive(Subcommand, Debug)]
pub enum CardAction {
    /// The built-in cards: name, ratio, rated torque, K1..K3 and how many values are missing.
    List {
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// One card: every value with its unit and source, and what is missing.
    Show {
        /// The card: a built-in card's name (hdgear card list), FILE.toml or FILE.toml#NAME.
        card: String,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// What a card implies: its curve and cubic fit, damping from the hysteresis loss, natural
    /// frequency and critical input speed, distance from the folds, and the verdict.
    Check {
        /// The card: a built-in card's name (hdgear card list), FILE.toml or FILE.toml#NAME.
        card: String,
        /// Damping of the torsional mode: loss (from the card's hysteresis loss) or assumed
        /// (the card's application zeta, else 10 %).
        #[arg(long, default_value = "loss")]
        damping: String,
        /// Also the design check: for each of k1, k2, C, T_am, backlash and T_m, the single
        /// change that would make the drive burst or stop it bursting.
        #[arg(long)]
        design: bool,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        knees: KneeArgs,
        #[command(flatten)]
        burst: BurstArgs,
    },
    /// The verdict over slow output-torque amplitudes up to the rated torque (T2 without a
    /// rating) and frequencies from 0.01 to 10 Hz (log-spaced): one row per point (its columns
    /// in `--out`'s help).
    Map(CardMapArgs),
    /// Write a new card file: a commented template, or a copy of --from under a new name.
    New {
        /// The new card's name.
        name: String,
        /// The card to start from (its values and sources are copied).
        #[arg(long, value_name = "CARD")]
        from: Option<String>,
        /// The file to write (.toml; standard output without it). Never overwrites.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
}

/// Arguments of `hdgear card map`.
#[derive(Args, Debug)]
pub struct CardMapArgs {
    /// The card: a built-in card's name (hdgear card list), FILE.toml or FILE.toml#NAME.
    pub card: String,
    /// Points per axis.
    #[arg(long, default_value_t = 20)]
    pub points: usize,
    /// LO:HI, the frequency range in Hz.
    #[arg(long, value_name = "LO:HI")]
    pub hz: Option<String>,
    /// Largest amplitude [N m] (default: the rated torque, T2 without a rating).
    #[arg(long, allow_negative_numbers = true)]
    pub t_am_max: Option<f64>,
    /// Damping of the torsional mode: loss or assumed (as for check).
    #[arg(long, default_value = "loss")]
    pub damping: String,
    /// Leave out the verdict with the catalogue's own curve (its two columns left empty): the
    /// fitted model alone, far faster (its knees make every response ring).
    #[arg(long)]
    pub fit_only: bool,
    #[arg(long, value_name = "N", help = coarse_help())]
    pub coarse: Option<usize>,
    #[command(flatten)]
    pub knees: KneeArgs,
    #[arg(long, value_name = "FILE", help = crate::export::out_help(MapRow::COLUMNS))]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub burst: BurstArgs,
}

/// `--coarse`'s help, with the default lattice's size.
fn coarse_help() -> String {
    let n = hdgear::physical::check::MAP_LATTICE;
    format!(
        "Simulate every N-th point per axis first, then refine wherever neighbouring verdicts \
         differ; the rest take their block's verdicts (the `computed` columns). 1: simulate \
         every point. Default: the points per axis over {n} (every point up to {} per axis)",
        2 * n - 1
    )
}

/// The flag of [`KneeArgs`]'s option, by the library's name for it.
const KNEE_FLAG: [(&str, &str); 1] = [("knee_rounding", "knee-rounding")];

/// How the catalogue curve's verdict rounds the knees (`card check` and `card map`).
#[derive(clap::Args, Debug)]
pub struct KneeArgs {
    /// Round the catalogue curve's knees over this fraction of the first knee's twist theta(T1),
    /// 0 to 1 (a hyperbola in place of each corner; 0: the catalogue's corners).
    #[arg(
        long,
        default_value_t = 0.0,
        allow_negative_numbers = true,
        value_name = "FRACTION"
    )]
    pub knee_rounding: f64,
}

/// A card with the sources of the file it came from.
pub struct Loaded {
    /// The card.
    pub card: Card,
    /// Its file's sources.
    pub sources: BTreeMap<String, Source>,
}

/// Limit on a card file's size: a card is a few kilobytes; more is not a card.
const MAX_CARD_FILE: u64 = 4 << 20;

/// The card `spec` names: a built-in card, `FILE.toml` (with one card) or `FILE.toml#NAME`.
pub fn load(spec: &str) -> Result<Loaded> {
    let (path, name) = match spec.split_once('#') {
        Some((p, n)) => (p, Some(n)),
        None => (spec, None),
    };
    if !path.ends_with(".toml") {
        let c = card::builtin_card(spec)?;
        return Ok(Loaded {
            card: c.clone(),
            sources: card::builtin().sources.clone(),
        });
    }
    let mut text = String::new();
    hdgear::output::open_input(Path::new(path))
        .and_then(|f| f.take(MAX_CARD_FILE + 1).read_to_string(&mut text))
        .with_context(|| format!("cannot read card file {path}"))?;
    if text.len() as u64 > MAX_CARD_FILE {
        bail!("card file {path} is larger than {MAX_CARD_FILE} bytes: not a card file");
    }
    let file = CardFile::parse(&text).with_context(|| format!("card file {path}"))?;
    let card = match (name, file.card.len()) {
        (Some(n), _) => file
            .get(n)
            .with_context(|| format!("card file {path}"))?
            .clone(),
        (None, 1) => file.card[0].clone(),
        (None, 0) => bail!("card file {path} holds no [[card]]"),
        (None, n) => bail!("card file {path} holds {n} cards: name one as {path}#NAME"),
    };
    Ok(Loaded {
        card,
        sources: file.sources,
    })
}

/// The document of `hdgear card check --json`: the check, and the design check when asked for.
#[derive(serde::Serialize)]
struct Checked {
    #[serde(flatten)]
    check: CardCheck,
    #[serde(skip_serializing_if = "Option::is_none")]
    design: Option<hdgear::physical::design::DesignCheck>,
}

/// One row of `hdgear card map`.
#[derive(serde::Serialize, hdgear::output::Record)]
struct MapRow {
    t_am_nm: f64,
    frequency_hz: f64,
    bursting: bool,
    verdict: &'static str,
    basis: &'static str,
    fast_slow_domain: bool,
    /// Empty without a friction law on the card.
    friction_bursting: Option<bool>,
    /// `not-judged` where the model with friction could not be simulated.
    friction_verdict: Option<&'static str>,
    /// With the catalogue's curve in place of the fit; empty where not judged.
    catalogue_bursting: Option<bool>,
    /// `not-judged` where the model with the catalogue's curve could not be simulated; empty
    /// with `--fit-only`.
    catalogue_verdict: Option<&'static str>,
    /// False where the fit's verdict is its block's, from the coarse lattice (`--coarse`).
    computed: bool,
    /// As `computed`, for the verdict with friction; empty without a law.
    friction_computed: Option<bool>,
    /// As `computed`, for the verdict with the catalogue's curve; empty with `--fit-only`.
    catalogue_computed: Option<bool>,
    /// With the wave generator held (a position-controlled motor).
    held_bursting: bool,
    /// The held drive's verdict.
    held_verdict: &'static str,
    /// Whether the held drive is in the fast-slow domain.
    held_fast_slow_domain: bool,
    /// As `computed`, for the held drive's verdict.
    held_computed: bool,
}

/// The metadata of `hdgear card map`'s table.
#[derive(serde::Serialize)]
struct MapMeta<'a> {
    card: &'a str,
    grid: MapGrid,
    damping: DampingChoice,
    /// The card's friction law, with where it is taken to act.
    #[serde(skip_serializing_if = "Option::is_none")]
    friction: Option<(hdgear::physical::friction::FrictionLaw, &'static str)>,
    /// How the catalogue's curve enters the model of the `catalogue_` columns (none with
    /// `--fit-only`).
    #[serde(skip_serializing_if = "Option::is_none")]
    catalogue_law: Option<&'static str>,
    /// The catalogue curve's knee rounding, a fraction of θ(T₁) (none with `--fit-only`).
    #[serde(skip_serializing_if = "Option::is_none")]
    knee_rounding: Option<f64>,
    /// What the `held_` columns assume.
    held_input: &'static str,
}

/// Runs `hdgear card`.
pub fn run(a: CardArgs) -> Result<()> {
    match a.action {
        CardAction::List { json } => list(json),
        CardAction::Show { card, json } => show(&card, json),
        CardAction::Check {
            card,
            damping,
            design,
            json,
            knees,
            burst,
        } => {
            let choice = DampingChoice::parse(&damping).context("--damping")?;
            let opts = burst.options()?;
            let l = load(&card)?;
            let check = check_card(&l.card, &l.sources, choice, knees.knee_rounding, &opts)
                .map_err(|e| as_flag(e, &KNEE_FLAG))?;
            let design = design
                .then(|| hdgear::physical::design::design_check(&check.summary.drive, &opts))
                .transpose()?;
            if json {
                let doc = Checked { check, design };
                crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
            } else {
                crate::sink::out!("{}", check_text(&check));
                if let Some(d) = &design {
                    crate::sink::out!("{}", crate::summary::design_text(d));
                }
            }
            Ok(())
        }
        CardAction::New { name, from, out } => new(&name, from.as_deref(), out.as_deref()),
        CardAction::Map(a) => map(a),
    }
}

/// Runs `hdgear card map`.
fn map(a: CardMapArgs) -> Result<()> {
    let CardMapArgs {
        card,
        points,
        hz,
        t_am_max,
        damping,
        fit_only,
        coarse,
        knees,
        out,
        burst,
    } = a;
    let choice = DampingChoice::parse(&damping).context("--damping")?;
    let opts = burst.options()?;
    crate::args::check_out(&out)?;
    let l = load(&card)?;
    let mut grid = MapGrid::for_card(&l.card, points);
    if let Some(range) = crate::args::parse_frequency_range("--hz", hz.as_deref())? {
        grid.hz = range;
    }
    if let Some(t) = t_am_max {
        grid.t_am_max = t;
    }
    if let Some(n) = coarse {
        grid.coarse = n;
    }
    let curve = (!fit_only).then_some(knees.knee_rounding);
    let map = load_map(&l.card, &l.sources, choice, &grid, &opts, curve).map_err(|e| {
        let grid_flags = [
            ("amplitudes", "points"),
            ("frequencies", "points"),
            ("hz", "hz"),
            ("t_am_max", "t-am-max"),
            ("coarse", "coarse"),
        ];
        as_flag(e, &[&grid_flags[..], &KNEE_FLAG].concat())
    })?;
    let law = l.card.friction_law()?;
    let has_friction = law.is_some();
    let rows = map.iter().map(|p| {
        let (friction_bursting, friction_verdict) = verdict_columns(has_friction, p.friction);
        let (catalogue_bursting, catalogue_verdict) = verdict_columns(!fit_only, p.catalogue);
        MapRow {
            t_am_nm: p.t_am,
            frequency_hz: p.frequency_hz,
            bursting: p.judgement.bursting,
            verdict: p.judgement.label(),
            basis: match p.judgement.basis {
                hdgear::physical::design::Basis::Simulation => "simulation",
                hdgear::physical::design::Basis::Prediction => "prediction",
            },
            fast_slow_domain: p.judgement.fast_slow_domain,
            friction_bursting,
            friction_verdict,
            catalogue_bursting,
            catalogue_verdict,
            computed: p.computed,
            friction_computed: has_friction.then_some(p.friction_computed),
            catalogue_computed: (!fit_only).then_some(p.catalogue_computed),
            held_bursting: p.held.bursting,
            held_verdict: p.held.label(),
            held_fast_slow_domain: p.held.fast_slow_domain,
            held_computed: p.held_computed,
        }
    });
    let meta = MapMeta {
        card: &l.card.name,
        grid,
        damping: choice,
        friction: law.map(|law| (law, hdgear::physical::friction::ASSUMPTION)),
        catalogue_law: (!fit_only).then_some(hdgear::physical::curve_law::ASSUMPTION),
        knee_rounding: curve,
        held_input: hdgear::physical::check::HELD_ASSUMPTION,
    };
    crate::sink::write_records(out.as_deref(), &meta, rows)?;
    if out.is_some() {
        map_summary(&l.card.name, &map, has_friction, fit_only)?;
    }
    Ok(())
}

/// What `hdgear card map --out` prints beside the file: how many points burst, with the fit, the
/// card's friction (when it has a law) and the catalogue's curve (unless `--fit-only`).
fn map_summary(
    name: &str,
    map: &[hdgear::physical::check::MapPoint],
    has_friction: bool,
    fit_only: bool,
) -> Result<()> {
    // how many points burst by `of`'s verdict, and how many of those lie outside the domain
    let bursts = |of: fn(&hdgear::physical::check::MapPoint) -> Judgement| {
        let burst: Vec<Judgement> = map.iter().map(of).filter(|j| j.bursting).collect();
        let outside = burst.iter().filter(|j| !j.fast_slow_domain).count();
        (burst.len(), outside)
    };
    let (n, outside) = bursts(|p| p.judgement);
    let computed =
        |of: fn(&hdgear::physical::check::MapPoint) -> bool| map.iter().filter(|p| of(p)).count();
    crate::sink::outln!(
        "{name}: {n} of {} points burst, {outside} of them outside the fast-slow domain \
         (the slow variation not slow against the drive's relaxation); {} points computed, \
         the rest given their agreeing neighbours' verdict",
        map.len(),
        computed(|p| p.computed)
    );
    let judged = |of: fn(&hdgear::physical::check::MapPoint) -> Option<Judgement>| {
        let with: Vec<Judgement> = map.iter().filter_map(of).collect();
        let bursting = with.iter().filter(|j| j.bursting).count();
        (with, bursting)
    };
    if has_friction {
        let (with, bursting) = judged(|p| p.friction);
        let slips = with
            .iter()
            .filter(|j| j.verdict == Some(hdgear::burst::Verdict::StickSlip))
            .count();
        crate::sink::outln!(
            "with its friction: {bursting} of {} judged points burst, {slips} of them by \
             stick-slip; {} points not judged; {} computed",
            with.len(),
            map.len() - with.len(),
            computed(|p| p.friction_computed)
        );
    }
    let (held, held_outside) = bursts(|p| p.held);
    crate::sink::outln!(
        "with the wave generator held: {held} of {} points burst, {held_outside} of them outside \
         the fast-slow domain; {} computed",
        map.len(),
        computed(|p| p.held_computed)
    );
    if !fit_only {
        let (with, bursting) = judged(|p| p.catalogue);
        crate::sink::outln!(
            "with the catalogue's curve: {bursting} of {} judged points burst; {} points \
             not judged; {} computed",
            with.len(),
            map.len() - with.len(),
            computed(|p| p.catalogue_computed)
        );
    }
    Ok(())
}

fn list(json: bool) -> Result<()> {
    let cards = &card::builtin().card;
    if json {
        crate::sink::outln!("{}", serde_json::to_string_pretty(cards)?);
        return Ok(());
    }
    crate::sink::outln!("name            ratio   rated[N m]     K1       K2       K3   missing");
    for c in cards {
        let s = &c.stiffness;
        let k = |v: Option<f64>| v.map_or("-".into(), |v| format!("{v:.2e}"));
        crate::sink::outln!(
            "{:<14} {:>6} {:>11} {:>8} {:>8} {:>8}   {}",
            c.name,
            c.ratio,
            c.rated_torque().map_or("-".into(), |t| t.to_string()),
            k(s.k1),
            k(s.k2),
            k(s.k3),
            c.missing().len()
        );
    }
    Ok(())
}

/// The document of `hdgear card show --json`.
#[derive(serde::Serialize)]
struct Shown<'a> {
    card: &'a Card,
    sources: BTreeMap<&'static str, Source>,
    missing: Vec<String>,
}

fn show(spec: &str, json: bool) -> Result<()> {
    let l = load(spec)?;
    if json {
        let doc = Shown {
            sources: l.card.cited(&l.sources),
            missing: l.card.missing(),
            card: &l.card,
        };
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    let c = &l.card;
    let mut s = format!("{} (ratio {})\n", c.name, c.ratio);
    for sec in c.sections() {
        let src = &l.sources[sec.source()];
        let _ = writeln!(s, "[{}] {}: {}", sec.key(), src.kind.name(), src.cite);
        if let Some(n) = sec.note() {
            let _ = writeln!(s, "  note: {n}");
        }
        for (f, v) in sec.fields().iter().zip(sec.values()) {
            if let Some(v) = v {
                let _ = writeln!(s, "  {:<16} {:>12} {:<10} {}", f.key, v, f.unit, f.meaning);
            }
        }
    }
    let missing = c.missing();
    if !missing.is_empty() {
        let _ = writeln!(s, "missing: {}", missing.join(", "));
    }
    crate::sink::out!("{s}");
    Ok(())
}

/// The card file `hdgear card new` writes.
fn new(name: &str, from: Option<&str>, out: Option<&Path>) -> Result<()> {
    hdgear::physical::card::check_name(name)?;
    let text = match from {
        Some(spec) => {
            let l = load(spec).context("--from")?;
            let mut c = l.card;
            c.name = name.to_string();
            let used: BTreeMap<String, Source> = c
                .sections()
                .iter()
                .map(|s| (s.source().to_string(), l.sources[s.source()].clone()))
                .collect();
            let f = CardFile {
                format: card::FORMAT,
                sources: used,
                card: vec![c],
            };
            format!(
                "# hdgear drive card, copied from {spec}: change the values and their sources\n{}",
                f.to_toml()
            )
        }
        None => template(name),
    };
    match out {
        None => crate::sink::out!("{text}"),
        Some(path) => {
            if path.extension().is_none_or(|e| e != "toml") {
                bail!("--out {}: a card file ends in .toml", path.display());
            }
            if path.exists() {
                bail!(
                    "--out {}: the file exists (card new never overwrites)",
                    path.display()
                );
            }
            let mut f = hdgear::output::AtomicFile::create(path).context("--out")?;
            f.write_all(text.as_bytes())
                .with_context(|| format!("cannot write {}", path.display()))?;
            f.commit()?;
        }
    }
    Ok(())
}

/// A commented template: every section and quantity (from the sections' own field tables),
/// with the four the curve needs to be filled in.
fn template(name: &str) -> String {
    use hdgear::physical::card::{
        Application, Friction, Hysteresis, Inertia, Speed, Stiffness, Torque,
    };
    let mut s = format!(
        "# hdgear drive card (format {}). Fill in stiffness t1, t2, k1, k2 at least; every section\n\
         # names the [sources] entry its numbers come from (kind: catalogue, fit, measured,\n\
         # assumption). Leave out what you have no source for.\n\
         format = {}\n\n[sources]\nmine = {{ kind = \"catalogue\", cite = \"document, table, page\" }}\n\n\
         [[card]]\nname = \"{name}\"\nratio = 50.0\n",
        card::FORMAT,
        card::FORMAT
    );
    let sections: [(&str, &[card::Field]); 7] = [
        (Stiffness::KEY, Stiffness::FIELDS),
        (Torque::KEY, Torque::FIELDS),
        (Speed::KEY, Speed::FIELDS),
        (Inertia::KEY, Inertia::FIELDS),
        (Hysteresis::KEY, Hysteresis::FIELDS),
        (Friction::KEY, Friction::FIELDS),
        (Application::KEY, Application::FIELDS),
    ];
    for (i, (key, fields)) in sections.iter().enumerate() {
        let c = if i == 0 { "" } else { "# " };
        let _ = write!(s, "\n{c}[card.{key}]\n{c}source = \"mine\"\n");
        for f in *fields {
            let _ = writeln!(s, "# {} = ...   # [{}] {}", f.key, f.unit, f.meaning);
        }
    }
    s.push_str(
        "\n# [card.tolerance]   # manufacturing spreads for hdgear robust (drive parameter names)\n\
         # source = \"mine\"\n\
         # bands = { k1 = \"±12%\", c_eq = \"normal:15%\" }   # ±X%, ±X, LO..HI, normal:SD, lognormal:S%, tnormal:SD:±X\n",
    );
    s
}

/// The text of `hdgear card check`.
fn check_text(r: &CardCheck) -> String {
    let mut s = String::new();
    let deg = |rad: f64| rad.to_degrees() * 60.0;
    let _ = writeln!(s, "card {}", r.name);
    let kinds: Vec<String> = r
        .sources
        .iter()
        .map(|(sec, src)| format!("{sec} {}", src.kind.name()))
        .collect();
    let _ = writeln!(
        s,
        "  sources: {} (hdgear card show cites them)",
        kinds.join(", ")
    );
    if !r.missing.is_empty() {
        let _ = writeln!(s, "  missing: {}", r.missing.join(", "));
    }
    let c = &r.curve;
    let _ = writeln!(
        s,
        "curve: twist {:.3}' at T1, {:.3}' at T2{}; used up to {} N m",
        deg(c.twist_t1),
        deg(c.twist_t2),
        c.twist_rated.map_or(String::new(), |t| format!(
            ", {:.3}' at the rated torque",
            deg(t)
        )),
        c.t_max
    );
    let fit_line = |f: &hdgear::physical::catalogue::CubicFit| {
        format!(
            "k1 = {:.4e} N m/rad, k2 = {:.4e} N m/rad^3 fitted up to {} N m: twist error {:.2} % at T1, \
             {:.2} % at T2, largest torque error {:.2} % of the fitted range",
            f.k1,
            f.k2,
            f.t_fit,
            100.0 * f.twist_error_t1,
            100.0 * f.twist_error_t2,
            100.0 * f.max_torque_error
        )
    };
    let _ = writeln!(s, "cubic fit (the drive's): {}", fit_line(&r.fit));
    if let Some(f) = &r.fit_to_rated {
        let _ = writeln!(s, "cubic fit to the rated torque: {}", fit_line(f));
    }
    mode_lines(&mut s, r);
    s.push_str(&crate::summary::physical_text(&r.summary));
    let law = &r.catalogue_law;
    let rounded = if law.rounding > 0.0 {
        format!(", knees rounded over {} theta(T1)", law.rounding)
    } else {
        String::new()
    };
    let _ = writeln!(
        s,
        "with the catalogue's curve (K1, K2, K3 segments{rounded}, knees returned to {:.1e}): {}",
        law.knee_residual,
        law.outcome.as_ref().map_or(NOT_JUDGED.into(), outcome_text)
    );
    let _ = writeln!(s, "  assumed: {}", law.assumption);
    if let (Some(o), Some(g)) = (&law.outcome, &law.signatures) {
        let _ = writeln!(
            s,
            "  largest overshoot {:.3e} X, largest ringing swing of the twist rate {:.3e} omega X, \
             {} ringing bursts per period",
            g.max_overshoot, g.max_ringing_swing, g.ringing_bursts_per_period
        );
        if o.judgement.bursting {
            let _ = writeln!(s, "  {}", hdgear::physical::curve_law::KNEES);
        }
    }
    held_lines(&mut s, &r.held_input, r.summary.drive.t_am);
    if let Some(f) = &r.friction {
        friction_lines(&mut s, f, &r.sources);
    }
    s
}

/// The lines of `card check` on the drive with its wave generator held, and whether the card's
/// starting torque holds it against the slow disturbance `t_am` \[N m\].
fn held_lines(s: &mut String, h: &hdgear::physical::check::HeldInput, t_am: f64) {
    let _ = writeln!(
        s,
        "with the wave generator held ({}; zeta = {:.4}, gamma = {:.6}, delta = {:.6}): {}",
        h.assumption,
        h.zeta,
        h.reduced.gamma,
        h.reduced.delta,
        outcome_text(&h.outcome)
    );
    let line = match (h.starting_at_output, h.held_by_friction) {
        (Some(t), Some(true)) => format!(
            "the card's starting torque, N*T_st = {t:.4} N m at the output, holds the input \
             against T_am = {t_am} N m: under a torque-driven motor too, this is the drive's verdict"
        ),
        (Some(t), _) => format!(
            "the card's starting torque, N*T_st = {t:.4} N m at the output, is below T_am = \
             {t_am} N m: under a torque-driven motor the input slips, between the free and the \
             held verdicts"
        ),
        _ => "the card gives no starting torque: whether its friction holds the input is not \
              known"
            .into(),
    };
    let _ = writeln!(s, "  {line}");
}

/// The friction lines of `card check`: the law, where it acts, the verdict with it and what
/// changes that verdict.
fn friction_lines(
    s: &mut String,
    f: &hdgear::physical::friction::FrictionCheck,
    sources: &BTreeMap<&'static str, Source>,
) {
    let l = &f.law;
    let _ = writeln!(
        s,
        "friction ({}): F_c = {} N m, F_s = {} N m, v_s = {} rad/s, c_v = {} N m s/rad",
        sources.get("friction").map_or("-", |src| src.kind.name()),
        l.coulomb,
        l.breakaway,
        l.stribeck_speed,
        l.viscous
    );
    let _ = writeln!(s, "  assumed: {}", f.assumption);
    if let (Some(mu), Some([_, theta])) = (l.mesh_loss, f.reduced.mesh) {
        let _ = writeln!(
            s,
            "  mesh loss: mu_m = 1/eta - 1 = {mu:.6} (reduced theta_m = {theta:.6e})\n  assumed: {}",
            hdgear::physical::friction::MESH_ASSUMPTION
        );
    }
    let r = &f.reduced;
    let _ = writeln!(
        s,
        "  reduced: f_c = {:.6}, f_s = {:.6}, v_st = {:.6}, c_v = {:.6}{}",
        r.fc,
        r.fs,
        r.vst,
        r.cv,
        match f.load_over_breakaway {
            Some(q) if q <= 1.0 => format!(
                "; delta/f_s = T_am (J_eq/J_o)/F_s = {q:.4}: the sticking band holds the slow load, no slip"
            ),
            Some(q) => format!("; delta/f_s = T_am (J_eq/J_o)/F_s = {q:.4}"),
            None => String::new(),
        }
    );
    let Some(o) = &f.outcome else {
        let _ = writeln!(s, "with friction: {NOT_JUDGED}");
        return;
    };
    let j = &o.outcome.judgement;
    let _ = writeln!(s, "with friction: {}", outcome_text(&o.outcome));
    if let Some(st) = &o.sticking {
        let _ = writeln!(
            s,
            "  rests: {:.2} per period, stuck {:.1} % of the time; largest slip {:.4e} rad/s",
            st.sticks_per_period,
            100.0 * st.stuck_fraction,
            o.slip_peak_rate
        );
    }
    let _ = writeln!(
        s,
        "what changes the verdict with friction (one change at a time):"
    );
    crate::summary::margin_lines(s, &f.margins, j.bursting);
}

/// What `card check` says of a model it could not simulate (a verdict of `None`).
const NOT_JUDGED: &str =
    "not judged (the reduced load frequency is too low, or the response too long, to simulate)";

/// A map's two columns of a verdict beside the fit's (with friction, with the catalogue's
/// curve): bursting, and its label, `not-judged` where asked for but not simulated; both empty
/// where not asked for.
fn verdict_columns(asked: bool, j: Option<Judgement>) -> (Option<bool>, Option<&'static str>) {
    let label = asked.then(|| j.map_or("not-judged", |j| j.label()));
    (j.map(|j| j.bursting), label)
}

/// A simulated verdict in `card check`'s words: bursting or not, its signature, mode and
/// mechanism, and whether it lies outside the fast-slow domain.
fn outcome_text(o: &hdgear::physical::design::DriveVerdict) -> String {
    let j = &o.judgement;
    format!(
        "{} (signature {}, mode {}, mechanism {}){}",
        if j.bursting {
            "bursting"
        } else {
            "not bursting"
        },
        j.label(),
        o.mode.map_or("-", |m| m.name()),
        o.mechanism.map_or("-", |m| m.name()),
        if j.fast_slow_domain {
            ""
        } else {
            " (outside the fast-slow domain)"
        }
    )
}

/// The damping, torsional-mode and fold lines of `card check`.
fn mode_lines(s: &mut String, r: &CardCheck) {
    let deg = |rad: f64| rad.to_degrees() * 60.0;
    let d = &r.damping;
    if let Some(l) = &d.from_loss {
        let _ = writeln!(
            s,
            "hysteresis loss {:.3}' ({}) → zeta_eq = {:.4} of a ±{} N m cycle",
            deg(l.loss),
            l.source.name(),
            l.zeta,
            l.amplitude
        );
    }
    let _ = writeln!(
        s,
        "damping used ({}): zeta = {:.4}, gamma = 1/(4 zeta^2) = {:.4}",
        d.choice.name(),
        d.zeta,
        d.gamma
    );
    let f = &r.frequencies;
    let _ = writeln!(
        s,
        "torsional mode: f_n = {:.2} Hz{}; a twice-per-revolution kinematic error meets it at {:.0} rpm input{}",
        f.natural_hz,
        f.required_hz.map_or(String::new(), |req| format!(
            " ({} the {req} Hz the application needs)",
            if f.natural_hz >= req {
                "meets"
            } else {
                "BELOW"
            }
        )),
        f.critical_input_rpm,
        f.max_input_rpm.map_or(String::new(), |m| format!(
            " ({} the {m} rpm maximum input speed)",
            if f.critical_input_rpm <= m {
                "within"
            } else {
                "above"
            }
        ))
    );
    let fo = &r.folds;
    let _ = writeln!(
        s,
        "folds: they need a backlash above sqrt(3 k1/k2) = {:.3}' against {:.3}' here",
        deg(fo.fold_backlash),
        deg(fo.backlash)
    );
}
