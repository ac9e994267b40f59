//! An FE model: nodes, consistent mass matrix `M` and stiffness matrix `K`
//! (order `3n`, node by node `ux, uy, uz`), checked.
//!
//! # The mass matrix must not couple directions
//! The nodal-based FFRF (docs/theory.md, "Bodies from finite-element
//! matrices") needs `M` to be the scalar mass matrix `M_s` in each direction
//! and nothing between directions — what every solid element with the same
//! scalar interpolation in x, y and z gives, consistent or lumped. Only then
//! is `M = ∫ρ SᵀS dV` for an `S` whose rows are the nodal functions, so that
//! `S̄_kl = P_kᵀ M_s P_l` (and `m_ff = Σ_k S̄_kk = M`). A general `M` has no
//! such `S`: the cross-direction integrals `S̄_kl` (k ≠ l) are not in it. So
//! [`FeModel::new`] refuses an `M` whose direction blocks differ or whose
//! cross-direction entries are non-zero (beyond [`DIRECTION_TOL`]); `M_s` is
//! the x block.
//!
//! # The stiffness matrix must be that of a free body
//! `K` must be symmetric positive semi-definite with exactly the six rigid
//! motions (translations, infinitesimal rotations) as zero-energy modes:
//! `‖K r‖ ≤ RIGID_TOL ‖K‖_F ‖r‖` for each, and `K` positive definite on
//! their orthogonal complement (a Cholesky factorization of `Zᵀ K Z`). An
//! FE model exported with supports, or with a mechanism, is refused; the
//! reference condition ([`super::FeBody`]) removes the rigid motions.

use super::{FeError, DIRECTIONS, MAX_FE_NODES};
use crate::modal::complement;
use nalgebra::{Cholesky, DMatrix, Vector3, SVD};
use std::path::Path;

/// `M`'s direction blocks must agree, and its cross-direction entries
/// vanish, to `DIRECTION_TOL · max|M|`.
pub const DIRECTION_TOL: f64 = 1e-12;

/// Relative residual `‖K r‖ / (‖K‖_F ‖r‖)` up to which a rigid motion `r`
/// counts as a zero-energy mode of `K` (the same bound as the beams' free
/// modal truncation).
pub const RIGID_TOL: f64 = 1e-10;

/// A checked FE model.
#[derive(Clone, Debug, PartialEq)]
pub struct FeModel {
    /// Node positions in the body frame (node `i` = row `i` of the node file).
    pub nodes: Vec<Vector3<f64>>,
    /// `M`, `3n × 3n`, exactly symmetric.
    pub mass: DMatrix<f64>,
    /// `K`, `3n × 3n`, exactly symmetric.
    pub stiffness: DMatrix<f64>,
    /// `M_s`, `n × n`: the x block of `M` (equal to the y and z blocks).
    pub scalar_mass: DMatrix<f64>,
    /// The mass matrix's file, as errors name it.
    pub mass_file: String,
    /// The stiffness matrix's file, as errors name it.
    pub stiffness_file: String,
}

/// The name of degree of freedom `d` (`ux_3`: node 3, direction x).
pub(crate) fn dof_name(d: usize) -> String {
    format!("{}_{}", DIRECTIONS[d % 3], d / 3)
}

/// How the refusal of a node file that does not describe the stiffness
/// matrix's model starts ([`FeModel::load`] puts the node file in front).
const NODES_MISMATCH: &str = "the nodes do not match the stiffness matrix";

impl FeModel {
    /// Read and check the three files (each path is shown as given).
    pub fn load(nodes: &Path, mass: &Path, stiffness: &Path) -> Result<Self, FeError> {
        let node_file = nodes.display().to_string();
        let (mass_file, stiffness_file) =
            (mass.display().to_string(), stiffness.display().to_string());
        let xs = super::read_nodes(nodes, &node_file)?;
        let order = 3 * xs.len();
        let (m, _) = super::read_matrix(mass, &mass_file, "mass", order)?;
        let (k, _) = super::read_matrix(stiffness, &stiffness_file, "stiffness", order)?;
        Self::new(xs, m, k, &mass_file, &stiffness_file).map_err(|e| match e {
            FeError::Model(m) if m.starts_with(NODES_MISMATCH) => FeError::file(&node_file, m),
            e => e,
        })
    }

