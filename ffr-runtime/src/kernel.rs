//! Element kernels: what generated code (or a tape of the same programs)
//! provides for one element of a flexible body, in body axes.
//!
//! With the element's coordinates `q` (`n_e` of them), its offset `x₀` along
//! body x and the frame motion `frame = [ā, α, ω]` (`ā = Aᵀ(R̈ − g)`,
//! `α = ω̄̇`, `ω = ω̄`, body axes), an element contributes the generalized
//! inertia and elastic forces (theory: `docs/theory.md`, "Equations of motion
//! in body axes")
//!
//! - `f_r = m ā − S̃_t α + S̄ q̈ + ω̃² S_t + 2 ω̃ S̄ q̇`
//! - `f_θ = S̃_t ā + Ī_θθ α + Ī_θf q̈ + ω̃ Ī_θθ ω + 2 (tr P ω − Pᵀ ω)`
//! - `f_e = S̄ᵀ ā + Ī_θfᵀ α + m_ff q̈ + h_e(q, q̇, ω) + K q + ∂U_nl/∂q`
//!
//! and the derivatives a Newton iteration needs. All matrices are row-major
//! slices; outputs not written by a kernel are structurally zero, so callers
//! clear their buffers before a call.

use ffr_spec::{ElementCoordinate, KernelOptions, Param, Params, Reference, SectionProp};
use std::borrow::Cow;

/// What a set of element kernels was generated for.
#[derive(Clone, Debug, PartialEq)]
pub struct KernelInfo {
    /// Shape name.
    pub shape: Cow<'static, str>,
    /// Shape dimension: 2 (planar, x–y) or 3.
    pub dim: usize,
    /// Element coordinates `n_e`.
    pub n_local: usize,
    /// The element's coordinates (node 0/1 and kind), in kernel order.
    pub coordinates: Cow<'static, [ElementCoordinate]>,
    /// The options the kernels were generated for, the scene resolved
    /// (`Some`). Without a free frame the reference rows (`residual`,
    /// `tangent`) do not exist and only a body whose frame motion is
    /// prescribed can use the kernels; at rest (`ā ≡ 0`) the kernels ignore
    /// `ā`, so the system refuses them where `ā` can be non-zero.
    pub options: KernelOptions,
    /// Length of the coefficient array.
    pub n_coefficients: usize,
    /// Parameters the kernels read (besides the derived element length).
    pub params_used: Cow<'static, [Param]>,
    /// Scratch space (f64 values) a call needs from its caller (0 for
    /// compiled kernels; registers of a tape).
    pub scratch: usize,
}

impl KernelInfo {
    /// Scene dimension the kernels were generated for: 2 (frame motion in
    /// the x–y plane) or 3.
    pub fn scene_dim(&self) -> usize {
        self.options.scene_or(self.dim).dim()
    }

    /// Whether the reference rows (`residual`, `tangent`) exist.
    pub fn free_frame(&self) -> bool {
        self.options.frame.is_free()
    }

    /// Whether the kernels were generated for `ā ≡ 0`.
    pub fn zero_frame_acceleration(&self) -> bool {
        self.options.frame.zero_frame_acceleration()
    }
}

/// Inputs of a residual or tangent kernel.
#[derive(Clone, Copy, Debug)]
pub struct KernelInput<'a> {
    /// Element offset `x₀` along body x.
    pub x0: f64,
    /// Element coordinates.
    pub q: &'a [f64],
    /// Their velocities.
    pub qd: &'a [f64],
    /// Their accelerations.
    pub qdd: &'a [f64],
    /// `[ā, α, ω]` in body axes.
    pub frame: &'a [f64; 9],
}

/// Outputs of `residual`.
#[derive(Debug)]
pub struct ResidualOut<'a> {
    /// `f_r` (3).
    pub f_r: &'a mut [f64; 3],
    /// `f_θ` (3).
    pub f_th: &'a mut [f64; 3],
    /// `f_e` (`n_e`).
    pub f_e: &'a mut [f64],
}

