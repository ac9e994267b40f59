//! Scenes shared by several integration tests.
#![allow(dead_code)]

use ffr::kernels::BeamSpec;
use ffr::runtime::nalgebra::{Vector2, Vector3};
use ffr::runtime::spec::{AttachedMass, Params, Stiffening};
use ffr::runtime::{Body, Driver, Marker, Pose, RigidBody, System, TorqueLaw};

pub const BAR: Params = Params {
    length: 1.0,
    rho: 2700.0,
    area: 1e-4,
    iy: 8.3e-10,
    iz: 8.3e-10,
    e: 7e10,
    g: 2.6e10,
    j: 1.4e-9,
};

/// A flexible arm on a revolute joint, a rigid link on its tip, a spring to
/// the ground, a point force and a driven joint: every kind of interaction.
pub fn mechanism(dim: usize) -> System<Box<dyn Body>> {
    mechanism_with_masses(dim, &[])
}

/// [`mechanism`] with `masses` attached on the arm.
pub fn mechanism_with_masses(dim: usize, masses: &[AttachedMass]) -> System<Box<dyn Body>> {
    let mut sys: System<Box<dyn Body>> = System::with_dim(dim);
    let arm = BeamSpec::new(if dim == 2 { "beam2" } else { "beam3" }, 4, BAR)
        .stiffening(Stiffening::FourthOrder)
        .scene_dim(dim)
        .body()
        .unwrap()
        .with_masses(masses)
        .unwrap();
    let a = sys
        .add_body("arm", Box::new(arm), Pose::identity(dim))
        .unwrap();
    let link: Box<dyn Body> = if dim == 2 {
        Box::new(RigidBody::planar(0.5, 1e-3, Vector2::new(0.1, 0.0)).unwrap())
    } else {
        Box::new(
            RigidBody::spatial(
                0.5,
                ffr::runtime::nalgebra::Matrix3::from_diagonal(&Vector3::new(1e-4, 1e-3, 1e-3)),
                Vector3::new(0.1, 0.0, 0.0),
            )
            .unwrap(),
        )
    };
    let pose = if dim == 2 {
        Pose::planar(1.0, 0.0, 0.0)
    } else {
        Pose::spatial(Vector3::new(1.0, 0.0, 0.0), Default::default())
    };
    let l = sys.add_body("link", link, pose).unwrap();
    let hub = Marker::ground(Vector3::zeros());
    let root = Marker::origin(a);
    sys.revolute(hub.clone(), root.clone()).unwrap();
    sys.prescribe_rotation(hub, root, Driver::linear(0.0, 1.0))
        .unwrap();
    let tip = sys.point(a, 1.0).unwrap();
    sys.revolute(tip.clone(), Marker::origin(l)).unwrap();
    let tip = tip.clone();
    let mid = sys.point(a, 0.5).unwrap();
    sys.add_spring_damper(
        Marker::ground(Vector3::new(0.5, 0.3, 0.0)),
        mid,
        50.0,
        0.5,
        0.25,
    )
    .unwrap();
    sys.add_point_force(Marker::at(l, Vector3::new(0.2, 0.0, 0.0)), |t| {
        Vector3::new(0.0, -0.5 * t.sin(), 0.1)
    })
    .unwrap();
    // A follower force at the arm's mid-point, a rotational spring–damper in
    // the tip joint and a PD motor in the hub.
    let quarter = sys.point(a, 0.25).unwrap();
    sys.add_follower_force(quarter, |t| Vector3::new(0.1, 0.3 * t.cos(), -0.05))
        .unwrap();
    sys.add_torque(
        tip,
        Marker::origin(l),
        TorqueLaw::SpringDamper {
            stiffness: 2.0,
            damping: 0.05,
            rest_angle: 0.3,
        },
    )
    .unwrap();
    sys.add_torque(
        Marker::ground(Vector3::zeros()),
        Marker::origin(a),
        TorqueLaw::Pd {
            target: Driver::linear(0.0, 1.0),
            kp: 5.0,
            kd: 0.5,
        },
    )
    .unwrap();
    sys.set_gravity(Vector3::new(0.0, -9.81, 0.0)).unwrap();
    sys
}
/// The largest column error of the generalized-α iteration matrix of `sys`
/// against central differences of its residual (and the column), at the
/// state reached after `t_end` s with steps of 1 ms.
pub fn iteration_matrix_error(sys: &System<Box<dyn Body>>, t_end: f64) -> (f64, usize) {
    use ffr::runtime::{Assembly, GeneralizedAlpha, Integrator};
    let integrator = Integrator::GeneralizedAlpha(GeneralizedAlpha::default());
    let h = 1e-3;
    let mut state = None;
    sys.simulate(t_end, h, &integrator, |v| {
        state = Some(v.state.clone());
        std::ops::ControlFlow::Continue(())
    })
    .unwrap();
    let s = state.unwrap();
    let (am, af, gamma, beta) = GeneralizedAlpha::default().coefficients();
    let bp = (1.0 - am) / ((1.0 - af) * beta * h * h);
    let gp = gamma / (beta * h);
    let mut asm = Assembly::new(sys).unwrap();
    let lam: Vec<f64> = s.lambda.iter().map(|l| l / bp).collect();
    asm.iteration_matrix_error(s.t, &s.q, &s.v, &s.a, &lam, bp, gp)
}

pub mod cli;
pub mod outputs;
