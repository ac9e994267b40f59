//! The body-frame equations of a body given by its invariants
//! (`docs/theory.md`, sections 3–5), over `k` coordinates `q` (a modal
//! body's modes, or the few coordinates an attached mass moves with):
//!
//! - `f_r = m ā − S_t × α + S̄ q̈ + ω̃² S_t + 2 ω̃ S̄ q̇`
//! - `f_θ = S_t × ā + Ī_θθ α + Ī_θf q̈ + ω × (Ī_θθ ω) + 2 (tr P ω − Pᵀ ω)`
//! - `f_f = S̄ᵀ ā + Ī_θfᵀ α + m_ff q̈ + Σ_kl [(ω̃²)_kl (Ī_lk + S̄_kl q) +
//!   2 ω̃_kl S̄_kl q̇] + K_ff q + ∂U_nl/∂q`
//!
//! with `S_t = S_t0 + S̄ q`, `Ī_θθ = tr(U) I − U`,
//! `U_kl = Θ_kl + (Ī_kl + Ī_lk) q + qᵀ S̄_kl q`, `P_kl = (Ī_kl + qᵀ S̄_kl) q̇`.
//! The derivatives the Newton matrix and the mass blocks need are exact:
//! forward-mode dual numbers through the same evaluation, one direction per
//! coordinate (seeded with `∂q = 1`, `∂q̇ = γ'`, `∂q̈ = β'`) and one per
//! frame component. Nothing allocates after [`InertiaTerms::new`].

use crate::body::{BodyForces, BodyMass, BodyState, BodyTangent, Invariants};
use crate::modal::ModalPoly;
use nalgebra::{DMatrix, DVector};
use std::ops::{Add, Mul, Sub};

/// The equations of one set of invariants (see the module documentation).
#[derive(Clone, Debug)]
pub(crate) struct InertiaTerms {
    inv: Invariants,
    k: usize,
    /// `∂U_nl/∂q_a` (empty: no stiffening energy).
    grad: Vec<ModalPoly>,
    /// Which `S̄_kl` are non-zero.
    s_kl_live: [[bool; 3]; 3],
    /// `Ī_ab − Ī_ba` for `(a, b)` = `(y, z)`, `(z, x)`, `(x, y)`.
    c_tf: [DVector<f64>; 3],
    /// `S̄_ab − S̄_ba` for the same pairs.
    d_tf: [DMatrix<f64>; 3],
    /// Which frame components a planar scene has (`ā_x, ā_y, α_z, ω_z`).
    frame_live: [bool; 9],
}

impl InertiaTerms {
    /// The terms of `inv` (`n_f = k`), with the stiffening gradient `grad`
    /// (`k` polynomials, or none), for a planar or spatial scene.
    pub(crate) fn new(inv: Invariants, grad: Vec<ModalPoly>, planar: bool) -> Self {
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
        Self {
            inv,
            k,
            grad,
            s_kl_live,
            c_tf,
            d_tf,
            frame_live,
        }
    }

    /// The invariants.
    pub(crate) fn invariants(&self) -> &Invariants {
        &self.inv
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
        let f_f = &mut out.f_f;
        let rf = self.eval::<f64>(s, Seed::NONE, frame_rows, |a, v| f_f[map[a]] += v);
        if frame_rows {
            for r in 0..3 {
                out.f_r[r] += rf[r];
                out.f_th[r] += rf[3 + r];
            }
        }
    }

    /// Adds the derivatives of [`InertiaTerms::add_forces`] (see
    /// [`BodyTangent`]) to `t`, through `map`.
    pub(crate) fn add_tangent(
        &self,
        s: &Inputs,
        bp: f64,
        gp: f64,
        frame_rows: bool,
        map: &[usize],
        t: &mut BodyTangent,
    ) {
        let nf = t.k_ff.n();
        for j in 0..self.k {
            let seed = Seed::mode(j, 1.0, gp, bp);
            let k_ff = &mut t.k_ff;
            let rf = self.eval::<Dual>(s, seed, frame_rows, |a, v| k_ff.add(map[a], map[j], v.d));
            if frame_rows {
                for (r, v) in rf.iter().enumerate() {
                    t.k_ref_f[r * nf + map[j]] += v.d;
                }
            }
        }
        if frame_rows {
            for i in (0..9).filter(|&i| self.frame_live[i]) {
                let d_f = &mut t.d_f_frame;
                let rf =
                    self.eval::<Dual>(s, Seed::frame(i), true, |a, v| d_f[map[a] * 9 + i] += v.d);
                for (r, v) in rf.iter().enumerate() {
                    t.d_ref_frame[r * 9 + i] += v.d;
                }
            }
        }
    }

