//! Modal bodies: a flexible body reduced to `k` modes, `q_f = Φ η`
//! (theory: `docs/theory.md`, "Modal bodies").
//!
//! A [`ModalBody`] evaluates the body-frame equations of [`crate::body`]
//! from the projected invariants `S̄Φ`, `Φᵀ S̄_kl Φ`, `Ī_kl Φ`, `Φᵀ m_ff Φ`,
//! `Φᵀ K_ff Φ` (`m`, `S_t0`, `Θ_kl` unchanged) and the stiffening energy
//! `U_nl(Φ η)` as a polynomial in `η`, with `η` in place of `q_f`:
//!
//! - `f_r = m ā − S_t × α + S̄ η̈ + ω̃² S_t + 2 ω̃ S̄ η̇`
//! - `f_θ = S_t × ā + Ī_θθ α + Ī_θf η̈ + ω × (Ī_θθ ω) + 2 (tr P ω − Pᵀ ω)`
//! - `f_f = S̄ᵀ ā + Ī_θfᵀ α + m_ff η̈ + Σ_kl [(ω̃²)_kl (Ī_lk + S̄_kl η) +
//!   2 ω̃_kl S̄_kl η̇] + K_ff η + ∂U_nl/∂η`
//!
//! (the terms of `ffr_codegen`'s element equations, over the whole body).
//! The derivatives the Newton matrix needs are exact: forward-mode dual
//! numbers through the same evaluation, one direction per mode (seeded with
//! `∂η = 1`, `∂η̇ = γ'`, `∂η̈ = β'`) and one per frame component. Nothing
//! allocates after [`ModalBody::new`].
//!
//! Markers on the body use the full body's point shapes times `Φ`; the
//! body's own damping (per-mode ratios) is [`Body::damping`].

use crate::body::{
    BandBuf, Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork, Invariants,
    PointShape,
};
use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};
use std::collections::BTreeMap;
use std::ops::{Add, Mul, Sub};

/// A polynomial in the modal coordinates, `Σ_t c_t Π_{i ∈ idx_t} η_i`
/// (indices sorted, repeated for powers).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModalPoly {
    coefs: Vec<f64>,
    /// Term `t` uses `idx[starts[t]..starts[t + 1]]`.
    starts: Vec<usize>,
    idx: Vec<u32>,
}

impl ModalPoly {
    /// From terms `(c, indices)`; equal index multisets are merged, zero
    /// coefficients dropped, terms kept in index order (deterministic).
    pub fn new(terms: impl IntoIterator<Item = (f64, Vec<u32>)>) -> Self {
        let mut map: BTreeMap<Vec<u32>, f64> = BTreeMap::new();
        for (c, mut idx) in terms {
            idx.sort_unstable();
            *map.entry(idx).or_insert(0.0) += c;
        }
        let mut out = ModalPoly {
            coefs: Vec::new(),
            starts: vec![0],
            idx: Vec::new(),
        };
        for (idx, c) in map {
            if c != 0.0 {
                out.coefs.push(c);
                out.idx.extend_from_slice(&idx);
                out.starts.push(out.idx.len());
            }
        }
        out
    }

    /// Number of terms.
    pub fn len(&self) -> usize {
        self.coefs.len()
    }

    /// Whether the polynomial is zero.
    pub fn is_empty(&self) -> bool {
        self.coefs.is_empty()
    }

    /// The terms `(c, indices)`.
    pub fn terms(&self) -> impl Iterator<Item = (f64, &[u32])> {
        self.coefs
            .iter()
            .enumerate()
            .map(|(t, &c)| (c, &self.idx[self.starts[t]..self.starts[t + 1]]))
    }

    /// The largest index used plus one (0 for a constant).
    pub fn vars(&self) -> usize {
        self.idx.iter().map(|&i| i as usize + 1).max().unwrap_or(0)
    }

    /// `∂/∂η_j` for `j < k`.
    pub fn gradient(&self, k: usize) -> Vec<ModalPoly> {
        let mut parts: Vec<Vec<(f64, Vec<u32>)>> = vec![Vec::new(); k];
        for (c, idx) in self.terms() {
            let mut p = 0;
            while p < idx.len() {
                let v = idx[p];
                let mut e = 0;
                while p + e < idx.len() && idx[p + e] == v {
                    e += 1;
                }
                let mut rest = idx.to_vec();
                rest.remove(p);
                parts[v as usize].push((c * e as f64, rest));
                p += e;
            }
        }
        parts.into_iter().map(ModalPoly::new).collect()
    }

