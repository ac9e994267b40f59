//! Exact polynomials with named intermediate quantities, and their
//! derivatives by the chain rule.
//!
//! A [`Dag`] holds *bindings* `z_m := D_m`, each an exact polynomial in the
//! kernel inputs and earlier bindings (symbols [`Sym::Z`]). Outputs are
//! polynomials in the same symbols. [`Dag::derivative`] differentiates with
//! respect to an input by the chain rule,
//!
//! `dF/dx = ∂F/∂x + Σ_m ∂F/∂z_m · dz_m/dx`,
//!
//! binding `dz_m/dx` and the partials `∂D_m/∂z_j` of bindings as new
//! intermediates where they are not trivial, so that forces and tangents of
//! an energy written in a few element scalars cost a few operations per
//! entry instead of expanded polynomials. Everything stays exact: a binding
//! is only a name for an exact polynomial.

use crate::poly::{Monomial, Poly, Rational, Sym};
use num_traits::One;
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// A named intermediate.
#[derive(Clone, Debug)]
pub struct Binding {
    /// Name for generated code (made unique by the program builder).
    pub name: String,
    /// Its definition.
    pub poly: Poly,
}

/// Bindings and the memo tables of their derivatives.
#[derive(Clone, Debug, Default)]
pub struct Dag {
    bindings: Vec<Binding>,
    /// Input symbols each binding depends on (transitively).
    support: Vec<BTreeSet<Sym>>,
    /// `dz_m/dx` (a binding symbol, or a small polynomial).
    total: HashMap<(u32, Sym), Poly>,
    /// `∂D_m/∂z_j`.
    partial: HashMap<(u32, u32), Poly>,
    /// Each definition once: the same polynomial gets the same name.
    by_poly: HashMap<Poly, Poly>,
}

/// Whether `s` is a kernel input (not a parameter, not an integration variable).
pub fn is_input(s: Sym) -> bool {
    !matches!(
        s,
        Sym::Param(_) | Sym::Moment(..) | Sym::Xi | Sym::Eta | Sym::Zeta | Sym::Z(_)
    )
}

fn z_of(s: Sym) -> Option<u32> {
    match s {
        Sym::Z(m) => Some(m),
        _ => None,
    }
}

/// The `Z` symbols a polynomial contains.
fn z_symbols(p: &Poly) -> BTreeSet<u32> {
    p.terms()
        .flat_map(|(m, _)| m.factors().iter().filter_map(|(s, _)| z_of(*s)))
        .collect()
}

/// Whether a polynomial is worth a name: more than one term, or one term
/// with more than a bare symbol times a parameter monomial.
fn is_trivial(p: &Poly) -> bool {
    match p.len() {
        0 => true,
        1 => {
            let (m, c) = p.terms().next().expect("one term");
            let runtime: Vec<_> = m
                .factors()
                .iter()
                .filter(|(s, _)| !s.is_coefficient())
                .collect();
            runtime.is_empty() || (runtime.len() == 1 && runtime[0].1 == 1 && c.is_one())
        }
        _ => false,
    }
}

impl Dag {
    /// An empty DAG.
    pub fn new() -> Self {
        Self::default()
    }

    /// The bindings in definition order (each refers only to earlier ones).
    pub fn bindings(&self) -> &[Binding] {
        &self.bindings
    }

    /// `z := poly` under `name`; returns the symbol's polynomial (or `poly`
    /// itself when it is trivial).
    pub fn bind(&mut self, name: &str, poly: Poly) -> Poly {
        if is_trivial(&poly) {
            return poly;
        }
        self.bind_always(name, poly)
    }

    /// `z := poly` under `name`, even when `poly` is trivial (element
    /// scalars: the energy is then a function of the scalars only, and its
    /// derivatives follow the chain rule through them).
    pub fn bind_always(&mut self, name: &str, poly: Poly) -> Poly {
        if let Some(z) = self.by_poly.get(&poly) {
            return z.clone();
        }
        let mut support = BTreeSet::new();
        for (m, _) in poly.terms() {
            for &(s, _) in m.factors() {
                match s {
                    Sym::Z(j) => support.extend(self.support[j as usize].iter().copied()),
                    s if is_input(s) => {
                        support.insert(s);
                    }
                    _ => {}
                }
            }
        }
        let id = self.bindings.len() as u32;
        self.bindings.push(Binding {
            name: name.to_string(),
            poly,
        });
        self.support.push(support);
        let z = Poly::var(Sym::Z(id));
        self.by_poly
            .insert(self.bindings[id as usize].poly.clone(), z.clone());
        z
    }

    /// Bind each entry of a vector.
    pub fn bind_all(&mut self, name: &str, polys: Vec<Poly>) -> Vec<Poly> {
        polys
            .into_iter()
            .enumerate()
            .map(|(i, p)| self.bind(&format!("{name}{i}"), p))
            .collect()
    }

    /// Whether `f` depends on input `x` (directly or through bindings).
    pub fn depends_on(&self, f: &Poly, x: Sym) -> bool {
        f.terms().any(|(m, _)| {
            m.factors().iter().any(|&(s, _)| match s {
                Sym::Z(j) => self.support[j as usize].contains(&x),
                s => s == x,
            })
        })
    }

