//! MBDyn `.fem` export read back by a reader written for this test, following
//! MBDyn's own text reader (`Modal` in `mbdyn/struct/modal.cc`): lines are
//! scanned for `** RECORD GROUP <n>`, group 1 skips one comment line, mode
//! shapes are preceded by one `**` line each, everything else is
//! whitespace-separated tokens. No code is shared with the writer.
//!
//! Compared with values computed directly from the body: total mass, centre
//! of mass and inertia (record 12, and the sum of record 11), modal mass and
//! stiffness, the mode shapes, node coordinates; and what MBDyn builds from
//! records 8 and 11 (its invariant 3, `Σ m_i φ_i`, and its diagnostic
//! generalized mass) against the consistent values.

#![cfg(feature = "modal")]

use ffr_codegen::export::{mbdyn_fem, ExportBody};
use ffr_codegen::modal::{reduce, Invariants, ModalBasis, Reduction};
use ffr_codegen::{BodySpec, Params, Reference, Shape};
use nalgebra::{DMatrix, Matrix3, Vector3};

struct Fem {
    rev: String,
    labels: Vec<String>,
    normal: usize,
    constraint: usize,
    modes: usize,
    initial: [Vec<f64>; 2],
    xyz: Vec<[f64; 3]>,
    /// `shapes[mode][node]`: x y z rx ry rz.
    shapes: Vec<Vec<[f64; 6]>>,
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    lumped: Vec<[f64; 6]>,
    rigid: Option<(f64, [f64; 3], [[f64; 3]; 3])>,
}

/// Token reader over lines, with MBDyn's two line-oriented operations.
struct Cursor<'a> {
    lines: Vec<&'a str>,
    next: usize,
    pending: Vec<&'a str>,
}

impl<'a> Cursor<'a> {
    fn line(&mut self) -> Option<&'a str> {
        // `getline`: the rest of the current line (must be blank here), or the next line.
        if !self.pending.is_empty() {
            panic!("unread tokens {:?} before a line read", self.pending);
        }
        let l = self.lines.get(self.next).copied();
        self.next += 1;
        l
    }
    fn token(&mut self) -> &'a str {
        while self.pending.is_empty() {
            let l = self.lines[self.next];
            self.next += 1;
            self.pending = l.split_whitespace().rev().collect();
        }
        self.pending.pop().unwrap()
    }
    fn real(&mut self) -> f64 {
        let t = self.token();
        t.parse().unwrap_or_else(|_| panic!("not a number: {t}"))
    }
    fn int(&mut self) -> usize {
        self.token().parse().unwrap()
    }
}

fn read_fem(text: &str) -> Fem {
    let mut c = Cursor {
        lines: text.lines().collect(),
        next: 0,
        pending: Vec::new(),
    };
    let mut f = Fem {
        rev: String::new(),
        labels: Vec::new(),
        normal: 0,
        constraint: 0,
        modes: 0,
        initial: [Vec::new(), Vec::new()],
        xyz: Vec::new(),
        shapes: Vec::new(),
        mass: DMatrix::zeros(0, 0),
        stiffness: DMatrix::zeros(0, 0),
        lumped: Vec::new(),
        rigid: None,
    };
    let mut seen = [false; 14];
    let mut nodes = 0;
    while let Some(line) = c.line() {
        if line.starts_with("** END OF FILE") {
            break;
        }
        let Some(rest) = line.strip_prefix("** RECORD GROUP ") else {
            continue;
        };
        let digits: String = rest.chars().take_while(|ch| ch.is_ascii_digit()).collect();
        let g: usize = digits.parse().unwrap();
        assert!(!seen[g], "group {g} twice");
        assert!(g == 1 || seen[1], "group {g} before the header");
        seen[g] = true;
        match g {
            1 => {
                c.line().unwrap(); // one comment line
                f.rev = c.token().to_string();
                nodes = c.int();
                f.normal = c.int();
                let attached = c.int();
                f.constraint = c.int();
                let rejected = c.int();
                f.modes = f.normal + attached + f.constraint - rejected;
                assert_eq!((attached, rejected), (0, 0));
            }
            2 => f.labels = (0..nodes).map(|_| c.token().to_string()).collect(),
            3 | 4 => f.initial[g - 3] = (0..f.modes).map(|_| c.real()).collect(),
            5..=7 => {
                f.xyz.resize(nodes, [0.0; 3]);
                for n in 0..nodes {
                    f.xyz[n][g - 5] = c.real();
                }
            }
            8 => {
                for _ in 0..f.modes {
                    let h = c.line().unwrap();
                    assert!(h.is_empty() || h.starts_with("**"), "mode header {h:?}");
                    f.shapes.push(
                        (0..nodes)
                            .map(|_| std::array::from_fn(|_| c.real()))
                            .collect(),
                    );
                }
            }
            9 | 10 => {
                let m = DMatrix::from_fn(f.modes, f.modes, |_, _| 0.0);
                let mut m = m;
                for i in 0..f.modes {
                    for j in 0..f.modes {
                        m[(i, j)] = c.real();
                    }
                }
                if g == 9 {
                    f.mass = m
                } else {
                    f.stiffness = m
                }
            }
            11 => {
                f.lumped = (0..nodes)
                    .map(|_| std::array::from_fn(|_| c.real()))
                    .collect()
            }
            12 => {
                let m = c.real();
                let x = std::array::from_fn(|_| c.real());
                let j = std::array::from_fn(|_| std::array::from_fn(|_| c.real()));
                f.rigid = Some((m, x, j));
            }
            _ => panic!("unexpected group {g}"),
        }
        assert!(
            c.pending.is_empty(),
            "group {g}: trailing tokens {:?}",
            c.pending
        );
    }
    for g in [1, 2, 5, 6, 7, 8, 9, 10] {
        assert!(seen[g], "required group {g} missing");
    }
    f
}

