//! From a body to straight-line programs for everything the runtime needs:
//! the invariants, the `q_f`-dependent inertia terms and, optionally, the
//! geometric-stiffening forces and tangent.

use crate::body::{BodySpec, Dof, ExactInvariants};
use crate::error::Error;
use crate::poly::{Monomial, Param, Poly, Sym};
use crate::program::{Expr, Program, ProgramBuilder, Target};

/// What to generate besides the invariants and inertia terms.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Options {
    /// Geometric (centrifugal) stiffening from `ε = u' + ½(v'² + w'²)`.
    pub stiffening: bool,
}

/// Everything generated for one body.
#[derive(Clone, Debug)]
pub struct Generated {
    /// The body.
    pub spec: BodySpec,
    /// Options it was generated with.
    pub options: Options,
    /// Its elastic coordinates.
    pub dofs: Vec<Dof>,
    /// The exact invariants.
    pub exact: ExactInvariants,
    /// `invariants()`: outputs `Mass … Kff`.
    pub invariants: Program,
    /// `inertia_terms(q_f)`: outputs `St`, `ItTheta`, `ItF`.
    pub inertia: Program,
    /// Stiffening force program (outputs `Force`), if generated.
    pub stiffening_force: Option<Program>,
    /// Stiffening tangent program (outputs `Tangent`), if generated.
    pub stiffening_tangent: Option<Program>,
}

impl Generated {
    /// Parameters read by any generated function, in field order.
    pub fn used_params(&self) -> Vec<Param> {
        let mut v: Vec<Param> = [&self.invariants, &self.inertia]
            .into_iter()
            .chain(self.stiffening_force.as_ref())
            .chain(self.stiffening_tangent.as_ref())
            .flat_map(|p| p.params())
            .collect();
        v.push(Param::Length);
        v.sort();
        v.dedup();
        v
    }
}

fn q(i: usize) -> Poly {
    Poly::var(Sym::Q(i as u32))
}

/// Generate all programs for `spec`.
pub fn generate(spec: &BodySpec, options: Options) -> Result<Generated, Error> {
    let exact = spec.exact_invariants()?;
    let invariants = invariants_program(&exact);
    let inertia = inertia_program(&exact);
    let (stiffening_force, stiffening_tangent) = if options.stiffening {
        let (f, t) = stiffening_programs(spec, exact.nf);
        (Some(f), Some(t))
    } else {
        (None, None)
    };
    Ok(Generated {
        spec: spec.clone(),
        options,
        dofs: spec.dofs(),
        exact,
        invariants,
        inertia,
        stiffening_force,
        stiffening_tangent,
    })
}

fn invariants_program(inv: &ExactInvariants) -> Program {
    let nf = inv.nf;
    let mut b = ProgramBuilder::new();
    b.output_poly(Target::Mass, &inv.mass);
    for k in 0..3 {
        b.output_poly(Target::St0(k), &inv.s_t0[k]);
    }
    for k in 0..3 {
        for a in 0..nf {
            b.output_poly(Target::SBar(k, a), inv.s_bar.get(k, a));
        }
    }
    for k in 0..3 {
        for l in k..3 {
            for a in 0..nf {
                for c in if k == l { a } else { 0 }..nf {
                    b.output_poly(Target::Skl(k, l, a, c), inv.s_kl[k][l].get(a, c));
                }
            }
        }
    }
    for k in 0..3 {
        for l in 0..3 {
            for a in 0..nf {
                b.output_poly(Target::Ikl(k, l, a), &inv.i_kl[k][l][a]);
            }
        }
    }
    for k in 0..3 {
        for l in k..3 {
            b.output_poly(Target::Theta(k, l), &inv.theta[k][l]);
        }
    }
    for a in 0..nf {
        for c in a..nf {
            b.output_poly(Target::Mff(a, c), inv.m_ff.get(a, c));
        }
    }
    for a in 0..nf {
        for c in a..nf {
            b.output_poly(Target::Kff(a, c), inv.k_ff.get(a, c));
        }
    }
    b.finish()
}

