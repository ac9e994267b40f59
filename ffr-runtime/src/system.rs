//! A multibody system under construction: bodies, their initial state,
//! prescribed coordinates, constraints, force elements, gravity.
//!
//! Coordinates of a body: planar `[R_x, R_y, θ, q_f]`, spatial
//! `[R (3), e (4 Euler parameters), q_f]`. The equations
//! `M(q) q̈ + Φ_qᵀ λ = Q(q, q̇, t)`, `Φ(q, t) = 0` are assembled and solved by
//! [`crate::assembly::Assembly`]; integrators are in [`crate::integrator`].

use crate::body::Body;
use crate::driver::Driver;
use crate::error::{Error, Result};
use crate::force::{ForceAxes, ForceElement, TorqueLaw, VectorFn};
use crate::joint::{angle_row, coincident_rows, offset_row, perpendicular_row, Constraint, Row};
use crate::marker::{BodyId, Marker};
use crate::rotation::{euler_parameters, Rotation};
use nalgebra::{UnitQuaternion, Vector3};
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

/// Rayleigh damping `D = α M_ff + β K_ff` on the elastic coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Rayleigh {
    /// Mass-proportional coefficient `α` (1/s).
    pub alpha: f64,
    /// Stiffness-proportional coefficient `β` (s).
    pub beta: f64,
}

/// A body of a system with its place in the coordinates.
#[derive(Clone, Debug)]
pub struct BodyEntry<B> {
    /// The body.
    pub body: B,
    /// Its name (for messages and outputs).
    pub name: String,
    /// Index of its first coordinate.
    pub offset: usize,
    /// Frame translations `d` (2 or 3).
    pub d: usize,
    /// Rotational coordinates `n_θ` (1 or 4).
    pub n_theta: usize,
    /// Elastic coordinates.
    pub nf: usize,
    /// Rayleigh damping of the elastic coordinates.
    pub damping: Option<Rayleigh>,
    /// Whether an initial elastic state was given ([`System::set_elastic`]):
    /// only then may the initial projection onto the joints move the
    /// elastic coordinates.
    pub elastic_state: bool,
}

impl<B> BodyEntry<B> {
    /// Number of coordinates `d + n_θ + n_f`.
    pub fn n_coords(&self) -> usize {
        self.d + self.n_theta + self.nf
    }
    /// Index (global) of the first elastic coordinate.
    pub fn f_offset(&self) -> usize {
        self.offset + self.d + self.n_theta
    }
}

/// A multibody system under construction.
pub struct System<B: Body = Box<dyn Body>> {
    pub(crate) dim: usize,
    pub(crate) bodies: Vec<BodyEntry<B>>,
    pub(crate) q0: Vec<f64>,
    pub(crate) v0: Vec<f64>,
    pub(crate) prescribed: Vec<(usize, Driver)>,
    pub(crate) constraints: Vec<Constraint>,
    pub(crate) forces: Vec<ForceElement>,
    pub(crate) gravity: Vector3<f64>,
    pub(crate) monitor: crate::monitor::Monitor,
    /// Bodies run as segments ([`System::add_segments`]).
    pub(crate) segments: Vec<crate::segmented::SegmentGroup>,
    /// The start values of the inputs ([`System::add_input`]).
    pub(crate) inputs: Vec<f64>,
}

impl<B: Body> System<B> {
    /// An empty planar scene (body coordinates `[R_x, R_y, θ, q_f]`).
    pub fn planar() -> Self {
        Self::with_dim(2)
    }
    /// An empty spatial scene (body coordinates `[R (3), e (4), q_f]`).
    pub fn spatial() -> Self {
        Self::with_dim(3)
    }
    /// An empty scene of dimension 2 or 3.
    pub fn with_dim(dim: usize) -> Self {
        assert!(dim == 2 || dim == 3, "a scene is planar (2) or spatial (3)");
        Self {
            dim,
            bodies: Vec::new(),
            q0: Vec::new(),
            v0: Vec::new(),
            prescribed: Vec::new(),
            constraints: Vec::new(),
            forces: Vec::new(),
            gravity: Vector3::zeros(),
            monitor: crate::monitor::Monitor::default(),
            segments: Vec::new(),
            inputs: Vec::new(),
        }
    }

