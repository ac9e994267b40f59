//! What an FMU says about itself: the variables (value references in one
//! fixed order), `modelDescription.xml`, the manifest the shared library
//! reads from `resources/` at instantiation, and the guid that ties them to
//! one scene and one binary.
//!
//! Value references: the inputs first (`0 … ni-1`, the scene's `[[inputs]]`
//! in file order), then the outputs (`ni … ni+no-1`, `[[outputs]]` in
//! order), then the parameters (`--parameter` keys in the order given).

use serde_json::{json, Value};

/// The file under `resources/` that the shared library reads at
/// instantiation (JSON: the scene's path inside `resources/`, the variables
/// and the guid).
pub const MANIFEST: &str = "ffr-fmu.json";

/// `generationTool` of every model description ffr writes; `ffr fmu`
/// replaces an existing `.fmu` only when its model description says this.
pub const GENERATION_TOOL: &str = concat!("ffr ", env!("CARGO_PKG_VERSION"), " (ffr fmu)");

/// The most `--parameter` keys of one FMU (the most overrides a scene text takes).
pub const MAX_PARAMETERS: usize = ffr::scene::edit::MAX_OVERRIDES;

/// A real parameter: a dotted scene key and the scene's value there.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// The dotted key (`bodies.arm.params.e`), also the variable's name.
    pub key: String,
    /// The scene's value (the variable's `start`).
    pub start: f64,
}

/// Everything an FMU of a scene declares and its shared library needs.
#[derive(Clone, Debug, PartialEq)]
pub struct Manifest {
    /// The FMU's guid (`{…}`), checked against `fmi2Instantiate`'s.
    pub guid: String,
    /// `modelIdentifier`: the shared library's name without `.so`, a C identifier.
    pub model_identifier: String,
    /// `modelName`.
    pub model_name: String,
    /// The scene's description line.
    pub description: Option<String>,
    /// The scene file's path inside `resources/` (`/`-separated).
    pub scene: String,
    /// Inputs: name and start value.
    pub inputs: Vec<(String, f64)>,
    /// Outputs: name and a description (what and the unit).
    pub outputs: Vec<(String, String)>,
    /// Parameters.
    pub parameters: Vec<Parameter>,
    /// The scene's step (s): `DefaultExperiment stepSize`.
    pub dt: f64,
    /// The scene's end time (s): `DefaultExperiment stopTime`.
    pub t_end: f64,
}

/// What a variable is, by value reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Var {
    /// Input `i` (0-based, file order).
    Input(usize),
    /// Output `i`.
    Output(usize),
    /// Parameter `i`.
    Parameter(usize),
}

impl Manifest {
    /// The variable a value reference names, if any.
    pub fn var(&self, vr: u32) -> Option<Var> {
        let vr = vr as usize;
        let (ni, no, np) = (self.inputs.len(), self.outputs.len(), self.parameters.len());
        if vr < ni {
            Some(Var::Input(vr))
        } else if vr < ni + no {
            Some(Var::Output(vr - ni))
        } else if vr < ni + no + np {
            Some(Var::Parameter(vr - ni - no))
        } else {
            None
        }
    }

    /// The number of value references (inputs, outputs, parameters).
    pub fn variable_count(&self) -> usize {
        self.inputs.len() + self.outputs.len() + self.parameters.len()
    }

    /// The variable's name.
    pub fn name(&self, v: Var) -> &str {
        match v {
            Var::Input(i) => &self.inputs[i].0,
            Var::Output(i) => &self.outputs[i].0,
            Var::Parameter(i) => &self.parameters[i].key,
        }
    }

