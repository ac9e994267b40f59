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
    /// Named inputs set between steps (`[[inputs]]`).
    #[serde(default)]
    pub inputs: Vec<RawInput>,
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
    /// A graded mesh: the nodes' x (m), from 0 to the length (instead of
    /// `elements`).
    pub nodes: Option<Spanned<Vec<f64>>>,
    /// Run as `N` FFR sub-bodies joined at `N − 1` cuts on nodes.
    pub segments: Option<Spanned<i64>>,
    /// Sections varying along the span: a CSV file (relative to the scene
    /// file) or an array of tables (instead of `params`).
    pub sections: Option<Spanned<toml::Value>>,
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
    /// Masses attached on the axis: `[[bodies.NAME.masses]]`.
    pub masses: Option<Vec<Spanned<RawAttachedMass>>>,
    // From finite-element matrices.
    /// `fe = { nodes = "….csv", mass = "….mtx", stiffness = "….mtx" }`.
    pub fe: Option<Spanned<RawFe>>,
    /// An FE body's interface nodes (0-based rows of its node file).
    pub interface: Option<Spanned<Vec<i64>>>,
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

/// An FE body's files (paths relative to the scene file).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawFe {
    /// The node file (CSV, header `x,y,z`).
    pub nodes: Spanned<String>,
    /// The mass matrix (Matrix Market).
    pub mass: Spanned<String>,
    /// The stiffness matrix (Matrix Market).
    pub stiffness: Spanned<String>,
    /// A factor on the stiffness matrix (Young's modulus scaled, Poisson's
    /// ratio kept; default 1).
    pub stiffness_scale: Option<Spanned<f64>>,
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

/// `[[bodies.NAME.masses]] x = 2.0, mass = 5.0, inertia = …`: a mass on a
/// flexible body's axis (inertia optional: a number, J_zz of a planar body;
/// `[Jxx, Jyy, Jzz]` or a 3×3 table in space; kg m², about its centre).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawAttachedMass {
    pub x: Spanned<f64>,
    pub mass: Spanned<f64>,
    pub inertia: Option<Spanned<toml::Value>>,
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
    pub a: Option<Spanned<RawMarker>>,
    pub b: Spanned<RawMarker>,
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
    pub at: Option<Spanned<RawMarker>>,
    pub a: Option<Spanned<RawMarker>>,
    pub b: Option<Spanned<RawMarker>>,
    pub force: Option<Spanned<Vec<f64>>>,
    pub axes: Option<Spanned<String>>,
    /// A point force's time function: `{ kind = "harmonic", … }` or
    /// `{ table = [[t0, f0], …] }`.
    pub profile: Option<Spanned<RawForceProfile>>,
    pub stiffness: Option<Spanned<f64>>,
    pub damping: Option<Spanned<f64>>,
    pub rest_length: Option<Spanned<f64>>,
    pub rest_angle: Option<Spanned<f64>>,
    pub torque: Option<Spanned<f64>>,
}

/// A named input.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawInput {
    pub name: Spanned<String>,
    pub kind: Spanned<String>,
    pub joint: Option<Spanned<i64>>,
    pub at: Option<Spanned<RawMarker>>,
    pub direction: Option<Spanned<Vec<f64>>>,
    pub axes: Option<Spanned<String>>,
    pub start: Option<Spanned<f64>>,
    /// The input's value when no caller sets it: `{ kind = "harmonic", … }`
    /// or `{ table = [[t0, u0], …] }`.
    pub profile: Option<Spanned<RawForceProfile>>,
}

/// A marker: a string (`"NAME@x=0.3"`, `"ground@[0, 0]"`, …) or an inline
/// table with its own axes, `{ at = "NAME@x=0.3", axes = { angle = 1.57 } }`
/// (planar) or `axes = { axis = [0, 0, 1], angle = 1.57 }` (spatial).
#[derive(Debug)]
pub enum RawMarker {
    /// The string form.
    Text(String),
    /// The table form.
    Table(RawMarkerTable),
}

