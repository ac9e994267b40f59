//! Linear models of a system about a state: `ẋ = A x + B u`, `y = C x + D u`
//! on the constraint manifold, their eigenvalues, and the states they are
//! taken about (static equilibrium, steady rotation).
//!
//! At a state `(t, q, q̇, q̈, λ)` the residual's derivatives over the free
//! coordinates are `M = ∂r/∂q̈`, `C = ∂r/∂q̇` and `K = ∂r/∂q + ∂(Φ_qᵀλ)/∂q`
//! ([`Assembly::tangent_parts`]: the exact tangents of the iteration
//! matrix). Perturbations that keep the joints closed satisfy
//! `Φ_q δq = 0`; coordinate partitioning splits the free coordinates into
//! dependent `d` (the pivots of a fully pivoted elimination of `Φ_q`) and
//! independent `z`, `δq = N z` with
//!
//! ```text
//! N = [−Φ_d⁻¹ Φ_z; I]  (rows in coordinate order),
//! ```
//!
//! and the projected equations `M̂ z̈ + Ĉ ż + K̂ z = Nᵀ Q_u u` with
//! `M̂ = NᵀMN`, `Ĉ = NᵀCN`, `K̂ = NᵀKN` (`Nᵀ Φ_qᵀ = 0` removes the
//! multipliers). With `x = [z; ż]`:
//!
//! ```text
//! A = [0, I; −M̂⁻¹K̂, −M̂⁻¹Ĉ],   B = [0; M̂⁻¹ Nᵀ Q_u],
//! C = [G_q N, G_v N],          D = 0,
//! ```
//!
//! `Q_u` the generalized force of a unit input, `G_q`, `G_v` the
//! derivatives of an output by the free coordinates and velocities. A drive
//! input `u = s̈` perturbs the driver of a driving constraint row `k`:
//! `δq = N z + P s` with `Φ_q P = e_k` (`P` on the dependent coordinates),
//! `s`, `ṡ` join the states, and `M̂ z̈ + Ĉ ż + K̂ z = −Nᵀ(K P s + C P ṡ +
//! M P u)`. The
//! basis is frozen at the state (`Ṅ z` is left out): exact about a state
//! at rest, and about a steady rotation whose joints' Jacobian does not
//! change along the motion in the independent directions (a body clamped to
//! a driven hub, the case of a Campbell diagram). Prescribed coordinates
//! are not states.

use crate::assembly::{Assembly, TangentParts};
use crate::body::Body;
use crate::error::{Error, Result};
use crate::force::ForceElement;
use crate::integrator::State;
use crate::marker::Marker;
use crate::system::System;
use ffr_spec::scene::OutputKind;
use nalgebra::{Complex, DMatrix, DVector};

/// An input of a linear model.
#[derive(Clone, Debug)]
pub struct LinearInput {
    /// Its name.
    pub name: String,
    /// What it does.
    pub load: InputLoad,
}

/// What an input does.
#[derive(Clone, Debug)]
pub enum InputLoad {
    /// A force element whose load at `u = 1` is the input's unit (a unit
    /// torque, a unit force along a direction).
    Force(Box<ForceElement>),
    /// The acceleration `u = s̈` of a perturbation `s` of the driver of a
    /// driving constraint (index into
    /// [`System::constraints`](crate::System::constraints); its row `k` is
    /// `g(q) − f(t)`, or `sin(φ − f)` for an angle): `s` and `ṡ` become
    /// states, `Φ_q δq = s e_k`.
    Drive {
        /// The driving constraint (one row).
        constraint: usize,
    },
}

/// An output of a linear model: what a scene's output column records.
#[derive(Clone, Debug)]
pub struct LinearOutput {
    /// Its name.
    pub name: String,
    /// What it records (energies are not linear outputs).
    pub kind: OutputKind,
    /// Where.
    pub marker: Marker,
    /// The reference marker of a relative angle.
    pub relative_to: Option<Marker>,
}

