//! Errors in scene files: each names `file:line:col` of the offending text
//! and what is allowed, and `ffr run` exits non-zero with it.

use ffr::scene;
use std::path::Path;

/// A valid planar scene: a beam pinned to the ground, a rigid block on its
/// tip, a force, an output. The error cases below change one thing.
const BASE: &str = r#"description = "error cases"
dimension = 2
gravity = [0.0, -9.81]
t_end = 0.01
dt = 1e-3

[bodies.rod]
shape = "beam2"
elements = 2
params = { length = 1.0, rho = 2700.0, area = 1e-4, iz = 8.3e-10, e = 7.0e10 }

[bodies.block]
mass = 0.5
inertia = 1e-3
position = [1.0, 0.0]

[[joints]]
kind = "revolute"
a = "ground@[0.0, 0.0]"
b = "rod"

[[joints]]
kind = "revolute"
a = "rod@x=1.0"
b = "block"

[[forces]]
kind = "point"
at = "rod@x=0.5"
force = [0.0, -1.0]

[[outputs]]
name = "tip_y"
kind = "position"
at = "rod@x=1.0"
component = "y"
"#;

/// `line:col` (1-based, columns in characters) of the first occurrence of
/// `needle` in `text`.
fn line_col(text: &str, needle: &str) -> String {
    let at = text.find(needle).unwrap_or_else(|| panic!("no `{needle}`"));
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    format!("{line}:{}", text[start..at].chars().count() + 1)
}