    /// Adds the mass blocks at `q` (see [`BodyMass`]) to `out`, through `map`.
    pub(crate) fn add_mass(&self, q: &[f64], map: &[usize], out: &mut BodyMass) {
        let inv = &self.inv;
        let (k, nf) = (self.k, out.m_ff.n());
        for a in 0..3 {
            out.s_t[a] += inv.s_t0[a] + (0..k).map(|j| inv.s_bar[(a, j)] * q[j]).sum::<f64>();
        }
        for a in 0..k {
            for b in 0..k {
                out.m_ff.add(map[a], map[b], inv.m_ff[(a, b)]);
            }
        }
        // The acceleration-linear blocks: derivatives at q̇ = q̈ = 0 and a
        // frame at rest, where the velocity terms vanish.
        let s = Inputs {
            q,
            qd: None,
            qdd: None,
            frame: [0.0; 9],
        };
        for j in 0..k {
            let rf = self.eval::<Dual>(&s, Seed::mode(j, 0.0, 0.0, 1.0), true, |_, _| {});
            for (r, v) in rf.iter().enumerate() {
                out.m_ref_f[r * nf + map[j]] += v.d;
            }
        }
        for i in (0..6).filter(|&i| self.frame_live[i]) {
            let m_f = &mut out.m_f_frame;
            let rf = self.eval::<Dual>(&s, Seed::frame(i), true, |a, v: Dual| {
                m_f[map[a] * 6 + i] += v.d
            });
            for (r, v) in rf.iter().enumerate() {
                out.m_ref_frame[r * 6 + i] += v.d;
            }
        }
    }