/// A linear model `ẋ = A x + B u`, `y = C x + D u` about a state.
#[derive(Clone, Debug)]
pub struct LinearModel {
    /// The state it was taken about.
    pub state: State,
    /// State labels: the independent coordinates and the drive inputs'
    /// perturbations, then their rates (`…_dot`).
    pub states: Vec<String>,
    /// Input names.
    pub inputs: Vec<String>,
    /// Output names.
    pub outputs: Vec<String>,
    /// `A` (2(n_z + drives) square).
    pub a: DMatrix<f64>,
    /// `B` (2n_z × inputs).
    pub b: DMatrix<f64>,
    /// `C` (outputs × 2n_z).
    pub c: DMatrix<f64>,
    /// `D` (outputs × inputs; zero for the outputs supported).
    pub d: DMatrix<f64>,
    /// The independent coordinates (global indices).
    pub independent: Vec<usize>,
    /// The null-space basis `N` (free coordinates × independent).
    pub basis: DMatrix<f64>,
    /// The drive inputs' particular solutions `P` (free coordinates ×
    /// drives, `Φ_q P = e_k`).
    pub drive_basis: DMatrix<f64>,
    /// The projected mass `M̂ = NᵀMN`.
    pub m_hat: DMatrix<f64>,
    /// The projected damping and gyroscopic matrix `Ĉ = NᵀCN`.
    pub c_hat: DMatrix<f64>,
    /// The projected stiffness `K̂ = NᵀKN`.
    pub k_hat: DMatrix<f64>,
    /// The unprojected parts (free coordinates).
    pub parts: TangentParts,
}

/// The label of every coordinate: `body.x`, `body.y`, `body.z`,
/// `body.theta` (planar) or `body.e0…e3` (Euler parameters), and the
/// elastic coordinates' labels (`body.uy_3`).
pub fn coordinate_labels<B: Body>(sys: &System<B>) -> Vec<String> {
    let mut out = Vec::with_capacity(sys.n_coords());
    for b in sys.bodies() {
        let frame: &[&str] = if b.d == 2 {
            &["x", "y", "theta"]
        } else {
            &["x", "y", "z", "e0", "e1", "e2", "e3"]
        };
        out.extend(frame.iter().map(|f| format!("{}.{f}", b.name)));
        let lay = b.body.layout();
        for j in 0..b.nf {
            match lay.labels.get(j) {
                Some(l) => out.push(format!("{}.{l}", b.name)),
                None => out.push(format!("{}.q{j}", b.name)),
            }
        }
    }
    out
}

/// Coordinate partitioning of `Φ_q` (rows × columns): the pivot columns of
/// an elimination with full pivoting (a pivot below `10⁻¹⁰` of the largest
/// entry ends it: the rows left are redundant) are the dependent
/// coordinates; returns the null-space basis `N = [−Φ_d⁻¹ Φ_z; I]`
/// (columns × independent) and the independent columns.
pub fn null_space_basis(phi_q: &DMatrix<f64>) -> (DMatrix<f64>, Vec<usize>) {
    let p = partition(phi_q);
    (p.basis, p.independent)
}

/// A coordinate partitioning of `Φ_q`.
struct Partition {
    basis: DMatrix<f64>,
    independent: Vec<usize>,
    dependent: Vec<usize>,
    /// The rows the dependent coordinates are solved from.
    rows: Vec<usize>,
    /// `Φ_d` (rows × dependent), factored.
    phi_d: nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
}

