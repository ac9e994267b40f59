//! Section tables in scene files (`sections = "…csv"` or an inline array):
//! the material and resultant forms, the NREL 5-MW blade as shipped, and a
//! located error for every kind of bad table.

#![cfg(feature = "scene")]

use ffr_codegen::scene::resolve_str;
use ffr_spec::scene::{BodyKind, SectionTable};
use std::path::{Path, PathBuf};

fn scene(sections: &str) -> String {
    format!(
        "dimension = 3\nt_end = 1.0\ndt = 0.01\n\n[bodies.blade]\nshape = \"beam3\"\nelements = 4\nsections = {sections}\n"
    )
}

fn table(text: &str, dir: &Path) -> Result<SectionTable, String> {
    let spec = resolve_str(text, "s.toml", dir).map_err(|e| e.to_string())?;
    match &spec.bodies[0].kind {
        BodyKind::Flexible(f) => {
            assert_eq!(
                f.params.length,
                f.sections.as_ref().unwrap().stations.last().unwrap().x
            );
            Ok(f.sections.clone().expect("a section table"))
        }
        _ => panic!("flexible"),
    }
}

fn temp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ffr-sections-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn the_nrel_5mw_blade_reads_as_shipped() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/data");
    let t = table(&scene("\"nrel5mw_blade.csv\""), &data).unwrap();
    assert_eq!(t.stations.len(), 49);
    assert_eq!(t.stations[0].x, 0.0);
    assert_eq!(t.stations[48].x, 61.5);
    // Independent of the reader: the CSV's own numbers, parsed here.
    let csv = std::fs::read_to_string(data.join("nrel5mw_blade.csv")).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for (row, st) in lines.zip(&t.stations) {
        let v: Vec<f64> = row.split(',').map(|x| x.trim().parse().unwrap()).collect();
        let col = |k: &str| v[header.iter().position(|h| *h == k).unwrap()];
        assert_eq!(st.x, col("x"));
        assert_eq!(st.mass, col("mass"));
        assert_eq!(st.ei_y, col("ei_y"));
        assert_eq!(st.ei_z, col("ei_z"));
        assert_eq!(st.twist, col("twist"));
        assert_eq!(st.rho_j, col("rho_iy") + col("rho_iz"));
    }
    // The mass: the exact integral of the piecewise-linear mass per length
    // (trapezoidal rule, exact here) is 17 608.83 kg (bench/blade/README.md).
    let m: f64 = t
        .stations
        .windows(2)
        .map(|w| 0.5 * (w[0].mass + w[1].mass) * (w[1].x - w[0].x))
        .sum();
    assert!((m - 17_608.83).abs() < 0.01, "{m}");
}

