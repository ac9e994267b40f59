//! Straight-line programs: the form in which every generated formula exists
//! before it becomes Rust (or runs on a [`Tape`]).
//!
//! A kernel program reads its inputs (coefficients `c[i]`, element
//! coordinates, frame motion, …), computes `let` temporaries (hoisted power
//! products, intermediates of the [`Dag`]) and assigns its
//! outputs. Every term `r · P(params) · X(inputs)` of an exact polynomial
//! becomes `κ · X` with the coefficient `κ = |r| · P` computed once per body
//! by the *coefficient program* (the [`Coefficients`] registry), so a kernel
//! call does no parameter arithmetic. Terms are grouped by their frame
//! monomial (`ω_z²`, `β'`, …) and summed left to right.
//!
//! [`Tape`] runs a program in exactly the emitted code's operation order, so
//! run-time (tape) bodies compute bit for bit what compiled bodies compute.

use crate::dag::Dag;
use crate::eom::OutArr;
use crate::poly::{rat, to_f64, Monomial, Param, Poly, Rational, SectionProp, Sym};

use num_traits::{One, Signed};
use std::collections::{BTreeMap, HashMap};

/// An expression over slots (inputs and temporaries) and literals.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A slot.
    Var(u32),
    /// A literal.
    Lit(f64),
    /// `a + b`.
    Add(Box<Expr>, Box<Expr>),
    /// `a − b`.
    Sub(Box<Expr>, Box<Expr>),
    /// `a · b`.
    Mul(Box<Expr>, Box<Expr>),
    /// `a / b`.
    Div(Box<Expr>, Box<Expr>),
    /// `−a`.
    Neg(Box<Expr>),
}

impl Expr {
    fn mul(a: Expr, b: Expr) -> Expr {
        Expr::Mul(Box::new(a), Box::new(b))
    }

    /// Arithmetic operations in the expression.
    pub fn ops(&self) -> usize {
        match self {
            Expr::Var(_) | Expr::Lit(_) => 0,
            Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) | Expr::Div(a, b) => {
                1 + a.ops() + b.ops()
            }
            Expr::Neg(a) => 1 + a.ops(),
        }
    }
}

/// What an input slot reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Input {
    /// A body parameter (coefficient program only; `ElemLength` is `l`).
    Param(Param),
    /// Coefficient `c[i]`.
    Coef(u32),
    /// Element moment `mu[i]` (section coefficient program only; `i` indexes
    /// the kernel set's list of moments).
    Moment(u32),
    /// A kernel input: `x0`, `frame[k]`, `bp`, `gp`, `q[i]`, `qd[i]`, `qdd[i]`, `xi`.
    Sym(Sym),
}

/// A straight-line program.
#[derive(Clone, Debug, Default)]
pub struct Program {
    /// Name of every slot: first the inputs, then the temporaries.
    pub names: Vec<String>,
    /// Input slots with what they read.
    pub inputs: Vec<(u32, Input)>,
    /// `let names[slot] = expr;` in order.
    pub stmts: Vec<(u32, Expr)>,
    /// Outputs in order: array entry and expression.
    pub outputs: Vec<((OutArr, u32), Expr)>,
}

impl Program {
    /// Arithmetic operations (adds, multiplies, divides, negations) in one run.
    pub fn ops(&self) -> usize {
        self.stmts.iter().map(|(_, e)| e.ops()).sum::<usize>()
            + self.outputs.iter().map(|(_, e)| e.ops()).sum::<usize>()
    }

    /// The parameters the program reads.
    pub fn params(&self) -> Vec<Param> {
        let mut v: Vec<Param> = self
            .inputs
            .iter()
            .filter_map(|(_, i)| match i {
                Input::Param(p) => Some(*p),
                _ => None,
            })
            .collect();
        v.sort();
        v
    }

    /// The highest coefficient index read, plus one.
    pub fn coefficients_read(&self) -> usize {
        self.inputs
            .iter()
            .filter_map(|(_, i)| match i {
                Input::Coef(c) => Some(*c as usize + 1),
                _ => None,
            })
            .max()
            .unwrap_or(0)
    }

    /// The program flattened into register operations, in the order the
    /// emitted Rust evaluates them (so results are bit for bit the same).
    pub fn tape(&self) -> Tape {
        let mut t = Tape {
            n_slots: self.names.len() as u32,
            ..Tape::default()
        };
        t.inputs = self.inputs.iter().map(|&(s, i)| (s, i)).collect();
        let mut consts = HashMap::new();
        for (slot, e) in &self.stmts {
            let r = t.compile(e, &mut consts);
            t.ops.push(Op::Copy(*slot, r));
        }
        for (target, e) in &self.outputs {
            let r = t.compile(e, &mut consts);
            t.outputs.push((*target, r));
        }
        t
    }
}

