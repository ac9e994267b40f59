//! Modal bases from `m_ff` and `K_ff`: modal truncation (eigenmodes of the
//! clamped or pinned body, elastic modes of a free body) and Craig–Bampton
//! (fixed-interface normal modes plus static constraint modes).
//!
//! # Eigenproblem
//! `K φ = λ M φ` with `K` positive definite is solved in the inverse form:
//! Cholesky `K = L Lᵀ`, symmetric eigenproblem `B y = μ y` of
//! `B = L⁻¹ M L⁻ᵀ` (nalgebra's `SymmetricEigen`), `λ = 1/μ`,
//! `φ = L⁻ᵀ y / √μ` (so `φᵀ M φ = 1`). The lowest modes are the largest `μ`,
//! which a symmetric eigensolver gets to an absolute error of `ε‖B‖ = ε μ_max`,
//! i.e. to a relative error of order `ε λ_i / λ_1` for mode `i`: the modes
//! one keeps are accurate to round-off, whereas the usual form with the
//! Cholesky factor of `M` has an absolute error `ε λ_max` on every `λ`
//! (a relative error `ε λ_max/λ_1`, ~1e-8 on the first mode of a 16-element
//! beam). Reported frequencies are the Rayleigh quotients
//! `√(φᵀKφ / φᵀMφ)` of the final vectors.
//!
//! nalgebra rather than faer: it is already the workspace's linear algebra,
//! its dense symmetric eigensolver is single-threaded (so the result does not
//! depend on a thread count), and the sizes are small (`n_f ≤ 6·257`).
//!
//! Coordinates that `K` and `M` do not couple (exact zeros; e.g. a straight
//! beam's axial and bending groups) are solved group by group, so that every
//! mode is exactly zero outside its group (`grouped_eigenpairs`).
//!
//! # Deterministic order and sign
//! Modes are sorted by ascending `λ` (ties by index). Eigenvalues that agree
//! to a relative `1e-9` (e.g. bending in y and z of a beam with `I_y = I_z`)
//! form a cluster whose eigenvectors are only defined as a subspace; the
//! cluster is replaced by a canonical basis of the same subspace: repeatedly
//! take the coordinate (row) with the largest norm over the not yet fixed
//! columns (the first on near-ties) and rotate those columns (a Householder
//! reflection) so that only the first of them is non-zero in that row. The
//! rotations are orthogonal, so the vectors stay `M`-orthonormal eigenvectors,
//! and the result does not depend on which basis of the subspace the
//! eigensolver returned (the members' Rayleigh quotients agree to round-off,
//! ~1e-14 relative, and need not be ascending at that level). Then each
//! normal mode's sign is chosen so that its
//! entry of largest magnitude is positive (the first such entry when several
//! agree to a relative `1e-9`). Constraint modes are `+1` at their own
//! boundary coordinate by definition.

use super::Invariants;
use super::ModalError;
use crate::body::{BodySpec, Reference};
use crate::shape::Kind;
use ffr_spec::Params;
use nalgebra::{Cholesky, DMatrix, DVector, SymmetricEigen, QR};
use std::collections::BTreeSet;

/// Relative gap below which two eigenvalues are treated as one cluster.
const CLUSTER_TOL: f64 = 1e-9;
/// Relative tolerance for ties (pivot rows, sign entries).
const TIE_TOL: f64 = 1e-9;

/// How to reduce a body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reduction {
    /// Modal truncation: the `modes` lowest eigenmodes of the body with its
    /// reference condition (clamped, pinned), or the `modes` lowest elastic
    /// modes of a free body.
    Modal {
        /// Number of modes kept.
        modes: usize,
    },
    /// Craig–Bampton: every elastic coordinate of the boundary nodes is a
    /// boundary coordinate; `modes` fixed-interface normal modes, then one
    /// static constraint mode per boundary coordinate.
    CraigBampton {
        /// Body node indices (`0..=N`).
        boundary_nodes: Vec<usize>,
        /// Number of fixed-interface normal modes.
        modes: usize,
    },
}

/// What a basis vector is.
#[derive(Clone, Debug, PartialEq)]
pub enum ModeKind {
    /// An eigenmode (of the fixed-interface body in Craig–Bampton), mass
    /// normalized, with its circular frequency in rad/s.
    Normal {
        /// `ω` in rad/s.
        omega: f64,
    },
    /// A static constraint mode: unit value of boundary coordinate `dof`
    /// (body coordinate index), zero at the other boundary coordinates, the
    /// interior in static equilibrium (`Ψ = −K_II⁻¹ K_IB`).
    Constraint {
        /// Body coordinate index.
        dof: usize,
    },
    /// A static mode added by [`augment`]: the static response `K_ff⁻¹ f`
    /// to a load `f` (an inertia load of the frame's motion, or a modal
    /// derivative), made mass-orthogonal to the modes before it and
    /// mass normalized.
    Static {
        /// What load it answers (its label without the `static_` prefix).
        load: String,
    },
}

