//! A flexible body assembled from element kernels: `N` elements of a shape
//! (equal, or between given nodes: a graded mesh; element count, reference
//! condition and parameters chosen at run time), or a single "element"
//! holding all coordinates (modal bodies).
//!
//! Every evaluation loops over the elements: gather the element's
//! coordinates through its dof map (removed coordinates read as zero), call
//! the kernel, scatter-add its outputs. Matrices built from element matrices
//! are banded with the mesh's half-bandwidth.

use crate::attached::Attachment;
use crate::body::{
    Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork, Invariants,
    PointShape, ScalarLayout,
};
use crate::error::{Error, Result};
use crate::kernel::{
    invariant_layout, CompiledBody, ElementKernels, KernelInput, MassOut, ResidualOut, TangentOut,
};
use ffr_spec::scene::Station;
use ffr_spec::text::Num;
use ffr_spec::{AttachedMass, Mesh, Params, Reference, SectionProp};

const REMOVED: usize = usize::MAX;

/// A body made of element kernels `K`.
#[derive(Clone, Debug)]
pub struct KernelBody<K> {
    kernels: K,
    layout: BodyLayout,
    params: Params,
    /// The coefficient arrays: one shared by every element of an equal
    /// mesh (`coef_stride = 0`), or one per element (`coef_stride` each).
    coef: Vec<f64>,
    coef_stride: usize,
    elements: usize,
    ne: usize,
    /// `elements × n_e` body indices (`REMOVED` where a coordinate is removed).
    maps: Vec<usize>,
    /// The nodes `x_0 = 0 < x_1 < … < x_N = L`; element `e` starts at
    /// `x0[e]` and has length `lengths[e]`.
    x0: Vec<f64>,
    lengths: Vec<f64>,
    /// Masses attached on the axis ([`KernelBody::with_masses`]).
    attached: Vec<Attachment>,
}

/// [`ffr_spec::check_nodes`] as the runtime's error.
fn check_nodes(nodes: &[f64], length: f64) -> Result<()> {
    ffr_spec::check_nodes(nodes, length).map_err(|e| Error::InvalidInput(e.to_string()))
}

/// Offsets of the scratch regions of one element evaluation.
struct Scratch {
    ne: usize,
    kernel: usize,
}

impl Scratch {
    fn len(&self) -> usize {
        kernel_scratch_at(self.ne) + self.kernel
    }
}

/// Where the kernels' own scratch starts in a [`KernelBody`]'s work buffer
/// (after `q, q̇, q̈, f_e, K_ee` and the frame blocks).
const fn kernel_scratch_at(n: usize) -> usize {
    4 * n + n * n + 9 * n + 6 * n + 54 + 6
}

impl<K: ElementKernels> KernelBody<K> {
    /// `elements` equal elements of the kernels' shape from `x = 0` to
    /// `params.length`, with reference condition `reference`.
    pub fn new(kernels: K, params: Params, elements: usize, reference: Reference) -> Result<Self> {
        let l = params.elem_length(elements);
        let x0: Vec<f64> = (0..elements).map(|e| e as f64 * l).collect();
        Self::build(kernels, params, x0, vec![l; elements], true, reference)
    }

    /// A graded mesh: elements between `nodes` (`x = 0` first, `x = L =
    /// params.length` last, strictly increasing, finite), with reference
    /// condition `reference`. Each element reads coefficients for its own
    /// length. Nodes exactly at `x_e = e·(L/N)` (as f64) give the body
    /// [`KernelBody::new`] builds with `N` elements, bit for bit.
    pub fn with_nodes(
        kernels: K,
        params: Params,
        nodes: &[f64],
        reference: Reference,
    ) -> Result<Self> {
        check_nodes(nodes, params.length)?;
        let n = nodes.len();
        // Nodes exactly at `e·L/N`: the equal mesh, as `new` builds it.
        let elements = n - 1;
        let l = params.elem_length(elements);
        if nodes
            .iter()
            .enumerate()
            .all(|(e, x)| *x == e as f64 * l || e == elements)
        {
            return Self::new(kernels, params, elements, reference);
        }
        let x0 = nodes[..elements].to_vec();
        let lengths: Vec<f64> = nodes.windows(2).map(|w| w[1] - w[0]).collect();
        Self::build(kernels, params, x0, lengths, false, reference)
    }

