//! Where the unknowns are: prescribed coordinates, the number of unknowns,
//! the joint a constraint row belongs to, the convergence classes, and the
//! check that a body's elastic coordinates do not repeat a free rigid motion
//! of its frame (used by [`Assembly::new`]).

use super::{Assembly, ClassLink};
use crate::body::{Body, BodyMass};

impl<B: Body> Assembly<'_, B> {
    /// Whether coordinate `c` is prescribed.
    pub fn is_prescribed(&self, c: usize) -> bool {
        self.presc[c].is_some()
    }

    /// Set the prescribed coordinates, their rates and accelerations at `t`.
    /// A driver perturbed by an input (a drive-acceleration input) adds
    /// the input's drive perturbation `δ(t)` ([`Assembly::drive_perturbation`]).
    pub fn apply_prescribed(&self, t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) {
        for (c, d) in &self.sys.prescribed {
            let [f, fd, fdd] = match d.input() {
                None => d.eval(t),
                Some(k) => d.eval_perturbed(t, self.drive_perturbation(k, t)),
            };
            q[*c] = f;
            v[*c] = fd;
            a[*c] = fdd;
        }
    }

    /// Number of unknowns (free coordinates and multipliers).
    pub fn n_unknowns(&self) -> usize {
        self.x_band.len() + self.x_border.len()
    }

    /// The joint (index into
    /// [`System::constraints`](crate::System::constraints)) that constraint
    /// row `k` belongs to, and the row's place in it; `None` for an
    /// Euler-parameter normalization row.
    pub fn row_owner(&self, k: usize) -> Option<(usize, usize)> {
        self.sys
            .constraints
            .iter()
            .zip(&self.cons)
            .enumerate()
            .find(|(_, (c, cw))| (cw.first..cw.first + c.rows.len()).contains(&k))
            .map(|(j, (_, cw))| (j, k - cw.first))
    }

    /// Class of each unknown coordinate and multiplier, and the links
    /// between classes (for convergence).
    pub(crate) fn classes(&self) -> (&[u32], &[u32], &[ClassLink]) {
        (&self.coord_class, &self.mult_class, &self.class_link)
    }
}

/// Whether a body's elastic coordinates can move it rigidly in a direction
/// its frame coordinates also move it (a `free` reference condition): the
/// inertia of that free frame direction (`R_k`, or a rotation) left after
/// the elastic coordinates take theirs, `M_rr − M_rf m_ff⁻¹ M_fr` at
/// `q_f = 0`, is round-off of its own (below `10⁴ ε`; a clamped beam of 256
/// elements keeps about `3·10⁻⁹` of its rotational inertia). The name of the
/// first such direction, or `None` (also when `m_ff` itself is singular: the
/// solver then names the coordinate without inertia).
pub(super) fn rigid_motion_in_elastic<B: Body>(
    b: &crate::system::BodyEntry<B>,
    presc: &[Option<usize>],
) -> Option<&'static str> {
    let lay = b.body.layout();
    let (o, d, nf, hb) = (b.offset, b.d, b.nf, lay.half_bandwidth);
    let mut work = b.body.work();
    let mut mass = BodyMass::zeros(nf, hb);
    b.body.mass(&vec![0.0; nf], &mut work, &mut mass);
    let mut mff = crate::linalg::BandMatrix::new(nf, hb, hb);
    for r in 0..nf {
        for c in r.saturating_sub(hb)..(r + hb + 1).min(nf) {
            mff.set(r, c, mass.m_ff.get(r, c));
        }
    }
    mff.factor().ok()?;
    // Free frame directions among [ā (3), α (3)]: a translation whose
    // coordinate is free, the rotations if any rotational coordinate is.
    let rot_free = (o + d..o + d + b.n_theta).any(|c| presc[c].is_none());
    let dirs: Vec<(usize, &'static str)> = if d == 2 {
        [(0, "R_x"), (1, "R_y"), (5, "θ")]
            .into_iter()
            .filter(|&(k, _)| {
                if k < 3 {
                    presc[o + k].is_none()
                } else {
                    rot_free
                }
            })
            .collect()
    } else {
        [
            (0, "R_x"),
            (1, "R_y"),
            (2, "R_z"),
            (3, "(rotation about the body x axis)"),
            (4, "(rotation about the body y axis)"),
            (5, "(rotation about the body z axis)"),
        ]
        .into_iter()
        .filter(|&(k, _)| {
            if k < 3 {
                presc[o + k].is_none()
            } else {
                rot_free
            }
        })
        .collect()
    };
    let n = dirs.len();
    // S = M_rr − M_rf m_ff⁻¹ M_fr on the free directions.
    let mut x = vec![0.0; nf * n];
    for (j, &(k, _)) in dirs.iter().enumerate() {
        x[j * nf..(j + 1) * nf].copy_from_slice(&mass.m_ref_f[k * nf..(k + 1) * nf]);
    }
    mff.solve_many(&mut x, n);
    let mut s = vec![0.0; n * n];
    for (i, &(ki, _)) in dirs.iter().enumerate() {
        for (j, &(kj, _)) in dirs.iter().enumerate() {
            let coupling: f64 = (0..nf)
                .map(|a| mass.m_ref_f[ki * nf + a] * x[j * nf + a])
                .sum();
            s[i * n + j] = mass.m_ref_frame[ki * 6 + kj] - coupling;
        }
    }
    // Symmetric elimination; a pivot at round-off of the direction's own
    // inertia is a direction the elastic coordinates already describe.
    for k in 0..n {
        let own = mass.m_ref_frame[dirs[k].0 * 7];
        let p = s[k * n + k];
        // `!(p > bound)`, not `p <= bound`: a NaN pivot fails the check too.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(p > 1e4 * f64::EPSILON * own) {
            return Some(dirs[k].1);
        }
        for i in k + 1..n {
            let f = s[i * n + k] / p;
            for j in k..n {
                s[i * n + j] -= f * s[k * n + j];
            }
        }
    }
    None
}