    /// Check what `ffr fmu` would declare: names unique across inputs,
    /// outputs and parameters, non-empty, without control characters; at
    /// most [`MAX_PARAMETERS`] parameters; finite starts; `dt` > 0.
    pub fn check(&self) -> Result<(), String> {
        if self.parameters.len() > MAX_PARAMETERS {
            return Err(format!(
                "{} parameters: an FMU takes at most {MAX_PARAMETERS}",
                self.parameters.len()
            ));
        }
        let mut seen: Vec<(&str, &str)> = Vec::new();
        let all = self
            .inputs
            .iter()
            .map(|(n, _)| (n.as_str(), "input"))
            .chain(self.outputs.iter().map(|(n, _)| (n.as_str(), "output")))
            .chain(
                self.parameters
                    .iter()
                    .map(|p| (p.key.as_str(), "parameter")),
            );
        for (name, what) in all {
            if name.is_empty() || name.chars().any(char::is_control) {
                return Err(format!(
                    "the {what} name {name:?} is empty or has a control character: an FMU variable needs a printable name"
                ));
            }
            if let Some((_, other)) = seen.iter().find(|(n, _)| *n == name) {
                return Err(format!(
                    "`{name}` names both an {other} and an {what}: an FMU's variables need distinct names"
                ));
            }
            seen.push((name, what));
        }
        for (n, s) in &self.inputs {
            if !s.is_finite() {
                return Err(format!("input `{n}` starts at {s}, not a finite number"));
            }
        }
        for p in &self.parameters {
            if !p.start.is_finite() {
                return Err(format!(
                    "parameter `{}` is {}, not a finite number",
                    p.key, p.start
                ));
            }
        }
        if !(self.dt > 0.0 && self.dt.is_finite() && self.t_end.is_finite()) {
            return Err(format!(
                "the scene's step {} and end time {} must be finite, the step positive",
                self.dt, self.t_end
            ));
        }
        Ok(())
    }

    /// The manifest as JSON (what `resources/ffr-fmu.json` holds).
    pub fn to_json(&self) -> String {
        let v = json!({
            "written_by": "ffr fmu",
            "guid": self.guid,
            "model_identifier": self.model_identifier,
            "model_name": self.model_name,
            "description": self.description,
            "scene": self.scene,
            "inputs": self.inputs.iter().map(|(n, s)| json!({"name": n, "start": s})).collect::<Vec<_>>(),
            "outputs": self.outputs.iter().map(|(n, d)| json!({"name": n, "description": d})).collect::<Vec<_>>(),
            "parameters": self.parameters.iter().map(|p| json!({"key": p.key, "start": p.start})).collect::<Vec<_>>(),
            "dt": self.dt,
            "t_end": self.t_end,
        });
        let mut s = serde_json::to_string_pretty(&v).expect("a JSON value serializes");
        s.push('\n');
        s
    }

    /// Read a manifest; errors say which key is wrong.
    pub fn from_json(text: &str) -> Result<Manifest, String> {
        let v: Value = serde_json::from_str(text).map_err(|e| format!("not valid JSON: {e}"))?;
        let s = |k: &str| -> Result<String, String> {
            v.get(k)
                .and_then(Value::as_str)
                .map(str::to_string)
                .ok_or_else(|| format!("no string `{k}`"))
        };
        let f = |x: &Value, k: &str| -> Result<f64, String> {
            x.get(k)
                .and_then(Value::as_f64)
                .ok_or_else(|| format!("no number `{k}`"))
        };
        let list = |k: &str| -> Result<&Vec<Value>, String> {
            v.get(k)
                .and_then(Value::as_array)
                .ok_or_else(|| format!("no list `{k}`"))
        };
        let name = |x: &Value, k: &str| -> Result<String, String> {
            x.get(k)
                .and_then(Value::as_str)
                .map(str::to_string)
                .ok_or_else(|| format!("an entry without a string `{k}`"))
        };
        if v.get("written_by").and_then(Value::as_str) != Some("ffr fmu") {
            return Err("not written by `ffr fmu` (no \"written_by\": \"ffr fmu\")".into());
        }
        let m = Manifest {
            guid: s("guid")?,
            model_identifier: s("model_identifier")?,
            model_name: s("model_name")?,
            description: v
                .get("description")
                .and_then(Value::as_str)
                .map(str::to_string),
            scene: s("scene")?,
            inputs: list("inputs")?
                .iter()
                .map(|x| Ok((name(x, "name")?, f(x, "start")?)))
                .collect::<Result<_, String>>()?,
            outputs: list("outputs")?
                .iter()
                .map(|x| Ok((name(x, "name")?, name(x, "description")?)))
                .collect::<Result<_, String>>()?,
            parameters: list("parameters")?
                .iter()
                .map(|x| {
                    Ok(Parameter {
                        key: name(x, "key")?,
                        start: f(x, "start")?,
                    })
                })
                .collect::<Result<_, String>>()?,
            dt: f(&v, "dt")?,
            t_end: f(&v, "t_end")?,
        };
        m.check()?;
        Ok(m)
    }

