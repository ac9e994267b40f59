//! Parser of the polynomial strings in a shape file.
//!
//! Grammar (`^` binds tighter than unary minus, as in mathematics):
//!
//! ```text
//! expr   = term { ("+" | "-") term }
//! term   = unary { ("*" | "/") unary }       // "/" only by a non-zero constant
//! unary  = { "+" | "-" } power
//! power  = atom [ "^" integer ]              // 0 ≤ integer ≤ MAX_EXPONENT
//! atom   = number | symbol | "(" expr ")"
//! symbol = "xi" | "eta" | "zeta" | "l"
//! number = digits [ "." digits ] [ ("e" | "E") [sign] digits ]   // read exactly
//! ```
//!
//! Arithmetic is exact, within the limits of [`crate::limits`]: parentheses
//! nest at most [`MAX_NESTING_DEPTH`] deep (the parser recurses only there;
//! signs are read in a loop), every intermediate result stays within
//! [`MAX_SYMBOL_DEGREE`], [`MAX_L_DEGREE`], [`MAX_TOTAL_DEGREE`], [`MAX_ENTRY_TERMS`] and
//! [`MAX_COEFFICIENT_BITS`], and a power is refused *before* it is expanded
//! when its degree, number of terms or coefficient size would exceed them.

use crate::limits::{
    MAX_COEFFICIENT_BITS, MAX_ENTRY_TERMS, MAX_EXPONENT, MAX_L_DEGREE, MAX_NESTING_DEPTH,
    MAX_SYMBOL_DEGREE, MAX_TOTAL_DEGREE,
};
use crate::poly::{Param, Poly, Rational, Sym};
use num_bigint::BigInt;
use num_traits::{One, Zero};

/// What went wrong in a polynomial string, at which byte offset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExprError {
    /// Byte offset into the string.
    pub offset: usize,
    /// What was found and what was expected.
    pub message: String,
}

/// The symbols a shape entry may use.
pub const SYMBOLS: &[&str] = &["xi", "eta", "zeta", "l"];

/// Parse a polynomial in `xi, eta, zeta, l` with exact rational coefficients.
pub fn parse_poly(src: &str) -> Result<Poly, ExprError> {
    let mut p = Parser {
        src,
        pos: 0,
        depth: 0,
    };
    p.skip_ws();
    if p.pos == src.len() {
        return Err(p.error("expected a polynomial, found an empty string"));
    }
    let e = p.expr()?;
    p.skip_ws();
    if p.pos < src.len() {
        let c = p.peek().unwrap_or(' ');
        let shown = if c == ')' {
            "`)` without a matching `(`".to_string()
        } else {
            format!("`{}`", crate::sanitize::snippet(&c.to_string(), 1))
        };
        return Err(p.error(&format!(
            "unexpected {shown}: expected an operator (`+ - * / ^`) or the end of the expression"
        )));
    }
    Ok(e)
}

/// Degrees, size and coefficient bits of a polynomial in the shape symbols.
#[derive(Clone, Copy, Debug, Default)]
struct Size {
    /// Highest exponent of xi, eta, zeta, l.
    degree: [u64; 4],
    /// Highest total degree of a term.
    total: u64,
    /// Number of terms.
    terms: usize,
    /// Most bits of a numerator or denominator.
    bits: u64,
}

const SYMBOL_ORDER: [Sym; 4] = [Sym::Xi, Sym::Eta, Sym::Zeta, Sym::Param(Param::ElemLength)];

/// The degree limit of symbol `i` of [`SYMBOL_ORDER`], and its name.
fn degree_limit(i: usize) -> (u64, &'static str) {
    if i == 3 {
        (MAX_L_DEGREE as u64, "MAX_L_DEGREE")
    } else {
        (MAX_SYMBOL_DEGREE as u64, "MAX_SYMBOL_DEGREE")
    }
}

fn size(p: &Poly) -> Size {
    let mut s = Size {
        terms: p.len(),
        ..Size::default()
    };
    for (m, c) in p.terms() {
        let mut total = 0u64;
        for &(sym, e) in m.factors() {
            let e = e.unsigned_abs() as u64;
            if let Some(i) = SYMBOL_ORDER.iter().position(|&t| t == sym) {
                s.degree[i] = s.degree[i].max(e);
            }
            total += e;
        }
        s.total = s.total.max(total);
        s.bits = s.bits.max(c.numer().bits()).max(c.denom().bits());
    }
    s
}