    /// A body whose section varies along the span: `stations` from `x = 0`
    /// to the body's length (every quantity linear in x between stations;
    /// the principal-axis stiffnesses and mass moments turned by each
    /// station's twist into body axes, `EI_y = ei_y cos²θ + ei_z sin²θ`,
    /// `EI_z = ei_y sin²θ + ei_z cos²θ`, `EI_yz = (ei_z − ei_y) sinθ cosθ`,
    /// and the same for `ρI`), on `elements` equal elements or between
    /// `nodes`. Each element reads coefficients from the exact moments
    /// `μ_{P,k} = ∫₀¹ P ξ^k dξ` of its piece of the table
    /// (`ffr_spec::element_moments`, split at the stations inside it); the
    /// kernels must be generated for varying sections.
    pub fn with_sections(
        kernels: K,
        stations: &[Station],
        elements: usize,
        nodes: Option<&[f64]>,
        reference: Reference,
    ) -> Result<Self> {
        let bad = |m: String| Error::InvalidInput(m);
        if stations.len() < 2 {
            return Err(bad(format!(
                "a section table needs at least two stations, found {}",
                stations.len()
            )));
        }
        let length = stations[stations.len() - 1].x;
        if stations[0].x != 0.0 || !(length.is_finite() && length > 0.0) {
            return Err(bad(format!(
                "a section table runs from x = 0 to the body's length, found x = {} to {}",
                Num(stations[0].x),
                Num(length)
            )));
        }
        let wanted = kernels.section_moments().to_vec();
        if wanted.is_empty() {
            return Err(bad(format!(
                "the kernels of `{}` were generated for a uniform section: a section table needs kernels for varying sections",
                kernels.info().shape
            )));
        }
        let (x0, lengths) = match nodes {
            None => {
                if !(1..=ffr_spec::MAX_ELEMENTS).contains(&elements) {
                    return Err(bad(format!(
                        "a body has 1 to {} elements, found {elements}",
                        ffr_spec::MAX_ELEMENTS
                    )));
                }
                let l = length / elements as f64;
                (
                    (0..elements).map(|e| e as f64 * l).collect::<Vec<_>>(),
                    vec![l; elements],
                )
            }
            Some(nodes) => {
                check_nodes(nodes, length)?;
                (
                    nodes[..nodes.len() - 1].to_vec(),
                    nodes.windows(2).map(|w| w[1] - w[0]).collect(),
                )
            }
        };
        // Each property at the stations, in body axes (the twist turns the
        // principal-axis values: `ffr_spec::twisted_moments`).
        let at_stations = |p: SectionProp| -> Vec<(f64, f64)> {
            stations
                .iter()
                .map(|s| {
                    let (ei_yy, ei_zz, ei_yz) = ffr_spec::twisted_moments(s.ei_y, s.ei_z, s.twist);
                    let (r_yy, r_zz, r_yz) = ffr_spec::twisted_moments(s.rho_iy, s.rho_iz, s.twist);
                    let v = match p {
                        SectionProp::RhoA => s.mass,
                        SectionProp::RhoIy => r_yy,
                        SectionProp::RhoIz => r_zz,
                        SectionProp::RhoIyz => r_yz,
                        SectionProp::RhoJ => s.rho_j,
                        SectionProp::Ea => s.ea,
                        SectionProp::EiY => ei_yy,
                        SectionProp::EiZ => ei_zz,
                        SectionProp::EiYz => ei_yz,
                        SectionProp::Gj => s.gj,
                    };
                    (s.x, v)
                })
                .collect()
        };
        let tables: Vec<Vec<(f64, f64)>> =
            SectionProp::ALL.iter().map(|p| at_stations(*p)).collect();
        let table = |p: SectionProp| -> &[(f64, f64)] {
            let i = SectionProp::ALL
                .iter()
                .position(|q| *q == p)
                .expect("every property");
            &tables[i]
        };
        let nc = kernels.info().n_coefficients;
        let elements = lengths.len();
        let mut coef = vec![0.0; nc * elements];
        let mut mu = vec![0.0; wanted.len()];
        for e in 0..elements {
            ffr_spec::fill_moments(&wanted, table, x0[e], lengths[e], &mut mu)
                .map_err(|m| bad(m.to_string()))?;
            kernels.section_coefficients(&mu, lengths[e], &mut coef[e * nc..(e + 1) * nc]);
        }
        let mut params = [0.0; 8];
        params[0] = length;
        Self::assemble(
            kernels,
            Params::from_array(params),
            x0,
            lengths,
            coef,
            nc,
            reference,
            if nodes.is_some() {
                "with varying sections, graded"
            } else {
                "with varying sections"
            },
        )
    }

