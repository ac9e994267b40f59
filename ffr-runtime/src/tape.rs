//! Element kernels run from tapes at run time instead of compiled: any
//! shape file without a rebuild, bit for bit the numbers the compiled
//! kernels give (same programs, same operations in the same order), at the
//! cost of an interpreter (see the README's speed table). The built-in shapes
//! use compiled kernels (the `ffr` crate's `compiled` module); this is the
//! path for a shape chosen at run time, and the reference the compiled
//! kernels are checked against bit for bit (`ffr-bench`). Feature `tape`
//! (it needs the generator, `ffr-codegen`).

use crate::spec::{KernelKind, Params, SectionProp};
use crate::{ElementKernels, KernelInfo, KernelInput, MassOut, ResidualOut, TangentOut};
use ffr_codegen::eom::OutArr;
use ffr_codegen::program::{Inputs, Tape};
use ffr_codegen::{generate_kernels, KernelModel, KernelSet};
use std::borrow::Cow;

/// Element kernels evaluated from the generator's programs.
#[derive(Debug)]
pub struct TapeKernels {
    info: KernelInfo,
    /// The element moments `section_coefficients` reads (varying sections).
    section_moments: Vec<(SectionProp, u8)>,
    /// One tape per [`KernelKind`] (`None`: not generated, the reference
    /// rows of a prescribed frame).
    tapes: [Option<Tape>; KernelKind::ALL.len()],
    /// The stiffening energy's element scalars (`elastic_scalars`).
    scalar_count: usize,
}

impl TapeKernels {
    /// Generate the kernels of `model` and put them on tapes.
    pub fn new(model: &KernelModel) -> Result<Self, ffr_codegen::Error> {
        Ok(Self::from_set(&generate_kernels(model)?))
    }

    /// Tapes of already generated programs.
    pub fn from_set(set: &KernelSet) -> Self {
        let m = set.model();
        let tapes = KernelKind::ALL.map(|k| set.program(k).map(|p| p.tape()));
        // Scratch for the largest tape, the coefficients' included.
        let scratch = tapes.iter().flatten().map(Tape::n_slots).max().unwrap_or(0);
        Self {
            info: KernelInfo {
                shape: Cow::Owned(m.shape.name.clone()),
                dim: m.shape.dimension,
                n_local: set.n(),
                coordinates: Cow::Owned(m.shape.element_coordinates()),
                options: m.resolved_options(),
                n_coefficients: set.coefficients.len(),
                params_used: Cow::Owned(set.params_used()),
                scratch,
            },
            section_moments: set.section_moments.clone(),
            scalar_count: set
                .elastic_scalars
                .as_ref()
                .and(set.polys.energy_form.as_ref())
                .map_or(0, |e| e.scalars.len()),
            tapes,
        }
    }

    /// The tape of kernel `k`.
    fn tape(&self, k: KernelKind) -> &Tape {
        self.tapes[k.index()].as_ref().unwrap_or_else(|| {
            panic!(
                "kernels of `{}` were generated without `{}` (the reference rows: prescribed frame motion only; section_coefficients: uniform section)",
                self.info.shape,
                k.name()
            )
        })
    }
}

fn run(t: &Tape, inputs: &Inputs, scratch: &mut [f64], mut out: impl FnMut(OutArr, usize, f64)) {
    let slots = &mut scratch[..t.n_slots()];
    t.run(inputs, slots);
    for &((arr, i), r) in &t.outputs {
        out(arr, i as usize, slots[r as usize]);
    }
}

fn kernel_inputs<'a>(c: &'a [f64], x: &KernelInput<'a>) -> Inputs<'a> {
    Inputs {
        coef: c,
        x0: x.x0,
        frame: x.frame,
        q: x.q,
        qd: x.qd,
        qdd: x.qdd,
        ..Inputs::default()
    }
}

impl ElementKernels for TapeKernels {
    fn info(&self) -> &KernelInfo {
        &self.info
    }

    fn coefficients(&self, params: &Params, l: f64, c: &mut [f64]) {
        let mut p = [0.0; 9];
        p[..8].copy_from_slice(&params.to_array());
        p[8] = l; // the derived parameter `Param::ElemLength`
        let t = self.tape(KernelKind::Coefficients);
        let mut scratch = vec![0.0; t.n_slots()];
        run(
            t,
            &Inputs {
                params: &p,
                ..Inputs::default()
            },
            &mut scratch,
            |_, i, v| c[i] = v,
        );
    }

    fn section_moments(&self) -> &[(SectionProp, u8)] {
        &self.section_moments
    }