/// A reduction basis `q_f = Φ η` and the reduced mass and stiffness.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalBasis {
    /// `Φ`, n_f × k: normal modes (ascending frequency), then constraint modes
    /// (ascending body coordinate).
    pub phi: DMatrix<f64>,
    /// Circular frequencies (rad/s) of the normal modes, ascending up to
    /// round-off within a degenerate cluster (the first entries of `kinds`).
    pub frequencies: Vec<f64>,
    /// `Φᵀ M Φ` (the identity for normal modes up to round-off).
    pub modal_mass: DMatrix<f64>,
    /// `Φᵀ K Φ` (`diag(ω²)` for normal modes up to round-off).
    pub modal_stiffness: DMatrix<f64>,
    /// One label per mode: `mode_1`, `mode_2`, … and `constraint_<dof>`
    /// (e.g. `constraint_uy_16`).
    pub labels: Vec<String>,
    /// One kind per mode.
    pub kinds: Vec<ModeKind>,
}

impl ModalBasis {
    /// Number of modes `k`.
    pub fn len(&self) -> usize {
        self.phi.ncols()
    }

    /// Whether the basis is empty.
    pub fn is_empty(&self) -> bool {
        self.phi.ncols() == 0
    }

    /// What the basis is: `modal truncation` or `Craig-Bampton`, `+ static
    /// modes` when [`augment`] added some.
    pub fn reduction_name(&self) -> &'static str {
        let cb = self
            .kinds
            .iter()
            .any(|k| matches!(k, ModeKind::Constraint { .. }));
        let st = self
            .kinds
            .iter()
            .any(|k| matches!(k, ModeKind::Static { .. }));
        match (cb, st) {
            (true, false) => "Craig-Bampton",
            (true, true) => "Craig-Bampton + static modes",
            (false, false) => "modal truncation",
            (false, true) => "modal truncation + static modes",
        }
    }

    fn assemble(
        m: &DMatrix<f64>,
        k: &DMatrix<f64>,
        phi: DMatrix<f64>,
        normal: usize,
        constraint_dofs: &[usize],
        dof_names: &[String],
    ) -> Self {
        let pt = phi.transpose();
        let modal_mass = sym(&pt * m * &phi);
        let modal_stiffness = sym(&pt * k * &phi);
        let mut frequencies = Vec::with_capacity(normal);
        let mut labels = Vec::with_capacity(phi.ncols());
        let mut kinds = Vec::with_capacity(phi.ncols());
        for j in 0..normal {
            let omega = (modal_stiffness[(j, j)] / modal_mass[(j, j)])
                .max(0.0)
                .sqrt();
            frequencies.push(omega);
            labels.push(format!("mode_{}", j + 1));
            kinds.push(ModeKind::Normal { omega });
        }
        for &d in constraint_dofs {
            labels.push(format!("constraint_{}", dof_names[d]));
            kinds.push(ModeKind::Constraint { dof: d });
        }
        Self {
            phi,
            frequencies,
            modal_mass,
            modal_stiffness,
            labels,
            kinds,
        }
    }
}

/// Relative mass norm below which an added static vector is taken to lie in
/// the span of the basis so far and is dropped.
pub const STATIC_DROP_TOL: f64 = 1e-6;

/// `basis` with static modes appended: for each `(name, f)` of `loads`, in
/// order, `ψ = K_ff⁻¹ f`, less its mass-orthogonal projection on the basis
/// so far (twice, for round-off); if what remains has a mass norm below
/// [`STATIC_DROP_TOL`] of `ψ`'s it is dropped (the basis already contains
/// that response), else it is mass normalized, its sign chosen so that its
/// largest entry is positive (the first on a relative `1e-9` tie), and it is
/// appended as `static_<name>` ([`ModeKind::Static`]). The existing modes are
/// not changed. `K_ff` must be positive definite (a clamped or pinned body).
pub fn augment(
    basis: &ModalBasis,
    m: &DMatrix<f64>,
    k: &DMatrix<f64>,
    loads: &[(String, DVector<f64>)],
) -> Result<ModalBasis, ModalError> {
    let n = m.nrows();
    check_square("m_ff", m, n)?;
    check_square("K_ff", k, n)?;
    if basis.phi.nrows() != n {
        return Err(ModalError::Input(format!(
            "the basis has {} rows, the matrices {n}",
            basis.phi.nrows()
        )));
    }
    let chol = Cholesky::new(k.clone()).ok_or_else(|| {
        ModalError::NotDefinite(
            "static modes need K_ff positive definite: a clamped or pinned body, not a free one"
                .into(),
        )
    })?;
    let mut cols: Vec<DVector<f64>> = (0..basis.len())
        .map(|j| basis.phi.column(j).into_owned())
        .collect();
    let mut labels = basis.labels.clone();
    let mut kinds = basis.kinds.clone();
    for (name, f) in loads {
        if f.len() != n || f.iter().any(|x| !x.is_finite()) {
            return Err(ModalError::Input(format!(
                "load `{name}` must be {n} finite numbers"
            )));
        }
        if f.amax() == 0.0 {
            continue;
        }
        let psi = chol.solve(f);
        let m_norm = |v: &DVector<f64>| v.dot(&(m * v)).max(0.0).sqrt();
        let size = m_norm(&psi);
        if size == 0.0 {
            continue;
        }
        let mut r = psi;
        for _ in 0..2 {
            // r −= Φ (ΦᵀMΦ)⁻¹ Φᵀ M r, with the columns so far.
            if cols.is_empty() {
                break;
            }
            let phi = DMatrix::from_columns(&cols);
            let mr = m * &r;
            let rhs = phi.transpose() * mr;
            let gram = sym(phi.transpose() * m * &phi);
            let c = Cholesky::new(gram)
                .ok_or_else(|| {
                    ModalError::NotDefinite("the basis is not linearly independent".into())
                })?
                .solve(&rhs);
            r -= phi * c;
        }
        let left = m_norm(&r);
        // Not above the tolerance, NaN included.
        if left.partial_cmp(&(STATIC_DROP_TOL * size)) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        r /= left;
        let big = r.amax();
        let at = r
            .iter()
            .position(|x| x.abs() >= big * (1.0 - TIE_TOL))
            .unwrap_or(0);
        if r[at] < 0.0 {
            r = -r;
        }
        cols.push(r);
        labels.push(format!("static_{name}"));
        kinds.push(ModeKind::Static { load: name.clone() });
    }
    let phi = DMatrix::from_columns(&cols);
    let pt = phi.transpose();
    Ok(ModalBasis {
        modal_mass: sym(&pt * m * &phi),
        modal_stiffness: sym(&pt * k * &phi),
        phi,
        frequencies: basis.frequencies.clone(),
        labels,
        kinds,
    })
}

