//! Issue 7, "Generated code that scales": a fixed-mesh body file is its
//! element kernels plus a coordinate list, so it does not grow with the
//! number of elements except for that list, and the fourth-order stiffening
//! makes it at most twice as large as without.

use ffr_codegen::builder::{BodyConfig, Builder};
use ffr_codegen::{Reference, Stiffening};

fn body_file(shape: &str, n: usize, s: Stiffening) -> usize {
    let files = Builder::new()
        .runtime_path("::ffr_runtime")
        .body(BodyConfig::new("arm", shape, n, Reference::Clamped).stiffening(s))
        .render()
        .unwrap();
    let lines = files[0].contents.lines().count();
    if n == 32 {
        eprintln!(
            "{shape} N=32 {s}: {} bytes, {lines} lines",
            files[0].contents.len()
        );
    }
    files[0].contents.len()
}

#[test]
fn body_files_grow_only_by_their_coordinate_list_and_stiffening_at_most_doubles_them() {
    for shape in ["beam2", "beam3"] {
        let mut rows = Vec::new();
        for s in [
            Stiffening::Off,
            Stiffening::SecondOrder,
            Stiffening::FourthOrder,
        ] {
            let base = body_file(shape, 1, s);
            for n in [1, 8, 32, 128] {
                let size = body_file(shape, n, s);
                // Everything but the coordinate list (header and `DOFS`) is
                // the same whatever N: at most 40 bytes per coordinate.
                let coords = if shape == "beam2" { 3 } else { 6 } * n;
                assert!(
                    size <= base + 40 * coords,
                    "{shape} {s} N={n}: {size} bytes against {base} at N=1"
                );
                rows.push((s, n, size));
            }
        }
        for n in [1, 8, 32, 128] {
            let size = |s| rows.iter().find(|r| r.0 == s && r.1 == n).unwrap().2;
            let (off, second, fourth) = (
                size(Stiffening::Off),
                size(Stiffening::SecondOrder),
                size(Stiffening::FourthOrder),
            );
            eprintln!(
                "{shape} N={n}: off {off} B, second-order {second} B ({:.2}×), fourth-order {fourth} B ({:.2}×)",
                second as f64 / off as f64,
                fourth as f64 / off as f64
            );
            assert!(fourth <= 2 * off, "{shape} N={n}: {fourth} > 2 × {off}");
            assert!(second <= 2 * off, "{shape} N={n}: {second} > 2 × {off}");
        }
    }
}