fn krb() -> Params {
    Params {
        length: 8.0,
        rho: 2766.67,
        area: 7.2968e-5,
        iy: 5.1e-9,
        iz: 8.2189e-9,
        e: 6.8952e10,
        g: 2.6e10,
        j: 1.6438e-8,
    }
}

fn setup(
    shape: &str,
    n: usize,
    r: Reference,
    red: Reduction,
) -> (BodySpec, Params, Invariants, ModalBasis) {
    let s = BodySpec::new(Shape::resolve(shape, None).unwrap(), n, r).unwrap();
    let p = krb();
    let full = Invariants::from_exact(&s.exact_invariants().unwrap(), &p).unwrap();
    let b = reduce(&s, &p, &full, &red).unwrap();
    (s, p, full, b)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

#[test]
fn mbdyn_fem_reads_back() {
    let cases = [
        (
            "beam2",
            16,
            Reference::Clamped,
            Reduction::Modal { modes: 6 },
        ),
        (
            "beam3",
            8,
            Reference::Clamped,
            Reduction::Modal { modes: 8 },
        ),
        (
            "beam3",
            6,
            Reference::Free,
            Reduction::CraigBampton {
                boundary_nodes: vec![0, 6],
                modes: 4,
            },
        ),
        (
            "beam2",
            10,
            Reference::Pinned,
            Reduction::Modal { modes: 3 },
        ),
    ];
    for (shape, n, r, red) in cases {
        let (s, p, full, b) = setup(shape, n, r, red);
        let body = ExportBody::new(&s, &p, &full, &b).unwrap();
        let text = mbdyn_fem(&body);
        let f = read_fem(&text);
        let k = b.len();
        let what = format!("{shape} {n} {r}");
        assert_eq!(f.rev, "REV0");
        assert_eq!(f.modes, k, "{what}");
        assert_eq!(f.normal, b.frequencies.len());
        assert_eq!(f.constraint, k - b.frequencies.len());
        assert_eq!(f.labels, (0..=n).map(|j| j.to_string()).collect::<Vec<_>>());
        assert!(f
            .initial
            .iter()
            .all(|v| v.len() == k && v.iter().all(|&x| x == 0.0)));
        for (j, x) in f.xyz.iter().enumerate() {
            let xj = j as f64 / n as f64 * p.length;
            assert!((x[0] - xj).abs() <= 2.0 * f64::EPSILON * xj && x[1] == 0.0 && x[2] == 0.0);
        }
        // Modal mass and stiffness: Φᵀ m_ff Φ, Φᵀ K_ff Φ (full precision, so
        // bit for bit the basis' values).
        assert_eq!(f.mass, b.modal_mass, "{what}");
        assert_eq!(f.stiffness, b.modal_stiffness, "{what}");
        let direct = b.phi.transpose() * &full.m_ff * &b.phi;
        assert!((&f.mass - &direct).norm() <= 1e-14 * direct.norm());
        // Mode shapes = the basis rows of each nodal coordinate.
        let kinds = ["ux", "uy", "uz", "rx", "ry", "rz"];
        let dofs = s.dofs();
        for mode in 0..k {
            for node in 0..=n {
                for (c, kind) in kinds.iter().enumerate() {
                    let expect = dofs
                        .iter()
                        .position(|d| d.node == node && d.kind.to_string() == *kind)
                        .map_or(0.0, |i| b.phi[(i, mode)]);
                    assert_eq!(
                        f.shapes[mode][node][c], expect,
                        "{what} mode {mode} {kind}_{node}"
                    );
                }
            }
        }
        // Record 12 against the body's exact invariants.
        let (m, x, jcm) = f.rigid.unwrap();
        assert_eq!(m, full.mass);
        let c = Vector3::from(x);
        assert!((c * m - full.s_t0).norm() <= 1e-15 * full.s_t0.norm());
        // MBDyn: J(origin) = J(cm) − m c̃ c̃.
        let j_origin = Matrix3::from_fn(|i, j| jcm[i][j]) - c.cross_matrix() * c.cross_matrix() * m;
        let j_exact = Matrix3::identity() * full.theta.trace() - full.theta;
        assert!(
            (j_origin - j_exact).norm() <= 1e-14 * j_exact.norm(),
            "{what}"
        );
        // Record 11: masses sum to the total; MBDyn's own rigid-body inertia
        // from them is the trapezoidal rule of ∫ρA x² dx (O(h²)).
        let sum: f64 = f.lumped.iter().map(|l| l[0]).sum();
        assert!(rel(sum, full.mass) < 1e-14, "{what}");
        assert!(f.lumped.iter().all(|l| l[0] == l[1] && l[1] == l[2]));
        let mut j_lumped = Matrix3::zeros();
        let mut inv3 = DMatrix::<f64>::zeros(3, k);
        let mut gen_mass = DMatrix::<f64>::zeros(k, k);
        for (node, l) in f.lumped.iter().enumerate() {
            let u = Vector3::from(f.xyz[node]);
            let jn = Matrix3::from_diagonal(&Vector3::new(l[3], l[4], l[5]));
            j_lumped += jn - u.cross_matrix() * u.cross_matrix() * l[0];
            for a in 0..k {
                let ta = &f.shapes[a][node];
                for r in 0..3 {
                    inv3[(r, a)] += l[0] * ta[r];
                }
                for bb in 0..k {
                    let tb = &f.shapes[bb][node];
                    gen_mass[(a, bb)] += l[0] * (ta[0] * tb[0] + ta[1] * tb[1] + ta[2] * tb[2])
                        + l[3] * ta[3] * tb[3]
                        + l[4] * ta[4] * tb[4]
                        + l[5] * ta[5] * tb[5];
                }
            }
        }
        let dj = (j_lumped - j_exact).norm() / j_exact.norm();
        let d3 = (&inv3 - &full.s_bar * &b.phi).norm() / (&full.s_bar * &b.phi).norm();
        let dm = (&gen_mass - &f.mass).norm() / f.mass.norm();
        eprintln!(
            "{what}: MBDyn from record 11: rigid J {dj:.2e}, invariant 3 (S̄Φ) {d3:.2e}, generalized mass {dm:.2e} (relative to the consistent values)"
        );
        // Per mode: Σ m_i v_i is the trapezoidal rule of ∫ρA v dx, which for
        // Hermite cubics misses only the end term ρA l²(θ_0 − θ_N)/12 — zero
        // for modes with both end slopes zero, relatively large for high
        // cantilever modes, whose ∫ρA v dx is small.
        let consistent = &full.s_bar * &b.phi;
        let per_mode: Vec<String> = (0..k)
            .map(|a| {
                let e = (inv3.column(a) - consistent.column(a)).norm()
                    / consistent.column(a).norm().max(1e-300);
                format!("{e:.1e}")
            })
            .collect();
        eprintln!("  invariant 3 per mode: {}", per_mode.join(" "));
        let h2 = 1.0 / (n * n) as f64;
        assert!(dj < h2, "{what}: {dj:e}");
        let first = (inv3.column(0) - consistent.column(0)).norm() / consistent.column(0).norm();
        if consistent.column(0).norm() > 1e-12 * consistent.norm() {
            assert!(first < h2, "{what}: {first:e}");
        }
    }
}

#[test]
fn mbdyn_fem_layout() {
    let (s, p, full, b) = setup(
        "beam2",
        2,
        Reference::Clamped,
        Reduction::Modal { modes: 2 },
    );
    let text = mbdyn_fem(&ExportBody::new(&s, &p, &full, &b).unwrap());
    let lines: Vec<&str> = text.lines().collect();
    let at = |h: &str| lines.iter().position(|l| l.starts_with(h)).unwrap();
    // Header: one comment line, then REV NNODES NNORMAL NATTACHED NCONSTRAINT NREJECTED.
    let h = at("** RECORD GROUP 1,");
    assert!(lines[h + 1].starts_with("**"));
    assert_eq!(lines[h + 2], "REV0 3 2 0 0 0");
    assert_eq!(lines[at("** RECORD GROUP 2,") + 1], "0 1 2");
    // 17 significant digits.
    let x = lines[at("** RECORD GROUP 5,") + 2];
    assert_eq!(x, "4.0000000000000000e0");
    let g8 = at("** RECORD GROUP 8,");
    assert!(lines[g8 + 1].starts_with("**    NORMAL MODE SHAPE #  1"));
    assert_eq!(lines[g8 + 2].split_whitespace().count(), 6);
    assert!(lines[g8 + 5].starts_with("**    NORMAL MODE SHAPE #  2"));
    assert_eq!(lines.last(), Some(&"** END OF FILE"));
    // Groups in ascending order, each once.
    let groups: Vec<usize> = lines
        .iter()
        .filter_map(|l| l.strip_prefix("** RECORD GROUP "))
        .map(|r| r.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(groups, (1..=12).collect::<Vec<_>>());
}