fn partition(phi_q: &DMatrix<f64>) -> Partition {
    let (m, n) = phi_q.shape();
    let mut a = phi_q.clone();
    let scale = a.amax();
    let mut rows: Vec<usize> = (0..m).collect();
    let mut cols: Vec<usize> = (0..n).collect();
    let mut rank = 0;
    if scale > 0.0 {
        for k in 0..m.min(n) {
            let (mut best, mut bi, mut bj) = (0.0, k, k);
            for i in k..m {
                for j in k..n {
                    let x = a[(rows[i], cols[j])].abs();
                    if x > best {
                        (best, bi, bj) = (x, i, j);
                    }
                }
            }
            if !(best > 1e-10 * scale) {
                break;
            }
            rows.swap(k, bi);
            cols.swap(k, bj);
            let (pr, pc) = (rows[k], cols[k]);
            for &r in &rows[k + 1..] {
                let f = a[(r, pc)] / a[(pr, pc)];
                if f != 0.0 {
                    for &c in &cols[k..] {
                        let v = a[(pr, c)];
                        a[(r, c)] -= f * v;
                    }
                }
            }
            rank = k + 1;
        }
    }
    let mut dep: Vec<usize> = cols[..rank].to_vec();
    let mut ind: Vec<usize> = cols[rank..].to_vec();
    dep.sort_unstable();
    ind.sort_unstable();
    let used: Vec<usize> = rows[..rank].to_vec();
    let phi_d = DMatrix::from_fn(rank, rank, |i, j| phi_q[(used[i], dep[j])]);
    let phi_z = DMatrix::from_fn(rank, ind.len(), |i, j| phi_q[(used[i], ind[j])]);
    let lu = phi_d.lu();
    let x = if rank > 0 {
        lu.solve(&phi_z)
            .unwrap_or_else(|| DMatrix::zeros(rank, ind.len()))
    } else {
        DMatrix::zeros(0, ind.len())
    };
    let mut basis = DMatrix::zeros(n, ind.len());
    for (j, &c) in ind.iter().enumerate() {
        basis[(c, j)] = 1.0;
        for (i, &d) in dep.iter().enumerate() {
            basis[(d, j)] = -x[(i, j)];
        }
    }
    Partition {
        basis,
        independent: ind,
        dependent: dep,
        rows: used,
        phi_d: lu,
    }
}

/// Schur iterations per eigenvalue at most (LAPACK's `dhseqr` allows 30
/// per eigenvalue; a matrix that needs more is refused, not iterated
/// forever).
pub const SCHUR_ITERATIONS_PER_EIGENVALUE: usize = 60;

/// The eigenvalues of `a` (real Schur form after balancing: a diagonal
/// similarity by powers of two that equalizes row and column norms, as
/// LAPACK's `dgebal`, so that the slow modes of a stiff model keep their
/// relative accuracy), sorted by modulus, then imaginary part (a conjugate
/// pair: negative first). Empty for an empty matrix. A matrix with an
/// entry that is not finite, or whose Schur iteration does not converge
/// in [`SCHUR_ITERATIONS_PER_EIGENVALUE`] × its size iterations, is an
/// error (the iteration is capped: it never runs forever).
pub fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<Complex<f64>>> {
    if a.nrows() == 0 {
        return Ok(Vec::new());
    }
    if let Some(k) = a.iter().position(|x| !x.is_finite()) {
        let (i, j) = (k % a.nrows(), k / a.nrows());
        return Err(Error::InvalidInput(format!(
            "the state matrix A has the entry {} at ({}, {}): its eigenvalues are not defined",
            a[(i, j)],
            i + 1,
            j + 1
        )));
    }
    let n = a.nrows();
    let cap = SCHUR_ITERATIONS_PER_EIGENVALUE * n.max(10);
    let schur = nalgebra::linalg::Schur::try_new(balance(a), f64::EPSILON, cap).ok_or_else(|| {
        Error::InvalidInput(format!(
            "the eigenvalues of the {n}×{n} state matrix A did not converge in {cap} Schur iterations"
        ))
    })?;
    let mut ev: Vec<Complex<f64>> = schur.complex_eigenvalues().iter().copied().collect();
    ev.sort_by(|x, y| {
        x.norm()
            .total_cmp(&y.norm())
            .then(x.im.total_cmp(&y.im))
            .then(x.re.total_cmp(&y.re))
    });
    Ok(ev)
}

