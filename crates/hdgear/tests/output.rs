//! Output encodings: explicit CSV headers equal serde's field names; atomic files; Parquet holds
//! the CSV's values.

use hdgear::Params;
use hdgear::output::{AtomicFile, Format, Record, RecordWriter};
use std::io::Write;

/// The names serde writes for an instance, in order, a nested struct's in its place (as csv
/// writes its values; csv itself writes no header for a nested struct): the keys of its JSON
/// text whose values are not objects, read off the text in the order serde wrote them.
fn serde_names<T: serde::Serialize>(v: &T) -> Vec<String> {
    let text = serde_json::to_string(v).unwrap();
    let (mut names, mut chars) = (Vec::new(), text.chars().peekable());
    while let Some(c) = chars.next() {
        if c != '"' {
            continue;
        }
        let mut s = String::new();
        while let Some(c) = chars.next() {
            match c {
                '\\' => s.push(chars.next().unwrap()),
                '"' => break,
                c => s.push(c),
            }
        }
        if chars.peek() == Some(&':') {
            chars.next();
            if chars.peek() != Some(&'{') {
                names.push(s);
            }
        }
    }
    names
}

/// The header serde and csv derive from an instance of a flat row.
fn serde_header<T: serde::Serialize>(v: &T) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.serialize(v).unwrap();
    let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
    text.lines().next().unwrap().to_string()
}

/// A record's columns are the names serde writes; a flat row's also the header csv writes.
fn check<T: Record>(v: &T) {
    assert_eq!(serde_names(v), T::COLUMNS);
    let nested = T::COLUMNS.len() != serde_json::to_value(v).unwrap().as_object().unwrap().len();
    if !nested {
        assert_eq!(serde_header(v), T::COLUMNS.join(","));
    }
}

#[test]
fn record_columns_match_the_fields() {
    let p = Params::default();
    check(&hdgear::fast::curve(&p, (-1.0, 1.0), 2).unwrap()[0]);
    check(&hdgear::fast::fold_curves(&p, 0.0, 2).unwrap()[0]);
    let r = hdgear::burst::response(&p, &Default::default()).unwrap();
    check(&r.bursts[0]);
    check(&p);
    assert_eq!(Params::COLUMNS, hdgear::params::Param::NAMES);
    check(&hdgear::simulate::StateSample::from([0.5, 1.0, -2.0]));
    // a point whose exponent failed: the row's columns are the same
    check(&hdgear::periodic::LyapunovRow {
        index: 3,
        params: p,
        lyapunov: f64::NAN,
        period: None,
        error: "no exponent".into(),
    });
}

/// What `#[derive(Record)]` reads of a struct, held to the header serde and csv write for it:
/// renamed and skipped fields, raw identifiers, nested records (csv writes their fields in
/// place), a type parameter at its default, a borrowed field.
#[test]
fn the_derived_columns_are_the_header_serde_writes() {
    #[derive(serde::Serialize, Record)]
    struct Inner {
        #[serde(rename = "inner_a")]
        a: f64,
        b: u32,
    }
    #[derive(serde::Serialize, Record)]
    struct Row<'a, V = Inner> {
        r#type: &'a str,
        #[serde(skip)]
        _hidden: f64,
        #[record(nested)]
        first: V,
        #[serde(rename = "middle")]
        m: Option<f64>,
        #[record(nested)]
        second: Params,
        last: bool,
    }
    let row = Row {
        r#type: "fold",
        _hidden: 1.0,
        first: Inner { a: 1.0, b: 2 },
        m: None,
        second: Params::default(),
        last: true,
    };
    assert_eq!(
        Row::COLUMNS,
        [
            "type", "inner_a", "b", "middle", "alpha", "gamma", "eps", "mu", "delta", "omega",
            "last"
        ]
    );
    check(&row);
}

/// Leaf keys of a JSON object, nested objects opened (sorted: `Value` keeps no order).
fn leaves(v: &serde_json::Value, out: &mut Vec<String>) {
    for (k, x) in v.as_object().unwrap() {
        if x.is_object() {
            leaves(x, out);
        } else {
            out.push(k.clone());
        }
    }
}

#[test]
fn sweep_rows_are_flat_columns_that_read_back_by_position() {
    // a sweep row nests its parameters and statistics; csv writes them as flat columns in
    // field order, and `--resume` reads them back by position: the round trip must be exact,
    // for a computed row and for a failed one (NaN statistics, no bursts per period)
    use hdgear::sweep::{SweepRow, run_point};
    let p = Params::default();
    let good = run_point(3, &p, &Default::default());
    let bad = run_point(4, &Params { omega: 1e-9, ..p }, &Default::default());
    assert!(!bad.error.is_empty());
    let mut names = Vec::new();
    leaves(&serde_json::to_value(&good).unwrap(), &mut names);
    names.sort();
    let mut columns: Vec<String> = SweepRow::COLUMNS.iter().map(|c| c.to_string()).collect();
    columns.sort();
    assert_eq!(names, columns);
    let mut w = RecordWriter::<_, SweepRow>::new(Vec::new(), Format::Csv, &()).unwrap();
    w.row(&good).unwrap();
    w.row(&bad).unwrap();
    let text = String::from_utf8(w.finish().unwrap()).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    assert_eq!(
        rdr.headers().unwrap().iter().collect::<Vec<_>>(),
        SweepRow::COLUMNS
    );
    let back: Vec<SweepRow> = rdr
        .records()
        .map(|r| r.unwrap().deserialize(None).unwrap())
        .collect();
    assert_eq!(back[0], good);
    assert_eq!(back[1].error, bad.error);
    assert_eq!(back[1].params, bad.params);
    assert!(back[1].rates.spikes_per_burst.is_nan() && back[1].rates.bursts_per_period.is_none());
}

