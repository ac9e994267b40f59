//! The body-frame equations of a body given by its invariants
//! (`docs/theory.md`, sections 3–5), over `k` coordinates `q` (a modal
//! body's modes, or the few coordinates an attached mass moves with):
//!
//! - `f_r = m ā − S_t × α + S̄ q̈ + ω̃² S_t + 2 ω̃ S̄ q̇`
//! - `f_θ = S_t × ā + Ī_θθ α + Ī_θf q̈ + ω × (Ī_θθ ω) + 2 (tr P ω − Pᵀ ω)`
//! - `f_f = S̄ᵀ ā + Ī_θfᵀ α + m_ff q̈ + Σ_kl [(ω̃²)_kl (Ī_lk + S̄_kl q) +
//!   2 ω̃_kl S̄_kl q̇] (+ K_ff q)`
//!
//! with `S_t = S_t0 + S̄ q`, `Ī_θθ = tr(U) I − U`,
//! `U_kl = Θ_kl + (Ī_kl + Ī_lk) q + qᵀ S̄_kl q`, `P_kl = (Ī_kl + qᵀ S̄_kl) q̇`,
//! `Ī_θf` row `x` `Ī_yz − Ī_zy + qᵀ (S̄_yz − S̄_zy)` (cyclic). Their
//! derivatives, which the Newton matrix and the mass blocks need, are
//! written out (`docs/theory.md` §13, "Derivatives of the equations from
//! invariants"): no dual numbers, no allocation.

use crate::body::{BodyForces, BodyMass, BodyState, BodyTangent, Invariants};
use nalgebra::{DMatrix, DVector};

/// The equations of one set of invariants (see the module documentation).
#[derive(Clone, Debug)]
pub(crate) struct InertiaTerms {
    inv: Invariants,
    k: usize,
    /// Whether `K_ff q` is part of `f_f` (else the caller adds the elastic
    /// force).
    elastic: bool,
    /// Which `S̄_kl` are non-zero.
    s_kl_live: [[bool; 3]; 3],
    /// `Ī_ab − Ī_ba` for `(a, b)` = `(y, z)`, `(z, x)`, `(x, y)`.
    c_tf: [DVector<f64>; 3],
    /// `S̄_ab − S̄_ba` for the same pairs.
    d_tf: [DMatrix<f64>; 3],
    /// Which frame components a planar scene has (`ā_x, ā_y, α_z, ω_z`).
    frame_live: [bool; 9],
    /// Row-major copies for the `f_f` rows (row `a` contiguous): `m_ff`,
    /// `K_ff`, and each non-zero `S̄_kl` (empty when zero).
    rows: Rows,
    /// Which `S̄_ab − S̄_ba` are non-zero.
    d_tf_live: [bool; 3],
}

/// Row-major copies of the `k × k` matrices `f_f` reads row by row (empty
/// when zero), combined as the symmetric and antisymmetric frame factors
/// use them.
#[derive(Clone, Debug)]
struct Rows {
    m_ff: Vec<f64>,
    k_ff: Vec<f64>,
    /// `S̄_kk`, then `S̄_kl + S̄_lk` at `[k][l]`, `k < l` (`(ω̃²)` is
    /// symmetric).
    s_sym: [[Vec<f64>; 3]; 3],
    /// `S̄_xx + S̄_yy`, for a spin about z (`ω̃² = diag(−ω², −ω², 0)`).
    s_spin_z: Vec<f64>,
    /// `Ī_xx + Ī_yy`, likewise.
    i_spin_z: Vec<f64>,
    /// `S̄_ab − S̄_ba` (as `d_tf`): the Coriolis terms
    /// `Σ_{k≠l} 2 ω̃_kl S̄_kl q̇ = −2 Σ_r ω_r (S̄_ab − S̄_ba) q̇`.
    d_tf: [Vec<f64>; 3],
}

/// `m` row-major (row `a` is `[a k .. (a + 1) k]`).
fn row_major(m: &DMatrix<f64>) -> Vec<f64> {
    m.transpose().as_slice().to_vec()
}

