//! From a resolved scene ([`SceneSpec`]) to a [`Scene`]: the bodies with
//! their kernels, the joints, forces and outputs, in file order. What only
//! the build can refuse (a joint that does not close, a parameter a body's
//! kernels need, a point off a beam) is reported at the place in the scene
//! file that the spec carries. A scene file gets here through
//! `scene::load` (feature `scene-files`); a compiled scene with its spec as generated data.

use crate::runtime::nalgebra::{Matrix3, Unit, UnitQuaternion, Vector3};
use crate::runtime::spec::scene::{
    IntegratorSpec, MarkerPoint, MarkerSpec, MotorSpec, Orientation, ProfileSpec, SceneSpec,
};
use crate::runtime::spec::text::quoted as q;
use crate::runtime::spec::Location;
use crate::runtime::{Body, BodyId, Driver, GeneralizedAlpha, Integrator, Marker, Rk4Baumgarte};
use crate::runtime::{System, TorqueLaw};
use crate::scene::model::{Output, Scene};
use crate::scene::provider::KernelProvider;
use crate::SceneError;
use std::sync::Arc;

mod bodies;
mod forces;
mod inputs;
mod joints;
mod outputs;

/// An error at `at`; the runtime's messages carry their kind, the scene's
/// say where.
fn err(at: &Location, msg: impl Into<String>) -> SceneError {
    SceneError {
        location: Some(at.clone()),
        message: msg.into().replace("invalid input: ", ""),
    }
}

