//! Independent floating-point reference for FFR beam bodies.
//!
//! Hand-coded Euler–Bernoulli shape functions (see `docs/theory.md`) integrated
//! by Gauss–Legendre quadrature in `f64`. Used only to cross-check the exact
//! symbolic generator; it shares no code with it.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix3xX, Vector3};

/// Element type: planar 6-dof `beam2` or spatial 12-dof `beam3`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Beam2,
    Beam3,
}

/// Reference conditions removing rigid-body motion from `q_f`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    Clamped,
    Pinned,
    Free,
}

/// Rectangular section: extents along body y and z. area = wy*wz, iz = ∫y² dA = wz*wy^3/12, iy = ∫z² dA = wy*wz^3/12.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefParams {
    pub length: f64,
    pub rho: f64,
    pub wy: f64,
    pub wz: f64,
    pub e: f64,
    pub g: f64,
    pub j: f64,
}

impl RefParams {
    /// `A = wy·wz`.
    pub fn area(&self) -> f64 {
        self.wy * self.wz
    }
    /// `I_y = ∫z² dA = wy·wz³/12`.
    pub fn iy(&self) -> f64 {
        self.wy * self.wz.powi(3) / 12.0
    }
    /// `I_z = ∫y² dA = wz·wy³/12`.
    pub fn iz(&self) -> f64 {
        self.wz * self.wy.powi(3) / 12.0
    }
}

/// A body of `elements` equal beam elements along body x from 0 to `length`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefBody {
    pub shape: Shape,
    pub elements: usize,
    pub reference: Reference,
    pub params: RefParams,
}

/// Inertia shape integrals and stiffness of a body (theory sheet names).
#[derive(Clone, Debug, PartialEq)]
pub struct RefInvariants {
    /// `m = ∫ρ dV`.
    pub mass: f64,
    /// `S_t0 = ∫ρ ū₀ dV`.
    pub s_t0: Vector3<f64>,
    /// `S̄ = ∫ρ S dV` (3 × n_f).
    pub s_bar: Matrix3xX<f64>,
    /// `S̄_kl = ∫ρ S_kᵀ S_l dV` (n_f × n_f).
    pub s_kl: [[DMatrix<f64>; 3]; 3],
    /// `Ī_kl = ∫ρ ū₀_k S_l dV` as a column (n_f).
    pub i_kl: [[DVector<f64>; 3]; 3],
    /// `Θ_kl = ∫ρ ū₀_k ū₀_l dV`.
    pub theta: Matrix3<f64>,
    /// `m_ff = S̄_xx + S̄_yy + S̄_zz`.
    pub m_ff: DMatrix<f64>,
    /// `K_ff = ∫E ε_xx² dV + ∫GJ φ'² dx`.
    pub k_ff: DMatrix<f64>,
}

impl RefInvariants {
    /// All zero, for `n` coordinates.
    pub fn zeros(n: usize) -> Self {
        RefInvariants {
            mass: 0.0,
            s_t0: Vector3::zeros(),
            s_bar: Matrix3xX::zeros(n),
            s_kl: std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(n, n))),
            i_kl: std::array::from_fn(|_| std::array::from_fn(|_| DVector::zeros(n))),
            theta: Matrix3::zeros(),
            m_ff: DMatrix::zeros(n, n),
            k_ff: DMatrix::zeros(n, n),
        }
    }
}

/// Gauss–Legendre points `(x_i, w_i)` on `[a, b]`: `∫f ≈ Σ w_i f(x_i)`, exact to degree `2n−1`.
pub fn gauss_legendre(n: usize, a: f64, b: f64) -> Vec<(f64, f64)> {
    assert!(n >= 1, "gauss_legendre needs at least one point");
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    (0..n)
        .map(|i| {
            // Newton on P_n from the Chebyshev-like initial guess.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            if d != 0.0 {
                dp = d;
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (mid + half * x, half * w)
        })
        .collect()
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

/// Hermite functions `[N1, N2, N3, N4](ξ)`.
fn hermite(xi: f64) -> [f64; 4] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    [
        1.0 - 3.0 * x2 + 2.0 * x3,
        xi - 2.0 * x2 + x3,
        3.0 * x2 - 2.0 * x3,
        -x2 + x3,
    ]
}