#[test]
fn material_and_inline_forms() {
    let dir = temp("forms");
    std::fs::write(
        dir.join("m.csv"),
        "# a tapered steel bar\nx, rho, area, iy, iz, e, g, j\n0, 7850, 2e-4, 2e-9, 3e-9, 2e11, 8e10, 4e-9\n2.0, 7850, 1e-4, 1e-9, 1.5e-9, 2e11, 8e10, 2e-9\n",
    )
    .unwrap();
    let t = table(&scene("\"m.csv\""), &dir).unwrap();
    let s = t.stations[1];
    assert_eq!(s.mass, 7850.0 * 1e-4);
    assert_eq!(s.ea, 2e11 * 1e-4);
    assert_eq!(s.ei_y, 2e11 * 1e-9);
    assert_eq!(s.ei_z, 2e11 * 1.5e-9);
    assert_eq!(s.gj, 8e10 * 2e-9);
    assert_eq!(s.rho_j, 7850.0 * (1e-9 + 1.5e-9));
    assert_eq!(
        t.at.to_string(),
        format!("{}:1:1", dir.join("m.csv").display())
    );
    let inline = table(
        &scene("[{ x = 0.0, mass = 2.0, ea = 1e6, ei_y = 10.0, ei_z = 20.0, gj = 5.0, rho_iy = 0.0, rho_iz = 0.0, rho_j = 1e-3, twist = 0.1 },\n  { x = 1.5, mass = 1.0, ea = 1e6, ei_y = 5.0, ei_z = 10.0, gj = 5.0, rho_iy = 0.0, rho_iz = 0.0, rho_j = 1e-3, twist = 0.2 }]"),
        &dir,
    )
    .unwrap();
    assert_eq!(inline.stations.len(), 2);
    assert_eq!(inline.stations[1].twist, 0.2);
    assert_eq!(inline.stations[0].rho_j, 1e-3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_tables_are_located_errors() {
    let dir = temp("bad");
    let head = "x,mass,ea,ei_y,ei_z,gj,rho_iy,rho_iz\n";
    let ok_row = "0,1,1e6,1,1,1,0,0\n";
    for (body, says, line) in [
        (
            format!("{head}{ok_row}1,1,1e6,1,1,oops,0,0\n"),
            "column `gj` must be a finite number, found `oops`",
            3,
        ),
        (
            format!("{head}{ok_row}0,1,1e6,1,1,1,0,0\n"),
            "must increase strictly",
            3,
        ),
        (
            format!("{head}1,1,1e6,1,1,1,0,0\n2,1,1e6,1,1,1,0,0\n"),
            "the first station is at x = 1.0",
            2,
        ),
        (
            format!("{head}{ok_row}1,-1,1e6,1,1,1,0,0\n"),
            "`mass` must be > 0",
            3,
        ),
        (
            format!("{head}{ok_row}1,1,1e6,1,1\n"),
            "a row has 5 fields, the header 8",
            3,
        ),
        (format!("{head}{ok_row}"), "at least two stations", 1),
        (
            "x,mass,ea,ei_y,ei_z,gj,rho_iy\n0,1,1,1,1,1,0\n1,1,1,1,1,1,0\n".to_string(),
            "no column `rho_iz`",
            1,
        ),
        (
            "x,mass,rho,ea\n0,1,1,1\n1,1,1,1\n".to_string(),
            "mix the material form",
            1,
        ),
        (
            "x,mass,ea,ei_y,ei_z,gj,rho_iy,rho_iz,colour\n".to_string(),
            "unknown section column `colour`",
            1,
        ),
        ("x,x\n0,0\n".to_string(), "column `x` appears twice", 1),
    ] {
        std::fs::write(dir.join("t.csv"), &body).unwrap();
        let e = table(&scene("\"t.csv\""), &dir)
            .err()
            .unwrap_or_else(|| panic!("{body} accepted"));
        assert!(e.contains(says), "{body}: {e}");
        assert!(
            e.starts_with(&format!("{}:{line}:", dir.join("t.csv").display())),
            "{body}: {e}"
        );
    }
    // Column of a bad field.
    std::fs::write(
        dir.join("t.csv"),
        format!("{head}{ok_row}1,1,1e6,1,1,oops,0,0\n"),
    )
    .unwrap();
    let e = table(&scene("\"t.csv\""), &dir).unwrap_err();
    assert!(e.contains(":3:13:"), "{e}");
    // In the scene file.
    for (sections, says) in [
        (
            "\"missing.csv\"",
            "s.toml:8:12: body `blade`: the section table `missing.csv`",
        ),
        (
            "3",
            "s.toml:8:12: body `blade`: `sections` is a CSV file's path",
        ),
        ("[1, 2]", "station 0 of `sections` is not a table"),
    ] {
        let e = table(&scene(sections), &dir).unwrap_err();
        assert!(e.contains(says), "{sections}: {e}");
    }
    let both =
        scene("\"t.csv\"").replace("elements = 4", "elements = 4\nparams = { length = 1.0 }");
    let e = table(&both, &dir).unwrap_err();
    assert!(e.contains("has `params` and `sections`"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `Builder` writes kernels for varying sections on request (a build
/// script's own, to use with `KernelBody::with_sections`): the file has the
/// section coefficient kernel and the list of moments it reads; the default
/// stays the uniform kernels, without them.
#[test]
fn builder_writes_varying_section_kernels_on_request() {
    use ffr_codegen::builder::{Builder, KernelConfig};
    use ffr_spec::SectionModel;
    let render = |k: KernelConfig| {
        let files = Builder::new()
            .kernels(k)
            .manifest_dir(env!("CARGO_MANIFEST_DIR"))
            .render()
            .unwrap();
        files[0].contents.clone()
    };
    let varying = render(KernelConfig::new("blade", "beam3").sections(SectionModel::Varying));
    assert!(
        varying.contains("fn section_coefficients("),
        "{}",
        &varying[..500]
    );
    assert!(varying.contains("fn section_moments("));
    assert!(varying.contains("SectionProp::EiYz"));
    let uniform = render(KernelConfig::new("blade", "beam3"));
    assert!(!uniform.contains("fn section_coefficients("));
    assert_ne!(varying, uniform);
}

/// `BodyConfig::sections`: the body's file bakes the table
/// (`CompiledBody::SECTIONS`, every station's numbers written to read back
/// to the same bits), lists the CSV among its inputs (rerun-if-changed),
/// reads no parameter field, and a bad table is an error at its cell; a
/// planar shape refuses twist.
#[test]
fn builder_bakes_a_body_section_table() {
    use ffr_codegen::builder::{BodyConfig, Builder};
    use ffr_spec::Reference;
    let dir = temp("body");
    std::fs::write(
        dir.join("t.csv"),
        "x,mass,ea,ei_y,ei_z,gj,rho_iy,rho_iz,twist\n0,3.5,2e9,4e7,6e6,3e6,0.1,0.2,0.3\n1.25,2.25,1e9,2e7,3e6,1e6,0.05,0.1,-0.1\n",
    )
    .unwrap();
    let render = |shape: &str, csv: &str| {
        Builder::new()
            .body(BodyConfig::new("blade", shape, 4, Reference::Clamped).sections(csv))
            .manifest_dir(&dir)
            .render()
    };
    let files = render("beam3", "t.csv").unwrap();
    // The formatted file, one space between tokens.
    let code = files[0]
        .contents
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(code.contains("const SECTIONS"), "{code}");
    assert!(code.contains("x: 1.25, mass: 2.25,"), "{code}");
    assert!(code.contains("twist: -0.1,"));
    assert!(code.contains("length: 1.25,"));
    assert!(!code.contains("self.rho"));
    assert!(code.contains("fn section_coefficients("));
    assert!(files[0].inputs.contains(&dir.join("t.csv")));
    std::fs::write(dir.join("bad.csv"), "x,mass\n0,1\n").unwrap();
    let e = render("beam3", "bad.csv").unwrap_err().to_string();
    assert!(
        e.starts_with("bad.csv:1:1: body `blade`: the section table has no column"),
        "{e}"
    );
    let e = render("beam2", "t.csv").unwrap_err().to_string();
    assert!(
        e.contains("station 0 has twist 0.3: a planar shape bends in x–y only"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
