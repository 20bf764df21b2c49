//! `hdgear export fmu`: the archive, its description derived from the drive's parameter table
//! (the same names as `hdgear physical`'s flags), the reference result against `physical
//! --simulate`, and refusals that leave nothing behind. FMPy's own checks of the FMU are
//! `crates/hdgear-fmu/tests/test_fmu.py` (scripts/fmu-tests.sh).

use crate::common::{fails_with, files_in, hdgear, stdout_of};
use hdgear::physical::DriveParam;

/// The entries of a stored ZIP archive (what `output::zip::stored` writes): name and bytes,
/// read from the local headers.
fn entries(zip: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut at = 0;
    let u16_at = |i: usize| u16::from_le_bytes([zip[i], zip[i + 1]]) as usize;
    let u32_at = |i: usize| u32::from_le_bytes(zip[i..i + 4].try_into().unwrap()) as usize;
    while zip[at..].starts_with(b"PK\x03\x04") {
        assert_eq!(u16_at(at + 8), 0, "stored, not compressed");
        let (size, name_len, extra) = (u32_at(at + 18), u16_at(at + 26), u16_at(at + 28));
        let name = String::from_utf8(zip[at + 30..at + 30 + name_len].to_vec()).unwrap();
        let data = at + 30 + name_len + extra;
        out.push((name, zip[data..data + size].to_vec()));
        at = data + size;
    }
    out
}

#[test]
fn the_archive_holds_the_description_the_library_and_the_resources() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = dir.path().join("drive.fmu");
    let said = stdout_of(&["export", "fmu", "--out", fmu.to_str().unwrap()]);
    assert!(
        said.contains("10 parameters, 2 inputs, 7 outputs"),
        "{said}"
    );
    assert_eq!(
        files_in(dir.path()),
        [
            "drive.fmu",
            "drive_in.csv",
            "drive_ref.csv",
            "drive_ref.opt"
        ]
    );
    let zip = std::fs::read(&fmu).unwrap();
    let e = entries(&zip);
    let names: Vec<&str> = e.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "modelDescription.xml",
            "binaries/linux64/hdgear_fmu.so",
            "resources/drive.json"
        ]
    );
    let xml = String::from_utf8(e[0].1.clone()).unwrap();
    assert!(e[1].1.starts_with(b"\x7fELF"));
    // the GUID of the description is the one the resources carry
    let json: serde_json::Value = serde_json::from_slice(&e[2].1).unwrap();
    let guid = json["guid"].as_str().unwrap();
    assert!(xml.contains(&format!("guid=\"{guid}\"")));
    // one parameter per drive parameter, named as `hdgear physical`'s flag is, with the
    // drive's value as its start (the same table: DriveParam)
    let physical_help = stdout_of(&["physical", "--help"]);
    let export_help = stdout_of(&["export", "fmu", "--help"]);
    for p in DriveParam::ALL {
        let flag = format!("--{}", p.name().replace('_', "-"));
        assert!(physical_help.contains(&flag), "{flag} in physical --help");
        assert!(export_help.contains(&flag), "{flag} in export fmu --help");
        let row = xml
            .lines()
            .find(|l| l.contains(&format!("name=\"{}\"", p.name())))
            .unwrap_or_else(|| panic!("{} in the description", p.name()));
        assert!(row.contains("causality=\"parameter\""), "{row}");
        let start = json["drive"]["drive"][p.name()].as_f64().unwrap();
        assert!(row.contains(&format!("start=\"{start:?}\"")), "{row}");
    }
}

/// Largest difference of each column over its range.
fn worst(a: &[Vec<f64>], b: &[Vec<f64>], columns: &[(usize, usize)]) -> f64 {
    let mut out: f64 = 0.0;
    for &(i, j) in columns {
        let col: Vec<f64> = b.iter().map(|r| r[j]).collect();
        let range = col.iter().cloned().fold(f64::MIN, f64::max)
            - col.iter().cloned().fold(f64::MAX, f64::min);
        for (p, q) in a.iter().zip(b) {
            out = out.max((p[i] - q[j]).abs() / range);
        }
    }
    out
}