/// Hermite derivatives `d[N1, N2, N3, N4]/dξ`.
fn hermite_d(xi: f64) -> [f64; 4] {
    let x2 = xi * xi;
    [
        -6.0 * xi + 6.0 * x2,
        1.0 - 4.0 * xi + 3.0 * x2,
        6.0 * xi - 6.0 * x2,
        -2.0 * xi + 3.0 * x2,
    ]
}

/// Hermite second derivatives `d²[N1, N2, N3, N4]/dξ²`.
fn hermite_dd(xi: f64) -> [f64; 4] {
    [
        -6.0 + 12.0 * xi,
        -4.0 + 6.0 * xi,
        6.0 - 12.0 * xi,
        -2.0 + 6.0 * xi,
    ]
}

/// Quadrature orders: ξ (degree ≤ 8 after squaring cubics) and section (degree ≤ 2).
const NXI: usize = 6;
const NSEC: usize = 4;

impl Shape {
    /// Coordinates per node: 3 (beam2) or 6 (beam3).
    pub fn node_dofs(self) -> usize {
        match self {
            Shape::Beam2 => 3,
            Shape::Beam3 => 6,
        }
    }

    /// Coordinates per element: `2 · node_dofs`.
    pub fn elem_dofs(self) -> usize {
        2 * self.node_dofs()
    }