    /// `[f_r; f_θ]` (when `frame_rows`) and each `f_f[a]` (to `sink`) at `s`,
    /// differentiated along `seed` when `T` is [`Dual`].
    pub(crate) fn eval<T: Num>(
        &self,
        s: &Inputs,
        seed: Seed,
        frame_rows: bool,
        mut sink: impl FnMut(usize, T),
    ) -> [T; 6] {
        let inv = &self.inv;
        let k = self.k;
        let d = |j: usize, v: f64| if j == seed.mode { v } else { 0.0 };
        let q = |j: usize| T::var(s.q[j], d(j, seed.dq));
        let qd = |j: usize| T::var(s.qd.map_or(0.0, |x| x[j]), d(j, seed.dqd));
        let qdd = |j: usize| T::var(s.qdd.map_or(0.0, |x| x[j]), d(j, seed.dqdd));
        let fr = |i: usize| {
            if self.frame_live[i] {
                T::var(s.frame[i], if i == seed.frame { 1.0 } else { 0.0 })
            } else {
                T::c(0.0)
            }
        };
        let zero = T::c(0.0);
        let a_bar = [fr(0), fr(1), fr(2)];
        let alpha = [fr(3), fr(4), fr(5)];
        let w = [fr(6), fr(7), fr(8)];
        // ω̃ and ω̃² = ω ωᵀ − |ω|² I.
        let w1 = [
            [zero, zero - w[2], w[1]],
            [w[2], zero, zero - w[0]],
            [zero - w[1], w[0], zero],
        ];
        let wsq = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        let w2: [[T; 3]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                if a == b {
                    w[a] * w[b] - wsq
                } else {
                    w[a] * w[b]
                }
            })
        });
        // Ī_θf row r, column a.
        let i_tf = |r: usize, a: usize| {
            let mut v = T::c(self.c_tf[r][a]);
            for c in 0..k {
                let x = self.d_tf[r][(c, a)];
                if x != 0.0 {
                    v = v + q(c).scale(x);
                }
            }
            v
        };
        let mut out = [zero; 6];
        if frame_rows {
            let s_t: [T; 3] = std::array::from_fn(|a| {
                T::c(inv.s_t0[a]) + dot(inv.s_bar.row(a).iter().copied(), &q)
            });
            let mut u = [[zero; 3]; 3];
            // The symmetric `u` filled by index, both triangles at once.
            #[allow(clippy::needless_range_loop)]
            for a in 0..3 {
                for b in a..3 {
                    let lin = inv.i_kl[a][b]
                        .iter()
                        .zip(inv.i_kl[b][a].iter())
                        .map(|(x, y)| x + y);
                    let mut v = T::c(inv.theta[(a, b)]) + dot(lin, &q);
                    if self.s_kl_live[a][b] {
                        v = v + bilinear(&inv.s_kl[a][b], &q, &q);
                    }
                    u[a][b] = v;
                    u[b][a] = v;
                }
            }
            let tr = u[0][0] + u[1][1] + u[2][2];
            let i_tt: [[T; 3]; 3] = std::array::from_fn(|a| {
                std::array::from_fn(|b| if a == b { tr - u[a][b] } else { zero - u[a][b] })
            });
            let p: [[T; 3]; 3] = std::array::from_fn(|a| {
                std::array::from_fn(|b| {
                    let mut v = dot(inv.i_kl[a][b].iter().copied(), &qd);
                    if self.s_kl_live[a][b] {
                        v = v + bilinear(&inv.s_kl[a][b], &q, &qd);
                    }
                    v
                })
            });
            let sbar_qd: [T; 3] =
                std::array::from_fn(|a| dot(inv.s_bar.row(a).iter().copied(), &qd));
            let sbar_qdd: [T; 3] =
                std::array::from_fn(|a| dot(inv.s_bar.row(a).iter().copied(), &qdd));
            let itf_qdd: [T; 3] = std::array::from_fn(|r| {
                dot(self.c_tf[r].iter().copied(), &qdd) + bilinear(&self.d_tf[r], &q, &qdd)
            });
            let mv = |m: &[[T; 3]; 3], v: &[T; 3]| -> [T; 3] {
                std::array::from_fn(|a| m[a][0] * v[0] + m[a][1] * v[1] + m[a][2] * v[2])
            };
            // f_r = m ā − S_t × α + S̄ η̈ + ω̃² S_t + 2 ω̃ S̄ η̇.
            let st_x_alpha = cross(&s_t, &alpha);
            let w2_st = mv(&w2, &s_t);
            let w1_sqd = mv(&w1, &sbar_qd);
            for a in 0..3 {
                out[a] = a_bar[a].scale(inv.mass) - st_x_alpha[a]
                    + sbar_qdd[a]
                    + w2_st[a]
                    + w1_sqd[a].scale(2.0);
            }
            // f_θ = S_t × ā + Ī_θθ α + Ī_θf η̈ + ω × (Ī_θθ ω) + 2 (tr P ω − Pᵀ ω).
            let st_x_a = cross(&s_t, &a_bar);
            let i_alpha = mv(&i_tt, &alpha);
            let gyro = cross(&w, &mv(&i_tt, &w));
            let tr_p = p[0][0] + p[1][1] + p[2][2];
            for a in 0..3 {
                let pt_w = p[0][a] * w[0] + p[1][a] * w[1] + p[2][a] * w[2];
                out[3 + a] =
                    st_x_a[a] + i_alpha[a] + itf_qdd[a] + gyro[a] + (w[a] * tr_p - pt_w).scale(2.0);
            }
        }
        // f_f.
        let row_dot = |m: &DMatrix<f64>, a: usize, x: &dyn Fn(usize) -> T| {
            let mut v = zero;
            for b in 0..k {
                let c = m[(a, b)];
                if c != 0.0 {
                    v = v + x(b).scale(c);
                }
            }
            v
        };
        for a in 0..k {
            let mut f = zero;
            for r in 0..3 {
                f = f + a_bar[r].scale(inv.s_bar[(r, a)]) + i_tf(r, a) * alpha[r];
            }
            f = f + row_dot(&inv.m_ff, a, &qdd);
            for kk in 0..3 {
                for l in 0..3 {
                    let c = inv.i_kl[l][kk][a];
                    let live = self.s_kl_live[kk][l];
                    if c != 0.0 || live {
                        let mut v = T::c(c);
                        if live {
                            v = v + row_dot(&inv.s_kl[kk][l], a, &q);
                        }
                        f = f + w2[kk][l] * v;
                    }
                    if kk != l && live {
                        f = f + (w1[kk][l] * row_dot(&inv.s_kl[kk][l], a, &qd)).scale(2.0);
                    }
                }
            }
            f = f + row_dot(&inv.k_ff, a, &q);
            if let Some(g) = self.grad.get(a) {
                f = f + g.eval(q);
            }
            sink(a, f);
        }
        out
    }
}

