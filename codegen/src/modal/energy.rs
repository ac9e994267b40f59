//! A polynomial strain energy `U(q_f)` at parameter values, and projected
//! onto modal coordinates `q_f = Φ η`.

use super::ModalError;
use crate::poly::{to_f64, Monomial, Param, Poly, Rational, Sym};
use ffr_spec::Params;
use nalgebra::DMatrix;
use num_traits::{One, Zero};
use std::collections::BTreeMap;

/// `poly` with every runtime parameter replaced by the exact rational its
/// `f64` value denotes; the other symbols (e.g. `Q(i)`) stay. Exact: the
/// coefficients of the result are the exact values of the coefficient
/// polynomials.
pub fn substitute_params(poly: &Poly, p: &Params) -> Result<Poly, ModalError> {
    let mut values: Vec<Rational> = Vec::with_capacity(8);
    for (param, v) in Param::FIELDS.iter().zip(p.to_array()) {
        values.push(Rational::from_float(v).ok_or_else(|| {
            ModalError::Input(format!(
                "parameter `{}` must be finite, found {v}",
                param.field()
            ))
        })?);
    }
    let mut cache: BTreeMap<Monomial, Rational> = BTreeMap::new();
    let mut out = Poly::zero();
    for (m, c) in poly.terms() {
        let (params, rest) = m.split(|s| matches!(s, Sym::Param(_)));
        let value = match cache.get(&params) {
            Some(v) => v.clone(),
            None => {
                let mut v = Rational::one();
                for &(s, e) in params.factors() {
                    let Sym::Param(param) = s else { unreachable!() };
                    let Some(i) = param.field_index() else {
                        return Err(ModalError::Eval {
                            poly: m.to_string(),
                            reason: "the element length is not a runtime parameter".into(),
                        });
                    };
                    let base = &values[i];
                    if e < 0 && base.is_zero() {
                        return Err(ModalError::Eval {
                            poly: m.to_string(),
                            reason: format!("parameter `{}` is zero and divides", param.field()),
                        });
                    }
                    v *= if e >= 0 {
                        num_traits::pow(base.clone(), e as usize)
                    } else {
                        num_traits::pow(base.recip(), (-e) as usize)
                    };
                }
                cache.insert(params, v.clone());
                v
            }
        };
        out.add_term(rest, value * c);
    }
    Ok(out)
}

/// Highest degree [`project_energy`] accepts (the energies of interest are quartic).
pub const MAX_ENERGY_DEGREE: usize = 8;

/// A partly substituted term: the remaining nodal coordinates (`idx[..nq]`,
/// sorted, with repetition), then the modal coordinates produced so far
/// (`idx[nq..nq + ne]`, sorted, with repetition). `Copy`, so the merging
/// maps do not allocate per term.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Key {
    nq: u8,
    ne: u8,
    idx: [u32; MAX_ENERGY_DEGREE],
}

/// The energy `U(q_f)` (a polynomial in `Q(i)`, `i < n_f`, with numeric
/// coefficients; see [`substitute_params`]) as a polynomial in the modal
/// coordinates, `U(Φ η)`, returned in the symbols `Q(j)`, `j` the mode index.
///
/// Done in `f64` (coefficients rounded once to `f64` on entry; the result's
/// coefficients are its `f64` values as exact rationals; exact zeros are
/// dropped), by substituting one factor at a time: each term
/// `c · q_{a1} ⋯ q_{ad}` becomes `c · q_{a1} ⋯ q_{a(d−1)} · Σ_j Φ[a_d, j] η_j`,
/// and terms with equal remaining nodal factors and equal modal factors are
/// merged after every round. The energies of interest are sums of element
/// polynomials in a few nodal coordinates each, so the merging keeps the
/// work near (terms × k) per round and the final round produces at most
/// `C(k+d−1, d)` terms of degree `d`; nothing is expanded with big rationals.
/// Deterministic: sums run in key order. Terms of degree above
/// [`MAX_ENERGY_DEGREE`] are refused.
pub fn project_energy(energy: &Poly, phi: &DMatrix<f64>) -> Result<Poly, ModalError> {
    let (nf, k) = phi.shape();
    let mut terms: BTreeMap<Key, f64> = BTreeMap::new();
    for (m, c) in energy.terms() {
        let mut key = Key {
            nq: 0,
            ne: 0,
            idx: [0; MAX_ENERGY_DEGREE],
        };
        for &(s, e) in m.factors() {
            match s {
                Sym::Q(i) if (i as usize) < nf && e >= 0 => {
                    for _ in 0..e {
                        if key.nq as usize == MAX_ENERGY_DEGREE {
                            return Err(ModalError::Input(format!(
                                "the energy term `{m}` has degree above {MAX_ENERGY_DEGREE}"
                            )));
                        }
                        key.idx[key.nq as usize] = i;
                        key.nq += 1;
                    }
                }
                Sym::Q(i) if (i as usize) >= nf => {
                    return Err(ModalError::Input(format!(
                        "the energy uses q{i}, but the basis has {nf} rows"
                    )))
                }
                other => {
                    return Err(ModalError::Eval {
                        poly: m.to_string(),
                        reason: format!(
                            "`{other}` with exponent {e}: the energy must be a polynomial in the elastic coordinates only (substitute the parameters first)"
                        ),
                    })
                }
            }
        }
        let v = to_f64(c);
        if v != 0.0 {
            *terms.entry(key).or_insert(0.0) += v;
        }
    }
    while terms.keys().any(|key| key.nq > 0) {
        let mut next: BTreeMap<Key, f64> = BTreeMap::new();
        for (key, v) in terms {
            if key.nq == 0 {
                *next.entry(key).or_insert(0.0) += v;
                continue;
            }
            // Pop the last (largest) nodal coordinate: the modal part shifts
            // one place left.
            let (nq, ne) = (key.nq as usize - 1, key.ne as usize);
            let a = key.idx[nq] as usize;
            let etas = &key.idx[nq + 1..nq + 1 + ne];
            for j in 0..k {
                let f = phi[(a, j)];
                if f == 0.0 {
                    continue;
                }
                let mut out = Key {
                    nq: nq as u8,
                    ne: ne as u8 + 1,
                    idx: key.idx,
                };
                let at = etas.partition_point(|&x| x <= j as u32);
                out.idx[nq..nq + at].copy_from_slice(&etas[..at]);
                out.idx[nq + at] = j as u32;
                out.idx[nq + at + 1..nq + 1 + ne].copy_from_slice(&etas[at..]);
                *next.entry(out).or_insert(0.0) += v * f;
            }
        }
        terms = next;
    }
    let mut out = Poly::zero();
    for (key, v) in terms {
        if v == 0.0 {
            continue;
        }
        let etas = &key.idx[..key.ne as usize];
        let mut m = Monomial::one();
        let mut i = 0;
        while i < etas.len() {
            let j = etas[i];
            let mut e = 0;
            while i < etas.len() && etas[i] == j {
                e += 1;
                i += 1;
            }
            m = m.mul(&Monomial::var(Sym::Q(j), e));
        }
        let c = Rational::from_float(v).ok_or_else(|| {
            ModalError::Input(format!("projected energy coefficient {v} is not finite"))
        })?;
        out.add_term(m, c);
    }
    Ok(out)
}
