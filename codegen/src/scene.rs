//! Scene files (TOML): the format as read (every value keeps its span so
//! that errors name `file:line:col`), and what a scene fixes for the
//! generator — which bodies are flexible, with which options, whether their
//! frame motion is prescribed (a revolute joint to the ground at the frame
//! origin with an angle drive) and whether their frame acceleration `ā`
//! vanishes (origin fixed, no gravity). The root crate builds and runs the
//! scene from the same description (`ffr::scene`); [`crate::Builder::scene`]
//! compiles its bodies' specialized kernels.

use crate::error::{Error, Location};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// A scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    /// `2` (planar) or `3` (spatial).
    pub dimension: Spanned<i64>,
    pub gravity: Option<Spanned<Vec<f64>>>,
    pub t_end: Spanned<f64>,
    pub dt: Spanned<f64>,
    pub integrator: Option<Spanned<RawIntegrator>>,
    /// Bodies by name (the name keeps its span, for errors about it).
    #[serde(default)]
    pub bodies: BTreeMap<Spanned<String>, RawBody>,
    #[serde(default)]
    pub joints: Vec<RawJoint>,
    #[serde(default)]
    pub forces: Vec<RawForce>,
    #[serde(default)]
    pub outputs: Vec<RawOutput>,
    /// A one-line description (shown in reports).
    pub description: Option<String>,
}

/// `integrator = { kind = "generalized-alpha", rho_inf = 0.8 }` or
/// `{ kind = "rk4", alpha = 10, beta = 10 }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawIntegrator {
    pub kind: Spanned<String>,
    pub rho_inf: Option<Spanned<f64>>,
    pub rtol: Option<Spanned<f64>>,
    pub alpha: Option<Spanned<f64>>,
    pub beta: Option<Spanned<f64>>,
}

/// A body: flexible (`shape = …`) or rigid (`mass = …`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBody {
    // Flexible.
    pub shape: Option<Spanned<String>>,
    pub elements: Option<Spanned<i64>>,
    pub reference: Option<Spanned<String>>,
    pub stiffening: Option<Spanned<toml::Value>>,
    pub formalism: Option<Spanned<String>>,
    pub params: Option<Spanned<BTreeMap<Spanned<String>, Spanned<f64>>>>,
    pub damping: Option<Spanned<RawDamping>>,
    pub modes: Option<Spanned<i64>>,
    pub reduction: Option<Spanned<String>>,
    pub boundary_nodes: Option<Spanned<Vec<i64>>>,
    pub modal_damping: Option<Spanned<toml::Value>>,
    pub static_modes: Option<Spanned<bool>>,
    // Rigid.
    pub mass: Option<Spanned<f64>>,
    pub inertia: Option<Spanned<toml::Value>>,
    pub centre: Option<Spanned<Vec<f64>>>,
    // Both.
    pub position: Option<Spanned<Vec<f64>>>,
    pub angle: Option<Spanned<f64>>,
    pub orientation: Option<Spanned<RawOrientation>>,
    pub velocity: Option<Spanned<Vec<f64>>>,
    pub omega: Option<Spanned<toml::Value>>,
    /// Initial elastic state (flexible bodies).
    pub elastic: Option<Spanned<RawElastic>>,
}

/// A table of values by coordinate label, `{ uy_4 = 1e-3, rz_4 = 0.01 }`.
pub type RawLabelled = BTreeMap<Spanned<String>, Spanned<f64>>;

/// `elastic = { q = { ux_8 = 1e-5 }, qd = { uy_4 = 0.4 } }`: initial
/// elastic coordinates and rates by label (the body's coordinate labels,
/// `ux_i`, `uy_i`, `rz_i`, …); labels not given start at 0.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawElastic {
    pub q: Option<Spanned<RawLabelled>>,
    pub qd: Option<Spanned<RawLabelled>>,
}

