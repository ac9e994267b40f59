//! Exact sparse multivariate polynomials with rational coefficients.
//!
//! A [`Poly`] is `Σ c_m · m` over monomials `m = Π s_i^{e_i}` of [`Sym`]bols.
//! Exponents are signed so that parameters may appear as Laurent powers after
//! section integration (`I_z / l²`); the integration variables `ξ, η, ζ` and
//! the elastic coordinates never get negative powers (the parser refuses them
//! and no operation here creates them).

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::collections::BTreeMap;
use std::fmt;

/// Exact rational number.
pub type Rational = BigRational;

/// `n / d` as an exact rational.
pub fn rat(n: i64, d: i64) -> Rational {
    BigRational::new(BigInt::from(n), BigInt::from(d))
}

/// The nearest `f64` to an exact rational (round to nearest, ties to even).
pub fn to_f64(r: &Rational) -> f64 {
    r.to_f64().unwrap_or_else(|| {
        if r.is_negative() {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        }
    })
}

/// A symbol of the generator's algebra.
///
/// Order matters: it fixes the canonical order of monomials and therefore the
/// order of terms in generated code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Sym {
    /// Element coordinate `ξ = (x − x₀)/l ∈ [0, 1]`.
    Xi,
    /// `η = y / l`.
    Eta,
    /// `ζ = z / l`.
    Zeta,
    /// A body parameter (element or body length, density, section, material).
    Param(Param),
    /// The element moment `μ_{P,k} = ∫₀¹ P(ξ) ξ^k dξ` of a section property
    /// (varying sections: a per-element coefficient input, like a parameter).
    Moment(SectionProp, u8),
    /// Kernel input: the element's offset `x₀` along body x.
    X0,
    /// Kernel input: the frame motion in body axes, `0..3` `ā = Aᵀ(R̈ − g)`,
    /// `3..6` `α = ω̄̇`, `6..9` `ω = ω̄`.
    Frame(u8),
    /// Kernel input: generalized-α `β'` (`∂q̈/∂q`).
    Bp,
    /// Kernel input: generalized-α `γ'` (`∂q̇/∂q`).
    Gp,
    /// Elastic (or local) coordinate `q[i]`.
    Q(u32),
    /// Its velocity `q̇[i]`.
    Qd(u32),
    /// Its acceleration `q̈[i]`.
    Qdd(u32),
    /// An intermediate quantity bound earlier in a program (element scalars,
    /// derivatives of an energy with respect to them).
    Z(u32),
}

/// Names of the frame inputs (`Sym::Frame(k)`).
pub const FRAME_NAMES: [&str; 9] = [
    "a_x", "a_y", "a_z", "alpha_x", "alpha_y", "alpha_z", "w_x", "w_y", "w_z",
];

pub use ffr_spec::{Param, SectionProp};

impl Sym {
    /// Whether the symbol is folded into coefficients (a parameter or an
    /// element moment) rather than read by a kernel call.
    pub fn is_coefficient(self) -> bool {
        matches!(self, Sym::Param(_) | Sym::Moment(..))
    }
}

impl fmt::Display for Sym {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Sym::Xi => write!(f, "xi"),
            Sym::Eta => write!(f, "eta"),
            Sym::Zeta => write!(f, "zeta"),
            Sym::Param(p) => write!(f, "{}", p.field()),
            Sym::Moment(p, k) => write!(f, "mu_{}_{k}", p.name()),
            Sym::X0 => write!(f, "x0"),
            Sym::Frame(k) => write!(f, "{}", FRAME_NAMES[*k as usize]),
            Sym::Bp => write!(f, "bp"),
            Sym::Gp => write!(f, "gp"),
            Sym::Q(i) => write!(f, "q{i}"),
            Sym::Qd(i) => write!(f, "qd{i}"),
            Sym::Qdd(i) => write!(f, "qdd{i}"),
            Sym::Z(i) => write!(f, "z{i}"),
        }
    }
}

/// A monomial: symbols with non-zero exponents, sorted by symbol.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Monomial(Vec<(Sym, i32)>);

impl Monomial {
    /// The monomial `1`.
    pub fn one() -> Self {
        Monomial(Vec::new())
    }

    /// `s^e`.
    pub fn var(s: Sym, e: i32) -> Self {
        if e == 0 {
            Self::one()
        } else {
            Monomial(vec![(s, e)])
        }
    }

    /// The factors `(symbol, exponent)` in canonical order.
    pub fn factors(&self) -> &[(Sym, i32)] {
        &self.0
    }

    /// Exponent of `s`.
    pub fn exp(&self, s: Sym) -> i32 {
        self.0.iter().find(|(t, _)| *t == s).map_or(0, |&(_, e)| e)
    }

    /// Whether this is the constant monomial.
    pub fn is_one(&self) -> bool {
        self.0.is_empty()
    }