/// Row `a` of a row-major `k × k` matrix.
fn row(m: &[f64], a: usize, k: usize) -> &[f64] {
    &m[a * k..(a + 1) * k]
}

/// `a · b` over equal lengths, four partial sums (vectorizes; no branches).
#[inline]
pub(crate) fn dot_slices(a: &[f64], b: &[f64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ra.iter().zip(rb) {
        s += x * y;
    }
    s
}

/// The coordinates an evaluation reads.
pub(crate) struct Inputs<'a> {
    pub(crate) q: &'a [f64],
    pub(crate) qd: &'a [f64],
    pub(crate) qdd: &'a [f64],
    pub(crate) frame: [f64; 9],
}

impl<'a> Inputs<'a> {
    pub(crate) fn of(s: &BodyState<'a>) -> Self {
        Inputs {
            q: s.q_f,
            qd: s.qd_f,
            qdd: s.qdd_f,
            frame: s.frame,
        }
    }
}

/// `a × b`.
fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `m v`.
fn mv(m: &[[f64; 3]; 3], v: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|a| m[a][0] * v[0] + m[a][1] * v[1] + m[a][2] * v[2])
}

/// `ω̃` (`ω̃ v = ω × v`).
fn skew(w: &[f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]]
}

/// `xᵀ M y`.
pub(crate) fn bilinear(m: &DMatrix<f64>, x: &[f64], y: &[f64]) -> f64 {
    let n = m.nrows();
    let mut s = 0.0;
    for b in 0..n {
        let mut col = 0.0;
        for a in 0..n {
            let v = m[(a, b)];
            if v != 0.0 {
                col += x[a] * v;
            }
        }
        s += col * y[b];
    }
    s
}

/// `c · x`.
fn dot<'c>(c: impl Iterator<Item = &'c f64>, x: &[f64]) -> f64 {
    let mut s = 0.0;
    for (v, xa) in c.zip(x) {
        if *v != 0.0 {
            s += xa * v;
        }
    }
    s
}

/// `(M x)_a`, row `a` of `M` times `x`.
fn row_dot(m: &DMatrix<f64>, a: usize, x: &[f64]) -> f64 {
    let mut v = 0.0;
    for (b, xb) in x.iter().enumerate() {
        let c = m[(a, b)];
        if c != 0.0 {
            v += xb * c;
        }
    }
    v
}

/// `(Mᵀ x)_a`, column `a` of `M` times `x`.
fn col_dot(m: &DMatrix<f64>, a: usize, x: &[f64]) -> f64 {
    let mut v = 0.0;
    for (b, xb) in x.iter().enumerate() {
        let c = m[(b, a)];
        if c != 0.0 {
            v += xb * c;
        }
    }
    v
}

/// The state-dependent quantities of one evaluation.
struct State<'a> {
    q: &'a [f64],
    qd: &'a [f64],
    qdd: &'a [f64],
    a_bar: [f64; 3],
    alpha: [f64; 3],
    w: [f64; 3],
    /// `ω̃`.
    w1: [[f64; 3]; 3],
    /// `ω̃² = ω ωᵀ − |ω|² I`.
    w2: [[f64; 3]; 3],
}

