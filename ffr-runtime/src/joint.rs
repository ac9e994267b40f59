//! Constraint equations between two markers, with exact first and second
//! derivatives.
//!
//! Every scalar constraint is `Φ = V₁(q) · V₂(q, t) − f(t)`, with `V₁`, `V₂`
//! linear combinations of the markers' positions and axes (coefficients
//! possibly `cos f(t)`, `sin f(t)` of a driver) or constant vectors:
//!
//! - coincident points: `(p_b − p_a) · e_k = 0`;
//! - perpendicular axes: `a_i · b_j = 0`;
//! - a driven angle about `z_a` (planar, or with a revolute joint):
//!   `x_b · (cos f · y_a − sin f · x_a) = 0`;
//! - an offset along an axis of `a` (prismatic joints, driven slides):
//!   `(p_b − p_a) · a_i − f(t) = 0`.
//!
//! Joints are sets of such rows ([`crate::system::System::revolute`] …).

use crate::driver::Driver;
use crate::marker::{Marker, MarkerKin};
use nalgebra::Vector3;

/// Which marker of a constraint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Marker `a`.
    A,
    /// Marker `b`.
    B,
}

/// A marker quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum What {
    /// The position `p`.
    Pos,
    /// Axis `k` (0, 1, 2 for x, y, z).
    Axis(usize),
    /// A constant vector.
    Const(Vector3<f64>),
}

/// A coefficient: constant, or `cos`/`sin` of a driver's value.
#[derive(Clone, Debug)]
pub enum Coef {
    /// A number.
    Const(f64),
    /// `cos f(t)`.
    Cos(Driver),
    /// `sin f(t)`.
    Sin(Driver),
}

impl Coef {
    /// `[c, ċ, c̈]` at `t`.
    pub fn eval(&self, t: f64) -> [f64; 3] {
        match self {
            Coef::Const(c) => [*c, 0.0, 0.0],
            Coef::Cos(d) => {
                let [f, fd, fdd] = d.eval(t);
                let (s, c) = f.sin_cos();
                [c, -s * fd, -c * fd * fd - s * fdd]
            }
            Coef::Sin(d) => {
                let [f, fd, fdd] = d.eval(t);
                let (s, c) = f.sin_cos();
                [s, c * fd, -s * fd * fd + c * fdd]
            }
        }
    }
}

/// One term `c · quantity(side)`.
#[derive(Clone, Debug)]
pub struct Term {
    /// Coefficient.
    pub coef: Coef,
    /// Which marker.
    pub side: Side,
    /// Which quantity.
    pub what: What,
}

impl Term {
    /// `c · what(side)`, constant `c`.
    pub fn new(c: f64, side: Side, what: What) -> Self {
        Self {
            coef: Coef::Const(c),
            side,
            what,
        }
    }
}

/// One scalar constraint `V₁ · V₂ − f(t) = 0` between markers `a` and `b`.
#[derive(Clone, Debug)]
pub struct Row {
    /// `V₁`.
    pub v1: Vec<Term>,
    /// `V₂`.
    pub v2: Vec<Term>,
    /// `f(t)` (`None`: zero).
    pub offset: Option<Driver>,
}

/// A constraint: two markers and the rows they satisfy.
#[derive(Clone, Debug)]
pub struct Constraint {
    /// What it is (for messages): `revolute`, `fixed`, …
    pub kind: String,
    /// Marker `a`.
    pub a: Marker,
    /// Marker `b`.
    pub b: Marker,
    /// Its scalar equations.
    pub rows: Vec<Row>,
}

/// A vector quantity with its derivatives over the constraint's local
/// coordinates (those of `a`, then those of `b`).
pub(crate) struct VecEval {
    pub val: Vector3<f64>,
    /// `∂V/∂q_i` (value at `t`).
    pub d: Vec<Vector3<f64>>,
    /// `∂V/∂t` (from time-dependent coefficients).
    pub dt: Vector3<f64>,
    /// `∂²V/∂t²`.
    pub dtt: Vector3<f64>,
    /// `∂(∂V/∂q_i)/∂t`.
    pub dqt: Vec<Vector3<f64>>,
}

impl VecEval {
    pub fn new(n: usize) -> Self {
        let z = Vector3::zeros();
        Self {
            val: z,
            d: vec![z; n],
            dt: z,
            dtt: z,
            dqt: vec![z; n],
        }
    }
}

fn quantity(k: &MarkerKin, what: What) -> (Vector3<f64>, &[Vector3<f64>]) {
    match what {
        What::Pos => (k.pos, &k.dpos),
        What::Axis(i) => (k.axes[i], &k.daxes[i]),
        What::Const(c) => (c, &[]),
    }
}