    /// Product of two monomials.
    pub fn mul(&self, other: &Monomial) -> Monomial {
        let (a, b) = (&self.0, &other.0);
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            if j == b.len() || (i < a.len() && a[i].0 < b[j].0) {
                out.push(a[i]);
                i += 1;
            } else if i == a.len() || b[j].0 < a[i].0 {
                out.push(b[j]);
                j += 1;
            } else {
                // Shape files are limited (crate::limits) so that exponents
                // stay far inside i32; never wrap silently.
                let e = a[i].1.checked_add(b[j].1).unwrap_or_else(|| {
                    panic!(
                        "exponent overflow: {}^{} · {}^{} does not fit in i32 (a bug: crate::limits should have refused the input)",
                        a[i].0, a[i].1, b[j].0, b[j].1
                    )
                });
                if e != 0 {
                    out.push((a[i].0, e));
                }
                i += 1;
                j += 1;
            }
        }
        Monomial(out)
    }

    /// The monomial with `s` removed, and the exponent it had.
    pub fn without(&self, s: Sym) -> (Monomial, i32) {
        let e = self.exp(s);
        (
            Monomial(self.0.iter().copied().filter(|(t, _)| *t != s).collect()),
            e,
        )
    }

    /// Split into the part made of symbols accepted by `pred` and the rest.
    pub fn split(&self, pred: impl Fn(Sym) -> bool) -> (Monomial, Monomial) {
        let (a, b): (Vec<_>, Vec<_>) = self.0.iter().partition(|(s, _)| pred(*s));
        (Monomial(a), Monomial(b))
    }
}

impl fmt::Display for Monomial {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return write!(f, "1");
        }
        for (k, (s, e)) in self.0.iter().enumerate() {
            if k > 0 {
                write!(f, "*")?;
            }
            if *e == 1 {
                write!(f, "{s}")?;
            } else {
                write!(f, "{s}^{e}")?;
            }
        }
        Ok(())
    }
}

/// Sparse polynomial `Σ c_m · m` with exact rational coefficients; no zero terms.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Poly {
    terms: BTreeMap<Monomial, Rational>,
}

impl Poly {
    /// The zero polynomial.
    pub fn zero() -> Self {
        Self::default()
    }

    /// A constant.
    pub fn constant(c: Rational) -> Self {
        Self::term(c, Monomial::one())
    }

    /// The integer constant `n`.
    pub fn int(n: i64) -> Self {
        Self::constant(rat(n, 1))
    }

    /// `c · m`.
    pub fn term(c: Rational, m: Monomial) -> Self {
        let mut p = Self::zero();
        p.add_term(m, c);
        p
    }

    /// The symbol `s`.
    pub fn var(s: Sym) -> Self {
        Self::term(Rational::one(), Monomial::var(s, 1))
    }

    /// Whether every coefficient is zero.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// Terms in canonical monomial order.
    pub fn terms(&self) -> impl Iterator<Item = (&Monomial, &Rational)> {
        self.terms.iter()
    }

    /// Number of terms.
    pub fn len(&self) -> usize {
        self.terms.len()
    }

    /// Whether the polynomial has no terms.
    pub fn is_empty(&self) -> bool {
        self.terms.is_empty()
    }

    /// Add `c · m` in place.
    pub fn add_term(&mut self, m: Monomial, c: Rational) {
        if c.is_zero() {
            return;
        }
        match self.terms.entry(m) {
            std::collections::btree_map::Entry::Vacant(v) => {
                v.insert(c);
            }
            std::collections::btree_map::Entry::Occupied(mut o) => {
                *o.get_mut() += c;
                if o.get().is_zero() {
                    o.remove();
                }
            }
        }
    }

    /// `self += other`.
    pub fn add_assign(&mut self, other: &Poly) {
        for (m, c) in &other.terms {
            self.add_term(m.clone(), c.clone());
        }
    }

    /// `self += k · other`.
    pub fn add_scaled(&mut self, k: &Rational, other: &Poly) {
        for (m, c) in &other.terms {
            self.add_term(m.clone(), c * k);
        }
    }

    /// `self + other`.
    pub fn add(&self, other: &Poly) -> Poly {
        let mut p = self.clone();
        p.add_assign(other);
        p
    }

    /// `self − other`.
    pub fn sub(&self, other: &Poly) -> Poly {
        let mut p = self.clone();
        p.add_scaled(&-Rational::one(), other);
        p
    }

    /// `k · self`.
    pub fn scale(&self, k: &Rational) -> Poly {
        let mut p = Poly::zero();
        p.add_scaled(k, self);
        p
    }

    /// `self · other`.
    pub fn mul(&self, other: &Poly) -> Poly {
        let mut p = Poly::zero();
        for (ma, ca) in &self.terms {
            for (mb, cb) in &other.terms {
                p.add_term(ma.mul(mb), ca * cb);
            }
        }
        p
    }

    /// `self · m`.
    pub fn mul_monomial(&self, m: &Monomial) -> Poly {
        Poly {
            terms: self
                .terms
                .iter()
                .map(|(k, c)| (k.mul(m), c.clone()))
                .collect(),
        }
    }

