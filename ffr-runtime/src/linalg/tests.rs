//! The solvers against nalgebra's dense LU on the assembled matrix, and their
//! failure modes.

use nalgebra::{DMatrix, DVector};

use super::*;

/// SplitMix64: reproducible random numbers without a dependency.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [-1, 1).
    fn sym(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// A sorted random subset of `0..k` with `m` elements.
    fn subset(&mut self, k: usize, m: usize) -> Vec<usize> {
        let mut all: Vec<usize> = (0..k).collect();
        for i in 0..m {
            let j = i + self.below(k - i);
            all.swap(i, j);
        }
        let mut s = all[..m].to_vec();
        s.sort_unstable();
        s
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Nonsymmetric, strictly diagonally dominant.
    Dominant,
    /// Symmetric, diagonally dominant with a positive diagonal (so SPD).
    Spd,
    /// Nonsymmetric, zero diagonal entries at even `i < n − 1` (so that the
    /// matrix stays generically nonsingular): step 0 needs a row interchange.
    /// Dominant if `kl = 0` or `ku = 0` (a triangular matrix would be
    /// singular).
    ZeroDiagonal,
    /// Like `ZeroDiagonal` with diagonal entries of size 1e-10 instead of
    /// zero: without pivoting about 10 digits would be lost.
    TinyDiagonal,
}

/// Random band entries of kind `kind` written into `band` and into the
/// dense matrix `a` at offset `off`.
fn fill_band(rng: &mut Rng, band: &mut BandMatrix, a: &mut DMatrix<f64>, off: usize, kind: Kind) {
    let (n, kl, ku) = (band.n(), band.kl(), band.ku());
    let mut b = DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        for i in j.saturating_sub(ku)..(j + kl + 1).min(n) {
            b[(i, j)] = rng.sym();
        }
    }
    let kind = match kind {
        Kind::ZeroDiagonal | Kind::TinyDiagonal if kl == 0 || ku == 0 => Kind::Dominant,
        k => k,
    };
    match kind {
        Kind::Dominant => {
            for i in 0..n {
                let s: f64 = b.row(i).iter().map(|v| v.abs()).sum();
                b[(i, i)] = if rng.sym() > 0.0 { s + 1.0 } else { -(s + 1.0) };
            }
        }
        Kind::Spd => {
            assert_eq!(kl, ku);
            let bt = b.transpose();
            b += bt;
            for i in 0..n {
                let s: f64 = b
                    .row(i)
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| *j != i)
                    .map(|(_, v)| v.abs())
                    .sum();
                b[(i, i)] = s + 0.5;
            }
        }
        Kind::ZeroDiagonal => {
            for i in (0..n.saturating_sub(1)).step_by(2) {
                b[(i, i)] = 0.0;
            }
        }
        Kind::TinyDiagonal => {
            for i in (0..n.saturating_sub(1)).step_by(2) {
                b[(i, i)] = 1e-10 * rng.sym();
            }
        }
    }
    for j in 0..n {
        for i in 0..n {
            if band.in_band(i, j) {
                band.add(i, j, b[(i, j)]);
            } else {
                assert_eq!(b[(i, j)], 0.0);
            }
            a[(off + i, off + j)] = b[(i, j)];
        }
    }
}

struct Case {
    sys: BorderedSystem,
    a: DMatrix<f64>,
}

/// A random bordered system and the same matrix assembled densely
/// (unknowns: band blocks concatenated, then the border).
fn random_case(seed: u64, shapes: &[BlockShape], kinds: &[Kind], k: usize) -> Case {
    let mut sys = BorderedSystem::new(shapes, k);
    let a = fill_case(seed, &mut sys, shapes, kinds);
    Case { sys, a }
}