/// The number of monomials of degree at most `n` in `k` variables, `C(n + k, k)`,
/// saturating (an upper bound on the terms of a power of a `k`-term sum).
fn multinomial_bound(k: usize, n: u64) -> f64 {
    // Terms of (t_1 + … + t_k)^n: C(n + k − 1, n).
    let mut r = 1.0f64;
    for i in 1..=n {
        r = r * (k as f64 - 1.0 + i as f64) / i as f64;
    }
    r
}

struct Parser<'a> {
    src: &'a str,
    pos: usize,
    depth: usize,
}

impl Parser<'_> {
    fn error(&self, msg: &str) -> ExprError {
        ExprError {
            offset: self.pos,
            message: msg.to_string(),
        }
    }

    fn error_at(&self, offset: usize, msg: &str) -> ExprError {
        ExprError {
            offset,
            message: msg.to_string(),
        }
    }

    fn peek(&self) -> Option<char> {
        self.src[self.pos..].chars().next()
    }

    fn skip_ws(&mut self) {
        while let Some(c) = self.peek() {
            if c.is_whitespace() {
                self.pos += c.len_utf8();
            } else {
                break;
            }
        }
    }

    fn eat(&mut self, c: char) -> bool {
        self.skip_ws();
        if self.peek() == Some(c) {
            self.pos += c.len_utf8();
            true
        } else {
            false
        }
    }

    /// Check an intermediate or final result against the limits; `at` is the
    /// operator that produced it, `what` describes it.
    fn check(&self, p: &Poly, at: usize, what: &str) -> Result<(), ExprError> {
        let s = size(p);
        for (i, &d) in s.degree.iter().enumerate() {
            let (max, name) = degree_limit(i);
            if d > max {
                return Err(self.error_at(
                    at,
                    &format!(
                        "{what} has degree {d} in {}: more than the limit of {max} ({name})",
                        SYMBOL_ORDER[i]
                    ),
                ));
            }
        }
        if s.total > MAX_TOTAL_DEGREE as u64 {
            return Err(self.error_at(
                at,
                &format!(
                    "{what} has total degree {}: more than the limit of {MAX_TOTAL_DEGREE} (MAX_TOTAL_DEGREE)",
                    s.total
                ),
            ));
        }
        if s.terms > MAX_ENTRY_TERMS {
            return Err(self.error_at(
                at,
                &format!(
                    "{what} has {} terms after expansion: more than the limit of {MAX_ENTRY_TERMS} (MAX_ENTRY_TERMS)",
                    s.terms
                ),
            ));
        }
        if s.bits > MAX_COEFFICIENT_BITS {
            return Err(self.error_at(
                at,
                &format!(
                    "{what} has a coefficient of {} bits: more than the limit of {MAX_COEFFICIENT_BITS} bits (MAX_COEFFICIENT_BITS, about 38 decimal digits)",
                    s.bits
                ),
            ));
        }
        Ok(())
    }

    /// `a · b`, refused before multiplying when the degrees would exceed
    /// the limits (degrees add exactly for non-zero factors).
    fn mul(&self, a: &Poly, b: &Poly, at: usize) -> Result<Poly, ExprError> {
        if a.is_zero() || b.is_zero() {
            return Ok(Poly::zero());
        }
        let (sa, sb) = (size(a), size(b));
        for (i, symbol) in SYMBOL_ORDER.iter().enumerate() {
            let d = sa.degree[i] + sb.degree[i];
            let (max, name) = degree_limit(i);
            if d > max {
                return Err(self.error_at(
                    at,
                    &format!(
                        "this product has degree {d} in {}: more than the limit of {max} ({name})",
                        symbol
                    ),
                ));
            }
        }
        let p = a.mul(b);
        self.check(&p, at, "this product")?;
        Ok(p)
    }

    fn expr(&mut self) -> Result<Poly, ExprError> {
        let mut acc = self.term()?;
        loop {
            self.skip_ws();
            let at = self.pos;
            if self.eat('+') {
                acc.add_assign(&self.term()?);
            } else if self.eat('-') {
                acc.add_scaled(&-Rational::one(), &self.term()?);
            } else {
                return Ok(acc);
            }
            self.check(&acc, at, "this sum")?;
        }
    }

    fn term(&mut self) -> Result<Poly, ExprError> {
        let mut acc = self.unary()?;
        loop {
            self.skip_ws();
            if self.src[self.pos..].starts_with("**") {
                return Err(self.error("`**` is not an operator here: write powers as `x^2`"));
            }
            let op = self.pos;
            if self.eat('*') {
                let rhs = self.unary()?;
                acc = self.mul(&acc, &rhs, op)?;
            } else if self.eat('/') {
                self.skip_ws();
                let at = self.pos;
                let d = self.unary()?;
                match d.as_constant() {
                    Some(c) if c.is_zero() => {
                        return Err(self.error_at(at, "division by zero"));
                    }
                    Some(c) => {
                        acc = acc.scale(&c.recip());
                        self.check(&acc, op, "this quotient")?;
                    }
                    None => {
                        return Err(self.error_at(
                            at,
                            &format!(
                                "division by `{}` is not polynomial: only division by a non-zero number is allowed",
                                crate::sanitize::snippet(&d.to_string(), 60)
                            ),
                        ));
                    }
                }
            } else {
                return Ok(acc);
            }
        }
    }

    /// Signs are read in a loop: any number of them costs no stack.
    fn unary(&mut self) -> Result<Poly, ExprError> {
        let mut negative = false;
        loop {
            if self.eat('-') {
                negative = !negative;
            } else if !self.eat('+') {
                break;
            }
        }
        let p = self.power()?;
        Ok(if negative {
            p.scale(&-Rational::one())
        } else {
            p
        })
    }

    fn power(&mut self) -> Result<Poly, ExprError> {
        let base = self.atom()?;
        self.skip_ws();
        let caret = self.pos;
        if !self.eat('^') {
            return Ok(base);
        }
        self.skip_ws();
        let at = self.pos;
        let negative = self.eat('-');
        self.skip_ws();
        let start = self.pos;
        while matches!(self.peek(), Some(c) if c.is_ascii_digit()) {
            self.pos += 1;
        }
        if self.pos == start {
            let hint = if self.peek() == Some('(') {
                ": the exponent must be a number written out, not an expression"
            } else {
                ""
            };
            return Err(self.error_at(at, &format!("expected a whole number after `^`{hint}")));
        }
        if self.peek() == Some('.') {
            return Err(self.error_at(
                at,
                "fractional powers are not polynomial: expected a whole number after `^`",
            ));
        }
        if negative {
            return Err(self.error_at(
                at,
                "negative powers are not polynomial: expected a whole number ≥ 0 after `^`",
            ));
        }
        let digits = self.src[start..self.pos].trim_start_matches('0');
        let n: u32 = if digits.is_empty() {
            0
        } else {
            digits
                .parse()
                .ok()
                .filter(|&n| n <= MAX_EXPONENT)
                .ok_or_else(|| {
                    self.error_at(
                        start,
                        &format!(
                            "power too large: at most {MAX_EXPONENT} (MAX_EXPONENT), found {}",
                            crate::sanitize::snippet(&self.src[start..self.pos], 24)
                        ),
                    )
                })?
        };
        self.pow(&base, n, caret)
    }

    /// `base^n`, refused before it is expanded when its degree, terms or
    /// coefficients would exceed the limits.
    fn pow(&self, base: &Poly, n: u32, at: usize) -> Result<Poly, ExprError> {
        if n == 0 {
            return Ok(Poly::int(1));
        }
        if base.is_zero() || n == 1 {
            return Ok(base.clone());
        }
        let s = size(base);
        let n64 = n as u64;
        for (i, symbol) in SYMBOL_ORDER.iter().enumerate() {
            let d = s.degree[i] * n64;
            let (max, name) = degree_limit(i);
            if d > max {
                return Err(self.error_at(
                    at,
                    &format!(
                        "`^{n}` would give degree {d} in {}: more than the limit of {max} ({name}); it is not expanded",
                        symbol
                    ),
                ));
            }
        }
        if s.total * n64 > MAX_TOTAL_DEGREE as u64 {
            return Err(self.error_at(
                at,
                &format!(
                    "`^{n}` would give total degree {}: more than the limit of {MAX_TOTAL_DEGREE} (MAX_TOTAL_DEGREE)",
                    s.total * n64
                ),
            ));
        }
        let by_degree: f64 = s.degree.iter().map(|&d| (d * n64 + 1) as f64).product();
        let terms = by_degree.min(multinomial_bound(s.terms, n64));
        if terms > MAX_ENTRY_TERMS as f64 {
            return Err(self.error_at(
                at,
                &format!(
                    "`^{n}` of a polynomial of {} terms could have up to {terms:.0} terms: more than the limit of {MAX_ENTRY_TERMS} (MAX_ENTRY_TERMS); it is not expanded",
                    s.terms
                ),
            ));
        }
        let log_terms = (usize::BITS - (s.terms - 1).leading_zeros()) as u64;
        let bits = n64 * (s.bits + log_terms);
        if bits > MAX_COEFFICIENT_BITS + n64 {
            return Err(self.error_at(
                at,
                &format!(
                    "`^{n}` could give coefficients of about {bits} bits: more than the limit of {MAX_COEFFICIENT_BITS} bits (MAX_COEFFICIENT_BITS); it is not expanded"
                ),
            ));
        }
        let p = base.pow(n);
        self.check(&p, at, "this power")?;
        Ok(p)
    }

    fn atom(&mut self) -> Result<Poly, ExprError> {
        self.skip_ws();
        let start = self.pos;
        match self.peek() {
            None => {
                Err(self
                    .error("unexpected end: expected a number, a symbol (xi, eta, zeta, l) or `(`"))
            }
            Some('(') => {
                if self.depth >= MAX_NESTING_DEPTH {
                    return Err(self.error(&format!(
                        "parentheses nest more than {MAX_NESTING_DEPTH} deep (MAX_NESTING_DEPTH)"
                    )));
                }
                self.pos += 1;
                self.depth += 1;
                let e = self.expr()?;
                self.depth -= 1;
                if !self.eat(')') {
                    let found = match self.peek() {
                        None => "the end of the expression".to_string(),
                        Some(c) => format!("`{}`", crate::sanitize::snippet(&c.to_string(), 1)),
                    };
                    return Err(self.error(&format!(
                        "expected `)` to close the `(` at offset {start}, found {found}"
                    )));
                }
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => self.number(),
            Some(c) if c.is_alphabetic() || c == '_' => {
                while matches!(self.peek(), Some(c) if c.is_alphanumeric() || c == '_') {
                    self.pos += self.peek().map_or(1, char::len_utf8);
                }
                let name = &self.src[start..self.pos];
                let shown = crate::sanitize::snippet(name, 40);
                let sym = match name {
                    "xi" => Sym::Xi,
                    "eta" => Sym::Eta,
                    "zeta" => Sym::Zeta,
                    "l" => Sym::Param(Param::ElemLength),
                    _ => {
                        self.skip_ws();
                        if self.peek() == Some('(') {
                            return Err(self.error_at(
                                start,
                                &format!("`{shown}(…)` is not polynomial: functions are not allowed, only + - * / ^ on xi, eta, zeta, l and numbers"),
                            ));
                        }
                        return Err(self.error_at(
                            start,
                            &format!("unknown symbol `{shown}`: expected one of xi, eta, zeta, l"),
                        ));
                    }
                };
                Ok(Poly::var(sym))
            }
            Some(c) => Err(self.error(&format!(
                "unexpected {}: expected a number, a symbol (xi, eta, zeta, l) or `(`",
                if c == ')' {
                    "`)`".to_string()
                } else {
                    format!("`{}`", crate::sanitize::snippet(&c.to_string(), 1))
                }
            ))),
        }
    }

    fn number(&mut self) -> Result<Poly, ExprError> {
        let start = self.pos;
        let digits = |p: &mut Self| {
            let s = p.pos;
            while matches!(p.peek(), Some(c) if c.is_ascii_digit()) {
                p.pos += 1;
            }
            s..p.pos
        };
        let int = digits(self);
        let mut frac = self.pos..self.pos;
        if self.peek() == Some('.') {
            self.pos += 1;
            frac = digits(self);
        }
        if int.is_empty() && frac.is_empty() {
            return Err(self.error_at(start, "expected a number"));
        }
        let mut exp: i64 = 0;
        if matches!(self.peek(), Some('e' | 'E')) {
            let at = self.pos;
            self.pos += 1;
            let neg = if self.peek() == Some('-') {
                self.pos += 1;
                true
            } else {
                if self.peek() == Some('+') {
                    self.pos += 1;
                }
                false
            };
            let e = digits(self);
            if e.is_empty() {
                return Err(self.error_at(at, "expected digits of the exponent after `e`"));
            }
            let e = self.src[e].trim_start_matches('0');
            exp = if e.is_empty() {
                0
            } else {
                e.parse::<i64>()
                    .ok()
                    .filter(|&e| e <= 300)
                    .ok_or_else(|| self.error_at(at, "exponent too large: at most e±300"))?
            };
            if neg {
                exp = -exp;
            }
        }
        // Significant digits only: leading zeros and trailing zeros of the
        // fraction do not change the value.
        let int_digits = self.src[int].trim_start_matches('0');
        let frac_digits = self.src[frac].trim_end_matches('0');
        let scale = exp - frac_digits.len() as i64;
        let mantissa_digits = format!("{int_digits}{frac_digits}");
        let mantissa_digits = mantissa_digits.trim_start_matches('0');
        if mantissa_digits.is_empty() {
            return Ok(Poly::zero());
        }
        // Bits of the numerator and denominator, before building them.
        const LOG2_10: f64 = std::f64::consts::LOG2_10;
        let numer_digits = mantissa_digits.len() as i64 + scale.max(0);
        let denom_digits = (-scale).max(0);
        let bits = (numer_digits.max(denom_digits) as f64 * LOG2_10).ceil() as u64;
        if bits > MAX_COEFFICIENT_BITS + 3 {
            return Err(self.error_at(
                start,
                &format!(
                    "number `{}` needs about {bits} bits: more than the limit of {MAX_COEFFICIENT_BITS} bits (MAX_COEFFICIENT_BITS, about 38 decimal digits)",
                    crate::sanitize::snippet(&self.src[start..self.pos], 24)
                ),
            ));
        }
        let mantissa: BigInt = mantissa_digits.parse().unwrap_or_default();
        let ten = BigInt::from(10);
        let value = if scale >= 0 {
            Rational::from_integer(mantissa * num_traits::pow(ten, scale as usize))
        } else {
            Rational::new(mantissa, num_traits::pow(ten, (-scale) as usize))
        };
        let p = Poly::constant(value);
        self.check(&p, start, "this number")?;
        Ok(p)
    }
}

