//! Every reproducer of issue 8 that concerns the generator, as a named test:
//! hostile shape files give a clear error at `file:line:col` quickly, never a
//! panic, a stack overflow, a hang or silently wrong numbers; user strings
//! cannot leave a comment of the generated code. (The command-line
//! reproducers are in the root crate's `tests/cli.rs`.)

mod common;

use common::{coefficient_values, thread_cpu_time, Dense, TapeBody};
use ffr_codegen::builder::{resolve_shape, BodyConfig};
use ffr_codegen::limits::{self, check_literals};
use ffr_codegen::program::Expr;
use ffr_codegen::{
    emit_body_file, emit_kernels_file, generate_kernels, BodySpec, Builder, EmitOptions, Error,
    Formalism, KernelModel, KernelOptions, KernelSet, Params, Reference, Shape, Stiffening,
};
use std::time::{Duration, Instant};

/// The bar of the other tests with entry `S[x][u2]` replaced.
fn bar(entry: &str) -> String {
    format!(
        r#"name = "bar2"
dimension = 2
coordinates = [
  {{ name = "u1", node = 0, kind = "ux" }},
  {{ name = "v1", node = 0, kind = "uy" }},
  {{ name = "u2", node = 1, kind = "ux" }},
  {{ name = "v2", node = 1, kind = "uy" }},
]
[S]
x = ["1 - xi", "0", "{entry}", "0"]
y = ["0", "1 - xi", "0", "xi"]
"#
    )
}

/// Parse a bar whose `S[x][u2]` is `entry`; must fail within a second.
fn refused(entry: &str) -> String {
    let t = Instant::now();
    let r = Shape::parse(&bar(entry), "bad.toml");
    let took = t.elapsed();
    assert!(took < Duration::from_secs(1), "took {took:?}");
    match r {
        Ok(_) => panic!("`{entry}` was accepted"),
        Err(e) => {
            let e = e.to_string();
            assert!(e.starts_with("bad.toml:10:"), "{e}");
            e
        }
    }
}

const KRB: Params = Params {
    length: 8.0,
    rho: 2766.67,
    area: 7.2968e-5,
    iy: 8.2189e-9,
    iz: 8.2189e-9,
    e: 6.8952e10,
    g: 2.6e10,
    j: 1.6438e-8,
};

#[test]
fn nested_powers_do_not_wrap_exponents() {
    // Was: a negative m_ff diagonal with exit 0.
    let e = refused("((((xi^64)^64)^64)^64)^64");
    assert!(e.contains("`^64` would give degree 64 in xi"), "{e}");
    assert!(e.contains("MAX_SYMBOL_DEGREE"), "{e}");
    // Was: treated as 1.
    refused("(((((xi^64)^64)^64)^64)^64)^64");
    // Was: K_ff = −9.7e25.
    let e = refused("xi^(2^31)");
    assert!(e.contains("expected a whole number after `^`"), "{e}");
    let e = refused("xi^2147483648");
    assert!(e.contains("power too large: at most 64"), "{e}");
    let e = refused("xi^4294967297");
    assert!(e.contains("power too large"), "{e}");
}

#[test]
fn nested_power_is_refused_before_it_is_expanded() {
    // Was: minutes of work.
    let e = refused("((1+xi)^8)^64");
    assert!(e.contains("would give degree 512 in xi"), "{e}");
    assert!(e.contains("not expanded"), "{e}");
    let e = refused("(1+xi+eta+zeta+l)^2*(1+xi+eta+zeta+l)^2*(1+xi+eta+zeta+l)^2");
    assert!(e.contains("terms") || e.contains("degree"), "{e}");
    let e = refused("(2^64)^64*xi");
    assert!(e.contains("MAX_COEFFICIENT_BITS"), "{e}");
    let e = refused("(1 + 2*xi + 3*xi^2 + 4*eta + l + xi*l)^8");
    assert!(e.contains("would give"), "{e}");
}