/// Fill a cleared `sys` of the given shapes with random entries; return the
/// dense matrix.
fn fill_case(
    seed: u64,
    sys: &mut BorderedSystem,
    shapes: &[BlockShape],
    kinds: &[Kind],
) -> DMatrix<f64> {
    let mut rng = Rng(seed);
    let (nb, dim, k) = (sys.n_band(), sys.dim(), sys.k());
    let mut a = DMatrix::<f64>::zeros(dim, dim);
    for (i, s) in shapes.iter().enumerate() {
        let off = sys.block_range(i).start;
        fill_band(&mut rng, sys.band_mut(i), &mut a, off, kinds[i]);
        let m = s.border.len();
        for l in 0..m {
            for r in 0..s.n {
                let c = 0.5 * rng.sym();
                let e = 0.5 * rng.sym();
                sys.c_mut(i).add(r, l, c);
                sys.e_mut(i).set(l, r, e);
                a[(off + r, nb + s.border[l])] = c;
                a[(nb + s.border[l], off + r)] = e;
            }
        }
    }
    // A banded border gets the entries of its band only.
    let band = sys.banded_border();
    for j in 0..k {
        for i in 0..k {
            let v = rng.sym() + if i == j { 2.0 + k as f64 } else { 0.0 };
            if band.is_none_or(|(kl, ku)| j <= i + ku && i <= j + kl) {
                sys.d_add(i, j, v);
                a[(nb + i, nb + j)] = v;
            }
        }
    }
    a
}

