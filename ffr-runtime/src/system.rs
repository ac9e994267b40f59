//! A multibody system: bodies, constraints, force elements, gravity; the
//! assembled equations `M(q) q̈ + Φ_qᵀ λ = Q(q, q̇, t)`, `Φ(q, t) = 0`.

use crate::body::FlexBody;
use crate::driver::Driver;
use crate::error::{Error, Result};
use crate::force::ForceElement;
use crate::joint::Constraint;
use crate::marker::{BodyId, Marker, MarkerState};
use crate::model::{BodyModel, Rayleigh};
use crate::rotation::euler_parameters;
use nalgebra::{DMatrix, DVector, Matrix3xX, UnitQuaternion, Vector3};
use std::sync::Arc;

/// Initial pose of a body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pose {
    /// Planar: origin `(x, y)` and angle about z.
    Planar {
        /// Origin x.
        x: f64,
        /// Origin y.
        y: f64,
        /// Angle (rad).
        angle: f64,
    },
    /// Spatial: origin and orientation.
    Spatial {
        /// Origin `R`.
        position: Vector3<f64>,
        /// Orientation `A`.
        orientation: UnitQuaternion<f64>,
    },
}

impl Pose {
    /// Planar pose.
    pub fn planar(x: f64, y: f64, angle: f64) -> Self {
        Pose::Planar { x, y, angle }
    }
    /// Spatial pose.
    pub fn spatial(position: Vector3<f64>, orientation: UnitQuaternion<f64>) -> Self {
        Pose::Spatial {
            position,
            orientation,
        }
    }
    /// The identity pose of a scene of dimension `d`.
    pub fn identity(d: usize) -> Self {
        if d == 2 {
            Self::planar(0.0, 0.0, 0.0)
        } else {
            Self::spatial(Vector3::zeros(), UnitQuaternion::identity())
        }
    }
}

/// Energy of a configuration (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// `½ q̇ᵀ M q̇`.
    pub kinetic: f64,
    /// `½ q_fᵀ K_ff q_f + U_nl`.
    pub elastic: f64,
    /// `−g · (m R + A S_t)` summed over bodies.
    pub gravity: f64,
    /// `½ k (l − l₀)²` summed over springs.
    pub springs: f64,
}

impl Energy {
    /// Total mechanical energy.
    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic + self.gravity + self.springs
    }
}

/// Constraint equations and their derivatives at one configuration.
#[derive(Clone, Debug)]
pub struct ConstraintEval {
    /// `Φ(q, t)`.
    pub phi: DVector<f64>,
    /// `Φ_q` (m × n).
    pub jac: DMatrix<f64>,
    /// `Φ_t`.
    pub phi_t: DVector<f64>,
}

/// The state of a system.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time.
    pub t: f64,
    /// Generalized coordinates.
    pub q: DVector<f64>,
    /// Generalized velocities.
    pub v: DVector<f64>,
    /// Accelerations `q̈`.
    pub a: DVector<f64>,
    /// Lagrange multipliers (physical, one per constraint equation incl. normalizations).
    pub lambda: DVector<f64>,
}

/// A multibody system under construction or ready to simulate.
pub struct System {
    dim: usize,
    bodies: Vec<BodyModel>,
    offsets: Vec<usize>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    constraints: Vec<Constraint>,
    forces: Vec<ForceElement>,
    gravity: Vector3<f64>,
}

impl System {
    /// An empty planar scene (body coordinates `[R_x, R_y, θ, q_f]`).
    pub fn planar() -> Self {
        Self::with_dim(2)
    }
    /// An empty spatial scene (body coordinates `[R (3), e (4), q_f]`).
    pub fn spatial() -> Self {
        Self::with_dim(3)
    }
    fn with_dim(dim: usize) -> Self {
        Self {
            dim,
            bodies: Vec::new(),
            offsets: Vec::new(),
            q0: Vec::new(),
            v0: Vec::new(),
            constraints: Vec::new(),
            forces: Vec::new(),
            gravity: Vector3::zeros(),
        }
    }

