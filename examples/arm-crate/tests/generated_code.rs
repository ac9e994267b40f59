//! Review changes of the generated code with `cargo insta review`: these
//! snapshots hold exactly what `build.rs` writes (the body list is shared
//! through `ffr_bodies.rs`). When ffr or a shape file changes, the test fails
//! and shows the diff; accept it with `cargo insta review`.

include!("../ffr_bodies.rs");

#[test]
fn generated_code() {
    let files = ffr_bodies()
        .manifest_dir(env!("CARGO_MANIFEST_DIR"))
        .render()
        .unwrap_or_else(|e| panic!("{e}"));
    for f in files {
        // The 8-element arm is ~150 kB of code; this example keeps only the
        // small bodies under review. A crate of your own would keep them all.
        if f.name == "arm" {
            continue;
        }
        // A compiled scene repeats kernels the codegen snapshots pin; its
        // header (bodies, specialization, costs, what was left out) is
        // what this crate reviews.
        if f.name == "two_links" {
            let header = f.contents.split("\n\n").next().unwrap_or_default();
            insta::assert_snapshot!("two_links.header", header);
            // And the scene as data: what `TwoLinksScene::load()` builds.
            let at = f
                .contents
                .find("/// The element kernels of the scene's flexible bodies.")
                .expect("the scene items follow the kernels");
            insta::assert_snapshot!("two_links.scene", &f.contents[at..]);
            continue;
        }
        // Bodies run as segments: the header (which kernel sets, for
        // which segments) and the kernel provider (which names run which
        // kernels, which reduction each modal segment gets).
        if f.name.ends_with("segments") {
            let header = f.contents.split("\n\n").next().unwrap_or_default();
            insta::assert_snapshot!(format!("{}.header", f.name), header);
            let from = f
                .contents
                .find("/// The element kernels of the scene's flexible bodies.")
                .expect("the provider follows the kernels");
            let to = f.contents[from..]
                .find("/// The scene `")
                .expect("the scene type follows the provider");
            insta::assert_snapshot!(format!("{}.provider", f.name), &f.contents[from..from + to]);
            continue;
        }
        // The built-in scenes are checked against the files they come from
        // (tests/compiled_scene.rs), not reviewed here.
        if f.name.starts_with("builtin_") {
            continue;
        }
        insta::assert_snapshot!(f.file_name.clone(), f.contents);
    }
}