    fn section_coefficients(&self, mu: &[f64], l: f64, c: &mut [f64]) {
        assert_eq!(
            mu.len(),
            self.section_moments.len(),
            "the moment array has {} entries",
            self.section_moments.len()
        );
        let mut p = [0.0; 9];
        p[8] = l; // `Param::ElemLength`, the only parameter it reads
        let t = self.tape(KernelKind::SectionCoefficients);
        let mut scratch = vec![0.0; t.n_slots()];
        run(
            t,
            &Inputs {
                params: &p,
                mu,
                ..Inputs::default()
            },
            &mut scratch,
            |_, i, v| c[i] = v,
        );
    }

    fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut MassOut, scratch: &mut [f64]) {
        let inputs = Inputs {
            coef: c,
            x0,
            q,
            ..Inputs::default()
        };
        run(
            self.tape(KernelKind::Mass),
            &inputs,
            scratch,
            |arr, i, v| match arr {
                OutArr::St => out.s_t[i] = v,
                OutArr::Mee => out.m_ee[i] = v,
                OutArr::MeFrame => out.m_e_frame[i] = v,
                OutArr::MrefE => out.m_ref_e[i] = v,
                OutArr::MrefFrame => out.m_ref_frame[i] = v,
                other => unreachable!("{other:?} in mass"),
            },
        );
    }

    fn residual(&self, c: &[f64], x: &KernelInput, out: &mut ResidualOut, scratch: &mut [f64]) {
        let t = self.tape(KernelKind::Residual);
        run(t, &kernel_inputs(c, x), scratch, |arr, i, v| match arr {
            OutArr::Fr => out.f_r[i] = v,
            OutArr::Fth => out.f_th[i] = v,
            OutArr::Fe => out.f_e[i] = v,
            other => unreachable!("{other:?} in residual"),
        });
    }

    fn tangent(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        out: &mut TangentOut,
        scratch: &mut [f64],
    ) {
        let t = self.tape(KernelKind::Tangent);
        let inputs = Inputs {
            bp,
            gp,
            ..kernel_inputs(c, x)
        };
        run(t, &inputs, scratch, |arr, i, v| match arr {
            OutArr::Fr => out.f_r[i] = v,
            OutArr::Fth => out.f_th[i] = v,
            OutArr::Fe => out.f_e[i] = v,
            OutArr::Kee => out.k_ee[i] = v,
            OutArr::DeFrame => out.d_e_frame[i] = v,
            OutArr::KrefE => out.k_ref_e[i] = v,
            OutArr::DrefFrame => out.d_ref_frame[i] = v,
            other => unreachable!("{other:?} in tangent"),
        });
    }

    fn residual_elastic(&self, c: &[f64], x: &KernelInput, f_e: &mut [f64], scratch: &mut [f64]) {
        run(
            self.tape(KernelKind::ResidualElastic),
            &kernel_inputs(c, x),
            scratch,
            |_, i, v| f_e[i] = v,
        );
    }

    fn tangent_elastic(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        f_e: &mut [f64],
        k_ee: &mut [f64],
        scratch: &mut [f64],
    ) {
        let inputs = Inputs {
            bp,
            gp,
            ..kernel_inputs(c, x)
        };
        run(
            self.tape(KernelKind::TangentElastic),
            &inputs,
            scratch,
            |arr, i, v| match arr {
                OutArr::Fe => f_e[i] = v,
                OutArr::Kee => k_ee[i] = v,
                other => unreachable!("{other:?} in tangent_elastic"),
            },
        );
    }

    fn energy(&self, c: &[f64], q: &[f64], scratch: &mut [f64]) -> f64 {
        let mut e = 0.0;
        let inputs = Inputs {
            coef: c,
            q,
            ..Inputs::default()
        };
        run(
            self.tape(KernelKind::Energy),
            &inputs,
            scratch,
            |_, _, v| e = v,
        );
        e
    }

    fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], scratch: &mut [f64]) {
        let inputs = Inputs {
            coef: c,
            x0,
            ..Inputs::default()
        };
        run(
            self.tape(KernelKind::ElementInvariants),
            &inputs,
            scratch,
            |_, i, v| out[i] = v,
        );
    }

    fn point_shape(&self, c: &[f64], xi: f64, s: &mut [f64], psi: &mut [f64], scratch: &mut [f64]) {
        let inputs = Inputs {
            coef: c,
            xi,
            ..Inputs::default()
        };
        run(
            self.tape(KernelKind::PointShape),
            &inputs,
            scratch,
            |arr, i, v| match arr {
                OutArr::S => s[i] = v,
                OutArr::Psi => psi[i] = v,
                other => unreachable!("{other:?} in point_shape"),
            },
        );
    }

    fn force_elastic(&self, c: &[f64], q: &[f64], f_e: &mut [f64], scratch: &mut [f64]) -> bool {
        let Some(t) = &self.tapes[KernelKind::ForceElastic.index()] else {
            return false;
        };
        let inputs = Inputs {
            coef: c,
            q,
            ..Inputs::default()
        };
        run(t, &inputs, scratch, |_, i, v| f_e[i] = v);
        true
    }

    fn elastic_scalars(&self, c: &[f64], q: &[f64], z: &mut [f64], scratch: &mut [f64]) -> usize {
        let Some(t) = &self.tapes[KernelKind::ElasticScalars.index()] else {
            return 0;
        };
        let inputs = Inputs {
            coef: c,
            q,
            ..Inputs::default()
        };
        run(t, &inputs, scratch, |_, i, v| z[i] = v);
        self.scalar_count
    }

    fn scalar_force(&self, c: &[f64], z: &[f64], g: &mut [f64], scratch: &mut [f64]) -> bool {
        let Some(t) = &self.tapes[KernelKind::ScalarForce.index()] else {
            return false;
        };
        let inputs = Inputs {
            coef: c,
            q: z,
            ..Inputs::default()
        };
        run(t, &inputs, scratch, |_, i, v| g[i] = v);
        true
    }

    fn scalar_tangent(
        &self,
        c: &[f64],
        z: &[f64],
        g: &mut [f64],
        h: &mut [f64],
        scratch: &mut [f64],
    ) -> bool {
        let Some(t) = &self.tapes[KernelKind::ScalarTangent.index()] else {
            return false;
        };
        let inputs = Inputs {
            coef: c,
            q: z,
            ..Inputs::default()
        };
        run(t, &inputs, scratch, |arr, i, v| match arr {
            OutArr::Gz => g[i] = v,
            OutArr::Hz => h[i] = v,
            other => unreachable!("{other:?} in scalar_tangent"),
        });
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::{KernelOptions, SectionModel, Stiffening};
    use ffr_codegen::Shape;

    /// Through the trait: a varying set's `section_coefficients` with the
    /// moments of constant properties give the coefficients under which its
    /// element invariants and energy are the uniform set's; a uniform set
    /// reports no moments.
    #[test]
    fn section_coefficients_through_the_trait() {
        let model = KernelModel::new(
            Shape::resolve("beam3", None).unwrap(),
            KernelOptions::new().stiffening(Stiffening::FourthOrder),
        );
        let uniform = TapeKernels::new(&model).unwrap();
        let varying = TapeKernels::new(&model.with_sections(SectionModel::Varying)).unwrap();
        assert!(uniform.section_moments().is_empty());
        assert!(!varying.section_moments().is_empty());
        let p = Params::from_array([2.0, 7850.0, 2e-4, 1.7e-9, 6.6e-9, 2.1e11, 8.1e10, 4e-9]);
        let l = 0.5;
        let mu: Vec<f64> = varying
            .section_moments()
            .iter()
            .map(|&(prop, k)| prop.uniform_value(&p) / (k as f64 + 1.0))
            .collect();
        let mut cu = vec![0.0; uniform.info().n_coefficients];
        let mut cv = vec![0.0; varying.info().n_coefficients];
        uniform.coefficients(&p, l, &mut cu);
        varying.section_coefficients(&mu, l, &mut cv);
        let n = uniform.info().n_local;
        let (off, len) = crate::spec::invariant_layout(n);
        let mut scratch = vec![0.0; uniform.info().scratch.max(varying.info().scratch)];
        let (mut a, mut b) = (vec![0.0; len], vec![0.0; len]);
        uniform.element_invariants(&cu, 1.0, &mut a, &mut scratch);
        varying.element_invariants(&cv, 1.0, &mut b, &mut scratch);
        // Round-off relative to each block's largest entry (`ρJ − ρI_y − ρI_z`
        // of the torsional moments leaves ~1e-16 ρI where the uniform set
        // has an exact 0).
        for (bi, &start) in off.iter().enumerate() {
            let end = off.get(bi + 1).copied().unwrap_or(len);
            let scale = a[start..end].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for i in start..end {
                assert!(
                    (a[i] - b[i]).abs() <= 1e-13 * scale,
                    "{i}: {} vs {}",
                    a[i],
                    b[i]
                );
            }
        }
        let q: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64 - 5.5)).collect();
        let (eu, ev) = (
            uniform.energy(&cu, &q, &mut scratch),
            varying.energy(&cv, &q, &mut scratch),
        );
        assert!((eu - ev).abs() <= 1e-13 * eu.abs(), "{eu} vs {ev}");
    }
}
