//! Masses attached to a flexible body ([`ffr_spec::AttachedMass`]): the
//! invariants of a rigid body of mass `m` and second moments `D` about its
//! centre, which sits on the axis at `P` and moves with the section there
//! (`S(d) = s_P + ψ̃_P d`; `docs/theory.md`, "Attached masses"), over the few
//! coordinates `s_P` and `ψ_P` depend on:
//!
//! - `m`, `S_t0 = m ū₀_P`, `Θ = m ū₀_P ū₀_Pᵀ + D`,
//! - `S̄_j = m s_j`, `S̄_kl[i][j] = m s_ik s_jl + (ψ̃_i D ψ̃_jᵀ)_kl`,
//! - `Ī_kl[j] = m ū₀_Pk s_jl + (D ψ̃_jᵀ)_kl`, `m_ff = Σ_k S̄_kk`, `K_ff = 0`:
//!
//! the lumped sums of `docs/theory.md` §7 for that rigid body. Its forces,
//! tangents and mass blocks are those of [`crate::inertia`].

use crate::body::{BodyState, Invariants, PointShape};
use crate::inertia::{InertiaTerms, Inputs};
use ffr_spec::AttachedMass;

/// An attached mass on a body: its invariants over the body coordinates
/// `map` (those its point moves with).
#[derive(Clone, Debug)]
pub(crate) struct Attachment {
    /// Body index of each local coordinate.
    pub(crate) map: Vec<usize>,
    pub(crate) terms: InertiaTerms,
}

/// `ψ̃` (`ψ̃ d = ψ × d`).
fn skew(p: &[f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]]
}

impl Attachment {
    /// The attachment of `mass` at the point whose shape is `point` on a
    /// body of dimension `dim` (invariants) in a scene of `scene_dim`.
    pub(crate) fn new(
        mass: &AttachedMass,
        point: &PointShape,
        dim: usize,
        scene_dim: usize,
    ) -> Self {
        let n = point.entries.len();
        let m = mass.mass;
        let d = mass.second_moments(dim);
        let u0 = point.u0;
        let mut inv = Invariants::zeros(dim, n);
        inv.mass = m;
        for k in 0..3 {
            inv.s_t0[k] = m * u0[k];
            for l in 0..3 {
                inv.theta[(k, l)] = m * u0[k] * u0[l] + d[k][l];
            }
        }
        // ψ̃_j and ψ̃_j D per local coordinate.
        let pt: Vec<[[f64; 3]; 3]> = point.entries.iter().map(|(_, _, p)| skew(p)).collect();
        for (j, (_, s, _)) in point.entries.iter().enumerate() {
            for k in 0..3 {
                inv.s_bar[(k, j)] = m * s[k];
                for l in 0..3 {
                    // (D ψ̃_jᵀ)_kl = Σ_b D_kb (ψ̃_j)_lb.
                    let dp: f64 = (0..3).map(|b| d[k][b] * pt[j][l][b]).sum();
                    inv.i_kl[k][l][j] = m * u0[k] * s[l] + dp;
                }
            }
        }
        for (i, (_, si, _)) in point.entries.iter().enumerate() {
            for (j, (_, sj, _)) in point.entries.iter().enumerate() {
                for k in 0..3 {
                    for l in 0..3 {
                        // (ψ̃_i D ψ̃_jᵀ)_kl = Σ_bc (ψ̃_i)_kb D_bc (ψ̃_j)_lc.
                        let mut r = 0.0;
                        for b in 0..3 {
                            for c in 0..3 {
                                r += pt[i][k][b] * d[b][c] * pt[j][l][c];
                            }
                        }
                        inv.s_kl[k][l][(i, j)] = m * si[k] * sj[l] + r;
                    }
                }
            }
        }
        inv.m_ff = &inv.s_kl[0][0] + &inv.s_kl[1][1] + &inv.s_kl[2][2];
        Self {
            map: point.entries.iter().map(|(ia, _, _)| *ia).collect(),
            terms: InertiaTerms::new(inv, false, scene_dim == 2),
        }
    }

    /// The attachment's coordinates of `s`, gathered into the scratch
    /// arrays `q`, `qd`, `qdd` (at least as long as the map).
    pub(crate) fn gather<'a>(
        &self,
        s: &BodyState,
        q: &'a mut [f64],
        qd: &'a mut [f64],
        qdd: &'a mut [f64],
    ) -> Inputs<'a> {
        let n = self.map.len();
        for (i, &ia) in self.map.iter().enumerate() {
            q[i] = s.q_f[ia];
            qd[i] = s.qd_f[ia];
            qdd[i] = s.qdd_f[ia];
        }
        Inputs {
            q: &q[..n],
            qd: &qd[..n],
            qdd: &qdd[..n],
            frame: s.frame,
        }
    }

    /// Adds the attachment's invariants to the body's `inv`.
    pub(crate) fn add_invariants(&self, inv: &mut Invariants) {
        let a = self.terms.invariants();
        inv.mass += a.mass;
        inv.s_t0 += a.s_t0;
        inv.theta += a.theta;
        for (i, &ia) in self.map.iter().enumerate() {
            for k in 0..3 {
                inv.s_bar[(k, ia)] += a.s_bar[(k, i)];
                for l in 0..3 {
                    inv.i_kl[k][l][ia] += a.i_kl[k][l][i];
                }
            }
            for (j, &jb) in self.map.iter().enumerate() {
                for k in 0..3 {
                    for l in 0..3 {
                        inv.s_kl[k][l][(ia, jb)] += a.s_kl[k][l][(i, j)];
                    }
                }
                inv.m_ff[(ia, jb)] += a.m_ff[(i, j)];
            }
        }
    }
}
