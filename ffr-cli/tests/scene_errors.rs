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
        // Attached masses: off the axis, negative, a spatial inertia on a
        // planar body, with a modal reduction, an unknown key, on a rigid body.
        (
            edit("e = 7.0e10 }\n", "e = 7.0e10 }\n\n[[bodies.rod.masses]]\nx = 1.5\nmass = 1.0\n"),
            "1.5\nmass",
            vec!["body `rod`: the attached mass's x = 1.5 is not on the axis", "from x = 0 to x = 1 m"],
        ),
        (
            edit("e = 7.0e10 }\n", "e = 7.0e10 }\n\n[[bodies.rod.masses]]\nx = 0.5\nmass = -1.0\n"),
            "-1.0",
            vec!["body `rod`: an attached `mass` must not be negative, found -1"],
        ),
        (
            edit("e = 7.0e10 }\n", "e = 7.0e10 }\n\n[[bodies.rod.masses]]\nx = 0.5\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n"),
            "[[bodies.rod.masses]]",
            vec!["body `rod`: attached mass: a planar body's attached mass turns about z only", "give `inertia` as a number"],
        ),
        (
            edit("e = 7.0e10 }\n", "e = 7.0e10 }\nmodes = 2\n\n[[bodies.rod.masses]]\nx = 0.5\nmass = 1.0\n"),
            "2\n\n[[bodies",
            vec!["body `rod`: a modal body with attached masses", "not reduced yet"],
        ),
        (
            edit("e = 7.0e10 }\n", "e = 7.0e10 }\n\n[[bodies.rod.masses]]\nx = 0.5\nmass = 1.0\noffset = 0.1\n"),
            "offset",
            vec!["unknown field `offset`", "`x`, `mass`, `inertia`"],
        ),
        (
            edit("position = [1.0, 0.0]\n", "position = [1.0, 0.0]\n\n[[bodies.block.masses]]\nx = 0.5\nmass = 1.0\n"),
            "0.5\ninertia = 1e-3",
            vec!["body `block` has `mass` (rigid) and `masses` (flexible)"],
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
            "drive = { angle = \"constant\"",
            vec!["`drive` does not apply to a `fixed` joint", "it takes `kind`, `a`, `b`", "revolute (angle) and prismatic (slide)"],
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

/// Check each case: the error starts with `bad.toml:LINE:COL: ` of the first
/// occurrence of `at`, says every one of `says`, and is short (no number or
/// user string echoed at length).
fn check_cases(cases: &[(String, &str, Vec<&str>)]) {
    for (text, at, says) in cases {
        let e = error(text);
        let want = format!("bad.toml:{}: ", line_col(text, at));
        println!("{e}");
        assert!(e.starts_with(&want), "`{e}` should start with `{want}`");
        for s in says {
            assert!(e.contains(s), "`{e}` should say `{s}`");
        }
        assert!(e.chars().count() < 600, "too long: {e}");
        assert!(!e.contains("0000000000"), "a number in long form: {e}");
    }
}

/// A key that means nothing for its table's kind is an error at the key,
/// naming the keys that apply (issue 17: such keys were silently ignored, or
/// one of two keys for the same thing silently won).
#[test]
fn keys_that_do_not_apply_are_errors_at_the_key() {
    let drive = |d: &str| edit("b = \"rod\"\n", &format!("b = \"rod\"\ndrive = {d}\n"));
    let integrator = |i: &str| edit("dt = 1e-3\n", &format!("dt = 1e-3\nintegrator = {i}\n"));
    let output = |o: &str| format!("{BASE}\n[[outputs]]\nname = \"extra\"\n{o}\n");
    let force = |f: &str| format!("{BASE}\n[[forces]]\n{f}\n");
    let elbow = |j: &str| {
        edit(
            "kind = \"revolute\"\na = \"rod@x=1.0\"\nb = \"block\"\n",
            &format!("a = \"rod@x=1.0\"\nb = \"block\"\n{j}\n"),
        )
    };
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        // `rate` next to `omega`: one of them used to win silently.
        (
            drive("{ angle = \"constant-rate\", omega = 1.0, rate = 2.0 }"),
            "rate = 2.0",
            vec!["`rate` and `omega` both give the rate of profile `constant-rate`", "give one"],
        ),
        // RK4's gains under generalized-α, and generalized-α's keys under RK4.
        (
            integrator("{ kind = \"generalized-alpha\", alpha = 10.0 }"),
            "alpha = 10.0",
            vec!["`alpha` does not apply to the generalized-alpha integrator", "it takes `kind`, `rho_inf`, `rtol`", "`kind = \"rk4\"`"],
        ),
        (
            integrator("{ kind = \"generalized-alpha\", rho_inf = 0.9, beta = 10.0 }"),
            "beta = 10.0",
            vec!["`beta` does not apply to the generalized-alpha integrator"],
        ),
        (
            integrator("{ kind = \"rk4\", rho_inf = 0.5 }"),
            "rho_inf",
            vec!["`rho_inf` does not apply to the rk4 integrator", "it takes `kind`, `alpha`, `beta`"],
        ),
        (
            integrator("{ kind = \"rk4\", alpha = 5.0, rtol = 1e-8 }"),
            "rtol",
            vec!["`rtol` does not apply to the rk4 integrator", "no Newton iteration"],
        ),
        // `slide` on a revolute drive, `angle` on a prismatic one.
        (
            drive("{ angle = \"constant\", value = 0.0, slide = \"constant\" }"),
            "slide",
            vec!["`slide` does not apply to the drive of a `revolute` joint", "it takes `angle = \"PROFILE\"`"],
        ),
        (
            elbow("kind = \"prismatic\"\ndrive = { slide = \"constant\", value = 0.0, angle = \"constant\" }"),
            "angle = \"constant\" }",
            vec!["`angle` does not apply to the drive of a `prismatic` joint", "it takes `slide = \"PROFILE\"`"],
        ),
        // A profile's keys: `ramp` and `start` mean nothing for `constant`.
        (
            drive("{ angle = \"constant\", value = 0.0, ramp = 1.0 }"),
            "ramp",
            vec!["`ramp` does not apply to profile `constant`", "it takes `angle`, `value`"],
        ),
        (
            drive("{ angle = \"constant\", value = 0.0, start = 1.0 }"),
            "start",
            vec!["`start` does not apply to profile `constant`"],
        ),
        (
            drive("{ angle = \"harmonic\", amplitude = 0.1, frequency = 1.0, omega = 2.0 }"),
            "omega",
            vec!["`omega` does not apply to profile `harmonic`", "`amplitude`, `frequency`, `start`, `phase`"],
        ),
        (
            drive("{ angle = \"spin-up\", omega = 1.0, ramp = 1.0, value = 2.0 }"),
            "value",
            vec!["`value` does not apply to profile `spin-up`", "`omega`, `ramp`, `start`"],
        ),
        // A motor target is an angle profile.
        (
            elbow("kind = \"revolute\"\nmotor = { kp = 1.0, target = { slide = \"constant\", value = 0.0 } }"),
            "slide",
            vec!["`slide` does not apply to a motor's target", "`angle = \"PROFILE\"`"],
        ),
        // A constant-torque motor has no gains; a driven joint no motor.
        (
            elbow("kind = \"revolute\"\nmotor = { torque = 1.0, kd = 0.1 }"),
            "kd",
            vec!["`kd` does not apply to a constant-torque motor", "it takes `torque`"],
        ),
        (
            elbow("kind = \"revolute\"\ndrive = { angle = \"constant\", value = 0.0 }\nmotor = { torque = 1.0 }"),
            "motor",
            vec!["`motor` does not apply to a driven revolute joint", "give `drive` or `motor`"],
        ),
        // Joint kinds.
        (
            elbow("kind = \"prismatic\"\nmotor = { torque = 1.0 }"),
            "motor",
            vec!["`motor` does not apply to a `prismatic` joint", "it takes `kind`, `a`, `b`, `drive`"],
        ),
        (
            edit("kind = \"revolute\"\na = \"ground@[0.0, 0.0]\"\nb = \"rod\"", "kind = \"ground\"\na = \"ground@[0.0, 0.0]\"\nb = \"rod\""),
            "a = \"ground",
            vec!["`a` does not apply to a `ground` joint", "it takes `kind`, `b`"],
        ),
        // Outputs.
        (
            output("kind = \"energy\"\nat = \"rod\""),
            "at = \"rod\"\n",
            vec!["`at` does not apply to an `energy` output", "it takes `name`, `kind`, `component`"],
        ),
        (
            output("kind = \"angle\"\nat = \"rod\"\ncomponent = \"z\""),
            "component = \"z\"",
            vec!["`component` does not apply to an `angle` output", "it takes `name`, `kind`, `at`, `a`"],
        ),
        (
            output("kind = \"position\"\nat = \"rod\"\ncomponent = \"x\"\na = \"block\""),
            "a = \"block\"\n",
            vec!["`a` does not apply to a `position` output"],
        ),
        // Forces.
        (
            force("kind = \"point\"\nat = \"rod@x=1.0\"\nforce = [0.0, 1.0]\nstiffness = 3.0"),
            "stiffness = 3.0",
            vec!["`stiffness` does not apply to a `point` force", "it takes `kind`, `at`, `force`, `axes`"],
        ),
        (
            force("kind = \"spring-damper\"\na = \"ground@[1.0, 0.0]\"\nb = \"rod@x=1.0\"\nstiffness = 3.0\nrest_length = 0.1\nrest_angle = 0.2"),
            "rest_angle",
            vec!["`rest_angle` does not apply to a `spring-damper` force", "`rotational-spring-damper`"],
        ),
        (
            force("kind = \"torque\"\na = \"ground@[1.0, 0.0]\"\nb = \"rod@x=1.0\"\ntorque = 1.0\ndamping = 0.1"),
            "damping = 0.1",
            vec!["`damping` does not apply to a `torque` force", "it takes `kind`, `a`, `b`, `torque`"],
        ),
        // Bodies: flexible keys on a rigid body and rigid ones on a flexible body.
        (
            edit("inertia = 1e-3\n", "inertia = 1e-3\nreference = \"pinned\"\n"),
            "reference",
            vec!["`reference` does not apply to rigid body `block` (it has `mass`)", "it takes `mass`, `inertia`, `centre`, `position`, `angle`"],
        ),
        (
            edit("inertia = 1e-3\n", "inertia = 1e-3\nstiffening = true\n"),
            "stiffening",
            vec!["`stiffening` does not apply to rigid body `block`"],
        ),
        (
            edit("elements = 2\n", "elements = 2\ninertia = 1e-3\n"),
            "inertia = 1e-3\nparams",
            vec!["`inertia` does not apply to flexible body `rod` (it has `shape`)", "follows from its shape and `params`"],
        ),
        (
            edit("elements = 2\n", "elements = 2\ncentre = [0.5, 0.0]\n"),
            "centre",
            vec!["`centre` does not apply to flexible body `rod`"],
        ),
    ];
    check_cases(&cases);
}