/// `{ at = "…", axes = { … } }`: a marker with its own axes (`axes` may be
/// left out: then it is the marker `at`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMarkerTable {
    pub at: Option<Spanned<String>>,
    pub axes: Option<Spanned<RawMarkerAxes>>,
}

/// A marker's axes: a rotation of the axes of its section, body or the
/// ground; planar `{ angle = φ }` (about z), spatial `{ axis = [x, y, z],
/// angle = φ }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMarkerAxes {
    pub axis: Option<Spanned<Vec<f64>>>,
    pub angle: Option<Spanned<f64>>,
}

impl RawMarker {
    /// The marker's point as written: the string, or a table's `at` (none
    /// when the table has no `at`).
    pub fn text(&self) -> Option<&str> {
        match self {
            RawMarker::Text(s) => Some(s),
            RawMarker::Table(t) => t.at.as_ref().map(|a| a.get_ref().as_str()),
        }
    }

    /// Whether the marker gives its own axes (an `angle` of 0 is the
    /// marker without: the same axes).
    pub fn has_axes(&self) -> bool {
        match self {
            RawMarker::Table(RawMarkerTable { axes: Some(a), .. }) => {
                a.get_ref().angle.as_ref().map(|x| *x.get_ref()) != Some(0.0)
            }
            _ => false,
        }
    }
}

impl<'de> Deserialize<'de> for RawMarker {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RawMarker;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a marker: a string such as \"NAME@x=0.3\", or a table such as { at = \"NAME@x=0.3\", axes = { angle = 1.5708 } }")
            }
            fn visit_str<E>(self, v: &str) -> Result<RawMarker, E> {
                Ok(RawMarker::Text(v.to_string()))
            }
            fn visit_string<E>(self, v: String) -> Result<RawMarker, E> {
                Ok(RawMarker::Text(v))
            }
            // The table's fields are read by the TOML deserializer itself,
            // so they keep their spans (and an unknown key is located).
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<RawMarker, A::Error> {
                RawMarkerTable::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(RawMarker::Table)
            }
        }
        d.deserialize_any(V)
    }
}

/// A point force's time function `f(t)`: a drive profile named by `kind`
/// with that profile's keys (`{ kind = "harmonic", amplitude = 1.0,
/// frequency = 2.0 }`), or a piecewise-linear `table = [[t0, f0], …]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawForceProfile {
    pub kind: Option<Spanned<String>>,
    pub table: Option<Spanned<RawProfileTable>>,
    pub omega: Option<Spanned<f64>>,
    pub ramp: Option<Spanned<f64>>,
    pub value: Option<Spanned<f64>>,
    pub start: Option<Spanned<f64>>,
    pub rate: Option<Spanned<f64>>,
    pub amplitude: Option<Spanned<f64>>,
    pub frequency: Option<Spanned<f64>>,
    pub phase: Option<Spanned<f64>>,
}

impl RawForceProfile {
    /// The drive-profile table of the same keys, the profile named by
    /// `angle` (so that it is checked and resolved as drives are).
    pub fn as_drive(&self) -> RawProfile {
        RawProfile {
            angle: self.kind.clone(),
            slide: None,
            omega: self.omega.clone(),
            ramp: self.ramp.clone(),
            value: self.value.clone(),
            start: self.start.clone(),
            rate: self.rate.clone(),
            amplitude: self.amplitude.clone(),
            frequency: self.frequency.clone(),
            phase: self.phase.clone(),
        }
    }
}

/// The rows of a profile table, each with its span; at most
/// [`ffr_spec::scene::MAX_PROFILE_ROWS`] rows are read (a longer table is
/// refused while it is read, before more rows are stored).
#[derive(Debug)]
pub struct RawProfileTable(pub Vec<Spanned<RawRow>>);

