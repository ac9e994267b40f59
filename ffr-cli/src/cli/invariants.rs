//! `ffr invariants`: a body's invariants at its parameters, as a summary or
//! the JSON of `--json`.

use crate::output;
use ffr::runtime::Invariants;
use serde_json::{json, Value};

const AXES: [&str; 3] = ["x", "y", "z"];

/// The invariants as the JSON object of `ffr invariants --json`: `mass`,
/// `St0`, `Sbar`, `Skl`, `Ikl`, `theta` (keyed `"xx"`, `"xy"`, …; a planar
/// body has only x, y), `mff`, `Kff`, `dofs`.
pub fn invariants_json(inv: &Invariants, dofs: &[String]) -> Value {
    let d = inv.dim;
    let n = inv.nf();
    let mat = |m: &ffr::runtime::nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| (0..n).map(|j| m[(i, j)]).collect())
            .collect()
    };
    let keyed = |f: &dyn Fn(usize, usize) -> Value| {
        let mut m = serde_json::Map::new();
        for k in 0..d {
            for l in 0..d {
                m.insert(format!("{}{}", AXES[k], AXES[l]), f(k, l));
            }
        }
        Value::Object(m)
    };
    json!({
        "mass": inv.mass,
        "St0": inv.s_t0.as_slice()[..d].to_vec(),
        "Sbar": (0..d).map(|k| (0..n).map(|a| inv.s_bar[(k, a)]).collect::<Vec<f64>>()).collect::<Vec<_>>(),
        "Skl": keyed(&|k, l| json!(mat(&inv.s_kl[k][l]))),
        "Ikl": keyed(&|k, l| json!(inv.i_kl[k][l].as_slice())),
        "theta": keyed(&|k, l| json!(inv.theta[(k, l)])),
        "mff": mat(&inv.m_ff),
        "Kff": mat(&inv.k_ff),
        "dofs": dofs,
    })
}

pub(super) fn print_summary(
    description: &str,
    inv: &Invariants,
    dofs: &[String],
) -> Result<(), output::OutputError> {
    crate::outln!("{description}")?;
    crate::outln!("elastic coordinates ({}): {}", dofs.len(), dofs.join(" "))?;
    crate::outln!("mass m = {:e}", inv.mass)?;
    let d = inv.dim;
    crate::outln!("S_t0 = {:?}", &inv.s_t0.as_slice()[..d])?;
    for k in 0..d {
        crate::outln!(
            "Θ_{}· = {:?}",
            AXES[k],
            (0..d).map(|l| inv.theta[(k, l)]).collect::<Vec<_>>()
        )?;
    }
    let diag = |m: &ffr::runtime::nalgebra::DMatrix<f64>| {
        (0..m.nrows()).map(|i| m[(i, i)]).collect::<Vec<_>>()
    };
    crate::outln!("diag m_ff = {:?}", diag(&inv.m_ff))?;
    crate::outln!("diag K_ff = {:?}", diag(&inv.k_ff))
}