fn rows(path: &std::path::Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let parse = |l: &str| l.split(',').map(|x| x.parse().unwrap()).collect();
    text.lines().skip(1).map(parse).collect()
}

#[test]
fn the_reference_result_is_physical_simulate_of_the_same_drive() {
    let dir = tempfile::tempdir().unwrap();
    let fmu = dir.path().join("d.fmu");
    let bearing = [
        "--output-bearing",
        "stribeck:fc=6.5,fs=9.5,vst=0.01,cv=0.01,vr=1e-4",
    ];
    let step = "0.013";
    let out = fmu.to_str().unwrap();
    let mut args = vec!["export", "fmu", "--out", out, "--step", step, "--stop", "3"];
    args.extend(bearing);
    hdgear().args(&args).assert().success();
    let csv = dir.path().join("p.csv");
    let mut args = vec![
        "physical",
        "--simulate",
        "--t-end",
        "3",
        "--dt",
        step,
        "--out",
    ];
    args.push(csv.to_str().unwrap());
    args.extend(bearing);
    hdgear().args(&args).assert().success();
    let (reference, physical) = (rows(&dir.path().join("d_ref.csv")), rows(&csv));
    assert_eq!(reference.len(), physical.len());
    // time, phi_in, phi_out, twist, twist_rate against t, theta_in, theta_out, theta, theta_dot
    let e = worst(
        &reference,
        &physical,
        &[(0, 0), (1, 1), (3, 2), (5, 3), (6, 4)],
    );
    assert!(e < 1e-8, "{e:e} of a column's range");
}

#[test]
fn refusals_name_the_value_and_leave_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let at = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let fmu = at("d.fmu");
    let card = at("joint.toml");
    hdgear()
        .args([
            "card",
            "new",
            "JOINT-20-50",
            "--from",
            "CSG-20-50",
            "--out",
            &card,
        ])
        .assert()
        .success();
    let text = std::fs::read_to_string(&card).unwrap();
    let law = "\n[card.friction]\nsource = \"hd-torsional-csg\"\ncoulomb = 1.0\nbreakaway = 3.0\nstribeck_speed = 1e-3\n";
    std::fs::write(&card, format!("{text}{law}")).unwrap();
    let bad_input = at("bad.csv");
    std::fs::write(&bad_input, "time,tau_motor,tau_load\n0,0,0\n0.1,1,x\n").unwrap();
    let backwards = at("back.csv");
    std::fs::write(&backwards, "time,tau_motor,tau_load\n0.2,0,0\n0.1,1,1\n").unwrap();
    let base = ["export", "fmu", "--out", fmu.as_str()];
    for (extra, needle) in [
        (vec!["--drive", card.as_str()], "fitted friction"),
        (vec!["--j-in=-1"], "j_in = -1"),
        (vec!["--tolerance", "0"], "--tolerance = 0"),
        (vec!["--step", "nan"], "--step = NaN"),
        (vec!["--stop", "1e9"], "reference rows"),
        (
            vec!["--library", "/nonexistent/lib.so"],
            "/nonexistent/lib.so",
        ),
        (vec!["--library", card.as_str()], "not a shared library"),
        (vec!["--input", bad_input.as_str()], "line 3"),
        (
            vec!["--input", backwards.as_str()],
            "times must not decrease",
        ),
        (vec!["--twist-friction", "coulomb:fc=1"], "coulomb"),
    ] {
        fails_with(&[&base[..], &extra].concat(), needle);
    }
    fails_with(&["export", "fmu", "--out", &at("d.zip")], "must be .fmu");
    let mut left = files_in(dir.path());
    left.retain(|f| !["joint.toml", "bad.csv", "back.csv"].contains(&f.as_str()));
    assert!(left.is_empty(), "{left:?}");
}
