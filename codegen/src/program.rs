//! Straight-line programs: the form in which every generated formula exists
//! before it becomes Rust.
//!
//! A [`Program`] is a list of `let` bindings (hoisted power products and
//! intermediate sums) and outputs, each an expression tree over inputs
//! (parameters, `q_f` entries), temporaries and `f64` literals rounded from
//! the exact rationals. [`Program::eval`] runs it in the same operation order
//! the emitted Rust has, so the command line reports exactly the numbers the
//! compiled code computes.

use crate::poly::{to_f64, Monomial, Param, Poly, Rational, Sym};
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
}

/// Where an output goes. Indices: `k, l ∈ {0, 1, 2}` for x, y, z; `a, b`
/// elastic coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Target {
    /// `m`.
    Mass,
    /// `S_t0[k]`.
    St0(usize),
    /// `S̄[k][a]`.
    SBar(usize, usize),
    /// `S̄_kl[a][b]` (emitted for `k < l` with its transpose `S̄_lk`, and for
    /// `k = l`, `a ≤ b` with its mirror).
    Skl(usize, usize, usize, usize),
    /// `Ī_kl[a]`.
    Ikl(usize, usize, usize),
    /// `Θ_kl`, `k ≤ l` (mirrored).
    Theta(usize, usize),
    /// `m_ff[a][b]`, `a ≤ b` (mirrored).
    Mff(usize, usize),
    /// `K_ff[a][b]`, `a ≤ b` (mirrored).
    Kff(usize, usize),
    /// `S_t(q)[k]`.
    St(usize),
    /// `Ī_θθ(q)[k][l]`, `k ≤ l` (mirrored).
    ItTheta(usize, usize),
    /// `Ī_θf(q)[k][a]`.
    ItF(usize, usize),
    /// `∂U_nl/∂q_a`.
    Force(usize),
    /// `∂²U_nl/∂q_a∂q_b`, `a ≤ b` (mirrored).
    Tangent(usize, usize),
}

/// A straight-line program.
#[derive(Clone, Debug, Default)]
pub struct Program {
    /// Name of every slot: first the inputs, then the temporaries.
    pub names: Vec<String>,
    /// Input slots: parameters and `q_f` entries, with what they read.
    pub inputs: Vec<(u32, Input)>,
    /// `let names[slot] = expr;` in order.
    pub stmts: Vec<(u32, Expr)>,
    /// Outputs in order.
    pub outputs: Vec<(Target, Expr)>,
}

/// What an input slot reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Input {
    /// A parameter field.
    Param(Param),
    /// `q_f[i]`.
    Q(usize),
}

impl Program {
    /// Run the program: parameter values in [`Param::FIELDS`] order, and `q_f`.
    pub fn eval(&self, params: &[f64; 8], q: &[f64]) -> Vec<(Target, f64)> {
        let tape = self.tape();
        let mut slots = Vec::new();
        tape.run(params, q, &mut slots);
        tape.outputs
            .iter()
            .map(|&(t, s)| (t, slots[s as usize]))
            .collect()
    }

