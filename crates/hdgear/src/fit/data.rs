//! Measured data: a CSV file's named columns with their units, read into SI values.

use super::FitWarning;
use crate::error::{Error, Result};
use serde::Serialize;
use std::path::Path;

/// What a data file measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DataKind {
    /// Friction torque against a constant sliding speed (a speed sweep): columns `speed` and
    /// `torque`.
    Friction,
    /// A quasi-static torque–twist loop (a lost-motion or hysteresis test), rows in the order
    /// the twist was applied: columns `twist` and `torque`.
    Loop,
}

impl DataKind {
    /// Both, as `--kind` lists them.
    pub const ALL: [DataKind; 2] = [DataKind::Friction, DataKind::Loop];

    /// The name users write.
    pub fn name(self) -> &'static str {
        match self {
            DataKind::Friction => "friction",
            DataKind::Loop => "loop",
        }
    }

    /// The quantity the torque is measured against.
    pub fn abscissa(self) -> &'static MeasuredQuantity {
        match self {
            DataKind::Friction => &SPEED,
            DataKind::Loop => &TWIST,
        }
    }
}

impl std::str::FromStr for DataKind {
    type Err = Error;
    fn from_str(s: &str) -> Result<DataKind> {
        crate::error::by_name(&DataKind::ALL, DataKind::name, "data kind", s)
    }
}

/// A measured quantity: its column name, SI unit and the units it may be given in, each with its
/// factor to SI.
#[derive(Debug, PartialEq, Serialize)]
pub struct MeasuredQuantity {
    /// The column's name.
    pub name: &'static str,
    /// Its SI unit.
    pub si: &'static str,
    /// Units accepted, with the factor that takes a value to SI.
    pub units: &'static [(&'static str, f64)],
}

/// A sliding speed.
pub const SPEED: MeasuredQuantity = MeasuredQuantity {
    name: "speed",
    si: "rad/s",
    units: &[
        ("rad/s", 1.0),
        ("rpm", std::f64::consts::PI / 30.0),
        ("deg/s", std::f64::consts::PI / 180.0),
    ],
};
/// A torque.
pub const TORQUE: MeasuredQuantity = MeasuredQuantity {
    name: "torque",
    si: "N m",
    units: &[
        ("N m", 1.0),
        ("Nm", 1.0),
        ("N·m", 1.0),
        ("mN m", 1e-3),
        ("mNm", 1e-3),
    ],
};
/// A twist.
pub const TWIST: MeasuredQuantity = MeasuredQuantity {
    name: "twist",
    si: "rad",
    units: &[
        ("rad", 1.0),
        ("mrad", 1e-3),
        ("deg", std::f64::consts::PI / 180.0),
        ("arcmin", std::f64::consts::PI / 10_800.0),
        ("arcsec", std::f64::consts::PI / 648_000.0),
    ],
};

/// The units each quantity takes, as help texts list them: `rad/s, rpm, deg/s; rad, …`.
pub fn units_text() -> String {
    [&SPEED, &TWIST, &TORQUE]
        .iter()
        .map(|q| q.units.iter().map(|u| u.0).collect::<Vec<_>>().join(", "))
        .collect::<Vec<_>>()
        .join("; ")
}

impl MeasuredQuantity {
    /// The factor to SI of `unit`, or an error naming the units this quantity takes.
    pub fn factor(&self, unit: &str) -> Result<f64> {
        let unit = unit.trim();
        self.units
            .iter()
            .find(|(u, _)| *u == unit)
            .map(|&(_, f)| f)
            .ok_or_else(|| Error::InvalidInput {
                what: "unit",
                text: unit.into(),
                reason: format!(
                    "{} takes {}",
                    self.name,
                    self.units
                        .iter()
                        .map(|u| u.0)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            })
    }
}

/// Which column holds a quantity, and its unit where the header does not give it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Column {
    /// The column's header name (default: the quantity's name).
    pub name: Option<String>,
    /// Its unit (default: the one in the header, `speed [rpm]`).
    pub unit: Option<String>,
}

/// Where a data file's numbers come from: what a fitted card cites.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DataSource {
    /// The file as given.
    pub path: String,
    /// CRC-32 of its bytes, as 8 hex digits.
    pub crc32: String,
    /// Rows read (after the header).
    pub rows: usize,
}

/// Measured torques against a speed or a twist, in SI units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Data {
    /// What was measured.
    pub kind: DataKind,
    /// The speeds \[rad/s\] or twists \[rad\], in row order.
    pub x: Vec<f64>,
    /// The torques \[N m\].
    pub torque: Vec<f64>,
    /// Each torque's standard deviation \[N m\] where the file gives one (`torque_sd`): the
    /// residuals are weighted by it.
    pub sd: Option<Vec<f64>>,
    /// Where they come from.
    pub source: DataSource,
}

impl Data {
    /// Data from values already in SI units (a test, a program, Python), checked as a file's
    /// are.
    pub fn new(
        kind: DataKind,
        x: Vec<f64>,
        torque: Vec<f64>,
        sd: Option<Vec<f64>>,
    ) -> Result<(Data, Vec<FitWarning>)> {
        let source = DataSource {
            path: "(in memory)".into(),
            crc32: String::new(),
            rows: x.len(),
        };
        checked(kind, x, torque, sd, source, |i| i + 1)
    }