/// Input values of one program run (unused ones may be empty).
#[derive(Clone, Copy, Debug, Default)]
pub struct Inputs<'a> {
    /// Parameter fields in [`Param::FIELDS`] order, then `l`.
    pub params: &'a [f64],
    /// Coefficients.
    pub coef: &'a [f64],
    /// Element moments of the section properties (the kernel set's list).
    pub mu: &'a [f64],
    /// `x₀`.
    pub x0: f64,
    /// `ā, α, ω` in body axes.
    pub frame: &'a [f64],
    /// `β'`.
    pub bp: f64,
    /// `γ'`.
    pub gp: f64,
    /// Element coordinates.
    pub q: &'a [f64],
    /// Their velocities.
    pub qd: &'a [f64],
    /// Their accelerations.
    pub qdd: &'a [f64],
    /// `ξ`.
    pub xi: f64,
}

impl Inputs<'_> {
    /// The value an input slot reads.
    pub fn get(&self, i: Input) -> f64 {
        match i {
            Input::Param(Param::ElemLength) => self.params[8],
            Input::Param(p) => self.params[p.field_index().expect("field")],
            Input::Coef(c) => self.coef[c as usize],
            Input::Moment(i) => self.mu[i as usize],
            Input::Sym(s) => match s {
                Sym::X0 => self.x0,
                Sym::Frame(k) => self.frame[k as usize],
                Sym::Bp => self.bp,
                Sym::Gp => self.gp,
                Sym::Q(i) => self.q[i as usize],
                Sym::Qd(i) => self.qd[i as usize],
                Sym::Qdd(i) => self.qdd[i as usize],
                Sym::Xi => self.xi,
                other => panic!("{other} is not a kernel input"),
            },
        }
    }
}

/// One register operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `dst = a + b`.
    Add(u32, u32, u32),
    /// `dst = a − b`.
    Sub(u32, u32, u32),
    /// `dst = a · b`.
    Mul(u32, u32, u32),
    /// `dst = a / b`.
    Div(u32, u32, u32),
    /// `dst = −a`.
    Neg(u32, u32),
    /// `dst = a`.
    Copy(u32, u32),
}

/// A [`Program`] as a flat list of register operations: what a run-time
/// (not compiled) body runs.
#[derive(Clone, Debug, Default)]
pub struct Tape {
    n_slots: u32,
    consts: Vec<(u32, f64)>,
    inputs: Vec<(u32, Input)>,
    ops: Vec<Op>,
    /// Each output and the register holding it after [`Tape::run`].
    pub outputs: Vec<((OutArr, u32), u32)>,
}

impl Tape {
    fn fresh(&mut self) -> u32 {
        self.n_slots += 1;
        self.n_slots - 1
    }

    /// Registers a run needs.
    pub fn n_slots(&self) -> usize {
        self.n_slots as usize
    }

    fn compile(&mut self, e: &Expr, consts: &mut HashMap<u64, u32>) -> u32 {
        match e {
            Expr::Var(i) => *i,
            Expr::Lit(x) => {
                if let Some(&r) = consts.get(&x.to_bits()) {
                    return r;
                }
                let r = self.fresh();
                self.consts.push((r, *x));
                consts.insert(x.to_bits(), r);
                r
            }
            Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) | Expr::Div(a, b) => {
                let (ra, rb) = (self.compile(a, consts), self.compile(b, consts));
                let d = self.fresh();
                self.ops.push(match e {
                    Expr::Add(..) => Op::Add(d, ra, rb),
                    Expr::Sub(..) => Op::Sub(d, ra, rb),
                    Expr::Mul(..) => Op::Mul(d, ra, rb),
                    _ => Op::Div(d, ra, rb),
                });
                d
            }
            Expr::Neg(a) => {
                let ra = self.compile(a, consts);
                let d = self.fresh();
                self.ops.push(Op::Neg(d, ra));
                d
            }
        }
    }

    /// Run with `inputs`; `slots` is scratch space of at least
    /// [`Tape::n_slots`] entries; read the outputs from it through
    /// [`Tape::outputs`]. No allocation.
    pub fn run(&self, inputs: &Inputs, slots: &mut [f64]) {
        for &(r, x) in &self.consts {
            slots[r as usize] = x;
        }
        for &(r, src) in &self.inputs {
            slots[r as usize] = inputs.get(src);
        }
        for op in &self.ops {
            match *op {
                Op::Add(d, a, b) => slots[d as usize] = slots[a as usize] + slots[b as usize],
                Op::Sub(d, a, b) => slots[d as usize] = slots[a as usize] - slots[b as usize],
                Op::Mul(d, a, b) => slots[d as usize] = slots[a as usize] * slots[b as usize],
                Op::Div(d, a, b) => slots[d as usize] = slots[a as usize] / slots[b as usize],
                Op::Neg(d, a) => slots[d as usize] = -slots[a as usize],
                Op::Copy(d, a) => slots[d as usize] = slots[a as usize],
            }
        }
    }
}

