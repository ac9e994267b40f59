//! The consistent initial state: the user's positions and velocities moved
//! onto the joints, and the joints checked for contradictions and
//! redundancy before a run starts.
//!
//! Positions are corrected by the weighted minimum-norm Gauss–Newton step
//! `Δq_S = −W⁻¹ J_Sᵀ (J_S W⁻¹ J_Sᵀ)⁺ Φ`, over a *selection* `S` of the free
//! coordinates, `W = diag(M_cc)` the mass matrix's diagonal on `S` (so the
//! correction is the one of least kinetic-energy measure), repeated until
//! `‖Φ‖∞ ≤ 10⁻¹³ (1 + ‖q‖∞)`. `S` is first the free frame coordinates of
//! every body: a body placed a little off its joint is moved, not bent. Only
//! if that cannot close the joints are the elastic coordinates of the bodies
//! whose elastic state the scene gave ([`System::set_elastic`]) added; a body
//! without one keeps its undeformed shape. A joint still open then is an
//! [`Error::Joint`] naming it with the distance left. Velocities follow the
//! same stages, `J_S Δv_S = −(Φ_q v + Φ_t)`.
//!
//! At the consistent state, the rows of `Φ_q` over every free coordinate
//! must be independent: a row that is a combination of the rows before it
//! (Gram–Schmidt on rows scaled to unit length, relative tolerance `10⁻⁸`)
//! is a redundant joint, whose reaction the equations cannot determine; it
//! is reported as [`Error::Joint`] too.
//!
//! [`System::set_elastic`]: crate::System::set_elastic

use crate::assembly::Assembly;
use crate::body::Body;
use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// The most `rows × columns` of the dense constraint Jacobian the set-up
/// checks form (2²⁶ entries, 512 MiB).
pub const MAX_DENSE_ENTRIES: usize = 1 << 26;

/// The most work of one dense factorization of the set-up checks,
/// `m · k · min(m, k)` for `m` constraint rows and `k` coordinates the joints
/// touch (2³⁴ ≈ 1.7e10 operations, seconds): a scene of thousands of joints
/// is refused rather than left to compute for hours.
pub const MAX_DENSE_WORK: usize = 1 << 34;

/// Positions are consistent when `‖Φ‖∞ ≤ POSITION_TOL (1 + ‖q‖∞)`.
const POSITION_TOL: f64 = 1e-10;
/// Rows whose remainder after Gram–Schmidt is below this (relative to the
/// unit row) are redundant.
const REDUNDANT_TOL: f64 = 1e-8;

/// Dense constraint data on the columns any constraint row touches.
struct Dense {
    /// Global coordinate of each local column.
    cols: Vec<usize>,
    phi: Vec<f64>,
    phi_t: Vec<f64>,
    /// `m × n` over all coordinates; only `cols` are non-zero.
    jac_full: DMatrix<f64>,
}

impl Dense {
    fn new<B: Body>(asm: &Assembly<B>) -> Result<Self> {
        let (n, m) = (asm.n, asm.m);
        if m.saturating_mul(n) > MAX_DENSE_ENTRIES {
            return Err(Error::InvalidInput(format!(
                "{m} constraint rows × {n} coordinates is more than the {MAX_DENSE_ENTRIES} entries the set-up checks of the joints may use: the scene is too large"
            )));
        }
        Ok(Self {
            cols: Vec::new(),
            phi: vec![0.0; m],
            phi_t: vec![0.0; m],
            jac_full: DMatrix::zeros(m, n),
        })
    }

    fn eval<B: Body>(&mut self, asm: &mut Assembly<B>, t: f64, q: &[f64]) {
        asm.constraints_dense(t, q, &mut self.phi, &mut self.phi_t, &mut self.jac_full);
        if self.cols.is_empty() {
            self.cols = (0..asm.n)
                .filter(|&c| self.jac_full.column(c).iter().any(|x| *x != 0.0))
                .collect();
        }
    }
}

/// Per joint, `√Σ Φ²` over its rows (index into the system's constraints).
fn joint_violations<B: Body>(asm: &Assembly<B>, phi: &[f64]) -> Vec<f64> {
    let mut v = vec![0.0; asm.sys.constraints.len()];
    for (k, p) in phi.iter().enumerate() {
        if let Some((j, _)) = asm.row_owner(k) {
            v[j] += p * p;
        }
    }
    v.iter_mut().for_each(|x| *x = x.sqrt());
    v
}

/// The joint with the largest violation `√Σ r²` of its rows in `r`, and
/// that violation; with no joint (only Euler-parameter normalizations
/// violated), [`Error::Inconsistent`].
fn worst_joint<B: Body>(asm: &Assembly<B>, r: &[f64]) -> Result<(usize, f64)> {
    joint_violations(asm, r)
        .into_iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or(Error::Inconsistent {
            violation: max_abs(r),
        })
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |s, v| s.max(v.abs()))
}

