fn main() {
    let a: Vec<String> = std::env::args().collect();
    let scene = ffr::scene::load(std::path::Path::new(&a[1])).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    println!("notes: {:?} kernels {:?}", scene.notes, scene.kernels);
    let r = ffr::scene::run(&scene).unwrap();
    let col = &r.columns[1];
    let (i, m) =
        col.iter().enumerate().fold(
            (0, f64::INFINITY),
            |(bi, b), (i, &v)| if v < b { (i, v) } else { (bi, b) },
        );
    println!("min tip_transverse {m} at {} ; wall {:.4}", r.t[i], r.wall);
    let cfg = ffr::scenes::spin_up::SpinUp::new(4.0);
    let s = ffr::scenes::spin_up::run(&cfg).unwrap();
    let same = s.tip_transverse == r.columns[1] && s.tip_axial == r.columns[0];
    println!(
        "spin-up command peak {:?}; bit-identical: {same}",
        s.min_transverse()
    );
}