/// The error of `text` (which must fail to load).
fn error(text: &str) -> String {
    match scene::from_str(text, "bad.toml", Path::new("."), &scene::DefaultKernels) {
        Ok(_) => panic!("loaded:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// `BASE` with `from` replaced by `to` (which must apply once).
fn edit(from: &str, to: &str) -> String {
    assert_eq!(BASE.matches(from).count(), 1, "`{from}`");
    BASE.replace(from, to)
}

/// Each case: the edited scene, the text the error must point at, and what
/// the message must say (the problem and what is allowed).
#[test]
fn every_error_names_its_place_and_what_is_allowed() {
    assert!(scene::from_str(BASE, "ok.toml", Path::new("."), &scene::DefaultKernels).is_ok());
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        // Unknown body in a marker.
        (
            edit("at = \"rod@x=0.5\"", "at = \"rot@x=0.5\""),
            "\"rot@x=0.5\"",
            vec!["no body named `rot`", "bodies: block, rod", "`ground@[x, y]`"],
        ),
        // A marker point beyond the body.
        (
            edit("at = \"rod@x=0.5\"", "at = \"rod@x=1.5\""),
            "\"rod@x=1.5\"",
            vec!["x = 1.5 is not on the body's axis", "from x = 0 to x = 1 m"],
        ),
        // A marker with a point of the wrong dimension.
        (
            edit("a = \"ground@[0.0, 0.0]\"", "a = \"ground@[0.0, 0.0, 0.0]\""),
            "\"ground@[0.0, 0.0, 0.0]\"",
            vec!["the ground needs a point, `ground@[x, y]`"],
        ),
        // An axis point on a rigid body.
        (
            edit("b = \"block\"", "b = \"block@x=0.1\""),
            "\"block@x=0.1\"",
            vec!["`block` is rigid and has no axis", "block@[x, y]"],
        ),
        // A joint kind that does not exist in 2D.
        (
            edit("kind = \"revolute\"\na = \"rod@x=1.0\"", "kind = \"spherical\"\na = \"rod@x=1.0\""),
            "\"spherical\"",
            vec!["`spherical` joint needs a spatial scene", "ground, fixed, revolute and prismatic"],
        ),
        // A joint kind that does not exist at all.
        (
            edit("kind = \"revolute\"\na = \"rod@x=1.0\"", "kind = \"hinge\"\na = \"rod@x=1.0\""),
            "\"hinge\"",
            vec!["unknown joint kind `hinge`", "ground, fixed, revolute, spherical or prismatic"],
        ),
        // Modal keys without `modes`.
        (
            edit("elements = 2\n", "elements = 2\nmodal_damping = 0.02\n"),
            "0.02",
            vec!["body `rod`: `modal_damping` needs `modes = K`"],
        ),
        // An unknown reduction.
        (
            edit("elements = 2\n", "elements = 2\nmodes = 2\nreduction = \"guyan\"\n"),
            "\"guyan\"",
            vec!["`reduction` is \"modal\" or \"craig-bampton\"", "`guyan`"],
        ),
        // More modes than the body has.
        (
            edit("elements = 2\n", "elements = 2\nmodes = 7\n"),
            "7",
            vec!["body `rod`: `modes` must be between 1 and 6", "found 7"],
        ),
        // A boundary node beyond the body.
        (
            edit("elements = 2\n", "elements = 2\nmodes = 2\nreduction = \"craig-bampton\"\nboundary_nodes = [3]\n"),
            "[3]",
            vec!["boundary node 3 out of range", "nodes 0 to 2"],
        ),
        // Damping ratios that do not match the normal modes.
        (
            edit("elements = 2\n", "elements = 2\nmodes = 2\nmodal_damping = [0.01, 0.02, 0.03]\n"),
            "2\nmodal",
            vec!["`modal_damping` has 3 ratios", "one per normal mode (2)"],
        ),
        // A missing parameter of a flexible body (e is used by the beam).
        (
            edit(", e = 7.0e10 }", " }"),
            "{ length = 1.0",
            vec!["body `rod`: `params` needs `e`", "uses"],
        ),
        // An unknown parameter.
        (
            edit("iz = 8.3e-10", "i_z = 8.3e-10"),
            "i_z",
            vec!["unknown parameter `i_z`", "length, rho, area, iy, iz, e, g, j"],
        ),
        // A missing key of a force.
        (
            edit("force = [0.0, -1.0]\n", ""),
            "\"point\"",
            vec!["`point` force needs `force = [Fx, Fy(, Fz)]`"],
        ),
        // A vector of the wrong length.
        (
            edit("gravity = [0.0, -9.81]", "gravity = [0.0, -9.81, 0.0]"),
            "[0.0, -9.81, 0.0]",
            vec!["`gravity` needs 2 components in a 2-D scene, found 3"],
        ),
        (
            edit("force = [0.0, -1.0]", "force = [-1.0]"),
            "[-1.0]",
            vec!["`force` needs 2 components in a 2-D scene, found 1"],
        ),
        // An unknown key.
        (
            edit("force = [0.0, -1.0]", "force = [0.0, -1.0]\nstrength = 2.0"),
            "strength",
            vec!["unknown field `strength`", "expected one of", "`force`"],
        ),
        // A wrong type.
        (
            edit("elements = 2", "elements = \"two\""),
            "\"two\"",
            vec!["invalid type: string \"two\", expected i64"],
        ),
        // Unknown output kind and component.
        (
            edit("kind = \"position\"", "kind = \"acceleration\""),
            "\"acceleration\"",
            vec!["unknown output kind `acceleration`", "position, deflection, angle, velocity or energy"],
        ),
        (
            edit("component = \"y\"", "component = \"w\""),
            "\"w\"",
            vec!["`component` is x, y — found `w`"],
        ),
        // A drive profile that does not exist, and one missing a value.
        (
            edit("b = \"rod\"\n", "b = \"rod\"\ndrive = { angle = \"ramp\", omega = 1.0 }\n"),
            "\"ramp\"",
            vec!["unknown profile `ramp`", "spin-up, constant-rate, constant or harmonic"],
        ),
        (
            edit("b = \"rod\"\n", "b = \"rod\"\ndrive = { angle = \"spin-up\", omega = 1.0 }\n"),
            "\"spin-up\"",
            vec!["profile `spin-up` needs `ramp`"],
        ),
        // Inside a motor's target profile table (parsed on its own).
        (
            edit(
                "b = \"rod\"\n",
                "b = \"rod\"\nmotor = { kp = 1.0, target = { angle = \"harmonic\", amplitude = 0.1 } }\n",
            ),
            "\"harmonic\"",
            vec!["profile `harmonic` needs `frequency`"],
        ),
        (
            edit(
                "b = \"rod\"\n",
                "b = \"rod\"\nmotor = { kp = 1.0, target = { angle = \"harmonic\", amplitud = 0.1 } }\n",
            ),
            "amplitud",
            vec!["unknown field `amplitud`", "`amplitude`"],
        ),
        // An initial elastic coordinate that the body does not have.
        (
            edit("e = 7.0e10 }\n", "e = 7.0e10 }\nelastic = { q = { uz_1 = 1e-3 } }\n"),
            "uz_1",
            vec!["no elastic coordinate `uz_1`", "ux_1, uy_1, rz_1"],
        ),
        // A drive on a fixed joint, a motor on a prismatic one.
        (
            edit(
                "kind = \"revolute\"\na = \"rod@x=1.0\"\nb = \"block\"\n",
                "kind = \"fixed\"\na = \"rod@x=1.0\"\nb = \"block\"\ndrive = { angle = \"constant\", value = 0.0 }\n",
            ),
            "{ angle = \"constant\"",
            vec!["a `fixed` joint has no drive", "revolute (angle) and prismatic (slide)"],
        ),
        // Dimension.
        (
            edit("dimension = 2", "dimension = 4"),
            "4\n",
            vec!["`dimension` must be 2 (planar) or 3 (spatial), found 4"],
        ),
        // A rigid body's planar inertia must be one number.
        (
            edit("inertia = 1e-3", "inertia = [1e-3, 1e-3, 1e-3]"),
            "[1e-3, 1e-3, 1e-3]",
            vec!["planar `inertia` is one number"],
        ),
    ];
    for (text, at, says) in &cases {
        let e = error(text);
        let want = format!("bad.toml:{}: ", line_col(text, at));
        println!("{e}");
        assert!(e.starts_with(&want), "`{e}` should start with `{want}`");
        for s in says {
            assert!(e.contains(s), "`{e}` should say `{s}`");
        }
    }
}

/// `ffr run` on a broken scene file exits with status 1 and the located
/// message on stderr, without a panic and without writing outputs.
#[test]
fn ffr_run_exits_non_zero_with_the_located_error() {
    let dir = std::env::temp_dir().join(format!("ffr-scene-errors-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = edit("at = \"rod@x=0.5\"", "at = \"rod@x=1.5\"");
    let path = dir.join("bad.toml");
    std::fs::write(&path, &text).unwrap();
    let csv = dir.join("out.csv");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
        .args([
            "run",
            &path.display().to_string(),
            "--csv",
            &csv.display().to_string(),
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stderr}");
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let want = format!("{}:{}: ", path.display(), line_col(&text, "\"rod@x=1.5\""));
    assert!(stderr.contains(&want), "{stderr} should contain {want}");
    assert!(stderr.contains("is not on the body's axis"), "{stderr}");
    assert!(!csv.exists());
    // A missing file and a directory are errors too.
    for p in [dir.join("missing.toml"), dir.clone()] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
            .args(["run", &p.display().to_string()])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&out.stderr).contains(&p.display().to_string()));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
