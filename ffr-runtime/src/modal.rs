//! Modal bodies: a flexible body reduced to `k` modes, `q_f = Φ η`
//! (theory: `docs/theory.md`, "Modal bodies").
//!
//! A [`ModalBody`] evaluates the body-frame equations of [`crate::body`]
//! from the projected invariants `S̄Φ`, `Φᵀ S̄_kl Φ`, `Ī_kl Φ`, `Φᵀ m_ff Φ`
//! (`m`, `S_t0`, `Θ_kl` unchanged), with `η` in place of `q_f`: the equations
//! of `ffr-runtime/src/inertia.rs`, with their derivatives written out. The elastic
//! force is `Φᵀ K_ff Φ η` for a linear body; with geometric stiffening it is
//! the full body's, `Φᵀ (K_ff q_f + ∇U_nl(q_f))` at `q_f = Φ η`, from the full
//! body's element kernels (its few scalars per element and their chain
//! rule), with the tangent `Φᵀ K_t Φ` from its banded tangent: no expanded
//! polynomial in the modes, no dual numbers, nothing allocated after
//! [`ModalBody::work`].
//!
//! Markers on the body use the full body's point shapes times `Φ`; the
//! body's own damping (per-mode ratios) is [`Body::damping`].

use crate::body::{
    BandBuf, Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork, InnerWork,
    Invariants, PointShape, ScalarLayout,
};
use crate::error::{Error, Result};
use crate::inertia::{bilinear, dot_slices, InertiaTerms, Inputs};
use crate::kernel::{KernelInput, MassOut, ResidualOut, TangentOut};
use crate::modal_kernels::ModalKernels;
use nalgebra::DMatrix;

/// What a modal body is made of (see [`ModalBody::new`]).
#[derive(Clone, Debug)]
pub struct ModalData {
    /// The projected invariants (`n_f = k`).
    pub invariants: Invariants,
    /// `Φ` (full body's `n_f` × `k`): maps the full body's point shapes.
    pub phi: DMatrix<f64>,
    /// Whether the full body's kernels have geometric stiffening: the
    /// elastic force is then the full body's at `q_f = Φ η` (`K_ff q_f +
    /// ∇U_nl`, projected by `Φᵀ`); otherwise `Φᵀ K_ff Φ η` (`invariants.k_ff`).
    pub stiffening: bool,
    /// The body's own damping matrix `D` (`k × k`, symmetric, positive
    /// semi-definite), e.g. `diag(2 ζ_i ω_i)`; `None`: none.
    pub damping: Option<DMatrix<f64>>,
    /// One label per mode (`mode_1`, `constraint_uy_8`, …).
    pub labels: Vec<String>,
    /// One line saying what the body is.
    pub description: String,
}