/// `D⁻¹ A D` with `D` diagonal, powers of two, chosen (Parlett & Reinsch)
/// until no row and column norm pair changes by more than a factor 0.95.
pub fn balance(a: &DMatrix<f64>) -> DMatrix<f64> {
    let mut b = a.clone();
    let n = b.nrows();
    for _ in 0..100 {
        let mut done = true;
        for i in 0..n {
            let (mut c, mut r) = (0.0, 0.0);
            for j in 0..n {
                if j != i {
                    c += b[(j, i)].abs();
                    r += b[(i, j)].abs();
                }
            }
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let s = c + r;
            let mut f = 1.0;
            let (mut cc, mut rr) = (c, r);
            while cc < rr / 2.0 {
                cc *= 2.0;
                rr /= 2.0;
                f *= 2.0;
            }
            while cc >= rr * 2.0 {
                cc /= 2.0;
                rr *= 2.0;
                f /= 2.0;
            }
            if (cc + rr) < 0.95 * s {
                done = false;
                for j in 0..n {
                    b[(i, j)] /= f;
                    b[(j, i)] *= f;
                }
            }
        }
        if done {
            break;
        }
    }
    b
}

/// The most unknowns — free coordinates and constraint rows — of the
/// dense matrices of a linear model ([`linearize`]) or a Campbell steady
/// state (whose Newton matrix is dense): each such matrix takes
/// `8 n²` bytes (32 MiB at the limit), a model several of them, and its
/// eigenvalues `O(n³)` time. Checked before anything dense is allocated
/// ([`check_dense_size`]); time runs, which are banded, have no such limit.
pub const MAX_DENSE_UNKNOWNS: usize = 2048;

/// Refuse, before allocating, a system whose dense linear model (with
/// `extra` more states per position, e.g. drive inputs) would exceed
/// [`MAX_DENSE_UNKNOWNS`], saying how large it is and what the limit is.
pub fn check_dense_size<B: Body>(sys: &System<B>, extra: usize) -> Result<()> {
    let free = sys.n_coords().saturating_sub(sys.prescribed().len());
    let rows: usize = sys
        .constraints()
        .iter()
        .map(|c| c.rows.len())
        .sum::<usize>()
        + sys.bodies().iter().filter(|b| b.n_theta == 4).count();
    let total = free.saturating_add(rows).saturating_add(extra);
    if total > MAX_DENSE_UNKNOWNS {
        let mib = (total as f64).powi(2) * 8.0 / (1024.0 * 1024.0);
        return Err(Error::InvalidInput(format!(
            "a linear model of this system needs dense matrices over {free} free coordinates and {rows} constraint rows{}: {total} unknowns ({mib:.0} MiB per matrix), more than the limit of {MAX_DENSE_UNKNOWNS} (MAX_DENSE_UNKNOWNS) for linearize and campbell; use fewer elements, segments or modes (time runs, which are banded, take this system)",
            if extra > 0 { format!(" and {extra} drive states") } else { String::new() }
        )));
    }
    Ok(())
}

/// Linearize `sys` about `state` (consistent: the residual vanishes) with
/// `inputs` and `outputs` (module documentation). A drive input adds the
/// driver's perturbation `s` and its rate to the states (after the
/// independent coordinates and after their rates): with `P` the particular
/// solution of `Φ_q P = e_k` on the dependent coordinates,
/// `δq = N z + P s`, and `s̈ = u`. Allocates.
pub fn linearize<B: Body>(
    sys: &System<B>,
    state: &State,
    inputs: &[LinearInput],
    outputs: &[LinearOutput],
) -> Result<LinearModel> {
    linearize_with_inputs(sys, state, inputs, outputs, None)
}

