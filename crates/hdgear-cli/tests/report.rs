//! The report: built once by the binary (the README's main command), then checked for structure,
//! numbers (against `hdgear table --json`), valid figures, and in a real browser.

use crate::common::hdgear;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The report's figure files, from the library's lists (the study's, the periodic section's).
fn figures() -> Vec<&'static str> {
    hdgear::report::FIGURES
        .iter()
        .map(|f| f.2)
        .chain(hdgear::report::PERIODIC_FIGURES.iter().map(|f| f.1))
        .chain([hdgear::report::control::CONTROL_FIGURE])
        .chain(hdgear::report::robust::ROBUST_FIGURES)
        .chain([hdgear::report::memory::MEMORY_FIGURE])
        .collect()
}

#[test]
fn every_figure_kind_is_in_its_table_line_and_in_the_report() {
    use hdgear::figures::{FigureKind, KINDS};
    for (i, e) in KINDS.iter().enumerate() {
        // `FigureKind::name` looks its line up by discriminant
        assert_eq!(e.kind as usize, i, "{} out of order", e.name);
        assert_eq!(e.name.parse::<FigureKind>().unwrap(), e.kind);
        assert_eq!(
            serde_json::to_value(e.kind).unwrap(),
            serde_json::json!(e.name)
        );
        assert!(
            hdgear::report::FIGURES.iter().any(|f| f.0 == e.kind)
                || hdgear::report::PERIODIC_FIGURES
                    .iter()
                    .any(|f| f.0 == Some(e.kind)),
            "{} not in the report",
            e.name
        );
    }
}

/// Builds the report once per test run.
fn report_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-test");
        let _ = std::fs::remove_dir_all(&dir);
        hdgear()
            .args(["report", "--out"])
            .arg(&dir)
            .assert()
            .success()
            .stderr(predicates::str::contains("index.html"));
        dir
    })
}

/// The report's data file `data/NAME`, parsed.
fn data(name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(report_dir().join("data").join(name)).unwrap())
        .unwrap()
}

fn html() -> String {
    std::fs::read_to_string(report_dir().join("index.html")).unwrap()
}

#[test]
fn report_has_every_section_and_figure_inline() {
    let h = html();
    assert!(h.starts_with("<!DOCTYPE html>"));
    assert!(h.trim_end().ends_with("</html>"));
    for id in [
        "summary",
        "model",
        "corrections",
        "tables",
        "figures",
        "mechanism",
        "physical",
        "periodic",
        "control",
        "robust",
        "memory",
        "methods",
    ] {
        assert!(
            h.contains(&format!("<section id=\"{id}\">")),
            "section {id}"
        );
    }
    for f in figures() {
        let start = h
            .find(&format!("<figure id=\"fig-{f}\""))
            .unwrap_or_else(|| panic!("figure {f}"));
        let end = start + h[start..].find("</figure>").unwrap();
        let block = &h[start..end];
        assert!(
            block.contains("<svg") && block.contains("</svg>"),
            "{f}: inline SVG"
        );
        assert!(block.contains("<figcaption>"), "{f}: caption");
    }
    // self-contained: no script, no remote resource
    assert!(!h.contains("<script"));
    assert!(!h.contains("src=\"http") && !h.contains("href=\"http"));
    // the corrections and the mechanism's evidence are stated
    assert!(h.contains("C<sup>4</sup>"));
    assert!(h.contains("α·ε = 11.36"));
    assert!(h.contains("trace -1"));
}

/// `data-value` of the cell `key` in the row that starts with `row_attr`.
fn cell_value(h: &str, row_attr: &str, key: &str) -> f64 {
    let row = &h[h.find(row_attr).unwrap_or_else(|| panic!("{row_attr}"))..];
    let row = &row[..row.find("</tr>").unwrap()];
    let at = row
        .find(&format!("data-key=\"{key}\" data-value=\""))
        .unwrap_or_else(|| panic!("{row_attr} {key}"));
    let rest = &row[at..];
    let v = rest.split("data-value=\"").nth(1).unwrap();
    v[..v.find('"').unwrap()].parse().unwrap()
}