/// A modal body's numbers as constants, in generated code (`ffr emit
/// --modes`, `ffr_codegen::BodyConfig::modes`): matrices as row-major
/// slices, written to read back to the same bits. [`ModalConsts::data`]
/// makes the [`ModalData`] of [`ModalBody::new`].
#[derive(Clone, Copy, Debug)]
pub struct ModalConsts {
    /// 2 (planar) or 3 (spatial).
    pub dim: usize,
    /// Number of modes `k`.
    pub modes: usize,
    /// The full body's elastic coordinates `n_f`.
    pub nf: usize,
    /// `m`.
    pub mass: f64,
    /// `S_t0`.
    pub s_t0: [f64; 3],
    /// `S̄ Φ` (3 × k).
    pub s_bar: &'static [f64],
    /// `Φᵀ S̄_kl Φ` (k × k each).
    pub s_kl: [[&'static [f64]; 3]; 3],
    /// `Ī_kl Φ` (k each).
    pub i_kl: [[&'static [f64]; 3]; 3],
    /// `Θ_kl`.
    pub theta: [[f64; 3]; 3],
    /// `Φᵀ m_ff Φ` (k × k).
    pub m_ff: &'static [f64],
    /// `Φᵀ K_ff Φ` (k × k).
    pub k_ff: &'static [f64],
    /// `Φ` (n_f × k).
    pub phi: &'static [f64],
    /// [`ModalData::stiffening`].
    pub stiffening: bool,
    /// The damping matrix (k × k), if any.
    pub damping: Option<&'static [f64]>,
    /// One label per mode.
    pub labels: &'static [&'static str],
    /// [`ModalData::description`].
    pub description: &'static str,
}

impl ModalConsts {
    /// The data of [`ModalBody::new`] (which checks the numbers); an error
    /// if a slice does not have its size.
    pub fn data(&self) -> Result<ModalData> {
        let (k, nf) = (self.modes, self.nf);
        let sized = |name: &str, v: &[f64], n: usize| {
            if v.len() == n {
                Ok(())
            } else {
                Err(Error::InvalidInput(format!(
                    "modal constants: `{name}` has {} numbers, expected {n}",
                    v.len()
                )))
            }
        };
        sized("s_bar", self.s_bar, 3 * k)?;
        sized("m_ff", self.m_ff, k * k)?;
        sized("k_ff", self.k_ff, k * k)?;
        sized("phi", self.phi, nf * k)?;
        for a in 0..3 {
            for b in 0..3 {
                sized("s_kl", self.s_kl[a][b], k * k)?;
                sized("i_kl", self.i_kl[a][b], k)?;
            }
        }
        if let Some(d) = self.damping {
            sized("damping", d, k * k)?;
        }
        if self.labels.len() != k {
            return Err(Error::InvalidInput(format!(
                "modal constants: {} labels for {k} modes",
                self.labels.len()
            )));
        }
        let square = |v: &[f64]| DMatrix::from_row_slice(k, k, v);
        let mut inv = Invariants::zeros(self.dim, k);
        inv.mass = self.mass;
        inv.s_t0 = nalgebra::Vector3::from(self.s_t0);
        inv.s_bar = nalgebra::Matrix3xX::from_row_slice(self.s_bar);
        for a in 0..3 {
            for b in 0..3 {
                inv.s_kl[a][b] = square(self.s_kl[a][b]);
                inv.i_kl[a][b] = nalgebra::DVector::from_column_slice(self.i_kl[a][b]);
            }
        }
        inv.theta = nalgebra::Matrix3::from_fn(|a, b| self.theta[a][b]);
        inv.m_ff = square(self.m_ff);
        inv.k_ff = square(self.k_ff);
        Ok(ModalData {
            invariants: inv,
            phi: DMatrix::from_row_slice(nf, k, self.phi),
            stiffening: self.stiffening,
            damping: self.damping.map(square),
            labels: self.labels.iter().map(|l| l.to_string()).collect(),
            description: self.description.to_string(),
        })
    }
}

/// A flexible body reduced to modes (see the module documentation).
pub struct ModalBody {
    inner: Box<dyn Body>,
    data: ModalData,
    layout: BodyLayout,
    /// The equations of the projected invariants, with `∂U_nl/∂η`.
    terms: InertiaTerms,
    /// Generated kernels of the same equations, used in place of `terms`
    /// ([`ModalBody::with_kernels`]).
    kernels: Option<Box<dyn ModalKernels>>,
    /// `0, 1, …, k − 1`: the modes are the body's coordinates.
    identity: Vec<usize>,
    /// `Φ` row-major (row `i`, the modes' values at coordinate `i`,
    /// contiguous), for the tangent's `K_t Φ` and `Φᵀ (K_t Φ)`.
    phi_rows: Vec<f64>,
    /// The stiffening through the full body's element scalars, when its
    /// kernels have them ([`ScalarMaps`]); otherwise [`Body::elastic_force`]
    /// at `Φ η`, projected.
    scalars: Option<ScalarMaps>,
}

/// Each element's scalars as linear forms in the modes, `z_e = Z_e η` with
/// `Z_e = S_e Φ_e` (`docs/theory.md`, "Modal bodies"). The modes are
/// taken in an order that groups them by the scalars they reach (`perm`;
/// e.g. a straight beam's axial modes reach only the axial slope, its
/// bending modes only the bending slopes, as the modes are exactly zero
/// outside their group), so that scalar `j` of every element reads one
/// contiguous range of the permuted modes, `lo[j]..lo[j] + len[j]`. Scalar
/// `j`'s rows of all elements are stored as one matrix, column-major
/// (elements × `len[j]`): the scalars of all elements are then a few
/// matrix–vector products with unit stride, and so are their forces.
#[derive(Clone, Debug)]
struct ScalarMaps {
    layout: ScalarLayout,
    /// `perm[p]`: the mode at permuted position `p`.
    perm: Vec<usize>,
    lo: Vec<usize>,
    len: Vec<usize>,
    /// `cols[j][d E + e] = Z_e[j, perm[lo[j] + d]]`, `E` elements.
    cols: Vec<Vec<f64>>,
}

impl ScalarMaps {
    /// The maps of `inner`'s element scalars through `phi` (`None`: the
    /// body has no element scalars). Allocates; at construction only.
    fn new(inner: &dyn Body, phi: &DMatrix<f64>) -> Option<Self> {
        let layout = inner.scalar_layout()?;
        let (n, k) = phi.shape();
        let (ne, nz) = (layout.elements, layout.scalars);
        let mut w = inner.work();
        let mut z = vec![0.0; layout.local];
        let mut g = vec![0.0; layout.local];
        let mut h = vec![0.0; layout.local * layout.local];
        if !inner.scalar_derivatives(0, &z, &mut w, &mut g, Some(&mut h)) {
            return None;
        }
        // dense[(e n_z + j) k + c] = Z_e[j, c].
        let mut dense = vec![0.0; ne * nz * k];
        let mut col = vec![0.0; n];
        for c in 0..k {
            col.copy_from_slice(phi.column(c).as_slice());
            for e in 0..ne {
                z.iter_mut().for_each(|x| *x = 0.0);
                inner.element_scalars(e, &col, &mut w, &mut z);
                for j in 0..nz {
                    dense[(e * nz + j) * k + c] = z[j];
                }
            }
        }
        let reaches = |j: usize, c: usize| (0..ne).any(|e| dense[(e * nz + j) * k + c] != 0.0);
        // Each mode's signature, the scalars it reaches in any element;
        // modes sorted by signature (ties keep their order).
        let sigs: Vec<Vec<bool>> = (0..k)
            .map(|c| (0..nz).map(|j| reaches(j, c)).collect())
            .collect();
        let mut perm: Vec<usize> = (0..k).collect();
        perm.sort_by(|a, b| sigs[*b].cmp(&sigs[*a]).then(a.cmp(b)));
        let (mut lo, mut len, mut cols) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..nz {
            let used: Vec<usize> = (0..k).filter(|p| reaches(j, perm[*p])).collect();
            let (first, last) = match (used.first(), used.last()) {
                (Some(f), Some(l)) => (*f, *l + 1),
                _ => (0, 0),
            };
            let mut m = Vec::with_capacity((last - first) * ne);
            for p in first..last {
                m.extend((0..ne).map(|e| dense[(e * nz + j) * k + perm[p]]));
            }
            lo.push(first);
            len.push(last - first);
            cols.push(m);
        }
        Some(Self {
            layout,
            perm,
            lo,
            len,
            cols,
        })
    }

    /// Scratch after the full-elastic part: `z`, `g`, `h`, `η` and `f`
    /// permuted, one row of `H Z_e`, the tangent's accumulator, the
    /// scalars of all elements and their forces.
    fn work_len(&self, k: usize) -> usize {
        let l = self.layout.local;
        2 * l + l * l + 3 * k + k * k + 2 * self.layout.scalars * self.layout.elements
    }
}

impl std::fmt::Debug for ModalBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModalBody")
            .field("layout", &self.layout)
            .field("modes", &self.data.labels)
            .field("generated_kernels", &self.kernels.is_some())
            .finish()
    }
}

impl ModalBody {
    /// A modal body from its data; `inner` is the full body (its point
    /// shapes, times `Φ`, place markers). Checks the sizes, that every
    /// number is finite, `m_ff` symmetric positive definite, `K_ff` and the
    /// damping symmetric.
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
        let inv = &data.invariants;
        let finite = |xs: &[f64]| xs.iter().all(|x| x.is_finite());
        let mut ok = finite(&[inv.mass])
            && finite(inv.s_t0.as_slice())
            && finite(inv.s_bar.as_slice())
            && finite(inv.theta.as_slice())
            && finite(inv.m_ff.as_slice())
            && finite(inv.k_ff.as_slice())
            && finite(data.phi.as_slice());
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
        let terms = InertiaTerms::new(data.invariants.clone(), !data.stiffening, planar);
        let scalars = if data.stiffening {
            ScalarMaps::new(&*inner, &data.phi)
        } else {
            None
        };
        Ok(Self {
            inner,
            layout,
            terms,
            kernels: None,
            identity: (0..k).collect(),
            phi_rows: data.phi.transpose().as_slice().to_vec(),
            scalars,
            data,
        })
    }