/// [`linearize`] with the system's inputs at the operating point: their
/// values and drive perturbations `[t₀, δ₀, δ̇₀]`
/// ([`crate::Assembly::drive_states`]; `None`: the start values, no
/// perturbation), as an integration that reached `state` holds them.
pub fn linearize_with_inputs<B: Body>(
    sys: &System<B>,
    state: &State,
    inputs: &[LinearInput],
    outputs: &[LinearOutput],
    values: Option<(&[f64], &[[f64; 3]])>,
) -> Result<LinearModel> {
    let drive_inputs = inputs
        .iter()
        .filter(|i| matches!(i.load, InputLoad::Drive { .. }))
        .count();
    check_dense_size(sys, drive_inputs)?;
    if state.q.len() != sys.n_coords() || state.v.len() != sys.n_coords() {
        return Err(Error::InvalidInput(format!(
            "the state has {} coordinates, the system {}",
            state.q.len(),
            sys.n_coords()
        )));
    }
    let mut asm = Assembly::new(sys)?;
    if let Some((u, d)) = values {
        if u.len() != sys.n_inputs() || d.len() != sys.n_inputs() {
            return Err(Error::InvalidInput(format!(
                "{} input values and {} drive perturbations for a system of {} inputs",
                u.len(),
                d.len(),
                sys.n_inputs()
            )));
        }
        asm.inputs_mut().copy_from_slice(u);
        asm.drive_states_mut().copy_from_slice(d);
        asm.sync_inputs();
    }
    let (t, q, v) = (state.t, &state.q, &state.v);
    let parts = asm.tangent_parts(t, q, v, &state.a, &state.lambda);
    let part = partition(&parts.phi_q);
    let independent: Vec<usize> = part.independent.iter().map(|&j| parts.free[j]).collect();
    let nz = independent.len();
    let nu = parts.free.len();
    // Drive inputs: their rows and particular solutions P.
    let joint_rows: usize = sys.constraints().iter().map(|c| c.rows.len()).sum();
    let n_norm = asm.m - joint_rows;
    let mut drives: Vec<(usize, DVector<f64>)> = Vec::new();
    for (k, inp) in inputs.iter().enumerate() {
        let InputLoad::Drive { constraint } = inp.load else {
            continue;
        };
        let c = sys.constraints().get(constraint).ok_or_else(|| {
            Error::InvalidInput(format!("input `{}`: no constraint {constraint}", inp.name))
        })?;
        if c.rows.len() != 1 {
            return Err(Error::InvalidInput(format!(
                "input `{}`: constraint {constraint} ({}) has {} rows, a drive has one",
                inp.name,
                c.kind,
                c.rows.len()
            )));
        }
        let row = n_norm
            + sys.constraints()[..constraint]
                .iter()
                .map(|c| c.rows.len())
                .sum::<usize>();
        let Some(i) = part.rows.iter().position(|&r| r == row) else {
            return Err(Error::InvalidInput(format!(
                "input `{}`: the {} row is redundant with the other joints at t = {t}",
                inp.name, c.kind
            )));
        };
        let mut e = DVector::zeros(part.rows.len());
        e[i] = 1.0;
        let pd = part
            .phi_d
            .solve(&e)
            .ok_or_else(|| Error::InvalidInput(format!("input `{}`: singular joints", inp.name)))?;
        let mut pv = DVector::zeros(nu);
        for (j, &d) in part.dependent.iter().enumerate() {
            pv[d] = pd[j];
        }
        drives.push((k, pv));
    }
    let nd = drives.len();
    let np = nz + nd;
    // Z = [N, P]: the free coordinates of the position states.
    let mut zb = DMatrix::zeros(nu, np);
    zb.view_mut((0, 0), (nu, nz)).copy_from(&part.basis);
    for (j, (_, pv)) in drives.iter().enumerate() {
        zb.set_column(nz + j, pv);
    }
    let basis = part.basis;
    let nt = basis.transpose();
    let m_hat = &nt * &parts.m * &basis;
    let c_hat = &nt * &parts.c * &basis;
    let k_hat = &nt * &parts.k * &basis;
    let lu = m_hat.clone().lu();
    let labels = coordinate_labels(sys);
    let singular = || {
        Error::InvalidInput(format!(
            "the projected mass matrix NᵀMN ({nz}×{nz}) is singular at t = {t}: a coordinate without inertia"
        ))
    };
    let minv_k = lu.solve(&(&nt * &parts.k * &zb)).ok_or_else(singular)?;
    let minv_c = lu.solve(&(&nt * &parts.c * &zb)).ok_or_else(singular)?;
    let mut a = DMatrix::zeros(2 * np, 2 * np);
    for i in 0..np {
        a[(i, np + i)] = 1.0;
    }
    for i in 0..nz {
        for j in 0..np {
            a[(np + i, j)] = -minv_k[(i, j)];
            a[(np + i, np + j)] = -minv_c[(i, j)];
        }
    }
    // Inputs: the generalized force of each unit load, or the inertia of a
    // drive's acceleration.
    let mut b = DMatrix::zeros(2 * np, inputs.len());
    for (k, inp) in inputs.iter().enumerate() {
        let rhs = match &inp.load {
            InputLoad::Force(fe) => {
                let qf = asm.generalized_force(fe, t, q, v);
                let qfree = DVector::from_iterator(nu, parts.free.iter().map(|&c| qf[c]));
                &nt * qfree
            }
            InputLoad::Drive { .. } => {
                let j = drives.iter().position(|(i, _)| *i == k).expect("a drive");
                b[(np + nz + j, k)] = 1.0;
                -(&nt * (&parts.m * &drives[j].1))
            }
        };
        let col = lu.solve(&rhs).ok_or_else(singular)?;
        for i in 0..nz {
            b[(np + i, k)] = col[i];
        }
    }
    // Outputs: derivatives by the free coordinates and velocities.
    let mut slot = vec![usize::MAX; sys.n_coords()];
    for (i, &c) in parts.free.iter().enumerate() {
        slot[c] = i;
    }
    let zt = zb.transpose();
    let mut c = DMatrix::zeros(outputs.len(), 2 * np);
    for (k, out) in outputs.iter().enumerate() {
        let (gq, gv) = output_gradient(sys, out, q, v)?;
        let mut gq_free = DVector::zeros(nu);
        let mut gv_free = DVector::zeros(nu);
        for (g, (dq, dv)) in gq.iter().zip(&gv).enumerate() {
            if slot[g] != usize::MAX {
                gq_free[slot[g]] += dq;
                gv_free[slot[g]] += dv;
            }
        }
        let rq = &zt * gq_free;
        let rv = &zt * gv_free;
        for j in 0..np {
            c[(k, j)] = rq[j];
            c[(k, np + j)] = rv[j];
        }
    }
    let d = DMatrix::zeros(outputs.len(), inputs.len());
    let mut pos: Vec<String> = independent.iter().map(|&g| labels[g].clone()).collect();
    pos.extend(drives.iter().map(|(k, _)| inputs[*k].name.clone()));
    let mut states = pos.clone();
    states.extend(pos.iter().map(|l| format!("{l}_dot")));
    let drive_basis = DMatrix::from_fn(nu, nd, |i, j| drives[j].1[i]);
    for (name, mat) in [("A", &a), ("B", &b), ("C", &c)] {
        if let Some(k) = mat.iter().position(|x| !x.is_finite()) {
            let (i, j) = (k % mat.nrows(), k / mat.nrows());
            return Err(Error::InvalidInput(format!(
                "the linear model about the state at t = {t:e} s is not finite: {name}({}, {}) = {}",
                i + 1,
                j + 1,
                mat[(i, j)]
            )));
        }
    }
    Ok(LinearModel {
        state: state.clone(),
        states,
        inputs: inputs.iter().map(|i| i.name.clone()).collect(),
        outputs: outputs.iter().map(|o| o.name.clone()).collect(),
        a,
        b,
        c,
        d,
        independent,
        basis,
        drive_basis,
        m_hat,
        c_hat,
        k_hat,
        parts,
    })
}