    /// A model from its parts; `mass_file` and `stiffness_file` name the
    /// matrices in errors. Checks: 1 to [`MAX_FE_NODES`] finite nodes not
    /// all on one line, matrices `3n × 3n`, finite and symmetric to
    /// [`super::SYMMETRY_TOL`] (then `(A + Aᵀ)/2` is kept); `M`
    /// positive definite and direction-decoupled, `K` as the module says.
    pub fn new(
        nodes: Vec<Vector3<f64>>,
        mass: DMatrix<f64>,
        stiffness: DMatrix<f64>,
        mass_file: &str,
        stiffness_file: &str,
    ) -> Result<Self, FeError> {
        let n = nodes.len();
        if n == 0 || n > MAX_FE_NODES {
            return Err(FeError::Model(format!(
                "an FE body needs 1 to {MAX_FE_NODES} nodes (MAX_FE_NODES), found {n}"
            )));
        }
        if let Some(i) = nodes.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
            return Err(FeError::Model(format!(
                "node {i} has a coordinate that is not a finite number"
            )));
        }
        let order = 3 * n;
        for (file, what, a) in [
            (mass_file, "mass", &mass),
            (stiffness_file, "stiffness", &stiffness),
        ] {
            if a.shape() != (order, order) {
                return Err(FeError::file(
                    file,
                    format!(
                        "the {what} matrix is {} × {}; with {n} nodes it must be {order} × {order}",
                        a.nrows(),
                        a.ncols()
                    ),
                ));
            }
            if let Some(i) = a.iter().position(|v| !v.is_finite()) {
                return Err(FeError::file(
                    file,
                    format!(
                        "{what} matrix entry ({}, {}) is {}, not a finite number",
                        i % order + 1,
                        i / order + 1,
                        a[i]
                    ),
                ));
            }
            let big = a.amax();
            if !a.norm().is_finite() {
                return Err(FeError::file(
                    file,
                    format!("the {what} matrix's entries are too large: its norm overflows f64 (largest entry {big:e})"),
                ));
            }
            for j in 0..order {
                for i in j + 1..order {
                    if (a[(i, j)] - a[(j, i)]).abs() > super::SYMMETRY_TOL * big {
                        return Err(FeError::file(
                            file,
                            format!(
                                "the {what} matrix is not symmetric: entries ({}, {}) and ({}, {}) differ",
                                i + 1,
                                j + 1,
                                j + 1,
                                i + 1
                            ),
                        ));
                    }
                }
            }
        }
        let (mut mass, mut stiffness) = (mass, stiffness);
        super::matrix::symmetrize(&mut mass);
        super::matrix::symmetrize(&mut stiffness);
        let scalar_mass = scalar_mass(&mass, mass_file)?;
        if Cholesky::new(mass.clone()).is_none() {
            return Err(FeError::file(
                mass_file,
                "the mass matrix is not positive definite (a node without mass, a negative mass, or not a mass matrix)",
            ));
        }
        let model = Self {
            nodes,
            mass,
            stiffness,
            scalar_mass,
            mass_file: mass_file.to_string(),
            stiffness_file: stiffness_file.to_string(),
        };
        model.check_stiffness()?;
        Ok(model)
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether there are no nodes (never, for a checked model).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The six rigid motions over all `3n` degrees of freedom, each of unit
    /// norm: translations along x, y, z, then infinitesimal rotations about
    /// x, y, z through the nodes' centroid (`ω × (x_i − c)`).
    pub fn rigid_motions(&self) -> DMatrix<f64> {
        let n = self.len();
        let c = self
            .nodes
            .iter()
            .map(|p| p / n as f64)
            .sum::<Vector3<f64>>();
        // Positions relative to the centroid in units of the largest, so
        // that the norms below cannot overflow.
        let scale = self
            .nodes
            .iter()
            .map(|p| (p - c).amax())
            .fold(0.0, f64::max);
        let scale = if scale > 0.0 { scale } else { 1.0 };
        let mut r = DMatrix::zeros(3 * n, 6);
        for (i, p) in self.nodes.iter().enumerate() {
            let d = (p - c) / scale;
            for k in 0..3 {
                r[(3 * i + k, k)] = 1.0;
                let w = Vector3::ith(k, 1.0).cross(&d);
                for a in 0..3 {
                    r[(3 * i + a, 3 + k)] = w[a];
                }
            }
        }
        for mut col in r.column_iter_mut() {
            let norm = col.norm();
            if norm > 0.0 {
                col /= norm;
            }
        }
        r
    }