/// Evaluate `V = Σ c_i · quantity_i` and its derivatives.
pub(crate) fn eval_vec(terms: &[Term], ka: &MarkerKin, kb: &MarkerKin, t: f64, out: &mut VecEval) {
    let z = Vector3::zeros();
    out.val = z;
    out.dt = z;
    out.dtt = z;
    out.d.iter_mut().for_each(|x| *x = z);
    out.dqt.iter_mut().for_each(|x| *x = z);
    let na = ka.len();
    for term in terms {
        let [c, cd, cdd] = term.coef.eval(t);
        let (k, shift) = match term.side {
            Side::A => (ka, 0),
            Side::B => (kb, na),
        };
        let (v, dv) = quantity(k, term.what);
        out.val += v * c;
        out.dt += v * cd;
        out.dtt += v * cdd;
        for (i, d) in dv.iter().enumerate() {
            out.d[shift + i] += d * c;
            out.dqt[shift + i] += d * cd;
        }
    }
}

/// `Σ_i Σ_j w_i w_j ∂²V/∂q_i∂q_j` … contracted forms of the second
/// derivatives of `V` (block-diagonal over the two markers).
pub(crate) fn d2_vec(
    terms: &[Term],
    ka: &MarkerKin,
    kb: &MarkerKin,
    t: f64,
    i: usize,
    j: usize,
) -> Vector3<f64> {
    let na = ka.len();
    let (side, ii, jj) = match (i < na, j < na) {
        (true, true) => (Side::A, i, j),
        (false, false) => (Side::B, i - na, j - na),
        _ => return Vector3::zeros(),
    };
    let k = if side == Side::A { ka } else { kb };
    let mut s = Vector3::zeros();
    for term in terms.iter().filter(|x| x.side == side) {
        let c = term.coef.eval(t)[0];
        match term.what {
            What::Pos => s += k.d2pos(ii, jj) * c,
            What::Axis(a) => s += k.d2axis(a, ii, jj) * c,
            What::Const(_) => {}
        }
    }
    s
}

/// The value and derivatives of one constraint row.
pub(crate) struct RowEval {
    /// `Φ`.
    pub phi: f64,
    /// `∂Φ/∂q` over the local coordinates.
    pub grad: Vec<f64>,
    /// `∂Φ/∂t`.
    pub phi_t: f64,
    pub v1: VecEval,
    pub v2: VecEval,
}

impl RowEval {
    pub fn new(n: usize) -> Self {
        Self {
            phi: 0.0,
            grad: vec![0.0; n],
            phi_t: 0.0,
            v1: VecEval::new(n),
            v2: VecEval::new(n),
        }
    }

    /// `Φ`, `∂Φ/∂q`, `∂Φ/∂t` of `row` at time `t`.
    pub fn eval(&mut self, row: &Row, ka: &MarkerKin, kb: &MarkerKin, t: f64) {
        eval_vec(&row.v1, ka, kb, t, &mut self.v1);
        eval_vec(&row.v2, ka, kb, t, &mut self.v2);
        let [f, fd, _] = row.offset.as_ref().map_or([0.0; 3], |d| d.eval(t));
        self.phi = self.v1.val.dot(&self.v2.val) - f;
        self.phi_t = self.v1.dt.dot(&self.v2.val) + self.v1.val.dot(&self.v2.dt) - fd;
        for i in 0..self.grad.len() {
            self.grad[i] = self.v1.d[i].dot(&self.v2.val) + self.v1.val.dot(&self.v2.d[i]);
        }
    }

    /// `∂²Φ/∂q_i∂q_j` (after [`RowEval::eval`]).
    pub fn hess(
        &self,
        row: &Row,
        ka: &MarkerKin,
        kb: &MarkerKin,
        t: f64,
        i: usize,
        j: usize,
    ) -> f64 {
        d2_vec(&row.v1, ka, kb, t, i, j).dot(&self.v2.val)
            + self.v1.d[i].dot(&self.v2.d[j])
            + self.v1.d[j].dot(&self.v2.d[i])
            + self.v1.val.dot(&d2_vec(&row.v2, ka, kb, t, i, j))
    }

    /// `γ = −(q̇ᵀ Φ_qq q̇ + 2 Φ_qt q̇ + Φ_tt)` for local velocities `qd`.
    pub fn gamma(&self, row: &Row, ka: &MarkerKin, kb: &MarkerKin, t: f64, qd: &[f64]) -> f64 {
        let n = qd.len();
        let mut quad = 0.0;
        for i in 0..n {
            if qd[i] == 0.0 {
                continue;
            }
            for j in 0..n {
                if qd[j] != 0.0 {
                    quad += qd[i] * qd[j] * self.hess(row, ka, kb, t, i, j);
                }
            }
        }
        let mut qt = 0.0;
        for (i, qd_i) in qd.iter().enumerate() {
            qt += qd_i
                * (self.v1.dqt[i].dot(&self.v2.val)
                    + self.v1.d[i].dot(&self.v2.dt)
                    + self.v1.dt.dot(&self.v2.d[i])
                    + self.v1.val.dot(&self.v2.dqt[i]));
        }
        let fdd = row.offset.as_ref().map_or(0.0, |d| d.eval(t)[2]);
        let tt = self.v1.dtt.dot(&self.v2.val)
            + 2.0 * self.v1.dt.dot(&self.v2.dt)
            + self.v1.val.dot(&self.v2.dtt)
            - fdd;
        -(quad + 2.0 * qt + tt)
    }
}

