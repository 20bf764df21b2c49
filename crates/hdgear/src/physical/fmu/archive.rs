//! The `.fmu` archive, its resources, and the reference result beside it.

use super::{FmuDrive, FmuError, Instance, MODEL_IDENTIFIER, Role};
use serde::{Deserialize, Serialize};

/// What the FMU's `resources/drive.json` holds: the drive and the GUID of the description it
/// was written with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Resources {
    /// The description's GUID ([`FmuDrive::guid`]).
    pub guid: String,
    /// The drive.
    pub drive: FmuDrive,
}

impl Resources {
    /// The resources of a drive.
    pub fn of(drive: &FmuDrive) -> Resources {
        Resources {
            guid: drive.guid(),
            drive: drive.clone(),
        }
    }

    /// Reads `drive.json` from the folder an FMU's `fmuResourceLocation` names (a `file:` URI,
    /// percent-encoded), and checks that the GUID the host gives is this drive's.
    pub fn load(location: &str, guid: &str) -> crate::error::Result<Resources> {
        let invalid = |reason: String| crate::error::Error::InvalidInput {
            what: "FMU resource location",
            text: location.to_string(),
            reason,
        };
        let folder = resource_folder(location)
            .ok_or_else(|| invalid("expected a file: URI of the FMU's resources folder".into()))?;
        let path = folder.join("drive.json");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| invalid(format!("cannot read {}: {e}", path.display())))?;
        let r: Resources =
            serde_json::from_str(&text).map_err(|e| invalid(format!("{}: {e}", path.display())))?;
        if r.guid != guid || r.drive.guid() != guid {
            return Err(invalid(format!(
                "the GUID {guid} is not this FMU's ({}): the description and the resources \
                 do not belong together",
                r.guid
            )));
        }
        Ok(r)
    }
}

/// The folder a `file:` URI names: `file:///a/b`, `file:/a/b` and `file://localhost/a/b`, with
/// `%XX` escapes decoded; `None` for anything else.
///
/// ```
/// use hdgear::physical::fmu::resource_folder;
/// assert_eq!(resource_folder("file:///tmp/a%20b/resources").unwrap().to_str(), Some("/tmp/a b/resources"));
/// assert_eq!(resource_folder("file:/tmp/r").unwrap().to_str(), Some("/tmp/r"));
/// assert!(resource_folder("http://x/r").is_none());
/// ```
pub fn resource_folder(uri: &str) -> Option<std::path::PathBuf> {
    let rest = uri.strip_prefix("file:")?;
    let path = match rest.strip_prefix("//") {
        Some(authority) => {
            let at = authority.find('/')?;
            match &authority[..at] {
                "" | "localhost" => &authority[at..],
                _ => return None,
            }
        }
        None => rest,
    };
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    Some(std::path::PathBuf::from(String::from_utf8(out).ok()?))
}

/// One row of an FMU's reference result: the time, the inputs held over the step that ends
/// there, and the outputs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReferenceRow {
    /// Communication point \[s\].
    pub time: f64,
    /// The motor and load torques \[N m\] applied up to this point.
    pub inputs: [f64; 2],
    /// The outputs at this point, in the order of [`FmuDrive::variables`].
    pub outputs: Vec<f64>,
}

impl FmuDrive {
    /// The `.fmu` archive: `modelDescription.xml`, the shared `library` as
    /// `binaries/linux64/hdgear_fmu.so`, and `resources/drive.json`.
    pub fn archive(&self, library: &[u8], step: f64, stop: f64) -> crate::error::Result<Vec<u8>> {
        let xml = self.model_description(step, stop);
        let json = serde_json::to_string_pretty(&Resources::of(self)).unwrap_or_default();
        let binary = format!("binaries/linux64/{MODEL_IDENTIFIER}.so");
        crate::output::zip::stored(&[
            ("modelDescription.xml", xml.as_bytes()),
            (&binary, library),
            ("resources/drive.json", json.as_bytes()),
        ])
    }

    /// The FMU's answer as a host gets it, through [`Instance`]: from rest at 0, rows at the
    /// communication points k·`step` up to `stop` (and at `stop`), the torques `inputs(t)` set at each point
    /// and held to the next. The steps are cut at the times `jumps` too (where the torques
    /// jump), as a host that steps to its inputs' events does (FMPy).
    pub fn reference(
        &self,
        step: f64,
        stop: f64,
        jumps: &[f64],
        inputs: impl Fn(f64) -> [f64; 2],
    ) -> Result<Vec<ReferenceRow>, FmuError> {
        let vars = self.variables();
        let refs = |role: Role| -> Vec<u32> {
            let of = (vars.iter().enumerate()).filter(|(_, v)| v.role == role);
            of.map(|(i, _)| i as u32).collect()
        };
        let (input_refs, output_refs) = (refs(Role::Input), refs(Role::Output));
        let mut fmu = Instance::new(self.clone());
        fmu.setup(None, 0.0)?;
        fmu.enter_initialisation()?;
        fmu.exit_initialisation()?;
        let read = |fmu: &Instance| -> Result<Vec<f64>, FmuError> {
            output_refs.iter().map(|&vr| fmu.get_real(vr)).collect()
        };
        let n = (stop / step * (1.0 + 1e-12)).floor() as usize;
        // the points: the grid (recorded), and the jumps between its points (not recorded)
        let mut points: Vec<(f64, bool)> = (0..=n).map(|k| (k as f64 * step, true)).collect();
        let slack = 1e-9 * step;
        // and `stop` itself when the grid does not land on it, as `physical --simulate` samples
        if stop - n as f64 * step > slack {
            points.push((stop, true));
        }
        let between = |t: f64| t > slack && t < stop - slack;
        let off_grid = |t: f64| ((t / step).round() * step - t).abs() > slack;
        points.extend(
            jumps
                .iter()
                .filter(|&&t| between(t) && off_grid(t))
                .map(|&t| (t, false)),
        );
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points.dedup_by(|b, a| b.0 == a.0);
        let mut rows = vec![ReferenceRow {
            time: 0.0,
            inputs: inputs(0.0),
            outputs: read(&fmu)?,
        }];
        for pair in points.windows(2) {
            let [(t, _), (next, recorded)] = [pair[0], pair[1]];
            let held = inputs(t);
            for (&vr, &value) in input_refs.iter().zip(&held) {
                fmu.set_real(vr, value)?;
            }
            fmu.do_step(t, next - t)?;
            if recorded {
                rows.push(ReferenceRow {
                    time: next,
                    inputs: held,
                    outputs: read(&fmu)?,
                });
            }
        }
        Ok(rows)
    }
}