#[test]
fn report_tables_equal_hdgear_table_json() {
    let h = html();
    let out = hdgear().args(["table", "--json"]).assert().success();
    let t: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    for row in t["gamma_table"].as_array().unwrap() {
        let g = row["gamma"].as_f64().unwrap();
        let attr = format!("<tr data-gamma=\"{g}\">");
        for key in [
            "max_slope",
            "slope_at_a0",
            "bursts_per_period",
            "spikes_per_burst",
            "peak_abs_xdot",
        ] {
            assert_eq!(
                cell_value(&h, &attr, key),
                row[key].as_f64().unwrap(),
                "gamma {g} {key}"
            );
        }
        let mode = row["mode"].as_str().unwrap();
        assert!(h.contains(&format!("<td data-key=\"mode\">{mode}</td>")));
    }
    for row in t["effects_table"].as_array().unwrap() {
        let name = row["parameter"].as_str().unwrap();
        let attr = format!("<tr data-parameter=\"{name}\">");
        for (key, json, i) in [
            ("amplitude_low", "amplitude", 0),
            ("amplitude_high", "amplitude", 1),
            ("spikes_low", "spikes", 0),
            ("quiescent_high", "quiescent_duration", 1),
        ] {
            assert_eq!(
                cell_value(&h, &attr, key),
                row[json][i].as_f64().unwrap(),
                "{name} {key}"
            );
        }
    }
}

/// Every file under `dir`, relative, sorted.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                todo.push(path);
            } else {
                out.push(path.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// `--threads 1` keeps every stage on one thread (the sections computed side by side and the
/// figures drawn side by side run one after the other) and changes no byte of any file: the
/// results do not depend on how the work is split, nor the drawings on the order they are drawn.
#[test]
fn a_one_thread_report_writes_the_same_bytes() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-one-thread");
    let _ = std::fs::remove_dir_all(&dir);
    hdgear()
        .args(["report", "--threads", "1", "--out"])
        .arg(&dir)
        .assert()
        .success();
    let (many, one) = (files_under(report_dir()), files_under(&dir));
    assert_eq!(many, one);
    assert!(many.len() > 40, "{} files", many.len());
    for f in &many {
        let same =
            std::fs::read(report_dir().join(f)).unwrap() == std::fs::read(dir.join(f)).unwrap();
        assert!(same, "{} differs with --threads 1", f.display());
    }
}

fn png_stats(path: &Path) -> (u32, u32, f64) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let bytes = &buf[..info.buffer_size()];
    let channels = info.color_type.samples();
    let px = bytes.len() / channels;
    let non_white = bytes
        .chunks(channels)
        .filter(|c| c.iter().take(3).any(|&v| v < 235))
        .count();
    (info.width, info.height, non_white as f64 / px as f64)
}

#[test]
fn every_figure_file_is_valid_and_not_empty() {
    let dir = report_dir();
    for f in figures() {
        let svg = std::fs::read_to_string(dir.join(format!("figures/{f}.svg"))).unwrap();
        assert!(
            svg.contains("<svg") && svg.trim_end().ends_with("</svg>"),
            "{f}.svg"
        );
        assert!(
            svg.contains("<polyline") || svg.contains("<rect"),
            "{f}.svg draws something"
        );
        let (w, h, ink) = png_stats(&dir.join(format!("figures/{f}.png")));
        assert!(w >= 800 && h >= 400, "{f}.png is {w}x{h}");
        assert!(ink > 0.02, "{f}.png is nearly blank ({ink})");
    }
    for d in [
        "tables.json",
        "tables.csv",
        "sweep-gamma.csv",
        "map-gamma-delta.csv",
    ] {
        assert!(
            std::fs::metadata(dir.join("data").join(d)).unwrap().len() > 100,
            "{d}"
        );
    }
}

