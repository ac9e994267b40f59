//! Masses attached to a flexible body (issue 19): a rigid body of mass `m`
//! and inertia tensor `J` (about its own centre of mass, body axes) whose
//! centre sits on the beam axis at `x` and moves with the section there.
//!
//! Its material points are `ū₀ = (x, 0, 0) + d` with `∫ρ d = 0` and second
//! moments `D = ∫ρ d dᵀ = ½ tr(J) I − J` (from `J = tr(D) I − D`); they move
//! with the section's displacement `s` and its small rotation `ψ`:
//! `S(d) = S_P + ψ̃_P d` (`docs/theory.md`, "Attached masses").

use crate::text::Num;
use std::fmt;

/// A mass attached on a beam's axis (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttachedMass {
    /// Position on the axis (m from the body's root).
    pub x: f64,
    /// Mass `m` (kg).
    pub mass: f64,
    /// Inertia tensor `J` about the mass's centre, body axes (kg m²).
    pub inertia: [[f64; 3]; 3],
}

/// What is wrong with an [`AttachedMass`].
#[derive(Clone, Debug, PartialEq)]
pub struct AttachedMassError(pub String);

impl fmt::Display for AttachedMassError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for AttachedMassError {}

impl AttachedMass {
    /// The second moments of the mass distribution about its centre,
    /// `D = ½ tr(J) I − J`; for a planar body (`dim = 2`, only `J_zz`) in
    /// its plane: `D = diag(J_zz/2, J_zz/2, 0)` (only `D_xx + D_yy = J_zz`
    /// enters a planar body's equations).
    pub fn second_moments(&self, dim: usize) -> [[f64; 3]; 3] {
        let j = &self.inertia;
        if dim == 2 {
            let h = 0.5 * j[2][2];
            return [[h, 0.0, 0.0], [0.0, h, 0.0], [0.0, 0.0, 0.0]];
        }
        let tr = j[0][0] + j[1][1] + j[2][2];
        std::array::from_fn(|a| {
            std::array::from_fn(|b| if a == b { 0.5 * tr } else { 0.0 } - j[a][b])
        })
    }

    /// Checks the mass for a body of axis length `length` and dimension
    /// `dim`: finite, `0 ≤ x ≤ length`, `m ≥ 0`, `J` symmetric, and a
    /// physical inertia (`D` positive semi-definite: principal moments
    /// non-negative and each at most the sum of the other two; in a planar
    /// body `J_zz ≥ 0` is the only entry).
    pub fn check(&self, length: f64, dim: usize) -> Result<(), AttachedMassError> {
        let bad = |m: String| Err(AttachedMassError(m));
        let j = &self.inertia;
        if !(self.x.is_finite()
            && self.mass.is_finite()
            && j.iter().flatten().all(|v| v.is_finite()))
        {
            return bad("x, mass and inertia must be finite numbers".into());
        }
        let tol = 1e-12 * length.abs();
        if !(self.x >= -tol && self.x <= length + tol) {
            return bad(format!(
                "x = {} is not on the body's axis: it runs from x = 0 to x = {} m",
                Num(self.x),
                Num(length)
            ));
        }
        if !(self.mass >= 0.0) {
            return bad(format!("mass = {} must not be negative", self.mass));
        }
        let scale = j.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in [(0, 1), (0, 2), (1, 2)] {
            if (j[a][b] - j[b][a]).abs() > 1e-12 * scale {
                return bad(format!(
                    "the inertia tensor is not symmetric: J[{a}][{b}] = {} but J[{b}][{a}] = {}",
                    j[a][b], j[b][a]
                ));
            }
        }
        if dim == 2 {
            let off_plane = j[0][0] != 0.0
                || j[1][1] != 0.0
                || [(0, 1), (0, 2), (1, 2)]
                    .iter()
                    .any(|&(a, b)| j[a][b] != 0.0);
            if off_plane {
                return bad("a planar body's attached mass turns about z only: give `inertia` as a number (J_zz, kg m²)".into());
            }
            if !(j[2][2] >= 0.0) {
                return bad(format!(
                    "the inertia J_zz = {} must not be negative",
                    j[2][2]
                ));
            }
            return Ok(());
        }
        // D = ½ tr(J) I − J positive semi-definite: all principal minors of
        // D non-negative (to round-off).
        let d = self.second_moments(3);
        let tol = 1e-12 * scale;
        let m2 = |a: usize, b: usize| d[a][a] * d[b][b] - d[a][b] * d[b][a];
        let det = d[0][0] * m2(1, 2) - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
            + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        let minors_ok = (0..3).all(|a| d[a][a] >= -tol)
            && [(0, 1), (0, 2), (1, 2)]
                .iter()
                .all(|&(a, b)| m2(a, b) >= -tol * scale)
            && det >= -tol * scale * scale;
        if !minors_ok {
            return bad(format!(
                "the inertia tensor {j:?} is not that of a rigid body: its principal moments must be non-negative and each at most the sum of the other two (a number gives J_zz of a planar body; in space give [jxx, jyy, jzz] or a 3 × 3 tensor)"
            ));
        }
        Ok(())
    }
}
