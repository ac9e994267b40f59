//! The lumped formalism has no nodal rotary inertia (theory: `docs/theory.md`),
//! so a body's `m_ff` is singular in its rotational coordinates: the runtime
//! must say so, naming the coordinate without inertia and the cause, instead
//! of integrating NaNs (the initial projection and the index-1 solve of RK4
//! factor the mass system `[M Φ_qᵀ; Φ_q 0]`).

use ffr::runtime::spec::{Formalism, KernelOptions, Params, Reference};
use ffr::runtime::{Body, Error, GeneralizedAlpha, Integrator};
use ffr::BeamSpec;
use ffr_cli::benchmarks::pendulum;

fn lumped(shape: &str) -> BeamSpec {
    BeamSpec {
        shape: shape.into(),
        elements: 4,
        reference: Reference::Clamped,
        options: KernelOptions::new().formalism(Formalism::Lumped),
        params: Params {
            length: 1.0,
            rho: 7850.0,
            area: 1e-4,
            iy: 8e-10,
            iz: 8e-10,
            e: 2.1e11,
            g: 8.1e10,
            j: 1.4e-8,
        },
        force_tape: false,
    }
}

#[test]
fn lumped_body_without_rotary_inertia_is_refused_in_a_dynamic_scene() {
    // The first coordinate without inertia: the bending rotation of node 1
    // in the plane, the torsion of node 1 in space.
    for (shape, first) in [("beam2", "rz_1"), ("beam3", "rx_1")] {
        let body = lumped(shape).body().unwrap();
        assert_eq!(body.kernels().path(), "compiled");
        let m_ff = body.invariants().m_ff;
        let rz = body
            .layout()
            .labels
            .iter()
            .position(|d| d == "rz_1")
            .unwrap();
        assert_eq!(
            m_ff[(rz, rz)],
            0.0,
            "{shape}: no rotary inertia at the nodes"
        );
        let (sys, _) = pendulum::scene(body).unwrap();
        for integrator in [
            Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.8)),
            Integrator::Rk4(Default::default()),
        ] {
            let run = sys.simulate(0.01, 1e-3, &integrator, |_| {
                std::ops::ControlFlow::Continue(())
            });
            match run {
                Err(e @ Error::Singular { .. }) => {
                    let msg = e.to_string();
                    println!("{shape}: {msg}");
                    // Names the coordinate, the body and its formalism, and the
                    // cause among the possible ones.
                    assert!(
                        msg.contains(&format!("coordinate `{first}` of body `bar`")),
                        "{msg}"
                    );
                    assert!(msg.contains("lumped formalism"), "{msg}");
                    assert!(msg.contains("no rotary inertia"), "{msg}");
                }
                Err(other) => panic!("{shape}: unexpected error: {other}"),
                Ok(_) => panic!("{shape}: a singular mass matrix was integrated"),
            }
        }
    }
}