/// `∂y/∂q` and `∂y/∂q̇` (all coordinates) of an output at `(q, q̇)`.
fn output_gradient<B: Body>(
    sys: &System<B>,
    out: &LinearOutput,
    q: &[f64],
    v: &[f64],
) -> Result<(Vec<f64>, Vec<f64>)> {
    let n = sys.n_coords();
    let (mut gq, mut gv) = (vec![0.0; n], vec![0.0; n]);
    let mut k = sys.marker_kin(&out.marker);
    k.eval(&out.marker, q);
    match out.kind {
        OutputKind::Position(c) => {
            for (i, &g) in k.idx.iter().enumerate() {
                gq[g] += k.dpos[i][c];
            }
        }
        OutputKind::Velocity(c) => {
            // ṗ = J q̇: ∂ṗ/∂q̇ = J, ∂ṗ/∂q_i = Σ_j ∂²p/∂q_i∂q_j q̇_j.
            for (i, &g) in k.idx.iter().enumerate() {
                gv[g] += k.dpos[i][c];
                let s: f64 = (0..k.len())
                    .map(|j| k.d2pos(i, j)[c] * v[k.idx[j]])
                    .sum();
                gq[g] += s;
            }
        }
        OutputKind::Deflection(c) => match &out.relative_to {
            // d = a_c · (p − p_r), a_c the reference's axis c.
            Some(rm) => {
                let mut kr = sys.marker_kin(rm);
                kr.eval(rm, q);
                let (a, dp) = (kr.axes[c], k.pos - kr.pos);
                for (i, &g) in k.idx.iter().enumerate() {
                    gq[g] += a.dot(&k.dpos[i]);
                }
                for (i, &g) in kr.idx.iter().enumerate() {
                    gq[g] += kr.daxes[c][i].dot(&dp) - a.dot(&kr.dpos[i]);
                }
            }
            None => {
                for (j, (_, s, _)) in out.marker.shape.entries.iter().enumerate() {
                    gq[k.idx[k.n_frame + j]] += s[c];
                }
            }
        },
        OutputKind::Angle => {
            let x = k.axes[0];
            match &out.relative_to {
                None => {
                    // φ = atan2(x_y, x_x).
                    let r2 = x.x * x.x + x.y * x.y;
                    for (i, &g) in k.idx.iter().enumerate() {
                        let dx = k.daxes[0][i];
                        gq[g] += (x.x * dx.y - x.y * dx.x) / r2;
                    }
                }
                Some(rm) => {
                    // φ = atan2(s, c), s = x·y_a, c = x·x_a.
                    let mut ka = sys.marker_kin(rm);
                    ka.eval(rm, q);
                    let (ya, xa) = (ka.axes[1], ka.axes[0]);
                    let (s, cc) = (x.dot(&ya), x.dot(&xa));
                    let r2 = s * s + cc * cc;
                    for (i, &g) in k.idx.iter().enumerate() {
                        let dx = k.daxes[0][i];
                        gq[g] += (cc * dx.dot(&ya) - s * dx.dot(&xa)) / r2;
                    }
                    for (i, &g) in ka.idx.iter().enumerate() {
                        let (dya, dxa) = (ka.daxes[1][i], ka.daxes[0][i]);
                        gq[g] += (cc * x.dot(&dya) - s * x.dot(&dxa)) / r2;
                    }
                }
            }
        }
        OutputKind::Energy(_) => {
            return Err(Error::InvalidInput(format!(
                "output `{}` is an energy, not a linear output (positions, velocities, deflections and angles are)",
                out.name
            )))
        }
    }
    Ok((gq, gv))
}

