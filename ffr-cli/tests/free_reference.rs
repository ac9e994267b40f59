//! A `free` reference condition keeps every nodal coordinate, so the elastic
//! coordinates can move the body rigidly, as its frame coordinates do: with
//! the frame free the mass matrix is singular. In floating point its pivots
//! are round-off, not zero, and the integrators used to run on: the
//! pendulum with a free-reference bar ended in `NoConvergence` at step 0 with
//! a residual of 2.8e132 and the advice to shorten the step. The runtime now
//! refuses such a body when the system is assembled, naming the body, its
//! reference condition and the frame motion its elastic coordinates repeat.

use ffr::runtime::nalgebra::Vector3;
use ffr::runtime::spec::Reference;
use ffr::runtime::{Error, GeneralizedAlpha, Integrator, Marker, Pose, System};
use ffr_cli::benchmarks::pendulum::{self, beam_spec, Beam, ALUMINIUM_BAR};
use std::ops::ControlFlow;

fn integrators() -> [Integrator; 2] {
    [
        Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.8)),
        Integrator::Rk4(Default::default()),
    ]
}

#[test]
fn free_reference_with_a_free_frame_is_refused_naming_the_cause() {
    for beam in [Beam::Beam2, Beam::Beam3] {
        let body = beam_spec(beam, 4, Reference::Free, ALUMINIUM_BAR)
            .body()
            .unwrap();
        let (sys, _) = pendulum::scene(body).unwrap();
        for integrator in integrators() {
            let run = sys.simulate(0.01, 1e-3, &integrator, |_| ControlFlow::Continue(()));
            match run {
                Err(e @ Error::InvalidBody { .. }) => {
                    let msg = e.to_string();
                    println!("{beam:?}: {msg}");
                    assert!(msg.contains("`bar`"), "{msg}");
                    assert!(msg.contains("free reference"), "{msg}");
                    assert!(msg.contains("rigid-body motion R_x"), "{msg}");
                    assert!(msg.contains("mass matrix is singular"), "{msg}");
                }
                Err(other) => panic!("{beam:?}: unexpected error: {other}"),
                Ok(_) => panic!("{beam:?}: a singular mass matrix was integrated"),
            }
        }
    }
}

/// With its frame grounded the free-reference bar is a plain finite-element
/// beam: pinned at node 0 by a revolute joint it swings (small rotations:
/// 0.01 s; RK4 below its stability limit), and a clamped or pinned bar with a free frame still runs.
#[test]
fn free_reference_with_a_prescribed_frame_and_other_references_still_run() {
    for beam in [Beam::Beam2, Beam::Beam3] {
        let body = beam_spec(beam, 4, Reference::Free, ALUMINIUM_BAR)
            .body()
            .unwrap();
        let d = beam.scene_dim();
        let mut sys = System::with_dim(d);
        let b = sys.add_body("bar", body, Pose::identity(d)).unwrap();
        sys.ground(b).unwrap();
        let pin = sys.point(b, 0.0).unwrap();
        sys.revolute(Marker::ground(Vector3::zeros()), pin).unwrap();
        sys.set_gravity(Vector3::new(0.0, -9.81, 0.0)).unwrap();
        for integrator in integrators() {
            let (t_end, dt) = if matches!(integrator, Integrator::Rk4(_)) {
                (1e-3, 1e-6)
            } else {
                (0.01, 1e-3)
            };
            let s = sys
                .simulate(t_end, dt, &integrator, |_| ControlFlow::Continue(()))
                .unwrap_or_else(|e| panic!("{beam:?}: {e}"));
            assert!(s.last.q.iter().all(|x| x.is_finite()));
        }
        for reference in [Reference::Clamped, Reference::Pinned] {
            let body = beam_spec(beam, 4, reference, ALUMINIUM_BAR).body().unwrap();
            let (sys, _) = pendulum::scene(body).unwrap();
            sys.simulate(0.01, 1e-3, &integrators()[0], |_| ControlFlow::Continue(()))
                .unwrap_or_else(|e| panic!("{beam:?} {reference}: {e}"));
        }
    }
}
