include!("ffr_bodies.rs");

fn main() {
    // The builder prints `cargo:rerun-if-changed` for every shape file; list
    // the build inputs of its own as well.
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=ffr_bodies.rs");
    if let Err(e) = ffr_bodies().compile() {
        panic!("ffr-codegen: {e}");
    }
}