/// How the free coordinates move in a steady state: at rest, or turning
/// rigidly about the global z axis through `center` at the rate `omega`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SteadyMotion {
    /// `q̇ = q̈ = 0` (static equilibrium).
    Rest,
    /// Every free frame coordinate follows the rigid rotation (planar:
    /// `Ṙ = Ω ẑ × (R − p)`, `R̈ = −Ω² (R − p)`, `θ̇ = Ω`; spatial also
    /// `ė = ½ Ω (−e₃, −e₂, e₁, e₀)`, `ë = −¼ Ω² e`); elastic coordinates
    /// at rest.
    Rotation {
        /// A point of the axis (global z).
        center: [f64; 3],
        /// The rate `Ω` (rad/s).
        omega: f64,
    },
}

/// `q̇`, `q̈` of the free coordinates for `motion` at `q`, and their
/// derivatives by `q` (dense, free × free, local indices).
pub(crate) fn steady_rates<B: Body>(
    sys: &System<B>,
    free: &[usize],
    motion: SteadyMotion,
    q: &[f64],
    v: &mut [f64],
    a: &mut [f64],
) -> (DMatrix<f64>, DMatrix<f64>) {
    let nu = free.len();
    let (mut dv, mut da) = (DMatrix::zeros(nu, nu), DMatrix::zeros(nu, nu));
    let mut slot = vec![usize::MAX; sys.n_coords()];
    for (i, &c) in free.iter().enumerate() {
        slot[c] = i;
        v[c] = 0.0;
        a[c] = 0.0;
    }
    let SteadyMotion::Rotation { center, omega: w } = motion else {
        return (dv, da);
    };
    for b in sys.bodies() {
        let o = b.offset;
        // Translations (x, y).
        let (x, y) = (o, o + 1);
        let (rx, ry) = (q[x] - center[0], q[y] - center[1]);
        if slot[x] != usize::MAX {
            v[x] = -w * ry;
            a[x] = -w * w * rx;
            da[(slot[x], slot[x])] = -w * w;
            if slot[y] != usize::MAX {
                dv[(slot[x], slot[y])] = -w;
            }
        }
        if slot[y] != usize::MAX {
            v[y] = w * rx;
            a[y] = -w * w * ry;
            da[(slot[y], slot[y])] = -w * w;
            if slot[x] != usize::MAX {
                dv[(slot[y], slot[x])] = w;
            }
        }
        if b.d == 2 {
            if slot[o + 2] != usize::MAX {
                v[o + 2] = w;
            }
            continue;
        }
        // Euler parameters: ė = W e, W = ½ Ω [[0,0,0,−1],[0,0,−1,0],[0,1,0,0],[1,0,0,0]].
        let e = o + 3;
        let wm: [[f64; 4]; 4] = [
            [0.0, 0.0, 0.0, -0.5 * w],
            [0.0, 0.0, -0.5 * w, 0.0],
            [0.0, 0.5 * w, 0.0, 0.0],
            [0.5 * w, 0.0, 0.0, 0.0],
        ];
        for i in 0..4 {
            if slot[e + i] == usize::MAX {
                continue;
            }
            v[e + i] = (0..4).map(|j| wm[i][j] * q[e + j]).sum();
            a[e + i] = -0.25 * w * w * q[e + i];
            da[(slot[e + i], slot[e + i])] = -0.25 * w * w;
            for j in 0..4 {
                if slot[e + j] != usize::MAX && wm[i][j] != 0.0 {
                    dv[(slot[e + i], slot[e + j])] = wm[i][j];
                }
            }
        }
    }
    (dv, da)
}