    fn build(
        kernels: K,
        params: Params,
        x0: Vec<f64>,
        lengths: Vec<f64>,
        equal: bool,
        reference: Reference,
    ) -> Result<Self> {
        let elements = lengths.len();
        let info = kernels.info().clone();
        params
            .validate_only(&info.params_used)
            .map_err(|e| Error::InvalidInput(e.to_string()))?;
        // One coefficient array when every element has the same length,
        // else one per element.
        let nc = info.n_coefficients;
        let blocks = if equal { 1 } else { elements };
        let mut coef = vec![0.0; nc * blocks];
        for (b, c) in coef.chunks_mut(nc.max(1)).enumerate().take(blocks) {
            kernels.coefficients(&params, lengths[b], c);
        }
        Self::assemble(
            kernels,
            params,
            x0,
            lengths,
            coef,
            if equal { 0 } else { nc },
            reference,
            if equal { "" } else { "graded" },
        )
    }

    /// The body from its elements' coefficient arrays (`stride` 0: one
    /// array for every element).
    #[allow(clippy::too_many_arguments)]
    fn assemble(
        kernels: K,
        params: Params,
        x0: Vec<f64>,
        lengths: Vec<f64>,
        coef: Vec<f64>,
        stride: usize,
        reference: Reference,
        mesh_note: &str,
    ) -> Result<Self> {
        let elements = lengths.len();
        let info = kernels.info().clone();
        let mesh = Mesh::new(&info.coordinates, info.dim, elements, reference)
            .map_err(|e| Error::InvalidInput(e.to_string()))?;
        let ne = info.n_local;
        let maps: Vec<usize> = (0..elements)
            .flat_map(|e| {
                mesh.element_map(e)
                    .map(|i| i.unwrap_or(REMOVED))
                    .collect::<Vec<_>>()
            })
            .collect();
        let nc = info.n_coefficients;
        if let Some(i) = coef.iter().position(|c| !c.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "the parameters ({}) give the element coefficient c[{}] = {} for {elements} × `{}`: a product of parameters is beyond the range of f64",
                params.describe(&info.params_used), i % nc.max(1), coef[i], info.shape
            )));
        }
        // "8", "8 graded"; a note naming the section goes after the shape.
        let (mesh_text, section_text) = match mesh_note {
            "" => (format!("{elements}"), ""),
            "graded" => (format!("{elements} graded"), ""),
            note => (format!("{elements}"), note),
        };
        let layout = BodyLayout {
            dim: info.dim,
            scene_dim: info.scene_dim(),
            nf: mesh.nf(),
            half_bandwidth: mesh.half_bandwidth(),
            free_frame: info.free_frame(),
            zero_frame_acceleration: info.zero_frame_acceleration(),
            labels: mesh.dofs().iter().map(|d| d.to_string()).collect(),
            length: Some(params.length),
            description: format!(
                "{} × `{}`{}{} ({} formalism, stiffening {}, {} reference, L = {} m)",
                mesh_text,
                info.shape,
                if section_text.is_empty() { "" } else { " " },
                section_text,
                info.options.formalism,
                info.options.stiffening,
                reference,
                params.length
            ),
        };
        Ok(Self {
            kernels,
            layout,
            params,
            coef,
            coef_stride: stride,
            elements,
            ne,
            maps,
            x0,
            lengths,
            attached: Vec::new(),
        })
    }

    /// The body with `masses` attached on its axis: rigid bodies whose
    /// centres move with the sections at their `x` (`ffr_spec::AttachedMass`),
    /// included in the body's invariants and equations.
    pub fn with_masses(mut self, masses: &[AttachedMass]) -> Result<Self> {
        let (dim, scene_dim) = (self.layout.dim, self.layout.scene_dim);
        for (i, m) in masses.iter().enumerate() {
            m.check(self.params.length, dim)
                .map_err(|e| Error::InvalidInput(format!("attached mass {i}: {e}")))?;
            let point = self.point_shape(m.x)?;
            self.attached
                .push(Attachment::new(m, &point, dim, scene_dim));
        }
        if !masses.is_empty() {
            let n = self.attached.len();
            self.layout.description.push_str(&format!(
                " with {n} attached mass{}",
                if n == 1 { "" } else { "es" }
            ));
        }
        Ok(self)
    }

    /// The body of a generated fixed-mesh type (`#[flex_body]`, `Builder::body`):
    /// its parameters on equal elements, or its baked section table
    /// ([`CompiledBody::SECTIONS`], [`KernelBody::with_sections`]).
    pub fn compiled<B: CompiledBody<Kernels = K>>(body: &B) -> Result<Self>
    where
        K: Default,
    {
        match B::SECTIONS {
            None => Self::new(K::default(), body.params(), B::ELEMENTS, B::REFERENCE),
            Some(stations) => {
                Self::with_sections(K::default(), stations, B::ELEMENTS, None, B::REFERENCE)
            }
        }
    }

    /// The kernels.
    pub fn kernels(&self) -> &K {
        &self.kernels
    }

    /// The parameter values.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The coefficient array the kernels read for element `e`.
    pub fn coefficients(&self, e: usize) -> &[f64] {
        self.coef_of(e)
    }

    /// The nodes `x_0 = 0, …, x_N = L`.
    pub fn nodes(&self) -> Vec<f64> {
        let mut out = self.x0.clone();
        out.push(self.params.length);
        out
    }

    fn coef_of(&self, e: usize) -> &[f64] {
        let s = self.coef_stride;
        if s == 0 {
            &self.coef
        } else {
            &self.coef[e * s..(e + 1) * s]
        }
    }

    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.elements
    }

    fn map(&self, e: usize) -> &[usize] {
        &self.maps[e * self.ne..(e + 1) * self.ne]
    }
}

