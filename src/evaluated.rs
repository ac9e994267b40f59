//! A body whose generated programs are evaluated at run time instead of
//! compiled: any shape file and element count without a rebuild, bit for bit
//! the numbers the compiled code gives (same operations in the same order).

use crate::codegen::program::Tape;
use crate::codegen::{BodySpec, Generated, Options, ParamValues, Target};
use crate::runtime::nalgebra::DMatrix;
use crate::runtime::{FlexBody, InertiaTerms, Invariants};
use std::cell::RefCell;

/// A [`FlexBody`] running the generator's programs on tapes.
#[derive(Debug)]
pub struct EvaluatedBody {
    dim: usize,
    dofs: Vec<String>,
    params: [f64; 8],
    invariants: Tape,
    inertia: Tape,
    stiffening: Option<(Tape, Tape)>,
    scratch: RefCell<Vec<f64>>,
}

impl EvaluatedBody {
    /// Generate `spec` with `options` and bind the parameter values.
    pub fn new(
        spec: &BodySpec,
        options: Options,
        params: ParamValues,
    ) -> Result<Self, crate::codegen::Error> {
        params.validate()?;
        Ok(Self::from_generated(
            &crate::codegen::generate(spec, options)?,
            params,
        ))
    }

    /// Bind parameter values to already generated programs.
    pub fn from_generated(g: &Generated, params: ParamValues) -> Self {
        Self {
            dim: g.exact.dim,
            dofs: g.dofs.iter().map(|d| d.to_string()).collect(),
            params: params.to_array(),
            invariants: g.invariants.tape(),
            inertia: g.inertia.tape(),
            stiffening: g
                .stiffening_force
                .as_ref()
                .zip(g.stiffening_tangent.as_ref())
                .map(|(f, t)| (f.tape(), t.tape())),
            scratch: RefCell::new(Vec::new()),
        }
    }

    fn run(&self, tape: &Tape, q: &[f64], mut out: impl FnMut(Target, f64)) {
        let mut slots = self.scratch.borrow_mut();
        tape.run(&self.params, q, &mut slots);
        for &(t, r) in &tape.outputs {
            out(t, slots[r as usize]);
        }
    }
}

impl FlexBody for EvaluatedBody {
    fn nf(&self) -> usize {
        self.dofs.len()
    }

    fn dim(&self) -> usize {
        self.dim
    }

    fn dof_labels(&self) -> Vec<String> {
        self.dofs.clone()
    }

    fn invariants(&self) -> Invariants {
        let mut inv = Invariants::zeros(self.dim, self.nf());
        self.run(&self.invariants, &[], |t, v| match t {
            Target::Mass => inv.mass = v,
            Target::St0(k) => inv.s_t0[k] = v,
            Target::SBar(k, a) => inv.s_bar[(k, a)] = v,
            Target::Skl(k, l, a, b) => {
                inv.s_kl[k][l][(a, b)] = v;
                inv.s_kl[l][k][(b, a)] = v;
            }
            Target::Ikl(k, l, a) => inv.i_kl[k][l][a] = v,
            Target::Theta(k, l) => {
                inv.theta[(k, l)] = v;
                inv.theta[(l, k)] = v;
            }
            Target::Mff(a, b) => {
                inv.m_ff[(a, b)] = v;
                inv.m_ff[(b, a)] = v;
            }
            Target::Kff(a, b) => {
                inv.k_ff[(a, b)] = v;
                inv.k_ff[(b, a)] = v;
            }
            _ => {}
        });
        inv
    }

    fn inertia_terms(&self, q_f: &[f64], out: &mut InertiaTerms) {
        assert_eq!(q_f.len(), self.nf(), "q_f must have {} entries", self.nf());
        out.s_t.fill(0.0);
        out.i_theta_theta.fill(0.0);
        out.i_theta_f.fill(0.0);
        self.run(&self.inertia, q_f, |t, v| match t {
            Target::St(k) => out.s_t[k] = v,
            Target::ItTheta(k, l) => {
                out.i_theta_theta[(k, l)] = v;
                out.i_theta_theta[(l, k)] = v;
            }
            Target::ItF(k, a) => out.i_theta_f[(k, a)] = v,
            _ => {}
        });
    }

    fn has_stiffening(&self) -> bool {
        self.stiffening.is_some()
    }

    fn stiffening(&self, q_f: &[f64], force: &mut [f64], tangent: Option<&mut DMatrix<f64>>) {
        let Some((ft, tt)) = &self.stiffening else {
            return;
        };
        self.run(ft, q_f, |t, v| {
            if let Target::Force(a) = t {
                force[a] += v;
            }
        });
        if let Some(k) = tangent {
            self.run(tt, q_f, |t, v| {
                if let Target::Tangent(a, b) = t {
                    k[(a, b)] += v;
                    if a != b {
                        k[(b, a)] += v;
                    }
                }
            });
        }
    }
}
