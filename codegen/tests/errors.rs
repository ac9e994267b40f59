//! Bad input: every error names the problem and where it is; nothing panics.

use ffr_codegen::{BodySpec, Error, Reference, Shape};

const GOOD: &str = r#"name = "bar2"
dimension = 2
coordinates = [
  { name = "u1", node = 0, kind = "ux" },
  { name = "v1", node = 0, kind = "uy" },
  { name = "u2", node = 1, kind = "ux" },
  { name = "v2", node = 1, kind = "uy" },
]
[S]
x = ["1 - xi", "0", "xi", "0"]
y = ["0", "1 - xi", "0", "xi"]
"#;

/// Parse `GOOD` with `from` replaced by `to`; return the error text.
fn err_with(from: &str, to: &str) -> String {
    assert!(
        GOOD.contains(from),
        "test setup: `{from}` not in the sample"
    );
    let text = GOOD.replacen(from, to, 1);
    match Shape::parse(&text, "bar2.toml") {
        Ok(_) => panic!("`{to}` was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_sample_is_valid() {
    let s = Shape::parse(GOOD, "bar2.toml").unwrap();
    assert_eq!(s.n_elem(), 4);
    assert_eq!(s.dimension, 2);
}

#[test]
fn toml_syntax_error_has_file_line_column() {
    let e = err_with("dimension = 2", "dimension = = 2");
    assert!(e.starts_with("bar2.toml:2:"), "{e}");
}

#[test]
fn missing_and_unknown_fields() {
    let e = err_with("dimension = 2\n", "");
    assert!(e.contains("missing field `dimension`"), "{e}");
    let e = err_with("dimension = 2", "dimension = 2\ncolour = 3");
    assert!(e.starts_with("bar2.toml:3:1"), "{e}");
    assert!(e.contains("unknown field `colour`"), "{e}");
}

#[test]
fn wrong_row_count() {
    let e = err_with("dimension = 2", "dimension = 3");
    assert!(e.contains("row `z` of S is missing"), "{e}");
    assert!(e.starts_with("bar2.toml:9:1"), "{e}");
    let e = err_with("y = [", "z = [\"0\", \"0\", \"0\", \"0\"]\ny = [");
    assert!(
        e.contains("unexpected row `z`: a shape of dimension 2 has rows x, y"),
        "{e}"
    );
    assert!(e.starts_with("bar2.toml:11:1"), "{e}");
}

#[test]
fn wrong_number_of_entries() {
    let e = err_with(
        r#"x = ["1 - xi", "0", "xi", "0"]"#,
        r#"x = ["1 - xi", "0", "xi"]"#,
    );
    assert!(e.contains("row `x` has 3 entries, expected 4"), "{e}");
    assert!(e.starts_with("bar2.toml:10:5"), "{e}");
}

#[test]
fn expression_errors_point_into_the_string() {
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "2*x""#);
    // Line 10: x = ["1 - xi", "0", "2*x", "0"]: the `x` is at column 24.
    assert!(e.starts_with("bar2.toml:10:24:"), "{e}");
    assert!(
        e.contains("S[x][u2] (`2*x`): unknown symbol `x`: expected one of xi, eta, zeta, l"),
        "{e}"
    );
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "sin(xi)""#);
    assert!(e.contains("`sin(…)` is not polynomial"), "{e}");
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "1/xi""#);
    assert!(e.contains("division by `xi` is not polynomial"), "{e}");
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "xi^-2""#);
    assert!(e.contains("negative powers are not polynomial"), "{e}");
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "xi^(1/2)""#);
    assert!(e.contains("expected a whole number after `^`"), "{e}");
}

#[test]
fn section_moment_the_model_does_not_have_names_the_term() {
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "xi + eta^3""#);
    assert!(
        e.contains("the term `eta^3` needs the section moment ∫y^6 dA"),
        "{e}"
    );
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "xi*eta^2""#);
    assert!(
        e.contains("the term `xi*eta^2` needs the section moment ∫y^4 dA"),
        "{e}"
    );
    let e = err_with(r#""1 - xi", "0", "xi""#, r#""1 - xi", "0", "zeta""#);
    assert!(
        e.contains("uses zeta, which a planar shape does not have"),
        "{e}"
    );
}

#[test]
fn coordinate_errors() {
    let e = err_with(
        r#"kind = "ux" },
  { name = "v1""#,
        r#"kind = "uw" },
  { name = "v1""#,
    );
    assert!(
        e.contains("unknown kind `uw`: expected one of ux, uy, uz, rx, ry, rz"),
        "{e}"
    );
    assert!(e.starts_with("bar2.toml:4:35"), "{e}");
    let e = err_with(r#"name = "u2", node = 1"#, r#"name = "u2", node = 2"#);
    assert!(
        e.contains("node must be 0 (element start) or 1 (element end), found 2"),
        "{e}"
    );
    let e = err_with(
        r#"name = "v1", node = 0, kind = "uy""#,
        r#"name = "v1", node = 0, kind = "rx""#,
    );
    assert!(
        e.contains("kind `rx` does not exist in a planar shape"),
        "{e}"
    );
    let e = err_with(r#"name = "v2""#, r#"name = "v1""#);
    assert!(e.contains("coordinate `v1` appears twice"), "{e}");
    let e = err_with(
        r#"name = "v2", node = 1, kind = "uy""#,
        r#"name = "v2", node = 1, kind = "rz""#,
    );
    assert!(e.contains("both ends need the same kinds"), "{e}");
    let e = err_with("dimension = 2", "dimension = 4");
    assert!(
        e.contains("dimension must be 2 (planar) or 3 (spatial), found 4"),
        "{e}"
    );
}

#[test]
fn unknown_shape_missing_file_and_bad_body() {
    let e = Shape::resolve("beam4", None).unwrap_err().to_string();
    assert_eq!(
        e,
        "unknown shape `beam4`: expected one of beam2, beam3, or a path to a .toml shape file"
    );
    let e = Shape::resolve("no/such/shape.toml", None).unwrap_err();
    assert!(matches!(e, Error::Io { .. }), "{e}");
    assert!(e.to_string().starts_with("no/such/shape.toml: "), "{e}");
    let shape = Shape::resolve("beam2", None).unwrap();
    let e = BodySpec::new(shape.clone(), 0, Reference::Clamped).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid body: elements must be at least 1, found 0"
    );
    let e = BodySpec::new(shape, 100_000, Reference::Clamped).unwrap_err();
    assert!(e.to_string().contains("at most 256"), "{e}");
    let e = "hinged".parse::<Reference>().unwrap_err().to_string();
    assert!(e.contains("expected clamped, pinned or free"), "{e}");
}

/// A scene dimension other than 2 or 3 is refused with an error when the
/// kernels are generated, not a panic in the build script; a later valid
/// dimension replaces it.
#[test]
fn scene_dimension_4_is_refused() {
    use ffr_codegen::builder::{Builder, KernelConfig};
    let base = std::path::Path::new(".");
    let e = KernelConfig::new("k", "beam2")
        .scene_dim(4)
        .model(base)
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "invalid body: kernels `k`: the scene dimension must be 2 or 3, found 4"
    );
    let e = Builder::new()
        .kernels(KernelConfig::new("k", "beam2").scene_dim(4))
        .render()
        .unwrap_err()
        .to_string();
    assert!(e.contains("found 4"), "{e}");
    assert!(KernelConfig::new("k", "beam2")
        .scene_dim(4)
        .scene_dim(3)
        .model(base)
        .is_ok());
}

#[test]
fn kernel_options_that_make_no_sense() {
    use ffr_codegen::builder::KernelConfig;
    use ffr_codegen::{Formalism, Stiffening};
    let base = std::path::Path::new(".");
    let e = KernelConfig::new("k", "beam3")
        .scene_dim(2)
        .model(base)
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "invalid body: shape `beam3` is spatial: it needs a spatial scene (scene dimension 3)"
    );
    assert!(KernelConfig::new("k", "beam2")
        .scene_dim(3)
        .model(base)
        .is_ok());
    let e = "quadratic".parse::<Stiffening>().unwrap_err();
    assert_eq!(
        e,
        "unknown stiffening `quadratic`: expected on, off, second-order or fourth-order"
    );
    assert_eq!("on".parse::<Stiffening>(), Ok(Stiffening::FourthOrder));
    assert_eq!("true".parse::<Stiffening>(), Ok(Stiffening::FourthOrder));
    assert_eq!("off".parse::<Stiffening>(), Ok(Stiffening::Off));
    assert_eq!(
        "second-order".parse::<Stiffening>(),
        Ok(Stiffening::SecondOrder)
    );
    let e = "diagonal".parse::<Formalism>().unwrap_err();
    assert_eq!(
        e,
        "unknown formalism `diagonal`: expected consistent or lumped"
    );
}

/// A modal body in a build script (`BodyConfig::modes`): bad parameters,
/// too many modes, a bad boundary node or a section table (not yet
/// supported) are errors that
/// name the body, not panics; a good one renders `<Name>Modal`.
#[test]
#[cfg(feature = "modal")]
fn modal_bodies_in_a_build_script() {
    use ffr_codegen::{BodyConfig, Builder, ModalSettings, Params};
    let p = Params {
        length: 2.0,
        rho: 2700.0,
        area: 3e-4,
        iy: 0.0,
        iz: 4e-9,
        e: 7e10,
        g: 0.0,
        j: 0.0,
    };
    let render = |p: Params, s: ModalSettings, sections: bool| {
        let shape = if sections { "beam3" } else { "beam2" };
        let mut b = BodyConfig::new("link", shape, 2, Reference::Clamped).modes(p, s);
        if sections {
            b = b.sections("../tests/data/taper.csv");
        }
        Builder::new()
            .manifest_dir(env!("CARGO_MANIFEST_DIR"))
            .body(b)
            .render()
            .map(|f| f[0].contents.clone())
            .map_err(|e| e.to_string())
    };
    let ok = render(p, ModalSettings::truncation(2), false).unwrap();
    assert!(ok.contains("pub struct LinkModal;"), "{ok}");
    let cases = [
        (
            Params { e: 0.0, ..p },
            ModalSettings::truncation(2),
            "body `link`: parameter `e` must be positive",
        ),
        (
            p,
            ModalSettings::truncation(7),
            "body `link`: modes must be between 1 and 6",
        ),
        (
            p,
            ModalSettings {
                boundary: vec![5],
                ..ModalSettings::truncation(1)
            },
            "body `link`: boundary node 5 out of range",
        ),
    ];
    for (p, s, msg) in cases {
        let e = render(p, s, false).unwrap_err();
        assert!(e.contains(msg), "{e}");
    }
    let e = render(p, ModalSettings::truncation(2), true).unwrap_err();
    assert!(
        e.contains("body `link`: a modal body of a section table cannot be generated yet"),
        "{e}"
    );
}
