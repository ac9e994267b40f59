fn main() {
    let a: Vec<String> = std::env::args().collect();
    let mut cfg = ffr::scenes::spin_up::SpinUp::new(a.get(1).map_or(4.0, |s| s.parse().unwrap()));
    cfg.elements = a.get(2).map_or(8, |s| s.parse().unwrap());
    cfg.dt = a.get(3).map_or(0.01, |s| s.parse().unwrap());
    if let Some(s) = a.get(4) {
        cfg.stiffening = s.parse().unwrap();
    }
    cfg.spatial = a.get(5).is_some_and(|s| s == "spatial");
    let r = ffr::scenes::spin_up::run(&cfg).unwrap();
    println!(
        "{:?} wall {:.3}s steps {} newton {} jac {} kernels {}",
        r.min_transverse(),
        r.wall,
        r.steps,
        r.newton_iterations,
        r.jacobians,
        r.kernels
    );
    if let Some(d) = r.diverged {
        println!("diverged: {d:?}");
    }
}
#[allow(dead_code)]
fn check() {}