    /// Label kinds of one node's coordinates, in element order.
    pub fn kinds(self) -> &'static [&'static str] {
        match self {
            Shape::Beam2 => &["ux", "uy", "rz"],
            Shape::Beam3 => &["ux", "uy", "uz", "rx", "ry", "rz"],
        }
    }

    /// Element shape matrix `S(ξ, η, ζ)` (3 × n_e) exactly as in the theory sheet; beam2 has `S_z = 0`.
    pub fn elem_s(self, l: f64, xi: f64, eta: f64, zeta: f64) -> Matrix3xX<f64> {
        let [n1, n2, n3, n4] = hermite(xi);
        let x2 = xi * xi;
        let mut s = Matrix3xX::zeros(self.elem_dofs());
        match self {
            Shape::Beam2 => {
                let rx = [
                    1.0 - xi,
                    6.0 * (xi - x2) * eta,
                    (-1.0 + 4.0 * xi - 3.0 * x2) * l * eta,
                    xi,
                    6.0 * (x2 - xi) * eta,
                    (2.0 * xi - 3.0 * x2) * l * eta,
                ];
                let ry = [0.0, n1, l * n2, 0.0, n3, l * n4];
                for i in 0..6 {
                    s[(0, i)] = rx[i];
                    s[(1, i)] = ry[i];
                }
            }
            Shape::Beam3 => {
                let rx = [
                    1.0 - xi,
                    6.0 * (xi - x2) * eta,
                    6.0 * (xi - x2) * zeta,
                    0.0,
                    (1.0 - 4.0 * xi + 3.0 * x2) * l * zeta,
                    (-1.0 + 4.0 * xi - 3.0 * x2) * l * eta,
                    xi,
                    6.0 * (x2 - xi) * eta,
                    6.0 * (x2 - xi) * zeta,
                    0.0,
                    (-2.0 * xi + 3.0 * x2) * l * zeta,
                    (2.0 * xi - 3.0 * x2) * l * eta,
                ];
                let ry = [
                    0.0,
                    n1,
                    0.0,
                    -(1.0 - xi) * l * zeta,
                    0.0,
                    l * n2,
                    0.0,
                    n3,
                    0.0,
                    -l * xi * zeta,
                    0.0,
                    l * n4,
                ];
                let rz = [
                    0.0,
                    0.0,
                    n1,
                    (1.0 - xi) * l * eta,
                    -l * n2,
                    0.0,
                    0.0,
                    0.0,
                    n3,
                    l * xi * eta,
                    -l * n4,
                    0.0,
                ];
                for i in 0..12 {
                    s[(0, i)] = rx[i];
                    s[(1, i)] = ry[i];
                    s[(2, i)] = rz[i];
                }
            }
        }
        s
    }

    /// Strain row `∂S_x/∂x = (1/l) ∂S_x/∂ξ` at `(ξ, η, ζ)` (n_e), so `ε_xx = (∂S_x/∂x) q_e`.
    pub fn elem_dsx_dx(self, l: f64, xi: f64, eta: f64, zeta: f64) -> DVector<f64> {
        let v: Vec<f64> = match self {
            Shape::Beam2 => vec![
                -1.0,
                6.0 * (1.0 - 2.0 * xi) * eta,
                (4.0 - 6.0 * xi) * l * eta,
                1.0,
                6.0 * (2.0 * xi - 1.0) * eta,
                (2.0 - 6.0 * xi) * l * eta,
            ],
            Shape::Beam3 => vec![
                -1.0,
                6.0 * (1.0 - 2.0 * xi) * eta,
                6.0 * (1.0 - 2.0 * xi) * zeta,
                0.0,
                (-4.0 + 6.0 * xi) * l * zeta,
                (4.0 - 6.0 * xi) * l * eta,
                1.0,
                6.0 * (2.0 * xi - 1.0) * eta,
                6.0 * (2.0 * xi - 1.0) * zeta,
                0.0,
                (-2.0 + 6.0 * xi) * l * zeta,
                (2.0 - 6.0 * xi) * l * eta,
            ],
        };
        DVector::from_vec(v) / l
    }

    /// Centerline gradient rows `(a, b, c)` with `u' = a·q_e`, `v' = b·q_e`, `w' = c·q_e`;
    /// `u = (1−ξ)u1 + ξu2`, `v = N1 v1 + lN2 θz1 + N3 v2 + lN4 θz2`, `w = N1 w1 − lN2 θy1 + N3 w2 − lN4 θy2`.
    pub fn centerline_grad(self, l: f64, xi: f64) -> (DVector<f64>, DVector<f64>, DVector<f64>) {
        let [d1, d2, d3, d4] = hermite_d(xi);
        let n = self.elem_dofs();
        let (mut a, mut b, mut c) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
        match self {
            Shape::Beam2 => {
                a[0] = -1.0 / l;
                a[3] = 1.0 / l;
                b[1] = d1 / l;
                b[2] = d2;
                b[4] = d3 / l;
                b[5] = d4;
            }
            Shape::Beam3 => {
                a[0] = -1.0 / l;
                a[6] = 1.0 / l;
                b[1] = d1 / l;
                b[5] = d2;
                b[7] = d3 / l;
                b[11] = d4;
                c[2] = d1 / l;
                c[4] = -d2;
                c[8] = d3 / l;
                c[10] = -d4;
            }
        }
        (a, b, c)
    }

    /// Centerline second-derivative rows `(b2, c2)` with `v'' = b2·q_e`, `w'' = c2·q_e`
    /// (`d²/dx² = (1/l²) d²/dξ²` of the same interpolation as [`Shape::centerline_grad`]);
    /// `c2 = 0` for beam2.
    pub fn centerline_curv(self, l: f64, xi: f64) -> (DVector<f64>, DVector<f64>) {
        let [d1, d2, d3, d4] = hermite_dd(xi);
        let n = self.elem_dofs();
        let (mut b, mut c) = (DVector::zeros(n), DVector::zeros(n));
        let l2 = l * l;
        match self {
            Shape::Beam2 => {
                b[1] = d1 / l2;
                b[2] = d2 / l;
                b[4] = d3 / l2;
                b[5] = d4 / l;
            }
            Shape::Beam3 => {
                b[1] = d1 / l2;
                b[5] = d2 / l;
                b[7] = d3 / l2;
                b[11] = d4 / l;
                c[2] = d1 / l2;
                c[4] = -d2 / l;
                c[8] = d3 / l2;
                c[10] = -d4 / l;
            }
        }
        (b, c)
    }
}

/// Per-element quadrature results before assembly.
struct ElemInv {
    mass: f64,
    s_t0: Vector3<f64>,
    s_bar: Matrix3xX<f64>,
    s_kl: [[DMatrix<f64>; 3]; 3],
    i_kl: [[DVector<f64>; 3]; 3],
    theta: Matrix3<f64>,
}

impl RefBody {
    /// Element length `l = L / N`.
    fn l(&self) -> f64 {
        assert!(self.elements >= 1, "a body needs at least one element");
        self.params.length / self.elements as f64
    }