/// The steady state of `sys` at time `t` with `motion` (static equilibrium
/// or a steady rotation), from `start`: the shared Newton driver of
/// [`crate::statics`] with automatic load stepping — Newton on the
/// residual `[r(q, q̇(q), q̈(q), λ); Φ(q, t)] = 0` over the free
/// coordinates and the multipliers with the exact matrix
/// `[K + C ∂q̇/∂q + M ∂q̈/∂q, Φ_qᵀ; Φ_q, 0]` (at rest the bordered
/// `[K, Φ_qᵀ; Φ_q, 0]`; prescribed coordinates from their drivers at `t`,
/// held at rest). No steady state ([`Error::NoEquilibrium`]) says why and
/// how far the load stepping got.
pub fn steady_state<B: Body>(
    sys: &System<B>,
    t: f64,
    start: &State,
    motion: SteadyMotion,
) -> Result<State> {
    steady_state_interruptible(sys, t, start, motion, crate::Interrupt::NEVER)
}

/// [`steady_state`], polling `interrupt` at every Newton iteration
/// ([`crate::statics::equilibrium_interruptible`]).
pub fn steady_state_interruptible<B: Body>(
    sys: &System<B>,
    t: f64,
    start: &State,
    motion: SteadyMotion,
    interrupt: crate::Interrupt<'_>,
) -> Result<State> {
    crate::statics::equilibrium_interruptible(
        sys,
        t,
        start,
        motion,
        &crate::statics::StaticOptions::default(),
        interrupt,
    )
    .map(|e| e.state)
}