/// `H = Σ_r λ_r ∂²Φ_r/∂q_i∂q_j` over the constraint's local coordinates
/// (those of `a`, then those of `b`; row-major `n × n`, overwritten), after
/// [`RowEval::eval`] of every row: the same sum as [`RowEval::hess`] row by
/// row, with the markers' second derivatives contracted once with the
/// weights `Σ_r λ_r c_t V₂` (and `V₁`) of each quantity they enter.
#[allow(clippy::too_many_arguments)]
pub(crate) fn contracted_hessian(
    rows: &[Row],
    evals: &[RowEval],
    ka: &MarkerKin,
    kb: &MarkerKin,
    t: f64,
    lam: &[f64],
    out: &mut [f64],
) {
    let na = ka.len();
    let n = na + kb.len();
    out[..n * n].iter_mut().for_each(|x| *x = 0.0);
    let z = Vector3::zeros();
    let mut w_pos = [z; 2];
    let mut w_axes = [[z; 3]; 2];
    for ((row, ev), &l) in rows.iter().zip(evals).zip(lam) {
        if l == 0.0 {
            continue;
        }
        for (terms, other) in [(&row.v1, &ev.v2.val), (&row.v2, &ev.v1.val)] {
            for term in terms {
                let c = term.coef.eval(t)[0] * l;
                let side = usize::from(term.side == Side::B);
                match term.what {
                    What::Pos => w_pos[side] += other * c,
                    What::Axis(k) => w_axes[side][k] += other * c,
                    What::Const(_) => {}
                }
            }
        }
        // λ (∂V₁/∂q_i · ∂V₂/∂q_j + ∂V₁/∂q_j · ∂V₂/∂q_i).
        for i in 0..n {
            let (d1, d2) = (&ev.v1.d[i], &ev.v2.d[i]);
            if *d1 == z && *d2 == z {
                continue;
            }
            let (d1, d2) = (d1 * l, d2 * l);
            for j in 0..n {
                out[i * n + j] += d1.dot(&ev.v2.d[j]) + ev.v1.d[j].dot(&d2);
            }
        }
    }
    ka.add_contracted_hessian(&w_pos[0], &w_axes[0], out, n, 0);
    kb.add_contracted_hessian(&w_pos[1], &w_axes[1], out, n, na);
}

/// Rows of coincident points: `(p_b − p_a) · e_k = 0`, `k < d`.
pub fn coincident_rows(d: usize) -> Vec<Row> {
    (0..d)
        .map(|k| {
            let mut e = Vector3::zeros();
            e[k] = 1.0;
            Row {
                v1: vec![
                    Term::new(1.0, Side::B, What::Pos),
                    Term::new(-1.0, Side::A, What::Pos),
                ],
                v2: vec![Term::new(1.0, Side::A, What::Const(e))],
                offset: None,
            }
        })
        .collect()
}

/// `a_i · b_j = 0`.
pub fn perpendicular_row(i: usize, j: usize) -> Row {
    Row {
        v1: vec![Term::new(1.0, Side::A, What::Axis(i))],
        v2: vec![Term::new(1.0, Side::B, What::Axis(j))],
        offset: None,
    }
}

/// `x_b · (cos f · y_a − sin f · x_a) = 0`: `b` turned by `f(t)` about `z_a`.
pub fn angle_row(driver: Driver) -> Row {
    Row {
        v1: vec![Term::new(1.0, Side::B, What::Axis(0))],
        v2: vec![
            Term {
                coef: Coef::Cos(driver.clone()),
                side: Side::A,
                what: What::Axis(1),
            },
            Term {
                coef: Coef::Sin(driver.map(|[f, fd, fdd]| [-f, -fd, -fdd])),
                side: Side::A,
                what: What::Axis(0),
            },
        ],
        offset: None,
    }
}

/// `(p_b − p_a) · a_i − f(t) = 0`.
pub fn offset_row(i: usize, f: Option<Driver>) -> Row {
    Row {
        v1: vec![
            Term::new(1.0, Side::B, What::Pos),
            Term::new(-1.0, Side::A, What::Pos),
        ],
        v2: vec![Term::new(1.0, Side::A, What::Axis(i))],
        offset: f,
    }
}