/// The coefficients that kernel programs read: each a polynomial in the
/// parameters (and `l`), normalized so that its first term is positive,
/// computed once per body.
#[derive(Clone, Debug, Default)]
pub struct Coefficients {
    index: HashMap<Poly, u32>,
    /// In index order.
    pub entries: Vec<Poly>,
}

impl Coefficients {
    fn get(&mut self, p: Poly) -> u32 {
        if let Some(&i) = self.index.get(&p) {
            return i;
        }
        let i = self.entries.len() as u32;
        self.entries.push(p.clone());
        self.index.insert(p, i);
        i
    }

    /// The coefficient program: parameters (and `l`) in, `c[i]` out.
    pub fn program(&self) -> Program {
        let mut b = ProgramBuilder::new(None);
        for (i, p) in self.entries.iter().enumerate() {
            let e = b.param_poly(p);
            b.prog.outputs.push(((OutArr::Coef, i as u32), e));
        }
        b.prog
    }

    /// The element moments the coefficients read (varying sections), sorted.
    pub fn moments(&self) -> Vec<(SectionProp, u8)> {
        let mut v: Vec<(SectionProp, u8)> = self
            .entries
            .iter()
            .flat_map(|p| {
                p.terms()
                    .flat_map(|(m, _)| m.factors().iter())
                    .filter_map(|(s, _)| match s {
                        Sym::Moment(p, k) => Some((*p, *k)),
                        _ => None,
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        v.sort();
        v.dedup();
        v
    }

    /// The section coefficient program of a varying section: the element
    /// moments `mu[i]` (in the order of `moments`) and `l` in, `c[i]` out.
    pub fn section_program(&self, moments: &[(SectionProp, u8)]) -> Program {
        let mut b = ProgramBuilder::new(None);
        b.moment_table = moments.to_vec();
        for (i, p) in self.entries.iter().enumerate() {
            let e = b.param_poly(p);
            b.prog.outputs.push(((OutArr::Coef, i as u32), e));
        }
        b.prog
    }

    /// The coefficient program of a varying section for a uniform body: every
    /// moment replaced by its value for constant properties,
    /// `μ_{P,k} = P/(k+1)` with `P` in the parameters
    /// ([`uniform_property`]).
    pub fn uniform_program(&self) -> Program {
        let mut b = ProgramBuilder::new(None);
        for (i, p) in self.entries.iter().enumerate() {
            let mut q = p.clone();
            for (prop, k) in self.moments() {
                let value = uniform_property(prop).scale(&rat(1, k as i64 + 1));
                q = q.substitute(Sym::Moment(prop, k), &value);
            }
            let e = b.param_poly(&q);
            b.prog.outputs.push(((OutArr::Coef, i as u32), e));
        }
        b.prog
    }

    /// Number of coefficients.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// A section property of a uniform body in its parameters: `ρA`, `ρI_y`,
/// `ρI_z`, 0, `ρ(I_y + I_z)`, `EA`, `EI_y`, `EI_z`, 0, `GJ`.
pub fn uniform_property(prop: SectionProp) -> Poly {
    let v = |a: Param, b: Param| Poly::var(Sym::Param(a)).mul(&Poly::var(Sym::Param(b)));
    match prop {
        SectionProp::RhoA => v(Param::Rho, Param::Area),
        SectionProp::RhoIy => v(Param::Rho, Param::Iy),
        SectionProp::RhoIz => v(Param::Rho, Param::Iz),
        SectionProp::RhoIyz | SectionProp::EiYz => Poly::zero(),
        SectionProp::RhoJ => v(Param::Rho, Param::Iy).add(&v(Param::Rho, Param::Iz)),
        SectionProp::Ea => v(Param::E, Param::Area),
        SectionProp::EiY => v(Param::E, Param::Iy),
        SectionProp::EiZ => v(Param::E, Param::Iz),
        SectionProp::Gj => v(Param::G, Param::J),
    }
}

/// Whether a symbol is grouped outside the sums of a program's expressions.
fn is_outer(s: Sym) -> bool {
    matches!(s, Sym::Frame(_) | Sym::Bp | Sym::Gp | Sym::X0)
}

fn factor_name(s: Sym, e: i32) -> String {
    let base = s.to_string();
    match e {
        1 => base,
        -1 => format!("inv_{base}"),
        e if e < 0 => format!("inv_{base}_{}", -e),
        e => format!("{base}_{e}"),
    }
}

/// Builds a [`Program`] from exact polynomials.
pub struct ProgramBuilder<'c> {
    prog: Program,
    coefs: Option<&'c mut Coefficients>,
    by_name: HashMap<String, u32>,
    monomials: HashMap<Monomial, u32>,
    inputs: HashMap<Input, u32>,
    zs: HashMap<u32, Expr>,
    /// The element moments a section coefficient program reads, in input order.
    moment_table: Vec<(SectionProp, u8)>,
}

impl<'c> ProgramBuilder<'c> {
    /// A builder; kernel programs fold parameters into `coefs`, the
    /// coefficient program (`None`) reads parameters directly.
    pub fn new(coefs: Option<&'c mut Coefficients>) -> Self {
        Self {
            prog: Program::default(),
            coefs,
            by_name: HashMap::new(),
            monomials: HashMap::new(),
            inputs: HashMap::new(),
            zs: HashMap::new(),
            moment_table: Vec::new(),
        }
    }

    fn slot(&mut self, name: String) -> u32 {
        let mut n = name.clone();
        let mut k = 1;
        while self.by_name.contains_key(&n) {
            k += 1;
            n = format!("{name}_{k}");
        }
        let id = self.prog.names.len() as u32;
        self.by_name.insert(n.clone(), id);
        self.prog.names.push(n);
        id
    }

    fn input(&mut self, i: Input) -> u32 {
        if let Some(&id) = self.inputs.get(&i) {
            return id;
        }
        let name = match i {
            Input::Param(p) => p.field().to_string(),
            Input::Coef(c) => format!("c{c}"),
            Input::Moment(i) => {
                let (p, k) = self.moment_table[i as usize];
                Sym::Moment(p, k).to_string()
            }
            Input::Sym(s) => s.to_string(),
        };
        let id = self.slot(name);
        self.prog.inputs.push((id, i));
        self.inputs.insert(i, id);
        id
    }

    /// A temporary `let name = expr;`.
    pub fn temp(&mut self, name: &str, expr: Expr) -> Expr {
        let id = self.slot(name.to_string());
        self.prog.stmts.push((id, expr));
        Expr::Var(id)
    }

    fn sym_expr(&mut self, s: Sym) -> Expr {
        match s {
            Sym::Z(m) => self.zs.get(&m).cloned().unwrap_or_else(|| {
                panic!("intermediate z{m} used before it was bound (a generator bug)")
            }),
            Sym::Param(p) => Expr::Var(self.input(Input::Param(p))),
            Sym::Moment(p, k) => {
                let i = self
                    .moment_table
                    .iter()
                    .position(|&m| m == (p, k))
                    .unwrap_or_else(|| {
                        panic!("{s} outside the section coefficient program (a generator bug)")
                    });
                Expr::Var(self.input(Input::Moment(i as u32)))
            }
            s => Expr::Var(self.input(Input::Sym(s))),
        }
    }

    /// An expression for a monomial, built from memoized prefix products:
    /// `s^e = s^(e−1)·s`, `s^−e = (1/s)^e`, `f₁…f_n = (f₁…f_{n−1})·f_n`.
    pub fn monomial(&mut self, m: &Monomial) -> Expr {
        if let Some(&id) = self.monomials.get(m) {
            return Expr::Var(id);
        }
        let f = m.factors();
        assert!(!f.is_empty(), "the constant monomial has no expression");
        let expr = if f.len() == 1 {
            let (s, e) = f[0];
            if e == 1 {
                return self.sym_expr(s);
            }
            if e == -1 {
                let x = self.monomial(&Monomial::var(s, 1));
                Expr::Div(Box::new(Expr::Lit(1.0)), Box::new(x))
            } else {
                let step = if e > 0 { 1 } else { -1 };
                let prev = self.monomial(&Monomial::var(s, e - step));
                let unit = self.monomial(&Monomial::var(s, step));
                Expr::mul(prev, unit)
            }
        } else {
            let (s, e) = f[f.len() - 1];
            let prefix = m.without(s).0;
            let a = self.monomial(&prefix);
            let b = self.monomial(&Monomial::var(s, e));
            Expr::mul(a, b)
        };
        let name = f
            .iter()
            .map(|&(s, e)| match s {
                Sym::Z(m) => {
                    let base = self.zname(m);
                    if e == 1 {
                        base
                    } else {
                        format!("{base}_{e}")
                    }
                }
                s => factor_name(s, e),
            })
            .collect::<Vec<_>>()
            .join("_");
        let v = self.temp(&name, expr);
        if let Expr::Var(id) = v {
            self.monomials.insert(m.clone(), id);
        }
        v
    }

    fn zname(&self, m: u32) -> String {
        match self.zs.get(&m) {
            Some(Expr::Var(id)) => self.prog.names[*id as usize].clone(),
            _ => format!("z{m}"),
        }
    }

    /// `Σ ± |κ_i| · X_i` as a left-to-right sum.
    fn signed_sum(terms: Vec<(bool, Expr)>) -> Expr {
        let mut acc: Option<Expr> = None;
        for (neg, x) in terms {
            acc = Some(match (acc, neg) {
                (None, false) => x,
                (None, true) => match x {
                    Expr::Lit(v) => Expr::Lit(-v),
                    Expr::Mul(l, r) if matches!(*l, Expr::Lit(_)) => {
                        let Expr::Lit(v) = *l else { unreachable!() };
                        Expr::Mul(Box::new(Expr::Lit(-v)), r)
                    }
                    other => Expr::Neg(Box::new(other)),
                },
                (Some(s), false) => Expr::Add(Box::new(s), Box::new(x)),
                (Some(s), true) => Expr::Sub(Box::new(s), Box::new(x)),
            });
        }
        acc.unwrap_or(Expr::Lit(0.0))
    }

    /// `Σ ± |r| · P` of a polynomial in the parameters only (the coefficient
    /// program's entries).
    fn param_poly(&mut self, p: &Poly) -> Expr {
        let mut terms = Vec::new();
        for (m, r) in p.terms() {
            let a = r.abs();
            let e = match (m.is_one(), a.is_one()) {
                (true, _) => Expr::Lit(to_f64(&a)),
                (false, true) => self.monomial(m),
                (false, false) => {
                    let x = self.monomial(m);
                    Expr::mul(Expr::Lit(to_f64(&a)), x)
                }
            };
            terms.push((r.is_negative(), e));
        }
        Self::signed_sum(terms)
    }

    /// A coefficient polynomial `C(params)` as `± κ`: a literal (`None` for
    /// the literal one) when it has no parameters, else a coefficient slot
    /// (or, in the coefficient program, the expression itself).
    fn coefficient(&mut self, c: &Poly) -> (bool, Option<Expr>) {
        if let Some(r) = c.as_constant() {
            let a = r.abs();
            return (
                r.is_negative(),
                (!a.is_one()).then(|| Expr::Lit(to_f64(&a))),
            );
        }
        let neg = c.terms().next().is_some_and(|(_, r)| r.is_negative());
        let norm = if neg {
            c.scale(&-Rational::one())
        } else {
            c.clone()
        };
        match self.coefs.as_deref_mut() {
            Some(reg) => {
                let i = reg.get(norm);
                (neg, Some(Expr::Var(self.input(Input::Coef(i)))))
            }
            None => (neg, Some(self.param_poly(&norm))),
        }
    }

    /// An expression for an exact polynomial over parameters, kernel inputs
    /// and bound intermediates: `Σ_O O · (Σ_X ± κ_X · X)` over the frame
    /// monomials `O` and the monomials `X` of coordinates and intermediates,
    /// with one coefficient `κ_X` (a polynomial in the parameters) per `X`;
    /// zero terms never appear.
    pub fn poly(&mut self, p: &Poly) -> Expr {
        let mut groups: BTreeMap<Monomial, BTreeMap<Monomial, Poly>> = BTreeMap::new();
        for (m, c) in p.terms() {
            let (params, rest) = m.split(|s| s.is_coefficient());
            let (outer, inner) = rest.split(is_outer);
            groups
                .entry(outer)
                .or_default()
                .entry(inner)
                .or_default()
                .add_term(params, c.clone());
        }
        let mut outer_terms: Vec<(bool, Expr)> = Vec::new();
        for (om, inner) in groups {
            let mut terms: Vec<(bool, Expr)> = Vec::new();
            for (im, cp) in inner {
                let (neg, k) = self.coefficient(&cp);
                let x = (!im.is_one()).then(|| self.monomial(&im));
                let e = match (k, x) {
                    (Some(k), Some(x)) => Expr::mul(k, x),
                    (Some(k), None) => k,
                    (None, Some(x)) => x,
                    (None, None) => Expr::Lit(1.0),
                };
                terms.push((neg, e));
            }
            if om.is_one() {
                outer_terms.extend(terms);
                continue;
            }
            let o = self.monomial(&om);
            if terms.len() == 1 {
                let (neg, e) = terms.pop().expect("one term");
                let e = match e {
                    Expr::Lit(1.0) => o,
                    e => Expr::mul(o, e),
                };
                outer_terms.push((neg, e));
            } else {
                outer_terms.push((false, Expr::mul(o, Self::signed_sum(terms))));
            }
        }
        Self::signed_sum(outer_terms)
    }

    /// Bind the DAG intermediates that `outputs` need, as temporaries.
    pub fn bind_dag(&mut self, dag: &Dag, outputs: &[&Poly]) {
        for m in dag.reachable(outputs) {
            if self.zs.contains_key(&m) {
                continue;
            }
            let b = &dag.bindings()[m as usize];
            let e = self.poly(&b.poly);
            let v = match e {
                Expr::Var(_) => e,
                e => self.temp(&b.name, e),
            };
            self.zs.insert(m, v);
        }
    }

    /// Add an output.
    pub fn output(&mut self, t: (OutArr, u32), e: Expr) {
        self.prog.outputs.push((t, e));
    }

    /// A complete program for `outputs` over `dag`.
    pub fn build(mut self, dag: &Dag, outputs: &[((OutArr, u32), Poly)]) -> Program {
        let polys: Vec<&Poly> = outputs.iter().map(|(_, p)| p).collect();
        self.bind_dag(dag, &polys);
        for (t, p) in outputs {
            let e = self.poly(p);
            self.output(*t, e);
        }
        self.prog
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly::rat;

    #[test]
    fn folds_parameters_into_coefficients_and_evaluates() {
        let l = Sym::Param(Param::Length);
        let rho = Sym::Param(Param::Rho);
        // 1/3 rho L^3 q0 − 2 q0 q1 rho L^3 w_z^2 + rho/L
        let mut p = Poly::zero();
        let rl3 = Monomial::var(rho, 1).mul(&Monomial::var(l, 3));
        p.add_term(rl3.mul(&Monomial::var(Sym::Q(0), 1)), rat(1, 3));
        p.add_term(
            rl3.mul(&Monomial::var(Sym::Q(0), 1))
                .mul(&Monomial::var(Sym::Q(1), 1))
                .mul(&Monomial::var(Sym::Frame(8), 2)),
            rat(-2, 1),
        );
        p.add_term(Monomial::var(rho, 1).mul(&Monomial::var(l, -1)), rat(1, 1));
        let mut coefs = Coefficients::default();
        let prog =
            ProgramBuilder::new(Some(&mut coefs)).build(&Dag::new(), &[((OutArr::Energy, 0), p)]);
        assert_eq!(coefs.len(), 3);
        assert!(prog.params().is_empty());
        let cprog = coefs.program();
        let params = [2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5];
        let mut cslots = vec![0.0; cprog.tape().n_slots()];
        let ct = cprog.tape();
        ct.run(
            &Inputs {
                params: &params,
                ..Inputs::default()
            },
            &mut cslots,
        );
        let c: Vec<f64> = ct
            .outputs
            .iter()
            .map(|&(_, r)| cslots[r as usize])
            .collect();
        let t = prog.tape();
        let mut slots = vec![0.0; t.n_slots()];
        let frame = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.7];
        t.run(
            &Inputs {
                coef: &c,
                frame: &frame,
                q: &[0.5, 0.25],
                ..Inputs::default()
            },
            &mut slots,
        );
        let v = slots[t.outputs[0].1 as usize];
        let expect = 3.0 * 8.0 / 3.0 * 0.5 - 2.0 * 0.125 * 3.0 * 8.0 * 0.49 + 3.0 / 2.0;
        assert!((v - expect).abs() < 1e-14, "{v} vs {expect}");
    }
}