    /// [`ModalBody::new`] whose mass blocks, forces and tangent come from
    /// generated kernels of its inertia equations (`kernels`, e.g. the
    /// `{Type}ModalKernels` of `ffr emit --modes`) instead of the run-time
    /// equations; the stiffening, energy, point shapes and damping are
    /// [`ModalBody::new`]'s. An error if the kernels are not for this body's
    /// modes, scene or elastic model.
    pub fn with_kernels(
        inner: Box<dyn Body>,
        data: ModalData,
        kernels: Box<dyn ModalKernels>,
    ) -> Result<Self> {
        let mut body = Self::new(inner, data)?;
        let k = body.layout.nf;
        if kernels.modes() != k
            || kernels.scene_dim() != body.layout.scene_dim
            || kernels.linear_elastic() == body.data.stiffening
        {
            return Err(Error::InvalidInput(format!(
                "modal body: kernels for {} modes, scene dimension {}, linear elastic force {}; the body has {k} modes, scene dimension {}, stiffening {}",
                kernels.modes(),
                kernels.scene_dim(),
                kernels.linear_elastic(),
                body.layout.scene_dim,
                body.data.stiffening
            )));
        }
        body.kernels = Some(kernels);
        Ok(body)
    }

    /// Whether the inertia equations run through generated kernels
    /// ([`ModalBody::with_kernels`]) rather than the run-time equations.
    pub fn uses_generated_kernels(&self) -> bool {
        self.kernels.is_some()
    }