/// `orientation = { axis = [0, 0, 1], angle = 0.0 }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawOrientation {
    pub axis: Spanned<Vec<f64>>,
    pub angle: Spanned<f64>,
}

/// `damping = { alpha = 0.0, beta = 1e-4 }` (Rayleigh).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawDamping {
    pub alpha: Option<Spanned<f64>>,
    pub beta: Option<Spanned<f64>>,
}

/// A joint.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawJoint {
    pub kind: Spanned<String>,
    pub a: Option<Spanned<String>>,
    pub b: Spanned<String>,
    pub drive: Option<Spanned<RawProfile>>,
    pub motor: Option<Spanned<RawMotor>>,
}

/// A prescribed motion: `{ angle = "spin-up", omega = 4.0, ramp = 15.0 }`,
/// `{ angle = "constant-rate", omega = 2.0 }`, `{ slide = "harmonic",
/// amplitude = 0.1, frequency = 1.0 }`, …
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawProfile {
    pub angle: Option<Spanned<String>>,
    pub slide: Option<Spanned<String>>,
    pub omega: Option<Spanned<f64>>,
    pub ramp: Option<Spanned<f64>>,
    pub value: Option<Spanned<f64>>,
    pub start: Option<Spanned<f64>>,
    pub rate: Option<Spanned<f64>>,
    pub amplitude: Option<Spanned<f64>>,
    pub frequency: Option<Spanned<f64>>,
    pub phase: Option<Spanned<f64>>,
}

/// A motor's target: an angle (rad) or a profile table.
#[derive(Debug)]
pub enum RawTarget {
    /// A constant angle.
    Angle(f64),
    /// A prescribed angle profile (`{ angle = "harmonic", … }`; boxed: it
    /// is much larger than an angle).
    Profile(Box<RawProfile>),
}

impl<'de> Deserialize<'de> for RawTarget {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RawTarget;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an angle (rad) or a profile table such as { angle = \"harmonic\", amplitude = 0.3, frequency = 1.0 }")
            }
            fn visit_f64<E>(self, v: f64) -> Result<RawTarget, E> {
                Ok(RawTarget::Angle(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<RawTarget, E> {
                Ok(RawTarget::Angle(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<RawTarget, E> {
                Ok(RawTarget::Angle(v as f64))
            }
            // The profile's fields are read by the TOML deserializer itself,
            // so they keep their spans.
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<RawTarget, A::Error> {
                RawProfile::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(|p| RawTarget::Profile(Box::new(p)))
            }
        }
        d.deserialize_any(V)
    }
}

/// `motor = { torque = 0.5 }` or `{ target = 1.0, kp = 10.0, kd = 1.0 }`
/// (or a target profile, `target = { angle = "constant-rate", omega = 1.0 }`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMotor {
    pub torque: Option<Spanned<f64>>,
    pub target: Option<Spanned<RawTarget>>,
    pub kp: Option<Spanned<f64>>,
    pub kd: Option<Spanned<f64>>,
}

/// A force element.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawForce {
    pub kind: Spanned<String>,
    pub at: Option<Spanned<String>>,
    pub a: Option<Spanned<String>>,
    pub b: Option<Spanned<String>>,
    pub force: Option<Spanned<Vec<f64>>>,
    pub axes: Option<Spanned<String>>,
    pub stiffness: Option<Spanned<f64>>,
    pub damping: Option<Spanned<f64>>,
    pub rest_length: Option<Spanned<f64>>,
    pub rest_angle: Option<Spanned<f64>>,
    pub torque: Option<Spanned<f64>>,
}

/// An output column.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawOutput {
    pub name: Spanned<String>,
    pub kind: Spanned<String>,
    pub at: Option<Spanned<String>>,
    pub a: Option<Spanned<String>>,
    pub component: Option<Spanned<String>>,
}