/// Weighted minimum-norm solution of `J_S Δ = rhs` over the columns `sel`
/// with weights `w` (`Δ = W^{-1/2} (J_S W^{-1/2})⁺ rhs`).
fn min_norm_step(jac: &DMatrix<f64>, sel: &[usize], w: &[f64], rhs: &[f64]) -> Option<Vec<f64>> {
    let m = jac.nrows();
    if sel.is_empty() || m == 0 {
        return Some(vec![0.0; sel.len()]);
    }
    let a = DMatrix::from_fn(m, sel.len(), |r, k| jac[(r, sel[k])] / w[k].sqrt());
    let svd = a.svd(true, true);
    let smax = svd.singular_values.iter().fold(0.0f64, |s, x| s.max(*x));
    let y = svd
        .solve(&DVector::from_column_slice(rhs), 1e-12 * smax)
        .ok()?;
    Some((0..sel.len()).map(|k| y[k] / w[k].sqrt()).collect())
}

/// The selections of the projection's stages: the free frame coordinates,
/// then (if any body has a given elastic state) those plus that body's
/// free elastic coordinates.
fn stages<B: Body>(asm: &Assembly<B>, touched: &[usize]) -> Vec<Vec<usize>> {
    let sys = asm.sys;
    let free = |c: &usize| !asm.is_prescribed(*c);
    let frame = |c: usize| {
        sys.bodies
            .iter()
            .any(|b| (b.offset..b.f_offset()).contains(&c))
    };
    let given = |c: usize| {
        sys.bodies
            .iter()
            .any(|b| b.elastic_state && (b.f_offset()..b.f_offset() + b.nf).contains(&c))
    };
    let a: Vec<usize> = touched
        .iter()
        .copied()
        .filter(free)
        .filter(|&c| frame(c))
        .collect();
    let b: Vec<usize> = touched
        .iter()
        .copied()
        .filter(free)
        .filter(|&c| frame(c) || given(c))
        .collect();
    if b.len() > a.len() {
        vec![a, b]
    } else {
        vec![a]
    }
}

/// Weights `M_cc` for `sel`, floored at `10⁻¹²` of the largest (a point
/// mass has no rotary inertia).
fn weights<B: Body>(asm: &mut Assembly<B>, q: &[f64], sel: &[usize]) -> Vec<f64> {
    let mut w = asm.mass_diagonal(q, sel);
    let top = w.iter().fold(0.0f64, |s, x| s.max(*x));
    let floor = if top > 0.0 { 1e-12 * top } else { 1.0 };
    w.iter_mut()
        .for_each(|x| *x = if x.is_finite() { x.max(floor) } else { floor });
    w
}

fn unit_name(kind: &str) -> &'static str {
    match kind {
        "rotation drive" => "rad",
        "slide drive" => "m",
        _ => "m for points, the cosine of the angle between axes that must be perpendicular",
    }
}