#[test]
fn json_records_stream_with_meta() {
    let p = Params::default();
    let mut w = RecordWriter::new(Vec::new(), Format::Json, &serde_json::json!({"k": 1})).unwrap();
    for q in hdgear::fast::curve(&p, (-1.0, 1.0), 3).unwrap() {
        w.row(&q).unwrap();
    }
    assert_eq!(w.rows(), 3);
    let doc: serde_json::Value = serde_json::from_slice(&w.finish().unwrap()).unwrap();
    assert_eq!(doc["meta"]["k"], 1);
    assert_eq!(doc["rows"].as_array().unwrap().len(), 3);
    assert_eq!(doc["rows"][0]["type"], "stable-focus");
}

#[test]
fn atomic_files_appear_only_when_committed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.csv");
    {
        let mut f = AtomicFile::create(&path).unwrap();
        f.write_all(b"partial").unwrap();
        // dropped without commit: nothing, not even the temporary, remains
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    let mut f = AtomicFile::create(&path).unwrap();
    f.write_all(b"done").unwrap();
    assert!(!path.exists());
    f.commit().unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "done");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn a_failed_commit_leaves_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.csv");
    let mut f = AtomicFile::create(&path).unwrap();
    f.write_all(b"a,b\n1,2\n").unwrap();
    // the target turns into a directory before the rename
    std::fs::create_dir(&path).unwrap();
    assert!(f.commit().is_err());
    assert_eq!(crate::common::files_in(dir.path()), ["x.csv"]);
    assert!(path.is_dir());
    // and a path that is a directory, or in a missing one, is refused before anything is written
    for bad in [path.clone(), dir.path().join("missing/y.csv")] {
        assert!(AtomicFile::create(&bad).is_err());
    }
    assert_eq!(crate::common::files_in(dir.path()), ["x.csv"]);
}

/// The lines of `text`, comments aside, that hold a study parameter's name as a string literal
/// (`"gamma"`): where a column list, a flag, a key or a message would restate the name.
fn name_literals(text: &str) -> Vec<&str> {
    let names = hdgear::params::Param::NAMES.map(|n| format!("\"{n}\""));
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .filter(|l| names.iter().any(|n| l.contains(n.as_str())))
        .collect()
}

/// Whether a line is an arm of a table of names (`Param::Gamma => "gamma",`), the one place a
/// name is written: the study's `Param::name`, or a parameter table of its own whose name
/// happens to be the same (the drive's Ω in rad/s, `DriveParam::Omega => "omega"`).
fn is_name_definition(line: &str) -> bool {
    let l = line.trim();
    (l.starts_with("Param::") || l.starts_with("DriveParam::"))
        && l.contains(" => \"")
        && l.ends_with("\",")
}

/// The study's parameter names are written once, in `Param::name`: every flag, column list,
/// table key and message of every crate's sources derives from it (issue 38: nothing outside
/// the definitions names a parameter by hand).
#[test]
fn the_study_s_parameter_names_are_written_only_where_they_are_defined() {
    // the scan flags a restated name and passes a definition
    let planted = "const COLUMNS: &[&str] = &[\"index\", \"gamma\"];\n// \"gamma\" in a comment";
    assert_eq!(name_literals(planted).len(), 1);
    assert!(!is_name_definition(name_literals(planted)[0]));
    assert!(is_name_definition("            Param::Gamma => \"gamma\","));

    let crates = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let (mut definitions, mut restated) = (0, Vec::new());
    let sources = ["hdgear/src", "hdgear-cli/src", "hdgear-py/src"]
        .iter()
        .flat_map(|d| crate::house::files_under(&crates.join(d)))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"));
    for path in sources {
        let text = std::fs::read_to_string(&path).unwrap();
        for line in name_literals(&text) {
            if is_name_definition(line) {
                definitions += 1;
            } else {
                restated.push(format!("{}: {}", path.display(), line.trim()));
            }
        }
    }
    assert!(
        restated.is_empty(),
        "names restated:\n{}",
        restated.join("\n")
    );
    // the six arms of Param::name (and the drive's Ω): the scan saw the sources
    assert_eq!(definitions, 7);
}