/// The loads whose static responses [`augment`] adds to a basis `phi`
/// (`n_f × k`) of a body with invariants `inv` and stiffening energy `u_nl`
/// (a polynomial in `Sym::Q(i)` at the parameters, e.g. from
/// [`super::substitute_params`]; zero without stiffening):
///
/// - the inertia loads of the frame's motion on the undeformed body, the
///   columns of `f_f` that do not depend on `q_f`: `S̄ᵀ e_k` (translational
///   acceleration along `k`, named `a_k`) and `Ī_kl` (rotational terms, named
///   `i_kl`) — the centrifugal stretch of a spinning beam is one of them;
/// - with stiffening, the modal derivatives of the normal modes `i ≤ j`
///   (named `d_i_j`, 1-based): `∂²(∂U_nl/∂q_f)/∂η_i∂η_j` at rest, the load
///   whose static response is the second-order deformation the pair couples
///   into (a bending mode's foreshortening: without it a reduced beam's
///   axial strain cannot relax and the fourth-order energy over-stiffens).
///
/// Zero loads are left out. Deterministic order: translations, rotations,
/// derivatives.
pub fn static_loads(
    inv: &Invariants,
    u_nl: &crate::poly::Poly,
    phi: &DMatrix<f64>,
    normal: usize,
) -> Result<Vec<(String, DVector<f64>)>, ModalError> {
    use crate::poly::{to_f64, Sym};
    let n = inv.nf();
    let axes = ["x", "y", "z"];
    let mut out = Vec::new();
    for (a, ax) in axes.iter().enumerate() {
        let f: DVector<f64> = inv.s_bar.row(a).transpose();
        if f.amax() != 0.0 {
            out.push((format!("a_{ax}"), f));
        }
    }
    for (a, ax) in axes.iter().enumerate() {
        for (b, bx) in axes.iter().enumerate() {
            let f = inv.i_kl[a][b].clone();
            if f.amax() != 0.0 {
                out.push((format!("i_{ax}{bx}"), f));
            }
        }
    }
    // The cubic part of U_nl: T_abc = ∂³U/∂q_a∂q_b∂q_c at 0.
    let mut cubic: Vec<(f64, [usize; 3])> = Vec::new();
    for (mono, c) in u_nl.terms() {
        let mut idx = Vec::with_capacity(3);
        let mut degree = 0;
        for &(s, e) in mono.factors() {
            match s {
                Sym::Q(i) if (i as usize) < n && e > 0 => {
                    degree += e;
                    for _ in 0..e {
                        idx.push(i as usize);
                    }
                }
                other => {
                    return Err(ModalError::Eval {
                        poly: mono.to_string(),
                        reason: format!(
                            "`{other}`: the energy must be a polynomial in the body's elastic coordinates"
                        ),
                    })
                }
            }
        }
        if degree == 3 {
            cubic.push((to_f64(c), [idx[0], idx[1], idx[2]]));
        }
    }
    if cubic.is_empty() {
        return Ok(out);
    }
    const PERMS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    for i in 0..normal.min(phi.ncols()) {
        for j in i..normal.min(phi.ncols()) {
            // f_a = Σ_bc T_abc φ_ib φ_jc.
            let mut f = DVector::zeros(n);
            for (c, t) in &cubic {
                for p in PERMS {
                    f[t[p[0]]] += c * phi[(t[p[1]], i)] * phi[(t[p[2]], j)];
                }
            }
            if f.amax() != 0.0 {
                out.push((format!("d_{}_{}", i + 1, j + 1), f));
            }
        }
    }
    Ok(out)
}