    fn check_stiffness(&self) -> Result<(), FeError> {
        let file = &self.stiffness_file;
        let r = self.rigid_motions();
        let sv = SVD::new(r.clone(), false, false).singular_values;
        if sv.min() < 1e-8 * sv.max() {
            return Err(FeError::Model(
                "the nodes lie on one line (or there is one node): a solid FE body needs nodes that span space".into(),
            ));
        }
        let k = &self.stiffness;
        let kn = k.norm();
        let names = ["x", "y", "z"];
        // A translation does not depend on the nodes: K resisting one has
        // supports. A rotation is built from the node file's coordinates:
        // K free in translation but resisting a rotation is a node file
        // that does not describe K's model (node order, coordinates), or
        // supports against rotation alone.
        for (j, col) in r.column_iter().enumerate() {
            let res = (k * col).norm();
            if res > RIGID_TOL * kn {
                return Err(if j < 3 {
                    FeError::file(
                        file,
                        format!(
                            "the stiffness matrix resists a rigid translation along {} (‖K r‖/(‖K‖ ‖r‖) = {:.3e} > {RIGID_TOL:e}, RIGID_TOL): export the FE model without supports",
                            names[j],
                            res / kn
                        ),
                    )
                } else {
                    FeError::Model(format!(
                        "{NODES_MISMATCH}: K is free in translation but resists the rigid rotation about {} through these nodes (‖K r‖/(‖K‖ ‖r‖) = {:.3e} > {RIGID_TOL:e}, RIGID_TOL); check that row i of the node file is node i of the matrices (the same order and coordinates), or remove supports against rotation",
                        names[j % 3],
                        res / kn
                    ))
                });
            }
        }
        let z = complement(&r);
        let kz = z.transpose() * k * &z;
        let kz = (&kz + kz.transpose()) * 0.5;
        if Cholesky::new(kz).is_none() {
            return Err(FeError::file(
                file,
                "the stiffness matrix is not positive semi-definite with the six rigid motions as its only zero-energy modes: it is indefinite, or the model has a mechanism",
            ));
        }
        Ok(())
    }
}

/// `M_s` (the x block of `mass`) after checking that the y and z blocks
/// equal it and that no entry couples two directions.
fn scalar_mass(mass: &DMatrix<f64>, file: &str) -> Result<DMatrix<f64>, FeError> {
    let n = mass.nrows() / 3;
    let tol = DIRECTION_TOL * mass.amax();
    let ms = DMatrix::from_fn(n, n, |i, j| mass[(3 * i, 3 * j)]);
    for i in 0..n {
        for j in 0..n {
            for a in 0..3 {
                for b in 0..3 {
                    let (r, c) = (3 * i + a, 3 * j + b);
                    let want = if a == b { ms[(i, j)] } else { 0.0 };
                    if (mass[(r, c)] - want).abs() > tol {
                        let why = if a == b {
                            format!(
                                "differs from the x block's ({}, {}) = {:e}: the direction blocks of M must be equal",
                                3 * i + 1,
                                3 * j + 1,
                                want
                            )
                        } else {
                            "couples two directions".to_string()
                        };
                        return Err(FeError::file(
                            file,
                            format!(
                                "mass matrix entry ({}, {}) ({}, {}) = {:e} {why}; the nodal-based FFRF needs the same scalar mass matrix in x, y and z and nothing between them (solid elements with translations only)",
                                r + 1,
                                c + 1,
                                dof_name(r),
                                dof_name(c),
                                mass[(r, c)]
                            ),
                        ));
                    }
                }
            }
        }
    }
    Ok(ms)
}
