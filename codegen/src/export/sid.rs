//! Standard Input Data (SID) of a flexible body (Wallrapp 1994; the
//! invariant-based input of SIMPACK and others), in the text layout of the
//! `.SID_FEM` files written by FEMBeam's `write_sid.m` (J. Geisler) and
//! welib's `yams/sid.py` (E. Branlard): `part` / `new modal` / `refmod` /
//! `frame` (one `new node` per body node) / the Taylor expansions `mdCM`,
//! `J`, `Ct`, `Cr`, `Me`, `Gr`, `Ge`, `Oe`, `ksigma`, `Ke`, `De`, each
//! with `order`, `nrow`, `ncol`, `nq`, `nqn`, `structure` and the entries
//! `m0(i, j)` (order 0) and `m1(i, j, l)` (coefficient of `q_l`);
//! `structure` 0 = no entries (zero), 2 = symmetric (lower triangle of `m0`
//! written), 3 = full.
//!
//! All terms refer to the body frame at the origin (node 0), `u = c + Φ q`
//! the position of a material point, `c` its undeformed position; with the
//! projected invariants (`P_ab = Φᵀ S̄_ab Φ`, `s_ab = Ī_ab Φ`):
//!
//! | term | order 0 | order 1 (coefficient of `q_i`) |
//! |---|---|---|
//! | `mdCM` (3 × 1) | `S_t0` | `S̄Φ_i` |
//! | `J` (3 × 3) | `tr(Θ) I − Θ` | `tr(U_i) I − U_i`, `U_i,ab = s_ab,i + s_ba,i` |
//! | `Ct` (k × 3) | `(S̄Φ)ᵀ` | — (order 0: no geometric stiffening `K0t`) |
//! | `Cr` (k × 3) | `(Ī_θf Φ)ᵀ = ∫ Φᵀ(−c̃) dm` | `Cr_ja,i = P_bc,ij − P_cb,ij`, `(a,b,c)` cyclic |
//! | `Me` (k × k) | `Φᵀ m_ff Φ` | — |
//! | `Gr` (3 × 3k) | `Gr_j = −2∫ c̃ Φ̃_j dm = 2(tr S_j I − S_jᵀ)`, `S_j,ab = s_ab,j` | `2(tr T I − Tᵀ)`, `T_ab = P_ab,ij` |
//! | `Ge` (k × 3k) | `Ge_j = −2∫ Φᵀ Φ̃_j dm`: `Ge_j,ma = −2(P_bc,mj − P_cb,mj)` | — |
//! | `Oe` (k × 6) | `∫ Φ_jᵀ ω̃ω̃ c dm = Oe_j · (ωx², ωy², ωz², ωxωy, ωyωz, ωxωz)` | the same with `c → Φ_i` |
//! | `ksigma` | structure 0 (no reference stresses) | |
//! | `Ke` (k × k) | `Φᵀ K_ff Φ` | — |
//! | `De` | structure 0 (no damping) | |
//!
//! `Gr`, `Ge`, `Oe` follow welib's conventions (`Oe` as the term on the
//! left-hand side of the modal equations); `Ct`'s and `Oe`'s geometric
//! stiffening parts (`K0t`, `K0ω`) and `ksigma` are not written: ffr's
//! stiffening is a polynomial energy, not a stiffness linearized about a
//! reference load. Node frames: `origin` (position, and the nodal
//! translations of the modes as order 1), `phi` (translations), `psi`
//! (rotations), `AP` (identity; order 1 `ψ̃_i`), no `sigma`.

use super::{num, ExportBody};
use crate::modal::ModeKind;
use nalgebra::{DMatrix, Matrix3};
use std::fmt::Write;

/// A Taylor block: `m0` (nrow × ncol, or `None` for structure 0) and the
/// first-order coefficients `m1[l]` (nrow × ncol each, one per `q_l`).
struct Taylor {
    name: &'static str,
    nq: usize,
    structure: u8,
    nrow: usize,
    ncol: usize,
    m0: Option<DMatrix<f64>>,
    m1: Option<Vec<DMatrix<f64>>>,
}

