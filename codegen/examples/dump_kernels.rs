//! Print a generated kernel file: `cargo run -p ffr-codegen --example dump_kernels -- beam2 fourth-order 2 free`.
use ffr_codegen::{generate_kernels, FrameModel, KernelModel, KernelOptions, SceneDim, Shape};
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let shape = Shape::resolve(&a[1], None).unwrap();
    let stiff = a[2].parse().unwrap();
    let scene_dim: usize = a[3].parse().unwrap();
    let free = a[4] == "free";
    let t = std::time::Instant::now();
    let options = KernelOptions::new()
        .stiffening(stiff)
        .scene(SceneDim::from_dim(scene_dim).expect("scene dimension 2 or 3"))
        .frame(FrameModel::from_flags(free, false));
    let set = generate_kernels(&KernelModel::new(shape, options)).unwrap();
    let gen = t.elapsed();
    let text = ffr_codegen::emit_kernels_file(&set, "K", "::ffr_runtime");
    eprintln!(
        "generated in {gen:?}, {} bytes, {} lines",
        text.len(),
        text.lines().count()
    );
    println!("{text}");
}