/// `U_kl = Θ_kl + (Ī_kl + Ī_lk) q + qᵀ S̄_kl q` as an exact polynomial.
fn u_kl(inv: &ExactInvariants, k: usize, l: usize) -> Poly {
    let nf = inv.nf;
    let mut u = inv.theta[k][l].clone();
    for a in 0..nf {
        let lin = inv.i_kl[k][l][a].add(&inv.i_kl[l][k][a]);
        if !lin.is_zero() {
            u.add_assign(&lin.mul(&q(a)));
        }
        for c in 0..nf {
            let s = inv.s_kl[k][l].get(a, c);
            if !s.is_zero() {
                u.add_assign(&s.mul_monomial(
                    &Monomial::var(Sym::Q(a as u32), 1).mul(&Monomial::var(Sym::Q(c as u32), 1)),
                ));
            }
        }
    }
    u
}

fn inertia_program(inv: &ExactInvariants) -> Program {
    let nf = inv.nf;
    let mut b = ProgramBuilder::new();
    // S_t = S_t0 + S̄ q.
    for k in 0..3 {
        let mut s = inv.s_t0[k].clone();
        for a in 0..nf {
            s.add_assign(&inv.s_bar.get(k, a).mul(&q(a)));
        }
        b.output_poly(Target::St(k), &s);
    }
    // Ī_θθ = tr(U) I − U from the six U_kl.
    const AXES: [&str; 3] = ["x", "y", "z"];
    let mut u: [[Option<Expr>; 3]; 3] = Default::default();
    for k in 0..3 {
        for l in k..3 {
            let p = u_kl(inv, k, l);
            if !p.is_zero() {
                let e = b.poly(&p);
                u[k][l] = Some(b.temp(&format!("u_{}{}", AXES[k], AXES[l]), e));
            }
        }
    }
    for k in 0..3 {
        let mut acc: Option<Expr> = None;
        for m in (0..3).filter(|&m| m != k) {
            if let Some(x) = u[m][m].clone() {
                acc = Some(match acc {
                    None => x,
                    Some(a) => Expr::Add(Box::new(a), Box::new(x)),
                });
            }
        }
        if let Some(e) = acc {
            b.output(Target::ItTheta(k, k), e);
        }
        for l in k + 1..3 {
            if let Some(x) = u[k][l].clone() {
                b.output(Target::ItTheta(k, l), Expr::Neg(Box::new(x)));
            }
        }
    }
    // Ī_θf row r: Ī_ab − Ī_ba + qᵀ(S̄_ab − S̄_ba), (a, b) cyclic after r.
    for (r, (ka, kb)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
        for a in 0..nf {
            let mut p = inv.i_kl[ka][kb][a].sub(&inv.i_kl[kb][ka][a]);
            for c in 0..nf {
                let s = inv.s_kl[ka][kb].get(c, a).sub(inv.s_kl[kb][ka].get(c, a));
                if !s.is_zero() {
                    p.add_assign(&s.mul(&q(c)));
                }
            }
            b.output_poly(Target::ItF(r, a), &p);
        }
    }
    b.finish()
}

fn stiffening_programs(spec: &BodySpec, nf: usize) -> (Program, Program) {
    let energy = spec.stiffening_energy();
    let forces: Vec<Poly> = (0..nf).map(|a| energy.diff(Sym::Q(a as u32))).collect();
    let mut bf = ProgramBuilder::new();
    for (a, f) in forces.iter().enumerate() {
        bf.output_poly(Target::Force(a), f);
    }
    let mut bt = ProgramBuilder::new();
    for (a, f) in forces.iter().enumerate() {
        for c in a..nf {
            bt.output_poly(Target::Tangent(a, c), &f.diff(Sym::Q(c as u32)));
        }
    }
    (bf.finish(), bt.finish())
}