fn write_taylor(w: &mut String, indent: &str, t: &Taylor) {
    let order = usize::from(t.m1.is_some());
    let _ = writeln!(w, "{indent}{}", t.name);
    let _ = writeln!(w, "{indent}    order        = {order}");
    let _ = writeln!(w, "{indent}    nrow         = {}", t.nrow);
    let _ = writeln!(w, "{indent}    ncol         = {}", t.ncol);
    let _ = writeln!(w, "{indent}    nq           = {}", t.nq);
    let _ = writeln!(w, "{indent}    nqn          = 0");
    let _ = writeln!(w, "{indent}    structure    = {}", t.structure);
    if let Some(m0) = &t.m0 {
        for i in 0..t.nrow {
            let cols = if t.structure == 2 { i + 1 } else { t.ncol };
            for j in 0..cols {
                let _ = writeln!(
                    w,
                    "{indent}    m0({:2},{:2})    = {}",
                    i + 1,
                    j + 1,
                    num(m0[(i, j)])
                );
            }
        }
    }
    if let Some(m1) = &t.m1 {
        for i in 0..t.nrow {
            for j in 0..t.ncol {
                for (l, m) in m1.iter().enumerate() {
                    let _ = writeln!(
                        w,
                        "{indent}    m1({:2},{:2},{:2}) = {}",
                        i + 1,
                        j + 1,
                        l + 1,
                        num(m[(i, j)])
                    );
                }
            }
        }
    }
    let _ = writeln!(w, "{indent}end {}", t.name);
}

fn skew(v: [f64; 3]) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

fn to_dmatrix(m: &Matrix3<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(3, 3, |i, j| m[(i, j)])
}

/// `2 (tr A I − Aᵀ)`.
fn gyro(a: &Matrix3<f64>) -> Matrix3<f64> {
    (Matrix3::identity() * a.trace() - a.transpose()) * 2.0
}

/// `(−(a_yy + a_zz), −(a_xx + a_zz), −(a_xx + a_yy), a_xy + a_yx, a_yz + a_zy, a_xz + a_zx)`.
fn centrifugal(a: &Matrix3<f64>) -> [f64; 6] {
    [
        -(a[(1, 1)] + a[(2, 2)]),
        -(a[(0, 0)] + a[(2, 2)]),
        -(a[(0, 0)] + a[(1, 1)]),
        a[(0, 1)] + a[(1, 0)],
        a[(1, 2)] + a[(2, 1)],
        a[(0, 2)] + a[(2, 0)],
    ]
}

