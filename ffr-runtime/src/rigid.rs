//! Rigid bodies: no elastic coordinates.
//!
//! With mass `m`, first moment `S = m c̄` and inertia `J_o` about the frame
//! origin (body axes):
//! `f_r = m ā − S × α + ω × (ω × S)`, `f_θ = S × ā + J_o α + ω × (J_o ω)`.

use crate::body::{
    Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork, Invariants,
    PointShape,
};
use crate::error::{Error, Result};
use crate::rotation::skew;
use nalgebra::{Matrix3, Vector2, Vector3};

/// A rigid body: mass, centre of mass `c̄` and inertia tensor `J_c` about the
/// centre of mass, in body axes. Its invariants are `m`, `S_t0 = m c̄` and
/// `Θ = ∫ρ ū ūᵀ dV = ½ tr(J_o) I − J_o` with `J_o = J_c + m (c̄ᵀc̄ I − c̄ c̄ᵀ)`.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBody {
    mass: f64,
    com: Vector3<f64>,
    inertia: Matrix3<f64>,
    layout: BodyLayout,
}

impl RigidBody {
    /// A planar rigid body (motion in x–y) with mass `mass`, moment of inertia
    /// `j_zz` about its centre of mass, centre of mass at `com` in body axes.
    pub fn planar(mass: f64, j_zz: f64, com: Vector2<f64>) -> Result<Self> {
        // All mass in the x–y plane: J_xx + J_yy = J_zz; split evenly (only
        // J_zz enters planar dynamics).
        Self::make(
            2,
            mass,
            Vector3::new(com.x, com.y, 0.0),
            Matrix3::from_diagonal(&Vector3::new(0.5 * j_zz, 0.5 * j_zz, j_zz)),
        )
    }

    /// A spatial rigid body with inertia tensor `inertia` about its centre of mass `com`.
    pub fn spatial(mass: f64, inertia: Matrix3<f64>, com: Vector3<f64>) -> Result<Self> {
        Self::make(3, mass, com, inertia)
    }

    fn make(dim: usize, mass: f64, com: Vector3<f64>, inertia: Matrix3<f64>) -> Result<Self> {
        if !(mass.is_finite() && mass > 0.0) {
            return Err(Error::InvalidInput(format!(
                "a rigid body's mass must be a finite number > 0, found {mass}"
            )));
        }
        if !com.iter().chain(inertia.iter()).all(|x| x.is_finite()) {
            return Err(Error::InvalidInput(
                "a rigid body's centre of mass and inertia must be finite".into(),
            ));
        }
        let sym = (inertia - inertia.transpose()).norm() <= 1e-12 * inertia.norm();
        let eig = inertia.symmetric_eigenvalues();
        if !sym || eig.iter().any(|&l| l < -1e-12 * inertia.norm()) {
            return Err(Error::InvalidInput(format!(
                "a rigid body's inertia tensor must be symmetric positive semi-definite, found eigenvalues {:?}",
                eig.as_slice()
            )));
        }
        Ok(Self {
            mass,
            com,
            inertia,
            layout: BodyLayout {
                dim,
                scene_dim: dim,
                nf: 0,
                half_bandwidth: 0,
                free_frame: true,
                zero_frame_acceleration: false,
                labels: Vec::new(),
                length: None,
                description: format!("rigid body, m = {mass} kg"),
            },
        })
    }

    /// `J_o`, the inertia tensor about the body-frame origin.
    pub fn inertia_about_origin(&self) -> Matrix3<f64> {
        self.inertia
            + (Matrix3::identity() * self.com.norm_squared() - self.com * self.com.transpose())
                * self.mass
    }

    /// The first moment `S = m c̄`.
    pub fn first_moment(&self) -> Vector3<f64> {
        self.com * self.mass
    }

    fn put(m: &mut [f64], ld: usize, r0: usize, c0: usize, b: &Matrix3<f64>) {
        for i in 0..3 {
            for j in 0..3 {
                m[(r0 + i) * ld + c0 + j] += b[(i, j)];
            }
        }
    }
}

fn v3(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

impl Body for RigidBody {
    fn layout(&self) -> &BodyLayout {
        &self.layout
    }

    fn work(&self) -> BodyWork {
        BodyWork::default()
    }

    fn forces(&self, s: &BodyState, _frame_rows: bool, _w: &mut BodyWork, out: &mut BodyForces) {
        let (a, al, w) = (v3(&s.frame[0..3]), v3(&s.frame[3..6]), v3(&s.frame[6..9]));
        let st = self.first_moment();
        let jo = self.inertia_about_origin();
        let fr = a * self.mass - st.cross(&al) + w.cross(&w.cross(&st));
        let fth = st.cross(&a) + jo * al + w.cross(&(jo * w));
        out.f_r = [fr.x, fr.y, fr.z];
        out.f_th = [fth.x, fth.y, fth.z];
    }

    fn tangent(
        &self,
        s: &BodyState,
        _bp: f64,
        _gp: f64,
        frame_rows: bool,
        w: &mut BodyWork,
        out: &mut BodyForces,
        t: &mut BodyTangent,
    ) {
        self.forces(s, frame_rows, w, out);
        t.clear();
        let om = v3(&s.frame[6..9]);
        let st = self.first_moment();
        let jo = self.inertia_about_origin();
        let d = &mut t.d_ref_frame;
        Self::put(d, 9, 0, 0, &(Matrix3::identity() * self.mass));
        Self::put(d, 9, 0, 3, &(-skew(&st)));
        // ∂(ω × (ω × S))/∂ω = (ω·S) I + ω Sᵀ − 2 S ωᵀ.
        let dw =
            Matrix3::identity() * om.dot(&st) + om * st.transpose() - st * om.transpose() * 2.0;
        Self::put(d, 9, 0, 6, &dw);
        Self::put(d, 9, 3, 0, &skew(&st));
        Self::put(d, 9, 3, 3, &jo);
        // ∂(ω × J ω)/∂ω = ω̃ J − (J ω)~.
        Self::put(d, 9, 3, 6, &(skew(&om) * jo - skew(&(jo * om))));
    }

    fn mass(&self, _q_f: &[f64], _w: &mut BodyWork, out: &mut BodyMass) {
        out.clear();
        let st = self.first_moment();
        out.s_t = [st.x, st.y, st.z];
        let m = &mut out.m_ref_frame;
        Self::put(m, 6, 0, 0, &(Matrix3::identity() * self.mass));
        Self::put(m, 6, 0, 3, &(-skew(&st)));
        Self::put(m, 6, 3, 0, &skew(&st));
        Self::put(m, 6, 3, 3, &self.inertia_about_origin());
    }

    fn elastic_energy(&self, _q_f: &[f64], _w: &mut BodyWork) -> f64 {
        0.0
    }

    fn invariants(&self) -> Invariants {
        let jo = self.inertia_about_origin();
        let mut inv = Invariants::zeros(self.layout.dim, 0);
        inv.mass = self.mass;
        inv.s_t0 = self.first_moment();
        inv.theta = Matrix3::identity() * (0.5 * jo.trace()) - jo;
        inv
    }

    fn point_shape(&self, x: f64) -> Result<PointShape> {
        Err(Error::InvalidInput(format!(
            "a rigid body has no axis to place a point at x = {} on: give the point's body-frame position instead",
            ffr_spec::text::Num(x)
        )))
    }
}