    /// Length of the work buffer the stiffening uses (at its start).
    fn stiffening_len(&self) -> usize {
        if !self.data.stiffening {
            return 0;
        }
        let n = self.inner.layout().nf;
        let k = self.layout.nf;
        let scalars = self.scalars.as_ref().map_or(0, |s| s.work_len(k));
        n * (2 + k) + k * k + scalars
    }

    /// The generated kernels and their work (a `k × k` block, then the
    /// kernels' scratch) after the stiffening's: `None` without kernels, or
    /// when `w` is not this body's work (the run-time equations then serve).
    fn kernel_work<'a>(
        &'a self,
        w: &'a mut BodyWork,
    ) -> Option<(&'a dyn ModalKernels, &'a mut [f64], &'a mut [f64])> {
        let kern = self.kernels.as_deref()?;
        let k = self.layout.nf;
        let off = self.stiffening_len();
        let buf = w.buf.get_mut(off..off + k * k + kern.scratch())?;
        let (dense, scratch) = buf.split_at_mut(k * k);
        Some((kern, dense, scratch))
    }

    /// The data the body was made from.
    pub fn data(&self) -> &ModalData {
        &self.data
    }

    /// The full body the modes were taken from.
    pub fn full_body(&self) -> &dyn Body {
        &*self.inner
    }

    /// A point of the full body (its point shape) in the modes: `s Φ`, `ψ Φ`.
    fn project_point(&self, full: PointShape) -> PointShape {
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
        PointShape {
            u0: full.u0,
            entries,
        }
    }

    /// `q_f = Φ η` into `qf`.
    fn expand(&self, eta: &[f64], qf: &mut [f64]) {
        // Column by column (`Φ` is column-major: column m contiguous).
        let n = qf.len();
        let phi = self.data.phi.as_slice();
        qf.iter_mut().for_each(|x| *x = 0.0);
        for (m, e) in eta.iter().enumerate() {
            if *e != 0.0 {
                for (x, p) in qf.iter_mut().zip(&phi[m * n..(m + 1) * n]) {
                    *x += p * e;
                }
            }
        }
    }

    /// Adds the full body's elastic force at `q_f = Φ η`, projected, `Φᵀ
    /// f_el(Φ η)` (`f_el = K_ff q_f + ∇U_nl`: its element kernels at rest,
    /// `q̇_f = q̈_f = 0`, frame at rest), to `f`, and with `k_t` its tangent
    /// `Φᵀ K_t Φ` (`K_t = K_ff + ∇²U_nl`, banded) to `k_t`.
    fn full_elastic(
        &self,
        eta: &[f64],
        w: &mut BodyWork,
        f: &mut [f64],
        k_t: Option<&mut BandBuf>,
    ) {
        let n = self.inner.layout().nf;
        let k = self.layout.nf;
        let phi = &self.data.phi;
        let (qf, rest) = w.buf.split_at_mut(n);
        let (zeros, kphi) = rest.split_at_mut(n);
        self.expand(eta, qf);
        let iw = w
            .inner
            .as_mut()
            .expect("ModalBody::work gives the full body's scratch");
        let state = BodyState {
            q_f: qf,
            qd_f: zeros,
            qdd_f: zeros,
            frame: [0.0; 9],
        };
        match &k_t {
            None => {
                // The elastic force alone where the kernels have it, else
                // the full body's forces at rest (the same numbers).
                if !self
                    .inner
                    .elastic_force(qf, &mut iw.work, &mut iw.forces.f_f)
                {
                    self.inner
                        .forces(&state, false, &mut iw.work, &mut iw.forces)
                }
            }
            Some(_) => self.inner.tangent(
                &state,
                0.0,
                0.0,
                false,
                &mut iw.work,
                &mut iw.forces,
                &mut iw.tangent,
            ),
        }
        // Φᵀ f, column by column of Φ.
        for (a, fa) in f.iter_mut().enumerate() {
            *fa += dot_slices(&phi.as_slice()[a * n..(a + 1) * n], &iw.forces.f_f);
        }
        let Some(k_t) = k_t else { return };
        // K_t Φ (n × k, row-major): row i is Σ_j K_t[i, j] Φ[j, :] over
        // the band, each a contiguous row of Φ.
        let (kphi, acc) = kphi.split_at_mut(n * k);
        let band = &iw.tangent.k_ff;
        kphi.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..n {
            let (lo, r) = band.row(i);
            let out = &mut kphi[i * k..(i + 1) * k];
            for (d, kij) in r.iter().enumerate() {
                if *kij != 0.0 {
                    let phi_j = &self.phi_rows[(lo + d) * k..(lo + d + 1) * k];
                    for (o, p) in out.iter_mut().zip(phi_j) {
                        *o += kij * p;
                    }
                }
            }
        }
        // Φᵀ (K_t Φ) = Σ_i Φ[i, :]ᵀ (K_t Φ)[i, :], one rank-one update per
        // coordinate, on the upper triangle (row a from column a,
        // contiguous): K_t is symmetric (the elastic Hessian, each pair
        // computed once by the kernels), so the lower one is its mirror.
        acc.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..n {
            let phi_i = &self.phi_rows[i * k..(i + 1) * k];
            let kphi_i = &kphi[i * k..(i + 1) * k];
            for (a, pa) in phi_i.iter().enumerate() {
                if *pa != 0.0 {
                    for (o, kb) in acc[a * k + a..(a + 1) * k].iter_mut().zip(&kphi_i[a..]) {
                        *o += pa * kb;
                    }
                }
            }
        }
        for a in 0..k {
            k_t.add(a, a, acc[a * k + a]);
            for b in a + 1..k {
                let v = acc[a * k + b];
                k_t.add(a, b, v);
                k_t.add(b, a, v);
            }
        }
    }
}