/// The body as an SID (`.SID_FEM`) text; terms and conventions in the module
/// documentation (and `docs/export.md`).
pub fn sid(body: &ExportBody) -> String {
    let inv = &body.invariants;
    let k = body.modes();
    // s_j (3 × 3): s_ab,j = (Ī_ab Φ)_j; t_ij (3 × 3): T_ab = (Φᵀ S̄_ab Φ)_ij.
    let s = |j: usize| Matrix3::from_fn(|a, b| inv.i_kl[a][b][j]);
    let t = |i: usize, j: usize| Matrix3::from_fn(|a, b| inv.s_kl[a][b][(i, j)]);
    let mut w = String::new();
    let _ = writeln!(
        w,
        "{} nodes, {k} modes, generated by ffr: {}",
        body.nodes.len(),
        body.title
    );
    let _ = writeln!(w, "part");
    let _ = writeln!(w, "    new modal");
    let _ = writeln!(w, "        refmod");
    let _ = writeln!(w, "            mass           = {}", num(inv.mass));
    let _ = writeln!(w, "            nelastq        = {k}");
    for (j, (label, kind)) in body.labels.iter().zip(&body.kinds).enumerate() {
        let name = match kind {
            ModeKind::Normal { omega } => format!("{label} : {} rad/s", num(*omega)),
            ModeKind::Constraint { .. } => format!("{label} : static constraint mode"),
            ModeKind::Static { load } => format!("{label} : static mode ({load})"),
        };
        let _ = writeln!(w, "            ielastq ({:4}) = {name}", j + 1);
    }
    let _ = writeln!(w, "        end refmod");
    let _ = writeln!(w, "        frame");
    let ind = "                    ";
    for n in &body.nodes {
        let _ = writeln!(w, "                new node   = {}", n.node);
        let _ = writeln!(w, "                    rframe = body ref");
        let tr = DMatrix::from_fn(3, k, |a, j| n.translation[(a, j)]);
        let rot = DMatrix::from_fn(3, k, |a, j| n.rotation[(a, j)]);
        write_taylor(
            &mut w,
            ind,
            &Taylor {
                name: "origin",
                nq: k,
                structure: 3,
                nrow: 3,
                ncol: 1,
                m0: Some(DMatrix::from_column_slice(3, 1, n.position.as_slice())),
                m1: Some((0..k).map(|j| tr.columns(j, 1).into_owned()).collect()),
            },
        );
        for (name, m) in [("phi", &tr), ("psi", &rot)] {
            write_taylor(
                &mut w,
                ind,
                &Taylor {
                    name,
                    nq: k,
                    structure: 3,
                    nrow: 3,
                    ncol: k,
                    m0: Some(m.clone()),
                    m1: None,
                },
            );
        }
        write_taylor(
            &mut w,
            ind,
            &Taylor {
                name: "AP",
                nq: k,
                structure: 3,
                nrow: 3,
                ncol: 3,
                m0: Some(DMatrix::identity(3, 3)),
                m1: Some(
                    (0..k)
                        .map(|j| to_dmatrix(&skew([rot[(0, j)], rot[(1, j)], rot[(2, j)]])))
                        .collect(),
                ),
            },
        );
        let _ = writeln!(w, "                end node");
    }
    let _ = writeln!(w, "        end frame");
    let ind = "        ";
    // mdCM
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "mdCM",
            nq: k,
            structure: 3,
            nrow: 3,
            ncol: 1,
            m0: Some(DMatrix::from_column_slice(3, 1, inv.s_t0.as_slice())),
            m1: Some(
                (0..k)
                    .map(|j| inv.s_bar.columns(j, 1).into_owned())
                    .collect(),
            ),
        },
    );
    // J
    let j1 = (0..k)
        .map(|j| {
            let sj = s(j);
            let u = sj + sj.transpose();
            to_dmatrix(&(Matrix3::identity() * u.trace() - u))
        })
        .collect();
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "J",
            nq: k,
            structure: 2,
            nrow: 3,
            ncol: 3,
            m0: Some(to_dmatrix(&inv.inertia_tensor())),
            m1: Some(j1),
        },
    );
    // Ct
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "Ct",
            nq: k,
            structure: 3,
            nrow: k,
            ncol: 3,
            m0: Some(inv.s_bar.transpose()),
            m1: None,
        },
    );
    // Cr
    let cr1 = (0..k)
        .map(|i| {
            DMatrix::from_fn(k, 3, |j, a| {
                let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                inv.s_kl[b][c][(i, j)] - inv.s_kl[c][b][(i, j)]
            })
        })
        .collect();
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "Cr",
            nq: k,
            structure: 3,
            nrow: k,
            ncol: 3,
            m0: Some(inv.i_theta_f().transpose()),
            m1: Some(cr1),
        },
    );
    // Me
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "Me",
            nq: 0,
            structure: 2,
            nrow: k,
            ncol: k,
            m0: Some(inv.m_ff.clone()),
            m1: None,
        },
    );
    // Gr
    let mut gr0 = DMatrix::zeros(3, 3 * k);
    for j in 0..k {
        gr0.view_mut((0, 3 * j), (3, 3)).copy_from(&gyro(&s(j)));
    }
    let gr1 = (0..k)
        .map(|i| {
            let mut m = DMatrix::zeros(3, 3 * k);
            for j in 0..k {
                m.view_mut((0, 3 * j), (3, 3)).copy_from(&gyro(&t(i, j)));
            }
            m
        })
        .collect();
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "Gr",
            nq: k,
            structure: 3,
            nrow: 3,
            ncol: 3 * k,
            m0: Some(gr0),
            m1: Some(gr1),
        },
    );
    // Ge
    let ge0 = DMatrix::from_fn(k, 3 * k, |m, col| {
        let (j, a) = (col / 3, col % 3);
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        -2.0 * (inv.s_kl[b][c][(m, j)] - inv.s_kl[c][b][(m, j)])
    });
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "Ge",
            nq: 0,
            structure: 3,
            nrow: k,
            ncol: 3 * k,
            m0: Some(ge0),
            m1: None,
        },
    );
    // Oe
    let oe0 = DMatrix::from_fn(k, 6, |j, c| centrifugal(&s(j))[c]);
    let oe1 = (0..k)
        .map(|i| DMatrix::from_fn(k, 6, |j, c| centrifugal(&t(i, j))[c]))
        .collect();
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "Oe",
            nq: k,
            structure: 3,
            nrow: k,
            ncol: 6,
            m0: Some(oe0),
            m1: Some(oe1),
        },
    );
    // ksigma, Ke, De
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "ksigma",
            nq: k,
            structure: 0,
            nrow: k,
            ncol: 1,
            m0: None,
            m1: None,
        },
    );
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "Ke",
            nq: 0,
            structure: 2,
            nrow: k,
            ncol: k,
            m0: Some(inv.k_ff.clone()),
            m1: None,
        },
    );
    write_taylor(
        &mut w,
        ind,
        &Taylor {
            name: "De",
            nq: 0,
            structure: 0,
            nrow: k,
            ncol: k,
            m0: None,
            m1: None,
        },
    );
    let _ = writeln!(w, "    end modal");
    let _ = writeln!(w, "end part");
    w
}