    /// The program flattened into register operations, in the order the
    /// emitted Rust evaluates them (so results are bit for bit the same).
    pub fn tape(&self) -> Tape {
        let mut t = Tape {
            n_slots: self.names.len() as u32,
            ..Tape::default()
        };
        t.inputs = self
            .inputs
            .iter()
            .map(|&(s, i)| {
                let src = match i {
                    Input::Param(p) => TapeInput::Param(p.field_index().expect("runtime field")),
                    Input::Q(k) => TapeInput::Q(k),
                };
                (s, src)
            })
            .collect();
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

    /// The parameters the program reads.
    pub fn params(&self) -> Vec<Param> {
        let mut v: Vec<Param> = self
            .inputs
            .iter()
            .filter_map(|(_, i)| match i {
                Input::Param(p) => Some(*p),
                Input::Q(_) => None,
            })
            .collect();
        v.sort();
        v
    }
}

/// Where a tape input comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TapeInput {
    /// Parameter by index into [`Param::FIELDS`].
    Param(usize),
    /// `q_f[i]`.
    Q(usize),
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

/// A [`Program`] as a flat list of register operations: what an evaluated
/// (not compiled) body runs.
#[derive(Clone, Debug, Default)]
pub struct Tape {
    n_slots: u32,
    consts: Vec<(u32, f64)>,
    inputs: Vec<(u32, TapeInput)>,
    ops: Vec<Op>,
    /// Each output and the register holding it after [`Tape::run`].
    pub outputs: Vec<(Target, u32)>,
}

impl Tape {
    fn fresh(&mut self) -> u32 {
        self.n_slots += 1;
        self.n_slots - 1
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

    /// Run with parameter values in [`Param::FIELDS`] order and `q_f`;
    /// `slots` is scratch space (resized as needed): read the outputs from it
    /// through [`Tape::outputs`].
    pub fn run(&self, params: &[f64; 8], q: &[f64], slots: &mut Vec<f64>) {
        slots.resize(self.n_slots as usize, 0.0);
        for &(r, x) in &self.consts {
            slots[r as usize] = x;
        }
        for &(r, src) in &self.inputs {
            slots[r as usize] = match src {
                TapeInput::Param(i) => params[i],
                TapeInput::Q(i) => q[i],
            };
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

/// Builds a [`Program`] from exact polynomials, hoisting power products of
/// parameters and of `q_f` entries into named, memoized temporaries.
#[derive(Default)]
pub struct ProgramBuilder {
    prog: Program,
    by_name: HashMap<String, u32>,
    monomials: HashMap<Monomial, u32>,
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

impl ProgramBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    fn slot(&mut self, name: String) -> u32 {
        let id = self.prog.names.len() as u32;
        self.by_name.insert(name.clone(), id);
        self.prog.names.push(name);
        id
    }

    fn input(&mut self, s: Sym) -> u32 {
        let name = s.to_string();
        if let Some(&id) = self.by_name.get(&name) {
            return id;
        }
        let input = match s {
            Sym::Param(p) => Input::Param(p),
            Sym::Q(i) => Input::Q(i as usize),
            other => panic!("{other} is not a runtime input"),
        };
        let id = self.slot(name);
        self.prog.inputs.push((id, input));
        id
    }

    /// A temporary `let name = expr;`.
    pub fn temp(&mut self, name: &str, expr: Expr) -> Expr {
        let mut n = name.to_string();
        let mut k = 1;
        while self.by_name.contains_key(&n) {
            k += 1;
            n = format!("{name}_{k}");
        }
        let id = self.slot(n);
        self.prog.stmts.push((id, expr));
        Expr::Var(id)
    }

    /// An expression for a monomial of runtime symbols, built from memoized
    /// prefix products: `s^e = s^(e−1)·s`, `s^−e = (1/s)^e`, and
    /// `f₁…f_n = (f₁…f_{n−1})·f_n`.
    pub fn monomial(&mut self, m: &Monomial) -> Expr {
        if let Some(&id) = self.monomials.get(m) {
            return Expr::Var(id);
        }
        let f = m.factors();
        assert!(!f.is_empty(), "the constant monomial has no expression");
        let expr = if f.len() == 1 {
            let (s, e) = f[0];
            if e == 1 {
                let id = self.input(s);
                self.monomials.insert(m.clone(), id);
                return Expr::Var(id);
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
            .map(|&(s, e)| factor_name(s, e))
            .collect::<Vec<_>>()
            .join("_");
        let v = self.temp(&name, expr);
        if let Expr::Var(id) = v {
            self.monomials.insert(m.clone(), id);
        }
        v
    }

    /// `Σ c_i · X_i` as a left-to-right sum; `X_i = None` is the constant 1.
    fn linear(&mut self, terms: Vec<(Rational, Option<Expr>)>) -> Expr {
        let mut acc: Option<Expr> = None;
        for (c, x) in terms {
            let neg = c.is_negative();
            let a = c.abs();
            let mag = match x {
                None => Expr::Lit(to_f64(&a)),
                Some(x) if a.is_one() => x,
                Some(x) => Expr::mul(Expr::Lit(to_f64(&a)), x),
            };
            acc = Some(match (acc, neg) {
                (None, false) => mag,
                (None, true) => match mag {
                    Expr::Lit(v) => Expr::Lit(-v),
                    Expr::Mul(l, r) if matches!(*l, Expr::Lit(_)) => {
                        let Expr::Lit(v) = *l else { unreachable!() };
                        Expr::Mul(Box::new(Expr::Lit(-v)), r)
                    }
                    other => Expr::Neg(Box::new(other)),
                },
                (Some(s), false) => Expr::Add(Box::new(s), Box::new(mag)),
                (Some(s), true) => Expr::Sub(Box::new(s), Box::new(mag)),
            });
        }
        acc.unwrap_or(Expr::Lit(0.0))
    }

    /// An expression for a polynomial in parameters and `q_f` entries:
    /// terms grouped by their parameter monomial `P`, each group
    /// `P · (Σ c · Q)` over monomials `Q` of `q_f`; zero terms never appear.
    pub fn poly(&mut self, p: &Poly) -> Expr {
        let mut groups: BTreeMap<Monomial, Vec<(Monomial, Rational)>> = BTreeMap::new();
        for (m, c) in p.terms() {
            let (params, qs) = m.split(|s| matches!(s, Sym::Param(_)));
            groups.entry(params).or_default().push((qs, c.clone()));
        }
        let mut outer: Vec<(Rational, Option<Expr>)> = Vec::new();
        for (pm, inner) in groups {
            let pe = (!pm.is_one()).then(|| self.monomial(&pm));
            if inner.len() == 1 {
                let (qm, c) = inner.into_iter().next().unwrap();
                let qe = (!qm.is_one()).then(|| self.monomial(&qm));
                let x = match (pe, qe) {
                    (Some(a), Some(b)) => Some(Expr::mul(a, b)),
                    (a, b) => a.or(b),
                };
                outer.push((c, x));
            } else {
                let terms = inner
                    .into_iter()
                    .map(|(qm, c)| {
                        let qe = (!qm.is_one()).then(|| self.monomial(&qm));
                        (c, qe)
                    })
                    .collect();
                let sum = self.linear(terms);
                let x = match pe {
                    Some(a) => Expr::mul(a, sum),
                    None => sum,
                };
                outer.push((Rational::one(), Some(x)));
            }
        }
        self.linear(outer)
    }

    /// Add an output.
    pub fn output(&mut self, t: Target, e: Expr) {
        self.prog.outputs.push((t, e));
    }

    /// Add an output for a polynomial unless it is zero.
    pub fn output_poly(&mut self, t: Target, p: &Poly) {
        if !p.is_zero() {
            let e = self.poly(p);
            self.output(t, e);
        }
    }

    /// The finished program.
    pub fn finish(self) -> Program {
        self.prog
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly::rat;

    #[test]
    fn hoists_and_evaluates() {
        let l = Sym::Param(Param::Length);
        let rho = Sym::Param(Param::Rho);
        // 1/3 rho L^3 - 2 q0 q1 rho L^3 + rho/L
        let mut p = Poly::zero();
        let rl3 = Monomial::var(rho, 1).mul(&Monomial::var(l, 3));
        p.add_term(rl3.clone(), rat(1, 3));
        p.add_term(
            rl3.mul(&Monomial::var(Sym::Q(0), 1))
                .mul(&Monomial::var(Sym::Q(1), 1)),
            rat(-2, 1),
        );
        p.add_term(Monomial::var(rho, 1).mul(&Monomial::var(l, -1)), rat(1, 1));
        let mut b = ProgramBuilder::new();
        let e = b.poly(&p);
        b.output(Target::Mass, e);
        let prog = b.finish();
        assert!(prog.names.contains(&"length_3".to_string()));
        assert!(prog.names.contains(&"inv_length".to_string()));
        let mut params = [0.0; 8];
        params[0] = 2.0;
        params[1] = 3.0;
        let v = prog.eval(&params, &[0.5, 0.25])[0].1;
        let expect = 3.0 * 8.0 / 3.0 - 2.0 * 0.125 * 3.0 * 8.0 + 3.0 / 2.0;
        assert!((v - expect).abs() < 1e-14, "{v} vs {expect}");
    }
}
