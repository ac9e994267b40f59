//! Modal bodies: a flexible body reduced to `k` modes, `q_f = Φ η`
//! (theory: `docs/theory.md`, "Modal bodies").
//!
//! A [`ModalBody`] evaluates the body-frame equations of [`crate::body`]
//! from the projected invariants `S̄Φ`, `Φᵀ S̄_kl Φ`, `Ī_kl Φ`, `Φᵀ m_ff Φ`,
//! `Φᵀ K_ff Φ` (`m`, `S_t0`, `Θ_kl` unchanged) and the stiffening energy
//! `U_nl(Φ η)` as a polynomial in `η`, with `η` in place of `q_f`: the
//! equations of [`crate::inertia`] (the terms of `ffr_codegen`'s element
//! equations, over the whole body), with exact derivatives by dual numbers.
//! Nothing allocates after [`ModalBody::new`].
//!
//! Markers on the body use the full body's point shapes times `Φ`; the
//! body's own damping (per-mode ratios) is [`Body::damping`].

use crate::body::{
    BandBuf, Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork, Invariants,
    PointShape,
};
use crate::error::{Error, Result};
use crate::inertia::{bilinear, InertiaTerms, Inputs, Num};
use nalgebra::DMatrix;
use std::collections::BTreeMap;

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

    pub(crate) fn eval<T: Num>(&self, x: impl Fn(usize) -> T) -> T {
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
    /// The equations of the projected invariants, with `∂U_nl/∂η`.
    terms: InertiaTerms,
    /// `0, 1, …, k − 1`: the modes are the body's coordinates.
    identity: Vec<usize>,
}

impl std::fmt::Debug for ModalBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModalBody")
            .field("layout", &self.layout)
            .field("modes", &self.data.labels)
            .finish()
    }
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
        let planar = full.scene_dim == 2;
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
        let terms = InertiaTerms::new(data.invariants.clone(), grad, planar);
        Ok(Self {
            inner,
            data,
            layout,
            terms,
            identity: (0..k).collect(),
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
        self.terms
            .add_forces(&Inputs::of(state), frame_rows, &self.identity, out);
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
        self.terms
            .add_tangent(&Inputs::of(state), bp, gp, frame_rows, &self.identity, t);
    }

    fn mass(&self, q_f: &[f64], _w: &mut BodyWork, out: &mut BodyMass) {
        out.clear();
        self.terms.add_mass(q_f, &self.identity, out);
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