/// Which coordinate a dual evaluation differentiates by.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Seed {
    /// Mode `j` (or `usize::MAX`) with `(∂η, ∂η̇, ∂η̈)`.
    pub(crate) mode: usize,
    pub(crate) dq: f64,
    pub(crate) dqd: f64,
    pub(crate) dqdd: f64,
    /// Frame component (or `usize::MAX`).
    pub(crate) frame: usize,
}

impl Seed {
    pub(crate) const NONE: Seed = Seed {
        mode: usize::MAX,
        dq: 0.0,
        dqd: 0.0,
        dqdd: 0.0,
        frame: usize::MAX,
    };
    pub(crate) fn mode(j: usize, dq: f64, dqd: f64, dqdd: f64) -> Self {
        Seed {
            mode: j,
            dq,
            dqd,
            dqdd,
            ..Seed::NONE
        }
    }
    pub(crate) fn frame(k: usize) -> Self {
        Seed {
            frame: k,
            ..Seed::NONE
        }
    }
}

/// The coordinates an evaluation reads (`None`: zero).
pub(crate) struct Inputs<'a> {
    pub(crate) q: &'a [f64],
    pub(crate) qd: Option<&'a [f64]>,
    pub(crate) qdd: Option<&'a [f64]>,
    pub(crate) frame: [f64; 9],
}

impl<'a> Inputs<'a> {
    pub(crate) fn of(s: &BodyState<'a>) -> Self {
        Inputs {
            q: s.q_f,
            qd: Some(s.qd_f),
            qdd: Some(s.qdd_f),
            frame: s.frame,
        }
    }
}

/// Real numbers and dual numbers `v + d ε` (`ε² = 0`).
pub(crate) trait Num:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self>
{
    fn c(v: f64) -> Self;
    fn var(v: f64, d: f64) -> Self;
    fn scale(self, s: f64) -> Self;
}

impl Num for f64 {
    #[inline]
    fn c(v: f64) -> Self {
        v
    }
    #[inline]
    fn var(v: f64, _: f64) -> Self {
        v
    }
    #[inline]
    fn scale(self, s: f64) -> Self {
        self * s
    }
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Dual {
    pub(crate) v: f64,
    pub(crate) d: f64,
}

impl Add for Dual {
    type Output = Dual;
    #[inline]
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}
impl Sub for Dual {
    type Output = Dual;
    #[inline]
    fn sub(self, o: Dual) -> Dual {
        Dual {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}
impl Mul for Dual {
    type Output = Dual;
    #[inline]
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}
impl Num for Dual {
    #[inline]
    fn c(v: f64) -> Self {
        Dual { v, d: 0.0 }
    }
    #[inline]
    fn var(v: f64, d: f64) -> Self {
        Dual { v, d }
    }
    #[inline]
    fn scale(self, s: f64) -> Self {
        Dual {
            v: self.v * s,
            d: self.d * s,
        }
    }
}

fn cross<T: Num>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `xᵀ M y`.
pub(crate) fn bilinear<T: Num>(
    m: &DMatrix<f64>,
    x: &impl Fn(usize) -> T,
    y: &impl Fn(usize) -> T,
) -> T {
    let n = m.nrows();
    let mut s = T::c(0.0);
    for b in 0..n {
        let mut col = T::c(0.0);
        for a in 0..n {
            let v = m[(a, b)];
            if v != 0.0 {
                col = col + x(a).scale(v);
            }
        }
        s = s + col * y(b);
    }
    s
}

/// `c · x`.
fn dot<T: Num>(c: impl Iterator<Item = f64>, x: &impl Fn(usize) -> T) -> T {
    let mut s = T::c(0.0);
    for (a, v) in c.enumerate() {
        if v != 0.0 {
            s = s + x(a).scale(v);
        }
    }
    s
}
