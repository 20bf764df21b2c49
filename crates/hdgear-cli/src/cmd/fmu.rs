//! `hdgear export fmu`: a drive as an FMI 2.0 co-simulation FMU, with its reference input and
//! result beside it (the layout of modelica/Reference-FMUs).

use crate::cmd::physical::DriveArgs;
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use hdgear::output::AtomicFile;
use hdgear::physical::fmu::{FmuDrive, Role};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Arguments of `hdgear export`.
#[derive(Args, Debug)]
pub struct ExportArgs {
    /// What to export.
    #[command(subcommand)]
    pub what: ExportCommand,
}

/// What `hdgear export` writes.
#[derive(Subcommand, Debug)]
pub enum ExportCommand {
    /// The drive as an FMI 2.0 co-simulation FMU for Linux x86-64 (inputs tau_motor and
    /// tau_load; outputs phi_in, w_in, phi_out, w_out, twist, twist_rate, tau_gear; the drive's
    /// values as parameters), with NAME_in.csv, NAME_ref.csv and NAME_ref.opt beside it.
    Fmu(FmuArgs),
}

/// Arguments of `hdgear export fmu`.
#[derive(Args, Debug)]
pub struct FmuArgs {
    #[command(flatten)]
    pub spec: DriveArgs,
    /// The FMU to write (NAME.fmu).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Relative and absolute tolerance of hdgear's stepper inside the FMU (the absolute one in
    /// units of the drive's angle scale); a host's fmi2SetupExperiment tolerance replaces it.
    #[arg(long, default_value = "1e-10")]
    pub tolerance: f64,
    /// Communication step of the default experiment and the reference result [s] (default
    /// J_eq/C / 20, the spacing of physical --simulate).
    #[arg(long, allow_negative_numbers = true)]
    pub step: Option<f64>,
    /// Stop time of the default experiment and the reference result [s] (default one period
    /// of the disturbance, 2π/Ω).
    #[arg(long, allow_negative_numbers = true)]
    pub stop: Option<f64>,
    /// The reference input: a CSV with columns time,tau_motor,tau_load [s, N m, N m], each
    /// torque held from its row's time to the next row's; a repeated time is a jump, where the
    /// reference cuts its step (as FMPy does); zero torques without it.
    #[arg(long, value_name = "FILE")]
    pub input: Option<PathBuf>,
    /// The FMU's shared library to pack (default: the libhdgear_fmu.so cargo built with this
    /// hdgear, in deps/ beside it, else beside it).
    #[arg(long, value_name = "FILE")]
    pub library: Option<PathBuf>,
}

/// The most rows of the reference result.
const MAX_REFERENCE_ROWS: f64 = 1e6;

/// Runs `hdgear export`.
pub fn run(a: ExportArgs) -> Result<()> {
    match a.what {
        ExportCommand::Fmu(a) => fmu(a),
    }
}

/// The checked settings of `export fmu`: the drive, the library's bytes, the default
/// experiment and the reference input.
struct Checked {
    spec: FmuDrive,
    binary: Vec<u8>,
    step: f64,
    stop: f64,
    profile: Vec<(f64, [f64; 2])>,
}

impl FmuArgs {
    /// Every option checked, and the drive built, before anything is written.
    fn check(&self) -> Result<Checked> {
        if !cfg!(all(target_os = "linux", target_arch = "x86_64")) {
            bail!("hdgear export fmu writes FMUs for Linux x86-64 only");
        }
        if self.out.extension().and_then(|e| e.to_str()) != Some("fmu") {
            bail!("--out {}: the extension must be .fmu", self.out.display());
        }
        hdgear::output::check_output_path(&self.out).context("--out")?;
        let tol = self.tolerance;
        if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
            bail!("invalid option --tolerance = {tol:?}: must be in (0, 1)");
        }
        let (sys, origin) = self.spec.system()?;
        let step = self.step.unwrap_or(sys.t_c() / 20.0);
        let stop = self
            .stop
            .unwrap_or(std::f64::consts::TAU / sys.drive().omega);
        for (flag, v) in [("--step", step), ("--stop", stop)] {
            if !(v.is_finite() && v > 0.0) {
                bail!("invalid option {flag} = {v:?}: must be finite and > 0");
            }
        }
        if stop / step > MAX_REFERENCE_ROWS {
            bail!(
                "--stop {stop:?} with --step {step:?} would make {:.3e} reference rows (at most \
                 {MAX_REFERENCE_ROWS:e}): choose a larger --step or a smaller --stop",
                stop / step
            );
        }
        let library = match &self.library {
            Some(p) => p.clone(),
            None => built_library()?,
        };
        let binary = std::fs::read(&library).with_context(|| {
            format!("cannot read the FMU's shared library {}", library.display())
        })?;
        if !binary.starts_with(b"\x7fELF") {
            bail!(
                "--library {}: not a shared library (ELF)",
                library.display()
            );
        }
        let card = crate::cmd::card::load(&self.spec.drive)
            .context("--drive")?
            .card;
        if let Some(law) = card.friction_law()? {
            bail!(
                "card {}: its fitted friction (F_c = {} N m, mesh loss {:?}) acts across the \
                 compliance with true sticking, which the FMU's two-inertia model does not \
                 carry; give the card without its [friction] table, and --twist-friction \
                 stribeck:… for a regularised stand-in",
                card.name,
                law.coulomb,
                law.mesh_loss
            );
        }
        let profile = match &self.input {
            Some(path) => read_profile(path)?,
            None => vec![(0.0, [0.0; 2])],
        };
        let spec = FmuDrive::new(&origin.name, &sys, tol)?;
        Ok(Checked {
            spec,
            binary,
            step,
            stop,
            profile,
        })
    }
}