    /// Whether coordinate `k` (element order) of body node `node` is removed by the reference conditions.
    fn removed(&self, node: usize, k: usize) -> bool {
        let last = self.elements;
        match (self.reference, self.shape) {
            (Reference::Free, _) => false,
            (Reference::Clamped, _) => node == 0,
            // beam2: ux, uy at node 0; uy at node N.
            (Reference::Pinned, Shape::Beam2) => (node == 0 && k <= 1) || (node == last && k == 1),
            // beam3: ux, uy, uz, rx at node 0; uy, uz at node N.
            (Reference::Pinned, Shape::Beam3) => {
                (node == 0 && k <= 3) || (node == last && (k == 1 || k == 2))
            }
        }
    }

    /// Body coordinate index (node-major) → position in `q_f`, or `None` if removed.
    fn dof_map(&self) -> Vec<Option<usize>> {
        let nn = self.shape.node_dofs();
        let mut next = 0;
        let mut map = Vec::with_capacity((self.elements + 1) * nn);
        for node in 0..=self.elements {
            for k in 0..nn {
                if self.removed(node, k) {
                    map.push(None);
                } else {
                    map.push(Some(next));
                    next += 1;
                }
            }
        }
        map
    }

    /// Element `e` local coordinate → position in `q_f` (element node 0 = body node e).
    fn elem_map(&self, full: &[Option<usize>], e: usize) -> Vec<Option<usize>> {
        let nn = self.shape.node_dofs();
        full[e * nn..(e + 2) * nn].to_vec()
    }

    /// Local element coordinates `q_e` gathered from `q_f` (removed ones are 0).
    fn gather(map: &[Option<usize>], q_f: &[f64]) -> DVector<f64> {
        DVector::from_iterator(map.len(), map.iter().map(|m| m.map_or(0.0, |i| q_f[i])))
    }

    fn check_q(&self, q_f: &[f64]) {
        assert_eq!(q_f.len(), self.nf(), "q_f has the wrong length");
    }

    /// Number of elastic coordinates `n_f` after the reference conditions.
    pub fn nf(&self) -> usize {
        self.dof_map().iter().filter(|m| m.is_some()).count()
    }

    /// Labels `kind_node` of the `q_f` entries, e.g. `"ux_1"`, `"rz_1"`.
    pub fn dof_labels(&self) -> Vec<String> {
        let kinds = self.shape.kinds();
        let mut out = Vec::new();
        for node in 0..=self.elements {
            for (k, kind) in kinds.iter().enumerate() {
                if !self.removed(node, k) {
                    out.push(format!("{kind}_{node}"));
                }
            }
        }
        out
    }

    /// Volume quadrature of element `e`: calls `f(ū₀, S_e, ρ dV)` at each Gauss point of the prism.
    fn for_each_point(&self, e: usize, mut f: impl FnMut(Vector3<f64>, &Matrix3xX<f64>, f64)) {
        let l = self.l();
        let p = &self.params;
        let x0 = e as f64 * l;
        let gx = gauss_legendre(NXI, 0.0, 1.0);
        let gy = gauss_legendre(NSEC, -0.5 * p.wy, 0.5 * p.wy);
        let gz = gauss_legendre(NSEC, -0.5 * p.wz, 0.5 * p.wz);
        for &(xi, wx) in &gx {
            for &(y, wy) in &gy {
                for &(z, wz) in &gz {
                    let s = self.shape.elem_s(l, xi, y / l, z / l);
                    let u0 = match self.shape {
                        Shape::Beam2 => Vector3::new(x0 + xi * l, y, 0.0),
                        Shape::Beam3 => Vector3::new(x0 + xi * l, y, z),
                    };
                    f(u0, &s, p.rho * l * wx * wy * wz);
                }
            }
        }
    }