#[test]
fn deep_nesting_does_not_overflow_the_stack() {
    // Was: a stack overflow (abort), in the CLI and inside rustc. Test
    // threads have small stacks, so this also shows the parser's stack use
    // is bounded.
    let deep = format!("{}xi{}", "(".repeat(8000), ")".repeat(8000));
    let e = refused(&deep);
    assert!(e.contains("parentheses nest more than 32 deep"), "{e}");
    let e = refused(&format!("{}xi", "(".repeat(100_000)));
    assert!(e.contains("MAX_NESTING_DEPTH"), "{e}");
    // 32 levels are fine.
    let ok = format!("{}xi{}", "(".repeat(32), ")".repeat(32));
    Shape::parse(&bar(&ok), "ok.toml").unwrap();
}

#[test]
fn fifty_thousand_unary_minus_signs_are_read_in_a_loop() {
    // Was: a stack overflow. Signs cost no recursion: an even number is `+`.
    let s = Shape::parse(&bar(&format!("{}xi", "-".repeat(50_000))), "minus.toml").unwrap();
    assert_eq!(s.rows[0][2].to_string(), "xi");
    let s = Shape::parse(&bar(&format!("{}xi", "-+".repeat(25_001))), "minus.toml").unwrap();
    assert_eq!(s.rows[0][2].to_string(), "-xi");
}

#[test]
fn huge_power_of_l_is_refused() {
    // Was: a stack overflow when the program builder hoisted l^32768.
    let e = refused("xi*((l^64)^64)^8");
    assert!(e.contains("degree 64 in l"), "{e}");
    assert!(e.contains("MAX_L_DEGREE"), "{e}");
    let e = refused("xi*l^3");
    assert!(e.contains("MAX_L_DEGREE"), "{e}");
}

#[test]
fn columns_have_the_units_of_their_coordinate() {
    // Found by fuzzing: `2*xi*eta*(1 - l)` mixes powers of l; its mass
    // cancels in floating point and m_ff[i][i] came out 0 at l = 1.
    let e = refused("xi*l");
    assert!(
        e.contains("the term `xi*l` has the factor l^1, but the shape of a translation coordinate (ux) is dimensionless"),
        "{e}"
    );
    let e = refused("2*xi*eta*(1 - l)");
    assert!(e.contains("translation coordinate (ux)"), "{e}");
    let rot = bar("xi")
        .replace(
            "name = \"u2\", node = 1, kind = \"ux\"",
            "name = \"t2\", node = 1, kind = \"rz\"",
        )
        .replace(
            "name = \"u1\", node = 0, kind = \"ux\"",
            "name = \"t1\", node = 0, kind = \"rz\"",
        );
    let e = Shape::parse(&rot, "rot.toml").unwrap_err().to_string();
    assert!(
        e.starts_with("rot.toml:10:7: S[x][t1] (`1 - xi`): the term `1` has no factor l"),
        "{e}"
    );
    let fixed = rot.replace(
        "x = [\"1 - xi\", \"0\", \"xi\"",
        "x = [\"l*(1 - xi)\", \"0\", \"l*xi\"",
    );
    Shape::parse(&fixed, "rot.toml").unwrap();
    assert!(
        e.contains(
            "every term of the shape of a rotation coordinate (rz) needs exactly one factor l"
        ),
        "{e}"
    );
}

#[test]
fn big_coefficients_are_refused_where_they_are_written() {
    // Was: inf/NaN in `invariants --json` (as null, exit 0) and `inf` literals
    // in emitted code. Such coefficients are beyond f64 anyway.
    let e = refused("1e300*1e300*xi");
    assert!(e.contains("number `1e300` needs about 1000 bits"), "{e}");
    let e = refused("1e30*1e30*xi");
    assert!(e.contains("this product has a coefficient of"), "{e}");
    let e = refused(&format!("{}*xi", "9".repeat(100_000)));
    assert!(e.contains("MAX_COEFFICIENT_BITS"), "{e}");
    // Leading and trailing zeros are not significant.
    let s = Shape::parse(
        &bar(&format!("{}1.5{}*xi", "0".repeat(5000), "0".repeat(5000))),
        "ok.toml",
    )
    .unwrap();
    assert_eq!(s.rows[0][2].to_string(), "3/2*xi");
}

#[test]
fn dev_zero_fails_at_once() {
    // Was: memory grew without bound.
    if !std::path::Path::new("/dev/zero").exists() {
        return;
    }
    let t = Instant::now();
    let e = Shape::resolve("/dev/zero", None).unwrap_err();
    assert!(t.elapsed() < Duration::from_secs(1));
    assert!(matches!(e, Error::Io { .. }), "{e}");
    let e = e.to_string();
    assert_eq!(
        e,
        "/dev/zero: is a character device, not a regular file: a shape file must be a regular file (not read)"
    );
}