/// One row of a profile table: its first two numbers and how many values it
/// has (a row of another length is refused by the loader, at the row).
#[derive(Debug)]
pub struct RawRow {
    /// The first two values (0 where the row is shorter).
    pub values: [f64; 2],
    /// How many values the row has.
    pub len: usize,
}

impl<'de> Deserialize<'de> for RawProfileTable {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RawProfileTable;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an array of [time, value] rows")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<RawProfileTable, A::Error> {
                use ffr_spec::scene::MAX_PROFILE_ROWS;
                let mut rows = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1024));
                while let Some(r) = seq.next_element::<Spanned<RawRow>>()? {
                    if rows.len() == MAX_PROFILE_ROWS {
                        return Err(serde::de::Error::custom(format!(
                            "a profile `table` has more than {MAX_PROFILE_ROWS} rows (MAX_PROFILE_ROWS)"
                        )));
                    }
                    rows.push(r);
                }
                Ok(RawProfileTable(rows))
            }
        }
        d.deserialize_seq(V)
    }
}

impl<'de> Deserialize<'de> for RawRow {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RawRow;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a row [time, value] of two numbers")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<RawRow, A::Error> {
                let mut values = [0.0; 2];
                let mut len = 0;
                // The first two values are kept, the others only counted.
                while len < 2 {
                    match seq.next_element::<f64>()? {
                        Some(x) => values[len] = x,
                        None => return Ok(RawRow { values, len }),
                    }
                    len += 1;
                }
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    len += 1;
                }
                Ok(RawRow { values, len })
            }
        }
        d.deserialize_seq(V)
    }
}

/// An output column.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawOutput {
    pub name: Spanned<String>,
    pub kind: Spanned<String>,
    pub at: Option<Spanned<RawMarker>>,
    pub a: Option<Spanned<RawMarker>>,
    pub component: Option<Spanned<String>>,
}

impl RawBody {
    /// A span inside the body's table (its first key present), for errors
    /// about the body as a whole.
    pub fn span(&self) -> Option<std::ops::Range<usize>> {
        self.shape
            .as_ref()
            .map(|x| x.span())
            .or(self.fe.as_ref().map(|x| x.span()))
            .or(self.mass.as_ref().map(|x| x.span()))
            .or(self.elements.as_ref().map(|x| x.span()))
            .or(self.nodes.as_ref().map(|x| x.span()))
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

pub use ffr_spec::text::{quoted, MAX_QUOTED_CHARS};

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
    /// drive and no motor. Flexible and rigid bodies alike. Markers with
    /// their own axes are not folded (the joint's angle is then measured
    /// between those axes).
    pub fn folds(&self) -> bool {
        self.kind.get_ref() == "revolute"
            && self.motor.is_none()
            && self
                .drive
                .as_ref()
                .is_some_and(|d| d.get_ref().angle.is_some())
            && self.a.as_ref().is_some_and(|a| {
                !a.get_ref().has_axes()
                    && a.get_ref()
                        .text()
                        .is_some_and(|a| a.trim().starts_with("ground@"))
            })
            && !self.b.get_ref().has_axes()
            && self.b.get_ref().text().is_some_and(|b| !b.contains('@'))
    }
}

impl RawScene {
    /// For each body (by name; flexible or rigid), the joint that folds its
    /// frame, if any.
    pub fn folded(&self) -> BTreeMap<String, usize> {
        let mut out = BTreeMap::new();
        for (i, j) in self.joints.iter().enumerate() {
            if j.folds() {
                let b = j.b.get_ref().text().unwrap_or("").trim().to_string();
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

pub(crate) fn scene_err(text: &str, file: &str, span: Range<usize>, message: String) -> Error {
    Error::Scene {
        location: Location::of(file, text, span.start),
        message,
    }
}

mod bake;
mod check;
mod model;
mod resolve;

pub use bake::scene_expr;
pub use check::check;
pub use model::{dimension_of, flex_models, stiffening_of, FlexBodyModel};
pub use resolve::{resolve, resolve_file, resolve_str};
