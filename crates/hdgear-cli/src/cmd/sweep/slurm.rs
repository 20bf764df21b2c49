//! `hdgear sweep … --slurm N`: writes (does not submit) the scripts that run a sweep as a SLURM
//! job array of N shards and merge them after all succeed, and prints the `sbatch` command.
//!
//! For `--out DIR/NAME.EXT` it writes, next to the output:
//! - `NAME.slurm-array.sh`: the job array (`--array=0-(N-1)`); task K runs
//!   `hdgear sweep … --shard K/N --threads $SLURM_CPUS_PER_TASK --resume` (a requeued task
//!   continues from its partial file), logging to `NAME.shard-K-of-N.log`;
//! - `NAME.slurm-merge.sh`: `hdgear merge` of the N shard files into `DIR/NAME.EXT`;
//! - `NAME.slurm-submit.sh`: submits the array, then the merge with `--dependency=afterok`.
//!
//! The scripts call this binary by its absolute path and name every file absolutely, so the
//! binary and the output directory must be on a file system the compute nodes share (as a
//! cluster's home or project directories are). The sweep's arguments are written from its checked
//! settings (every parameter, axis and option explicitly, floats to the last bit), not copied
//! from the command line, and then parsed back and checked to give the same settings: a scenario
//! file or preset need not exist on the cluster, and the shards cannot compute anything else.

use super::SweepArgs;
use super::{Job, check, shard_path};
use anyhow::{Context, Result, bail};
use clap::Parser;
use hdgear::output::AtomicFile;
use hdgear::params::Param;
use hdgear::sweep::Shard;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Checked job-array settings.
pub struct Cluster {
    /// Shards (array tasks).
    shards: usize,
    /// CPUs (worker threads) per shard.
    cpus: usize,
    /// `#SBATCH` lines shared by both jobs (partition, time).
    extra: Vec<String>,
}

/// Checks a SLURM value against the characters it may hold (it goes into a `#SBATCH` line).
fn slurm_value(flag: &str, v: &str, allowed: impl Fn(char) -> bool, what: &str) -> Result<()> {
    if v.is_empty() || !v.chars().all(allowed) {
        bail!("invalid {flag} '{v}': expected {what}");
    }
    Ok(())
}

impl Cluster {
    /// Checks `--slurm N` and its companions against the grid.
    pub fn check(a: &SweepArgs, shards: usize) -> Result<Cluster> {
        let cpus = a.cpus_per_task.unwrap_or(1);
        if shards == 0 {
            bail!("invalid --slurm 0: give the number of shards (≥ 1)");
        }
        if cpus == 0 {
            bail!("invalid --cpus-per-task 0: must be ≥ 1");
        }
        let mut extra = Vec::new();
        if let Some(p) = &a.partition {
            slurm_value(
                "--partition",
                p,
                |c| c.is_ascii_alphanumeric() || "-_.,".contains(c),
                "a partition name (letters, digits, - _ . ,)",
            )?;
            extra.push(format!("#SBATCH --partition={p}"));
        }
        if let Some(t) = &a.time {
            slurm_value(
                "--time",
                t,
                |c| c.is_ascii_digit() || ":-".contains(c),
                "a SLURM time such as 30, 30:00, 2:00:00 or 1-12:00:00",
            )?;
            extra.push(format!("#SBATCH --time={t}"));
        }
        Ok(Cluster {
            shards,
            cpus,
            extra,
        })
    }
}

/// A log path as the value of an `#SBATCH --output` line: in double quotes (sbatch reads them, so
/// a space is kept), the user's path `p` with `%` doubled (sbatch expands `%j`, `%a`, … in file
/// names; `%%` is a `%`), then `pattern`, which hdgear writes and sbatch is meant to expand (such
/// as `%a` for the array task). Paths with a double quote or a line break are refused before
/// anything is written ([`check_path`]).
fn sbatch_log(p: &Path, pattern: &str) -> String {
    format!(
        "\"{}{pattern}\"",
        p.display().to_string().replace('%', "%%")
    )
}

/// Refuses a path that cannot be written into an `#SBATCH` line.
fn check_path(p: &Path) -> Result<()> {
    let text = p.display().to_string();
    if text.contains(['"', '\n', '\r']) {
        bail!(
            "invalid option --out '{}': with --slurm the path may not hold a double quote or a \
             line break (it goes into an #SBATCH line)",
            text.escape_debug()
        );
    }
    Ok(())
}