impl ModalBody {
    /// Whether the stiffening runs through the full body's element scalars
    /// (`true`) or its elastic force at `Φ η` (`false`; also without
    /// stiffening).
    pub fn uses_element_scalars(&self) -> bool {
        self.scalars.is_some()
    }

    /// Adds the elastic force in the modes to `f`, and with `k_t` its
    /// tangent: `K̃ η + Σ_e Z_eᵀ ∂U_e/∂z (Z_e η)` and `K̃ + Σ_e Z_eᵀ
    /// ∂²U_e/∂z² Z_e`, `K̃ = Φᵀ K_ff Φ` (the same as `Φᵀ f_el(Φ η)` and
    /// `Φᵀ K_t Φ`: `U_nl = Σ_e U_e(S_e q_e)` with `q_e = Φ_e η`). The
    /// scalars of all elements by unit-stride matrix–vector products, one
    /// call of the generated `scalar_force` (`scalar_tangent`) per element,
    /// the forces back by the transposed products; no `q_f = Φ η`.
    fn scalar_elastic(
        &self,
        sm: &ScalarMaps,
        eta: &[f64],
        w: &mut BodyWork,
        f: &mut [f64],
        k_t: Option<&mut BandBuf>,
    ) {
        let k = self.layout.nf;
        let n = self.inner.layout().nf;
        let (l, nz, ne) = (sm.layout.local, sm.layout.scalars, sm.layout.elements);
        // K̃ η: K̃ symmetric, column a (contiguous) is row a.
        let kff = self.data.invariants.k_ff.as_slice();
        for (a, fa) in f.iter_mut().enumerate() {
            *fa += dot_slices(&kff[a * k..(a + 1) * k], eta);
        }
        let (_, rest) = w.buf.split_at_mut(n * (2 + k) + k * k);
        let (z, rest) = rest.split_at_mut(l);
        let (g, rest) = rest.split_at_mut(l);
        let (h, rest) = rest.split_at_mut(l * l);
        let (eta_p, rest) = rest.split_at_mut(k);
        let (f_p, rest) = rest.split_at_mut(k);
        let (t, rest) = rest.split_at_mut(k);
        let (acc, rest) = rest.split_at_mut(k * k);
        let (z_all, rest) = rest.split_at_mut(nz * ne);
        let g_all = &mut rest[..nz * ne];
        let iw = w
            .inner
            .as_mut()
            .expect("ModalBody::work gives the full body's scratch");
        for (p, &c) in sm.perm.iter().enumerate() {
            eta_p[p] = eta[c];
        }
        // z_all[j E + e] = Σ_d Z_e[j, lo_j + d] η_p[lo_j + d].
        z_all.iter_mut().for_each(|x| *x = 0.0);
        // Four modes per pass over `z_j` (the same sums in the same order
        // as one mode per pass, a quarter of the passes).
        for j in 0..nz {
            let zj = &mut z_all[j * ne..(j + 1) * ne];
            let x = &eta_p[sm.lo[j]..sm.lo[j] + sm.len[j]];
            let quads = sm.cols[j].chunks_exact(4 * ne);
            let rest = quads.remainder();
            for (m, x4) in quads.zip(x.chunks_exact(4)) {
                let (c0, m) = m.split_at(ne);
                let (c1, m) = m.split_at(ne);
                let (c2, c3) = m.split_at(ne);
                for ((((o, a), b), c), d) in zj.iter_mut().zip(c0).zip(c1).zip(c2).zip(c3) {
                    *o = *o + a * x4[0] + b * x4[1] + c * x4[2] + d * x4[3];
                }
            }
            let x = &x[x.len() - rest.len() / ne.max(1)..];
            for (col, &x) in rest.chunks_exact(ne).zip(x) {
                if x != 0.0 {
                    for (o, v) in zj.iter_mut().zip(col) {
                        *o += v * x;
                    }
                }
            }
        }
        let tangent = k_t.is_some();
        if tangent {
            acc.iter_mut().for_each(|x| *x = 0.0);
        }
        // Without the tangent, all elements in one call.
        let batched = !tangent && self.inner.scalar_forces(z_all, &mut iw.work, g_all);
        for e in (0..ne).filter(|_| !batched) {
            for j in 0..nz {
                z[j] = z_all[j * ne + e];
            }
            let ok = self.inner.scalar_derivatives(
                e,
                z,
                &mut iw.work,
                g,
                if tangent { Some(&mut *h) } else { None },
            );
            debug_assert!(ok, "the scalar kernels were checked at construction");
            for j in 0..nz {
                g_all[j * ne + e] = g[j];
            }
            if !tangent {
                continue;
            }
            // Z_eᵀ H Z_e: for each scalar j, t = Σ_i H_ji Z_e[i, :], then
            // the upper triangle gets Z_e[j, a] t[b], b ≥ a.
            for j in 0..nz {
                if sm.len[j] == 0 {
                    continue;
                }
                t.iter_mut().for_each(|x| *x = 0.0);
                for i in 0..nz {
                    let hji = h[j * l + i];
                    if hji != 0.0 {
                        for d in 0..sm.len[i] {
                            t[sm.lo[i] + d] += hji * sm.cols[i][d * ne + e];
                        }
                    }
                }
                for d in 0..sm.len[j] {
                    let zja = sm.cols[j][d * ne + e];
                    let a = sm.lo[j] + d;
                    if zja != 0.0 {
                        for (o, tb) in acc[a * k + a..(a + 1) * k].iter_mut().zip(&t[a..]) {
                            *o += zja * tb;
                        }
                    }
                }
            }
        }
        // f_p[lo_j + d] += Σ_e Z_e[j, lo_j + d] g_e[j].
        f_p.iter_mut().for_each(|x| *x = 0.0);
        for j in 0..nz {
            let gj = &g_all[j * ne..(j + 1) * ne];
            for (d, col) in sm.cols[j].chunks_exact(ne).enumerate() {
                f_p[sm.lo[j] + d] += dot_slices(col, gj);
            }
        }
        for (p, &c) in sm.perm.iter().enumerate() {
            f[c] += f_p[p];
        }
        let Some(k_t) = k_t else { return };
        for a in 0..k {
            let ca = sm.perm[a];
            k_t.add(ca, ca, acc[a * k + a] + kff[ca * k + ca]);
            for b in a + 1..k {
                let cb = sm.perm[b];
                let v = acc[a * k + b] + kff[ca * k + cb];
                k_t.add(ca, cb, v);
                k_t.add(cb, ca, v);
            }
        }
    }