    /// A new input with value `start` until a caller sets another
    /// ([`crate::Assembly::inputs_mut`], [`crate::Stepper::set_input`]):
    /// its index, for [`TorqueLaw::Input`], [`ForceElement::Input`] and
    /// [`Driver::with_input`]. Each integration holds its own values.
    pub fn add_input(&mut self, start: f64) -> Result<usize> {
        if !start.is_finite() {
            return Err(Error::InvalidInput(format!(
                "an input's start value must be finite (got {start})"
            )));
        }
        self.inputs.push(start);
        Ok(self.inputs.len() - 1)
    }

    /// The number of inputs.
    pub fn n_inputs(&self) -> usize {
        self.inputs.len()
    }

    fn check_input(&self, k: usize) -> Result<()> {
        if k >= self.inputs.len() {
            return Err(Error::InvalidInput(format!(
                "input {k} does not exist (the system has {} inputs)",
                self.inputs.len()
            )));
        }
        Ok(())
    }

    /// The divergence monitor's bounds ([`crate::monitor`]; on by default).
    pub fn monitor(&self) -> crate::monitor::Monitor {
        self.monitor
    }
    /// Set the divergence monitor's bounds (`Monitor::off()` to follow a
    /// run past its validity, e.g. in a stability study).
    pub fn set_monitor(&mut self, monitor: crate::monitor::Monitor) {
        self.monitor = monitor;
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
    /// The bodies with their places.
    pub fn bodies(&self) -> &[BodyEntry<B>] {
        &self.bodies
    }
    /// Rotational coordinates per body (1 planar, 4 spatial).
    pub fn n_theta(&self) -> usize {
        if self.dim == 2 {
            1
        } else {
            4
        }
    }

    /// Add a body named `name` at `pose`, at rest and undeformed.
    pub fn add_body(&mut self, name: &str, body: B, pose: Pose) -> Result<BodyId> {
        let lay = body.layout();
        if lay.dim > self.dim {
            return Err(Error::InvalidInput(format!(
                "body `{name}` is spatial ({}); a planar scene needs planar bodies",
                lay.description
            )));
        }
        // Kernels for a spatial scene are general: they also serve a planar
        // one (the out-of-plane frame motion is zero); planar-scene kernels
        // leave out the out-of-plane terms and cannot serve a spatial scene.
        if lay.nf > 0 && lay.scene_dim < self.dim {
            return Err(Error::InvalidInput(format!(
                "body `{name}` ({}) was generated for a {} scene, but this scene is {}: generate it with scene dimension {}",
                lay.description,
                if lay.scene_dim == 2 { "planar" } else { "spatial" },
                if self.dim == 2 { "planar" } else { "spatial" },
                self.dim
            )));
        }
        if self.bodies.iter().any(|b| b.name == name) {
            return Err(Error::InvalidInput(format!(
                "two bodies are named `{name}`"
            )));
        }
        let id = self.bodies.len();
        let (d, nth, nf) = (self.dim, self.n_theta(), lay.nf);
        let off = self.q0.len();
        let mut q = vec![0.0; d + nth + nf];
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
                    "the pose of `{name}` ({pose:?}) does not match a {}-D scene",
                    self.dim
                )))
            }
        }
        if !q.iter().all(|x| x.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "the pose of `{name}` is not finite: {pose:?}"
            )));
        }
        self.q0.extend_from_slice(&q);
        self.v0.extend(std::iter::repeat_n(0.0, q.len()));
        self.bodies.push(BodyEntry {
            body,
            name: name.to_string(),
            offset: off,
            d,
            n_theta: nth,
            nf,
            damping: None,
            elastic_state: false,
        });
        Ok(BodyId(id))
    }

    fn entry(&self, id: BodyId) -> Result<&BodyEntry<B>> {
        self.bodies
            .get(id.0)
            .ok_or_else(|| Error::InvalidInput(format!("no body {}", id.0)))
    }

    /// The body.
    pub fn body(&self, id: BodyId) -> &B {
        &self.bodies[id.0].body
    }
    /// The body's entry (name, offsets).
    pub fn body_entry(&self, id: BodyId) -> &BodyEntry<B> {
        &self.bodies[id.0]
    }
    /// The body named `name`.
    pub fn body_id(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name).map(BodyId)
    }
    /// Offset of the body's coordinates in `q`.
    pub fn offset(&self, id: BodyId) -> usize {
        self.bodies[id.0].offset
    }

    /// Rayleigh damping `α M_ff + β K_ff` on the body's elastic coordinates.
    pub fn set_damping(&mut self, id: BodyId, damping: Rayleigh) -> Result<()> {
        self.entry(id)?;
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
        // A segmented body's damping is every segment's.
        if let Some(g) = self.segments.iter().find(|g| g.root() == id) {
            for b in g.bodies.clone() {
                self.bodies[b.0].damping = Some(damping);
            }
        }
        Ok(())
    }

    /// Initial velocity of the body frame: origin velocity `v` and angular
    /// velocity `omega` (global axes; only `omega.z` in the plane).
    ///
    /// On the root of a body run as segments, the whole body moves
    /// rigidly: segment `k` at `v + ω × (R_k − R_root)`.
    pub fn set_velocity(&mut self, id: BodyId, v: Vector3<f64>, omega: Vector3<f64>) -> Result<()> {
        self.set_frame_velocity(id, v, omega)?;
        let outboard: Vec<BodyId> = self
            .segments
            .iter()
            .find(|g| g.root() == id)
            .map(|g| g.bodies[1..].to_vec())
            .unwrap_or_default();
        if !outboard.is_empty() {
            let o = self.bodies[id.0].offset;
            let d = self.dim;
            let r0 =
                Vector3::from_iterator((0..3).map(|k| if k < d { self.q0[o + k] } else { 0.0 }));
            for b in outboard {
                let ob = self.bodies[b.0].offset;
                let r =
                    Vector3::from_iterator(
                        (0..3).map(|k| if k < d { self.q0[ob + k] } else { 0.0 }),
                    );
                self.set_frame_velocity(b, v + omega.cross(&(r - r0)), omega)?;
            }
        }
        Ok(())
    }

    fn set_frame_velocity(
        &mut self,
        id: BodyId,
        v: Vector3<f64>,
        omega: Vector3<f64>,
    ) -> Result<()> {
        let (o, d, nth) = {
            let e = self.entry(id)?;
            (e.offset, e.d, e.n_theta)
        };
        if !v.iter().chain(omega.iter()).all(|x| x.is_finite()) {
            return Err(Error::InvalidInput("non-finite initial velocity".into()));
        }
        self.v0[o..o + d].copy_from_slice(&v.as_slice()[..d]);
        if d == 2 {
            self.v0[o + 2] = omega.z;
        } else {
            // θ̇ = ½ Ḡᵀ ω̄, ω̄ = Aᵀ ω (Ḡ Ḡᵀ = 4 I, Ḡ e = 0).
            let rot = Rotation::new(&self.q0[o + d..o + d + nth]);
            let wb = rot.a.transpose() * omega;
            let g = rot.g_t(&wb);
            for (v, gj) in self.v0[o + 3..o + 7].iter_mut().zip(g) {
                *v = 0.5 * gj;
            }
        }
        Ok(())
    }

    /// Initial elastic coordinates and velocities.
    pub fn set_elastic(&mut self, id: BodyId, q_f: &[f64], qd_f: &[f64]) -> Result<()> {
        if self.segment_group(id).is_some() {
            return Err(Error::InvalidInput(format!(
                "body `{}` runs as segments: its initial elastic state is not available (start it undeformed)",
                self.bodies[id.0].name
            )));
        }
        let e = self.entry(id)?;
        let (o, nf) = (e.f_offset(), e.nf);
        if q_f.len() != nf || qd_f.len() != nf {
            return Err(Error::InvalidInput(format!(
                "body `{}` has {nf} elastic coordinates",
                e.name
            )));
        }
        if !q_f.iter().chain(qd_f).all(|x| x.is_finite()) {
            return Err(Error::InvalidInput(
                "non-finite elastic initial conditions".into(),
            ));
        }
        self.q0[o..o + nf].copy_from_slice(q_f);
        self.v0[o..o + nf].copy_from_slice(qd_f);
        self.bodies[id.0].elastic_state = true;
        Ok(())
    }

    /// Gravity (global; z ignored in the plane).
    pub fn set_gravity(&mut self, g: Vector3<f64>) -> Result<()> {
        if !g.iter().all(|x| x.is_finite()) {
            return Err(Error::InvalidInput(format!("gravity {g:?} is not finite")));
        }
        self.gravity = if self.dim == 2 {
            Vector3::new(g.x, g.y, 0.0)
        } else {
            g
        };
        Ok(())
    }
    /// Gravity vector.
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }
    /// Initial coordinates and velocities as set (before any projection).
    pub fn initial_coords(&self) -> (&[f64], &[f64]) {
        (&self.q0, &self.v0)
    }

    /// The point at `x` on body `b`'s undeformed axis (a beam body), with
    /// the body's axes.
    ///
    /// On the root of a body run as segments ([`System::add_segments`]),
    /// `x` is on the whole body's axis, `[0, L]`, and the marker is on the
    /// segment that holds it (see [`crate::segmented`]).
    pub fn point(&self, b: BodyId, x: f64) -> Result<Marker> {
        if let Some(g) = self.segments.iter().find(|g| g.root() == b) {
            let (k, local) = g.locate(x).ok_or_else(|| {
                Error::InvalidInput(format!(
                    "body `{}`: x = {x:?} is not on its axis (0 to {:?} m, {} segments)",
                    self.bodies[b.0].name,
                    g.bounds[g.bounds.len() - 1],
                    g.bodies.len()
                ))
            })?;
            return self.point_on(g.bodies[k], local);
        }
        let e = self.entry(b)?;
        let shape = e
            .body
            .point_shape(x)
            .map_err(|err| Error::InvalidInput(format!("body `{}`: {err}", e.name)))?;
        Ok(Marker::point(b, shape))
    }

    /// A marker at node `node` of FE body `b` (its node shape).
    pub fn node(&self, b: BodyId, node: usize) -> Result<Marker> {
        let e = self.entry(b)?;
        let shape = e
            .body
            .node_shape(node)
            .map_err(|err| Error::InvalidInput(format!("body `{}`: {err}", e.name)))?;
        Ok(Marker::point(b, shape))
    }

    fn check_marker(&self, m: &Marker) -> Result<()> {
        let Some(b) = m.body else {
            return Ok(());
        };
        let e = self.entry(b)?;
        for (dof, _, _) in &m.shape.entries {
            if *dof >= e.nf {
                return Err(Error::InvalidInput(format!(
                    "marker on `{}` refers to elastic coordinate {dof}, the body has {}",
                    e.name, e.nf
                )));
            }
        }
        if m.shape.entries.len() > crate::marker::MAX_POINT_DOFS {
            return Err(Error::InvalidInput(format!(
                "a marker may depend on at most {} elastic coordinates",
                crate::marker::MAX_POINT_DOFS
            )));
        }
        if !m
            .shape
            .u0
            .iter()
            .chain(m.axes.iter())
            .all(|x| x.is_finite())
        {
            return Err(Error::InvalidInput("non-finite marker".into()));
        }
        Ok(())
    }

    /// Add a constraint.
    pub fn add_constraint(&mut self, c: Constraint) -> Result<()> {
        self.check_marker(&c.a)?;
        self.check_marker(&c.b)?;
        if c.a.body.is_none() && c.b.body.is_none() {
            return Err(Error::InvalidInput(format!(
                "a {} joint between two ground markers",
                c.kind
            )));
        }
        self.constraints.push(c);
        Ok(())
    }

    fn joint(&mut self, kind: &str, a: Marker, b: Marker, rows: Vec<Row>) -> Result<()> {
        self.add_constraint(Constraint {
            kind: kind.to_string(),
            a,
            b,
            rows,
        })
    }

    /// Prescribe body coordinate `index` (0-based within the body) as `f(t)`.
    pub fn prescribe_coordinate(
        &mut self,
        body: BodyId,
        index: usize,
        driver: Driver,
    ) -> Result<()> {
        if let Some(k) = driver.input() {
            self.check_input(k)?;
        }
        let e = self.entry(body)?;
        if index >= e.n_coords() {
            return Err(Error::InvalidInput(format!(
                "body `{}` has no coordinate {index} (it has {})",
                e.name,
                e.n_coords()
            )));
        }
        let g = e.offset + index;
        if self.prescribed.iter().any(|(c, _)| *c == g) {
            return Err(Error::InvalidInput(format!(
                "coordinate {index} of `{}` is prescribed twice",
                e.name
            )));
        }
        self.prescribed.push((g, driver));
        Ok(())
    }

    /// Fix a body's frame to the ground in its initial pose (all frame
    /// coordinates prescribed constant).
    pub fn ground(&mut self, body: BodyId) -> Result<()> {
        let e = self.entry(body)?;
        let (o, n) = (e.offset, e.d + e.n_theta);
        for i in 0..n {
            let c = self.q0[o + i];
            self.prescribe_coordinate(body, i, Driver::constant(c))?;
        }
        Ok(())
    }

    /// Prescribe a spatial body's frame rotation as the angle `f(t)` about
    /// global z from its initial orientation (Euler parameters
    /// `e = q_z(f) ⊗ e₀`), and its origin fixed.
    pub fn prescribe_rotation_about_z(&mut self, body: BodyId, driver: Driver) -> Result<()> {
        let e = self.entry(body)?;
        let o = e.offset;
        if self.dim != 3 {
            self.prescribe_coordinate(body, 0, Driver::constant(self.q0[o]))?;
            self.prescribe_coordinate(body, 1, Driver::constant(self.q0[o + 1]))?;
            let t0 = self.q0[o + 2];
            return self.prescribe_coordinate(
                body,
                2,
                driver.map(move |[f, fd, fdd]| [t0 + f, fd, fdd]),
            );
        }
        for i in 0..3 {
            let c = self.q0[o + i];
            self.prescribe_coordinate(body, i, Driver::constant(c))?;
        }
        let e0 = [
            self.q0[o + 3],
            self.q0[o + 4],
            self.q0[o + 5],
            self.q0[o + 6],
        ];
        // q_z(f) = (cos f/2, 0, 0, sin f/2); (c, 0, 0, s) ⊗ (w, x, y, z) =
        // (c w − s z, c x − s y, c y + s x, c z + s w).
        let comps: [[f64; 2]; 4] = [
            [e0[0], -e0[3]],
            [e0[1], -e0[2]],
            [e0[2], e0[1]],
            [e0[3], e0[0]],
        ];
        for (k, [cc, ss]) in comps.into_iter().enumerate() {
            self.prescribe_coordinate(
                body,
                3 + k,
                driver.map(move |[f, fd, fdd]| {
                    let (s, c) = (0.5 * f).sin_cos();
                    let h = 0.5 * fd;
                    // d/dt (cc cos(f/2) + ss sin(f/2)), twice.
                    let v = cc * c + ss * s;
                    let vd = (-cc * s + ss * c) * h;
                    let vdd = -v * h * h + (-cc * s + ss * c) * 0.5 * fdd;
                    [v, vd, vdd]
                }),
            )?;
        }
        Ok(())
    }

    /// Fixed joint: `a` and `b` coincide with aligned axes (planar: point +
    /// angle; spatial: point + `x_a·y_b = y_a·z_b = z_a·x_b = 0`).
    pub fn fixed(&mut self, a: Marker, b: Marker) -> Result<()> {
        let mut rows = coincident_rows(self.dim);
        if self.dim == 2 {
            rows.push(angle_row(Driver::constant(0.0)));
        } else {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                rows.push(perpendicular_row(i, j));
            }
        }
        self.joint("fixed", a, b, rows)
    }

    /// Revolute joint about the markers' z axes (planar: coincident points;
    /// spatial: coincident points and `z_a·x_b = z_a·y_b = 0`).
    pub fn revolute(&mut self, a: Marker, b: Marker) -> Result<()> {
        let mut rows = coincident_rows(self.dim);
        if self.dim == 3 {
            rows.push(perpendicular_row(2, 0));
            rows.push(perpendicular_row(2, 1));
        }
        self.joint("revolute", a, b, rows)
    }

    /// Spherical joint (spatial only): coincident points.
    pub fn spherical(&mut self, a: Marker, b: Marker) -> Result<()> {
        if self.dim != 3 {
            return Err(Error::InvalidInput(
                "a spherical joint needs a spatial scene".into(),
            ));
        }
        let rows = coincident_rows(3);
        self.joint("spherical", a, b, rows)
    }

    /// Prismatic joint along marker `a`'s x axis: `b` keeps `a`'s
    /// orientation and slides along `x_a` (planar: `(p_b − p_a)·y_a = 0` and
    /// no relative rotation; spatial: `(p_b − p_a)·y_a = (p_b − p_a)·z_a = 0`
    /// and aligned axes).
    pub fn prismatic(&mut self, a: Marker, b: Marker) -> Result<()> {
        let mut rows = vec![offset_row(1, None)];
        if self.dim == 2 {
            rows.push(angle_row(Driver::constant(0.0)));
        } else {
            rows.push(offset_row(2, None));
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                rows.push(perpendicular_row(i, j));
            }
        }
        self.joint("prismatic", a, b, rows)
    }

    /// Driving constraint: `b` turned by `f(t)` about the z axis of `a`
    /// (combine with a revolute joint).
    pub fn prescribe_rotation(&mut self, a: Marker, b: Marker, driver: Driver) -> Result<()> {
        self.joint("rotation drive", a, b, vec![angle_row(driver)])
    }

    /// Driving constraint: `(p_b − p_a)·x_a = f(t)` (combine with a prismatic joint).
    pub fn prescribe_slide(&mut self, a: Marker, b: Marker, driver: Driver) -> Result<()> {
        self.joint("slide drive", a, b, vec![offset_row(0, Some(driver))])
    }

    /// Add a force element.
    pub fn add_force(&mut self, f: ForceElement) -> Result<()> {
        let (ma, mb) = f.markers();
        self.check_marker(ma)?;
        if let Some(mb) = mb {
            self.check_marker(mb)?;
        }
        match &f {
            ForceElement::Input {
                direction, input, ..
            } => {
                self.check_input(*input)?;
                if !(direction.iter().all(|x| x.is_finite()) && direction.norm() > 0.0) {
                    return Err(Error::InvalidInput(format!(
                        "an input force's direction must be finite and not zero (got {:?})",
                        direction.as_slice()
                    )));
                }
            }
            ForceElement::Torque {
                law: TorqueLaw::Input(k),
                ..
            } => self.check_input(*k)?,
            _ => {}
        }
        if let ForceElement::SpringDamper {
            stiffness,
            damping,
            rest_length,
            ..
        } = &f
        {
            if !(stiffness.is_finite()
                && damping.is_finite()
                && rest_length.is_finite()
                && *stiffness >= 0.0
                && *damping >= 0.0
                && *rest_length >= 0.0)
            {
                return Err(Error::InvalidInput(format!(
                    "spring–damper needs finite k, c, l₀ ≥ 0 (got {stiffness}, {damping}, {rest_length})"
                )));
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
        let force: VectorFn = Arc::new(force);
        self.add_force(ForceElement::Point {
            marker,
            force,
            axes: ForceAxes::Global,
        })
    }

    /// A force `F(t)` at a marker given in the marker's axes (a follower force).
    pub fn add_follower_force(
        &mut self,
        marker: Marker,
        force: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static,
    ) -> Result<()> {
        let force: VectorFn = Arc::new(force);
        self.add_force(ForceElement::Point {
            marker,
            force,
            axes: ForceAxes::Marker,
        })
    }

    /// A torque about `z_a` between markers `a` and `b` (on `b`; `−τ` on `a`)
    /// following `law`.
    pub fn add_torque(&mut self, a: Marker, b: Marker, law: TorqueLaw) -> Result<()> {
        match &law {
            TorqueLaw::SpringDamper {
                stiffness,
                damping,
                rest_angle,
            } if !(stiffness.is_finite()
                && damping.is_finite()
                && rest_angle.is_finite()
                && *stiffness >= 0.0
                && *damping >= 0.0) =>
            {
                return Err(Error::InvalidInput(format!(
                    "rotational spring–damper needs finite k, c ≥ 0 and a finite rest angle (got {stiffness}, {damping}, {rest_angle})"
                )))
            }
            TorqueLaw::Pd { kp, kd, .. } if !(kp.is_finite() && kd.is_finite() && *kp >= 0.0 && *kd >= 0.0) => {
                return Err(Error::InvalidInput(format!(
                    "PD gains must be finite and ≥ 0 (got kp = {kp}, kd = {kd})"
                )))
            }
            _ => {}
        }
        self.add_force(ForceElement::Torque { a, b, law })
    }

    /// A linear spring–damper between two markers.
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

    /// Constraints.
    pub fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }
    /// Force elements.
    pub fn forces(&self) -> &[ForceElement] {
        &self.forces
    }
    /// Prescribed coordinates (global index, driver).
    pub fn prescribed(&self) -> &[(usize, Driver)] {
        &self.prescribed
    }
}