fn gather(local: &mut [f64], global: &[f64], map: &[usize]) {
    for (l, &i) in local.iter_mut().zip(map) {
        *l = if i == REMOVED { 0.0 } else { global[i] };
    }
}

fn scatter(local: &[f64], global: &mut [f64], map: &[usize]) {
    for (l, &i) in local.iter().zip(map) {
        if i != REMOVED {
            global[i] += l;
        }
    }
}

impl<K: ElementKernels> Body for KernelBody<K> {
    fn layout(&self) -> &BodyLayout {
        &self.layout
    }

    fn work(&self) -> BodyWork {
        BodyWork {
            inner: None,
            buf: vec![
                0.0;
                Scratch {
                    ne: self.ne,
                    kernel: self.kernels.info().scratch
                }
                .len()
            ],
        }
    }

    fn forces(&self, s: &BodyState, frame_rows: bool, w: &mut BodyWork, out: &mut BodyForces) {
        assert!(
            !frame_rows || self.layout.free_frame,
            "body `{}` has no reference rows (kernels for prescribed frame motion)",
            self.layout.description
        );
        out.clear();
        let ne = self.ne;
        let (q, rest) = w.buf.split_at_mut(ne);
        let (qd, rest) = rest.split_at_mut(ne);
        let (qdd, rest) = rest.split_at_mut(ne);
        let (fe, rest) = rest.split_at_mut(ne);
        let (_, rest) = rest.split_at_mut(ne * ne + 15 * ne + 60);
        let ks = rest;
        for e in 0..self.elements {
            let map = self.map(e);
            gather(q, s.q_f, map);
            gather(qd, s.qd_f, map);
            gather(qdd, s.qdd_f, map);
            fe.iter_mut().for_each(|x| *x = 0.0);
            let x = KernelInput {
                x0: self.x0[e],
                q,
                qd,
                qdd,
                frame: &s.frame,
            };
            if frame_rows {
                let (mut f_r, mut f_th) = ([0.0; 3], [0.0; 3]);
                self.kernels.residual(
                    self.coef_of(e),
                    &x,
                    &mut ResidualOut {
                        f_r: &mut f_r,
                        f_th: &mut f_th,
                        f_e: fe,
                    },
                    ks,
                );
                for k in 0..3 {
                    out.f_r[k] += f_r[k];
                    out.f_th[k] += f_th[k];
                }
            } else {
                self.kernels.residual_elastic(self.coef_of(e), &x, fe, ks);
            }
            scatter(fe, &mut out.f_f, map);
        }
        for a in &self.attached {
            let x = a.gather(s, q, qd, qdd);
            a.terms.add_forces(&x, frame_rows, &a.map, out);
        }
    }