    /// The elastic force (and tangent) of a stiffened modal body, by the
    /// element scalars when available.
    fn stiffening(&self, eta: &[f64], w: &mut BodyWork, f: &mut [f64], k_t: Option<&mut BandBuf>) {
        match &self.scalars {
            Some(sm) => self.scalar_elastic(sm, eta, w, f, k_t),
            None => self.full_elastic(eta, w, f, k_t),
        }
    }
}

impl Body for ModalBody {
    fn layout(&self) -> &BodyLayout {
        &self.layout
    }

    fn work(&self) -> BodyWork {
        // The generated kernels' dense block and scratch, after the
        // stiffening's work.
        let k = self.layout.nf;
        let kernels = self
            .kernels
            .as_ref()
            .map_or(0, |kern| k * k + kern.scratch());
        if !self.data.stiffening {
            return BodyWork {
                buf: vec![0.0; kernels],
                inner: None,
            };
        }
        // q_f = Φ η, zero velocities and accelerations, K_t Φ, Φᵀ K_t Φ.
        let (n, hb) = (self.inner.layout().nf, self.inner.layout().half_bandwidth);
        BodyWork {
            buf: vec![0.0; self.stiffening_len() + kernels],
            inner: Some(Box::new(InnerWork {
                work: self.inner.work(),
                forces: BodyForces::zeros(n),
                tangent: BodyTangent::zeros(n, hb),
            })),
        }
    }