#[test]
#[cfg_attr(
    hdgear_no_chromium,
    ignore = "no Chromium on this machine: install chromium or set HDGEAR_CHROMIUM"
)]
fn report_renders_in_headless_chromium() {
    let Some(browser) = crate::common::chromium() else {
        // CI installs Chromium (.ci/run) and must run this test; elsewhere it is optional.
        assert!(
            std::env::var_os("CI").is_none(),
            "CI=true but no Chromium found: .ci/run should install it"
        );
        panic!(
            "no Chromium found: {}",
            if std::env::var_os("CI").is_some() {
                "CI=true, so .ci/run should have installed it"
            } else {
                "the build saw one; set HDGEAR_CHROMIUM to its path"
            }
        );
    };
    let dir = report_dir();
    let profile = tempfile::tempdir().unwrap();
    // (beside the report, not in it: the other report tests list the report's files while this
    // one runs)
    let shot = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-screenshot.png");
    let _ = std::fs::remove_file(&shot);
    let out = std::process::Command::new(&browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1200,3000",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", dir.join("index.html").display()))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "chromium failed: {stderr}");
    let console: Vec<&str> = stderr.lines().filter(|l| l.contains("CONSOLE")).collect();
    assert!(console.is_empty(), "console messages: {console:?}");
    let (w, h, ink) = png_stats(&shot);
    assert_eq!((w, h), (1200, 3000));
    assert!(
        ink > 0.05,
        "the page looks blank: {:.3} of the pixels are not white",
        ink
    );
}

/// The direct check [`hdgear::figures::decimate`] replaced: every point between an anchor and a
/// candidate end measured against the line between them.
fn direct(points: &[(f64, f64)], tol: f64) -> Vec<(f64, f64)> {
    if points.len() < 3 {
        return points.to_vec();
    }
    let mut out = vec![points[0]];
    let mut anchor = 0;
    for i in 2..points.len() {
        let ((x0, y0), (x1, y1)) = (points[anchor], points[i]);
        let ok = (anchor + 1..i).all(|j| {
            let (x, y) = points[j];
            let w = if x1 != x0 { (x - x0) / (x1 - x0) } else { 0.0 };
            (y0 + w * (y1 - y0) - y).abs() <= tol
        });
        if !ok {
            anchor = i - 1;
            out.push(points[anchor]);
        }
    }
    out.push(points[points.len() - 1]);
    out
}

/// The linear-time decimation keeps exactly the points the direct check (every point between an
/// anchor and a candidate end measured against the line between them) keeps, on the kinds of
/// series the figures draw: a ringing signal at the plots' tolerance, a random walk, an S-shaped
/// curve whose x turns back (an equilibrium curve drawn against a), repeated x, a NaN.
#[test]
fn decimation_keeps_the_points_the_direct_check_keeps() {
    use hdgear::figures::decimate;
    let ringing: Vec<(f64, f64)> = (0..20_000)
        .map(|i| {
            let t = 0.05 * f64::from(i);
            (
                t,
                (-t / 300.0).exp() * (0.7 * t).sin() + 0.2 * (0.01 * t).sin(),
            )
        })
        .collect();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut walk = vec![(0.0, 0.0)];
    for i in 1..5000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let step = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let last = walk[walk.len() - 1].1;
        walk.push((
            f64::from(i),
            last + step * if i % 500 < 250 { 1e-3 } else { 1.0 },
        ));
    }
    let s_curve: Vec<(f64, f64)> = (0..4000)
        .map(|i| {
            let x = -1.2 + 2.4 * f64::from(i) / 3999.0;
            (16.0 * x * x * x - 3.0 * x, x)
        })
        .collect();
    let repeated = vec![
        (0.0, 0.0),
        (0.0, 1e-4),
        (1.0, 1.0),
        (1.0, 1.0),
        (2.0, 2.0),
        (2.0, 5.0),
        (3.0, 0.0),
        (4.0, f64::NAN),
        (5.0, 1.0),
        (6.0, 2.0),
    ];
    for (name, points, tol) in [
        ("ringing", &ringing, 1e-3 * 2.4),
        ("random walk", &walk, 1e-2),
        ("S-curve", &s_curve, 1e-3),
        ("repeated x and a NaN", &repeated, 1e-3),
    ] {
        let (fast, slow) = (decimate(points, tol), direct(points, tol));
        eprintln!("{name}: {} points -> {}", points.len(), fast.len());
        assert!(
            fast.len() < points.len() || points.len() < 20,
            "{name}: nothing dropped"
        );
        let same = fast.len() == slow.len()
            && fast
                .iter()
                .zip(&slow)
                .all(|(a, b)| a.0.to_bits() == b.0.to_bits() && a.1.to_bits() == b.1.to_bits());
        assert!(same, "{name}: {} vs {} points", fast.len(), slow.len());
    }
}