fn random_rhs(seed: u64, dim: usize) -> Vec<f64> {
    let mut rng = Rng(seed ^ 0xdead_beef);
    (0..dim).map(|_| rng.sym()).collect()
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Solve the case with the bordered solver and with nalgebra; check the
/// product, the solution and the residual. Returns the relative error.
fn check_case(seed: u64, mut case: Case) -> f64 {
    let sys = &mut case.sys;
    let (nb, k, dim) = (sys.n_band(), sys.k(), sys.dim());
    let b = random_rhs(seed, dim);

    // y = A x agrees with the dense product.
    let mut y = vec![0.0; dim];
    let (yb, yk) = y.split_at_mut(nb);
    sys.mul_vec(&b[..nb], &b[nb..], yb, yk);
    let y_ref = &case.a * DVector::from_column_slice(&b);
    let a_norm = case
        .a
        .row_iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    for (u, v) in y.iter().zip(y_ref.iter()) {
        assert!(
            (u - v).abs() <= 1e-14 * a_norm * norm_inf(&b),
            "mul_vec: {u} vs {v}"
        );
    }

    sys.factor().expect("nonsingular test matrix");
    // The sign of the determinant from the factors (block elimination:
    // Π det B_i · det S) is nalgebra's of the whole matrix.
    if dim > 0 {
        let det = case.a.clone().lu().determinant();
        assert!(det.is_finite() && det != 0.0, "test determinant {det:e}");
        assert_eq!(sys.det_sign(), det.signum(), "det = {det:e}");
    }
    let mut x = b.clone();
    let (xb, xk) = x.split_at_mut(nb);
    sys.solve(xb, xk);
    assert_eq!(xk.len(), k);

    if dim == 0 {
        return 0.0;
    }
    let x_ref = case
        .a
        .clone()
        .lu()
        .solve(&DVector::from_column_slice(&b))
        .expect("nalgebra: singular");
    let diff: Vec<f64> = x.iter().zip(x_ref.iter()).map(|(u, v)| u - v).collect();
    let rel = norm_inf(&diff) / norm_inf(x_ref.as_slice());
    let r = &case.a * DVector::from_column_slice(&x) - DVector::from_column_slice(&b);
    let res = norm_inf(r.as_slice()) / (a_norm * norm_inf(&x));
    let r_ref = &case.a * &x_ref - DVector::from_column_slice(&b);
    let res_ref = norm_inf(r_ref.as_slice()) / (a_norm * norm_inf(x_ref.as_slice()));
    eprintln!(
        "dim {dim}: relative error {rel:.1e}, relative residual {res:.1e} (nalgebra {res_ref:.1e})"
    );
    assert!(
        rel <= 1e-12,
        "solution differs from nalgebra by {rel:e} (relative)"
    );
    // Block elimination is backward stable only up to about cond(B_i): the
    // worst case here (cond B = 1e5, tridiagonal with zeros on the
    // diagonal) has 2.8e-15, where nalgebra's LU of the whole matrix has 1.5e-17.
    assert!(res <= 1e-14, "relative residual {res:e}");
    rel
}

fn shape(n: usize, kl: usize, ku: usize, border: Vec<usize>) -> BlockShape {
    BlockShape { n, kl, ku, border }
}

const KINDS: [Kind; 4] = [
    Kind::Dominant,
    Kind::Spd,
    Kind::ZeroDiagonal,
    Kind::TinyDiagonal,
];

#[test]
fn one_block_each_kind_against_nalgebra() {
    for (s, &kind) in KINDS.iter().enumerate() {
        for &(n, bw) in &[(24, 5), (60, 11), (7, 2)] {
            let seed = 100 + s as u64 * 10 + n as u64;
            let case = random_case(
                seed,
                &[shape(n, bw, bw, vec![0, 1, 2, 3, 4, 5])],
                &[kind],
                6,
            );
            check_case(seed, case);
        }
    }
}

#[test]
fn three_blocks_random_borders_against_nalgebra() {
    let mut rng = Rng(7);
    for trial in 0..20u64 {
        let k = 3 + rng.below(20);
        let mut shapes = Vec::new();
        let mut kinds = Vec::new();
        for b in 0..3 {
            let n = 1 + rng.below(40);
            let kl = rng.below(12);
            let ku = rng.below(12);
            let m = if b == 1 && trial.is_multiple_of(2) {
                0
            } else {
                rng.below(k.min(15) + 1)
            };
            let border = rng.subset(k, m);
            let kind = KINDS[rng.below(4)];
            let kind = if kind == Kind::Spd && kl != ku {
                Kind::Dominant
            } else {
                kind
            };
            shapes.push(shape(n, kl, ku, border));
            kinds.push(kind);
        }
        let case = random_case(1000 + trial, &shapes, &kinds, k);
        check_case(1000 + trial, case);
    }
}

/// A chain: block `i` couples to border unknowns `2i … 2i + 3`, so that
/// the border is banded (`kl = ku = 3`) and its Schur complement is
/// factored in band storage; solution and the sign of the determinant
/// against nalgebra, for each kind of block.
#[test]
fn banded_border_chain_against_nalgebra() {
    for (t, &kind) in KINDS.iter().enumerate() {
        let blocks = 6;
        let k = 2 * blocks + 2;
        let shapes: Vec<BlockShape> = (0..blocks)
            .map(|i| shape(5 + i, 2, 2, (2 * i..2 * i + 4).collect()))
            .collect();
        let kinds = vec![kind; blocks];
        let seed = 4000 + t as u64;
        let mut sys = BorderedSystem::with_banded_border(&shapes, k, 3, 3);
        assert_eq!(sys.banded_border(), Some((3, 3)));
        let a = fill_case(seed, &mut sys, &shapes, &kinds);
        check_case(seed, Case { sys, a });
    }
}

#[test]
fn no_blocks_rigid_only() {
    let case = random_case(3, &[], &[], 9);
    check_case(3, case);
    // Nothing at all.
    let case = random_case(4, &[], &[], 0);
    check_case(4, case);
}

#[test]
fn no_border() {
    let case = random_case(5, &[shape(30, 5, 5, vec![])], &[Kind::ZeroDiagonal], 0);
    check_case(5, case);
    let shapes = [
        shape(30, 5, 2, vec![]),
        shape(1, 0, 0, vec![]),
        shape(17, 3, 11, vec![]),
    ];
    let kinds = [Kind::TinyDiagonal, Kind::Dominant, Kind::ZeroDiagonal];
    let case = random_case(6, &shapes, &kinds, 0);
    check_case(6, case);
}

#[test]
fn tiny_blocks_and_empty_borders() {
    // n_i = 1, n_i smaller than the bandwidth, n_i = 0, m_i = 0, m_i = k.
    let shapes = [
        shape(1, 0, 0, vec![0, 2]),
        shape(1, 11, 11, vec![1]),
        shape(3, 11, 11, vec![0, 1, 2, 3]),
        shape(0, 5, 5, vec![2, 3]),
        shape(5, 11, 2, vec![]),
        shape(2, 1, 1, vec![3]),
    ];
    let kinds = [
        Kind::Dominant,
        Kind::TinyDiagonal,
        Kind::ZeroDiagonal,
        Kind::Dominant,
        Kind::TinyDiagonal,
        Kind::Spd,
    ];
    let case = random_case(8, &shapes, &kinds, 4);
    assert_eq!(case.sys.band(1).kl(), 0, "bandwidth clamped to n - 1");
    assert_eq!(case.sys.band(2).ku(), 2, "bandwidth clamped to n - 1");
    check_case(8, case);
}

#[test]
fn refactor_after_clear_reuses_storage() {
    let shapes = [
        shape(50, 5, 5, vec![0, 3, 5]),
        shape(40, 11, 11, vec![1, 2, 3, 4]),
    ];
    let kinds = [Kind::ZeroDiagonal, Kind::Dominant];
    let mut case = random_case(9, &shapes, &kinds, 6);
    case.sys.factor().unwrap();
    let (mut xb, mut xk) = (vec![1.0; 90], vec![1.0; 6]);
    case.sys.solve(&mut xb, &mut xk);
    // Clear and refill the same system with other entries: the old factors
    // and fill-in must not leak into the new factorization.
    case.sys.clear();
    let kinds = [Kind::TinyDiagonal, Kind::ZeroDiagonal];
    case.a = fill_case(10, &mut case.sys, &shapes, &kinds);
    check_case(10, case);

    // Clear really zeroes: with only unit diagonals set, solve is identity.
    let mut sys = random_case(11, &shapes, &kinds, 6).sys;
    sys.factor().unwrap();
    sys.clear();
    for i in 0..2 {
        let n = sys.block_range(i).len();
        for r in 0..n {
            sys.band_mut(i).add(r, r, 1.0);
        }
    }
    for g in 0..6 {
        sys.d_mut().set(g, g, 1.0);
    }
    sys.factor().unwrap();
    let mut xb: Vec<f64> = (0..90).map(|i| i as f64).collect();
    let mut xk: Vec<f64> = (0..6).map(|i| -(i as f64)).collect();
    sys.solve(&mut xb, &mut xk);
    assert!(xb.iter().enumerate().all(|(i, &v)| v == i as f64));
    assert!(xk.iter().enumerate().all(|(i, &v)| v == -(i as f64)));
}

#[test]
fn band_matrix_alone_multi_rhs_against_nalgebra() {
    let mut rng = Rng(11);
    for &(n, kl, ku) in &[(40, 0, 3), (40, 4, 0), (40, 2, 7), (13, 12, 12), (1, 0, 0)] {
        let mut band = BandMatrix::new(n, kl, ku);
        let mut a = DMatrix::zeros(n, n);
        fill_band(&mut rng, &mut band, &mut a, 0, Kind::TinyDiagonal);
        let nrhs = 3;
        let b: Vec<f64> = (0..n * nrhs).map(|_| rng.sym()).collect();
        let mut y = vec![0.0; n];
        band.mul_vec_add(&b[..n], &mut y);
        let y_ref = &a * DVector::from_column_slice(&b[..n]);
        for (u, v) in y.iter().zip(y_ref.iter()) {
            assert!((u - v).abs() < 1e-13);
        }
        band.factor().unwrap();
        let mut x = b.clone();
        band.solve_many(&mut x, nrhs);
        let x_ref = a
            .clone()
            .lu()
            .solve(&DMatrix::from_column_slice(n, nrhs, &b))
            .unwrap();
        let err = x
            .iter()
            .zip(x_ref.iter())
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        assert!(
            err <= 1e-12 * x_ref.amax(),
            "n {n} kl {kl} ku {ku}: error {err:e}"
        );
        let info = band.pivot_info();
        assert!(
            info.min_pivot > 0.0
                && info.min_pivot <= info.max_pivot
                && info.max_u >= info.max_pivot
        );
        assert!(
            info.growth() > 0.0 && info.growth() < 100.0,
            "growth {}",
            info.growth()
        );
    }
}

#[test]
fn pivoting_is_needed_and_done() {
    // [[0, 1], [1, 1]]: without the interchange the first pivot is zero.
    let mut band = BandMatrix::new(2, 1, 1);
    band.add(0, 1, 1.0);
    band.add(1, 0, 1.0);
    band.add(1, 1, 1.0);
    band.factor().unwrap();
    let mut b = [3.0, 5.0];
    band.solve(&mut b);
    assert_eq!(b, [2.0, 3.0]);
    let mut d = DenseLu::new(2);
    d.set(0, 1, 1.0);
    d.set(1, 0, 1.0);
    d.set(1, 1, 1.0);
    d.factor().unwrap();
    let mut b = [3.0, 5.0];
    d.solve(&mut b);
    assert_eq!(b, [2.0, 3.0]);
}

#[test]
fn dense_lu_against_nalgebra() {
    let mut rng = Rng(12);
    for n in [1usize, 2, 7, 40] {
        let mut d = DenseLu::new(n);
        let mut a = DMatrix::zeros(n, n);
        for j in 0..n {
            for i in 0..n {
                let v = if i == j { 1e-9 * rng.sym() } else { rng.sym() };
                d.set(i, j, v);
                a[(i, j)] = v;
            }
        }
        d.factor().unwrap();
        let b: Vec<f64> = (0..2 * n).map(|_| rng.sym()).collect();
        let mut x = b.clone();
        d.solve_many(&mut x, 2);
        let x_ref = a.lu().solve(&DMatrix::from_column_slice(n, 2, &b)).unwrap();
        let err = x
            .iter()
            .zip(x_ref.iter())
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        assert!(err <= 1e-12 * x_ref.amax(), "n {n}: error {err:e}");
    }
}

#[test]
fn singular_band_block_is_reported() {
    // Block 1 gets an all-zero column 7: row operations keep it zero, so the
    // pivot at step 7 is exactly zero.
    let shapes = [shape(20, 3, 3, vec![0, 1]), shape(15, 2, 4, vec![1, 2])];
    let mut sys = random_case(13, &shapes, &[Kind::Dominant, Kind::ZeroDiagonal], 3).sys;
    for r in 3..=9 {
        sys.band_mut(1).set(r, 7, 0.0);
    }
    let err = sys.factor().unwrap_err();
    assert_eq!(
        err,
        Singular {
            part: Part::Block(1),
            column: 7,
            failure: Failure::ZeroPivot
        }
    );
    assert!(!sys.is_factored());
}

#[test]
#[should_panic(expected = "solve without a successful factor")]
fn solve_after_failed_factor_panics() {
    let mut sys = BorderedSystem::new(&[shape(3, 1, 1, vec![0])], 1);
    sys.d_mut().set(0, 0, 1.0);
    assert!(sys.factor().is_err());
    let (mut xb, mut xk) = (vec![1.0; 3], vec![1.0]);
    sys.solve(&mut xb, &mut xk);
}

#[test]
fn redundant_constraint_gives_singular_schur_complement() {
    // Border unknowns 2 and 4 are Lagrange multipliers of the same
    // constraint, imposed twice: identical E rows, identical C columns and
    // zero D rows/columns. S then has two bit-identical rows, and the
    // elimination makes one of them exactly zero.
    let shapes = [
        shape(25, 5, 5, vec![0, 2, 4]),
        shape(12, 2, 2, vec![1, 2, 3, 4]),
    ];
    let mut case = random_case(14, &shapes, &[Kind::Dominant, Kind::ZeroDiagonal], 5);
    let sys = &mut case.sys;
    for i in 0..2 {
        let (l2, l4) = (
            sys.border_local(i, 2).unwrap(),
            sys.border_local(i, 4).unwrap(),
        );
        let e2 = sys.e_row_mut(i, l2).to_vec();
        sys.e_row_mut(i, l4).copy_from_slice(&e2);
        let c2 = sys.c_col_mut(i, l2).to_vec();
        sys.c_col_mut(i, l4).copy_from_slice(&c2);
    }
    let mut d = sys.d_mut();
    for g in 0..5 {
        for h in [2, 4] {
            d.set(g, h, 0.0);
            d.set(h, g, 0.0);
        }
    }
    let err = sys.factor().unwrap_err();
    assert_eq!(err.part, Part::Schur);
    assert_eq!(err.failure, Failure::ZeroPivot);
}

#[test]
fn singular_d_alone() {
    // No blocks: S = D = [[2, 1], [4, 2]] has an exactly zero second pivot.
    let mut sys = BorderedSystem::new(&[], 2);
    let mut d = sys.d_mut();
    d.set(0, 0, 2.0);
    d.set(0, 1, 1.0);
    d.set(1, 0, 4.0);
    d.set(1, 1, 2.0);
    let err = sys.factor().unwrap_err();
    assert_eq!(
        err,
        Singular {
            part: Part::Schur,
            column: 1,
            failure: Failure::ZeroPivot
        }
    );
}

#[test]
fn non_finite_input_is_reported_not_passed_on() {
    let shapes = [shape(10, 2, 2, vec![0, 1]), shape(8, 1, 3, vec![1, 2])];
    let kinds = [Kind::Dominant, Kind::Dominant];
    let base = random_case(15, &shapes, &kinds, 3).sys;

    let mut sys = base.clone();
    sys.band_mut(1).add(4, 5, f64::NAN);
    assert_eq!(
        sys.factor().unwrap_err(),
        Singular {
            part: Part::Block(1),
            column: 5,
            failure: Failure::NonFinite
        }
    );

    // NaN or infinity in C or E reaches S (0 · ∞ = NaN included).
    for v in [f64::NAN, f64::INFINITY] {
        let mut sys = base.clone();
        sys.c_mut(0).set(3, 1, v);
        let err = sys.factor().unwrap_err();
        assert_eq!((err.part, err.failure), (Part::Schur, Failure::NonFinite));
        let mut sys = base.clone();
        sys.e_mut(1).set(0, 7, v);
        let err = sys.factor().unwrap_err();
        assert_eq!((err.part, err.failure), (Part::Schur, Failure::NonFinite));
    }
    let mut sys = base.clone();
    sys.d_mut().set(2, 0, f64::NEG_INFINITY);
    let err = sys.factor().unwrap_err();
    assert_eq!(
        err,
        Singular {
            part: Part::Schur,
            column: 0,
            failure: Failure::NonFinite
        }
    );

    // Overflow during the elimination is caught too: pivot 1 (row 0),
    // l = −1, u_11 = 1.7e308 + 1.7e308 = ∞.
    let mut band = BandMatrix::new(2, 1, 1);
    band.add(0, 0, 1.0);
    band.add(0, 1, 1.7e308);
    band.add(1, 0, -1.0);
    band.add(1, 1, 1.7e308);
    assert_eq!(band.factor().unwrap_err().failure, Failure::NonFinite);
}

#[test]
fn near_singular_is_visible_in_the_pivot_report() {
    let shapes = [shape(20, 2, 2, vec![0]), shape(20, 2, 2, vec![1])];
    let mut case = random_case(16, &shapes, &[Kind::Dominant, Kind::Dominant], 2);
    let healthy = {
        let mut s = case.sys.clone();
        s.factor().unwrap();
        s.pivot_report()
    };
    assert!(healthy.min_ratio > 1e-2, "{healthy:?}");
    // Make block 1 nearly singular: column 3 ← column 2 + 1e-14 · e_3.
    let sys = &mut case.sys;
    for r in 0..20 {
        let v = sys.band(1).get(r, 2);
        if sys.band(1).in_band(r, 3) {
            sys.band_mut(1).set(r, 3, v);
        }
    }
    // Column 2 has rows 0..=4; column 3 holds rows 1..=5: row 0 of column 2
    // must be zero for an exact copy.
    sys.band_mut(1).set(0, 2, 0.0);
    sys.band_mut(1).set(5, 3, 0.0);
    sys.band_mut(1).add(3, 3, 1e-14);
    sys.factor().unwrap();
    let report = sys.pivot_report();
    assert_eq!(report.min_ratio_part, Part::Block(1));
    assert!(report.min_ratio < 1e-13, "{report:?}");
}