    /// Reads `path`: a CSV file with a header row naming the columns, each with its unit in
    /// brackets (`speed [rpm]`, `torque [N m]`) or given in `x`, `torque` ([`Column`]).
    pub fn read(
        path: &Path,
        kind: DataKind,
        x: &Column,
        torque: &Column,
    ) -> Result<(Data, Vec<FitWarning>)> {
        let io = |e: std::io::Error| Error::Io {
            path: path.to_path_buf(),
            source: e,
        };
        let bytes = std::fs::read(path).map_err(io)?;
        let bad = |reason: String| Error::InvalidInput {
            what: "data file",
            text: path.display().to_string(),
            reason,
        };
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(&bytes[..]);
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| bad(e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        let find =
            |q: &MeasuredQuantity, c: &Column, required: bool| locate(&header, q, c, required, bad);
        let q = kind.abscissa();
        let (ix, fx) = find(q, x, true)?.expect("required");
        let (it, ft) = find(&TORQUE, torque, true)?.expect("required");
        let sd_column = Column {
            name: Some(format!(
                "{}_sd",
                torque.name.as_deref().unwrap_or(TORQUE.name)
            )),
            unit: torque.unit.clone(),
        };
        let isd = find(&TORQUE, &sd_column, false)?;
        let (mut xs, mut ts, mut sds) = (Vec::new(), Vec::new(), Vec::new());
        let mut rows = 0;
        for (row, record) in reader.records().enumerate() {
            let record = record.map_err(|e| bad(e.to_string()))?;
            rows += 1;
            let number = |i: usize| -> Result<f64> {
                let text = record.get(i).unwrap_or("");
                if text.is_empty() || text.eq_ignore_ascii_case("nan") {
                    return Ok(f64::NAN);
                }
                text.parse::<f64>().map_err(|_| {
                    bad(format!(
                        "line {}: {} '{text}' is not a number",
                        row + 2,
                        header[i]
                    ))
                })
            };
            xs.push(number(ix)? * fx);
            ts.push(number(it)? * ft);
            if let Some((i, f)) = isd {
                sds.push(number(i)? * f);
            }
        }
        let source = DataSource {
            path: path.display().to_string(),
            crc32: format!("{:08x}", crc32fast::hash(&bytes)),
            rows,
        };
        let sd = isd.map(|_| sds);
        checked(kind, xs, ts, sd, source, |i| i + 2)
    }

    /// The number of points.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}

/// The index of quantity `q`'s column in `header` and its unit's factor to SI (`None` for a
/// column that is not there and not `required`); `bad` turns a reason into the file's error.
fn locate(
    header: &[String],
    q: &MeasuredQuantity,
    c: &Column,
    required: bool,
    bad: impl Fn(String) -> Error,
) -> Result<Option<(usize, f64)>> {
    let want = c.name.as_deref().unwrap_or(q.name);
    let Some(i) = header.iter().position(|h| split_unit(h).0 == want) else {
        return if required {
            Err(bad(format!(
                "no column {want} (columns: {})",
                header.join(", ")
            )))
        } else {
            Ok(None)
        };
    };
    let unit = match (&c.unit, split_unit(&header[i]).1) {
        (Some(u), _) => u.clone(),
        (None, Some(u)) => u.to_string(),
        (None, None) => {
            return Err(bad(format!(
                "column {want} has no unit: write it in the header ({want} [{}]) or give its unit ({}={})",
                q.si, q.name, q.si
            )));
        }
    };
    Ok(Some((i, q.factor(&unit)?)))
}

/// A header cell's name and unit: `speed [rpm]` or `speed (rpm)`.
fn split_unit(h: &str) -> (&str, Option<&str>) {
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let (Some(a), true) = (h.find(open), h.ends_with(close)) {
            return (h[..a].trim(), Some(h[a + 1..h.len() - 1].trim()));
        }
    }
    (h.trim(), None)
}

/// The rows kept: those with every number finite (and, for a friction sweep, a speed ≠ 0, where
/// friction is any torque in its sticking band); each dropped kind of row is a warning naming
/// the first line. `line` turns a row index into the file's line.
fn checked(
    kind: DataKind,
    x: Vec<f64>,
    torque: Vec<f64>,
    sd: Option<Vec<f64>>,
    source: DataSource,
    line: impl Fn(usize) -> usize,
) -> Result<(Data, Vec<FitWarning>)> {
    let n = x.len();
    let mut warnings = Vec::new();
    let bad_sd = |i: usize| {
        sd.as_ref()
            .is_some_and(|s| !(s[i] > 0.0 && s[i].is_finite()))
    };
    let not_finite: Vec<usize> = (0..n)
        .filter(|&i| !x[i].is_finite() || !torque[i].is_finite() || bad_sd(i))
        .collect();
    let at_rest: Vec<usize> = (0..n)
        .filter(|&i| kind == DataKind::Friction && x[i] == 0.0 && !not_finite.contains(&i))
        .collect();
    let dropped = [
        (
            &not_finite,
            "a number missing, not finite, or a standard deviation ≤ 0",
        ),
        (
            &at_rest,
            "speed 0, where friction is any torque within its sticking band",
        ),
    ];
    for (rows, why) in dropped {
        if let Some(&first) = rows.first() {
            warnings.push(FitWarning::DroppedRows {
                count: rows.len(),
                first_line: line(first),
                why,
            });
        }
    }
    let keep: Vec<usize> = (0..n)
        .filter(|i| !not_finite.contains(i) && !at_rest.contains(i))
        .collect();
    let data = Data {
        kind,
        x: keep.iter().map(|&i| x[i]).collect(),
        torque: keep.iter().map(|&i| torque[i]).collect(),
        sd: sd.map(|s| keep.iter().map(|&i| s[i]).collect()),
        source,
    };
    Ok((data, warnings))
}