fn fmu(a: FmuArgs) -> Result<()> {
    let c = a.check()?;
    let archive = c.spec.archive(&c.binary, c.step, c.stop)?;
    // the torques jump where two rows share a time
    let jumps: Vec<f64> = (c.profile.windows(2))
        .filter(|w| w[0].0 == w[1].0)
        .map(|w| w[0].0)
        .collect();
    let rows = (c.spec).reference(c.step, c.stop, &jumps, |t| held(&c.profile, t))?;
    let vars = c.spec.variables();
    let names = |keep: fn(Role) -> bool| -> Vec<&str> {
        let kept = vars.iter().filter(|v| keep(v.role));
        kept.map(|v| v.name.as_str()).collect()
    };
    let (inputs, outputs) = (names(|r| r == Role::Input), names(|r| r == Role::Output));
    let mut input_csv = format!("time,{}\n", inputs.join(","));
    let mut ref_csv = format!("time,{}\n", outputs.join(","));
    for r in &rows {
        input_csv += &line(r.time, &r.inputs);
        ref_csv += &line(r.time, &r.outputs);
    }
    let (step, stop) = (c.step, c.stop);
    let opt = format!(
        "StartTime, 0.0\nStopTime, {stop:?}\nStepSize, {step:?}\nRelTol, {:?}\n",
        a.tolerance
    );
    let stem = a.out.with_extension("");
    let beside = |suffix: &str| PathBuf::from(format!("{}{suffix}", stem.display()));
    write_all(&[
        (a.out.clone(), archive),
        (beside("_in.csv"), input_csv.into_bytes()),
        (beside("_ref.csv"), ref_csv.into_bytes()),
        (beside("_ref.opt"), opt.into_bytes()),
    ])?;
    crate::sink::outln!(
        "wrote {} ({} parameters, 2 inputs, {} outputs; GUID {}) with its reference input and \
         result ({} rows, step {step:?} s)",
        a.out.display(),
        names(|r| matches!(r, Role::Parameter(_))).len(),
        outputs.len(),
        c.spec.guid(),
        rows.len()
    );
    Ok(())
}

/// The FMU's shared library built with this hdgear: cargo writes it to `deps/` beside the
/// binary whenever it builds hdgear (hdgear-fmu is a dependency), and beside the binary when it
/// builds the hdgear-fmu package itself. The first that exists.
fn built_library() -> Result<PathBuf> {
    let exe = std::env::current_exe().context("cannot locate the hdgear binary")?;
    let name = format!("lib{}.so", hdgear::physical::fmu::MODEL_IDENTIFIER);
    let dir = exe.parent().unwrap_or(Path::new("."));
    let candidates = [dir.join("deps").join(&name), dir.join(&name)];
    let found = candidates.iter().find(|p| p.is_file());
    found.cloned().ok_or_else(|| {
        anyhow::anyhow!(
            "no FMU shared library {name} in {} or beside it (cargo build --release builds it \
             with hdgear; or give --library FILE)",
            dir.join("deps").display()
        )
    })
}

/// A reference input: rows (time, [motor, load]), times non-decreasing.
fn read_profile(path: &Path) -> Result<Vec<(f64, [f64; 2])>> {
    let bad =
        |line: usize, why: &str| anyhow::anyhow!("--input {}: line {line}: {why}", path.display());
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("--input: cannot read {}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(str::trim)
        .collect();
    if header != ["time", "tau_motor", "tau_load"] {
        return Err(bad(1, "the header must be time,tau_motor,tau_load"));
    }
    let mut rows: Vec<(f64, [f64; 2])> = Vec::new();
    for (i, l) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let v: Vec<f64> = l
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad(i + 2, "three numbers expected"))?;
        let [t, motor, load] = v[..] else {
            return Err(bad(i + 2, "three numbers expected"));
        };
        if !(t.is_finite() && motor.is_finite() && load.is_finite()) {
            return Err(bad(i + 2, "every value must be finite"));
        }
        if rows.last().is_some_and(|r| t < r.0) {
            return Err(bad(i + 2, "times must not decrease"));
        }
        rows.push((t, [motor, load]));
    }
    if rows.is_empty() {
        return Err(bad(2, "no rows"));
    }
    Ok(rows)
}

/// The torques held at `t`: the last row at or before it (the first row's before the first
/// time).
fn held(profile: &[(f64, [f64; 2])], t: f64) -> [f64; 2] {
    let slack = 1e-9 * t.abs().max(1e-300);
    let at = profile.partition_point(|r| r.0 <= t + slack);
    profile[at.saturating_sub(1)].1
}

/// A CSV line: the time, then the values, each read back to the same bits.
fn line(t: f64, values: &[f64]) -> String {
    let mut s = format!("{t:?}");
    for v in values {
        s += &format!(",{v:?}");
    }
    s + "\n"
}

/// Writes every file or none: each to a temporary, all renamed once all are written.
fn write_all(files: &[(PathBuf, Vec<u8>)]) -> Result<()> {
    let mut done = Vec::new();
    for (path, bytes) in files {
        let mut f = AtomicFile::create(path).with_context(|| writing(path))?;
        f.write_all(bytes).with_context(|| writing(path))?;
        done.push((path, f));
    }
    for (path, f) in done {
        f.commit().with_context(|| writing(path))?;
    }
    Ok(())
}

fn writing(path: &Path) -> String {
    format!("cannot write {}", path.display())
}
