//! The analytic generalized-α iteration matrix against central differences
//! of the residual, for generated bodies in the built-in scenes' settings.

use ffr::runtime::{Assembly, GeneralizedAlpha};
use ffr::scenes::spin_up::{self, SpinUp};

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

#[test]
fn residual_of_the_tangent_kernels_equals_the_residual() {
    let mut cfg = SpinUp::new(4.0);
    cfg.elements = 8;
    cfg.t_end = 3.0;
    let (sys, _) = spin_up::system(&cfg).unwrap();
    let mut state = None;
    sys.simulate(cfg.t_end, 0.01, &cfg.integrator, |v| {
        state = Some(v.state.clone());
        std::ops::ControlFlow::Continue(())
    })
    .unwrap();
    let s = state.unwrap();
    let mut asm = Assembly::new(&sys).unwrap();
    let n = s.q.len() + s.lambda.len();
    let (mut r1, mut r2) = (vec![0.0; n], vec![0.0; n]);
    asm.residual(s.t, &s.q, &s.v, &s.a, &s.lambda, &mut r1);
    asm.jacobian(s.t, &s.q, &s.v, &s.a, &s.lambda, 3e4, 200.0, &mut r2);
    for i in 0..n {
        println!("{i}: {:e} {:e} diff {:e}", r1[i], r2[i], r1[i] - r2[i]);
    }
}