/// Outputs of `tangent` (with `β'`, `γ'` the generalized-α factors
/// `∂q̈/∂q`, `∂q̇/∂q`).
#[derive(Debug)]
pub struct TangentOut<'a> {
    /// `f_r` (3).
    pub f_r: &'a mut [f64; 3],
    /// `f_θ` (3).
    pub f_th: &'a mut [f64; 3],
    /// `f_e` (`n_e`).
    pub f_e: &'a mut [f64],
    /// `β' ∂f_e/∂q̈ + γ' ∂f_e/∂q̇ + ∂f_e/∂q` (`n_e × n_e`).
    pub k_ee: &'a mut [f64],
    /// `∂f_e/∂[ā, α, ω]` (`n_e × 9`).
    pub d_e_frame: &'a mut [f64],
    /// `β' ∂f/∂q̈ + γ' ∂f/∂q̇ + ∂f/∂q` of `[f_r; f_θ]` (`6 × n_e`).
    pub k_ref_e: &'a mut [f64],
    /// `∂[f_r; f_θ]/∂[ā, α, ω]` (`6 × 9`).
    pub d_ref_frame: &'a mut [f64],
}

/// Outputs of `mass`: `S_t` and the acceleration-linear blocks.
#[derive(Debug)]
pub struct MassOut<'a> {
    /// `S_t = S_t0 + S̄ q` (3).
    pub s_t: &'a mut [f64; 3],
    /// `m_ff` (`n_e × n_e`).
    pub m_ee: &'a mut [f64],
    /// `∂f_e/∂[ā, α]` = `[S̄ᵀ, Ī_θfᵀ]` (`n_e × 6`).
    pub m_e_frame: &'a mut [f64],
    /// `∂[f_r; f_θ]/∂q̈` = `[S̄; Ī_θf]` (`6 × n_e`).
    pub m_ref_e: &'a mut [f64],
    /// `∂[f_r; f_θ]/∂[ā, α]` = `[m I, −S̃_t; S̃_t, Ī_θθ]` (`6 × 6`).
    pub m_ref_frame: &'a mut [f64],
}

/// The element kernels of a flexible body (generated code, or tapes of the
/// same programs): `info` and one method per [`KernelKind`](ffr_spec::KernelKind),
/// in its order. Object safe.
pub trait ElementKernels: Send + Sync {
    /// What the kernels were generated for.
    fn info(&self) -> &KernelInfo;

    /// The coefficients `c` (length `info().n_coefficients`) for parameter
    /// values `params` and element length `l = L/N`.
    fn coefficients(&self, params: &Params, l: f64, c: &mut [f64]);

    /// The element moments `μ_{P,k} = ∫₀¹ P(ξ) ξ^k dξ` of the section
    /// properties that [`ElementKernels::section_coefficients`] reads, in
    /// the order of its `mu` (see `ffr_spec::element_moments`). Empty for
    /// kernels of a uniform section, which take their coefficients from the
    /// body's parameters only.
    fn section_moments(&self) -> &[(SectionProp, u8)] {
        &[]
    }

    /// The coefficients `c` (length `info().n_coefficients`) of one element
    /// of a varying section, from its moments `mu` (in the order of
    /// [`ElementKernels::section_moments`]) and its length `l` (only for
    /// kernels with a non-empty `section_moments`; `coefficients` gives the
    /// same kernels' coefficients for a uniform body).
    fn section_coefficients(&self, mu: &[f64], l: f64, c: &mut [f64]) {
        let _ = (mu, l, c);
        unreachable!(
            "kernels of `{}` were generated for a uniform section: no section_coefficients (use coefficients)",
            self.info().shape
        )
    }

