//! Drive cards on the command line: `card new|show|check|map`, their text and JSON, and bad input.

use crate::common::{fails_with, hdgear, json_of, stdout_of};
use predicates::prelude::*;

#[test]
fn card_new_show_check_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mine.toml");
    let p = path.to_str().unwrap();
    copy_of_csg("MINE-20-50", p);
    // the copy is the catalogue card under a new name, with the sources it uses
    let shown = json_of(&["card", "show", p, "--json"]);
    assert_eq!(shown["card"]["name"], "MINE-20-50");
    assert_eq!(shown["card"]["stiffness"]["k3"], 23000.0);
    assert_eq!(shown["sources"]["hysteresis"]["kind"], "assumption");
    let a = json_of(&["card", "check", p, "--json"]);
    assert!(a.get("design").is_none());
    // with --design, the margins of the six parameters (the same as physical --design gives)
    let d = json_of(&["card", "check", p, "--json", "--design"]);
    let margins = d["design"]["margins"].as_array().unwrap();
    assert_eq!(margins.len(), 6);
    assert_eq!(d["summary"], a["summary"]);
    let b = json_of(&["card", "check", "CSG-20-50", "--json"]);
    assert_eq!(a["damping"], b["damping"]);
    assert_eq!(a["summary"]["reduced"], b["summary"]["reduced"]);
    // the physical command takes the same card
    let ph = json_of(&["physical", "--json", "--drive", p]);
    assert_eq!(ph["catalogue"]["name"], "MINE-20-50");
    // never overwrites
    hdgear()
        .args(["card", "new", "X", "--out", p])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("exists"));
    // the template lists every section and needs its stiffness filled in
    let t = stdout_of(&["card", "new", "TEMPLATE-1"]);
    assert!(t.contains("[card.stiffness]") && t.contains("# [card.friction]"));
    let tpl = dir.path().join("t.toml");
    std::fs::write(&tpl, &t).unwrap();
    hdgear()
        .args(["card", "check", tpl.to_str().unwrap()])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("stiffness.t1 = missing"));
}

#[test]
fn card_bad_input_exits_2() {
    fails_with(&["card", "show", "CSG-99-50"], "'CSG-99-50'");
    fails_with(&["card", "check", "CSG-20-50", "--damping", "wet"], "'wet'");
    fails_with(
        &["card", "show", "/nonexistent/c.toml"],
        "/nonexistent/c.toml",
    );
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("bad.toml");
    std::fs::write(&f, "format = 1\n[[card]]\nname = \"A\"\nratio = 50\n").unwrap();
    fails_with(&["card", "show", f.to_str().unwrap()], "stiffness");
    fails_with(&["card", "new", "A#B"], "A#B");
    let out = dir.path().join("c.txt");
    fails_with(
        &["card", "new", "A", "--out", out.to_str().unwrap()],
        ".toml",
    );
    assert!(!out.exists());
    assert_eq!(crate::common::files_in(dir.path()), ["bad.toml"]);
}

#[test]
fn card_map_writes_one_row_per_load() {
    let text = stdout_of(&["card", "map", "CSG-20-50", "--points", "3", "--hz", "0.1:1"]);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "t_am_nm,frequency_hz,bursting,verdict,basis,fast_slow_domain,friction_bursting,friction_verdict,catalogue_bursting,catalogue_verdict,computed,friction_computed,catalogue_computed,held_bursting,held_verdict,held_fast_slow_domain,held_computed"
        )
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 9);
    // no friction law on a built-in card: its columns are empty; the catalogue's curve judges
    // every point; a 3 × 3 map is simulated at every point
    for r in &rows {
        let cells: Vec<&str> = r.split(',').collect();
        assert_eq!(cells.len(), 17, "{r}");
        assert_eq!(cells[6..8], ["", ""], "{r}");
        assert!(["true", "false"].contains(&cells[8]), "{r}");
        assert_eq!(cells[10..13], ["true", "", "true"], "{r}");
        // the held drive's verdict, computed at every point
        assert!(["true", "false"].contains(&cells[13]), "{r}");
        assert!(["true", "false"].contains(&cells[15]), "{r}");
        assert_eq!(cells[16], "true", "{r}");
    }
    assert!(
        rows[0].starts_with("11.0,0.1,") && rows[8].starts_with("33.0,1.0,"),
        "{rows:?}"
    );
    // --fit-only: the catalogue's two columns left empty, the others the same
    let fit = stdout_of(&[
        "card",
        "map",
        "CSG-20-50",
        "--points",
        "3",
        "--hz",
        "0.1:1",
        "--fit-only",
    ]);
    for (r, f) in rows.iter().zip(fit.lines().skip(1)) {
        let cells: Vec<&str> = r.split(',').collect();
        let held = cells[13..].join(",");
        assert_eq!(f, format!("{},,,true,,,{held}", cells[..8].join(",")));
    }
    // each refusal names the user's flag and value, not the library's field
    for (args, message) in [
        (&["--points", "0"][..], "--points = 0:"),
        (&["--coarse", "0"], "--coarse = 0:"),
        (&["--hz", "0:1"], "0:1"),
        (&["--t-am-max=-1"], "--t-am-max = -1:"),
        (&["--knee-rounding=-1"], "--knee-rounding = -1:"),
        (&["--window-periods", "0"], "--window-periods = 0:"),
    ] {
        fails_with(&[&["card", "map", "CSG-20-50"][..], args].concat(), message);
    }
    fails_with(
        &["card", "check", "CSG-20-50", "--knee-rounding", "1.5"],
        "--knee-rounding = 1.5:",
    );
}

