//! Simeon's own rod discretization (two sine modes, a quadratic axial
//! ansatz, no rotary inertia) as a hand-written runtime [`Body`]: the
//! verification rod of the slider-crank benchmark, not generated code.

use super::{DENSITY, ROD_HEIGHT, ROD_LENGTH, ROD_WIDTH, YOUNG};
use ffr::runtime::nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use ffr::runtime::rotation::skew;
use ffr::runtime::{
    Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork, Error as RtError,
    Invariants, PointShape,
};
use std::f64::consts::PI;

/// Simeon's own rod discretization as a runtime body: the FFR equations of
/// a body with constant invariants (linear elasticity, no stiffening) in
/// body-frame form (theory: `docs/theory.md`, section 5), with their exact
/// derivatives for the analytic Newton matrix, evaluated densely (4
/// coordinates).
///
/// Invariants: consistent FFR inertia of the shape functions of the
/// benchmark, no section terms in `S`, `J₂ = m (l²/3 + h²/12)` as in the
/// benchmark data. The axial block of `S̄_xx` (and so of `m_ff`) is multiplied
/// by `axial_mass_factor`: the benchmark's code (`crank.f`) uses
/// `ρbhl·[8 1; 1 2]` where the quadratic ansatz gives `ρbhl/15·[8 1; 1 2]` —
/// pass 15 to reproduce it, 1 for the ansatz's own mass. Elastic coordinates
/// `(q₁, q₂, q₃, q₄)` carry the labels `uy_1, mode2, ux_1, ux_2` (node 1 the
/// midpoint, node 2 the slider pin), so the scene finds the midpoint. With
/// `rotary_inertia` the section's rotary inertia (the `−y v'` axial
/// displacement of the beam shapes), which the benchmark neglects, is added.
#[derive(Clone, Debug)]
pub struct SimeonRod {
    inv: Invariants,
    layout: BodyLayout,
    /// `D_r = S̄_ab − S̄_ba`, `(r, a, b)` cyclic.
    d: [DMatrix<f64>; 3],
    /// `c_r = Ī_ab − Ī_ba`, `(r, a, b)` cyclic.
    c: [DVector<f64>; 3],
}

const CYCLIC: [(usize, usize); 3] = [(1, 2), (2, 0), (0, 1)];