impl InertiaTerms {
    /// The terms of `inv` (`n_f = k`) for a planar or spatial scene; with
    /// `elastic`, `f_f` includes `K_ff q`.
    pub(crate) fn new(inv: Invariants, elastic: bool, planar: bool) -> Self {
        let k = inv.nf();
        let s_kl_live =
            std::array::from_fn(|a| std::array::from_fn(|b| inv.s_kl[a][b].amax() != 0.0));
        let cyc = [(1, 2), (2, 0), (0, 1)];
        let c_tf = std::array::from_fn(|r| {
            let (a, b) = cyc[r];
            &inv.i_kl[a][b] - &inv.i_kl[b][a]
        });
        let d_tf = std::array::from_fn(|r| {
            let (a, b) = cyc[r];
            &inv.s_kl[a][b] - &inv.s_kl[b][a]
        });
        let frame_live = std::array::from_fn(|i| !(planar && matches!(i, 2 | 3 | 4 | 6 | 7)));
        let d_tf_live: [bool; 3] = std::array::from_fn(|r| d_tf[r].amax() != 0.0);
        let nonzero = |m: DMatrix<f64>| {
            if m.amax() != 0.0 {
                row_major(&m)
            } else {
                Vec::new()
            }
        };
        let rows = Rows {
            m_ff: row_major(&inv.m_ff),
            k_ff: if elastic {
                row_major(&inv.k_ff)
            } else {
                Vec::new()
            },
            s_sym: std::array::from_fn(|a| {
                std::array::from_fn(|b| match a.cmp(&b) {
                    std::cmp::Ordering::Equal => nonzero(inv.s_kl[a][a].clone()),
                    std::cmp::Ordering::Less => nonzero(&inv.s_kl[a][b] + &inv.s_kl[b][a]),
                    std::cmp::Ordering::Greater => Vec::new(),
                })
            }),
            s_spin_z: nonzero(&inv.s_kl[0][0] + &inv.s_kl[1][1]),
            i_spin_z: (&inv.i_kl[0][0] + &inv.i_kl[1][1]).as_slice().to_vec(),
            d_tf: std::array::from_fn(|r: usize| nonzero(d_tf[r].clone())),
        };
        Self {
            inv,
            k,
            elastic,
            s_kl_live,
            c_tf,
            d_tf,
            frame_live,
            rows,
            d_tf_live,
        }
    }

    /// The invariants.
    pub(crate) fn invariants(&self) -> &Invariants {
        &self.inv
    }