#[test]
fn a_file_above_the_limit_and_a_fifo_are_refused_without_reading() {
    let dir = std::env::temp_dir().join(format!("ffr-regr-big-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let big = dir.join("big.toml");
    std::fs::write(&big, vec![b'#'; limits::MAX_SOURCE_BYTES as usize + 1]).unwrap();
    let e = Shape::resolve(big.to_str().unwrap(), None)
        .unwrap_err()
        .to_string();
    assert!(
        e.ends_with("big.toml: larger than 1048576 bytes, the limit for shape files (MAX_SOURCE_BYTES): not read"),
        "{e}"
    );
    // Exactly at the limit it is read (and is a comment, not a shape).
    std::fs::write(&big, vec![b'#'; limits::MAX_SOURCE_BYTES as usize]).unwrap();
    let e = Shape::resolve(big.to_str().unwrap(), None)
        .unwrap_err()
        .to_string();
    assert!(!e.contains("larger than"), "{e}");
    #[cfg(unix)]
    {
        // Was: opening a FIFO blocked until a writer came.
        let fifo = dir.join("fifo.toml");
        let ok = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success());
        if ok {
            let t = Instant::now();
            let e = limits::read_input(&fifo, 100, "scene file", "X").unwrap_err();
            assert!(t.elapsed() < Duration::from_secs(1));
            assert_eq!(
                e,
                "is a FIFO (named pipe), not a regular file: a scene file must be a regular file (not read)"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_directory_and_binary_data_are_clear_errors() {
    let dir = std::env::temp_dir().join(format!("ffr-regr-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("d.toml")).unwrap();
    let e = Shape::resolve(dir.join("d.toml").to_str().unwrap(), None).unwrap_err();
    assert!(
        e.to_string()
            .ends_with("d.toml: is a directory, not a shape file"),
        "{e}"
    );
    std::fs::write(dir.join("bin.toml"), b"name = \"a\"\n\xff\xfe").unwrap();
    let e = Shape::resolve(dir.join("bin.toml").to_str().unwrap(), None).unwrap_err();
    let e = e.to_string();
    assert!(
        e.contains("bin.toml:2:1: the file is not UTF-8 text (byte 0xff"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_truncated_shape_file_says_what_is_missing() {
    // Was: an empty message.
    let text = bar("xi");
    for cut in [text.len() - 3, text.len() - 20, 120, 60, 14] {
        let e = Shape::parse(&text[..cut], "cut.toml")
            .unwrap_err()
            .to_string();
        let message = e.splitn(4, ':').nth(3).unwrap_or("").trim();
        assert!(message.len() > 10, "cut at {cut}: `{e}`");
        assert!(!e.contains('\n'), "{e}");
    }
    let e = Shape::parse(&text[..text.len() - 3], "cut.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("truncated"), "{e}");
}

/// The kernels of `shape` for a free frame in its own scene.
fn kernels(shape: Shape, formalism: Formalism, stiffening: Stiffening) -> KernelSet {
    let options = KernelOptions::new()
        .formalism(formalism)
        .stiffening(stiffening);
    generate_kernels(&KernelModel::new(shape, options)).unwrap()
}

/// A shape whose name (or coordinate name) is `name`, as TOML.
fn named(name: &str, coordinate: &str) -> String {
    bar("xi")
        .replace("name = \"bar2\"", &format!("name = {name}"))
        .replace("name = \"u2\"", &format!("name = {coordinate}"))
}

#[test]
fn names_cannot_inject_code() {
    // Was: a name holding a newline plus Rust code became code in `ffr emit`
    // output and in Builder files; `\r` did the same.
    for evil in [
        r#""x\nfn main() { std::process::exit(3) }\n//""#,
        r#""x\rfn main() {}""#,
        r#""x */ fn f() {} /*""#,
        r#""x\u202e""#,
        r#""""#,
        r#""a b""#,
    ] {
        let e = Shape::parse(&named(evil, "\"u2\""), "evil.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("evil.toml:1:"), "{e}");
        assert!(e.contains("shape name"), "{e}");
        assert!(!e.contains('\n') && !e.contains('\r'), "{e}");
        let e = Shape::parse(&named("\"bar2\"", evil), "evil.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("evil.toml:6:"), "{e}");
        assert!(e.contains("coordinate name"), "{e}");
    }
    // The column points at the offending character.
    let e = Shape::parse(&named("\"ab\\ncd\"", "\"u2\""), "evil.toml").unwrap_err();
    assert!(e.to_string().starts_with("evil.toml:1:10:"), "{e}");
    let e = Shape::parse(
        &named(&format!("\"{}\"", "a".repeat(65)), "\"u2\""),
        "x.toml",
    )
    .unwrap_err();
    assert!(e.to_string().contains("at most 64"), "{e}");
}

#[test]
fn origin_and_type_name_cannot_leave_a_comment() {
    // A path with a newline (e.g. from a build script) reaches the header.
    let mut shape = Shape::resolve("beam2", None).unwrap();
    shape.origin = "shapes/\nfn main() {}\r\n/* */ \u{202e}.toml".into();
    let spec = BodySpec::new(shape.clone(), 1, Reference::Clamped).unwrap();
    let set = kernels(shape, Formalism::Consistent, Stiffening::Off);
    let body = emit_body_file(
        &set,
        &spec,
        &EmitOptions {
            type_name: "Arm".into(),
            ..EmitOptions::default()
        },
    );
    let kernels = emit_kernels_file(&set, "ArmKernels", "::ffr::runtime");
    for code in [body, kernels] {
        // In the header (`// Input: …`) and in the doc comment of the type.
        let escaped = "shapes/\\nfn main() {}\\r\\n/\\* *\\/ \\u{202e}.toml";
        assert!(code.matches(escaped).count() >= 2, "{code}");
        for line in code.lines() {
            assert!(!line.trim_start().starts_with("fn main"), "{line}");
        }
        let file = syn::parse_file(&code).unwrap();
        assert!(!file
            .items
            .iter()
            .any(|i| matches!(i, syn::Item::Fn(f) if f.sig.ident == "main")));
        assert!(!code.contains('\u{202e}') && !code.contains('\r'));
    }
}

#[test]
fn body_names_must_be_plain_identifiers() {
    for bad in ["fn", "Self", "_", "r#arm", "a\nb", "gen", "self_", "ärm"] {
        let e = Builder::new()
            .body(BodyConfig::new(bad, "beam2", 1, Reference::Clamped))
            .render()
            .unwrap_err();
        assert!(matches!(e, Error::Name(_)), "{bad}: {e}");
        assert!(e.to_string().starts_with("body name `"), "{e}");
        assert!(!e.to_string().contains('\n'), "{e}");
    }
}

#[test]
fn the_attribute_path_reads_shapes_through_the_same_limits() {
    // `#[flex_body]` resolves shapes with `resolve_shape`: the limits apply
    // there too, so rustc never sees unbounded recursion from a shape file.
    let dir = std::env::temp_dir().join(format!("ffr-attr-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("shapes")).unwrap();
    let deep = format!("{}xi{}", "(".repeat(8000), ")".repeat(8000));
    std::fs::write(dir.join("shapes/deep.toml"), bar(&deep)).unwrap();
    let e = resolve_shape("shapes/deep.toml", &dir)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("shapes/deep.toml:10:"), "{e}");
    assert!(e.contains("MAX_NESTING_DEPTH"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn non_finite_invariants_are_caught_where_they_are_computed() {
    // Was: `null` in `invariants --json` with exit 0 (--length 1e308). The
    // generator no longer evaluates invariants: it emits exact programs, and
    // numbers exist only where a body is built at given parameters. There
    // they are checked: the runtime's `KernelBody::new` refuses a coefficient
    // that is not finite, naming the parameters, and `ffr invariants` checks
    // every invariant (finite; a positive m_ff diagonal for the consistent
    // formalism), naming the quantity by its JSON key; the root crate's
    // `tests/cli.rs` pins both messages. Here: such parameters do give the
    // numbers those checks catch, in the exact invariants and in the
    // programs, and KRB's parameters do not.
    let shape = Shape::resolve("beam2", None).unwrap();
    let spec = BodySpec::new(shape.clone(), 2, Reference::Clamped).unwrap();
    let exact = spec.exact_invariants().unwrap();
    let set = kernels(shape, Formalism::Consistent, Stiffening::Off);
    let used = set.params_used();
    let labels: Vec<String> = spec.dofs().iter().map(ToString::to_string).collect();
    let rest = vec![0.0; spec.nf()];

    // KRB: every number finite and the m_ff diagonal positive, from the exact
    // polynomials and from the programs on tapes.
    limits::check_params(&KRB, &used).unwrap();
    let from_exact = Dense::from_exact(&exact, &KRB);
    let body = TapeBody::new(&set, 2, Reference::Clamped, KRB);
    let from_program = body.invariants();
    assert_eq!(from_exact.first_not_finite(), None);
    assert_eq!(from_program.first_not_finite(), None);
    let mass = body.mass(&rest);
    for (a, label) in labels.iter().enumerate() {
        assert!(from_exact.m_ff[(a, a)] > 0.0, "{label}");
        assert!(from_program.m_ff[(a, a)] > 0.0, "{label}");
        assert!(mass.m_ff[(a, a)] > 0.0, "{label}");
    }

    // --length 1e308 is a valid parameter, but the body's moments overflow
    // (Θ_xx = ρ A L³/3 is about 1e922; which overflows first depends on the
    // order of the products).
    let p = Params {
        length: 1e308,
        ..KRB
    };
    limits::check_params(&p, &used).unwrap();
    let big = Dense::from_exact(&exact, &p);
    let (quantity, v) = big.first_not_finite().unwrap();
    assert_eq!(v, f64::INFINITY, "{quantity}");
    assert_eq!(big.theta[(0, 0)], f64::INFINITY);
    // So does a coefficient (what `KernelBody::new` refuses, before any
    // kernel runs).
    let c = coefficient_values(&set, &p, p.elem_length(2));
    assert!(c.iter().any(|x| !x.is_finite()), "{c:?}");

    // Tiny parameters: a mass-matrix diagonal that underflows to zero, while
    // every coefficient stays finite (so the runtime builds the body; its
    // factorization then names the coordinate, `ffr invariants` says
    // `mff[0][0] (ux_1) is 0`).
    let p = Params {
        rho: 1e-300,
        area: 1e-300,
        iz: 1e-300,
        ..KRB
    };
    limits::check_params(&p, &used).unwrap();
    let tiny = Dense::from_exact(&exact, &p);
    assert_eq!(tiny.first_not_finite(), None);
    assert_eq!(labels[0], "ux_1");
    assert_eq!(tiny.m_ff[(0, 0)], 0.0);
    let body = TapeBody::new(&set, 2, Reference::Clamped, p);
    assert_eq!(body.mass(&rest).m_ff[(0, 0)], 0.0);
    assert_eq!(body.invariants().m_ff[(0, 0)], 0.0);
}

#[test]
fn non_finite_literals_are_refused_before_emission() {
    // Was: `inf * …` in emitted code, which does not compile. Within the
    // limits no literal can be beyond f64; the check is a net, tried here by
    // planting one in an output, in a temporary and in the coefficients.
    let fresh = || {
        kernels(
            Shape::resolve("beam2", None).unwrap(),
            Formalism::Consistent,
            Stiffening::FourthOrder,
        )
    };
    let times = |x: f64, e: &Expr| Expr::Mul(Box::new(Expr::Lit(x)), Box::new(e.clone()));
    check_literals(&fresh()).unwrap();

    let mut set = fresh();
    let last = set.element_invariants.outputs.len() - 1;
    let (target, e) = set.element_invariants.outputs[last].clone();
    set.element_invariants.outputs[last].1 = times(f64::INFINITY, &e);
    let e = check_literals(&set).unwrap_err();
    assert!(matches!(e, Error::Invalid { .. }), "{e}");
    let e = e.to_string();
    assert!(
        e.starts_with(&format!(
            "{target:?} has the coefficient inf in element_invariants: an exact coefficient"
        )),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");

    let mut set = fresh();
    let tangent = set.tangent.as_mut().unwrap();
    let (slot, e) = tangent.stmts[0].clone();
    tangent.stmts[0].1 = times(f64::NAN, &e);
    let name = tangent.names[slot as usize].clone();
    let e = check_literals(&set).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!(
            "the temporary `{name}` has the coefficient NaN in tangent:"
        )),
        "{e}"
    );

    let mut set = fresh();
    let (_, e) = set.coefficient_program.outputs[0].clone();
    set.coefficient_program.outputs[0].1 = times(f64::NEG_INFINITY, &e);
    let e = check_literals(&set).unwrap_err().to_string();
    assert!(
        e.contains("has the coefficient -inf in coefficients():"),
        "{e}"
    );
}

#[test]
fn physically_invalid_parameters_name_the_parameter() {
    use ffr_codegen::poly::Param;
    let set = kernels(
        Shape::resolve("beam2", None).unwrap(),
        Formalism::Consistent,
        Stiffening::Off,
    );
    let used = set.params_used();
    assert_eq!(
        used,
        [Param::Length, Param::Rho, Param::Area, Param::Iz, Param::E]
    );
    for (field, value, expect) in [
        (
            "length",
            0.0,
            "parameter `length` must be positive, found 0",
        ),
        ("rho", -1.0, "parameter `rho` must be positive, found -1"),
        ("area", 0.0, "parameter `area` must be positive"),
        ("e", -2.0, "parameter `e` must be positive"),
        ("iy", -1e-9, "parameter `iy` must not be negative"),
        (
            "iz",
            0.0,
            "parameter `iz` must be positive for this body, which uses it",
        ),
        ("g", -1.0, "parameter `g` must not be negative"),
        ("j", f64::NAN, "parameter `j` must be finite"),
    ] {
        let mut p = KRB;
        match field {
            "length" => p.length = value,
            "rho" => p.rho = value,
            "area" => p.area = value,
            "e" => p.e = value,
            "iy" => p.iy = value,
            "iz" => p.iz = value,
            "g" => p.g = value,
            _ => p.j = value,
        }
        let e = limits::check_params(&p, &used).unwrap_err();
        assert!(matches!(e, Error::Parameter { .. }), "{field}: {e}");
        let e = e.to_string();
        assert!(e.starts_with(expect), "{field}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
    // Zero is fine where the body does not use the parameter.
    let p = Params {
        iy: 0.0,
        g: 0.0,
        j: 0.0,
        ..KRB
    };
    limits::check_params(&p, &used).unwrap();
}

#[test]
fn lumped_formalism_after_a_big_exponent_is_an_error_not_a_panic() {
    // Was: a panic (exit 101) in `--formalism lumped` after an overflowed
    // exponent; the shape is now refused before.
    refused("((((xi^64)^64)^64)^64)^64");
    let s = Shape::parse(&bar("xi^8"), "ok.toml").unwrap();
    let spec = BodySpec::new(s.clone(), 3, Reference::Pinned)
        .unwrap()
        .with_formalism(Formalism::Lumped);
    spec.exact_invariants().unwrap();
    for stiffening in [Stiffening::SecondOrder, Stiffening::FourthOrder] {
        check_literals(&kernels(s.clone(), Formalism::Lumped, stiffening)).unwrap();
    }
}

#[test]
fn legitimate_shapes_are_far_inside_the_limits() {
    for name in ["beam2", "beam3"] {
        let s = Shape::resolve(name, None).unwrap();
        let terms: usize = s.rows.iter().flatten().map(|p| p.len()).sum();
        assert!(terms * 2 < limits::MAX_SHAPE_TERMS, "{name}: {terms}");
        for p in s.rows.iter().flatten() {
            for (m, c) in p.terms() {
                for &(sym, e) in m.factors() {
                    let max = if sym.to_string() == "l" {
                        limits::MAX_L_DEGREE
                    } else {
                        limits::MAX_SYMBOL_DEGREE
                    };
                    assert!(e as u32 * 2 <= max, "{name}: {m}");
                }
                assert!(c.numer().bits() * 4 < limits::MAX_COEFFICIENT_BITS);
            }
        }
    }
}

/// The most expensive shape the limits allow, roughly: 12 coordinates,
/// 3 terms per entry (108 in all, within `MAX_SHAPE_TERMS`), 38-digit
/// coefficients, degree up to 8 in `ξ`, `l` in the rotation columns.
fn costly_shape() -> String {
    let kinds = ["ux", "uy", "uz", "rx", "ry", "rz"];
    let mut coords = Vec::new();
    for node in 0..2 {
        for k in kinds {
            coords.push(format!(
                "{{ name = \"{k}{node}\", node = {node}, kind = \"{k}\" }}"
            ));
        }
    }
    let mut text = format!(
        "name = \"costly\"\ndimension = 3\ncoordinates = [{}]\n[S]\n",
        coords.join(", ")
    );
    let mut seed: u64 = 1;
    let mut digits = || {
        (0..38)
            .map(|i| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let d = (seed >> 60) % 10;
                char::from(b'0' + if i == 0 { 1 + d % 9 } else { d } as u8)
            })
            .collect::<String>()
    };
    for row in ["x", "y", "z"] {
        let mut entries = Vec::new();
        for a in 0..12u32 {
            let l = if a % 6 >= 3 { "*l" } else { "" };
            let terms: Vec<String> = (0..3u32)
                .map(|i| {
                    let xi = (a + 3 * i) % 9;
                    format!("{}e-38*xi^{xi}{l}", digits())
                })
                .collect();
            entries.push(format!("\"{}\"", terms.join(" + ")));
        }
        text += &format!("{row} = [{}]\n", entries.join(", "));
    }
    text
}

/// Longest the costly shape may take, for each stiffening model: exact
/// invariants of a 2-element body, every kernel program (free frame,
/// spatial scene), the literal check and emission, in CPU time of the test
/// thread. Measured (`cargo test -p ffr-codegen --test regressions costliest
/// -- --nocapture --test-threads 1`, three runs on a 2-core machine under a
/// load of 3–4): without stiffening 2.9–3.9 s (exact invariants 0.4–0.5 s,
/// kernels 2.2–3.0 s with 50 000 operations per call of all kernels,
/// emission 0.3 s of 0.9 MB), second order 3.6–3.8 s, fourth order
/// 4.5–5.4 s (kernels 3.2–4.1 s with 156 000 operations, emission 0.9 s of
/// 2.7 MB); `--release` is barely faster (3.1, 2.8–3.4, 3.5–4.6 s). The
/// limit is about four times the slowest: seconds, not minutes.
const COSTLY_LIMIT: Duration = Duration::from_secs(20);

/// Generate and emit everything for the costly shape with `stiffening`;
/// the CPU time of each step.
fn costly(stiffening: Stiffening) {
    let shape = Shape::parse(&costly_shape(), "costly.toml").unwrap();
    let terms: usize = shape.rows.iter().flatten().map(|p| p.len()).sum();
    assert!(terms <= limits::MAX_SHAPE_TERMS, "{terms}");
    let spec = BodySpec::new(shape.clone(), 2, Reference::Free).unwrap();
    let start = thread_cpu_time();
    spec.exact_invariants().unwrap();
    let invariants = thread_cpu_time();
    let set = kernels(shape, Formalism::Consistent, stiffening);
    check_literals(&set).unwrap();
    let generated = thread_cpu_time();
    let code = emit_body_file(&set, &spec, &EmitOptions::default());
    let end = thread_cpu_time();
    let ops: usize = set.programs().iter().map(|(_, p)| p.ops()).sum();
    println!(
        "costly shape, stiffening {stiffening}: {:?} CPU: exact invariants of 2 elements {:?}, kernels {:?} ({ops} operations, {} coefficients), emission {:?} ({} bytes)",
        end - start,
        invariants - start,
        generated - invariants,
        set.coefficients.len(),
        end - generated,
        code.len()
    );
    assert!(end - start < COSTLY_LIMIT, "{:?}", end - start);
}

#[test]
fn the_costliest_shape_within_the_limits_takes_seconds_not_minutes() {
    costly(Stiffening::Off);
}

/// Stiffening no longer expands the body's energy (it is written in element
/// scalars): the costly shape with stiffening costs about as much as without.
#[test]
fn the_costliest_shape_with_second_order_stiffening() {
    costly(Stiffening::SecondOrder);
}

#[test]
fn the_costliest_shape_with_fourth_order_stiffening() {
    costly(Stiffening::FourthOrder);
}