    /// `modelDescription.xml` (FMI 2.0, Co-Simulation).
    pub fn model_description(&self) -> String {
        let mut x = String::new();
        x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        x.push_str(&format!(
            "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{}\" guid=\"{}\"{} generationTool=\"{}\" variableNamingConvention=\"flat\" numberOfEventIndicators=\"0\">\n",
            esc(&self.model_name),
            esc(&self.guid),
            self.description
                .as_ref()
                .map_or(String::new(), |d| format!(" description=\"{}\"", esc(d))),
            esc(GENERATION_TOOL),
        ));
        x.push_str(&format!(
            "  <CoSimulation modelIdentifier=\"{}\" needsExecutionTool=\"false\" canHandleVariableCommunicationStepSize=\"true\" canInterpolateInputs=\"false\" maxOutputDerivativeOrder=\"0\" canRunAsynchronuously=\"false\" canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\" canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"false\" providesDirectionalDerivative=\"false\"/>\n",
            esc(&self.model_identifier)
        ));
        x.push_str("  <LogCategories>\n");
        for (name, what) in LOG_CATEGORIES {
            x.push_str(&format!(
                "    <Category name=\"{name}\" description=\"{what}\"/>\n"
            ));
        }
        x.push_str("  </LogCategories>\n");
        x.push_str(&format!(
            "  <DefaultExperiment startTime=\"0.0\" stopTime=\"{}\" stepSize=\"{}\"/>\n",
            num(self.t_end),
            num(self.dt)
        ));
        x.push_str("  <ModelVariables>\n");
        let mut vr = 0usize;
        for (name, start) in &self.inputs {
            x.push_str(&format!(
                "    <ScalarVariable name=\"{}\" valueReference=\"{vr}\" description=\"input of the scene (held between communication points)\" causality=\"input\" variability=\"continuous\">\n      <Real start=\"{}\"/>\n    </ScalarVariable>\n",
                esc(name),
                num(*start)
            ));
            vr += 1;
        }
        for (name, what) in &self.outputs {
            x.push_str(&format!(
                "    <ScalarVariable name=\"{}\" valueReference=\"{vr}\" description=\"{}\" causality=\"output\" variability=\"continuous\" initial=\"calculated\">\n      <Real/>\n    </ScalarVariable>\n",
                esc(name),
                esc(what)
            ));
            vr += 1;
        }
        for p in &self.parameters {
            x.push_str(&format!(
                "    <ScalarVariable name=\"{}\" valueReference=\"{vr}\" description=\"scene value at this key (set before initialization)\" causality=\"parameter\" variability=\"fixed\" initial=\"exact\">\n      <Real start=\"{}\"/>\n    </ScalarVariable>\n",
                esc(&p.key),
                num(p.start)
            ));
            vr += 1;
        }
        x.push_str("  </ModelVariables>\n  <ModelStructure>\n");
        let first_output = self.inputs.len() + 1;
        if !self.outputs.is_empty() {
            // No direct feedthrough: an output at a communication point is
            // a function of the state; the inputs act through the step.
            x.push_str("    <Outputs>\n");
            for i in 0..self.outputs.len() {
                x.push_str(&format!(
                    "      <Unknown index=\"{}\" dependencies=\"\"/>\n",
                    first_output + i
                ));
            }
            x.push_str("    </Outputs>\n    <InitialUnknowns>\n");
            for i in 0..self.outputs.len() {
                x.push_str(&format!(
                    "      <Unknown index=\"{}\"/>\n",
                    first_output + i
                ));
            }
            x.push_str("    </InitialUnknowns>\n");
        }
        x.push_str("  </ModelStructure>\n</fmiModelDescription>\n");
        x
    }
}

/// The log categories the model description declares: name, meaning.
pub const LOG_CATEGORIES: [(&str, &str); 3] = [
    (
        "logStatusError",
        "refused calls and their reason (always logged)",
    ),
    (
        "logStatusDiscard",
        "failed steps and their reason (always logged)",
    ),
    ("logAll", "every call (with fmi2SetDebugLogging)"),
];

/// A number as XML attributes and JSON take it: the shortest decimal that
/// reads back to the same `f64`.
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// Text for an XML attribute value.
pub fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            '\n' => o.push_str("&#10;"),
            '\r' => o.push_str("&#13;"),
            '\t' => o.push_str("&#9;"),
            c if (c as u32) < 0x20 => o.push(' '),
            c => o.push(c),
        }
    }
    o
}