    fn eval<T: Num>(&self, x: impl Fn(usize) -> T) -> T {
        let mut s = T::c(0.0);
        for (c, idx) in self.terms() {
            let mut t = T::c(c);
            for &i in idx {
                t = t * x(i as usize);
            }
            s = s + t;
        }
        s
    }

    /// The value at `eta`.
    pub fn value(&self, eta: &[f64]) -> f64 {
        self.eval(|i| eta[i])
    }
}

/// What a modal body is made of (see [`ModalBody::new`]).
#[derive(Clone, Debug)]
pub struct ModalData {
    /// The projected invariants (`n_f = k`).
    pub invariants: Invariants,
    /// `Φ` (full body's `n_f` × `k`): maps the full body's point shapes.
    pub phi: DMatrix<f64>,
    /// `U_nl(Φ η)` (zero without stiffening).
    pub stiffening: ModalPoly,
    /// The body's own damping matrix `D` (`k × k`, symmetric, positive
    /// semi-definite), e.g. `diag(2 ζ_i ω_i)`; `None`: none.
    pub damping: Option<DMatrix<f64>>,
    /// One label per mode (`mode_1`, `constraint_uy_8`, …).
    pub labels: Vec<String>,
    /// One line saying what the body is.
    pub description: String,
}

/// A flexible body reduced to modes (see the module documentation).
pub struct ModalBody {
    inner: Box<dyn Body>,
    data: ModalData,
    layout: BodyLayout,
    /// `∂U_nl/∂η_a`.
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

impl std::fmt::Debug for ModalBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModalBody")
            .field("layout", &self.layout)
            .field("modes", &self.data.labels)
            .finish()
    }
}

/// Which coordinate a dual evaluation differentiates by.
#[derive(Clone, Copy, Debug)]
struct Seed {
    /// Mode `j` (or `usize::MAX`) with `(∂η, ∂η̇, ∂η̈)`.
    mode: usize,
    dq: f64,
    dqd: f64,
    dqdd: f64,
    /// Frame component (or `usize::MAX`).
    frame: usize,
}

impl Seed {
    const NONE: Seed = Seed {
        mode: usize::MAX,
        dq: 0.0,
        dqd: 0.0,
        dqdd: 0.0,
        frame: usize::MAX,
    };
    fn mode(j: usize, dq: f64, dqd: f64, dqdd: f64) -> Self {
        Seed {
            mode: j,
            dq,
            dqd,
            dqdd,
            ..Seed::NONE
        }
    }
    fn frame(k: usize) -> Self {
        Seed {
            frame: k,
            ..Seed::NONE
        }
    }
}

/// The coordinates an evaluation reads (`None`: zero).
struct Inputs<'a> {
    q: &'a [f64],
    qd: Option<&'a [f64]>,
    qdd: Option<&'a [f64]>,
    frame: [f64; 9],
}

impl<'a> Inputs<'a> {
    fn of(s: &BodyState<'a>) -> Self {
        Inputs {
            q: s.q_f,
            qd: Some(s.qd_f),
            qdd: Some(s.qdd_f),
            frame: s.frame,
        }
    }
}

