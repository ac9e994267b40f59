use ffr::runtime::{Assembly, GeneralizedAlpha, Integrator};
#[test]
fn dbg() {
    for f in ["/tmp/t4.toml", "/tmp/a3.toml"] {
        let scene = ffr::scene::load(std::path::Path::new(f)).unwrap();
        let sys = &scene.system;
        let h = 1e-4;
        let mut state = None;
        sys.simulate(
            0.05,
            h,
            &Integrator::GeneralizedAlpha(GeneralizedAlpha::default()),
            |v| {
                state = Some(v.state.clone());
                std::ops::ControlFlow::Continue(())
            },
        )
        .unwrap();
        let s = state.unwrap();
        let (am, af, gamma, beta) = GeneralizedAlpha::default().coefficients();
        let bp = (1.0 - am) / ((1.0 - af) * beta * h * h);
        let gp = gamma / (beta * h);
        let mut asm = Assembly::new(sys).unwrap();
        let lam: Vec<f64> = s.lambda.iter().map(|l| l / bp).collect();
        let (err, col) = asm.iteration_matrix_error(s.t, &s.q, &s.v, &s.a, &lam, bp, gp);
        println!("{f}: {err:e} at {col} (n = {})", s.q.len());
    }
}