    /// `S_t` and the acceleration-linear blocks at `q`.
    fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut MassOut, scratch: &mut [f64]);

    /// `f_r`, `f_θ`, `f_e` (only with `info().free_frame()`).
    fn residual(&self, c: &[f64], x: &KernelInput, out: &mut ResidualOut, scratch: &mut [f64]) {
        let _ = (c, x, out, scratch);
        unreachable!("kernels of `{}` were generated without the reference rows (prescribed frame motion only)", self.info().shape)
    }

    /// The residual and its derivatives (only with `info().free_frame()`).
    fn tangent(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        out: &mut TangentOut,
        scratch: &mut [f64],
    ) {
        let _ = (c, x, bp, gp, out, scratch);
        unreachable!("kernels of `{}` were generated without the reference rows (prescribed frame motion only)", self.info().shape)
    }

    /// `f_e` only (frame motion prescribed).
    fn residual_elastic(&self, c: &[f64], x: &KernelInput, f_e: &mut [f64], scratch: &mut [f64]);

    /// `f_e` and `β' ∂f_e/∂q̈ + γ' ∂f_e/∂q̇ + ∂f_e/∂q` (frame motion prescribed).
    // The generated signature: inputs, the two Newton factors, two outputs
    // and the caller's scratch (CasADi style), like `tangent`.
    #[allow(clippy::too_many_arguments)]
    fn tangent_elastic(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        f_e: &mut [f64],
        k_ee: &mut [f64],
        scratch: &mut [f64],
    );

    /// Elastic energy `½ qᵀ K q + U_nl(q)` of the element.
    fn energy(&self, c: &[f64], q: &[f64], scratch: &mut [f64]) -> f64;

    /// The element's invariants at offset `x₀`, flat:
    /// `[m, S_t0 (3), S̄ (3 n), S̄_kl (9 n², k, l, a, b), Ī_kl (9 n, k, l, a),
    /// Θ_kl (9), m_ff (n²), K_ff (n²)]`.
    fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], scratch: &mut [f64]);

    /// `S(ξ)` (3 × n) and the section rotation `ψ(ξ) = ½ ∇ × u` (3 × n) on
    /// the element's centre line.
    fn point_shape(&self, c: &[f64], xi: f64, s: &mut [f64], psi: &mut [f64], scratch: &mut [f64]);

    /// The elastic force alone, `f_e = K_e q + ∇U_nl(q)`: writes its
    /// non-zero entries, as `residual_elastic` does (zero `f_e` first).
    /// `false` (and `f_e` untouched) when the kernels were generated without
    /// it (models without stiffening, whose elastic force is `K_e q`): the
    /// caller then evaluates `residual_elastic` at rest.
    fn force_elastic(&self, c: &[f64], q: &[f64], f_e: &mut [f64], scratch: &mut [f64]) -> bool {
        let _ = (c, q, f_e, scratch);
        false
    }

    /// The element scalars of the stiffening energy, `z = S q` (linear
    /// forms in the element coordinates: the slopes' coefficients,
    /// `docs/theory.md` "Geometric stiffening"), into `z[..n_z]` (`z` has
    /// `n` entries); returns `n_z`. `0` (and `z` untouched) when the kernels
    /// were generated without them (no stiffening).
    fn elastic_scalars(&self, c: &[f64], q: &[f64], z: &mut [f64], scratch: &mut [f64]) -> usize {
        let _ = (c, q, z, scratch);
        0
    }

    /// `g = ∂U_nl/∂z` at the element scalars `z` (`n` entries each, the
    /// first `n_z` used; writes the non-zero entries of `g`, zero it
    /// first). `false` when not generated.
    fn scalar_force(&self, c: &[f64], z: &[f64], g: &mut [f64], scratch: &mut [f64]) -> bool {
        let _ = (c, z, g, scratch);
        false
    }

    /// [`ElementKernels::scalar_force`] of `elements` elements in one call:
    /// `g_all[j E + e] = ∂U_nl/∂z_j` at `z_all[j E + e]` (`E = elements`,
    /// scalar `j` of every element contiguous; `g_all` overwritten, `n_z E`
    /// entries each), element `e`'s coefficients at `c[e c_stride..]`
    /// (`c_stride = 0`: one set for every element). `false` when not
    /// generated or the sizes disagree. The default calls `scalar_force` per
    /// element, its `z` and `g` in the first `2 n` entries of `scratch`
    /// (the rest passed on); generated kernels override it with the loop
    /// inside, the coefficients read once when shared.
    fn scalar_force_batch(
        &self,
        c: &[f64],
        c_stride: usize,
        z_all: &[f64],
        g_all: &mut [f64],
        elements: usize,
        scratch: &mut [f64],
    ) -> bool {
        let n = self.info().n_local;
        let nc = self.info().n_coefficients;
        if elements == 0 || scratch.len() < 2 * n {
            return elements == 0 && z_all.is_empty() && g_all.is_empty();
        }
        let nz = z_all.len() / elements;
        let fits = (elements - 1)
            .checked_mul(c_stride)
            .and_then(|x| x.checked_add(nc))
            .is_some_and(|len| len <= c.len());
        let strided = c_stride == 0 || c_stride >= nc;
        if nz > n || z_all.len() != nz * elements || g_all.len() != z_all.len() || !fits || !strided
        {
            return false;
        }
        let (z, rest) = scratch.split_at_mut(n);
        let (g, rest) = rest.split_at_mut(n);
        for e in 0..elements {
            for j in 0..nz {
                z[j] = z_all[j * elements + e];
            }
            g.iter_mut().for_each(|x| *x = 0.0);
            if !self.scalar_force(&c[e * c_stride..e * c_stride + nc], z, g, rest) {
                return false;
            }
            for j in 0..nz {
                g_all[j * elements + e] = g[j];
            }
        }
        true
    }

    /// `g = ∂U_nl/∂z` and `h = ∂²U_nl/∂z²` (row-major with stride `n`,
    /// symmetric) at `z`; writes the non-zero entries (zero both first).
    /// `false` when not generated.
    fn scalar_tangent(
        &self,
        c: &[f64],
        z: &[f64],
        g: &mut [f64],
        h: &mut [f64],
        scratch: &mut [f64],
    ) -> bool {
        let _ = (c, z, g, h, scratch);
        false
    }
}