/// Real numbers and dual numbers `v + d ε` (`ε² = 0`).
trait Num: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {
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
struct Dual {
    v: f64,
    d: f64,
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
fn bilinear<T: Num>(m: &DMatrix<f64>, x: &impl Fn(usize) -> T, y: &impl Fn(usize) -> T) -> T {
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

impl ModalBody {
    /// A modal body from its data; `inner` is the full body (its point
    /// shapes, times `Φ`, place markers). Checks the sizes, that every
    /// number is finite, `m_ff` symmetric positive definite, `K_ff` and the
    /// damping symmetric, and that the stiffening polynomial uses the modes
    /// only.
    pub fn new(inner: Box<dyn Body>, data: ModalData) -> Result<Self> {
        let k = data.invariants.nf();
        let full = inner.layout().clone();
        let bad = |msg: String| Err(Error::InvalidInput(format!("modal body: {msg}")));
        if k == 0 {
            return bad("no modes".into());
        }
        if data.phi.shape() != (full.nf, k) {
            return bad(format!(
                "Φ is {}×{}, the full body has {} elastic coordinates and the invariants {k} modes",
                data.phi.nrows(),
                data.phi.ncols(),
                full.nf
            ));
        }
        if data.labels.len() != k {
            return bad(format!("{} labels for {k} modes", data.labels.len()));
        }
        if data.stiffening.vars() > k {
            return bad(format!(
                "the stiffening energy uses mode {} of {k}",
                data.stiffening.vars()
            ));
        }
        let inv = &data.invariants;
        let finite = |xs: &[f64]| xs.iter().all(|x| x.is_finite());
        let mut ok = finite(&[inv.mass])
            && finite(inv.s_t0.as_slice())
            && finite(inv.s_bar.as_slice())
            && finite(inv.theta.as_slice())
            && finite(inv.m_ff.as_slice())
            && finite(inv.k_ff.as_slice())
            && finite(data.phi.as_slice())
            && data.stiffening.coefs.iter().all(|c| c.is_finite());
        for kk in 0..3 {
            for l in 0..3 {
                ok &= finite(inv.s_kl[kk][l].as_slice()) && finite(inv.i_kl[kk][l].as_slice());
                ok &= inv.s_kl[kk][l].shape() == (k, k) && inv.i_kl[kk][l].len() == k;
            }
        }
        if !ok {
            return bad("the invariants or Φ contain a non-finite number or a wrong size".into());
        }
        let sym = |m: &DMatrix<f64>| {
            let scale = m.amax().max(f64::MIN_POSITIVE);
            (m - m.transpose()).amax() <= 1e-12 * scale
        };
        if inv.k_ff.shape() != (k, k) || !sym(&inv.k_ff) || !sym(&inv.m_ff) {
            return bad("m_ff and K_ff must be symmetric k × k matrices".into());
        }
        if inv.m_ff.clone().cholesky().is_none() {
            return bad("the modal mass matrix is not positive definite".into());
        }
        if let Some(d) = &data.damping {
            if d.shape() != (k, k) || !finite(d.as_slice()) || !sym(d) {
                return bad("the damping matrix must be a finite symmetric k × k matrix".into());
            }
        }
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
        let planar = full.scene_dim == 2;
        let frame_live = std::array::from_fn(|i| !(planar && matches!(i, 2 | 3 | 4 | 6 | 7)));
        let layout = BodyLayout {
            dim: full.dim,
            scene_dim: full.scene_dim,
            nf: k,
            half_bandwidth: k - 1,
            free_frame: true,
            zero_frame_acceleration: false,
            labels: data.labels.clone(),
            length: full.length,
            description: data.description.clone(),
        };
        let grad = data.stiffening.gradient(k);
        Ok(Self {
            inner,
            data,
            layout,
            grad,
            s_kl_live,
            c_tf,
            d_tf,
            frame_live,
        })
    }

    /// The data the body was made from.
    pub fn data(&self) -> &ModalData {
        &self.data
    }

    /// The full body the modes were taken from.
    pub fn full_body(&self) -> &dyn Body {
        &*self.inner
    }

    /// `[f_r; f_θ]` (when `frame_rows`) and each `f_f[a]` (to `sink`) at `s`,
    /// differentiated along `seed` when `T` is [`Dual`].
    fn eval<T: Num>(
        &self,
        s: &Inputs,
        seed: Seed,
        frame_rows: bool,
        mut sink: impl FnMut(usize, T),
    ) -> [T; 6] {
        let inv = &self.data.invariants;
        let k = self.layout.nf;
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
            f = f + row_dot(&inv.k_ff, a, &q) + self.grad[a].eval(q);
            sink(a, f);
        }
        out
    }
}

impl Body for ModalBody {
    fn layout(&self) -> &BodyLayout {
        &self.layout
    }

    fn work(&self) -> BodyWork {
        BodyWork::default()
    }

    fn forces(&self, state: &BodyState, frame_rows: bool, _w: &mut BodyWork, out: &mut BodyForces) {
        out.clear();
        let rf = self.eval::<f64>(&Inputs::of(state), Seed::NONE, frame_rows, |a, v| {
            out.f_f[a] = v
        });
        if frame_rows {
            out.f_r.copy_from_slice(&rf[..3]);
            out.f_th.copy_from_slice(&rf[3..]);
        }
    }

