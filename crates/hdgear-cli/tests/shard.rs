//! Sharded sweeps: the interleaved split, `sweep --shard`, `merge` (byte-identical to one run;
//! missing, duplicated, foreign, edited and unfinished shards refused with a one-line message
//! and no output), resuming a shard, and the `--slurm` scripts run by hand as SLURM would run
//! them. The run on a real cluster is `scripts/slurm-local.sh` (in `.ci/run`).

use crate::common::{files_in, hdgear};
use hdgear::sweep::{Axis, Grid, Settings, Shard, plan};
use std::path::Path;
use std::process::Command;

/// A small grid whose rows hold every kind of value: finite numbers, NaN (failed points, with
/// an error message with commas and quotes), ∞ (max_slope with folds).
const GRID: [&str; 4] = [
    "--param",
    "gamma=0.001:0.1:3:log",
    "--param",
    "omega=1e-9:0.01:2:log",
];

fn sweep(dir: &Path, extra: &[&str]) -> std::process::Output {
    hdgear()
        .current_dir(dir)
        .arg("sweep")
        .args(GRID)
        .args(extra)
        .arg("--quiet")
        .output()
        .unwrap()
}

fn merge(dir: &Path, args: &[&str]) -> std::process::Output {
    hdgear()
        .current_dir(dir)
        .arg("merge")
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs the shards `ks` of `n` into `NAME.shard-K-of-N.csv`.
fn shards(dir: &Path, name: &str, n: usize, ks: &[usize], extra: &[&str]) {
    for k in ks {
        let shard = format!("{k}/{n}");
        let out = sweep(dir, &[&["--out", name, "--shard", &shard], extra].concat());
        assert!(out.status.success(), "{}", stderr(&out));
    }
}

#[test]
fn shards_partition_the_grid_and_interleave() {
    for len in [1, 5, 6, 1000] {
        for n in 1..=len.min(9) {
            let mut seen = vec![0; len];
            for index in 0..n {
                let s = Shard { index, count: n };
                let idx: Vec<usize> = s.indices(len).collect();
                assert_eq!(idx.len(), s.len(len));
                assert!(idx.windows(2).all(|w| w[1] - w[0] == n), "interleaved");
                idx.iter().for_each(|&i| seen[i] += 1);
            }
            assert!(seen.iter().all(|&c| c == 1), "len {len}, {n} shards");
        }
    }
    for (text, needle) in [
        ("3", "expected K/N"),
        ("4/4", "0 ≤ K ≤ 3"),
        ("-1/4", "'-1' is not a whole number"),
        ("1/0", "N must be ≥ 1"),
        ("a/b", "'a' is not a whole number"),
    ] {
        let e = Shard::parse(text).unwrap_err().to_string();
        assert!(e.contains(needle) && e.contains(text), "{text}: {e}");
    }
}

#[test]
fn merged_shards_equal_one_run_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for out in ["one.csv", "one.json"] {
        assert!(sweep(d, &["--out", out]).status.success());
    }
    let one = std::fs::read(d.join("one.csv")).unwrap();
    let text = String::from_utf8_lossy(&one);
    assert!(text.contains("NaN") && text.contains("inf") && text.contains("\"the run spans"));
    // 4 shards of 6 points (2, 2, 1, 1 rows), given to merge in another order
    shards(d, "s.csv", 4, &[2, 0, 3, 1], &[]);
    let given = [
        "s.shard-3-of-4.csv",
        "s.shard-1-of-4.csv",
        "s.shard-0-of-4.csv",
        "s.shard-2-of-4.csv",
    ];
    let o = merge(d, &given);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("wrote s.csv: 6 rows from 4 shards, 3 failed"));
    assert_eq!(std::fs::read(d.join("s.csv")).unwrap(), one, "CSV");
    let o = merge(d, &[&given[..], &["--out", "s.json"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.join("s.json")).unwrap(),
        std::fs::read(d.join("one.json")).unwrap(),
        "JSON"
    );
    // one shard: the whole grid
    shards(d, "w.csv", 1, &[0], &[]);
    assert!(merge(d, &["w.shard-0-of-1.csv"]).status.success());
    assert_eq!(std::fs::read(d.join("w.csv")).unwrap(), one);
}