impl RawBody {
    /// A span inside the body's table (its first key present), for errors
    /// about the body as a whole.
    pub fn span(&self) -> Option<std::ops::Range<usize>> {
        self.shape
            .as_ref()
            .map(|x| x.span())
            .or(self.mass.as_ref().map(|x| x.span()))
            .or(self.elements.as_ref().map(|x| x.span()))
            .or(self.params.as_ref().map(|x| x.span()))
            .or(self.position.as_ref().map(|x| x.span()))
    }
}

impl RawJoint {
    /// The joint's span (its `kind`).
    pub fn span(&self) -> std::ops::Range<usize> {
        self.kind.span()
    }
}

impl RawForce {
    /// The force's span (its `kind`).
    pub fn span(&self) -> std::ops::Range<usize> {
        self.kind.span()
    }
}

impl RawOutput {
    /// The output's span (its `name`).
    pub fn span(&self) -> std::ops::Range<usize> {
        self.name.span()
    }
}

/// The most bytes a scene file may have.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// Parse a scene file's text (`file` names it in errors).
pub fn parse(text: &str, file: &str) -> Result<RawScene, Error> {
    toml::from_str(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        let msg = shorten_quoted(&crate::shape::parser_message(&e, text));
        Error::Scene {
            location: Location::of(file, text, offset),
            message: if msg.is_empty() {
                "the file is not valid TOML".into()
            } else {
                msg
            },
        }
    })
}

/// The most characters of a user string (a name, a key, a marker) quoted in
/// a message; longer ones are cut with `…`.
pub const MAX_QUOTED_CHARS: usize = 64;

/// A user string as quoted in a message: escaped and at most
/// [`MAX_QUOTED_CHARS`] characters ([`crate::sanitize::snippet`]).
pub fn quoted(s: &str) -> String {
    crate::sanitize::snippet(s, MAX_QUOTED_CHARS)
}

/// `msg` (of the TOML parser, which quotes keys and values in full) with
/// every `` `…` `` and `"…"` part escaped and shortened ([`quoted`]).
fn shorten_quoted(msg: &str) -> String {
    let mut out = String::new();
    let mut rest = msg;
    while let Some(i) = rest.find(['`', '"']) {
        let q = rest[i..].chars().next().expect("found");
        out.push_str(&rest[..=i]);
        rest = &rest[i + 1..];
        match rest.find(q) {
            Some(j) => {
                out.push_str(&quoted(&rest[..j]));
                out.push(q);
                rest = &rest[j + 1..];
            }
            None => {
                out.push_str(&quoted(rest));
                rest = "";
            }
        }
    }
    out.push_str(rest);
    crate::sanitize::snippet(&out, 1024)
}

/// The name of a body's generated kernel type in a compiled scene (without
/// the scene type's prefix): the CamelCase of its snake case (`two_link` and
/// `twoLink` both give `TwoLink`).
pub fn body_type_name(name: &str) -> String {
    crate::builder::camel_case(&crate::builder::snake_case(name))
}

/// Read a scene file through a bound of [`MAX_SCENE_BYTES`] (only a regular
/// file: [`crate::limits::read_input`]), as UTF-8.
pub fn read(path: &Path) -> Result<String, Error> {
    let file = crate::sanitize::snippet(&path.display().to_string(), usize::MAX);
    let io = |m: String| Error::Io {
        path: file.clone(),
        message: m,
    };
    let bytes = crate::limits::read_input(path, MAX_SCENE_BYTES, "scene file", "MAX_SCENE_BYTES")
        .map_err(io)?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        io(format!(
            "is not UTF-8 text (byte 0x{:02x} at byte offset {at})",
            e.as_bytes()[at]
        ))
    })
}

impl RawJoint {
    /// Whether this joint fixes its body's frame completely and can be
    /// folded into prescribed frame coordinates: a revolute joint between a
    /// ground point and a body's frame origin (`b = "NAME"`), with an angle
    /// drive and no motor. Flexible and rigid bodies alike.
    pub fn folds(&self) -> bool {
        self.kind.get_ref() == "revolute"
            && self.motor.is_none()
            && self
                .drive
                .as_ref()
                .is_some_and(|d| d.get_ref().angle.is_some())
            && self
                .a
                .as_ref()
                .is_some_and(|a| a.get_ref().trim().starts_with("ground@"))
            && !self.b.get_ref().contains('@')
    }
}