    fn forces(&self, state: &BodyState, frame_rows: bool, w: &mut BodyWork, out: &mut BodyForces) {
        out.clear();
        if let Some((kern, _, scratch)) = self.kernel_work(w) {
            let x = kernel_input(state);
            if frame_rows {
                let mut r = ResidualOut {
                    f_r: &mut out.f_r,
                    f_th: &mut out.f_th,
                    f_e: &mut out.f_f,
                };
                kern.residual(&x, &mut r, scratch);
            } else {
                kern.residual_elastic(&x, &mut out.f_f, scratch);
            }
        } else {
            self.terms
                .add_forces(&Inputs::of(state), frame_rows, &self.identity, out);
        }
        if self.data.stiffening {
            self.stiffening(state.q_f, w, &mut out.f_f, None);
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
        out.clear();
        t.clear();
        if let Some((kern, k_ee, scratch)) = self.kernel_work(w) {
            let x = kernel_input(state);
            k_ee.iter_mut().for_each(|v| *v = 0.0);
            if frame_rows {
                let mut o = TangentOut {
                    f_r: &mut out.f_r,
                    f_th: &mut out.f_th,
                    f_e: &mut out.f_f,
                    k_ee: &mut *k_ee,
                    d_e_frame: &mut t.d_f_frame,
                    k_ref_e: &mut t.k_ref_f,
                    d_ref_frame: &mut t.d_ref_frame,
                };
                kern.tangent(&x, bp, gp, &mut o, scratch);
            } else {
                kern.tangent_elastic(&x, bp, gp, &mut out.f_f, k_ee, scratch);
            }
            add_dense(&mut t.k_ff, k_ee, self.layout.nf);
        } else {
            let x = Inputs::of(state);
            self.terms.add_forces(&x, frame_rows, &self.identity, out);
            self.terms
                .add_tangent(&x, bp, gp, frame_rows, &self.identity, t);
        }
        if self.data.stiffening {
            self.stiffening(state.q_f, w, &mut out.f_f, Some(&mut t.k_ff));
        }
    }

    fn mass(&self, q_f: &[f64], w: &mut BodyWork, out: &mut BodyMass) {
        out.clear();
        let Some((kern, m_ee, scratch)) = self.kernel_work(w) else {
            self.terms.add_mass(q_f, &self.identity, out);
            return;
        };
        m_ee.iter_mut().for_each(|v| *v = 0.0);
        let mut o = MassOut {
            s_t: &mut out.s_t,
            m_ee: &mut *m_ee,
            m_e_frame: &mut out.m_f_frame,
            m_ref_e: &mut out.m_ref_f,
            m_ref_frame: &mut out.m_ref_frame,
        };
        kern.mass(q_f, &mut o, scratch);
        add_dense(&mut out.m_ff, m_ee, self.layout.nf);
    }

    fn elastic_energy(&self, q_f: &[f64], w: &mut BodyWork) -> f64 {
        if !self.data.stiffening {
            let k_ff = &self.data.invariants.k_ff;
            return 0.5 * bilinear(k_ff, q_f, q_f);
        }
        let n = self.inner.layout().nf;
        let (qf, _) = w.buf.split_at_mut(n);
        self.expand(q_f, qf);
        let iw = w
            .inner
            .as_mut()
            .expect("ModalBody::work gives the full body's scratch");
        self.inner.elastic_energy(qf, &mut iw.work)
    }

    fn invariants(&self) -> Invariants {
        self.data.invariants.clone()
    }

    fn point_shape(&self, x: f64) -> Result<PointShape> {
        Ok(self.project_point(self.inner.point_shape(x)?))
    }

    fn node_count(&self) -> usize {
        self.inner.node_count()
    }

    fn node_shape(&self, node: usize) -> Result<PointShape> {
        Ok(self.project_point(self.inner.node_shape(node)?))
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

/// The kernel input of a body state (the modes are the coordinates).
fn kernel_input<'a>(state: &'a BodyState<'a>) -> KernelInput<'a> {
    KernelInput {
        x0: 0.0,
        q: state.q_f,
        qd: state.qd_f,
        qdd: state.qdd_f,
        frame: &state.frame,
    }
}

/// Adds a dense row-major `k × k` matrix to a band of half-bandwidth `k − 1`.
fn add_dense(band: &mut BandBuf, m: &[f64], k: usize) {
    for (a, row) in m.chunks_exact(k).enumerate() {
        for (b, v) in row.iter().enumerate() {
            if *v != 0.0 {
                band.add(a, b, *v);
            }
        }
    }
}