    fn tangent(
        &self,
        state: &BodyState,
        bp: f64,
        gp: f64,
        frame_rows: bool,
        w: &mut BodyWork,
        out: &mut BodyForces,
        t: &mut BodyTangent,
    ) {
        self.forces(state, frame_rows, w, out);
        t.clear();
        let k = self.layout.nf;
        let s = Inputs::of(state);
        for j in 0..k {
            let seed = Seed::mode(j, 1.0, gp, bp);
            let k_ff = &mut t.k_ff;
            let rf = self.eval::<Dual>(&s, seed, frame_rows, |a, v| k_ff.add(a, j, v.d));
            if frame_rows {
                for (r, v) in rf.iter().enumerate() {
                    t.k_ref_f[r * k + j] = v.d;
                }
            }
        }
        if frame_rows {
            for i in (0..9).filter(|&i| self.frame_live[i]) {
                let d_f = &mut t.d_f_frame;
                let rf = self.eval::<Dual>(&s, Seed::frame(i), true, |a, v| d_f[a * 9 + i] = v.d);
                for (r, v) in rf.iter().enumerate() {
                    t.d_ref_frame[r * 9 + i] = v.d;
                }
            }
        }
    }

    fn mass(&self, q_f: &[f64], _w: &mut BodyWork, out: &mut BodyMass) {
        out.clear();
        let inv = &self.data.invariants;
        let k = self.layout.nf;
        for a in 0..3 {
            out.s_t[a] = inv.s_t0[a] + (0..k).map(|j| inv.s_bar[(a, j)] * q_f[j]).sum::<f64>();
        }
        for a in 0..k {
            for b in 0..k {
                out.m_ff.add(a, b, inv.m_ff[(a, b)]);
            }
        }
        // The acceleration-linear blocks: derivatives at η̇ = η̈ = 0 and a
        // frame at rest, where the velocity terms vanish.
        let s = Inputs {
            q: q_f,
            qd: None,
            qdd: None,
            frame: [0.0; 9],
        };
        for j in 0..k {
            let rf = self.eval::<Dual>(&s, Seed::mode(j, 0.0, 0.0, 1.0), true, |_, _| {});
            for (r, v) in rf.iter().enumerate() {
                out.m_ref_f[r * k + j] = v.d;
            }
        }
        for i in (0..6).filter(|&i| self.frame_live[i]) {
            let m_f = &mut out.m_f_frame;
            let rf = self.eval::<Dual>(&s, Seed::frame(i), true, |a, v: Dual| m_f[a * 6 + i] = v.d);
            for (r, v) in rf.iter().enumerate() {
                out.m_ref_frame[r * 6 + i] = v.d;
            }
        }
    }

    fn elastic_energy(&self, q_f: &[f64], _w: &mut BodyWork) -> f64 {
        let k_ff = &self.data.invariants.k_ff;
        let x = |i: usize| q_f[i];
        0.5 * bilinear(k_ff, &x, &x) + self.data.stiffening.value(q_f)
    }

    fn invariants(&self) -> Invariants {
        self.data.invariants.clone()
    }

    fn point_shape(&self, x: f64) -> Result<PointShape> {
        let full = self.inner.point_shape(x)?;
        let phi = &self.data.phi;
        let mut entries = Vec::new();
        for m in 0..phi.ncols() {
            let mut s = [0.0; 3];
            let mut psi = [0.0; 3];
            for (dof, sj, pj) in &full.entries {
                let f = phi[(*dof, m)];
                for a in 0..3 {
                    s[a] += sj[a] * f;
                    psi[a] += pj[a] * f;
                }
            }
            if s.iter().chain(&psi).any(|v| *v != 0.0) {
                entries.push((m, s, psi));
            }
        }
        Ok(PointShape {
            u0: full.u0,
            entries,
        })
    }

    fn damping(&self) -> Option<BandBuf> {
        let d = self.data.damping.as_ref()?;
        let k = self.layout.nf;
        let mut out = BandBuf::zeros(k, k - 1);
        for a in 0..k {
            for b in 0..k {
                out.add(a, b, d[(a, b)]);
            }
        }
        Some(out)
    }
}