fn v3(x: [f64; 3]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

/// The runtime marker of `m` (a point on a beam's axis is looked up in the
/// body's mesh), with its own axes if it gives them: the axes of its
/// section, body or the ground turned by the rotation `R` of
/// [`MarkerSpec::axes`] (`Marker::axes` = those axes times `R`; a section's
/// deformation turns them further at run time).
pub(crate) fn marker(sys: &System<Box<dyn Body>>, m: &MarkerSpec) -> Result<Marker, SceneError> {
    let mk = point_marker(sys, m)?;
    Ok(match &m.axes {
        None => mk,
        Some(o) => {
            let r = rotation(o);
            let axes = mk.axes * r;
            mk.with_axes(axes)
        }
    })
}

/// The rotation matrix of an orientation (columns: the turned x, y, z).
fn rotation(o: &Orientation) -> Matrix3<f64> {
    match *o {
        Orientation::Planar(a) => {
            let (s, c) = a.sin_cos();
            Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
        }
        Orientation::Identity => Matrix3::identity(),
        Orientation::AxisAngle { axis, angle } => {
            UnitQuaternion::from_axis_angle(&Unit::new_normalize(v3(axis)), angle)
                .to_rotation_matrix()
                .into_inner()
        }
    }
}

fn point_marker(sys: &System<Box<dyn Body>>, m: &MarkerSpec) -> Result<Marker, SceneError> {
    Ok(match m.point {
        MarkerPoint::Ground(p) => Marker::ground(v3(p)),
        MarkerPoint::Origin(b) => Marker::origin(BodyId(b)),
        MarkerPoint::Point(b, p) => Marker::at(BodyId(b), v3(p)),
        MarkerPoint::Axis(b, x) => sys
            .point(BodyId(b), x)
            .map_err(|e| err(&m.at, format!("`{}`: {e}", q(&m.text))))?,
        MarkerPoint::Node(b, n) => sys
            .node(BodyId(b), n)
            .map_err(|e| err(&m.at, format!("`{}`: {e}", q(&m.text))))?,
    })
}

/// The driver of a profile: `f(t)`, `ḟ`, `f̈`.
fn driver(p: &ProfileSpec) -> Driver {
    match *p {
        ProfileSpec::SpinUp { omega, ramp, start } => {
            Driver::spin_up(omega, ramp).map(move |[f, fd, fdd]| [start + f, fd, fdd])
        }
        ProfileSpec::ConstantRate { start, rate } => Driver::linear(start, rate),
        ProfileSpec::Constant(v) => Driver::constant(v),
        ProfileSpec::Harmonic {
            start,
            amplitude,
            frequency,
            phase,
        } => Driver::harmonic(start, amplitude, frequency, phase),
    }
}

/// The torque law of a motor.
fn torque_law(m: &MotorSpec) -> TorqueLaw {
    match *m {
        MotorSpec::Torque(tau) => TorqueLaw::Torque(Arc::new(move |_| tau)),
        MotorSpec::Pd { target, kp, kd } => TorqueLaw::Pd {
            target: driver(&target),
            kp,
            kd,
        },
    }
}

fn integrator(i: &IntegratorSpec) -> Integrator {
    match *i {
        IntegratorSpec::GeneralizedAlpha { rho_inf, rtol } => {
            let mut g = GeneralizedAlpha::default();
            if let Some(x) = rho_inf {
                g.rho_inf = x;
            }
            if let Some(x) = rtol {
                g.rtol = x;
            }
            Integrator::GeneralizedAlpha(g)
        }
        IntegratorSpec::Rk4 { alpha, beta } => {
            let mut k = Rk4Baumgarte::default();
            if let Some(x) = alpha {
                k.alpha = x;
            }
            if let Some(x) = beta {
                k.beta = x;
            }
            Integrator::Rk4(k)
        }
    }
}

/// What the sections add to, in file order: the system, the notes on what
/// was folded in, how each body runs, the flexible bodies as built.
struct Parts {
    sys: System<Box<dyn Body>>,
    notes: Vec<String>,
    kernels: Vec<(String, String)>,
    flex: Vec<crate::runtime::spec::scene::FlexSpec>,
    fe: Vec<crate::runtime::spec::scene::FeSpec>,
    unsplit: Vec<(String, Box<dyn Body>)>,
}

/// Build the scene `spec` describes, with the flexible bodies' kernels from
/// `provider`.
pub fn build(spec: &SceneSpec, provider: &dyn KernelProvider) -> Result<Scene, SceneError> {
    let mut parts = Parts {
        sys: System::with_dim(spec.dim),
        notes: Vec::new(),
        kernels: Vec::new(),
        flex: Vec::new(),
        fe: Vec::new(),
        unsplit: Vec::new(),
    };
    bodies::add_bodies(spec, provider, &mut parts)?;
    if let Some((g, at)) = &spec.gravity {
        parts
            .sys
            .set_gravity(v3(*g))
            .map_err(|e| err(at, e.to_string()))?;
    }
    // Inputs first (a drive perturbed by one names its index), their
    // torques and forces after the scene's forces.
    let inputs = inputs::add_inputs(spec, &mut parts.sys)?;
    let joint_sites = joints::add_joints(spec, &mut parts)?;
    for f in &spec.forces {
        forces::add_force(&mut parts.sys, f)?;
    }
    inputs::add_input_loads(spec, &mut parts.sys)?;
    let outputs = spec
        .outputs
        .iter()
        .map(|o| outputs::output(&parts.sys, o))
        .collect::<Result<Vec<Output>, _>>()?;
    // The initial state: the joints must close by moving the bodies' frames
    // (or the elastic states the scene gives), and none may be redundant.
    if let Err(crate::runtime::Error::Joint {
        joint,
        kind,
        reason,
    }) = parts.sys.initial_state(0.0)
    {
        let at = joint_sites.get(joint).unwrap_or(&spec.dt_at);
        return Err(err(at, format!("{kind} joint: {reason}")));
    }
    Ok(Scene {
        origin: spec.origin.clone(),
        description: spec.description.clone(),
        system: parts.sys,
        t_end: spec.t_end,
        dt: spec.dt,
        integrator: integrator(&spec.integrator),
        outputs,
        inputs,
        flex: parts.flex,
        fe: parts.fe,
        unsplit: parts.unsplit,
        kernels: parts.kernels,
        notes: parts.notes,
    })
}