/// A card with a fitted friction law: `card check` answers with it (the verdict, the rests and
/// one margin per knob), `card map` fills the friction columns, and a law that does not hold
/// together is refused with its key and value.
#[test]
fn card_check_answers_with_the_cards_friction() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("joint.toml");
    let p = path.to_str().unwrap();
    let card = copy_of_csg("JOINT-20-50", p);
    let law = "\n[card.friction]\nsource = \"hd-torsional-csg\"\ncoulomb = 1.0\nbreakaway = 3.0\nstribeck_speed = 1e-3\n";
    std::fs::write(&path, format!("{card}{law}")).unwrap();
    let text = stdout_of(&["card", "check", p]);
    assert!(text.contains("with friction: not bursting"), "{text}");
    assert!(
        text.contains("the sticking band holds the slow load"),
        "{text}"
    );
    let j = json_of(&["card", "check", p, "--json"]);
    let f = &j["friction"];
    assert_eq!(f["law"]["breakaway"], 3.0);
    assert_eq!(f["outcome"]["verdict"], "no-bursts");
    let margins = f["margins"].as_array().unwrap();
    assert_eq!(margins.len(), 5);
    let t_am = margins.iter().find(|m| m["parameter"] == "t_am").unwrap();
    assert_eq!(t_am["outside"]["judgement"]["verdict"], "stick-slip");
    let map = stdout_of(&["card", "map", p, "--points", "1", "--hz", "0.2:0.3"]);
    assert!(
        map.lines().nth(1).unwrap().contains(",true,stick-slip,"),
        "{map}"
    );
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, format!("{card}{}", law.replace("3.0", "0.5"))).unwrap();
    fails_with(
        &["card", "check", bad.to_str().unwrap()],
        "friction.breakaway = 0.5",
    );
}

/// `card check` judges the drive with its wave generator held as well, and a card's starting
/// torque says whether its friction holds the input: CSG-20-50's assumed T_am = T1/4 = 1.75 N m
/// against N·T_st = 50·0.04 = 2 N m (held) and 50·0.03 = 1.5 N m (slips).
#[test]
fn card_check_says_whether_the_starting_torque_holds_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("joint.toml");
    let p = path.to_str().unwrap();
    let plain = stdout_of(&["card", "check", "CSG-20-50"]);
    assert!(plain.contains("with the wave generator held ("), "{plain}");
    assert!(
        plain.contains("the card gives no starting torque"),
        "{plain}"
    );
    // one statement of what the held verdict assumes: in the text, the JSON and a map's metadata
    let assumption = json_of(&["card", "check", "CSG-20-50", "--json"])["held_input"]["assumption"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(assumption.contains("J_o alone"), "{assumption}");
    assert!(plain.contains(&format!("held ({assumption};")), "{plain}");
    let out = dir.path().join("m.json");
    let o = out.to_str().unwrap();
    let args = [
        "card",
        "map",
        "CSG-20-50",
        "--points",
        "1",
        "--fit-only",
        "--out",
        o,
    ];
    hdgear().args(args).assert().success();
    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(map["meta"]["held_input"], assumption.as_str());
    for (starting, says) in [("0.04", "holds the input"), ("0.03", "the input slips")] {
        let card = copy_of_csg("JOINT-20-50", p);
        let friction =
            format!("\n[card.friction]\nsource = \"hd-torsional-csg\"\nstarting = {starting}\n");
        std::fs::write(&path, format!("{card}{friction}")).unwrap();
        let text = stdout_of(&["card", "check", p]);
        assert!(text.contains(says), "{starting}: {text}");
        let j = json_of(&["card", "check", p, "--json"]);
        let held = &j["held_input"];
        let at_output: f64 = starting.parse::<f64>().unwrap() * 50.0;
        assert!((held["starting_at_output"].as_f64().unwrap() - at_output).abs() < 1e-12);
        assert_eq!(held["held_by_friction"], says == "holds the input");
        std::fs::remove_file(&path).unwrap();
    }
}

/// Writes a copy of CSG-20-50 named `name` to `path` by `card new` and returns its text.
fn copy_of_csg(name: &str, path: &str) -> String {
    hdgear()
        .args(["card", "new", name, "--from", "CSG-20-50", "--out", path])
        .assert()
        .success();
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn card_check_names_the_damping_it_used_when_the_card_has_no_loss() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("noloss.toml");
    let p = path.to_str().unwrap();
    let text = copy_of_csg("NOLOSS-20-50", p);
    // the same card without its [card.hysteresis] table
    let start = text.find("[card.hysteresis]").unwrap();
    let end = text[start..].find("\n\n").map_or(text.len(), |e| start + e);
    std::fs::write(&path, format!("{}{}", &text[..start], &text[end..])).unwrap();
    // the default asks for the loss's damping; without a loss the assumed 10 % is used
    let a = json_of(&["card", "check", p, "--json"]);
    assert!(a["damping"]["from_loss"].is_null());
    assert_eq!(a["damping"]["choice"], "assumed");
    assert!((a["damping"]["zeta"].as_f64().unwrap() - 0.1).abs() < 1e-15);
    assert!(stdout_of(&["card", "check", p]).contains("damping used (assumed)"));
    // with the loss, the loss's
    let b = json_of(&["card", "check", "CSG-20-50", "--json"]);
    assert_eq!(b["damping"]["choice"], "hysteresis-loss");
}