/// The control section's numbers are the data file's: each law's least gain at γ = 1 and 0.1
/// removes the bursts, and on the drive each torque is the reduced effort times the printed
/// scale, flagged against the stand-in ratings as its fraction says.
#[test]
fn report_control_section_is_its_data() {
    let h = html();
    let doc = data("control.json");
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let study = doc["study"].as_array().unwrap();
    assert_eq!(study.len(), 2);
    for cmp in study {
        for t in cmp["tunings"].as_array().unwrap() {
            assert_eq!(t["tuned"]["verdict"], "no-bursts");
            let law = t["law"].as_str().unwrap();
            let row = h.find(&format!("<tr data-law=\"{law}\">")).unwrap();
            assert!(h[row..].contains(&format!("data-value=\"{}\"", f(&t["tuned"]["gain"]))));
        }
    }
    let d = &doc["drive"];
    let scale = f(&d["torque_scale"]);
    let rows = d["comparison"]["tunings"].as_array().unwrap();
    let efforts = d["efforts"].as_array().unwrap();
    assert_eq!(efforts.len(), hdgear::control::DEFAULT_LAWS.len());
    for (t, e) in rows.iter().zip(efforts) {
        let u = scale * f(&t["tuned"]["effort_peak"]);
        assert!((f(&e["output_peak"]) / u - 1.0).abs() < 1e-12);
        let of_rated = f(&e["of_rated"]);
        let rated = f(&d["ratings"]["rated"]);
        assert!((of_rated * rated / u - 1.0).abs() < 1e-12);
        // the drive's table is the section's last: its row of this law
        let law = e["law"].as_str().unwrap();
        let at = h.rfind(&format!("<tr data-law=\"{law}\">")).unwrap();
        let row = &h[at..at + h[at..].find("</tr>").unwrap()];
        assert!(
            row.contains(&format!("data-value=\"{}\"", f(&e["output_peak"]))),
            "{row}"
        );
        assert_eq!(row.contains("above"), of_rated > 1.0, "{row}");
    }
}

/// The spread section's numbers are its data file's, and its P(burst) is what `hdgear physical
/// --robust` computes for the same drive and samples (the section's drive is the report's
/// catalogue drive with k1 = 2000 N m/rad, T_am = 22 N m).
#[test]
fn report_robust_section_is_its_data() {
    let h = html();
    let doc = data("robust.json");
    let a = &doc["analysis"];
    let p = a["probability"]["p"].as_f64().unwrap();
    let section = &h[h.find("<section id=\"robust\">").unwrap()..];
    assert!(section.contains(&format!("data-key=\"p\" data-value=\"{p}\"")));
    let sens = &a["sensitivity"];
    let names = sens["parameters"].as_array().unwrap();
    let burst = &sens["measures"][0];
    assert_eq!(burst[0], "burst");
    for (i, n) in names.iter().enumerate() {
        let v = burst[1]["total"][i]["value"].as_f64().unwrap();
        let key = format!(
            "data-key=\"total-{}\" data-value=\"{v}\"",
            n.as_str().unwrap()
        );
        assert!(section.contains(&key), "{key}");
    }
    let (k1, t_am) = hdgear::report::robust::ROBUST_DRIVE;
    let samples = hdgear::report::robust::ROBUST_SAMPLES.0.to_string();
    let cli = crate::common::json_of(&[
        "physical",
        "--k1",
        &k1.to_string(),
        "--t-am",
        &t_am.to_string(),
        "--robust",
        "--samples",
        &samples,
        "--no-worst",
        "--json",
    ]);
    assert_eq!(cli["probability"], a["probability"]);
    assert!(p > 0.05 && p < 0.5, "the drive is near its boundary: {p}");
}