/// `text` as one word of a POSIX shell: as it is when it holds only characters no shell
/// interprets, quoted otherwise (for messages a user pastes).
pub(crate) fn shell_word(text: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "._/-+=:,@".contains(c);
    if !text.is_empty() && text.chars().all(plain) {
        text.to_string()
    } else {
        quote(text)
    }
}

/// `text` quoted for a POSIX shell.
fn quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

/// The arguments of `hdgear sweep` that compute `job`'s grid with its options, from the checked
/// settings, without --out, --shard and --threads.
fn sweep_args(job: &Job) -> Vec<String> {
    let s = &job.settings;
    let (p, o) = (s.grid.base, s.options);
    let mut v: Vec<String> = vec!["sweep".into()];
    for q in Param::ALL {
        v.extend([format!("--{}", q.name()), format!("{:?}", p.value(q))]);
    }
    for (flag, value) in [
        ("--discard", o.discard_periods),
        ("--rtol", o.tol.rtol),
        ("--atol", o.tol.atol),
    ] {
        v.extend([flag.to_string(), format!("{value:?}")]);
    }
    v.extend(["--window-periods".into(), o.periods.to_string()]);
    v.extend(["--method".into(), o.tol.method.to_string()]);
    for ax in &s.grid.axes {
        let log = if ax.log { ":log" } else { "" };
        v.extend([
            "--param".into(),
            format!("{}={:?}:{:?}:{}{log}", ax.param, ax.start, ax.end, ax.count),
        ]);
    }
    v
}

/// The job script's command line, `hdgear sweep …`, parsed as the command's own arguments.
#[derive(Parser)]
#[command(name = "hdgear")]
enum SweepLine {
    Sweep(SweepArgs),
}

/// Parses the shard command back and checks that it computes `job`'s settings.
fn verify(job: &Job, args: &[String], out: &Path, count: usize) -> Result<()> {
    for index in [0, count - 1] {
        let shard = Shard { index, count };
        let mut argv = vec!["hdgear".to_string()];
        argv.extend(args.iter().cloned());
        argv.extend([
            "--out".into(),
            out.display().to_string(),
            "--shard".into(),
            shard.to_string(),
        ]);
        let SweepLine::Sweep(a) =
            SweepLine::try_parse_from(&argv).context("the job script's sweep arguments")?;
        let want = job.settings.clone().with_shard(Some(shard));
        if let Some(d) = check(&a)?.settings.first_difference(&want) {
            bail!(
                "cannot write the job scripts: their arguments would compute other settings \
                 ({} is {} there, {} here); please report this",
                d.key,
                d.here,
                d.there
            );
        }
    }
    Ok(())
}

/// The three scripts' paths: array, merge, submit.
fn script_paths(out: &Path) -> [PathBuf; 3] {
    let stem = out.file_stem().unwrap_or_default().to_string_lossy();
    ["array", "merge", "submit"].map(|k| out.with_file_name(format!("{stem}.slurm-{k}.sh")))
}

/// What the three scripts are made of.
struct Scripts<'a> {
    job: &'a Job,
    cluster: &'a Cluster,
    /// The merged output, absolute.
    out: PathBuf,
    /// This binary, absolute.
    exe: PathBuf,
    /// array, merge, submit.
    paths: [PathBuf; 3],
}