    /// Element invariants by volume quadrature: `∫ρ dV`, `∫ρū₀`, `∫ρS`, `∫ρS_kᵀS_l`, `∫ρū₀_k S_l`, `∫ρū₀ū₀ᵀ`.
    fn elem_invariants(&self, e: usize) -> ElemInv {
        let ne = self.shape.elem_dofs();
        let mut r = ElemInv {
            mass: 0.0,
            s_t0: Vector3::zeros(),
            s_bar: Matrix3xX::zeros(ne),
            s_kl: std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(ne, ne))),
            i_kl: std::array::from_fn(|_| std::array::from_fn(|_| DVector::zeros(ne))),
            theta: Matrix3::zeros(),
        };
        self.for_each_point(e, |u0, s, w| {
            r.mass += w;
            r.s_t0 += w * u0;
            r.s_bar += w * s;
            r.theta += w * u0 * u0.transpose();
            for k in 0..3 {
                let sk = s.row(k).transpose();
                for l in 0..3 {
                    let sl = s.row(l);
                    r.s_kl[k][l] += w * &sk * sl;
                    r.i_kl[k][l] += (w * u0[k]) * sl.transpose();
                }
            }
        });
        r
    }

    /// Element `K_e = ∫E (∂S_x/∂x)ᵀ(∂S_x/∂x) dV + ∫GJ tᵀt dx`, `t = (e_θx2 − e_θx1)/l` (beam3); equal for all elements.
    fn elem_stiffness(&self) -> DMatrix<f64> {
        let l = self.l();
        let p = &self.params;
        let ne = self.shape.elem_dofs();
        let mut k = DMatrix::zeros(ne, ne);
        let gx = gauss_legendre(NXI, 0.0, 1.0);
        let gy = gauss_legendre(NSEC, -0.5 * p.wy, 0.5 * p.wy);
        let gz = gauss_legendre(NSEC, -0.5 * p.wz, 0.5 * p.wz);
        for &(xi, wx) in &gx {
            for &(y, wy) in &gy {
                for &(z, wz) in &gz {
                    let g = self.shape.elem_dsx_dx(l, xi, y / l, z / l);
                    k += (p.e * l * wx * wy * wz) * &g * g.transpose();
                }
            }
            if self.shape == Shape::Beam3 {
                let mut t = DVector::zeros(ne);
                t[3] = -1.0 / l;
                t[9] = 1.0 / l;
                k += (p.g * p.j * l * wx) * &t * t.transpose();
            }
        }
        k
    }

    /// Adds local `v` (n_e) into global `out` (n_f) through `map`.
    fn scatter_vec(map: &[Option<usize>], v: &DVector<f64>, out: &mut DVector<f64>) {
        for (i, mi) in map.iter().enumerate() {
            if let Some(gi) = mi {
                out[*gi] += v[i];
            }
        }
    }

    /// Adds local `m` (n_e × n_e) into global `out` (n_f × n_f) through `map`.
    fn scatter_mat(map: &[Option<usize>], m: &DMatrix<f64>, out: &mut DMatrix<f64>) {
        for (i, mi) in map.iter().enumerate() {
            let Some(gi) = mi else { continue };
            for (j, mj) in map.iter().enumerate() {
                if let Some(gj) = mj {
                    out[(*gi, *gj)] += m[(i, j)];
                }
            }
        }
    }

    /// Adds local columns of `m` (3 × n_e) into `out` (3 × n_f) through `map`.
    fn scatter_cols(map: &[Option<usize>], m: &Matrix3xX<f64>, out: &mut Matrix3xX<f64>) {
        for (i, mi) in map.iter().enumerate() {
            if let Some(gi) = mi {
                let c = m.column(i).into_owned();
                let mut col = out.column_mut(*gi);
                col += c;
            }
        }
    }

    /// Assembled `K_ff = Σ_e K_e` (n_f × n_f).
    fn k_ff(&self) -> DMatrix<f64> {
        let full = self.dof_map();
        let nf = self.nf();
        let mut k = DMatrix::zeros(nf, nf);
        let ke = self.elem_stiffness();
        for e in 0..self.elements {
            let map = self.elem_map(&full, e);
            Self::scatter_mat(&map, &ke, &mut k);
        }
        k
    }

    fn empty_invariants(&self) -> RefInvariants {
        RefInvariants::zeros(self.nf())
    }

    /// Consistent invariants by volume quadrature; `m_ff = S̄_xx + S̄_yy + S̄_zz`.
    pub fn invariants(&self) -> RefInvariants {
        let full = self.dof_map();
        let mut r = self.empty_invariants();
        for e in 0..self.elements {
            let map = self.elem_map(&full, e);
            let ei = self.elem_invariants(e);
            r.mass += ei.mass;
            r.s_t0 += ei.s_t0;
            r.theta += ei.theta;
            Self::scatter_cols(&map, &ei.s_bar, &mut r.s_bar);
            for k in 0..3 {
                for l in 0..3 {
                    Self::scatter_mat(&map, &ei.s_kl[k][l], &mut r.s_kl[k][l]);
                    Self::scatter_vec(&map, &ei.i_kl[k][l], &mut r.i_kl[k][l]);
                }
            }
        }
        r.m_ff = &r.s_kl[0][0] + &r.s_kl[1][1] + &r.s_kl[2][2];
        r.k_ff = self.k_ff();
        r
    }

    /// Lumped invariants: node `j` is a rigid body on the axis
    /// ([`rigid_body`]) of mass `m_j` (half of `ρAl` per adjacent element)
    /// with second moments `D_j = diag(m_j l²/39, ρ I_z s_j, ρ I_y s_j)`
    /// (`s_j`: half a length per adjacent element; `l²/39`: the HRZ lumping
    /// of the bending rotational inertia, `ρAl³/78` per element end), moving
    /// with the section there; `K_ff` as consistent.
    pub fn lumped_invariants(&self) -> RefInvariants {
        let l = self.l();
        let full = self.dof_map();
        let p = self.params;
        let planar = self.shape == Shape::Beam2;
        let mut r = self.empty_invariants();
        for j in 0..=self.elements {
            let s = if j == 0 || j == self.elements {
                0.5 * l
            } else {
                l
            };
            let m = p.rho * p.area() * s;
            let d = Matrix3::from_diagonal(&Vector3::new(
                m * l * l / 39.0,
                p.rho * p.iz() * s,
                if planar { 0.0 } else { p.rho * p.iy() * s },
            ));
            let (e, xi) = if j < self.elements {
                (j, 0.0)
            } else {
                (j - 1, 1.0)
            };
            let ei = rigid_body(self.shape, e as f64 * l, l, xi, m, d);
            let map = self.elem_map(&full, e);
            r.mass += ei.mass;
            r.s_t0 += ei.s_t0;
            r.theta += ei.theta;
            Self::scatter_cols(&map, &ei.s_bar, &mut r.s_bar);
            for k in 0..3 {
                for ll in 0..3 {
                    Self::scatter_mat(&map, &ei.s_kl[k][ll], &mut r.s_kl[k][ll]);
                    Self::scatter_vec(&map, &ei.i_kl[k][ll], &mut r.i_kl[k][ll]);
                }
            }
        }
        r.m_ff = &r.s_kl[0][0] + &r.s_kl[1][1] + &r.s_kl[2][2];
        r.k_ff = self.k_ff();
        r
    }

    /// Volume quadrature over the body of `f(u, S_e, map, ρ dV)` with `u = ū₀ + S_e q_e`.
    fn for_each_deformed(
        &self,
        q_f: &[f64],
        mut f: impl FnMut(Vector3<f64>, &Matrix3xX<f64>, &[Option<usize>], f64),
    ) {
        self.check_q(q_f);
        let full = self.dof_map();
        for e in 0..self.elements {
            let map = self.elem_map(&full, e);
            let qe = Self::gather(&map, q_f);
            self.for_each_point(e, |u0, s, w| f(u0 + s * &qe, s, &map, w));
        }
    }

    /// `S_t = ∫ρ u dV`, `u = ū₀ + S q_f`.
    pub fn s_t(&self, q_f: &[f64]) -> Vector3<f64> {
        let mut r = Vector3::zeros();
        self.for_each_deformed(q_f, |u, _, _, w| r += w * u);
        r
    }

    /// `Ī_θθ = ∫ρ ũᵀũ dV = ∫ρ (|u|² I − u uᵀ) dV`.
    pub fn i_theta_theta(&self, q_f: &[f64]) -> Matrix3<f64> {
        let mut r = Matrix3::zeros();
        self.for_each_deformed(q_f, |u, _, _, w| {
            r += w * (u.norm_squared() * Matrix3::identity() - u * u.transpose());
        });
        r
    }

    /// `Ī_θf = ∫ρ ũ S dV` (3 × n_f).
    pub fn i_theta_f(&self, q_f: &[f64]) -> Matrix3xX<f64> {
        let mut r = Matrix3xX::zeros(self.nf());
        self.for_each_deformed(q_f, |u, s, map, w| {
            let local = w * u.cross_matrix() * s;
            Self::scatter_cols(map, &local, &mut r);
        });
        r
    }
}

mod attached;
mod stiffening;
pub use attached::{attached_mass, rigid_body};
pub mod varying;
pub use stiffening::{StiffeningEnergy, StiffeningModel, N_BEND, N_MEAN};

#[cfg(test)]
mod tests;