    /// Scene dimension (2 or 3).
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// Number of generalized coordinates.
    pub fn n_coords(&self) -> usize {
        self.q0.len()
    }
    /// Number of bodies.
    pub fn n_bodies(&self) -> usize {
        self.bodies.len()
    }
    /// Number of scalar constraint equations (joints and Euler-parameter normalizations).
    pub fn n_constraints(&self) -> usize {
        self.n_normalizations()
            + self
                .constraints
                .iter()
                .map(|c| c.len(self.dim))
                .sum::<usize>()
    }
    fn n_normalizations(&self) -> usize {
        if self.dim == 3 {
            self.bodies.len()
        } else {
            0
        }
    }

    /// Add a body at `pose`, at rest and undeformed. The body's stiffening is
    /// on if it has any ([`BodyModel::stiffening`]).
    pub fn add_body(&mut self, body: Box<dyn FlexBody>, pose: Pose) -> Result<BodyId> {
        let id = self.bodies.len();
        let model = BodyModel::new(body, self.dim, id)?;
        let off = self.q0.len();
        let mut q = vec![0.0; model.n_coords()];
        match (pose, self.dim) {
            (Pose::Planar { x, y, angle }, 2) => q[..3].copy_from_slice(&[x, y, angle]),
            (
                Pose::Spatial {
                    position,
                    orientation,
                },
                3,
            ) => {
                q[..3].copy_from_slice(position.as_slice());
                q[3..7].copy_from_slice(euler_parameters(&orientation).as_slice());
            }
            _ => {
                return Err(Error::InvalidInput(format!(
                    "pose {pose:?} does not match a {}-D scene",
                    self.dim
                )))
            }
        }
        if !q.iter().all(|x| x.is_finite()) {
            return Err(Error::InvalidInput(format!("pose {pose:?} is not finite")));
        }
        self.q0.extend_from_slice(&q);
        self.v0.extend(std::iter::repeat(0.0).take(q.len()));
        self.offsets.push(off);
        self.bodies.push(model);
        Ok(BodyId(id))
    }

    fn check_body(&self, id: BodyId) -> Result<()> {
        if id.0 < self.bodies.len() {
            Ok(())
        } else {
            Err(Error::InvalidInput(format!("no body {}", id.0)))
        }
    }