    fn elastic_force(&self, q_f: &[f64], w: &mut BodyWork, f_f: &mut [f64]) -> bool {
        // Attached masses add nothing at rest (their terms are inertial).
        let ne = self.ne;
        let (q, rest) = w.buf.split_at_mut(ne);
        let (_, rest) = rest.split_at_mut(2 * ne);
        let (fe, rest) = rest.split_at_mut(ne);
        let (_, rest) = rest.split_at_mut(ne * ne + 15 * ne + 60);
        let ks = rest;
        f_f.iter_mut().for_each(|x| *x = 0.0);
        for e in 0..self.elements {
            let map = self.map(e);
            gather(q, q_f, map);
            fe.iter_mut().for_each(|x| *x = 0.0);
            if !self.kernels.force_elastic(self.coef_of(e), q, fe, ks) {
                return false;
            }
            scatter(fe, f_f, map);
        }
        true
    }

    fn scalar_layout(&self) -> Option<ScalarLayout> {
        let ne = self.ne;
        let mut w = self.work();
        let (q, rest) = w.buf.split_at_mut(ne);
        let (z, rest) = rest.split_at_mut(ne);
        let ks = &mut rest[kernel_scratch_at(ne) - 2 * ne..];
        let scalars = self.kernels.elastic_scalars(self.coef_of(0), q, z, ks);
        (scalars > 0 && scalars <= ne && self.elements > 0).then_some(ScalarLayout {
            elements: self.elements,
            scalars,
            local: ne,
        })
    }

    fn element_scalars(&self, e: usize, q_f: &[f64], w: &mut BodyWork, z: &mut [f64]) {
        let ne = self.ne;
        let (q, rest) = w.buf.split_at_mut(ne);
        let ks = &mut rest[kernel_scratch_at(ne) - ne..];
        gather(q, q_f, self.map(e));
        self.kernels.elastic_scalars(self.coef_of(e), q, z, ks);
    }

    fn scalar_derivatives(
        &self,
        e: usize,
        z: &[f64],
        w: &mut BodyWork,
        g: &mut [f64],
        h: Option<&mut [f64]>,
    ) -> bool {
        let ks = &mut w.buf[kernel_scratch_at(self.ne)..];
        g.iter_mut().for_each(|x| *x = 0.0);
        match h {
            None => self.kernels.scalar_force(self.coef_of(e), z, g, ks),
            Some(h) => {
                h.iter_mut().for_each(|x| *x = 0.0);
                self.kernels.scalar_tangent(self.coef_of(e), z, g, h, ks)
            }
        }
    }

    fn scalar_forces(&self, z_all: &[f64], w: &mut BodyWork, g_all: &mut [f64]) -> bool {
        // The scratch from `z` on: the default batch's `z`, `g` and the
        // kernels' scratch, as `scalar_derivatives` lays them out.
        let ks = &mut w.buf[kernel_scratch_at(self.ne) - 2 * self.ne..];
        self.kernels.scalar_force_batch(
            &self.coef,
            self.coef_stride,
            z_all,
            g_all,
            self.elements,
            ks,
        )
    }