/// Make `q` and `v` consistent with the constraints at `t0` and check the
/// joints (module docs). `q`, `v` hold the prescribed coordinates already.
pub(crate) fn make_consistent<B: Body>(
    asm: &mut Assembly<B>,
    t0: f64,
    q: &mut [f64],
    v: &mut [f64],
) -> Result<()> {
    if asm.m == 0 {
        return Ok(());
    }
    let mut d = Dense::new(asm)?;
    d.eval(asm, t0, q);
    let touched = d.cols.clone();
    let (m, k) = (asm.m, touched.len());
    if m.saturating_mul(k).saturating_mul(m.min(k)) > MAX_DENSE_WORK {
        return Err(Error::InvalidInput(format!(
            "{m} constraint rows on {k} coordinates: the set-up checks of the joints would take more than {MAX_DENSE_WORK} operations (MAX_DENSE_WORK); the scene has too many joints"
        )));
    }
    let stages = stages(asm, &touched);
    let scale = 1.0 + max_abs(q);
    let start = joint_violations(asm, &d.phi);
    let q_user = q.to_vec();

    // Positions.
    let mut ok = false;
    for sel in &stages {
        q.copy_from_slice(&q_user);
        let w = weights(asm, q, sel);
        let mut best = f64::INFINITY;
        let mut stalled = 0;
        for _ in 0..60 {
            d.eval(asm, t0, q);
            let viol = max_abs(&d.phi);
            if !viol.is_finite() {
                break;
            }
            if viol <= 1e-13 * scale {
                break;
            }
            if viol < 0.5 * best {
                stalled = 0;
            } else {
                stalled += 1;
                if stalled >= 6 {
                    break;
                }
            }
            best = best.min(viol);
            let rhs: Vec<f64> = d.phi.iter().map(|x| -x).collect();
            let Some(dq) = min_norm_step(&d.jac_full, sel, &w, &rhs) else {
                break;
            };
            for (k, &c) in sel.iter().enumerate() {
                q[c] += dq[k];
            }
        }
        d.eval(asm, t0, q);
        if max_abs(&d.phi) <= POSITION_TOL * scale {
            ok = true;
            break;
        }
    }
    if !ok {
        let (j, gap) = worst_joint(asm, &d.phi)?;
        let c = &asm.sys.constraints[j];
        let any_given = asm.sys.bodies.iter().any(|b| b.elastic_state);
        let moved = if any_given {
            "moving the bodies' frames and the given elastic states"
        } else {
            "moving the bodies' frames (their elastic coordinates stay undeformed)"
        };
        q.copy_from_slice(&q_user);
        return Err(Error::Joint {
            joint: j,
            kind: c.kind.clone(),
            reason: format!(
                "the initial state cannot satisfy it without straining a body: its equations start violated by {:.3e} and {moved} leaves {gap:.3e} ({}); place the bodies so that its markers meet, and check that the joints do not contradict each other",
                start[j],
                unit_name(&c.kind)
            ),
        });
    }

    // Redundancy: independent rows of Φ_q over the free coordinates.
    let free: Vec<usize> = touched
        .iter()
        .copied()
        .filter(|&c| !asm.is_prescribed(c))
        .collect();
    let wf = weights(asm, q, &free);
    let m = asm.m;
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for r in 0..m {
        let mut row: Vec<f64> = free
            .iter()
            .enumerate()
            .map(|(k, &c)| d.jac_full[(r, c)] / wf[k].sqrt())
            .collect();
        let norm = row.iter().map(|x| x * x).sum::<f64>().sqrt();
        let redundant = if norm == 0.0 || !norm.is_finite() {
            true
        } else {
            row.iter_mut().for_each(|x| *x /= norm);
            for _ in 0..2 {
                for b in &basis {
                    let p: f64 = row.iter().zip(b).map(|(x, y)| x * y).sum();
                    row.iter_mut().zip(b).for_each(|(x, y)| *x -= p * y);
                }
            }
            let rest = row.iter().map(|x| x * x).sum::<f64>().sqrt();
            if rest < REDUNDANT_TOL {
                true
            } else {
                row.iter_mut().for_each(|x| *x /= rest);
                basis.push(row);
                false
            }
        };
        if redundant {
            let Some((j, k)) = asm.row_owner(r) else {
                return Err(Error::InvalidInput(format!(
                    "the Euler-parameter normalization row {r} depends on the joints' rows: a body's rotation is constrained twice"
                )));
            };
            let c = &asm.sys.constraints[j];
            let why = if norm == 0.0 {
                "it acts on no free coordinate (both of its markers are held already)".to_string()
            } else {
                "the joints before it already impose it".to_string()
            };
            q.copy_from_slice(&q_user);
            return Err(Error::Joint {
                joint: j,
                kind: c.kind.clone(),
                reason: format!(
                    "redundant: its equation {} repeats a constraint, {why}, so its reaction is not determined; remove the joint or use one that constrains less",
                    k + 1
                ),
            });
        }
    }

    // Velocities: J_S Δv = −(Φ_q v + Φ_t), stage by stage.
    let rate = |d: &Dense, v: &[f64]| -> Vec<f64> {
        (0..m)
            .map(|r| {
                d.phi_t[r]
                    + d.cols
                        .iter()
                        .map(|&c| d.jac_full[(r, c)] * v[c])
                        .sum::<f64>()
            })
            .collect()
    };
    let v_user = v.to_vec();
    let vscale = 1.0 + max_abs(v) + max_abs(&d.phi_t);
    let mut ok = false;
    for sel in &stages {
        v.copy_from_slice(&v_user);
        let w = weights(asm, q, sel);
        for _ in 0..3 {
            let res = rate(&d, v);
            if max_abs(&res) <= 1e-13 * vscale {
                break;
            }
            let rhs: Vec<f64> = res.iter().map(|x| -x).collect();
            let Some(dv) = min_norm_step(&d.jac_full, sel, &w, &rhs) else {
                break;
            };
            for (k, &c) in sel.iter().enumerate() {
                v[c] += dv[k];
            }
        }
        if max_abs(&rate(&d, v)) <= POSITION_TOL * vscale {
            ok = true;
            break;
        }
    }
    if !ok {
        let (j, gap) = worst_joint(asm, &rate(&d, v))?;
        let c = &asm.sys.constraints[j];
        return Err(Error::Joint {
            joint: j,
            kind: c.kind.clone(),
            reason: format!(
                "the initial velocities cannot satisfy it without straining a body: the rates of its equations stay at {gap:.3e} after the frames' velocities are corrected; give the bodies velocities that the joint allows"
            ),
        });
    }
    Ok(())
}