/// A body generated with a fixed mesh (`#[flex_body]`, `Builder::body`):
/// its kernels, element count and reference condition are known at compile
/// time; the parameter values are the struct's fields.
pub trait CompiledBody {
    /// The element kernels.
    type Kernels: ElementKernels + Default + 'static;
    /// Number of elements.
    const ELEMENTS: usize;
    /// Reference condition.
    const REFERENCE: Reference;
    /// Number of elastic coordinates.
    const NF: usize;
    /// Shape dimension.
    const DIM: usize;
    /// A label per elastic coordinate (`kind_node`).
    const DOFS: &'static [&'static str];
    /// The parameter values (unused parameters are 0).
    fn params(&self) -> Params;
    /// Sections that vary along the span (`#[flex_body(sections = …)]`,
    /// `BodyConfig::sections`): the stations of the table, baked into the
    /// type, for kernels generated for varying sections; `None` (the
    /// default): the uniform section of [`CompiledBody::params`].
    const SECTIONS: Option<&'static [ffr_spec::scene::Station]> = None;
}

pub use ffr_spec::invariant_layout;

/// Implement [`ElementKernels`] for a wrapper by forwarding every method to
/// the kernels `$dispatch!(self, k => k.method(…))` selects: a `match` over
/// an enum's variants, or a dereference. One list of the trait's methods for
/// every wrapper (boxes, the `ffr` crate's built-in and compiled-or-tape
/// enums). `[$gen]` are the impl's generic parameters (may be empty).
#[macro_export]
macro_rules! forward_element_kernels {
    ([$($gen:tt)*] $ty:ty, $dispatch:ident) => {
        impl<$($gen)*> $crate::ElementKernels for $ty {
            fn info(&self) -> &$crate::KernelInfo {
                $dispatch!(self, k => k.info())
            }
            fn coefficients(&self, params: &$crate::spec::Params, l: f64, c: &mut [f64]) {
                $dispatch!(self, k => k.coefficients(params, l, c))
            }
            fn section_moments(&self) -> &[($crate::spec::SectionProp, u8)] {
                $dispatch!(self, k => k.section_moments())
            }
            fn section_coefficients(&self, mu: &[f64], l: f64, c: &mut [f64]) {
                $dispatch!(self, k => k.section_coefficients(mu, l, c))
            }
            fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut $crate::MassOut, s: &mut [f64]) {
                $dispatch!(self, k => k.mass(c, x0, q, out, s))
            }
            fn residual(
                &self,
                c: &[f64],
                x: &$crate::KernelInput,
                out: &mut $crate::ResidualOut,
                s: &mut [f64],
            ) {
                $dispatch!(self, k => k.residual(c, x, out, s))
            }
            fn tangent(
                &self,
                c: &[f64],
                x: &$crate::KernelInput,
                bp: f64,
                gp: f64,
                out: &mut $crate::TangentOut,
                s: &mut [f64],
            ) {
                $dispatch!(self, k => k.tangent(c, x, bp, gp, out, s))
            }
            fn residual_elastic(&self, c: &[f64], x: &$crate::KernelInput, f_e: &mut [f64], s: &mut [f64]) {
                $dispatch!(self, k => k.residual_elastic(c, x, f_e, s))
            }
            fn tangent_elastic(
                &self,
                c: &[f64],
                x: &$crate::KernelInput,
                bp: f64,
                gp: f64,
                f_e: &mut [f64],
                k_ee: &mut [f64],
                s: &mut [f64],
            ) {
                $dispatch!(self, k => k.tangent_elastic(c, x, bp, gp, f_e, k_ee, s))
            }
            fn energy(&self, c: &[f64], q: &[f64], s: &mut [f64]) -> f64 {
                $dispatch!(self, k => k.energy(c, q, s))
            }
            fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], s: &mut [f64]) {
                $dispatch!(self, k => k.element_invariants(c, x0, out, s))
            }
            fn point_shape(&self, c: &[f64], xi: f64, sh: &mut [f64], psi: &mut [f64], s: &mut [f64]) {
                $dispatch!(self, k => k.point_shape(c, xi, sh, psi, s))
            }
            fn force_elastic(&self, c: &[f64], q: &[f64], f_e: &mut [f64], s: &mut [f64]) -> bool {
                $dispatch!(self, k => k.force_elastic(c, q, f_e, s))
            }
            fn elastic_scalars(&self, c: &[f64], q: &[f64], z: &mut [f64], s: &mut [f64]) -> usize {
                $dispatch!(self, k => k.elastic_scalars(c, q, z, s))
            }
            fn scalar_force(&self, c: &[f64], z: &[f64], g: &mut [f64], s: &mut [f64]) -> bool {
                $dispatch!(self, k => k.scalar_force(c, z, g, s))
            }
            fn scalar_tangent(
                &self,
                c: &[f64],
                z: &[f64],
                g: &mut [f64],
                h: &mut [f64],
                s: &mut [f64],
            ) -> bool {
                $dispatch!(self, k => k.scalar_tangent(c, z, g, h, s))
            }
            fn scalar_force_batch(
                &self,
                c: &[f64],
                c_stride: usize,
                z_all: &[f64],
                g_all: &mut [f64],
                elements: usize,
                s: &mut [f64],
            ) -> bool {
                $dispatch!(self, k => k.scalar_force_batch(c, c_stride, z_all, g_all, elements, s))
            }
        }
    };
}

/// `{ let k = &**self; e }`: the dispatch of a box.
macro_rules! deref_dispatch {
    ($self:ident, $k:ident => $e:expr) => {{
        let $k = &**$self;
        $e
    }};
}

forward_element_kernels!([K: ElementKernels + ?Sized] Box<K>, deref_dispatch);