impl Scripts<'_> {
    fn n(&self) -> usize {
        self.cluster.shards
    }

    fn stem(&self) -> String {
        self.out
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned()
    }

    /// The lines every job script starts with.
    fn head(&self, name: String, log: String, cpus: usize) -> Vec<String> {
        let mut h = vec![
            "#!/bin/bash".to_string(),
            format!(
                "# Written by hdgear {} (hdgear sweep --slurm {}). Submit with: bash {}",
                env!("CARGO_PKG_VERSION"),
                self.n(),
                qp(&self.paths[2])
            ),
            format!("#SBATCH --job-name={name}"),
            "#SBATCH --ntasks=1".into(),
            format!("#SBATCH --cpus-per-task={cpus}"),
            format!("#SBATCH --output={log}"),
        ];
        h.extend(self.cluster.extra.iter().cloned());
        h.push("set -euo pipefail".into());
        h
    }

    fn job_name(&self) -> String {
        let stem: String = self
            .stem()
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
            .collect();
        format!("hdgear-{stem}")
    }

    /// The job array: task K computes shard K.
    fn array(&self, args: &[String]) -> Vec<String> {
        let (n, cpus) = (self.n(), self.cluster.cpus);
        let prefix = self.out.with_file_name(format!("{}.shard-", self.stem()));
        let log = sbatch_log(&prefix, &format!("%a-of-{n}.log"));
        let mut a = self.head(self.job_name(), log, cpus);
        a.insert(3, format!("#SBATCH --array=0-{}", n - 1));
        a.push(format!(
            "exec {} {} --out {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{n}\" \
             --threads \"${{SLURM_CPUS_PER_TASK:-{cpus}}}\" --resume",
            qp(&self.exe),
            args.iter().map(|s| quote(s)).collect::<Vec<_>>().join(" "),
            qp(&self.out),
        ));
        a
    }

    /// The merge job.
    fn merge(&self) -> Vec<String> {
        let n = self.n();
        let log = sbatch_log(
            &self
                .out
                .with_file_name(format!("{}.merge.log", self.stem())),
            "",
        );
        let mut m = self.head(format!("{}-merge", self.job_name()), log, 1);
        let shards: Vec<String> = (0..n)
            .map(|index| qp(&shard_path(&self.out, Shard { index, count: n })))
            .collect();
        m.push(format!(
            "exec {} merge {} --out {}",
            qp(&self.exe),
            shards.join(" "),
            qp(&self.out)
        ));
        m
    }

    /// The submission: the array, then the merge after all its tasks succeed.
    fn submit(&self) -> Vec<String> {
        let [array, merge, _] = &self.paths;
        let (n, out) = (self.n(), self.out.display());
        vec![
            "#!/bin/bash".to_string(),
            format!(
                "# Submits the {n} shards of the sweep into {out} as a SLURM job array, and the \
                 merge job to run after all of them succeed."
            ),
            "set -euo pipefail".into(),
            format!("array=$(sbatch --parsable {})", qp(array)),
            "array=${array%%;*}".into(),
            format!(
                "merge=$(sbatch --parsable --dependency=afterok:\"$array\" {})",
                qp(merge)
            ),
            "merge=${merge%%;*}".into(),
            format!(
                "echo \"submitted job array $array ({n} shards) and merge job $merge: they \
                 write {out}\""
            ),
        ]
    }
}

/// A path quoted for a POSIX shell.
fn qp(p: &Path) -> String {
    quote(&p.display().to_string())
}

/// Writes the scripts of `job` as `cluster` says, and prints the sbatch command.
pub fn write(job: &Job, cluster: &Cluster) -> Result<()> {
    let n = cluster.shards;
    if n > job.settings.grid.len() {
        bail!(
            "invalid --slurm {n}: {n} shards of a grid of {} points would leave some empty",
            job.settings.grid.len()
        );
    }
    let out = std::path::absolute(&job.out).context("--out")?;
    let args = sweep_args(job);
    verify(job, &args, &out, n)?;
    let s = Scripts {
        job,
        cluster,
        exe: std::env::current_exe().context("cannot find the hdgear binary's path")?,
        paths: script_paths(&out),
        out,
    };
    // the logs named in the #SBATCH lines are siblings of --out, with its stem
    check_path(&s.out)?;
    for p in &s.paths {
        hdgear::output::check_output_path(p)?;
    }
    // all three or none
    let mut files = Vec::new();
    for (path, lines) in s.paths.iter().zip([s.array(&args), s.merge(), s.submit()]) {
        let mut f = AtomicFile::create(path)?;
        f.write_all((lines.join("\n") + "\n").as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        files.push(f);
    }
    for f in files {
        f.commit()?;
    }
    let [array, merge, submit] = &s.paths;
    eprintln!(
        "wrote {}, {} and {} ({n} shards of {} points); submit with: bash {}",
        array.display(),
        merge.display(),
        submit.display(),
        s.job.settings.grid.len(),
        qp(submit)
    );
    crate::sink::outln!(
        "jid=$(sbatch --parsable {}) && sbatch --dependency=afterok:${{jid%%;*}} {}",
        qp(array),
        qp(merge)
    );
    Ok(())
}