/// Body names become generated identifiers (`ffr emit --scene`): ASCII Rust
/// identifiers, not keywords, at most 64 characters, distinct after the
/// conversion to CamelCase.
#[test]
fn body_names_are_identifiers_that_stay_distinct() {
    let body = |name: &str| format!("{BASE}\n[bodies.{name}]\nmass = 1.0\ninertia = 1.0\n");
    let long = "b".repeat(20_000);
    let long_body = body(&long);
    let two = format!("{BASE}\n[bodies.a_b]\nmass = 1.0\ninertia = 1.0\n\n[bodies.aB]\nmass = 1.0\ninertia = 1.0\n");
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        (
            two.clone(),
            "a_b]",
            vec![
                "bodies `aB` and `a_b` both give the generated name `AB`",
                "must differ",
            ],
        ),
        (
            body("my-arm"),
            "my-arm",
            vec![
                "body name `my-arm` is not a Rust identifier",
                "the character `-`",
            ],
        ),
        (
            body("\"2nd\""),
            "\"2nd\"",
            vec![
                "body name `2nd` is not a Rust identifier",
                "starts with a digit",
            ],
        ),
        (body("fn"), "fn]", vec!["body name `fn` is a Rust keyword"]),
        (
            body("Self"),
            "Self]",
            vec!["body name `Self` is a Rust keyword"],
        ),
        (
            body("ground"),
            "ground]",
            vec!["`ground` cannot name a body"],
        ),
        (
            long_body.clone(),
            "bbbb",
            vec!["is 20000 characters long", "at most 64", "…"],
        ),
    ];
    check_cases(&cases);
    // `ffr emit --scene` refuses the collision too (the generated file
    // would not compile), at the same place.
    let dir = std::env::temp_dir().join(format!("ffr-scene-names-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    std::fs::write(&path, &two).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
        .args(["emit", "--scene", &path.display().to_string()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    let want = format!("{}:{}: ", path.display(), line_col(&two, "a_b]"));
    assert!(stderr.contains(&want), "{stderr} should contain {want}");
    assert!(stderr.contains("`aB` and `a_b`"), "{stderr}");
    assert!(out.stdout.is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Force elements whose ends cannot move relative to each other (they did
/// nothing and reported energy), point forces on the ground, and numbers,
/// drives and names echoed in messages: located, short.
#[test]
fn degenerate_forces_overflows_and_long_strings_are_located_and_short() {
    let force = |f: &str| format!("{BASE}\n[[forces]]\n{f}\n");
    let long = "x".repeat(20_000);
    let long_marker = edit("at = \"rod@x=0.5\"", &format!("at = \"{long}@x=0.5\""));
    let long_output = format!("{BASE}\n[[outputs]]\nname = \"{long}\"\nkind = \"energy\"\n\n[[outputs]]\nname = \"{long}\" # again\nkind = \"energy\"\n");
    let again = format!("\"{long}\" # again");
    let long_kind = edit("kind = \"point\"", &format!("kind = \"{long}\""));
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        // Issue 36: numbers in messages in short form (was `x = 1000…`
        // with 309 digits), subnormal values refused by name (were "singular
        // mass system… redundant constraints", blaming a joint).
        (
            edit("at = \"rod@x=0.5\"", "at = \"rod@x=1e308\""),
            "\"rod@x=1e308\"",
            vec!["x = 1e308 is not on the body's axis", "to x = 1 m"],
        ),
        (
            edit("a = \"ground@[0.0, 0.0]\"", "a = \"ground@[-1e308, 0.0]\""),
            "\"ground@[-1e308, 0.0]\"",
            vec!["the coordinate -1e308 is beyond ±1e9 m (MAX_COORDINATE)"],
        ),
        (
            edit("position = [1.0, 0.0]", "position = [1.0, 2e9]"),
            "[1.0, 2e9]",
            vec!["`position`: the coordinate 2e9 is beyond ±1e9 m"],
        ),
        (
            edit("at = \"rod@x=0.5\"", "at = \"block@[1e10, 0.0]\""),
            "\"block@[1e10, 0.0]\"",
            vec!["the coordinate 1e10 is beyond"],
        ),
        (
            edit("rho = 2700.0", "rho = 1e-310"),
            "{ length",
            vec!["parameter `rho` is subnormal, found 1e-310", "smallest normal f64"],
        ),
        (
            edit("mass = 0.5", "mass = 1e-310"),
            "1e-310",
            vec!["`mass` = 1e-310 is subnormal"],
        ),
        // A spring from a marker to itself.
        (
            force("kind = \"spring-damper\"\na = \"rod@x=0.5\"\nb = \"rod@x=0.5\"\nstiffness = 10.0\nrest_length = 0.0"),
            "\"rod@x=0.5\"\nstiffness",
            vec!["`spring-damper` force's ends `a` = `rod@x=0.5` and `b` = `rod@x=0.5` are the same point of body `rod`", "does nothing"],
        ),
        // Two points fixed in one rigid body's frame.
        (
            force("kind = \"spring-damper\"\na = \"block\"\nb = \"block@[0.1, 0.0]\"\nstiffness = 10.0\nrest_length = 0.0\ndamping = 1.0"),
            "\"block@[0.1, 0.0]\"",
            vec!["are both fixed in the frame of body `block`"],
        ),
        (
            force("kind = \"rotational-spring-damper\"\na = \"ground@[0.0, 1.0]\"\nb = \"ground@[0.0, 0.0]\"\nstiffness = 10.0"),
            "\"ground@[0.0, 0.0]\"\nstiff",
            vec!["are both fixed to the ground"],
        ),
        (
            force("kind = \"torque\"\na = \"block\"\nb = \"block\"\ntorque = 1.0"),
            "\"block\"\ntorque",
            vec!["`torque` force's ends", "are both fixed in the frame of body `block`"],
        ),
        (
            force("kind = \"point\"\nat = \"ground@[0.0, 1.0]\"\nforce = [1.0, 0.0]"),
            "\"ground@[0.0, 1.0]\"",
            vec!["a `point` force at the ground", "does nothing"],
        ),
        // Numbers in short form, every refusal located.
        (
            edit("dt = 1e-3\n", "dt = 1e-3\nintegrator = { kind = \"generalized-alpha\", rtol = 1e300 }\n"),
            "1e300",
            vec!["`rtol` (the relative Newton tolerance) must be in (0, 1), found 1e300"],
        ),
        (
            edit("dt = 1e-3\n", "dt = 1e-3\nintegrator = { kind = \"generalized-alpha\", rho_inf = -1e300 }\n"),
            "-1e300",
            vec!["`rho_inf` must be in [0, 1], found -1e300"],
        ),
        (
            force("kind = \"spring-damper\"\na = \"ground@[1.0, 0.0]\"\nb = \"rod@x=1.0\"\nstiffness = -1e300\nrest_length = 0.0"),
            "-1e300",
            vec!["`stiffness` must be ≥ 0, found -1e300"],
        ),
        // A drive that overflows names its joint.
        (
            edit("b = \"rod\"\n", "b = \"rod\"\ndrive = { angle = \"harmonic\", amplitude = 1e290, frequency = 1e10 }\n"),
            "{ angle = \"harmonic\"",
            vec!["the drive of joint 1 (`revolute`, a = `ground@[0.0, 0.0]`, b = `rod`)", "acceleration (amplitude (2π frequency)²) reaches inf", "beyond the range of f64"],
        ),
        (
            edit(
                "kind = \"revolute\"\na = \"rod@x=1.0\"\nb = \"block\"\n",
                "kind = \"revolute\"\na = \"rod@x=1.0\"\nb = \"block\"\nmotor = { kp = 1.0, target = { angle = \"spin-up\", omega = 1e300, ramp = 1e-10 } }\n",
            ),
            "{ angle = \"spin-up\"",
            vec!["the motor target of joint 2 (`revolute`, a = `rod@x=1.0`, b = `block`)", "acceleration (2 omega/ramp) reaches inf"],
        ),
        // Long user strings are shortened.
        (long_marker, "\"xxxx", vec!["no body named `xxxxxxxx", "…`"]),
        (long_output, &again, vec!["is named twice", "…`"]),
        (long_kind, "\"xxxx", vec!["unknown force kind `xxxx", "…`"]),
        // An overflow in a modal body's eigenproblem is not blamed on a
        // coordinate without mass.
        (
            edit(
                "elements = 2\nparams = { length = 1.0, rho = 2700.0, area = 1e-4, iz = 8.3e-10, e = 7.0e10 }",
                "elements = 2\nmodes = 2\nparams = { length = 1.0, rho = 1e300, area = 1e-4, iz = 8.3e-10, e = 1e-300 }",
            ),
            "2\nparams",
            vec!["body `rod`", "beyond the range of f64"],
        ),
    ];
    check_cases(&cases);
    for (text, _, _) in &cases {
        assert!(!error(text).contains("carries no mass"));
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

/// `BASE`'s point force with `profile = P` (the time function of its
/// vector).
fn profiled(p: &str) -> String {
    edit(
        "force = [0.0, -1.0]\n",
        &format!("force = [0.0, -1.0]\nprofile = {p}\n"),
    )
}

/// A spatial scene: a beam3 on a spherical joint, a block on its tip.
const SPATIAL: &str = r#"dimension = 3
t_end = 0.01
dt = 1e-3

[bodies.rod]
shape = "beam3"
elements = 2
params = { length = 1.0, rho = 2700.0, area = 1e-4, iy = 8.3e-10, iz = 8.3e-10, e = 7.0e10, g = 2.6e10, j = 1.4e-9 }

[bodies.block]
mass = 0.5
inertia = [1e-3, 1e-3, 1e-3]
position = [1.0, 0.0, 0.0]

[[joints]]
kind = "spherical"
a = "ground@[0.0, 0.0, 0.0]"
b = "rod"

[[joints]]
kind = "fixed"
a = "rod@x=1.0"
b = "block"
"#;

/// A point force's `profile` (a drive profile or a table) and markers with
/// their own axes (`{ at = "…", axes = { … } }`): every hostile value is
/// refused at its place, with what is allowed.
#[test]
fn force_profiles_and_marker_axes_give_located_errors() {
    // Each profile that is fine loads.
    for ok in [
        "{ table = [[0.0, 1.0], [0.5, 2.0]] }",
        "{ table = [[0, 1], [1, 0]] }",
        "{ kind = \"harmonic\", amplitude = 1.0, frequency = 2.0 }",
        "{ kind = \"constant\", value = 0.5 }",
        "{ kind = \"spin-up\", omega = 1.0, ramp = 0.5 }",
        "{ kind = \"constant-rate\", rate = 2.0, start = 1.0 }",
    ] {
        let text = profiled(ok);
        if let Err(e) = scene::from_str(&text, "ok.toml", Path::new("."), &scene::DefaultKernels) {
            panic!("{ok}: {e}");
        }
    }
    let spring = format!(
        "{BASE}\n[[forces]]\nkind = \"spring-damper\"\na = \"ground@[1.0, 0.0]\"\nb = \"rod@x=1.0\"\nstiffness = 3.0\nrest_length = 0.1\nprofile = {{ kind = \"constant\", value = 1.0 }}\n"
    );
    let elbow = |b: &str| edit("b = \"block\"", &format!("b = {b}"));
    let spatial = |b: &str| {
        assert_eq!(SPATIAL.matches("b = \"block\"").count(), 1);
        SPATIAL.replace("b = \"block\"", &format!("b = {b}"))
    };
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        // Tables: times that do not increase, or are not finite.
        (
            profiled("{ table = [[0.0, 1.0], [0.0, 2.0]] }"),
            "[0.0, 2.0]",
            vec!["row 2 of the profile `table`: the time 0.0 is not after row 1's 0.0", "increase strictly"],
        ),
        (
            profiled("{ table = [[1.0, 0.0], [2.0, 1.0], [1.5, 1.0]] }"),
            "[1.5, 1.0]",
            vec!["row 3 of the profile `table`: the time 1.5 is not after row 2's 2.0"],
        ),
        (
            profiled("{ table = [[0.0, 0.0], [inf, 1.0]] }"),
            "[inf, 1.0]",
            vec!["row 2 of the profile `table`: the time inf is not a finite number"],
        ),
        (
            profiled("{ table = [[nan, 0.0]] }"),
            "[nan, 0.0]",
            vec!["row 1 of the profile `table`: the time NaN is not a finite number"],
        ),
        (
            profiled("{ table = [[-1e308, 0.0], [1e308, 1.0]] }"),
            "[[-1e308",
            vec!["times span -1e308 to 1e308", "beyond the range of f64"],
        ),
        // Values that are not finite.
        (
            profiled("{ table = [[0.0, 1.0], [1.0, nan]] }"),
            "[1.0, nan]",
            vec!["row 2 of the profile `table`: the value NaN is not a finite number"],
        ),
        (
            profiled("{ table = [[0.0, -inf]] }"),
            "[0.0, -inf]",
            vec!["the value -inf is not a finite number"],
        ),
        // An empty table, rows of the wrong length or type.
        (
            profiled("{ table = [] }"),
            "[] }",
            vec!["a profile `table` needs at least one row [time, value]"],
        ),
        (
            profiled("{ table = [[0.0, 1.0], [1.0, 2.0, 3.0]] }"),
            "[1.0, 2.0, 3.0]",
            vec!["row 2 of the profile `table` has 3 values: each row is [time, value]"],
        ),
        (
            profiled("{ table = [[0.5]] }"),
            "[0.5]",
            vec!["row 1 of the profile `table` has 1 value: each row is [time, value]"],
        ),
        (
            profiled("{ table = [0.0, 1.0] }"),
            "0.0, 1.0] }",
            vec!["expected a row [time, value] of two numbers"],
        ),
        (
            profiled("{ table = [[0.0, \"one\"]] }"),
            "\"one\"",
            vec!["invalid type: string"],
        ),
        // `kind` and `table` together; neither; keys that do not apply.
        (
            profiled("{ kind = \"constant\", value = 1.0, table = [[0.0, 1.0]] }"),
            "table =",
            vec!["`table` and `kind` both give the force's profile", "not both"],
        ),
        (
            profiled("{ table = [[0.0, 1.0]], kind = \"constant\", value = 1.0 }"),
            "kind = \"constant\", value",
            vec!["`kind` and `table` both give the force's profile"],
        ),
        (
            profiled("{ }"),
            "{ }",
            vec!["a force's `profile` needs `kind = \"PROFILE\"`", "or `table = [[t0, f0], [t1, f1], …]`"],
        ),
        (
            profiled("{ table = [[0.0, 1.0]], amplitude = 2.0 }"),
            "amplitude",
            vec!["`amplitude` does not apply to a table profile (`table`): it takes `table`"],
        ),
        (
            profiled("{ kind = \"constant\", value = 1.0, ramp = 1.0 }"),
            "ramp",
            vec!["`ramp` does not apply to profile `constant` (a point force's profile): it takes `kind`, `value`"],
        ),
        (
            profiled("{ kind = \"harmonic\", amplitude = 1.0, frequency = 1.0, omega = 2.0 }"),
            "omega",
            vec!["`omega` does not apply to profile `harmonic`", "`kind`, `amplitude`, `frequency`, `start`, `phase`"],
        ),
        (
            profiled("{ kind = \"constant\", value = 1.0, gain = 2.0 }"),
            "gain",
            vec!["unknown field `gain`"],
        ),
        (
            profiled("{ kind = \"square\", value = 1.0 }"),
            "\"square\"",
            vec!["unknown profile `square`", "spin-up, constant-rate, constant or harmonic"],
        ),
        (
            profiled("{ kind = \"harmonic\", amplitude = 1.0 }"),
            "\"harmonic\"",
            vec!["profile `harmonic` needs `frequency`"],
        ),
        (
            profiled("{ kind = \"constant\", value = inf }"),
            "inf }",
            vec!["`value` must be a finite number, found inf"],
        ),
        // f(t) force beyond the range of f64; a drive profile that overflows.
        (
            edit("force = [0.0, -1.0]\n", "force = [0.0, -1e300]\nprofile = { table = [[0.0, 1e20]] }\n"),
            "{ table",
            vec!["force 1 (`point` at `rod@x=0.5`)", "the profile's value reaches 1e20", "1e300", "beyond the range of f64"],
        ),
        (
            profiled("{ kind = \"harmonic\", amplitude = 1e290, frequency = 1e10 }"),
            "{ kind",
            vec!["force 1 (`point` at `rod@x=0.5`)", "reaches inf", "beyond the range of f64"],
        ),
        // `profile` is for point forces.
        (
            spring,
            "profile = { kind = \"constant\", value = 1.0 }\n",
            vec!["`profile` does not apply to a `spring-damper` force", "scales the vector of a `point` force"],
        ),
        // Marker tables: no `at`, unknown keys, a planar `axis`, values.
        (
            elbow("{ axes = { angle = 1.0 } }"),
            "{ axes = { angle = 1.0 } }",
            vec!["a marker table needs `at = \"MARKER\"`"],
        ),
        (
            elbow("{ at = \"block\", angle = 1.0 }"),
            "angle = 1.0 }",
            vec!["unknown field `angle`, expected `at` or `axes`"],
        ),
        (
            elbow("{ at = \"block\", axes = { angle = 1.0, spin = 2.0 } }"),
            "spin",
            vec!["unknown field `spin`, expected `axis` or `angle`"],
        ),
        (
            elbow("{ at = \"block\", axes = { axis = [0.0, 0.0, 1.0], angle = 1.0 } }"),
            "axis =",
            vec!["`axis` does not apply to a marker's `axes` in a planar scene (a rotation about z): it takes `angle`"],
        ),
        (
            elbow("{ at = \"block\", axes = { angle = nan } }"),
            "nan",
            vec!["`angle` must be a finite number, found NaN"],
        ),
        (
            elbow("{ at = \"block\", axes = { } }"),
            "{ } }",
            vec!["a marker's `axes` needs `angle` (rad)"],
        ),
        (
            elbow("3.0"),
            "3.0\n",
            vec!["expected a marker: a string such as \"NAME@x=0.3\", or a table"],
        ),
        // The point of a marker table is located at its `at`.
        (
            elbow("{ at = \"block@x=0.1\", axes = { angle = 1.0 } }"),
            "\"block@x=0.1\"",
            vec!["`block` is rigid and has no axis"],
        ),
        (
            edit("at = \"rod@x=0.5\"", "at = { at = \"rod@x=1.5\", axes = { angle = 0.1 } }"),
            "\"rod@x=1.5\"",
            vec!["x = 1.5 is not on the body's axis"],
        ),
        // A ground joint fixes its body's frame: no axes.
        (
            edit(
                "kind = \"revolute\"\na = \"ground@[0.0, 0.0]\"\nb = \"rod\"",
                "kind = \"ground\"\nb = { at = \"rod\", axes = { angle = 0.5 } }",
            ),
            "{ at = \"rod\"",
            vec!["a `ground` joint fixes body `b`'s frame where it starts: its marker takes no `axes`"],
        ),
        // Spatial: the axis must be a finite, non-zero direction.
        (
            spatial("{ at = \"block\", axes = { axis = [0.0, 0.0, 0.0], angle = 1.0 } }"),
            "[0.0, 0.0, 0.0], angle",
            vec!["`axis` = [0.0, 0.0, 0.0] is zero: the rotation needs a direction"],
        ),
        (
            spatial("{ at = \"block\", axes = { axis = [1e-200, 0.0, 0.0], angle = 1.0 } }"),
            "[1e-200",
            vec!["is too short (its squared length underflows to 0)"],
        ),
        (
            spatial("{ at = \"block\", axes = { axis = [1e200, 1e200, 0.0], angle = 1.0 } }"),
            "[1e200",
            vec!["is too long (its squared length overflows)"],
        ),
        (
            spatial("{ at = \"block\", axes = { axis = [0.0, nan, 1.0], angle = 1.0 } }"),
            "[0.0, nan, 1.0]",
            vec!["`axis` must be finite, found NaN"],
        ),
        (
            spatial("{ at = \"block\", axes = { axis = [0.0, 1.0], angle = 1.0 } }"),
            "[0.0, 1.0]",
            vec!["`axis` needs 3 components"],
        ),
        (
            spatial("{ at = \"block\", axes = { angle = 1.0 } }"),
            "{ angle = 1.0 }",
            vec!["a spatial marker's `axes` need `axis = [x, y, z]`"],
        ),
        (
            spatial("{ at = \"block\", axes = { axis = [0.0, 0.0, 1.0], angle = inf } }"),
            "inf }",
            vec!["`angle` must be a finite number, found inf"],
        ),
    ];
    check_cases(&cases);
    // Each is refused by `ffr run` with exit status 1 and the same place.
    let dir = std::env::temp_dir().join(format!("ffr-scene-profiles-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (k, (text, at, says)) in cases.iter().enumerate() {
        let path = dir.join(format!("bad{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
            .args(["run", &path.display().to_string()])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        let want = format!("{}:{}: ", path.display(), line_col(text, at));
        assert!(stderr.contains(&want), "{stderr} should contain {want}");
        assert!(stderr.contains(says[0]), "{stderr} should say {}", says[0]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A profile table of more rows than `MAX_PROFILE_ROWS` is refused while it
/// is read (before more rows are stored), at the table, by the library and
/// by `ffr run` (exit 1); one of exactly that many rows loads.
#[test]
fn a_profile_table_longer_than_the_bound_is_refused() {
    use ffr::scene::spec::MAX_PROFILE_ROWS;
    let table = |n: usize| {
        let rows: Vec<String> = (0..n).map(|i| format!("[{i},0]")).collect();
        profiled(&format!("{{ table = [{}] }}", rows.join(",")))
    };
    let long = table(MAX_PROFILE_ROWS + 1);
    // A scene file of this table is within the bound on scene files.
    assert!(long.len() < (1 << 20), "{} bytes", long.len());
    let e = error(&long);
    let want = format!("bad.toml:{}: ", line_col(&long, "[[0,0]"));
    assert!(e.starts_with(&want), "`{e}` should start with `{want}`");
    assert!(
        e.contains(&format!("has more than {MAX_PROFILE_ROWS} rows")),
        "{e}"
    );
    let full = table(MAX_PROFILE_ROWS);
    let spec = ffr_codegen::scene::resolve_str(&full, "ok.toml", Path::new(".")).unwrap();
    match &spec.forces[0].kind {
        ffr::scene::spec::ForceKind::Point {
            profile: Some(ffr::scene::spec::ForceProfile::Table(rows)),
            ..
        } => assert_eq!(rows.len(), MAX_PROFILE_ROWS),
        other => panic!("{other:?}"),
    }
    let dir = std::env::temp_dir().join(format!("ffr-scene-rows-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("long.toml");
    std::fs::write(&path, &long).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
        .args(["run", &path.display().to_string()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!("{}:{}", path.display(), line_col(&long, "[[0,0]"))),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