impl RawScene {
    /// For each body (by name; flexible or rigid), the joint that folds its
    /// frame, if any.
    pub fn folded(&self) -> BTreeMap<String, usize> {
        let mut out = BTreeMap::new();
        for (i, j) in self.joints.iter().enumerate() {
            if j.folds() {
                let b = j.b.get_ref().trim().to_string();
                if self.bodies.contains_key(b.as_str()) {
                    out.entry(b).or_insert(i);
                }
            }
        }
        out
    }

    /// Whether the scene has non-zero gravity.
    pub fn has_gravity(&self) -> bool {
        self.gravity
            .as_ref()
            .is_some_and(|g| g.get_ref().iter().any(|x| *x != 0.0))
    }
}

/// What the generator needs of a flexible body of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexBodyModel {
    /// Body name.
    pub name: String,
    /// Its shape as written (a built-in name, or a path relative to the scene file).
    pub shape: String,
    /// Span of the shape string (for errors).
    pub span: Range<usize>,
    /// Its kernel options: the scene's dimension, a free frame unless a
    /// folded joint prescribes its motion (then at rest when, in addition,
    /// the scene has no gravity: `ā = Aᵀ(R̈ − g) ≡ 0`).
    pub options: ffr_spec::KernelOptions,
}

fn scene_err(text: &str, file: &str, span: Range<usize>, message: String) -> Error {
    Error::Scene {
        location: Location::of(file, text, span.start),
        message,
    }
}

/// The stiffening model of `stiffening = true | false | "second-order" | "fourth-order"`.
pub fn stiffening_of(
    v: &Spanned<toml::Value>,
    text: &str,
    file: &str,
) -> Result<ffr_spec::Stiffening, Error> {
    match v.get_ref() {
        toml::Value::Boolean(b) => Ok(ffr_spec::Stiffening::from_bool(*b)),
        toml::Value::String(s) if matches!(s.as_str(), "second-order" | "fourth-order" | "off") => {
            Ok(s.parse().expect("checked"))
        }
        other => Err(scene_err(
            text,
            file,
            v.span(),
            format!(
                "`stiffening` must be true, false, \"second-order\" or \"fourth-order\", found a {}",
                other.type_str()
            ),
        )),
    }
}

/// The scene's dimension (2 or 3).
pub fn dimension_of(raw: &RawScene, text: &str, file: &str) -> Result<usize, Error> {
    match *raw.dimension.get_ref() {
        2 => Ok(2),
        3 => Ok(3),
        d => Err(scene_err(
            text,
            file,
            raw.dimension.span(),
            format!("`dimension` must be 2 (planar) or 3 (spatial), found {d}"),
        )),
    }
}

/// What the generator needs of each flexible body of a scene, in body-name
/// order: its options, and what the scene fixes (frame motion prescribed by
/// a folded joint; `ā ≡ 0` when, in addition, there is no gravity).
pub fn flex_models(raw: &RawScene, text: &str, file: &str) -> Result<Vec<FlexBodyModel>, Error> {
    let dim = dimension_of(raw, text, file)?;
    let folded = raw.folded();
    let gravity = raw.has_gravity();
    let mut out = Vec::new();
    for (name, rb) in &raw.bodies {
        let name = name.get_ref();
        let Some(shape) = &rb.shape else { continue };
        let formalism = match &rb.formalism {
            Some(f) => f.get_ref().parse().map_err(|_: String| {
                scene_err(
                    text,
                    file,
                    f.span(),
                    format!(
                        "unknown formalism `{}`: expected consistent or lumped",
                        quoted(f.get_ref())
                    ),
                )
            })?,
            None => ffr_spec::Formalism::Consistent,
        };
        let stiffening = match &rb.stiffening {
            Some(v) => stiffening_of(v, text, file)?,
            None => ffr_spec::Stiffening::Off,
        };
        let fixed = folded.contains_key(name.as_str());
        out.push(FlexBodyModel {
            name: name.clone(),
            shape: shape.get_ref().clone(),
            span: shape.span(),
            options: ffr_spec::KernelOptions {
                formalism,
                stiffening,
                scene: ffr_spec::SceneDim::from_dim(dim),
                frame: ffr_spec::FrameModel::from_flags(!fixed, fixed && !gravity),
            },
        });
    }
    Ok(out)
}