    /// `∂D_m/∂z_j`, bound when not trivial.
    fn partial_of_binding(&mut self, m: u32, j: u32) -> Poly {
        if let Some(p) = self.partial.get(&(m, j)) {
            return p.clone();
        }
        let d = self.bindings[m as usize].poly.diff(Sym::Z(j));
        let name = format!(
            "d_{}_d_{}",
            self.bindings[m as usize].name, self.bindings[j as usize].name
        );
        let p = self.bind(&name, d);
        self.partial.insert((m, j), p.clone());
        p
    }

    /// `dz_m/dx`, bound when not trivial.
    fn total_of_binding(&mut self, m: u32, x: Sym) -> Poly {
        if let Some(p) = self.total.get(&(m, x)) {
            return p.clone();
        }
        let p = if self.support[m as usize].contains(&x) {
            let def = self.bindings[m as usize].poly.clone();
            let mut d = def.diff(x);
            for j in z_symbols(&def) {
                if !self.support[j as usize].contains(&x) {
                    continue;
                }
                let dj = self.total_of_binding(j, x);
                if dj.is_zero() {
                    continue;
                }
                let pj = self.partial_of_binding(m, j);
                d.add_assign(&pj.mul(&dj));
            }
            let name = format!("d_{}_d_{x}", self.bindings[m as usize].name);
            self.bind(&name, d)
        } else {
            Poly::zero()
        };
        self.total.insert((m, x), p.clone());
        p
    }

    /// `dF/dx` of a polynomial over inputs and bindings, by the chain rule.
    pub fn derivative(&mut self, f: &Poly, x: Sym) -> Poly {
        let mut d = f.diff(x);
        for m in z_symbols(f) {
            if !self.support[m as usize].contains(&x) {
                continue;
            }
            let dm = self.total_of_binding(m, x);
            if dm.is_zero() {
                continue;
            }
            d.add_assign(&f.diff(Sym::Z(m)).mul(&dm));
        }
        d
    }

    /// `F` with every binding replaced by its definition (for checks: the
    /// expanded polynomial the bindings stand for).
    pub fn expand(&self, f: &Poly) -> Poly {
        let mut out = f.clone();
        loop {
            let zs = z_symbols(&out);
            let Some(&m) = zs.iter().next_back() else {
                return out;
            };
            out = out.substitute(Sym::Z(m), &self.bindings[m as usize].poly);
        }
    }

    /// The bindings `f` needs, transitively, in definition order.
    pub fn reachable(&self, outputs: &[&Poly]) -> Vec<u32> {
        let mut need: BTreeSet<u32> = BTreeSet::new();
        let mut stack: Vec<u32> = outputs.iter().flat_map(|p| z_symbols(p)).collect();
        while let Some(m) = stack.pop() {
            if need.insert(m) {
                stack.extend(z_symbols(&self.bindings[m as usize].poly));
            }
        }
        need.into_iter().collect()
    }
}

/// `Σ_a c_a x_a` as a polynomial.
pub fn linear(coeffs: &[Poly], var: impl Fn(usize) -> Sym) -> Poly {
    let mut p = Poly::zero();
    for (a, c) in coeffs.iter().enumerate() {
        if !c.is_zero() {
            p.add_assign(&c.mul_monomial(&Monomial::var(var(a), 1)));
        }
    }
    p
}

/// A coefficient `c` times a symbol.
pub fn term(c: Rational, s: Sym) -> Poly {
    Poly::term(c, Monomial::var(s, 1))
}

/// Group a polynomial's terms by the monomial of the symbols selected by
/// `outer` (used by the program builder; exposed for tests).
pub fn group_by(p: &Poly, outer: impl Fn(Sym) -> bool) -> BTreeMap<Monomial, Poly> {
    let mut g: BTreeMap<Monomial, Poly> = BTreeMap::new();
    for (m, c) in p.terms() {
        let (o, i) = m.split(&outer);
        g.entry(o).or_default().add_term(i, c.clone());
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly::rat;

    fn q(i: u32) -> Poly {
        Poly::var(Sym::Q(i))
    }

    #[test]
    fn chain_rule_matches_expansion() {
        let mut dag = Dag::new();
        // z0 = 2 q0 + q1, z1 = q1 − q2, E = z0² z1 + 3 z1²
        let z0 = dag.bind("z0", q(0).scale(&rat(2, 1)).add(&q(1)));
        let z1 = dag.bind("z1", q(1).sub(&q(2)));
        let e_def = z0.mul(&z0).mul(&z1).add(&z1.mul(&z1).scale(&rat(3, 1)));
        let e = dag.bind("e", e_def);
        for a in 0..3 {
            let g = dag.derivative(&e, Sym::Q(a));
            let exact = dag.expand(&e).diff(Sym::Q(a));
            assert_eq!(dag.expand(&g), exact);
            for b in 0..3 {
                let h = dag.derivative(&g, Sym::Q(b));
                assert_eq!(dag.expand(&h), exact.diff(Sym::Q(b)));
            }
        }
        // An input not in the support has derivative zero.
        assert!(dag.derivative(&e, Sym::Qd(0)).is_zero());
    }
}
