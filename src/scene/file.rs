//! The scene file format (TOML), as read: every value keeps its span so that
//! errors name `file:line:col`.

use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// A scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    pub dimension: Spanned<i64>,
    pub gravity: Option<Spanned<Vec<f64>>>,
    pub t_end: Spanned<f64>,
    pub dt: Spanned<f64>,
    pub integrator: Option<Spanned<RawIntegrator>>,
    #[serde(default)]
    pub bodies: BTreeMap<String, RawBody>,
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
    pub modal_damping: Option<Spanned<Vec<f64>>>,
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

/// `motor = { torque = 0.5 }` or `{ target = 1.0, kp = 10.0, kd = 1.0 }`
/// (or a target profile, `target = { angle = "constant-rate", omega = 1.0 }`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMotor {
    pub torque: Option<Spanned<f64>>,
    pub target: Option<Spanned<toml::Value>>,
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