/// The span of the key whose value is at `value` (the text before it reads
/// `key =`, bare or quoted); the value's own span otherwise.
fn key_span(text: &str, value: Range<usize>) -> Range<usize> {
    let Some(before) = text.get(..value.start) else {
        return value;
    };
    let Some(t) = before.trim_end().strip_suffix('=') else {
        return value;
    };
    let t = t.trim_end();
    let end = t.len();
    let start = match t.chars().last() {
        Some(q @ ('"' | '\'')) => t[..end - 1].rfind(q).unwrap_or(end),
        _ => t
            .char_indices()
            .rev()
            .find(|(_, c)| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-')))
            .map_or(0, |(i, c)| i + c.len_utf8()),
    };
    if start < end {
        start..end
    } else {
        value
    }
}

/// The keys of a table that are present, with their values' spans.
type Keys = Vec<(&'static str, Range<usize>)>;

fn keys<const N: usize>(list: [(&'static str, Option<Range<usize>>); N]) -> Keys {
    let mut out: Keys = list
        .into_iter()
        .filter_map(|(k, s)| s.map(|s| (k, s)))
        .collect();
    out.sort_by_key(|(_, s)| s.start);
    out
}

fn sp<T>(v: &Option<Spanned<T>>) -> Option<Range<usize>> {
    v.as_ref().map(|x| x.span())
}

/// The first key of `present` that `takes` does not list, as the error
/// `` `key` does not apply to WHAT: it takes `a`, `b`, … `` (and the hint for
/// that key, if any), at the key.
fn applies(
    text: &str,
    file: &str,
    present: &Keys,
    takes: &[&str],
    what: &str,
    hints: &[(&str, &str)],
) -> Result<(), Error> {
    for (k, span) in present {
        if !takes.contains(k) {
            let list: Vec<String> = takes.iter().map(|t| format!("`{t}`")).collect();
            let hint = hints
                .iter()
                .find(|(h, _)| h == k)
                .map_or(String::new(), |(_, h)| format!(" ({h})"));
            return Err(scene_err(
                text,
                file,
                key_span(text, span.clone()),
                format!(
                    "`{k}` does not apply to {what}: it takes {}{hint}",
                    list.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// A drive's (or a motor target's) profile table: `key` (`angle` or `slide`)
/// names the profile, and each profile takes its own keys.
fn check_profile(
    text: &str,
    file: &str,
    p: &RawProfile,
    key: &str,
    owner: &str,
) -> Result<(), Error> {
    let all = keys([
        ("angle", sp(&p.angle)),
        ("slide", sp(&p.slide)),
        ("omega", sp(&p.omega)),
        ("ramp", sp(&p.ramp)),
        ("value", sp(&p.value)),
        ("start", sp(&p.start)),
        ("rate", sp(&p.rate)),
        ("amplitude", sp(&p.amplitude)),
        ("frequency", sp(&p.frequency)),
        ("phase", sp(&p.phase)),
    ]);
    let other = if key == "angle" { "slide" } else { "angle" };
    if let Some((_, span)) = all.iter().find(|(k, _)| *k == other) {
        return Err(scene_err(
            text,
            file,
            key_span(text, span.clone()),
            format!(
                "`{other}` does not apply to {owner}: it takes `{key} = \"PROFILE\"` ({})",
                if key == "angle" {
                    "the relative angle; `slide` is for prismatic joints"
                } else {
                    "the relative displacement along `a`'s x axis; `angle` is for revolute joints and motors"
                }
            ),
        ));
    }
    let name = if key == "angle" { &p.angle } else { &p.slide };
    let Some(name) = name else { return Ok(()) };
    let takes: &[&str] = match name.get_ref().as_str() {
        "spin-up" => &["omega", "ramp", "start"],
        "constant-rate" => {
            if let (Some(_), Some(r)) = (&p.omega, &p.rate) {
                return Err(scene_err(
                    text,
                    file,
                    key_span(text, r.span()),
                    "`rate` and `omega` both give the rate of profile `constant-rate`: give one"
                        .into(),
                ));
            }
            &["omega", "rate", "start"]
        }
        "constant" => &["value"],
        "harmonic" => &["amplitude", "frequency", "start", "phase"],
        // Reported by the loader with the list of profiles.
        _ => return Ok(()),
    };
    let takes: Vec<&str> = std::iter::once(key).chain(takes.iter().copied()).collect();
    let present: Keys = all.into_iter().filter(|(k, _)| *k != key).collect();
    applies(
        text,
        file,
        &present,
        &takes,
        &format!("profile `{}` ({owner})", name.get_ref()),
        &[
            ("start", "`value` is the value of a constant profile"),
            ("ramp", "`ramp` is the ramp time of profile `spin-up`"),
        ],
    )
}

/// Check what the deserializer cannot: body names (they become generated
/// identifiers: ASCII Rust identifiers of at most 64 characters, not
/// keywords, distinct after conversion to CamelCase; `ground` reserved),
/// and that every key present applies to its table's kind (an integrator's,
/// body's, joint's, drive profile's, motor's, force's or output's): a key
/// that would do nothing is an error at the key, naming the keys that
/// apply. Kinds that do not exist are left to the loader, which lists them.
pub fn check(raw: &RawScene, text: &str, file: &str) -> Result<(), Error> {
    // Body names.
    let mut types: BTreeMap<String, &str> = BTreeMap::new();
    for name in raw.bodies.keys() {
        let n = name.get_ref().as_str();
        let at = name.span();
        if n == "ground" {
            return Err(scene_err(
                text,
                file,
                at,
                "`ground` cannot name a body: it is the fixed frame of markers `ground@[…]`".into(),
            ));
        }
        crate::builder::type_name_of(n).map_err(|e| {
            let m = match e {
                Error::Name(m) => m,
                other => other.to_string(),
            };
            scene_err(text, file, at.clone(), m)
        })?;
        let ty = body_type_name(n);
        if let Some(first) = types.get(&ty) {
            return Err(scene_err(
                text,
                file,
                at,
                format!(
                    "bodies `{first}` and `{n}` both give the generated name `{ty}` (a compiled scene's kernel type `…{ty}Kernels`): body names must differ after conversion to CamelCase"
                ),
            ));
        }
        types.insert(ty, n);
    }
    // The integrator.
    if let Some(i) = &raw.integrator {
        let i = i.get_ref();
        let present = keys([
            ("rho_inf", sp(&i.rho_inf)),
            ("rtol", sp(&i.rtol)),
            ("alpha", sp(&i.alpha)),
            ("beta", sp(&i.beta)),
        ]);
        let hints = [
            ("alpha", "`alpha` and `beta` are the Baumgarte gains of `kind = \"rk4\"`"),
            ("beta", "`alpha` and `beta` are the Baumgarte gains of `kind = \"rk4\"`"),
            ("rho_inf", "`rho_inf` and `rtol` are for `kind = \"generalized-alpha\"`"),
            ("rtol", "`rho_inf` and `rtol` are for `kind = \"generalized-alpha\"`: RK4 has no Newton iteration"),
        ];
        match i.kind.get_ref().as_str() {
            "generalized-alpha" => applies(
                text,
                file,
                &present,
                &["kind", "rho_inf", "rtol"],
                "the generalized-alpha integrator",
                &hints,
            )?,
            "rk4" => applies(
                text,
                file,
                &present,
                &["kind", "alpha", "beta"],
                "the rk4 integrator",
                &hints,
            )?,
            _ => {}
        }
    }
    // Bodies: rigid (`mass`) or flexible (`shape`).
    let spatial = *raw.dimension.get_ref() == 3;
    let orientation = if spatial { "orientation" } else { "angle" };
    for (name, rb) in &raw.bodies {
        let n = name.get_ref();
        // The planar/spatial pose keys have their own messages (the loader).
        let present: Keys = keys([
            ("shape", sp(&rb.shape)),
            ("elements", sp(&rb.elements)),
            ("reference", sp(&rb.reference)),
            ("stiffening", sp(&rb.stiffening)),
            ("formalism", sp(&rb.formalism)),
            ("params", sp(&rb.params)),
            ("damping", sp(&rb.damping)),
            ("modes", sp(&rb.modes)),
            ("reduction", sp(&rb.reduction)),
            ("boundary_nodes", sp(&rb.boundary_nodes)),
            ("modal_damping", sp(&rb.modal_damping)),
            ("static_modes", sp(&rb.static_modes)),
            ("elastic", sp(&rb.elastic)),
            ("mass", sp(&rb.mass)),
            ("inertia", sp(&rb.inertia)),
            ("centre", sp(&rb.centre)),
        ]);
        let both = ["position", orientation, "velocity", "omega"];
        if rb.mass.is_some() {
            let takes: Vec<&str> = ["mass", "inertia", "centre"]
                .into_iter()
                .chain(both)
                .collect();
            applies(
                text,
                file,
                &present,
                &takes,
                &format!("rigid body `{n}` (it has `mass`)"),
                &[
                    (
                        "damping",
                        "Rayleigh `damping` is for the elastic coordinates of a flexible body",
                    ),
                    (
                        "elastic",
                        "`elastic` is the initial state of a flexible body",
                    ),
                ],
            )?;
        } else if rb.shape.is_some() {
            let takes: Vec<&str> = [
                "shape",
                "elements",
                "reference",
                "stiffening",
                "formalism",
                "params",
                "damping",
                "modes",
                "reduction",
                "boundary_nodes",
                "static_modes",
                "modal_damping",
                "elastic",
            ]
            .into_iter()
            .chain(both)
            .collect();
            applies(
                text,
                file,
                &present,
                &takes,
                &format!("flexible body `{n}` (it has `shape`)"),
                &[
                    (
                        "inertia",
                        "a flexible body's inertia follows from its shape and `params`",
                    ),
                    (
                        "centre",
                        "a flexible body's centre of mass follows from its shape and `params`",
                    ),
                ],
            )?;
        }
    }
    // Joints, their drives and motors.
    for j in &raw.joints {
        let kind = j.kind.get_ref().as_str();
        let present = keys([
            ("a", sp(&j.a)),
            ("b", Some(j.b.span())),
            ("drive", sp(&j.drive)),
            ("motor", sp(&j.motor)),
        ]);
        let takes: &[&str] = match kind {
            "ground" => &["kind", "b"],
            "fixed" | "spherical" => &["kind", "a", "b"],
            "revolute" => &["kind", "a", "b", "drive", "motor"],
            "prismatic" => &["kind", "a", "b", "drive"],
            _ => continue,
        };
        applies(
            text,
            file,
            &present,
            takes,
            &format!("a `{kind}` joint"),
            &[
                ("a", "a `ground` joint fixes body `b` where it starts"),
                (
                    "drive",
                    "drives are for revolute (angle) and prismatic (slide) joints",
                ),
                (
                    "motor",
                    "motors act in revolute joints (a torque about the joint axis)",
                ),
            ],
        )?;
        if let (Some(_), Some(m)) = (&j.drive, &j.motor) {
            return Err(scene_err(
                text,
                file,
                key_span(text, m.span()),
                "`motor` does not apply to a driven revolute joint: its `drive` prescribes the angle, so a motor's torque would change nothing; give `drive` or `motor`".into(),
            ));
        }
        if let Some(d) = &j.drive {
            let key = if kind == "prismatic" {
                "slide"
            } else {
                "angle"
            };
            check_profile(
                text,
                file,
                d.get_ref(),
                key,
                &format!("the drive of a `{kind}` joint"),
            )?;
        }
        if let Some(m) = &j.motor {
            let m = m.get_ref();
            let present = keys([
                ("torque", sp(&m.torque)),
                ("target", sp(&m.target)),
                ("kp", sp(&m.kp)),
                ("kd", sp(&m.kd)),
            ]);
            if m.torque.is_some() {
                applies(
                    text,
                    file,
                    &present,
                    &["torque"],
                    "a constant-torque motor (`torque`)",
                    &[
                        (
                            "target",
                            "a PD motor is `{ target = φ, kp = …, kd = … }`, without `torque`",
                        ),
                        ("kp", "`kp` and `kd` are the gains of a PD motor (`target`)"),
                        ("kd", "`kp` and `kd` are the gains of a PD motor (`target`)"),
                    ],
                )?;
            }
            if let Some(t) = &m.target {
                if let RawTarget::Profile(p) = t.get_ref() {
                    check_profile(text, file, p, "angle", "a motor's target")?;
                }
            }
        }
    }
    // Forces.
    for f in &raw.forces {
        let kind = f.kind.get_ref().as_str();
        let present = keys([
            ("at", sp(&f.at)),
            ("a", sp(&f.a)),
            ("b", sp(&f.b)),
            ("force", sp(&f.force)),
            ("axes", sp(&f.axes)),
            ("stiffness", sp(&f.stiffness)),
            ("damping", sp(&f.damping)),
            ("rest_length", sp(&f.rest_length)),
            ("rest_angle", sp(&f.rest_angle)),
            ("torque", sp(&f.torque)),
        ]);
        let takes: &[&str] = match kind {
            "point" => &["kind", "at", "force", "axes"],
            "spring-damper" => &["kind", "a", "b", "stiffness", "rest_length", "damping"],
            "rotational-spring-damper" => &["kind", "a", "b", "stiffness", "damping", "rest_angle"],
            "torque" => &["kind", "a", "b", "torque"],
            _ => continue,
        };
        applies(
            text,
            file,
            &present,
            takes,
            &format!("a `{kind}` force"),
            &[
                (
                    "rest_angle",
                    "`rest_angle` is for a `rotational-spring-damper`",
                ),
                ("rest_length", "`rest_length` is for a `spring-damper`"),
            ],
        )?;
    }
    // Outputs.
    for o in &raw.outputs {
        let kind = o.kind.get_ref().as_str();
        let present = keys([
            ("at", sp(&o.at)),
            ("a", sp(&o.a)),
            ("component", sp(&o.component)),
        ]);
        let takes: &[&str] = match kind {
            "position" | "velocity" | "deflection" => &["name", "kind", "at", "component"],
            "angle" => &["name", "kind", "at", "a"],
            "energy" => &["name", "kind", "component"],
            _ => continue,
        };
        applies(
            text,
            file,
            &present,
            takes,
            &format!(
                "{} `{kind}` output",
                if kind.starts_with(['a', 'e']) {
                    "an"
                } else {
                    "a"
                }
            ),
            &[
                ("a", "`a` is the reference marker of an angle output"),
                ("at", "an energy is the whole system's"),
                (
                    "component",
                    "an angle output has one value (the angle about z)",
                ),
            ],
        )?;
    }
    Ok(())
}
