fn main() {
    let a: Vec<String> = std::env::args().collect();
    let omega: f64 = a.get(1).map_or(4.0, |s| s.parse().unwrap());
    let reference = ffr::reference::spin_up(omega).unwrap();
    for el in [4usize, 8, 16, 32] {
        for dt in [0.01, 0.005, 0.002, 0.001] {
            let mut cfg = ffr::scenes::spin_up::SpinUp::new(omega);
            cfg.elements = el;
            cfg.dt = dt;
            if let Some(s) = a.get(2) {
                cfg.stiffening = s.parse().unwrap();
            }
            let mut best = f64::INFINITY;
            let mut r = None;
            for _ in 0..3 {
                let t0 = std::time::Instant::now();
                let rr = ffr::scenes::spin_up::run(&cfg).unwrap();
                best = best.min(t0.elapsed().as_secs_f64());
                r = Some(rr);
            }
            let r = r.unwrap();
            let (e, _) = reference
                .error("tip_transverse", &r.t, &r.tip_transverse, 20.0)
                .unwrap();
            println!(
                "{el:3} {dt:7} err {e:.3e} time {best:.4}s newton/step {:.2} jac/step {:.2}",
                r.newton_iterations as f64 / r.steps as f64,
                r.jacobians as f64 / r.steps as f64
            );
        }
    }
}