fn sym(a: DMatrix<f64>) -> DMatrix<f64> {
    let t = a.transpose();
    (a + t) * 0.5
}

fn check_square(name: &str, a: &DMatrix<f64>, n: usize) -> Result<(), ModalError> {
    if a.nrows() != n || a.ncols() != n {
        return Err(ModalError::Input(format!(
            "{name} must be {n} × {n}, found {} × {}",
            a.nrows(),
            a.ncols()
        )));
    }
    if a.iter().any(|v| !v.is_finite()) {
        return Err(ModalError::Input(format!("{name} has a non-finite entry")));
    }
    Ok(())
}

/// The coordinates split into groups that `K` and `M` do not couple: the
/// connected components of the graph with an edge `i — j` wherever
/// `K_ij` or `M_ij` is not exactly zero (a straight beam's axial, torsional
/// and two bending groups; one group for a body whose coordinates all
/// couple). Each group's indices ascending; groups ordered by their first
/// index.
fn coupled_groups(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<Vec<usize>> {
    let n = k.nrows();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for j in 0..n {
        for i in 0..n {
            if i != j && (k[(i, j)] != 0.0 || m[(i, j)] != 0.0) {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                if a != b {
                    // The smaller index is the root: groups are named by
                    // their first coordinate.
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut of_root: Vec<Option<usize>> = vec![None; n];
    for i in 0..n {
        let r = root(&mut parent, i);
        match of_root[r] {
            Some(g) => groups[g].push(i),
            None => {
                of_root[r] = Some(groups.len());
                groups.push(vec![i]);
            }
        }
    }
    groups
}

/// All eigenpairs of `K φ = λ M φ` (`K`, `M` symmetric positive definite),
/// `λ` ascending, `Φ` mass normalized and canonical (module documentation),
/// solved group by group ([`coupled_groups`]): each mode is exactly zero
/// outside its group, which keeps the projected stiffening energy sparse
/// (`docs/modal.md`, "Cost"). The groups' modes are merged by ascending
/// `λ`; within a cluster of equal eigenvalues (relative `CLUSTER_TOL`)
/// spanning several groups, by group (e.g. bending in y before bending in
/// z). One group: [`eigenpairs`] and [`canonicalize`] of the whole.
fn grouped_eigenpairs(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    what: &str,
) -> Result<(Vec<f64>, DMatrix<f64>), ModalError> {
    let n = k.nrows();
    let groups = coupled_groups(k, m);
    if groups.len() <= 1 {
        let (lambda, mut phi) = eigenpairs(k, m, what)?;
        canonicalize(&mut phi, &lambda);
        return Ok((lambda, phi));
    }
    // (λ, group, column of the group's solution, the mode in full size).
    let mut all: Vec<(f64, usize, usize)> = Vec::with_capacity(n);
    let mut solved: Vec<DMatrix<f64>> = Vec::with_capacity(groups.len());
    for (g, idx) in groups.iter().enumerate() {
        let kg = k.select_rows(idx).select_columns(idx);
        let mg = m.select_rows(idx).select_columns(idx);
        let (lambda, mut phi) = eigenpairs(&kg, &mg, what)?;
        canonicalize(&mut phi, &lambda);
        all.extend(lambda.iter().enumerate().map(|(c, &l)| (l, g, c)));
        solved.push(phi);
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut start = 0;
    while start < all.len() {
        let mut end = start + 1;
        while end < all.len()
            && (all[end].0 - all[end - 1].0).abs()
                <= CLUSTER_TOL * all[end].0.abs().max(all[end - 1].0.abs())
        {
            end += 1;
        }
        all[start..end].sort_by(|a, b| a.1.cmp(&b.1).then(a.2.cmp(&b.2)));
        start = end;
    }
    let mut lambda = Vec::with_capacity(n);
    let mut phi = DMatrix::zeros(n, n);
    for (col, &(l, g, c)) in all.iter().enumerate() {
        lambda.push(l);
        for (r, &i) in groups[g].iter().enumerate() {
            phi[(i, col)] = solved[g][(r, c)];
        }
    }
    Ok((lambda, phi))
}

/// All eigenpairs of `K φ = λ M φ` (`K`, `M` symmetric positive definite):
/// `λ` ascending and `Φ` mass normalized, not yet canonical (see the module
/// documentation).
fn eigenpairs(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    what: &str,
) -> Result<(Vec<f64>, DMatrix<f64>), ModalError> {
    let n = k.nrows();
    if n == 0 {
        return Ok((Vec::new(), DMatrix::zeros(0, 0)));
    }
    for (name, a) in [("stiffness", k), ("mass", m)] {
        if let Some(v) = a.iter().find(|v| !v.is_finite()) {
            return Err(ModalError::NotDefinite(format!(
                "the {name} matrix of the eigenproblem with stiffness {what} has the entry {v:?}: the parameters are beyond the range of f64"
            )));
        }
    }
    let chol = Cholesky::new(k.clone()).ok_or_else(|| {
        ModalError::NotDefinite(format!(
            "the stiffness {what} is not positive definite: the body has a mechanism or a rigid-body motion its reference condition does not remove"
        ))
    })?;
    let l = chol.l();
    // B = L⁻¹ M L⁻ᵀ = L⁻¹ (L⁻¹ M)ᵀ (M symmetric).
    let x = l
        .solve_lower_triangular(m)
        .expect("a Cholesky factor has a non-zero diagonal");
    let b = l
        .solve_lower_triangular(&x.transpose())
        .expect("a Cholesky factor has a non-zero diagonal");
    if let Some(v) = b.iter().find(|v| !v.is_finite()) {
        return Err(ModalError::NotDefinite(format!(
            "the eigenproblem with stiffness {what} overflows: L⁻¹ M L⁻ᵀ has the entry {v:?}, as the mass and stiffness matrices are too far apart in scale for f64 (largest mass {:.3e}, largest stiffness {:.3e}): the parameters are beyond the range of f64",
            m.amax(),
            k.amax()
        )));
    }
    let b = sym(b);
    let mut eig = SymmetricEigen::new(b.clone());
    repair_pairing(&b, &mut eig);
    let mut order: Vec<usize> = (0..n).collect();
    // Largest μ first (= smallest λ); ties by index.
    order.sort_by(|&a, &b| {
        eig.eigenvalues[b]
            .total_cmp(&eig.eigenvalues[a])
            .then(a.cmp(&b))
    });
    let lt = l.transpose();
    let mut lambda = Vec::with_capacity(n);
    let mut phi = DMatrix::zeros(n, n);
    for (col, &i) in order.iter().enumerate() {
        let mu = eig.eigenvalues[i];
        if !mu.is_finite() {
            return Err(ModalError::NotDefinite(format!(
                "the eigenproblem with stiffness {what} gives the eigenvalue {mu:?} of L⁻¹ M L⁻ᵀ, not a finite number: the parameters are beyond the range of f64"
            )));
        }
        if mu <= 0.0 {
            return Err(ModalError::NotDefinite(format!(
                "the mass matrix of the eigenproblem with stiffness {what} is not positive definite (eigenvalue {mu:e} of L⁻¹ M L⁻ᵀ): a coordinate carries no mass (e.g. the nodal rotations of the lumped formalism), so some frequencies are infinite; reduce the consistent-formalism body"
            )));
        }
        let y = eig.eigenvectors.column(i).into_owned();
        let v = lt
            .solve_upper_triangular(&y)
            .expect("a Cholesky factor has a non-zero diagonal");
        // φᵀMφ = μ in exact arithmetic; normalize with the computed value so
        // that the modal mass is 1 to round-off even for high modes.
        let mass = v.dot(&(m * &v));
        phi.set_column(col, &(v / mass.sqrt()));
        lambda.push(1.0 / mu);
    }
    Ok((lambda, phi))
}

/// Pair `eig`'s eigenvalues with the right eigenvectors. nalgebra's
/// `SymmetricEigen` can return accurate eigenvectors with their eigenvalues
/// swapped (dimforge/nalgebra#1109, open; met on the solid cantilever of
/// tests/data/fe, where two modes at λ = 3.8e8 and 6.2e8 came back
/// exchanged). Each eigenvector's Rayleigh quotient `yᵀBy` is its
/// eigenvalue to `ε‖B‖`; if any differs from the eigenvalue it came with by
/// more than `1e-6 |μ| + 100 ε μ_max`, the eigenvalues (a correct set) are
/// reassigned by rank: the vector with the k-th largest quotient gets the
/// k-th largest eigenvalue (ties by index). Otherwise nothing changes, so
/// results are bit for bit those of the solver whenever it paired them.
fn repair_pairing(b: &DMatrix<f64>, eig: &mut SymmetricEigen<f64, nalgebra::Dyn>) {
    let n = b.nrows();
    let by = b * &eig.eigenvectors;
    let rq: Vec<f64> = (0..n)
        .map(|i| eig.eigenvectors.column(i).dot(&by.column(i)))
        .collect();
    let mu_max = eig.eigenvalues.amax();
    let paired = (0..n).all(|i| {
        let mu = eig.eigenvalues[i];
        (rq[i] - mu).abs() <= 1e-6 * mu.abs() + 100.0 * f64::EPSILON * mu_max
    });
    if paired {
        return;
    }
    let mut by_rq: Vec<usize> = (0..n).collect();
    by_rq.sort_by(|&a, &b| rq[b].total_cmp(&rq[a]).then(a.cmp(&b)));
    let mut values: Vec<f64> = eig.eigenvalues.iter().copied().collect();
    values.sort_by(|a, b| b.total_cmp(a));
    for (rank, &i) in by_rq.iter().enumerate() {
        eig.eigenvalues[i] = values[rank];
    }
}

/// `M`-orthonormalize the columns in order (classical Gram–Schmidt, two
/// passes per column), then fix every column's sign. The inverse form makes
/// the low modes accurate but leaves `φ_iᵀ M φ_j` of order `ε λ_max/λ_1`
/// between high modes; the lowest modes come first and only change at
/// round-off level, the higher ones are made orthogonal to them.
fn orthonormalize(phi: &mut DMatrix<f64>, m: &DMatrix<f64>) {
    for j in 0..phi.ncols() {
        for _ in 0..2 {
            let mv = m * phi.column(j);
            if j > 0 {
                let prev = phi.columns(0, j).into_owned();
                let c = prev.transpose() * &mv;
                let corr = prev * c;
                let mut col = phi.column_mut(j);
                col -= corr;
            }
        }
        let mv = m * phi.column(j);
        let norm = phi.column(j).dot(&mv).sqrt();
        phi.column_mut(j).unscale_mut(norm);
    }
    for j in 0..phi.ncols() {
        fix_sign(phi, j);
    }
}

/// Replace each cluster of (numerically) equal eigenvalues by the canonical
/// basis of its subspace (module documentation).
fn canonicalize(phi: &mut DMatrix<f64>, lambda: &[f64]) {
    let n = lambda.len();
    let mut start = 0;
    while start < n {
        let mut end = start + 1;
        while end < n
            && (lambda[end] - lambda[end - 1]).abs()
                <= CLUSTER_TOL * lambda[end].abs().max(lambda[end - 1].abs())
        {
            end += 1;
        }
        if end - start > 1 {
            canonical_cluster(phi, start, end);
        }
        start = end;
    }
}

/// The first index whose value is within `TIE_TOL` (relative) of the maximum.
fn first_max(values: impl Iterator<Item = (usize, f64)> + Clone) -> Option<usize> {
    let max = values.clone().map(|(_, v)| v).fold(0.0_f64, f64::max);
    if max <= 0.0 {
        return None;
    }
    values
        .filter(|&(_, v)| v >= (1.0 - TIE_TOL) * max)
        .map(|(i, _)| i)
        .next()
}

fn canonical_cluster(phi: &mut DMatrix<f64>, start: usize, end: usize) {
    let rows = phi.nrows();
    let mut pivots: Vec<usize> = Vec::new();
    for t in start..end {
        let norms: Vec<f64> = (0..rows)
            .map(|r| {
                if pivots.contains(&r) {
                    0.0
                } else {
                    (t..end).map(|j| phi[(r, j)].powi(2)).sum::<f64>().sqrt()
                }
            })
            .collect();
        let Some(p) = first_max(norms.iter().copied().enumerate()) else {
            return;
        };
        // Householder reflection H (symmetric, orthogonal) with v H = α e₁,
        // v the pivot row over columns t..end.
        let v: Vec<f64> = (t..end).map(|j| phi[(p, j)]).collect();
        let norm = norms[p];
        let alpha = if v[0] >= 0.0 { -norm } else { norm };
        let mut u = v;
        u[0] -= alpha;
        let beta: f64 = u.iter().map(|x| x * x).sum();
        if beta > 0.0 {
            for r in 0..rows {
                let w: f64 = u
                    .iter()
                    .enumerate()
                    .map(|(i, ui)| phi[(r, t + i)] * ui)
                    .sum();
                let f = 2.0 * w / beta;
                for (i, ui) in u.iter().enumerate() {
                    phi[(r, t + i)] -= f * ui;
                }
            }
        }
        for j in t + 1..end {
            phi[(p, j)] = 0.0;
        }
        pivots.push(p);
    }
}

fn fix_sign(phi: &mut DMatrix<f64>, j: usize) {
    let col = phi.column(j);
    if let Some(i) = first_max(col.iter().map(|v| v.abs()).enumerate()) {
        if phi[(i, j)] < 0.0 {
            phi.column_mut(j).neg_mut();
        }
    }
}

/// An orthonormal basis (n × (n − r)) of the orthogonal complement of the
/// columns of `c` (n × r, full column rank): the trailing columns of the
/// Householder `Q` of `[c | e₁ … e_{n−r}]`.
pub(crate) fn complement(c: &DMatrix<f64>) -> DMatrix<f64> {
    let (n, r) = c.shape();
    let mut a = DMatrix::zeros(n, n);
    a.view_mut((0, 0), (n, r)).copy_from(c);
    for i in 0..n - r {
        a[(i, r + i)] = 1.0;
    }
    let q = QR::new(a).q();
    q.columns(r, n - r).into_owned()
}

/// The rigid-body motions of the body's nodal coordinates that its dof kinds
/// can represent (n_f × r): translations along x, y, z and infinitesimal
/// rotations about x, y, z of node `j` at `(x_j, 0, 0)`, `x_j = j L/N`:
/// `u = t + ω × (x_j, 0, 0)`, nodal rotation `ω`. A motion is kept only if
/// every non-zero nodal value it needs is one of the body's coordinates
/// (a planar beam has 3, a spatial one 6, an axial bar 1). Meaningful for a
/// free body (other reference conditions remove coordinates the motions
/// need, so they come out empty or partial).
pub fn rigid_body_modes(spec: &BodySpec, length: f64) -> DMatrix<f64> {
    let h = length / spec.elements as f64;
    let dofs = spec.dofs();
    let present: BTreeSet<(usize, Kind)> = dofs.iter().map(|d| (d.node, d.kind)).collect();
    // Nodal value of kind `kind` at position x for rigid motion `m`
    // (0..3 translations, 3..6 rotations).
    let value = |m: usize, kind: Kind, x: f64| -> f64 {
        let (t, w) = if m < 3 {
            (m as i32, -1)
        } else {
            (-1, m as i32 - 3)
        };
        match kind {
            Kind::Ux => f64::from(t == 0),
            Kind::Uy => f64::from(t == 1) + if w == 2 { x } else { 0.0 },
            Kind::Uz => f64::from(t == 2) - if w == 1 { x } else { 0.0 },
            Kind::Rx => f64::from(w == 0),
            Kind::Ry => f64::from(w == 1),
            Kind::Rz => f64::from(w == 2),
        }
    };
    let all = [Kind::Ux, Kind::Uy, Kind::Uz, Kind::Rx, Kind::Ry, Kind::Rz];
    let mut cols: Vec<Vec<f64>> = Vec::new();
    for m in 0..6 {
        let representable = (0..=spec.elements).all(|node| {
            let x = node as f64 * h;
            all.iter()
                .all(|&kind| value(m, kind, x) == 0.0 || present.contains(&(node, kind)))
        });
        if representable {
            cols.push(
                dofs.iter()
                    .map(|d| value(m, d.kind, d.node as f64 * h))
                    .collect(),
            );
        }
    }
    DMatrix::from_fn(dofs.len(), cols.len(), |i, j| cols[j][i])
}

/// Modal truncation: the `count` lowest modes of `K φ = λ M φ`.
///
/// With `rigid = None`, `K` must be positive definite (clamped or pinned
/// body). With `rigid = Some(R)` (n_f × r rigid-body motions, e.g.
/// [`rigid_body_modes`] of a free body), the rigid-body modes are removed
/// exactly rather than by thresholding small eigenvalues: `K R ≈ 0` is
/// checked (`‖K r‖ ≤ 1e-10 ‖K‖_F ‖r‖` for each motion), and the problem is
/// solved in the `M`-orthogonal complement of `span R` (an orthonormal basis
/// `Z` of the null space of `(M R)ᵀ`, reduced `Zᵀ K Z`, `Zᵀ M Z`), where `K`
/// is positive definite; the elastic modes `φ = Z φ_z` are then
/// `M`-orthogonal to every rigid motion up to round-off, whatever their
/// frequencies.
pub fn modal_truncation(
    m: &DMatrix<f64>,
    k: &DMatrix<f64>,
    count: usize,
    rigid: Option<&DMatrix<f64>>,
) -> Result<ModalBasis, ModalError> {
    let n = m.nrows();
    check_square("m_ff", m, n)?;
    check_square("K_ff", k, n)?;
    let (lambda, phi) = match rigid {
        None => grouped_eigenpairs(k, m, "K_ff")?,
        Some(r) => {
            if r.nrows() != n {
                return Err(ModalError::Input(format!(
                    "rigid-body motions must have {n} rows, found {}",
                    r.nrows()
                )));
            }
            let kn = k.norm();
            for (j, col) in r.column_iter().enumerate() {
                let res = (k * col).norm();
                if res > 1e-10 * kn * col.norm() {
                    return Err(ModalError::Input(format!(
                        "rigid-body motion {j} is not in the null space of K_ff (‖K r‖ = {res:e}, ‖K‖ ‖r‖ = {:e})",
                        kn * col.norm()
                    )));
                }
            }
            let z = complement(&(m * r));
            let zt = z.transpose();
            // `Z` couples every coordinate: one group, canonical in the
            // body's coordinates.
            let (lambda, phi_z) = eigenpairs(
                &sym(&zt * k * &z),
                &sym(&zt * m * &z),
                "K_ff in the complement of the rigid-body motions",
            )?;
            let mut phi = z * phi_z;
            canonicalize(&mut phi, &lambda);
            (lambda, phi)
        }
    };
    if count == 0 || count > lambda.len() {
        return Err(ModalError::Input(format!(
            "modes must be between 1 and {} (the body's elastic modes), found {count}",
            lambda.len()
        )));
    }
    let mut phi = phi.columns(0, count).into_owned();
    orthonormalize(&mut phi, m);
    Ok(ModalBasis::assemble(m, k, phi, count, &[], &[]))
}

/// Craig–Bampton: boundary coordinates `boundary` (body coordinate indices,
/// any order, no duplicates), the `count` lowest fixed-interface normal modes
/// (`K_II φ = λ M_II φ`, zero at the boundary), then one static constraint
/// mode per boundary coordinate in ascending order
/// (`[−K_II⁻¹ K_IB; I]`). `dof_names[i]` names coordinate `i` in the labels.
pub fn craig_bampton(
    m: &DMatrix<f64>,
    k: &DMatrix<f64>,
    boundary: &[usize],
    count: usize,
    dof_names: &[String],
) -> Result<ModalBasis, ModalError> {
    let n = m.nrows();
    check_square("m_ff", m, n)?;
    check_square("K_ff", k, n)?;
    if dof_names.len() != n {
        return Err(ModalError::Input(format!(
            "need {n} coordinate names, found {}",
            dof_names.len()
        )));
    }
    let mut b: Vec<usize> = boundary.to_vec();
    b.sort_unstable();
    if b.windows(2).any(|w| w[0] == w[1]) {
        return Err(ModalError::Input(
            "boundary coordinates must not repeat".into(),
        ));
    }
    if let Some(&bad) = b.iter().find(|&&i| i >= n) {
        return Err(ModalError::Input(format!(
            "boundary coordinate {bad} out of range (the body has {n})"
        )));
    }
    if b.is_empty() {
        return Err(ModalError::Input(
            "Craig–Bampton needs at least one boundary coordinate".into(),
        ));
    }
    let interior: Vec<usize> = (0..n).filter(|i| b.binary_search(i).is_err()).collect();
    if count > interior.len() {
        return Err(ModalError::Input(format!(
            "modes must be at most {} (the interior coordinates), found {count}",
            interior.len()
        )));
    }
    let ni = interior.len();
    let kii = k.select_rows(&interior).select_columns(&interior);
    let mii = m.select_rows(&interior).select_columns(&interior);
    let kib = k.select_rows(&interior).select_columns(&b);
    let mut phi = DMatrix::zeros(n, count + b.len());
    if ni > 0 {
        let (_, phi_i) = grouped_eigenpairs(&kii, &mii, "K_II (interior, boundary fixed)")?;
        let mut full = DMatrix::zeros(n, ni);
        for (r, &i) in interior.iter().enumerate() {
            full.row_mut(i).copy_from(&phi_i.row(r));
        }
        let mut normal = full.columns(0, count).into_owned();
        orthonormalize(&mut normal, m);
        phi.columns_mut(0, count).copy_from(&normal);
        let chol = Cholesky::new(kii).expect("K_II is positive definite (factored above)");
        let psi = -chol.solve(&kib);
        for (c, &d) in b.iter().enumerate() {
            let col = count + c;
            for (r, &i) in interior.iter().enumerate() {
                phi[(i, col)] = psi[(r, c)];
            }
            phi[(d, col)] = 1.0;
        }
    } else {
        for (c, &d) in b.iter().enumerate() {
            phi[(d, count + c)] = 1.0;
        }
    }
    Ok(ModalBasis::assemble(m, k, phi, count, &b, dof_names))
}

/// Reduce a body: `inv` are its invariants at `p` (n_f = `spec.nf()`); uses
/// `inv.m_ff` and `inv.k_ff`.
/// A free body's modal truncation drops the rigid-body modes
/// ([`rigid_body_modes`]); Craig–Bampton's boundary nodes must keep at least
/// one elastic coordinate (node 0 of a clamped body has none).
pub fn reduce(
    spec: &BodySpec,
    p: &Params,
    inv: &Invariants,
    reduction: &Reduction,
) -> Result<ModalBasis, ModalError> {
    let (m_ff, k_ff) = (&inv.m_ff, &inv.k_ff);
    let dofs = spec.dofs();
    if m_ff.nrows() != dofs.len() {
        return Err(ModalError::Input(format!(
            "the body has {} elastic coordinates, the matrices {}",
            dofs.len(),
            m_ff.nrows()
        )));
    }
    match reduction {
        Reduction::Modal { modes } => {
            let rigid =
                (spec.reference == Reference::Free).then(|| rigid_body_modes(spec, p.length));
            modal_truncation(m_ff, k_ff, *modes, rigid.as_ref())
        }
        Reduction::CraigBampton {
            boundary_nodes,
            modes,
        } => {
            let mut boundary = Vec::new();
            let mut nodes = boundary_nodes.clone();
            nodes.sort_unstable();
            nodes.dedup();
            for &node in &nodes {
                if node > spec.elements {
                    return Err(ModalError::Input(format!(
                        "boundary node {node} out of range: the body has nodes 0 to {}",
                        spec.elements
                    )));
                }
                let here: Vec<usize> = (0..dofs.len()).filter(|&i| dofs[i].node == node).collect();
                if here.is_empty() {
                    return Err(ModalError::Input(format!(
                        "boundary node {node} has no elastic coordinates (the {} reference condition removes them)",
                        spec.reference
                    )));
                }
                boundary.extend(here);
            }
            let names: Vec<String> = dofs.iter().map(|d| d.to_string()).collect();
            craig_bampton(m_ff, k_ff, &boundary, *modes, &names)
        }
    }
}