    fn tangent(
        &self,
        s: &BodyState,
        bp: f64,
        gp: f64,
        frame_rows: bool,
        w: &mut BodyWork,
        out: &mut BodyForces,
        t: &mut BodyTangent,
    ) {
        assert!(
            !frame_rows || self.layout.free_frame,
            "body `{}` has no reference rows (kernels for prescribed frame motion)",
            self.layout.description
        );
        out.clear();
        t.clear();
        let (ne, nf) = (self.ne, self.layout.nf);
        let (q, rest) = w.buf.split_at_mut(ne);
        let (qd, rest) = rest.split_at_mut(ne);
        let (qdd, rest) = rest.split_at_mut(ne);
        let (fe, rest) = rest.split_at_mut(ne);
        let (kee, rest) = rest.split_at_mut(ne * ne);
        let (def, rest) = rest.split_at_mut(9 * ne);
        let (kre, rest) = rest.split_at_mut(6 * ne);
        let (drf, rest) = rest.split_at_mut(54);
        let (_, ks) = rest.split_at_mut(6);
        for e in 0..self.elements {
            let map = self.map(e);
            gather(q, s.q_f, map);
            gather(qd, s.qd_f, map);
            gather(qdd, s.qdd_f, map);
            fe.iter_mut().for_each(|x| *x = 0.0);
            kee.iter_mut().for_each(|x| *x = 0.0);
            let x = KernelInput {
                x0: self.x0[e],
                q,
                qd,
                qdd,
                frame: &s.frame,
            };
            if frame_rows {
                def.iter_mut().for_each(|x| *x = 0.0);
                kre.iter_mut().for_each(|x| *x = 0.0);
                drf.iter_mut().for_each(|x| *x = 0.0);
                let (mut f_r, mut f_th) = ([0.0; 3], [0.0; 3]);
                self.kernels.tangent(
                    self.coef_of(e),
                    &x,
                    bp,
                    gp,
                    &mut TangentOut {
                        f_r: &mut f_r,
                        f_th: &mut f_th,
                        f_e: fe,
                        k_ee: kee,
                        d_e_frame: def,
                        k_ref_e: kre,
                        d_ref_frame: drf,
                    },
                    ks,
                );
                for k in 0..3 {
                    out.f_r[k] += f_r[k];
                    out.f_th[k] += f_th[k];
                }
                for (a, &ia) in map.iter().enumerate() {
                    if ia == REMOVED {
                        continue;
                    }
                    for k in 0..9 {
                        t.d_f_frame[ia * 9 + k] += def[a * 9 + k];
                    }
                    for r in 0..6 {
                        t.k_ref_f[r * nf + ia] += kre[r * ne + a];
                    }
                }
                for (d, v) in t.d_ref_frame.iter_mut().zip(drf.iter()) {
                    *d += v;
                }
            } else {
                self.kernels
                    .tangent_elastic(self.coef_of(e), &x, bp, gp, fe, kee, ks);
            }
            scatter(fe, &mut out.f_f, map);
            for (a, &ia) in map.iter().enumerate() {
                if ia == REMOVED {
                    continue;
                }
                for (b, &ib) in map.iter().enumerate() {
                    if ib != REMOVED {
                        t.k_ff.add(ia, ib, kee[a * ne + b]);
                    }
                }
            }
        }
        for a in &self.attached {
            let x = a.gather(s, q, qd, qdd);
            a.terms.add_forces(&x, frame_rows, &a.map, out);
            a.terms.add_tangent(&x, bp, gp, frame_rows, &a.map, t);
        }
    }

    fn mass(&self, q_f: &[f64], w: &mut BodyWork, out: &mut BodyMass) {
        out.clear();
        let (ne, nf) = (self.ne, self.layout.nf);
        let (q, rest) = w.buf.split_at_mut(ne);
        let (_, rest) = rest.split_at_mut(3 * ne);
        let (mee, rest) = rest.split_at_mut(ne * ne);
        let (mef, rest) = rest.split_at_mut(9 * ne);
        let (mre, rest) = rest.split_at_mut(6 * ne);
        let (mrf, rest) = rest.split_at_mut(54);
        let (_, ks) = rest.split_at_mut(6);
        for e in 0..self.elements {
            let map = self.map(e);
            gather(q, q_f, map);
            mee.iter_mut().for_each(|x| *x = 0.0);
            mef.iter_mut().for_each(|x| *x = 0.0);
            mre.iter_mut().for_each(|x| *x = 0.0);
            mrf.iter_mut().for_each(|x| *x = 0.0);
            let mut s_t = [0.0; 3];
            self.kernels.mass(
                self.coef_of(e),
                self.x0[e],
                q,
                &mut MassOut {
                    s_t: &mut s_t,
                    m_ee: mee,
                    m_e_frame: &mut mef[..6 * ne],
                    m_ref_e: mre,
                    m_ref_frame: &mut mrf[..36],
                },
                ks,
            );
            for (d, v) in out.s_t.iter_mut().zip(s_t.iter()) {
                *d += v;
            }
            for (d, v) in out.m_ref_frame.iter_mut().zip(mrf.iter()) {
                *d += v;
            }
            for (a, &ia) in map.iter().enumerate() {
                if ia == REMOVED {
                    continue;
                }
                for k in 0..6 {
                    out.m_f_frame[ia * 6 + k] += mef[a * 6 + k];
                }
                for r in 0..6 {
                    out.m_ref_f[r * nf + ia] += mre[r * ne + a];
                }
                for (b, &ib) in map.iter().enumerate() {
                    if ib != REMOVED {
                        out.m_ff.add(ia, ib, mee[a * ne + b]);
                    }
                }
            }
        }
        for a in &self.attached {
            let n = a.map.len();
            gather(&mut q[..n], q_f, &a.map);
            a.terms.add_mass(&q[..n], &a.map, out);
        }
    }

