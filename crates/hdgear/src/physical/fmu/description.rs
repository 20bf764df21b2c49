//! The FMU's `modelDescription.xml` and GUID, from [`FmuDrive::variables`].

use super::{FmuDrive, MODEL_IDENTIFIER, Role, UNITS};

impl FmuDrive {
    /// The GUID of these values: a hash of their JSON, so that the same drive gives the same
    /// GUID and the description and the resources a library reads are checked to belong
    /// together.
    pub fn guid(&self) -> String {
        let text = serde_json::to_string(self).unwrap_or_default();
        // FNV-1a, 64 bits, from two offsets: 128 bits written as a GUID
        let fnv = |offset: u64| {
            text.bytes().fold(offset, |h, b| {
                (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
            })
        };
        let (a, b) = (fnv(0xcbf2_9ce4_8422_2325), fnv(0x6c62_272e_07bb_0142));
        format!(
            "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
            a >> 32,
            (a >> 16) & 0xffff,
            a & 0xffff,
            b >> 48,
            b & 0xffff_ffff_ffff
        )
    }

    /// The FMU's `modelDescription.xml` (FMI 2.0, co-simulation). `step` is the default
    /// experiment's communication step \[s\] and `stop` its end.
    pub fn model_description(&self, step: f64, stop: f64) -> String {
        use std::fmt::Write;
        let mut x = String::new();
        let w = &mut x;
        let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
        let _ = writeln!(
            w,
            r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="harmonic drive {} (hdgear's two-inertia model)" generationTool="hdgear {}" variableNamingConvention="structured" numberOfEventIndicators="0">"#,
            esc(&self.name),
            self.guid(),
            esc(&self.name),
            env!("CARGO_PKG_VERSION")
        );
        let _ = writeln!(
            w,
            r#"  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" needsExecutionTool="false" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="false" providesDirectionalDerivative="false"/>"#
        );
        let _ = writeln!(w, "  <UnitDefinitions>");
        for (name, [kg, m, s, rad]) in UNITS {
            let mut base = String::new();
            for (unit, e) in [("kg", kg), ("m", m), ("s", s), ("rad", rad)] {
                if e != 0 {
                    let _ = write!(base, r#" {unit}="{e}""#);
                }
            }
            let _ = writeln!(
                w,
                r#"    <Unit name="{}"><BaseUnit{base}/></Unit>"#,
                esc(name)
            );
        }
        let _ = writeln!(w, "  </UnitDefinitions>");
        let _ = writeln!(
            w,
            r#"  <DefaultExperiment startTime="0" stopTime="{}" tolerance="{}" stepSize="{}"/>"#,
            real(stop),
            real(self.tolerance),
            real(step)
        );
        let _ = writeln!(w, "  <ModelVariables>");
        let vars = self.variables();
        for (vr, v) in vars.iter().enumerate() {
            let (causality, variability, start) = match v.role {
                Role::Parameter(s) => ("parameter", "fixed", Some(s)),
                Role::Input => ("input", "continuous", Some(0.0)),
                Role::Output => ("output", "continuous", None),
            };
            let unit = v
                .unit
                .map(|u| format!(r#" unit="{}""#, esc(u)))
                .unwrap_or_default();
            let start = start
                .map(|s| format!(r#" start="{}""#, real(s)))
                .unwrap_or_default();
            let _ = writeln!(
                w,
                r#"    <ScalarVariable name="{}" valueReference="{vr}" description="{}" causality="{causality}" variability="{variability}"><Real{start}{unit}/></ScalarVariable>"#,
                esc(&v.name),
                esc(&v.description)
            );
        }
        let _ = writeln!(w, "  </ModelVariables>");
        let _ = writeln!(w, "  <ModelStructure>");
        let outputs: Vec<usize> = (vars.iter().enumerate())
            .filter(|(_, v)| v.role == Role::Output)
            .map(|(i, _)| i + 1)
            .collect();
        // no output depends on an input within a step: the inputs act through the state
        let _ = writeln!(w, "    <Outputs>");
        for i in &outputs {
            let _ = writeln!(w, r#"      <Unknown index="{i}" dependencies=""/>"#);
        }
        let _ = writeln!(w, "    </Outputs>");
        let _ = writeln!(w, "    <InitialUnknowns>");
        for i in &outputs {
            let _ = writeln!(w, r#"      <Unknown index="{i}"/>"#);
        }
        let _ = writeln!(w, "    </InitialUnknowns>");
        let _ = writeln!(w, "  </ModelStructure>");
        let _ = writeln!(w, "</fmiModelDescription>");
        x
    }
}

/// A number as the description writes it: the shortest text that reads back to the same bits.
fn real(v: f64) -> String {
    format!("{v:?}")
}

/// Text escaped for an XML attribute.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
