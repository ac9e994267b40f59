//! The analytic generalized-α iteration matrix against central differences
//! of the residual, for generated bodies in the built-in scenes' settings.

mod common;
use ffr::runtime::{Assembly, GeneralizedAlpha};
use ffr_cli::benchmarks::spin_up::{self, SpinUp};

#[test]
fn spin_up_iteration_matrix_matches_differences() {
    for stiffening in ["off", "second-order", "fourth-order"] {
        for spatial in [false, true] {
            let mut cfg = SpinUp::new(4.0);
            cfg.elements = 3;
            cfg.spatial = spatial;
            cfg.stiffening = stiffening.parse().unwrap();
            cfg.t_end = 6.0;
            let (sys, _) = spin_up::system(&cfg).unwrap();
            // A state along the run.
            let mut state = None;
            sys.simulate(cfg.t_end, 0.01, &cfg.integrator, |v| {
                state = Some(v.state.clone());
                std::ops::ControlFlow::Continue(())
            })
            .unwrap();
            let s = state.unwrap();
            let (am, af, gamma, beta) = GeneralizedAlpha::default().coefficients();
            let h = 0.01;
            let bp = (1.0 - am) / ((1.0 - af) * beta * h * h);
            let gp = gamma / (beta * h);
            let mut asm = Assembly::new(&sys).unwrap();
            let lam: Vec<f64> = s.lambda.iter().map(|l| l / bp).collect();
            let (err, col) = asm.iteration_matrix_error(s.t, &s.q, &s.v, &s.a, &lam, bp, gp);
            println!("{stiffening} spatial={spatial}: {err:e} at {col}");
            assert!(
                err < 1e-6,
                "{stiffening} spatial={spatial}: {err:e} at column {col}"
            );
        }
    }
}

/// Joints (revolute, driven angle) between flexible and rigid bodies, a
/// spring–damper and a point force at beam points, gravity: the iteration
/// matrix with constraint Hessians and force-element derivatives.
#[test]
fn mechanism_iteration_matrix_matches_differences() {
    for dim in [2, 3] {
        let sys = common::mechanism(dim);
        let (err, col) = common::iteration_matrix_error(&sys, 0.2);
        println!("mechanism dim {dim}: {err:e} at {col}");
        assert!(err < 1e-5, "dim {dim}: {err:e} at column {col}");
    }
}