    fn elastic_energy(&self, q_f: &[f64], w: &mut BodyWork) -> f64 {
        let ne = self.ne;
        let (q, rest) = w.buf.split_at_mut(ne);
        let (_, ks) = rest.split_at_mut(3 * ne + ne * ne + 15 * ne + 60);
        let mut e = 0.0;
        for el in 0..self.elements {
            gather(q, q_f, self.map(el));
            e += self.kernels.energy(self.coef_of(el), q, ks);
        }
        e
    }

    fn invariants(&self) -> Invariants {
        let (ne, nf) = (self.ne, self.layout.nf);
        let (off, len) = invariant_layout(ne);
        let mut buf = vec![0.0; len];
        let mut ks = vec![0.0; self.kernels.info().scratch];
        let mut inv = Invariants::zeros(self.layout.dim, nf);
        for e in 0..self.elements {
            buf.iter_mut().for_each(|x| *x = 0.0);
            self.kernels
                .element_invariants(self.coef_of(e), self.x0[e], &mut buf, &mut ks);
            let map = self.map(e);
            inv.mass += buf[off[0]];
            for k in 0..3 {
                inv.s_t0[k] += buf[off[1] + k];
                for l in 0..3 {
                    inv.theta[(k, l)] += buf[off[5] + k * 3 + l];
                }
            }
            for (a, &ia) in map.iter().enumerate() {
                if ia == REMOVED {
                    continue;
                }
                for k in 0..3 {
                    inv.s_bar[(k, ia)] += buf[off[2] + k * ne + a];
                    for l in 0..3 {
                        inv.i_kl[k][l][ia] += buf[off[4] + (k * 3 + l) * ne + a];
                    }
                }
                for (b, &ib) in map.iter().enumerate() {
                    if ib == REMOVED {
                        continue;
                    }
                    for k in 0..3 {
                        for l in 0..3 {
                            inv.s_kl[k][l][(ia, ib)] +=
                                buf[off[3] + ((k * 3 + l) * ne + a) * ne + b];
                        }
                    }
                    inv.m_ff[(ia, ib)] += buf[off[6] + a * ne + b];
                    inv.k_ff[(ia, ib)] += buf[off[7] + a * ne + b];
                }
            }
        }
        for a in &self.attached {
            a.add_invariants(&mut inv);
        }
        inv
    }

    fn point_shape(&self, x: f64) -> Result<PointShape> {
        let length = self.params.length;
        let tol = 1e-12 * length;
        if !(x.is_finite() && x >= -tol && x <= length + tol) {
            return Err(Error::InvalidInput(format!(
                "x = {} is not on the body's axis: it runs from x = 0 to x = {} m",
                Num(x),
                Num(length)
            )));
        }
        let x = x.clamp(0.0, length);
        let e = if self.coef_stride == 0 {
            // Equal elements: the element by division (as before graded
            // meshes, so that markers are placed bit for bit as then).
            ((x / self.lengths[0]).floor() as usize).min(self.elements - 1)
        } else {
            // The last element whose start is at or before x.
            self.x0.partition_point(|x0| *x0 <= x).saturating_sub(1)
        };
        let l = self.lengths[e];
        let xi = (x - self.x0[e]) / l;
        let ne = self.ne;
        let mut s = vec![0.0; 3 * ne];
        let mut psi = vec![0.0; 3 * ne];
        let mut ks = vec![0.0; self.kernels.info().scratch];
        self.kernels
            .point_shape(self.coef_of(e), xi, &mut s, &mut psi, &mut ks);
        let mut entries = Vec::new();
        for (a, &ia) in self.map(e).iter().enumerate() {
            if ia == REMOVED {
                continue;
            }
            let sa = [s[a], s[ne + a], s[2 * ne + a]];
            let pa = [psi[a], psi[ne + a], psi[2 * ne + a]];
            if sa.iter().chain(&pa).any(|v| *v != 0.0) {
                entries.push((ia, sa, pa));
            }
        }
        Ok(PointShape {
            u0: [x, 0.0, 0.0],
            entries,
        })
    }
}