    /// `self^n` (exponents checked through [`Monomial::mul`]).
    pub fn pow(&self, n: u32) -> Poly {
        let mut p = Poly::int(1);
        for _ in 0..n {
            p = p.mul(self);
        }
        p
    }

    /// `∂ self / ∂ s`.
    pub fn diff(&self, s: Sym) -> Poly {
        let mut p = Poly::zero();
        for (m, c) in &self.terms {
            let (rest, e) = m.without(s);
            if e != 0 {
                p.add_term(rest.mul(&Monomial::var(s, e - 1)), c * rat(e as i64, 1));
            }
        }
        p
    }

    /// Replace every occurrence of `s` by the polynomial `value`
    /// (`s` must have non-negative exponents).
    pub fn substitute(&self, s: Sym, value: &Poly) -> Poly {
        let mut p = Poly::zero();
        for (m, c) in &self.terms {
            let (rest, e) = m.without(s);
            assert!(e >= 0, "substitute: negative power of {s}");
            let v = value.pow(e as u32).mul_monomial(&rest).scale(c);
            p.add_assign(&v);
        }
        p
    }

    /// Replace `s` by `k · t` for a rational `k` and a symbol `t`, allowing
    /// negative powers of `s` (a change of scale, e.g. `l = L / N`).
    pub fn rescale(&self, s: Sym, k: &Rational, t: Sym) -> Poly {
        let mut p = Poly::zero();
        for (m, c) in &self.terms {
            let (rest, e) = m.without(s);
            let f = if e >= 0 {
                num_traits::pow(k.clone(), e as usize)
            } else {
                num_traits::pow(k.recip(), (-e) as usize)
            };
            p.add_term(rest.mul(&Monomial::var(t, e)), c * f);
        }
        p
    }

    /// Rename symbols through `f` (which must be injective on the symbols present);
    /// a symbol mapped to `None` is set to zero.
    pub fn rename(&self, f: impl Fn(Sym) -> Option<Sym>) -> Poly {
        let mut p = Poly::zero();
        'terms: for (m, c) in &self.terms {
            let mut out = Monomial::one();
            for &(s, e) in m.factors() {
                match f(s) {
                    Some(t) => out = out.mul(&Monomial::var(t, e)),
                    None => continue 'terms,
                }
            }
            p.add_term(out, c.clone());
        }
        p
    }

    /// `∫₀¹ self dξ` (ξ appears with non-negative powers only).
    pub fn integrate_xi(&self) -> Poly {
        let mut p = Poly::zero();
        for (m, c) in &self.terms {
            let (rest, e) = m.without(Sym::Xi);
            p.add_term(rest, c * rat(1, e as i64 + 1));
        }
        p
    }

    /// Whether any term contains `s`.
    pub fn contains(&self, s: Sym) -> bool {
        self.terms.keys().any(|m| m.exp(s) != 0)
    }

    /// The constant term's coefficient if the polynomial is a constant.
    pub fn as_constant(&self) -> Option<Rational> {
        match self.terms.len() {
            0 => Some(Rational::zero()),
            1 => self
                .terms
                .iter()
                .next()
                .filter(|(m, _)| m.is_one())
                .map(|(_, c)| c.clone()),
            _ => None,
        }
    }
}

impl fmt::Display for Poly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.terms.is_empty() {
            return write!(f, "0");
        }
        for (k, (m, c)) in self.terms.iter().enumerate() {
            let neg = c.is_negative();
            let a = c.abs();
            match (k, neg) {
                (0, true) => write!(f, "-")?,
                (0, false) => {}
                (_, true) => write!(f, " - ")?,
                (_, false) => write!(f, " + ")?,
            }
            if m.is_one() {
                write!(f, "{a}")?;
            } else if a.is_one() {
                write!(f, "{m}")?;
            } else {
                write!(f, "{a}*{m}")?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn to_f64_is_correctly_rounded_for_small_ratios() {
        // IEEE division of two exactly representable integers is correctly rounded.
        for n in -50i64..50 {
            for d in 1i64..60 {
                assert_eq!(to_f64(&rat(n, d)), n as f64 / d as f64, "{n}/{d}");
            }
        }
        let big = rat(1, 3) * rat(1i64 << 62, 1) * rat(1i64 << 62, 1);
        assert_eq!(to_f64(&big), 2f64.powi(124) / 3.0);
    }

    #[test]
    fn algebra() {
        let x = Poly::var(Sym::Xi);
        let one = Poly::int(1);
        let p = one.sub(&x).mul(&one.add(&x)); // 1 - xi^2
        assert_eq!(p.to_string(), "1 - xi^2");
        assert_eq!(p.diff(Sym::Xi).to_string(), "-2*xi");
        assert_eq!(p.integrate_xi().as_constant(), Some(rat(2, 3)));
        let l = Sym::Param(Param::ElemLength);
        let q = Poly::term(rat(3, 1), Monomial::var(l, -2));
        let r = q.rescale(l, &rat(1, 4), Sym::Param(Param::Length));
        assert_eq!(r.to_string(), "48*length^-2");
        assert!(p.sub(&p).is_zero());
    }
}
