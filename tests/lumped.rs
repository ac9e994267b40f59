//! The lumped formalism has no nodal rotary inertia (theory sheet), so a
//! body's `m_ff` is singular in its rotational coordinates: the runtime must
//! say so instead of integrating NaNs.

use ffr::codegen::{BodySpec, Formalism, Options, ParamValues, Reference, Shape};
use ffr::runtime::{scenes, Error, FlexBody, GeneralizedAlpha, Integrator};
use ffr::EvaluatedBody;

#[test]
fn lumped_body_without_rotary_inertia_is_reported_singular() {
    let spec = BodySpec::new(
        Shape::resolve("beam2", None).unwrap(),
        4,
        Reference::Clamped,
    )
    .unwrap()
    .with_formalism(Formalism::Lumped);
    let p = ParamValues {
        length: 1.0,
        rho: 7850.0,
        area: 1e-4,
        iy: 8e-10,
        iz: 8e-10,
        e: 2.1e11,
        g: 8.1e10,
        j: 1.4e-8,
    };
    let body = EvaluatedBody::new(&spec, Options::default(), p).unwrap();
    let m_ff = body.invariants().m_ff;
    let rz = body.dof_labels().iter().position(|d| d == "rz_1").unwrap();
    assert_eq!(m_ff[(rz, rz)], 0.0, "no rotary inertia at the nodes");
    let (sys, _) = scenes::pendulum(Box::new(body)).unwrap();
    let run = sys.simulate(
        0.01,
        1e-3,
        &Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.8)),
        |_| std::ops::ControlFlow::Continue(()),
    );
    match run {
        Err(e @ Error::Singular { .. }) => println!("{e}"),
        Err(other) => panic!("unexpected error: {other}"),
        Ok(_) => panic!("a singular mass matrix was integrated"),
    }
}