fn v3(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

impl SimeonRod {
    /// The rod (see the type's docs).
    pub fn new(axial_mass_factor: f64, rotary_inertia: bool) -> Self {
        let (l, h, a) = (ROD_LENGTH, ROD_HEIGHT, ROD_WIDTH * ROD_HEIGHT);
        let m = DENSITY * a * l;
        let ei = YOUNG * ROD_WIDTH * h * h * h / 12.0;
        let ea = YOUNG * a;
        let mut inv = Invariants::zeros(2, 4);
        inv.mass = m;
        inv.s_t0 = Vector3::new(m * l / 2.0, 0.0, 0.0);
        // ∫ S_x dξ = (0, 0, 2/3, 1/6), ∫ S_y dξ = (2/π, 0, 0, 0).
        inv.s_bar[(0, 2)] = m * 2.0 / 3.0;
        inv.s_bar[(0, 3)] = m / 6.0;
        inv.s_bar[(1, 0)] = m * 2.0 / PI;
        let (x, y) = (0, 1);
        let f = axial_mass_factor;
        for (i, j, v) in [(2, 2, 8.0), (2, 3, 1.0), (3, 2, 1.0), (3, 3, 2.0)] {
            inv.s_kl[x][x][(i, j)] = f * m * v / 15.0;
        }
        inv.s_kl[y][y][(0, 0)] = m / 2.0;
        inv.s_kl[y][y][(1, 1)] = m / 2.0;
        if rotary_inertia {
            // S_x gains −y v'(x): ∫ρ S_xᵀ S_x gains ρ I_z ∫ v'_k² dx = m h²/12 (kπ/l)²/2
            // (all other invariants unchanged: ∫y dA = 0, v_k(0) = v_k(l) = 0).
            for k in 0..2 {
                let kp = (k + 1) as f64 * PI / l;
                inv.s_kl[x][x][(k, k)] = m * h * h / 12.0 * kp * kp / 2.0;
            }
        }
        // S̄_xy(a, b) = ∫ρ S_x,a S_y,b: ∫N₃ sin πξ = 16/π³, ∫N₄ sin πξ = 1/π − 8/π³,
        // ∫N₄ sin 2πξ = −1/(2π), ∫N₃ sin 2πξ = 0.
        let p3 = PI * PI * PI;
        for (i, j, v) in [
            (2, 0, 16.0 / p3),
            (3, 0, 1.0 / PI - 8.0 / p3),
            (3, 1, -0.5 / PI),
        ] {
            inv.s_kl[x][y][(i, j)] = m * v;
            inv.s_kl[y][x][(j, i)] = m * v;
        }
        // Ī_xx = ∫ρ x S_x = m l (0, 0, 1/3, 1/6), Ī_xy = ∫ρ x S_y = m l (1/π, −1/(2π), 0, 0).
        inv.i_kl[x][x][2] = m * l / 3.0;
        inv.i_kl[x][x][3] = m * l / 6.0;
        inv.i_kl[x][y][0] = m * l / PI;
        inv.i_kl[x][y][1] = -m * l / (2.0 * PI);
        inv.theta = Matrix3::from_diagonal(&Vector3::new(m * l * l / 3.0, m * h * h / 12.0, 0.0));
        inv.m_ff = &inv.s_kl[x][x] + &inv.s_kl[y][y];
        // K: EI π⁴/(2 l³) (1, 16) laterally, EA/l [16/3 −8/3; −8/3 7/3] axially.
        let kb = ei * PI.powi(4) / (2.0 * l * l * l);
        inv.k_ff[(0, 0)] = kb;
        inv.k_ff[(1, 1)] = 16.0 * kb;
        for (i, j, v) in [
            (2, 2, 16.0 / 3.0),
            (2, 3, -8.0 / 3.0),
            (3, 2, -8.0 / 3.0),
            (3, 3, 7.0 / 3.0),
        ] {
            inv.k_ff[(i, j)] = ea / l * v;
        }
        let d = CYCLIC.map(|(a, b)| &inv.s_kl[a][b] - &inv.s_kl[b][a]);
        let c = CYCLIC.map(|(a, b)| &inv.i_kl[a][b] - &inv.i_kl[b][a]);
        let layout = BodyLayout {
            dim: 2,
            scene_dim: 2,
            nf: 4,
            half_bandwidth: 3,
            free_frame: true,
            zero_frame_acceleration: false,
            labels: ["uy_1", "mode2", "ux_1", "ux_2"].map(String::from).to_vec(),
            length: Some(l),
            description: format!(
                "Simeon's rod (2 sine modes, quadratic axial; axial mass ×{axial_mass_factor}, rotary inertia {})",
                if rotary_inertia { "on" } else { "off" }
            ),
        };
        Self { inv, layout, d, c }
    }

    /// The invariants it was built from.
    pub fn invariant_data(&self) -> &Invariants {
        &self.inv
    }

    /// `S_t`, `Ī_θθ`, `Ī_θf` (3 × n) at `q`.
    fn moments(&self, q: &DVector<f64>) -> (Vector3<f64>, Matrix3<f64>, DMatrix<f64>) {
        let inv = &self.inv;
        let s_t = inv.s_t0 + &inv.s_bar * q;
        let u = Matrix3::from_fn(|k, l| {
            inv.theta[(k, l)]
                + (&inv.i_kl[k][l] + &inv.i_kl[l][k]).dot(q)
                + q.dot(&(&inv.s_kl[k][l] * q))
        });
        let i_tt = Matrix3::identity() * u.trace() - u;
        let mut i_tf = DMatrix::zeros(3, 4);
        for r in 0..3 {
            let row = &self.c[r] + self.d[r].transpose() * q;
            i_tf.set_row(r, &row.transpose());
        }
        (s_t, i_tt, i_tf)
    }

    /// `P` with `P_kl = Ī_kl · q̇ + qᵀ S̄_kl q̇`.
    fn velocity_moments(&self, q: &DVector<f64>, qd: &DVector<f64>) -> Matrix3<f64> {
        let inv = &self.inv;
        Matrix3::from_fn(|k, l| inv.i_kl[k][l].dot(qd) + q.dot(&(&inv.s_kl[k][l] * qd)))
    }

    /// `f_r`, `f_θ`, `f_f` (theory, section 5).
    fn eval(&self, s: &BodyState, out: &mut BodyForces) {
        let inv = &self.inv;
        let q = DVector::from_column_slice(s.q_f);
        let qd = DVector::from_column_slice(s.qd_f);
        let qdd = DVector::from_column_slice(s.qdd_f);
        let (a, al, w) = (v3(&s.frame[0..3]), v3(&s.frame[3..6]), v3(&s.frame[6..9]));
        let (s_t, i_tt, i_tf) = self.moments(&q);
        let p = self.velocity_moments(&q, &qd);
        let sq = &inv.s_bar * &qd;
        let fr = a * inv.mass - s_t.cross(&al)
            + &inv.s_bar * &qdd
            + w.cross(&w.cross(&s_t))
            + w.cross(&sq) * 2.0;
        let fth = s_t.cross(&a)
            + i_tt * al
            + &i_tf * &qdd
            + w.cross(&(i_tt * w))
            + (w * p.trace() - p.transpose() * w) * 2.0;
        let om = skew(&w);
        let ww = om * om;
        let mut ff =
            inv.s_bar.transpose() * a + i_tf.transpose() * al + &inv.m_ff * &qdd + &inv.k_ff * &q;
        for k in 0..3 {
            for l in 0..3 {
                if ww[(k, l)] != 0.0 {
                    ff += (&inv.i_kl[l][k] + &inv.s_kl[k][l] * &q) * ww[(k, l)];
                }
                if om[(k, l)] != 0.0 {
                    ff += &inv.s_kl[k][l] * &qd * (2.0 * om[(k, l)]);
                }
            }
        }
        out.f_r = [fr.x, fr.y, fr.z];
        out.f_th = [fth.x, fth.y, fth.z];
        out.f_f.copy_from_slice(ff.as_slice());
    }
}

impl Body for SimeonRod {
    fn layout(&self) -> &BodyLayout {
        &self.layout
    }

    fn work(&self) -> BodyWork {
        BodyWork::default()
    }

    fn forces(&self, s: &BodyState, _frame_rows: bool, _w: &mut BodyWork, out: &mut BodyForces) {
        self.eval(s, out);
    }

    fn tangent(
        &self,
        s: &BodyState,
        bp: f64,
        gp: f64,
        _frame_rows: bool,
        _w: &mut BodyWork,
        out: &mut BodyForces,
        t: &mut BodyTangent,
    ) {
        self.eval(s, out);
        t.clear();
        let inv = &self.inv;
        let nf = 4;
        let q = DVector::from_column_slice(s.q_f);
        let qd = DVector::from_column_slice(s.qd_f);
        let qdd = DVector::from_column_slice(s.qdd_f);
        let (a, al, w) = (v3(&s.frame[0..3]), v3(&s.frame[3..6]), v3(&s.frame[6..9]));
        let (s_t, i_tt, i_tf) = self.moments(&q);
        let p = self.velocity_moments(&q, &qd);
        let om = skew(&w);
        let ww = om * om;
        let e = [0, 1, 2].map(|j| skew(&Vector3::ith(j, 1.0)));

        // k_ff = β' m_ff + γ' 2 Σ Ω_kl S̄_kl + Σ_r α_r D_rᵀ + Σ W_kl S̄_kl + K.
        let mut kff = &inv.m_ff * bp + &inv.k_ff;
        for r in 0..3 {
            kff += self.d[r].transpose() * al[r];
        }
        for k in 0..3 {
            for l in 0..3 {
                kff += &inv.s_kl[k][l] * (ww[(k, l)] + 2.0 * gp * om[(k, l)]);
            }
        }
        for i in 0..nf {
            for j in 0..nf {
                t.k_ff.add(i, j, kff[(i, j)]);
            }
        }

        // ∂f_f/∂[ā, α, ω] (n × 9).
        for i in 0..nf {
            for j in 0..3 {
                t.d_f_frame[i * 9 + j] = inv.s_bar[(j, i)];
                t.d_f_frame[i * 9 + 3 + j] = i_tf[(j, i)];
            }
        }
        for (j, ej) in e.iter().enumerate() {
            let dww = ej * om + om * ej;
            let mut col = DVector::zeros(nf);
            for k in 0..3 {
                for l in 0..3 {
                    if dww[(k, l)] != 0.0 {
                        col += (&inv.i_kl[l][k] + &inv.s_kl[k][l] * &q) * dww[(k, l)];
                    }
                    if ej[(k, l)] != 0.0 {
                        col += &inv.s_kl[k][l] * &qd * (2.0 * ej[(k, l)]);
                    }
                }
            }
            for i in 0..nf {
                t.d_f_frame[i * 9 + 6 + j] = col[i];
            }
        }

        // β' ∂/∂q̈ + γ' ∂/∂q̇ + ∂/∂q of [f_r; f_θ] (6 × n).
        let kr = &inv.s_bar * bp + (om * 2.0 * gp + skew(&al) + ww) * &inv.s_bar;
        let mut kth = &i_tf * bp - skew(&a) * &inv.s_bar;
        // g_kl = Ī_kl + S̄_klᵀ q = ∂P_kl/∂q̇; S̄_kl q̇ = ∂P_kl/∂q.
        for r in 0..3 {
            let mut gv = DVector::zeros(nf);
            let mut pv = DVector::zeros(nf);
            for k in 0..3 {
                let g_kk = &inv.i_kl[k][k] + inv.s_kl[k][k].transpose() * &q;
                let g_kr = &inv.i_kl[k][r] + inv.s_kl[k][r].transpose() * &q;
                gv += g_kk * w[r] - g_kr * w[k];
                pv += &inv.s_kl[k][k] * &qd * w[r] - &inv.s_kl[k][r] * &qd * w[k];
            }
            let dq = &self.d[r] * &qdd;
            for b in 0..nf {
                kth[(r, b)] += 2.0 * gp * gv[b] + 2.0 * pv[b] + dq[b];
            }
        }
        for b in 0..nf {
            let du = Matrix3::from_fn(|k, l| {
                inv.i_kl[k][l][b]
                    + inv.i_kl[l][k][b]
                    + ((&inv.s_kl[k][l] + inv.s_kl[k][l].transpose()) * &q)[b]
            });
            let di = Matrix3::identity() * du.trace() - du;
            let col = di * al + w.cross(&(di * w));
            for r in 0..3 {
                kth[(r, b)] += col[r];
            }
        }
        for b in 0..nf {
            for r in 0..3 {
                t.k_ref_f[r * nf + b] = kr[(r, b)];
                t.k_ref_f[(3 + r) * nf + b] = kth[(r, b)];
            }
        }

        // ∂[f_r; f_θ]/∂[ā, α, ω] (6 × 9).
        let sq = &inv.s_bar * &qd;
        let blocks = [
            [
                Matrix3::identity() * inv.mass,
                -skew(&s_t),
                Matrix3::identity() * w.dot(&s_t) + w * s_t.transpose()
                    - s_t * w.transpose() * 2.0
                    - skew(&sq) * 2.0,
            ],
            [
                skew(&s_t),
                i_tt,
                om * i_tt - skew(&(i_tt * w))
                    + (Matrix3::identity() * p.trace() - p.transpose()) * 2.0,
            ],
        ];
        for (bi, row) in blocks.iter().enumerate() {
            for (bj, m) in row.iter().enumerate() {
                for i in 0..3 {
                    for j in 0..3 {
                        t.d_ref_frame[(3 * bi + i) * 9 + 3 * bj + j] = m[(i, j)];
                    }
                }
            }
        }
    }

    fn mass(&self, q_f: &[f64], _w: &mut BodyWork, out: &mut BodyMass) {
        out.clear();
        let inv = &self.inv;
        let nf = 4;
        let q = DVector::from_column_slice(q_f);
        let (s_t, i_tt, i_tf) = self.moments(&q);
        out.s_t = [s_t.x, s_t.y, s_t.z];
        for i in 0..nf {
            for j in 0..nf {
                out.m_ff.add(i, j, inv.m_ff[(i, j)]);
            }
            for k in 0..3 {
                out.m_f_frame[i * 6 + k] = inv.s_bar[(k, i)];
                out.m_f_frame[i * 6 + 3 + k] = i_tf[(k, i)];
                out.m_ref_f[k * nf + i] = inv.s_bar[(k, i)];
                out.m_ref_f[(3 + k) * nf + i] = i_tf[(k, i)];
            }
        }
        let blocks = [
            [Matrix3::identity() * inv.mass, -skew(&s_t)],
            [skew(&s_t), i_tt],
        ];
        for (bi, row) in blocks.iter().enumerate() {
            for (bj, m) in row.iter().enumerate() {
                for i in 0..3 {
                    for j in 0..3 {
                        out.m_ref_frame[(3 * bi + i) * 6 + 3 * bj + j] = m[(i, j)];
                    }
                }
            }
        }
    }

    fn elastic_energy(&self, q_f: &[f64], _w: &mut BodyWork) -> f64 {
        let q = DVector::from_column_slice(q_f);
        0.5 * q.dot(&(&self.inv.k_ff * &q))
    }

    fn invariants(&self) -> Invariants {
        self.inv.clone()
    }

    /// Centreline point at `x`: `u = S_x q`, `v = S_y q` and the section
    /// rotation `ψ_z = v'(x)`.
    fn point_shape(&self, x: f64) -> ffr::runtime::Result<PointShape> {
        let l = ROD_LENGTH;
        if !(x.is_finite() && (-1e-12 * l..=l * (1.0 + 1e-12)).contains(&x)) {
            return Err(RtError::InvalidInput(format!(
                "x = {x} is not on the rod's axis: it runs from x = 0 to x = {l} m"
            )));
        }
        let xi = (x / l).clamp(0.0, 1.0);
        // sin kπξ, exactly 0 at both ends.
        let sin = |k: f64| {
            if xi == 0.0 || xi == 1.0 {
                0.0
            } else {
                (k * PI * xi).sin()
            }
        };
        let cos = |k: f64| (k * PI * xi).cos();
        let cols: [([f64; 3], [f64; 3]); 4] = [
            ([0.0, sin(1.0), 0.0], [0.0, 0.0, PI / l * cos(1.0)]),
            ([0.0, sin(2.0), 0.0], [0.0, 0.0, 2.0 * PI / l * cos(2.0)]),
            ([4.0 * xi * (1.0 - xi), 0.0, 0.0], [0.0; 3]),
            ([xi * (2.0 * xi - 1.0), 0.0, 0.0], [0.0; 3]),
        ];
        Ok(PointShape {
            u0: [xi * l, 0.0, 0.0],
            entries: cols
                .into_iter()
                .enumerate()
                .filter(|(_, (s, p))| s.iter().chain(p).any(|v| *v != 0.0))
                .map(|(j, (s, p))| (j, s, p))
                .collect(),
        })
    }
}

/// [`SimeonRod::new`], boxed for the scene.
pub fn simeon_rod(axial_mass_factor: f64, rotary_inertia: bool) -> Box<dyn Body> {
    Box::new(SimeonRod::new(axial_mass_factor, rotary_inertia))
}