/// The memory section's rows are its data file's: each case's verdict, and its worst distance
/// of a burst's onset from the branches' prediction recomputed from the onsets listed (within
/// the 15 % of the load's range where bursts are not slips); and `hdgear bursts` gives
/// each case's model, written as a scenario file, the same verdict.
#[test]
fn report_memory_section_is_its_data() {
    use hdgear::report::memory::MEMORY_CASES;
    let h = html();
    let doc = data("memory.json");
    let cases = doc["cases"].as_array().unwrap();
    assert_eq!(cases.len(), MEMORY_CASES.len());
    let section = &h[h.find("<section id=\"memory\">").unwrap()..];
    let dir = tempfile::tempdir().unwrap();
    for (i, (c, (gamma, kind, values, _))) in cases.iter().zip(MEMORY_CASES).enumerate() {
        let at = section.find(&format!("<tr data-case=\"{i}\">")).unwrap();
        let row = &section[at..at + section[at..].find("</tr>").unwrap()];
        let verdict = c["classification"]["verdict"].as_str().unwrap();
        assert!(row.contains(&format!("<td>{verdict}</td>")), "{row}");
        let worst = c["onsets"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|o| Some((o["a"].as_f64()? - o["predicted"].as_f64()?).abs()))
            .fold(0.0, f64::max);
        if c["sticking"]["slip_dominates"] == true {
            assert_eq!(verdict, "stick-slip");
            assert!(row.contains("data-value=\"NaN\""), "{row}");
        } else {
            assert!(worst > 0.0 && worst <= 0.15, "case {i}: {worst}");
            assert!(row.contains(&format!("data-value=\"{worst}\"")), "{row}");
        }
        // the same model from a scenario file, judged by `hdgear bursts`
        let term = hdgear::model::terms::AnyTerm::new(kind, values).unwrap();
        let keys: String = term
            .params()
            .iter()
            .zip(values)
            .map(|(p, v)| format!("{} = {v:?}\n", p.name))
            .collect();
        let scenario = dir.path().join(format!("case{i}.toml"));
        std::fs::write(
            &scenario,
            format!("[params]\ngamma = {gamma:?}\n\n[{kind}]\n{keys}"),
        )
        .unwrap();
        let out = dir.path().join(format!("case{i}.json"));
        hdgear()
            .args(["--quiet", "bursts", "--config"])
            .arg(&scenario)
            .arg("--out")
            .arg(&out)
            .assert()
            .success();
        let bursts: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(
            bursts["meta"]["classification"]["verdict"], verdict,
            "case {i}"
        );
    }
}

/// The physical section judges its drive with the catalogue's own curve too: the verdicts,
/// overshoot and swing it states are what `curve_law::check` gives for the same card and drive,
/// with the corners and with the illustrated knee rounding, and the rounding's passage is
/// x_r·k₁/(δω) torsional periods 2π/√k₁, computed here from the reduced law.
#[test]
fn report_physical_section_judges_the_catalogue_curve() {
    use hdgear::physical::{card::builtin_card, catalogue::preset, curve_law};
    let h = html();
    let name = hdgear::report::PHYSICAL_DRIVE;
    let (drive, _) = preset(name, None).unwrap();
    let opts = hdgear::burst::BurstOptions::default();
    let check = |rounding| curve_law::check(builtin_card(name).unwrap(), &drive, rounding, &opts);
    let law = check(0.0).unwrap();
    let o = law.outcome.unwrap();
    // CSF-20-50's mean load sits on its first knee: the corner makes it burst
    assert!(o.judgement.bursting);
    let at = h.find("With the catalogue's own curve").unwrap();
    let p = &h[at..at + h[at..].find("</p>").unwrap()];
    let sig = law.signatures.unwrap();
    let stated = format!(
        "the same drive bursts ({}, largest overshoot {:.1e} of the slow swing X, ringing swing \
         {:.3} ωX)",
        o.judgement.label(),
        sig.max_overshoot,
        sig.max_ringing_swing
    );
    assert!(p.contains(&stated), "{p}");
    let rounded = check(curve_law::ILLUSTRATED_ROUNDING).unwrap();
    let r = drive.reduce().unwrap().params;
    let (k1, xr) = (rounded.reduced[0], rounded.reduced[6]);
    let passage = xr * k1 / (r.delta * r.omega) * k1.sqrt() / std::f64::consts::TAU;
    let ro = rounded.outcome.unwrap();
    let verdict = if ro.judgement.bursting {
        "bursts"
    } else {
        "does not burst"
    };
    let stated = format!(
        "which the slow load passes in {passage:.2} torsional periods, it {verdict} ({}",
        ro.judgement.label()
    );
    assert!(p.contains(&stated), "{stated} not in {p}");
}