/// Merges that must be refused: exit 2, one line naming the problem, no output file.
fn refused(dir: &Path, args: &[&str], needle: &str) {
    let before = files_in(dir);
    let o = merge(dir, args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(
        err.contains(needle),
        "{args:?}: expected '{needle}' in: {err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(files_in(dir), before, "{args:?} left a file");
}

#[test]
fn merge_refuses_missing_duplicated_and_foreign_shards() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    shards(d, "s.csv", 3, &[0, 1, 2], &[]);
    shards(d, "t.csv", 3, &[1], &["--rtol", "1e-8"]);
    shards(d, "u.csv", 2, &[1], &[]);
    let (s0, s1, s2) = (
        "s.shard-0-of-3.csv",
        "s.shard-1-of-3.csv",
        "s.shard-2-of-3.csv",
    );
    refused(
        d,
        &[s0, s2],
        "shard 1 of 3 missing: rerun the sweep for it (--shard 1/3)",
    );
    refused(d, &[s2], "shards 0, 1 of 3 missing");
    refused(d, &[s0, s1, s2, s1], "shard 1/3 is given twice");
    std::fs::copy(d.join(s1), d.join("copy.csv")).unwrap();
    refused(
        d,
        &[s0, s1, s2, "copy.csv"],
        "is given twice: s.shard-1-of-3.csv and copy.csv",
    );
    refused(
        d,
        &[s0, "t.shard-1-of-3.csv", s2],
        "t.shard-1-of-3.csv is not a shard of the same sweep as s.shard-0-of-3.csv: options.tol.rtol is 1e-8 there and 1e-10",
    );
    refused(
        d,
        &[s0, "u.shard-1-of-2.csv", s2],
        "shard.count is 2 there and 3",
    );
    // another grid
    let o = hdgear()
        .current_dir(d)
        .args([
            "sweep",
            "--param",
            "gamma=0.001:0.1:4:log",
            "--out",
            "g.csv",
            "--shard",
            "1/3",
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    refused(d, &[s0, "g.shard-1-of-3.csv", s2], "grid.axes");
    // a whole sweep's output, and a file that is not a sweep's
    assert!(sweep(d, &["--out", "whole.csv"]).status.success());
    refused(d, &[s0, "whole.csv"], "whole.csv is not a sweep's row file");
    refused(
        d,
        &["nope.shard-0-of-1.csv"],
        "cannot read nope.shard-0-of-1.csv",
    );
    refused(
        d,
        &[s0, s1, s2, "--out", "m.txt"],
        "the extension must be .csv, .json or .parquet",
    );
    refused(
        d,
        &["x.csv"],
        "cannot tell the merged file's name from 'x.csv'",
    );
}

/// Rewrites a shard file's rows through `edit` (the settings line and header stay).
fn edit_rows(path: &Path, edit: impl FnOnce(&mut Vec<String>)) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut rows = lines.split_off(2);
    edit(&mut rows);
    lines.extend(rows);
    std::fs::write(path, lines.join("\n") + "\n").unwrap();
}

#[test]
fn merge_refuses_edited_and_unfinished_shard_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let names: Vec<String> = (0..2).map(|k| format!("s.shard-{k}-of-2.csv")).collect();
    let args: Vec<&str> = names.iter().map(String::as_str).collect();
    type Edit = fn(&mut Vec<String>);
    let cases: [(&str, Edit); 5] = [
        (
            "ends before grid point 5 of shard 1/2: resume that shard to finish it (--shard 1/2 --resume)",
            |r| {
                r.pop();
            },
        ),
        (
            "expected the row of grid point 1 next, found grid point 3",
            |r| {
                r.remove(0);
            },
        ),
        ("has rows after the last grid point of its shard", |r| {
            let last = r.last().unwrap().clone();
            r.push(last);
        }),
        ("row 1 has alpha = 17.0 (the grid has 16.0 there)", |r| {
            r[0] = r[0].replacen(",16.0,", ",17.0,", 1);
        }),
        ("row 1 is unreadable", |r| r[0] = "1,x".into()),
    ];
    for (needle, edit) in cases {
        shards(d, "s.csv", 2, &[0, 1], &[]);
        edit_rows(&d.join(&names[1]), edit);
        refused(d, &args, needle);
    }
}

#[test]
fn an_interrupted_shard_resumes_and_merges() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let grid = [
        "sweep",
        "--param",
        "gamma=0.1:30:3000:log",
        "--threads",
        "1",
        "--quiet",
    ];
    let whole = tempfile::tempdir().unwrap();
    let o = hdgear()
        .current_dir(whole.path())
        .args(grid)
        .args(["--out", "s.csv"])
        .output()
        .unwrap();
    assert!(o.status.success());
    // shard 1 of 2, stopped part-way by SIGTERM, keeps its rows in the partial file
    let child = Command::new(assert_cmd::cargo::cargo_bin("hdgear"))
        .current_dir(d)
        .args(grid)
        .args(["--out", "s.csv", "--shard", "1/2"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // stopped once rows are in the partial file (polled: a fixed wait raced the run once the
    // sweep got fast enough to finish a shard inside it)
    let partial = d.join("s.shard-1-of-2.csv.partial");
    let started = std::time::Instant::now();
    while std::fs::read_to_string(&partial).map_or(0, |t| t.lines().count()) < 3 {
        assert!(
            started.elapsed() < std::time::Duration::from_secs(30),
            "no rows written"
        );
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    assert!(
        Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status()
            .unwrap()
            .success()
    );
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(143), "{}", stderr(&out));
    assert_eq!(files_in(d), ["s.shard-1-of-2.csv.partial"]);
    // other settings are refused on resume
    let o = hdgear()
        .current_dir(d)
        .args(grid)
        .args([
            "--out", "s.csv", "--shard", "1/2", "--resume", "--rtol", "1e-9",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    for k in ["1/2", "0/2"] {
        let o = hdgear()
            .current_dir(d)
            .args(grid)
            .args(["--out", "s.csv", "--shard", k, "--resume"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = merge(d, &["s.shard-0-of-2.csv", "s.shard-1-of-2.csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.join("s.csv")).unwrap(),
        std::fs::read(whole.path().join("s.csv")).unwrap()
    );
}

#[test]
fn slurm_scripts_run_as_slurm_would_run_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = sweep(
        d,
        &[
            "--out",
            "map.json",
            "--slurm",
            "3",
            "--time",
            "5:00",
            "--partition",
            "short",
            "--cpus-per-task",
            "2",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let printed = String::from_utf8_lossy(&o.stdout);
    assert!(
        printed.starts_with("jid=$(sbatch --parsable ")
            && printed.contains("--dependency=afterok:${jid%%;*}"),
        "{printed}"
    );
    assert_eq!(
        files_in(d),
        [
            "map.slurm-array.sh",
            "map.slurm-merge.sh",
            "map.slurm-submit.sh"
        ]
    );
    let array = std::fs::read_to_string(d.join("map.slurm-array.sh")).unwrap();
    for line in [
        "#SBATCH --array=0-2",
        "#SBATCH --cpus-per-task=2",
        "#SBATCH --time=5:00",
        "#SBATCH --partition=short",
        "--shard \"${SLURM_ARRAY_TASK_ID}/3\"",
        "--threads \"${SLURM_CPUS_PER_TASK:-2}\"",
        // sbatch expands the task's %a; the user's path is not expanded
        "map.shard-%a-of-3.log\"",
    ] {
        assert!(array.contains(line), "{line} not in {array}");
    }
    let submit = std::fs::read_to_string(d.join("map.slurm-submit.sh")).unwrap();
    // a `%` in the user's directory is doubled for sbatch, the task pattern is not
    let pct = d.join("at %x");
    std::fs::create_dir(&pct).unwrap();
    let o = sweep(&pct, &["--out", "map.json", "--slurm", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(pct.join("map.slurm-array.sh")).unwrap();
    assert!(text.contains("at %%x/map.shard-%a-of-2.log\""), "{text}");
    let text = std::fs::read_to_string(pct.join("map.slurm-merge.sh")).unwrap();
    assert!(text.contains("at %%x/map.merge.log\""), "{text}");
    assert!(
        submit.contains("--dependency=afterok:\"$array\""),
        "{submit}"
    );
    // each array task, as SLURM starts it (its environment), from another directory
    for k in 0..3 {
        let o = Command::new("bash")
            .arg(d.join("map.slurm-array.sh"))
            .current_dir("/")
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .env("SLURM_CPUS_PER_TASK", "1")
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = Command::new("bash")
        .arg(d.join("map.slurm-merge.sh"))
        .current_dir("/")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(sweep(d, &["--out", "one.json"]).status.success());
    assert_eq!(
        std::fs::read(d.join("map.json")).unwrap(),
        std::fs::read(d.join("one.json")).unwrap()
    );
}

#[test]
fn bad_cluster_settings_are_refused_before_any_file() {
    let e = tempfile::tempdir().unwrap();
    for (extra, needle) in [
        (&["--slurm", "0"][..], "invalid --slurm 0"),
        (&["--slurm", "7"][..], "7 shards of a grid of 6 points"),
        (
            &["--slurm", "2", "--time", "1;rm -rf ~"][..],
            "invalid --time '1;rm -rf ~'",
        ),
        (
            &["--slurm", "2", "--partition", "a b"][..],
            "invalid --partition 'a b'",
        ),
        (
            &["--slurm", "2", "--cpus-per-task", "0"][..],
            "invalid --cpus-per-task 0",
        ),
        (&["--shard", "0/7"][..], "7 shards of a grid of 6 points"),
        (&["--time", "5"][..], "--slurm"),
        (
            &["--slurm", "2", "--shard", "0/2"][..],
            "cannot be used with",
        ),
    ] {
        let o = sweep(e.path(), &[&["--out", "m.csv"], extra].concat());
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        assert!(err.contains(needle), "{extra:?}: {err}");
        assert!(files_in(e.path()).is_empty(), "{extra:?}");
    }
}

#[test]
fn plan_checks_settings_before_rows() {
    let grid = Grid::new(
        Default::default(),
        vec![Axis::parse("gamma=0.1:1:7").unwrap()],
    )
    .unwrap();
    let whole = Settings::new(&grid, &Default::default());
    let part = |k: usize, n: usize| {
        (
            format!("p{k}"),
            whole.clone().with_shard(Some(Shard { index: k, count: n })),
        )
    };
    assert_eq!(
        plan(vec![]).unwrap_err().to_string(),
        "no shard files given"
    );
    assert!(matches!(
        plan(vec![part(0, 2), ("w".into(), whole.clone())]),
        Err(hdgear::sweep::MergeError::NotAShard { .. })
    ));
    let p = plan(vec![part(1, 2), part(0, 2)]).unwrap();
    assert_eq!(p.settings(), &whole);
    // rows from in-memory "files": grid point i from shard i mod 2
    let row = |i: usize| hdgear::sweep::run_point(i, &grid.point(i), &Default::default());
    let files: Vec<_> = [1, 0]
        .map(|k: usize| {
            Shard { index: k, count: 2 }
                .indices(grid.len())
                .map(|i| Ok::<_, hdgear::sweep::MergeError>(row(i)))
                .collect::<Vec<_>>()
                .into_iter()
        })
        .into();
    let mut got = Vec::new();
    let n = p.merge(files, |r| {
        got.push(r.index);
        Ok::<_, hdgear::sweep::MergeError>(())
    });
    assert_eq!(n.unwrap(), 7);
    assert_eq!(got, (0..7).collect::<Vec<_>>());
}
