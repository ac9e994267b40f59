//! Parser of the polynomial strings in a shape file.
//!
//! Grammar (`^` binds tighter than unary minus, as in mathematics):
//!
//! ```text
//! expr   = term { ("+" | "-") term }
//! term   = unary { ("*" | "/") unary }       // "/" only by a non-zero constant
//! unary  = ("+" | "-") unary | power
//! power  = atom [ "^" integer ]              // integer ≥ 0
//! atom   = number | symbol | "(" expr ")"
//! symbol = "xi" | "eta" | "zeta" | "l"
//! number = digits [ "." digits ] [ ("e" | "E") [sign] digits ]   // read exactly
//! ```

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
    let mut p = Parser { src, pos: 0 };
    p.skip_ws();
    if p.pos == src.len() {
        return Err(p.error("expected a polynomial, found an empty string"));
    }
    let e = p.expr()?;
    p.skip_ws();
    if p.pos < src.len() {
        let c = p.peek().unwrap_or(' ');
        return Err(p.error(&format!(
            "unexpected `{c}`: expected an operator (`+ - * / ^`) or the end of the expression"
        )));
    }
    Ok(e)
}

struct Parser<'a> {
    src: &'a str,
    pos: usize,
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

    fn expr(&mut self) -> Result<Poly, ExprError> {
        let mut acc = self.term()?;
        loop {
            if self.eat('+') {
                acc = acc.add(&self.term()?);
            } else if self.eat('-') {
                acc = acc.sub(&self.term()?);
            } else {
                return Ok(acc);
            }
        }
    }

    fn term(&mut self) -> Result<Poly, ExprError> {
        let mut acc = self.unary()?;
        loop {
            self.skip_ws();
            if self.src[self.pos..].starts_with("**") {
                return Err(self.error("`**` is not an operator here: write powers as `x^2`"));
            }
            if self.eat('*') {
                acc = acc.mul(&self.unary()?);
            } else if self.eat('/') {
                self.skip_ws();
                let at = self.pos;
                let d = self.unary()?;
                match d.as_constant() {
                    Some(c) if c.is_zero() => {
                        return Err(self.error_at(at, "division by zero"));
                    }
                    Some(c) => acc = acc.scale(&c.recip()),
                    None => {
                        return Err(self.error_at(
                            at,
                            &format!(
                                "division by `{d}` is not polynomial: only division by a non-zero number is allowed"
                            ),
                        ));
                    }
                }
            } else {
                return Ok(acc);
            }
        }
    }

    fn unary(&mut self) -> Result<Poly, ExprError> {
        if self.eat('-') {
            Ok(self.unary()?.scale(&-Rational::one()))
        } else if self.eat('+') {
            self.unary()
        } else {
            self.power()
        }
    }

    fn power(&mut self) -> Result<Poly, ExprError> {
        let base = self.atom()?;
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
            return Err(self.error_at(at, "expected a whole number after `^`"));
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
        let n: u32 = self.src[start..self.pos]
            .parse()
            .ok()
            .filter(|&n| n <= 64)
            .ok_or_else(|| self.error_at(start, "power too large (at most 64)"))?;
        Ok(base.pow(n))
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
                self.pos += 1;
                let e = self.expr()?;
                if !self.eat(')') {
                    return Err(self.error("expected `)`"));
                }
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => self.number(),
            Some(c) if c.is_alphabetic() || c == '_' => {
                while matches!(self.peek(), Some(c) if c.is_alphanumeric() || c == '_') {
                    self.pos += self.peek().map_or(1, char::len_utf8);
                }
                let name = &self.src[start..self.pos];
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
                                &format!("`{name}(…)` is not polynomial: functions are not allowed, only + - * / ^ on xi, eta, zeta, l and numbers"),
                            ));
                        }
                        return Err(self.error_at(
                            start,
                            &format!("unknown symbol `{name}`: expected one of xi, eta, zeta, l"),
                        ));
                    }
                };
                Ok(Poly::var(sym))
            }
            Some(c) => Err(self.error(&format!(
                "unexpected `{c}`: expected a number, a symbol (xi, eta, zeta, l) or `(`"
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
            p.src[s..p.pos].to_string()
        };
        let int = digits(self);
        let mut frac = String::new();
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
            exp = e
                .parse::<i64>()
                .ok()
                .filter(|&e| e <= 300)
                .ok_or_else(|| self.error_at(at, "exponent too large"))?;
            if neg {
                exp = -exp;
            }
        }
        let mantissa: BigInt = format!("{int}{frac}").parse().unwrap_or_default();
        let scale = exp - frac.len() as i64;
        let ten = BigInt::from(10);
        let value = if scale >= 0 {
            Rational::from_integer(mantissa * num_traits::pow(ten, scale as usize))
        } else {
            Rational::new(mantissa, num_traits::pow(ten, (-scale) as usize))
        };
        Ok(Poly::constant(value))
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