    /// The body model (for settings: stiffening, damping).
    pub fn body(&self, id: BodyId) -> &BodyModel {
        &self.bodies[id.0]
    }
    /// Mutable body model.
    pub fn body_mut(&mut self, id: BodyId) -> &mut BodyModel {
        &mut self.bodies[id.0]
    }
    /// Offset of the body's coordinates in `q`.
    pub fn offset(&self, id: BodyId) -> usize {
        self.offsets[id.0]
    }
    /// The body's coordinates within a system vector.
    pub fn body_slice<'a>(&self, id: BodyId, q: &'a DVector<f64>) -> &'a [f64] {
        let o = self.offsets[id.0];
        &q.as_slice()[o..o + self.bodies[id.0].n_coords()]
    }
    /// Turn the body's geometric stiffening on or off (on requires the body to have it).
    pub fn set_stiffening(&mut self, id: BodyId, on: bool) -> Result<()> {
        self.check_body(id)?;
        if on && !self.bodies[id.0].body().has_stiffening() {
            return Err(Error::InvalidInput(format!(
                "body {} has no geometric stiffening",
                id.0
            )));
        }
        self.bodies[id.0].stiffening = on;
        Ok(())
    }
    /// Rayleigh damping `α M_ff + β K_ff` on the body's elastic coordinates.
    pub fn set_damping(&mut self, id: BodyId, damping: Rayleigh) -> Result<()> {
        self.check_body(id)?;
        if !(damping.alpha.is_finite()
            && damping.beta.is_finite()
            && damping.alpha >= 0.0
            && damping.beta >= 0.0)
        {
            return Err(Error::InvalidInput(format!(
                "Rayleigh coefficients {damping:?} must be finite and ≥ 0"
            )));
        }
        self.bodies[id.0].damping = Some(damping);
        Ok(())
    }
    /// Initial velocity of the body frame: origin velocity `v` and angular
    /// velocity `omega` (global axes; only `omega.z` in the plane).
    pub fn set_velocity(&mut self, id: BodyId, v: Vector3<f64>, omega: Vector3<f64>) -> Result<()> {
        self.check_body(id)?;
        let (o, m) = (self.offsets[id.0], &self.bodies[id.0]);
        let d = self.dim;
        self.v0[o..o + d].copy_from_slice(&v.as_slice()[..d]);
        if d == 2 {
            self.v0[o + 2] = omega.z;
        } else {
            // θ̇ = ½ Ḡᵀ ω̄, ω̄ = Aᵀ ω (Ḡ Ḡᵀ = 4 I, Ḡ θ = 0).
            let fr = m.frame(&self.q0[o..o + m.n_coords()]);
            let ed = fr.g.transpose() * (fr.a.transpose() * omega) * 0.5;
            self.v0[o + 3..o + 7].copy_from_slice(ed.as_slice());
        }
        Ok(())
    }
    /// Initial elastic coordinates and velocities.
    pub fn set_elastic(&mut self, id: BodyId, q_f: &[f64], qd_f: &[f64]) -> Result<()> {
        self.check_body(id)?;
        let m = &self.bodies[id.0];
        let (o, nf) = (self.offsets[id.0] + m.f_offset(), m.nf());
        if q_f.len() != nf || qd_f.len() != nf {
            return Err(Error::InvalidInput(format!(
                "body {} has {nf} elastic coordinates",
                id.0
            )));
        }
        if !q_f.iter().chain(qd_f).all(|x| x.is_finite()) {
            return Err(Error::InvalidInput(
                "non-finite elastic initial conditions".into(),
            ));
        }
        self.q0[o..o + nf].copy_from_slice(q_f);
        self.v0[o..o + nf].copy_from_slice(qd_f);
        Ok(())
    }
    /// Gravity (global; z ignored in the plane).
    pub fn set_gravity(&mut self, g: Vector3<f64>) {
        self.gravity = if self.dim == 2 {
            Vector3::new(g.x, g.y, 0.0)
        } else {
            g
        };
    }
    /// Gravity vector.
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }
    /// Initial coordinates and velocities as set (before any projection).
    pub fn initial_coords(&self) -> (DVector<f64>, DVector<f64>) {
        (
            DVector::from_column_slice(&self.q0),
            DVector::from_column_slice(&self.v0),
        )
    }

    fn check_marker(&self, m: &Marker) -> Result<()> {
        let Some(b) = m.body else { return Ok(()) };
        self.check_body(b)?;
        let nf = self.bodies[b.0].nf();
        for s in [&m.shape, &m.rotation_shape].into_iter().flatten() {
            if s.ncols() != nf {
                return Err(Error::InvalidInput(format!(
                    "marker shape has {} columns, body {} has n_f = {nf}",
                    s.ncols(),
                    b.0
                )));
            }
        }
        if !m.u0.iter().chain(m.axes.iter()).all(|x| x.is_finite()) {
            return Err(Error::InvalidInput("non-finite marker".into()));
        }
        Ok(())
    }

    /// Add a raw constraint.
    pub fn add_constraint(&mut self, c: Constraint) -> Result<()> {
        match &c {
            Constraint::Coordinate { body, index, .. } => {
                self.check_body(*body)?;
                if *index >= self.bodies[body.0].n_coords() {
                    return Err(Error::InvalidInput(format!(
                        "body {} has no coordinate {index}",
                        body.0
                    )));
                }
            }
            Constraint::Coincident { a, b } | Constraint::Angle { a, b, .. } => {
                self.check_marker(a)?;
                self.check_marker(b)?;
            }
            Constraint::Perpendicular {
                a,
                axis_a,
                b,
                axis_b,
            } => {
                self.check_marker(a)?;
                self.check_marker(b)?;
                if *axis_a > 2 || *axis_b > 2 {
                    return Err(Error::InvalidInput("axis index must be 0, 1 or 2".into()));
                }
            }
        }
        if c.bodies().is_empty() {
            return Err(Error::InvalidInput(
                "a constraint between two ground markers".into(),
            ));
        }
        self.constraints.push(c);
        Ok(())
    }

    /// Fix a body to the ground in its initial pose (planar: `R` and `θ`; spatial: `R`, `e1..e3`).
    pub fn ground(&mut self, body: BodyId) -> Result<()> {
        self.check_body(body)?;
        let o = self.offsets[body.0];
        let idx: &[usize] = if self.dim == 2 {
            &[0, 1, 2]
        } else {
            &[0, 1, 2, 4, 5, 6]
        };
        for &i in idx {
            let c = self.q0[o + i];
            self.add_constraint(Constraint::Coordinate {
                body,
                index: i,
                driver: Driver::constant(c),
            })?;
        }
        Ok(())
    }
    /// Prescribe body coordinate `index` (local) as `f(t)`.
    pub fn prescribe_coordinate(
        &mut self,
        body: BodyId,
        index: usize,
        driver: Driver,
    ) -> Result<()> {
        self.add_constraint(Constraint::Coordinate {
            body,
            index,
            driver,
        })
    }
    /// Fixed joint: `a` and `b` coincide with aligned axes (planar: point + angle;
    /// spatial: point + `x_a·y_b = y_a·z_b = z_a·x_b = 0`).
    pub fn fixed(&mut self, a: Marker, b: Marker) -> Result<()> {
        self.add_constraint(Constraint::Coincident {
            a: a.clone(),
            b: b.clone(),
        })?;
        if self.dim == 2 {
            self.add_constraint(Constraint::Angle {
                a,
                b,
                driver: Driver::constant(0.0),
            })
        } else {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                self.add_constraint(Constraint::Perpendicular {
                    a: a.clone(),
                    axis_a: i,
                    b: b.clone(),
                    axis_b: j,
                })?;
            }
            Ok(())
        }
    }
    /// Revolute joint about the markers' z axes (planar: coincident points;
    /// spatial: coincident points and `z_a·x_b = z_a·y_b = 0`).
    pub fn revolute(&mut self, a: Marker, b: Marker) -> Result<()> {
        self.add_constraint(Constraint::Coincident {
            a: a.clone(),
            b: b.clone(),
        })?;
        if self.dim == 3 {
            for j in [0, 1] {
                self.add_constraint(Constraint::Perpendicular {
                    a: a.clone(),
                    axis_a: 2,
                    b: b.clone(),
                    axis_b: j,
                })?;
            }
        }
        Ok(())
    }
    /// Spherical joint (spatial only): coincident points.
    pub fn spherical(&mut self, a: Marker, b: Marker) -> Result<()> {
        if self.dim != 3 {
            return Err(Error::InvalidInput(
                "a spherical joint needs a spatial scene".into(),
            ));
        }
        self.add_constraint(Constraint::Coincident { a, b })
    }
    /// Driving constraint: `b` turned by `f(t)` about the z axis of `a`
    /// (combine with a revolute joint).
    pub fn prescribe_rotation(&mut self, a: Marker, b: Marker, driver: Driver) -> Result<()> {
        self.add_constraint(Constraint::Angle { a, b, driver })
    }
    /// Add a force element.
    pub fn add_force(&mut self, f: ForceElement) -> Result<()> {
        match &f {
            ForceElement::Point { marker, .. } => self.check_marker(marker)?,
            ForceElement::SpringDamper {
                a,
                b,
                stiffness,
                damping,
                rest_length,
            } => {
                self.check_marker(a)?;
                self.check_marker(b)?;
                if ![stiffness, damping, rest_length]
                    .iter()
                    .all(|x| x.is_finite())
                {
                    return Err(Error::InvalidInput("non-finite spring-damper data".into()));
                }
            }
        }
        self.forces.push(f);
        Ok(())
    }
    /// A global force `F(t)` at a marker.
    pub fn add_point_force(
        &mut self,
        marker: Marker,
        force: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static,
    ) -> Result<()> {
        self.add_force(ForceElement::Point {
            marker,
            force: Arc::new(force),
        })
    }
    /// A spring–damper between two markers.
    pub fn add_spring_damper(
        &mut self,
        a: Marker,
        b: Marker,
        stiffness: f64,
        damping: f64,
        rest_length: f64,
    ) -> Result<()> {
        self.add_force(ForceElement::SpringDamper {
            a,
            b,
            stiffness,
            damping,
            rest_length,
        })
    }
    /// A marker at beam node `node` (undeformed position `u0`) of `body`, from its `dof_labels()`.
    pub fn node_marker(&self, body: BodyId, node: usize, u0: Vector3<f64>) -> Marker {
        Marker::node(body, u0, &self.bodies[body.0].body().dof_labels(), node)
    }

    // ---------------------------------------------------------------- assembly

    pub(crate) fn offsets_of(&self, i: usize) -> usize {
        self.offsets[i]
    }
    pub(crate) fn has_elements(&self) -> bool {
        !self.forces.is_empty()
    }

    fn marker_state(&self, m: &Marker, q: &DVector<f64>) -> MarkerState {
        match m.body {
            Some(b) => m.state(Some(&self.bodies[b.0]), self.body_slice(b, q)),
            None => m.state(None, &[]),
        }
    }

    /// Global position of a marker.
    pub fn marker_position(&self, m: &Marker, q: &DVector<f64>) -> Vector3<f64> {
        self.marker_state(m, q).pos
    }

    /// Add `J_local` (rows × n_b) into `out` at the body's columns.
    fn scatter_row(
        &self,
        out: &mut DMatrix<f64>,
        row: usize,
        body: Option<BodyId>,
        vals: impl Iterator<Item = f64>,
    ) {
        if let Some(b) = body {
            let o = self.offsets[b.0];
            for (j, v) in vals.enumerate() {
                out[(row, o + j)] += v;
            }
        }
    }

    /// `M(q)`, block diagonal over bodies.
    pub fn mass_matrix(&self, q: &DVector<f64>) -> DMatrix<f64> {
        let n = self.n_coords();
        let mut m = DMatrix::zeros(n, n);
        for (i, b) in self.bodies.iter().enumerate() {
            let o = self.offsets[i];
            let nb = b.n_coords();
            m.view_mut((o, o), (nb, nb))
                .copy_from(&b.mass_matrix(&q.as_slice()[o..o + nb]));
        }
        m
    }

    /// The body's own terms: `M_b q̈_b − Q_v − Q_applied` (no interactions).
    pub(crate) fn body_residual(&self, i: usize, q: &[f64], v: &[f64], a: &[f64]) -> DVector<f64> {
        let b = &self.bodies[i];
        b.mass_matrix(q) * DVector::from_column_slice(a)
            - b.quadratic_velocity(q, v)
            - b.applied_forces(q, v, &self.gravity)
    }

    /// Generalized forces of the force elements.
    pub fn element_forces(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(self.n_coords());
        let d = self.dim;
        let mut add = |m: &Marker, st: &MarkerState, f: &Vector3<f64>| {
            if let Some(b) = m.body {
                let o = self.offsets[b.0];
                let mut f3 = *f;
                if d == 2 {
                    f3.z = 0.0;
                }
                let qb = st.pos_jac.transpose() * f3;
                let mut seg = out.rows_mut(o, qb.len());
                seg += qb;
            }
        };
        for fe in &self.forces {
            match fe {
                ForceElement::Point { marker, force } => {
                    let st = self.marker_state(marker, q);
                    add(marker, &st, &force(t));
                }
                ForceElement::SpringDamper {
                    a,
                    b,
                    stiffness,
                    damping,
                    rest_length,
                } => {
                    let (sa, sb) = (self.marker_state(a, q), self.marker_state(b, q));
                    let dvec = sb.pos - sa.pos;
                    let l = dvec.norm();
                    if l <= f64::EPSILON * (1.0 + rest_length.abs()) {
                        continue; // direction undefined; a coincident spring carries no force along a line
                    }
                    let e = dvec / l;
                    let vel = |m: &Marker, s: &MarkerState| match m.body {
                        Some(bb) => &s.pos_jac * DVector::from_column_slice(self.body_slice(bb, v)),
                        None => Vector3::zeros(),
                    };
                    let ld = e.dot(&(vel(b, &sb) - vel(a, &sa)));
                    let f = stiffness * (l - rest_length) + damping * ld;
                    add(a, &sa, &(e * f));
                    add(b, &sb, &(-e * f));
                }
            }
        }
        out
    }

    /// All generalized forces `Q(q, q̇, t) = Q_v + Q_applied + Q_elements`.
    pub fn forces(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
        let mut out = self.element_forces(t, q, v);
        for (i, b) in self.bodies.iter().enumerate() {
            let o = self.offsets[i];
            let nb = b.n_coords();
            let (qb, vb) = (&q.as_slice()[o..o + nb], &v.as_slice()[o..o + nb]);
            let mut seg = out.rows_mut(o, nb);
            seg += b.quadratic_velocity(qb, vb) + b.applied_forces(qb, vb, &self.gravity);
        }
        out
    }

    /// `Φ`, `Φ_q`, `Φ_t` at `(q, t)`. Rows: Euler-parameter normalizations
    /// `½(eᵀe − 1)` of spatial bodies first, then the constraints in order.
    pub fn constraints(&self, t: f64, q: &DVector<f64>) -> ConstraintEval {
        let (m, n, d) = (self.n_constraints(), self.n_coords(), self.dim);
        let mut phi = DVector::zeros(m);
        let mut jac = DMatrix::zeros(m, n);
        let mut phi_t = DVector::zeros(m);
        let mut row = 0;
        if d == 3 {
            for o in &self.offsets {
                let e = q.rows(o + 3, 4);
                phi[row] = 0.5 * (e.norm_squared() - 1.0);
                for k in 0..4 {
                    jac[(row, o + 3 + k)] = e[k];
                }
                row += 1;
            }
        }
        for c in &self.constraints {
            match c {
                Constraint::Coordinate {
                    body,
                    index,
                    driver,
                } => {
                    let [f, fd, _] = driver.eval(t);
                    let j = self.offsets[body.0] + index;
                    phi[row] = q[j] - f;
                    jac[(row, j)] = 1.0;
                    phi_t[row] = -fd;
                    row += 1;
                }
                Constraint::Coincident { a, b } => {
                    let (sa, sb) = (self.marker_state(a, q), self.marker_state(b, q));
                    for k in 0..d {
                        phi[row] = sb.pos[k] - sa.pos[k];
                        self.scatter_row(&mut jac, row, b.body, sb.pos_jac.row(k).iter().copied());
                        self.scatter_row(
                            &mut jac,
                            row,
                            a.body,
                            sa.pos_jac.row(k).iter().map(|x| -x),
                        );
                        row += 1;
                    }
                }
                Constraint::Perpendicular {
                    a,
                    axis_a,
                    b,
                    axis_b,
                } => {
                    let (sa, sb) = (self.marker_state(a, q), self.marker_state(b, q));
                    let (va, vb) = (sa.axes[*axis_a], sb.axes[*axis_b]);
                    phi[row] = va.dot(&vb);
                    self.scatter_row(
                        &mut jac,
                        row,
                        a.body,
                        (vb.transpose() * &sa.axes_jac[*axis_a]).iter().copied(),
                    );
                    self.scatter_row(
                        &mut jac,
                        row,
                        b.body,
                        (va.transpose() * &sb.axes_jac[*axis_b]).iter().copied(),
                    );
                    row += 1;
                }
                Constraint::Angle { a, b, driver } => {
                    let (sa, sb) = (self.marker_state(a, q), self.marker_state(b, q));
                    let [f, fd, _] = driver.eval(t);
                    let (s, c) = f.sin_cos();
                    let (xa, ya, xb) = (sa.axes[0], sa.axes[1], sb.axes[0]);
                    // Φ = (x_b·y_a) c − (x_b·x_a) s
                    phi[row] = xb.dot(&ya) * c - xb.dot(&xa) * s;
                    phi_t[row] = -(xb.dot(&ya) * s + xb.dot(&xa) * c) * fd;
                    let gb = ya * c - xa * s;
                    self.scatter_row(
                        &mut jac,
                        row,
                        b.body,
                        (gb.transpose() * &sb.axes_jac[0]).iter().copied(),
                    );
                    let ja: Matrix3xX<f64> = &sa.axes_jac[1] * c - &sa.axes_jac[0] * s;
                    self.scatter_row(&mut jac, row, a.body, (xb.transpose() * ja).iter().copied());
                    row += 1;
                }
            }
        }
        debug_assert_eq!(row, m);
        ConstraintEval { phi, jac, phi_t }
    }

    /// `Φ̈ = Φ_q q̈ − γ`: returns `γ = −(d/dt)(Φ_q q̇ + Φ_t)|_{q̈=0}` by a central
    /// difference along `(q̇, 1)` (step `ε = 1e-6 / max(1, ‖q̇‖∞)`), except
    /// for the Euler-parameter normalizations, whose `γ = −ėᵀė` is exact.
    ///
    /// The difference carries a round-off error of about `ε_mach ‖q‖ ‖q̇‖ / ε`
    /// (≈ 1e-10 relative); on the normalizations that error would drive a
    /// Baumgarte-stabilized `eᵀe − 1` to ~1e-13 and with it `A(e)`, the
    /// momenta and the energy of every spatial body.
    pub fn gamma(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
        let eps = 1e-6 / v.amax().max(1.0);
        let psi = |s: f64| {
            let qs = q + v * s;
            let c = self.constraints(t + s, &qs);
            c.jac * v + c.phi_t
        };
        let mut g = -(psi(eps) - psi(-eps)) / (2.0 * eps);
        if self.dim == 3 {
            // Rows of `½(eᵀe − 1)`, in body order (see `constraints`).
            for (row, o) in self.offsets.iter().enumerate() {
                g[row] = -v.rows(o + 3, 4).norm_squared();
            }
        }
        g
    }

    /// `(‖Φ‖∞, ‖Φ_q q̇ + Φ_t‖∞)`: position and velocity constraint violation.
    pub fn constraint_violation(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> (f64, f64) {
        let c = self.constraints(t, q);
        let vel = &c.jac * v + &c.phi_t;
        (c.phi.amax(), vel.amax())
    }

    /// Energies at `(q, q̇)`.
    pub fn energy(&self, q: &DVector<f64>, v: &DVector<f64>) -> Energy {
        let mut e = Energy::default();
        for (i, b) in self.bodies.iter().enumerate() {
            let o = self.offsets[i];
            let nb = b.n_coords();
            let (qb, vb) = (&q.as_slice()[o..o + nb], &v.as_slice()[o..o + nb]);
            e.kinetic += b.kinetic_energy(qb, vb);
            e.elastic += b.elastic_energy(qb);
            e.gravity += b.gravity_energy(qb, &self.gravity);
        }
        for f in &self.forces {
            if let ForceElement::SpringDamper {
                a,
                b,
                stiffness,
                rest_length,
                ..
            } = f
            {
                let l = (self.marker_position(b, q) - self.marker_position(a, q)).norm();
                e.springs += 0.5 * stiffness * (l - rest_length).powi(2);
            }
        }
        e
    }

    /// Total linear momentum and angular momentum about the global origin.
    pub fn momentum(&self, q: &DVector<f64>, v: &DVector<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let mut p = Vector3::zeros();
        let mut h = Vector3::zeros();
        for (i, b) in self.bodies.iter().enumerate() {
            let o = self.offsets[i];
            let nb = b.n_coords();
            let (pb, hb) = b.momentum(&q.as_slice()[o..o + nb], &v.as_slice()[o..o + nb]);
            p += pb;
            h += hb;
        }
        (p, h)
    }

    /// Solve `[M Φ_qᵀ; Φ_q 0] [q̈; λ] = [Q; γ_s]` with
    /// `γ_s = γ − 2α(Φ_q q̇ + Φ_t) − β² Φ` (Baumgarte; α = β = 0 for the plain index-1 form).
    pub fn accelerations(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        baumgarte: (f64, f64),
    ) -> Result<(DVector<f64>, DVector<f64>)> {
        let (n, m) = (self.n_coords(), self.n_constraints());
        let c = self.constraints(t, q);
        let mut k = DMatrix::zeros(n + m, n + m);
        k.view_mut((0, 0), (n, n)).copy_from(&self.mass_matrix(q));
        k.view_mut((0, n), (n, m)).copy_from(&c.jac.transpose());
        k.view_mut((n, 0), (m, n)).copy_from(&c.jac);
        let mut rhs = DVector::zeros(n + m);
        rhs.rows_mut(0, n).copy_from(&self.forces(t, q, v));
        if m > 0 {
            let (al, be) = baumgarte;
            let g = self.gamma(t, q, v) - (&c.jac * v + &c.phi_t) * (2.0 * al) - &c.phi * (be * be);
            rhs.rows_mut(n, m).copy_from(&g);
        }
        if !k.iter().chain(rhs.iter()).all(|x| x.is_finite()) {
            return Err(Error::Unstable {
                what: "mass matrix, forces or constraint terms",
                t,
            });
        }
        let x = k.lu().solve(&rhs).ok_or(Error::Singular {
            what: "index-1 system [M Φ_qᵀ; Φ_q 0]",
            t,
        })?;
        if !x.iter().all(|v| v.is_finite()) {
            return Err(Error::Singular {
                what: "index-1 system [M Φ_qᵀ; Φ_q 0]",
                t,
            });
        }
        Ok((x.rows(0, n).into(), x.rows(n, m).into()))
    }

    /// Consistent initial state: positions projected onto `Φ = 0` and velocities
    /// onto `Φ_q q̇ + Φ_t = 0` (least-norm corrections), accelerations and
    /// multipliers from the index-1 equations.
    pub fn initial_state(&self, t0: f64) -> Result<State> {
        let (mut q, mut v) = self.initial_coords();
        let m = self.n_constraints();
        if m > 0 {
            let proj = |jac: &DMatrix<f64>, r: &DVector<f64>| -> Result<DVector<f64>> {
                let jjt = jac * jac.transpose();
                let y = jjt.lu().solve(r).ok_or(Error::Singular {
                    what: "constraint Jacobian Φ_q Φ_qᵀ",
                    t: t0,
                })?;
                Ok(jac.transpose() * y)
            };
            let scale = 1.0 + q.amax();
            for _ in 0..30 {
                let c = self.constraints(t0, &q);
                if c.phi.amax() <= 1e-13 * scale {
                    break;
                }
                q -= proj(&c.jac, &c.phi)?;
            }
            let c = self.constraints(t0, &q);
            if !(c.phi.amax() <= 1e-10 * scale) {
                return Err(Error::Inconsistent {
                    violation: c.phi.amax(),
                });
            }
            let r = &c.jac * &v + &c.phi_t;
            v -= proj(&c.jac, &r)?;
        }
        let (a, lambda) = self.accelerations(t0, &q, &v, (0.0, 0.0))?;
        Ok(State {
            t: t0,
            q,
            v,
            a,
            lambda,
        })
    }
}