    fn state<'a>(&self, s: &'a Inputs) -> State<'a> {
        let fr = |i: usize| {
            if self.frame_live[i] {
                s.frame[i]
            } else {
                0.0
            }
        };
        let w = [fr(6), fr(7), fr(8)];
        let wsq = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        State {
            q: s.q,
            qd: s.qd,
            qdd: s.qdd,
            a_bar: [fr(0), fr(1), fr(2)],
            alpha: [fr(3), fr(4), fr(5)],
            w,
            w1: skew(&w),
            w2: std::array::from_fn(|a| {
                std::array::from_fn(|b| {
                    if a == b {
                        w[a] * w[b] - wsq
                    } else {
                        w[a] * w[b]
                    }
                })
            }),
        }
    }

    /// `S_t = S_t0 + S̄ q`.
    fn s_t(&self, q: &[f64]) -> [f64; 3] {
        std::array::from_fn(|a| self.inv.s_t0[a] + dot(self.inv.s_bar.row(a).iter(), q))
    }

    /// `U_ab = Θ_ab + (Ī_ab + Ī_ba) q + qᵀ S̄_ab q`.
    fn u(&self, q: &[f64]) -> [[f64; 3]; 3] {
        let inv = &self.inv;
        let mut u = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in a..3 {
                let mut v = inv.theta[(a, b)];
                for (j, qj) in q.iter().enumerate() {
                    let c = inv.i_kl[a][b][j] + inv.i_kl[b][a][j];
                    if c != 0.0 {
                        v += qj * c;
                    }
                }
                if self.s_kl_live[a][b] {
                    v += bilinear(&inv.s_kl[a][b], q, q);
                }
                u[a][b] = v;
                u[b][a] = v;
            }
        }
        u
    }

    /// `Ī_θθ = tr(U) I − U`.
    fn i_tt(u: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let tr = u[0][0] + u[1][1] + u[2][2];
        std::array::from_fn(|a| {
            std::array::from_fn(|b| if a == b { tr - u[a][b] } else { -u[a][b] })
        })
    }

    /// `P_ab = (Ī_ab + qᵀ S̄_ab) q̇`.
    fn p(&self, q: &[f64], qd: &[f64]) -> [[f64; 3]; 3] {
        std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                let mut v = dot(self.inv.i_kl[a][b].iter(), qd);
                if self.s_kl_live[a][b] {
                    v += bilinear(&self.inv.s_kl[a][b], q, qd);
                }
                v
            })
        })
    }

    /// `Ī_θf[r][a] = c_tf[r][a] + (d_tfᵀ q)_a`.
    fn i_tf(&self, r: usize, a: usize, q: &[f64]) -> f64 {
        self.c_tf[r][a] + col_dot(&self.d_tf[r], a, q)
    }

    /// Adds `[f_r; f_θ]` (when `frame_rows`) and `f_f` at `s` to `out`,
    /// coordinate `a` to `out.f_f[map[a]]`.
    pub(crate) fn add_forces(
        &self,
        s: &Inputs,
        frame_rows: bool,
        map: &[usize],
        out: &mut BodyForces,
    ) {
        let inv = &self.inv;
        let k = self.k;
        let st = self.state(s);
        let (q, qd, qdd) = (st.q, st.qd, st.qdd);
        if frame_rows {
            let s_t = self.s_t(q);
            let i_tt = Self::i_tt(&self.u(q));
            let p = self.p(q, qd);
            let sbar_qd: [f64; 3] = std::array::from_fn(|a| dot(inv.s_bar.row(a).iter(), qd));
            let sbar_qdd: [f64; 3] = std::array::from_fn(|a| dot(inv.s_bar.row(a).iter(), qdd));
            let itf_qdd: [f64; 3] = std::array::from_fn(|r| {
                dot(self.c_tf[r].iter(), qdd) + bilinear(&self.d_tf[r], q, qdd)
            });
            // f_r = m ā − S_t × α + S̄ q̈ + ω̃² S_t + 2 ω̃ S̄ q̇.
            let st_x_alpha = cross(&s_t, &st.alpha);
            let w2_st = mv(&st.w2, &s_t);
            let w1_sqd = mv(&st.w1, &sbar_qd);
            for a in 0..3 {
                out.f_r[a] += st.a_bar[a] * inv.mass - st_x_alpha[a]
                    + sbar_qdd[a]
                    + w2_st[a]
                    + 2.0 * w1_sqd[a];
            }
            // f_θ = S_t × ā + Ī_θθ α + Ī_θf q̈ + ω × (Ī_θθ ω) + 2 (tr P ω − Pᵀ ω).
            let st_x_a = cross(&s_t, &st.a_bar);
            let i_alpha = mv(&i_tt, &st.alpha);
            let gyro = cross(&st.w, &mv(&i_tt, &st.w));
            let tr_p = p[0][0] + p[1][1] + p[2][2];
            let w = &st.w;
            for a in 0..3 {
                let pt_w = p[0][a] * w[0] + p[1][a] * w[1] + p[2][a] * w[2];
                out.f_th[a] +=
                    st_x_a[a] + i_alpha[a] + itf_qdd[a] + gyro[a] + 2.0 * (w[a] * tr_p - pt_w);
            }
        }
        // f_f row by row over contiguous rows, each frame factor once: the
        // symmetric (ω̃²)_kl on S̄_kl + S̄_lk, the Coriolis pairs on
        // S̄_ab − S̄_ba, a spin about z on S̄_xx + S̄_yy. A term whose factor
        // is zero in this state (it would add `0 · x`) is skipped.
        let rows = &self.rows;
        let w2 = &st.w2;
        let spin_z = st.w[0] == 0.0 && st.w[1] == 0.0;
        for a in 0..k {
            let mut f = 0.0;
            for r in 0..3 {
                f += st.a_bar[r] * inv.s_bar[(r, a)];
                let (alpha, w) = (st.alpha[r], st.w[r]);
                if alpha != 0.0 {
                    // Ī_θf[r][a] α_r, Ī_θf[r][a] = c_tf[r][a] + (d_tfᵀ q)_a.
                    let mut i_tf = self.c_tf[r][a];
                    if self.d_tf_live[r] {
                        i_tf += dot_slices(&self.d_tf[r].as_slice()[a * k..(a + 1) * k], q);
                    }
                    f += i_tf * alpha;
                }
                if w != 0.0 && self.d_tf_live[r] {
                    f -= 2.0 * w * dot_slices(row(&rows.d_tf[r], a, k), qd);
                }
            }
            f += dot_slices(row(&rows.m_ff, a, k), qdd);
            if spin_z {
                // (ω̃²)_xx = (ω̃²)_yy = −ω_z², the rest zero.
                if w2[0][0] != 0.0 {
                    let mut v = rows.i_spin_z[a];
                    if !rows.s_spin_z.is_empty() {
                        v += dot_slices(row(&rows.s_spin_z, a, k), q);
                    }
                    f += w2[0][0] * v;
                }
            } else {
                for kk in 0..3 {
                    for l in kk..3 {
                        let w2 = w2[kk][l];
                        if w2 == 0.0 {
                            continue;
                        }
                        let mut v = inv.i_kl[l][kk][a];
                        if kk != l {
                            v += inv.i_kl[kk][l][a];
                        }
                        if !rows.s_sym[kk][l].is_empty() {
                            v += dot_slices(row(&rows.s_sym[kk][l], a, k), q);
                        }
                        f += w2 * v;
                    }
                }
            }
            if self.elastic {
                f += dot_slices(row(&rows.k_ff, a, k), q);
            }
            out.f_f[map[a]] += f;
        }
    }

    /// Adds the derivatives of [`InertiaTerms::add_forces`] (see
    /// [`BodyTangent`]: `β' ∂/∂q̈ + γ' ∂/∂q̇ + ∂/∂q` and the frame
    /// derivatives) to `t`, through `map`.
    pub(crate) fn add_tangent(
        &self,
        s: &Inputs,
        bp: f64,
        gp: f64,
        frame_rows: bool,
        map: &[usize],
        t: &mut BodyTangent,
    ) {
        let inv = &self.inv;
        let k = self.k;
        let nf = t.k_ff.n();
        let st = self.state(s);
        let (q, qd, qdd) = (st.q, st.qd, st.qdd);
        let (w, w1, w2) = (&st.w, &st.w1, &st.w2);
        // ∂f_f/∂q: Ī_θf's q-part times α, ω̃²'s S̄_kl; ∂/∂q̇: 2 ω̃_kl S̄_kl;
        // ∂/∂q̈: m_ff.
        for a in 0..k {
            for j in 0..k {
                let mut v = bp * inv.m_ff[(a, j)];
                for r in 0..3 {
                    v += self.d_tf[r][(j, a)] * st.alpha[r];
                }
                for kk in 0..3 {
                    for l in 0..3 {
                        if self.s_kl_live[kk][l] {
                            let c = inv.s_kl[kk][l][(a, j)];
                            v += w2[kk][l] * c;
                            if kk != l {
                                v += gp * 2.0 * w1[kk][l] * c;
                            }
                        }
                    }
                }
                if self.elastic {
                    v += inv.k_ff[(a, j)];
                }
                if v != 0.0 {
                    t.k_ff.add(map[a], map[j], v);
                }
            }
        }
        if !frame_rows {
            return;
        }
        let s_t = self.s_t(q);
        let i_tt = Self::i_tt(&self.u(q));
        let p = self.p(q, qd);
        let sbar_qd: [f64; 3] = std::array::from_fn(|a| dot(inv.s_bar.row(a).iter(), qd));
        // Columns of [f_r; f_θ] by coordinate.
        for j in 0..k {
            let sj = [inv.s_bar[(0, j)], inv.s_bar[(1, j)], inv.s_bar[(2, j)]];
            // f_r: ∂/∂q_j = α × S̄_j + ω̃² S̄_j; ∂/∂q̇_j = 2 ω × S̄_j; ∂/∂q̈_j = S̄_j.
            let a_x_s = cross(&st.alpha, &sj);
            let w2_s = mv(w2, &sj);
            let w_x_s = cross(w, &sj);
            for r in 0..3 {
                t.k_ref_f[r * nf + map[j]] += a_x_s[r] + w2_s[r] + gp * 2.0 * w_x_s[r] + bp * sj[r];
            }
            // f_θ: ∂U_ab/∂q_j = Ī_ab[j] + Ī_ba[j] + ((S̄_ab + S̄_ba) q)_j,
            // ∂P_ab/∂q_j = (S̄_ab q̇)_j, ∂P_ab/∂q̇_j = Ī_ab[j] + (S̄_abᵀ q)_j,
            // ∂(Ī_θf q̈)_r/∂q_j = (d_tf[r] q̈)_j.
            let mut du = [[0.0; 3]; 3];
            let mut dp = [[0.0; 3]; 3];
            let mut dpd = [[0.0; 3]; 3];
            for a in 0..3 {
                for b in 0..3 {
                    let mut v = inv.i_kl[a][b][j] + inv.i_kl[b][a][j];
                    let mut vd = inv.i_kl[a][b][j];
                    if self.s_kl_live[a][b] {
                        v += row_dot(&inv.s_kl[a][b], j, q) + col_dot(&inv.s_kl[a][b], j, q);
                        dp[a][b] = row_dot(&inv.s_kl[a][b], j, qd);
                        vd += col_dot(&inv.s_kl[a][b], j, q);
                    }
                    du[a][b] = v;
                    dpd[a][b] = vd;
                }
            }
            let di = Self::i_tt(&du);
            let di_alpha = mv(&di, &st.alpha);
            let gyro = cross(w, &mv(&di, w));
            let s_x_a = cross(&sj, &st.a_bar);
            let tr_dp = dp[0][0] + dp[1][1] + dp[2][2];
            let tr_dpd = dpd[0][0] + dpd[1][1] + dpd[2][2];
            for r in 0..3 {
                let dp_w = dp[0][r] * w[0] + dp[1][r] * w[1] + dp[2][r] * w[2];
                let dpd_w = dpd[0][r] * w[0] + dpd[1][r] * w[1] + dpd[2][r] * w[2];
                let dq = s_x_a[r]
                    + di_alpha[r]
                    + row_dot(&self.d_tf[r], j, qdd)
                    + gyro[r]
                    + 2.0 * (tr_dp * w[r] - dp_w);
                let dqd = 2.0 * (tr_dpd * w[r] - dpd_w);
                let dqdd = self.i_tf(r, j, q);
                t.k_ref_f[(3 + r) * nf + map[j]] += dq + gp * dqd + bp * dqdd;
            }
        }
        // ∂f_f/∂[ā, α, ω]: S̄ᵀ, Ī_θfᵀ, and through ω̃², ω̃:
        // ∂(ω̃²)_kl/∂ω_i = δ_ki ω_l + ω_k δ_li − 2 ω_i δ_kl, ∂ω̃_kl/∂ω_i = −ε_kli.
        for a in 0..k {
            // x_kl = Ī_lk[a] + (S̄_kl q)_a, y_kl = (S̄_kl q̇)_a.
            let mut x = [[0.0; 3]; 3];
            let mut y = [[0.0; 3]; 3];
            for kk in 0..3 {
                for l in 0..3 {
                    x[kk][l] = inv.i_kl[l][kk][a];
                    if self.s_kl_live[kk][l] {
                        x[kk][l] += row_dot(&inv.s_kl[kk][l], a, q);
                        y[kk][l] = row_dot(&inv.s_kl[kk][l], a, qd);
                    }
                }
            }
            let row = map[a] * 9;
            for r in 0..3 {
                if self.frame_live[r] {
                    t.d_f_frame[row + r] += inv.s_bar[(r, a)];
                }
                if self.frame_live[3 + r] {
                    t.d_f_frame[row + 3 + r] += self.i_tf(r, a, q);
                }
            }
            for i in 0..3 {
                if !self.frame_live[6 + i] {
                    continue;
                }
                let mut v = 0.0;
                for kk in 0..3 {
                    for l in 0..3 {
                        let mut dw2 = 0.0;
                        if kk == i {
                            dw2 += w[l];
                        }
                        if l == i {
                            dw2 += w[kk];
                        }
                        if kk == l {
                            dw2 -= 2.0 * w[i];
                        }
                        v += dw2 * x[kk][l];
                    }
                }
                // −ε_kli: (k, l) = (i+1, i+2) gives −1, (i+2, i+1) gives +1.
                let (k1, k2) = ((i + 1) % 3, (i + 2) % 3);
                v += 2.0 * (-y[k1][k2] + y[k2][k1]);
                t.d_f_frame[row + 6 + i] += v;
            }
        }
        // ∂[f_r; f_θ]/∂[ā, α, ω] (6 × 9).
        let m = inv.mass;
        let st_sk = skew(&s_t);
        let w_dot_s = w[0] * s_t[0] + w[1] * s_t[1] + w[2] * s_t[2];
        let v_sk = skew(&sbar_qd);
        let h = mv(&i_tt, w);
        let h_sk = skew(&h);
        let tr_p = p[0][0] + p[1][1] + p[2][2];
        for r in 0..3 {
            for c in 0..3 {
                let d = if r == c { 1.0 } else { 0.0 };
                // f_r: m I, −S̃_t, (ω·S_t) I + ω S_tᵀ − 2 S_t ωᵀ − 2 ṽ.
                let fr = [
                    m * d,
                    -st_sk[r][c],
                    w_dot_s * d + w[r] * s_t[c] - 2.0 * s_t[r] * w[c] - 2.0 * v_sk[r][c],
                ];
                // f_θ: S̃_t, Ī_θθ, ω̃ Ī_θθ − (Ī_θθ ω)~ + 2 (tr P I − Pᵀ).
                let w_i = (0..3).map(|b| w1[r][b] * i_tt[b][c]).sum::<f64>();
                let fth = [
                    st_sk[r][c],
                    i_tt[r][c],
                    w_i - h_sk[r][c] + 2.0 * (tr_p * d - p[c][r]),
                ];
                for g in 0..3 {
                    let col = 3 * g + c;
                    if self.frame_live[col] {
                        t.d_ref_frame[r * 9 + col] += fr[g];
                        t.d_ref_frame[(3 + r) * 9 + col] += fth[g];
                    }
                }
            }
        }
    }

    /// Adds the mass blocks at `q` (see [`BodyMass`]) to `out`, through `map`:
    /// `m_ff`, `[S̄; Ī_θf]`, their transposes and `[m I, −S̃_t; S̃_t, Ī_θθ]`.
    pub(crate) fn add_mass(&self, q: &[f64], map: &[usize], out: &mut BodyMass) {
        let inv = &self.inv;
        let (k, nf) = (self.k, out.m_ff.n());
        let s_t = self.s_t(q);
        for a in 0..3 {
            out.s_t[a] += s_t[a];
        }
        for a in 0..k {
            for b in 0..k {
                out.m_ff.add(map[a], map[b], inv.m_ff[(a, b)]);
            }
        }
        for j in 0..k {
            for r in 0..3 {
                let (s, i) = (inv.s_bar[(r, j)], self.i_tf(r, j, q));
                out.m_ref_f[r * nf + map[j]] += s;
                out.m_ref_f[(3 + r) * nf + map[j]] += i;
                if self.frame_live[r] {
                    out.m_f_frame[map[j] * 6 + r] += s;
                }
                if self.frame_live[3 + r] {
                    out.m_f_frame[map[j] * 6 + 3 + r] += i;
                }
            }
        }
        let i_tt = Self::i_tt(&self.u(q));
        let st_sk = skew(&s_t);
        for r in 0..3 {
            for c in 0..3 {
                let d = if r == c { 1.0 } else { 0.0 };
                let blocks = [
                    (r, c, inv.mass * d),
                    (r, 3 + c, -st_sk[r][c]),
                    (3 + r, c, st_sk[r][c]),
                    (3 + r, 3 + c, i_tt[r][c]),
                ];
                for (row, col, v) in blocks {
                    if self.frame_live[col] {
                        out.m_ref_frame[row * 6 + col] += v;
                    }
                }
            }
        }
    }
}