/// A C identifier from `s` (for `modelIdentifier`): letters, digits and `_`,
/// anything else as `_`, a leading digit (or nothing) prefixed with `_`.
pub fn c_identifier(s: &str) -> String {
    let mut o: String = s
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if o.is_empty() || o.starts_with(|c: char| c.is_ascii_digit()) {
        o.insert(0, '_');
    }
    o
}

/// A 128-bit FNV-1a hash of byte strings (each with its length in front, so
/// that the parts are delimited), for the guid. Not cryptographic: the guid
/// tells FMUs of different scenes or binaries apart.
#[derive(Clone, Debug)]
pub struct Fingerprint(u128);

impl Default for Fingerprint {
    fn default() -> Self {
        Fingerprint(0x6c62272e07bb014262b821756295c58d)
    }
}

impl Fingerprint {
    /// Add a part.
    pub fn add(&mut self, bytes: &[u8]) {
        const PRIME: u128 = 0x0000000001000000000000000000013B;
        for b in (bytes.len() as u64).to_le_bytes().iter().chain(bytes) {
            self.0 ^= u128::from(*b);
            self.0 = self.0.wrapping_mul(PRIME);
        }
    }

    /// The guid: `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
    pub fn guid(&self) -> String {
        let h = format!("{:032x}", self.0);
        format!(
            "{{{}-{}-{}-{}-{}}}",
            &h[0..8],
            &h[8..12],
            &h[12..16],
            &h[16..20],
            &h[20..32]
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifest() -> Manifest {
        Manifest {
            guid: "{0}".into(),
            model_identifier: "arm".into(),
            model_name: "arm".into(),
            description: Some("a \"flexible\" arm & <hub>".into()),
            scene: "arm.toml".into(),
            inputs: vec![("tau".into(), 0.5)],
            outputs: vec![("tip_y".into(), "position y (m)".into())],
            parameters: vec![Parameter {
                key: "bodies.arm.params.e".into(),
                start: 7e10,
            }],
            dt: 1e-3,
            t_end: 2.0,
        }
    }

    #[test]
    fn value_references_are_inputs_outputs_parameters() {
        let m = manifest();
        assert_eq!(m.var(0), Some(Var::Input(0)));
        assert_eq!(m.var(1), Some(Var::Output(0)));
        assert_eq!(m.var(2), Some(Var::Parameter(0)));
        assert_eq!(m.var(3), None);
        assert_eq!(m.var(u32::MAX), None);
        assert_eq!(m.name(Var::Parameter(0)), "bodies.arm.params.e");
    }

    #[test]
    fn the_manifest_reads_back() {
        let m = manifest();
        assert_eq!(Manifest::from_json(&m.to_json()).unwrap(), m);
        let e = Manifest::from_json("{\"guid\": \"x\"}").unwrap_err();
        assert!(e.contains("not written by `ffr fmu`"), "{e}");
        let bad = m.to_json().replace("\"dt\": 0.001", "\"dt\": -1.0");
        let e = Manifest::from_json(&bad).unwrap_err();
        assert!(e.contains("step"), "{e}");
    }

    #[test]
    fn names_must_be_distinct() {
        let mut m = manifest();
        m.outputs[0].0 = "tau".into();
        let e = m.check().unwrap_err();
        assert!(e.contains("`tau` names both an input and an output"), "{e}");
    }

    #[test]
    fn text_is_escaped_and_numbers_round_trip() {
        let x = manifest().model_description();
        assert!(
            x.contains("a &quot;flexible&quot; arm &amp; &lt;hub&gt;"),
            "{x}"
        );
        assert!(x.contains("stepSize=\"0.001\""), "{x}");
        assert!(x.contains("<Real start=\"70000000000.0\"/>"), "{x}");
        assert!(
            x.contains("<Unknown index=\"2\" dependencies=\"\"/>"),
            "{x}"
        );
        assert_eq!(c_identifier("2-link arm"), "_2_link_arm");
        assert_eq!(c_identifier(""), "_");
    }

    #[test]
    fn the_guid_depends_on_every_part_and_their_bounds() {
        let g = |parts: &[&[u8]]| {
            let mut f = Fingerprint::default();
            for p in parts {
                f.add(p);
            }
            f.guid()
        };
        assert_eq!(g(&[b"a", b"b"]), g(&[b"a", b"b"]));
        assert_ne!(g(&[b"a", b"b"]), g(&[b"ab"]));
        assert_ne!(g(&[b"a", b"b"]), g(&[b"a", b"c"]));
        assert_eq!(g(&[b"x"]).len(), 38);
    }
}