/// Parse helper for tests and built-in checks: panics on error.
#[cfg(test)]
fn p(s: &str) -> Poly {
    parse_poly(s).unwrap()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poly::rat;

    #[test]
    fn parses_polynomials_exactly() {
        assert_eq!(p("1 - 3*xi^2 + 2*xi^3").to_string(), "1 - 3*xi^2 + 2*xi^3");
        assert_eq!(p("6*(xi - xi^2)*eta").to_string(), "6*xi*eta - 6*xi^2*eta");
        assert_eq!(p("-xi^2").to_string(), "-xi^2");
        assert_eq!(p("0.25*l/2").to_string(), "1/8*l");
        assert_eq!(p("1.5e-1").as_constant(), Some(rat(3, 20)));
        assert_eq!(p("(1-xi)^2").to_string(), "1 - 2*xi + xi^2");
        assert!(p("0").is_zero());
        assert!(p("xi - xi").is_zero());
    }

    fn err(s: &str) -> ExprError {
        parse_poly(s).unwrap_err()
    }

    #[test]
    fn rejects_non_polynomials_with_position() {
        let e = err("1 + sin(xi)");
        assert_eq!(e.offset, 4);
        assert!(
            e.message.contains("`sin(…)` is not polynomial"),
            "{}",
            e.message
        );
        let e = err("xi / eta");
        assert_eq!(e.offset, 5);
        assert!(e.message.contains("division by `eta`"), "{}", e.message);
        let e = err("xi^-1");
        assert!(e.message.contains("negative powers"), "{}", e.message);
        let e = err("xi^0.5");
        assert!(e.message.contains("fractional powers"), "{}", e.message);
        let e = err("2*x");
        assert_eq!(e.offset, 2);
        assert!(e.message.contains("unknown symbol `x`"), "{}", e.message);
        assert!(err("(xi").message.contains("expected `)`"));
        assert!(err("xi 2").message.contains("unexpected `2`"));
        assert!(err("").message.contains("empty"));
        assert!(err("1/0").message.contains("division by zero"));
        assert!(err("xi**2").message.contains("`**`"));
    }
}
