//! `ffr::scene::SceneText`: scene variants by dotted keys, checked against
//! the scene the loader resolves and against the same file edited by hand.

use ffr::scene::spec::{BodyKind, ForceKind, ForceProfile, Orientation, ProfileSpec};
use ffr::scene::{SceneText, SceneValue};
use std::path::Path;

fn spin_up() -> SceneText {
    SceneText::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/spin_up.toml")).unwrap()
}

fn flex(spec: &ffr::scene::SceneSpec) -> &ffr::scene::FlexSpec {
    match &spec.bodies[0].kind {
        BodyKind::Flexible(f) => f,
        other => panic!("not flexible: {other:?}"),
    }
}

#[test]
fn every_key_kind_reaches_the_resolved_scene() {
    let mut s = spin_up();
    let before = s.text();
    s.set("bodies.beam.params.e", 7e10.into()).unwrap(); // in an inline table
    s.set("joints.0.drive.omega", 2.5.into()).unwrap(); // an array of tables, by index
    s.set("bodies.beam.elements", 4.into()).unwrap(); // a table's integer
    s.set("t_end", 3.0.into()).unwrap(); // the top level
    s.set("bodies.beam.position.1", 0.5.into()).unwrap(); // an array element
    s.set(
        "bodies.beam.stiffening",
        SceneValue::Str("second-order".into()),
    )
    .unwrap();
    let spec = s.spec().unwrap();
    let f = flex(&spec);
    assert_eq!(f.params.e, 7e10);
    assert_eq!(f.elements, 4);
    assert_eq!(spec.t_end, 3.0);
    assert_eq!(spec.bodies[0].position, [0.0, 0.5, 0.0]);
    assert!(matches!(
        spec.joints[0].drive.as_ref().map(|d| d.0),
        Some(ProfileSpec::SpinUp { omega, .. }) if omega == 2.5
    ));
    // The layout is kept: the same lines, and a replaced value in its place.
    assert_eq!(s.text().lines().count(), before.lines().count());
    assert_eq!(s.get("bodies.beam.params.e"), Some(SceneValue::Float(7e10)));
    assert_eq!(s.get("joints.0.drive.omega"), Some(SceneValue::Float(2.5)));
    assert_eq!(s.overrides().len(), 6);
}

#[test]
fn a_set_scene_runs_bit_identically_to_the_file_edited_by_hand() {
    let mut s = spin_up();
    s.set("joints.0.drive.omega", 2.0.into()).unwrap();
    s.set("t_end", 1.0.into()).unwrap();
    let by_key = ffr::scene::run(&s.load().unwrap()).unwrap();
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/spin_up.toml"))
            .unwrap()
            .replace("t_end = 20.0", "t_end = 1.0")
            .replace("omega = 4.0", "omega = 2.0");
    let spec_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let by_hand = ffr::scene::run(
        &ffr::scene::from_str(
            &text,
            "spin_up.toml",
            &spec_dir,
            &ffr::scene::DefaultKernels,
        )
        .unwrap(),
    )
    .unwrap();
    assert_eq!(by_key.columns.len(), by_hand.columns.len());
    for (a, b) in by_key.columns.iter().zip(&by_hand.columns) {
        let a: Vec<u64> = a.iter().map(|x| x.to_bits()).collect();
        let b: Vec<u64> = b.iter().map(|x| x.to_bits()).collect();
        assert_eq!(a, b);
    }
}

#[test]
fn bad_keys_are_refused_with_the_place_and_what_is_there() {
    let mut s = spin_up();
    let msg = |r: Result<(), ffr::SceneError>| r.unwrap_err().to_string();
    let m = msg(s.set("bodies.beem.params.e", 1.0.into()));
    assert!(
        m.contains("spin_up.toml: key `bodies.beem.params.e`"),
        "{m}"
    );
    assert!(
        m.contains("`bodies` has no `beem`") && m.contains("beam"),
        "{m}"
    );
    let m = msg(s.set("joints.3.drive.omega", 1.0.into()));
    assert!(m.contains("`joints` has no `3`"), "{m}");
    let m = msg(s.set("t_end.x", 1.0.into()));
    assert!(
        m.contains("`t_end` is a number, not a table or an array"),
        "{m}"
    );
    let m = msg(s.set("bodies..e", 1.0.into()));
    assert!(m.contains("empty segment"), "{m}");
    let m = msg(s.set("bodies.beam.position.7", 1.0.into()));
    assert!(m.contains("an array of 2; `7` is not an index"), "{m}");
    let m = msg(s.set("joints", 1.0.into()));
    assert!(m.contains("is an array of tables"), "{m}");
    let m = msg(s.set("bodies.beam.params.e", f64::NAN.into()));
    assert!(m.contains("not a finite number"), "{m}");
    let m = msg(s.set(&"x.".repeat(400), 1.0.into()));
    assert!(m.contains("longer than 512 bytes"), "{m}");
    let mut deep = SceneValue::Float(1.0);
    for _ in 0..=ffr::scene::edit::MAX_VALUE_DEPTH {
        deep = SceneValue::Array(vec![deep]);
    }
    let m = msg(s.set("bodies.beam.position", deep));
    assert!(m.contains("nested more than 32"), "{m}");
    // Nothing was set by the refusals.
    assert!(s.overrides().is_empty());
    assert_eq!(
        s.get("bodies.beam.params.e"),
        Some(SceneValue::Float(6.8952e10))
    );
}

#[test]
fn bad_values_get_the_loaders_located_message_with_the_keys_set() {
    let mut s = spin_up();
    s.set("bodies.beam.elements", 0.into()).unwrap();
    let e = s.spec().unwrap_err();
    let at = e.location.clone().expect("located");
    // `elements = 8` is line 12 of the file; the edit keeps the line.
    assert!(at.file.ends_with("spin_up.toml") && at.line == 12, "{e}");
    assert!(
        e.message.ends_with("(with bodies.beam.elements = 0)"),
        "{e}"
    );
    // An unknown key the file leaves out is refused by the loader, located.
    let mut s = spin_up();
    s.set("bodies.beam.paramz", 1.0.into()).unwrap();
    let e = s.spec().unwrap_err().to_string();
    assert!(e.contains("paramz"), "{e}");
    // A value of the wrong type.
    let mut s = spin_up();
    s.set("dt", SceneValue::Str("fast".into())).unwrap();
    let e = s.spec().unwrap_err();
    assert!(
        e.location.is_some() && e.to_string().contains("dt = \"fast\""),
        "{e}"
    );
}

#[test]
fn syntax_errors_are_located() {
    let e = SceneText::parse("t_end = \n", "x.toml", Path::new(".")).unwrap_err();
    let at = e.location.expect("located");
    assert_eq!((at.file.as_str(), at.line), ("x.toml", 1));
}

fn l_frame() -> SceneText {
    SceneText::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/l_frame.toml")).unwrap()
}

fn point_profile(spec: &ffr::scene::SceneSpec) -> Option<ForceProfile> {
    match &spec.forces[0].kind {
        ForceKind::Point { profile, .. } => profile.clone(),
        other => panic!("not a point force: {other:?}"),
    }
}

/// A point force's `profile` by dotted keys: its table (integers and
/// floats alike), a whole profile table in its place, and a bad table
/// refused by the loader at its row with the key set named.
#[test]
fn a_force_profile_is_set_by_its_keys() {
    let mut s = l_frame();
    let int = |i: i64| SceneValue::Int(i);
    s.set(
        "forces.0.profile.table",
        SceneValue::Array(vec![
            SceneValue::Array(vec![int(0), int(0)]),
            SceneValue::Array(vec![int(1), int(1)]),
        ]),
    )
    .unwrap();
    assert_eq!(
        point_profile(&s.spec().unwrap()),
        Some(ForceProfile::Table(vec![[0.0, 0.0], [1.0, 1.0]]))
    );
    assert_eq!(
        s.get("forces.0.profile.table.1"),
        Some(SceneValue::Array(vec![int(1), int(1)]))
    );
    s.set(
        "forces.0.profile",
        SceneValue::Table(vec![
            ("kind".into(), "harmonic".into()),
            ("amplitude".into(), 2.0.into()),
            ("frequency".into(), 0.5.into()),
        ]),
    )
    .unwrap();
    assert_eq!(
        point_profile(&s.spec().unwrap()),
        Some(ForceProfile::Drive(ProfileSpec::Harmonic {
            start: 0.0,
            amplitude: 2.0,
            frequency: 0.5,
            phase: 0.0
        }))
    );
    s.set("forces.0.profile.frequency", 1.5.into()).unwrap();
    assert!(matches!(
        point_profile(&s.spec().unwrap()),
        Some(ForceProfile::Drive(ProfileSpec::Harmonic { frequency, .. })) if frequency == 1.5
    ));
    // Times that do not increase: the loader's message, at the table's line.
    let mut s = l_frame();
    let row = |t: f64, f: f64| SceneValue::Array(vec![t.into(), f.into()]);
    s.set(
        "forces.0.profile.table",
        SceneValue::Array(vec![row(0.0, 0.0), row(0.0, 1.0)]),
    )
    .unwrap();
    let e = s.spec().unwrap_err();
    let line =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/l_frame.toml"))
            .unwrap()
            .lines()
            .position(|l| l.starts_with("profile = "))
            .unwrap()
            + 1;
    assert_eq!(e.location.as_ref().map(|l| l.line), Some(line), "{e}");
    assert!(
        e.message
            .contains("row 2 of the profile `table`: the time 0.0 is not after row 1's 0.0"),
        "{e}"
    );
    assert!(
        e.message
            .contains("(with forces.0.profile.table = [[0, 0], [0, 1]])"),
        "{e}"
    );
}

/// A marker by dotted keys: a string replaced by a table with axes and
/// back, and a table's angle on its own.
#[test]
fn a_marker_is_set_as_a_string_or_a_table() {
    let mut s = l_frame();
    let a = |spec: &ffr::scene::SceneSpec| spec.joints[1].a.clone().unwrap();
    assert_eq!(
        a(&s.spec().unwrap()).axes,
        Some(Orientation::Planar(std::f64::consts::FRAC_PI_2))
    );
    s.set("joints.1.a", "leg1@x=0.5".into()).unwrap();
    let m = a(&s.spec().unwrap());
    assert_eq!((m.text.as_str(), m.axes), ("leg1@x=0.5", None));
    assert_eq!(s.get("joints.1.a"), Some("leg1@x=0.5".into()));
    s.set(
        "joints.1.a",
        SceneValue::Table(vec![
            ("at".into(), "leg1@x=1.0".into()),
            (
                "axes".into(),
                SceneValue::Table(vec![("angle".into(), 0.25.into())]),
            ),
        ]),
    )
    .unwrap();
    let m = a(&s.spec().unwrap());
    assert_eq!(
        (m.text.as_str(), m.axes),
        ("leg1@x=1.0", Some(Orientation::Planar(0.25)))
    );
    s.set("joints.1.a.axes.angle", 1.0.into()).unwrap();
    assert_eq!(a(&s.spec().unwrap()).axes, Some(Orientation::Planar(1.0)));
    s.set("joints.1.a.at", "leg1@x=0.9".into()).unwrap();
    assert_eq!(a(&s.spec().unwrap()).text, "leg1@x=0.9");
    // A key a marker table does not have: the loader's located error.
    s.set("joints.1.a.axis", SceneValue::Array(vec![0.0.into(); 3]))
        .unwrap();
    let e = s.spec().unwrap_err().to_string();
    assert!(
        e.contains("unknown field `axis`, expected `at` or `axes`"),
        "{e}"
    );
}

/// A key set again replaces its earlier value (also spelt with a leading
/// zero, the same array entry), a whole value replaces the keys set inside
/// it, and 20 000 sets of one key keep one override: the list, and the
/// error messages that name it, stay short.
#[test]
fn a_key_set_again_replaces_its_value() {
    let mut s = spin_up();
    for i in 0..20_000 {
        s.set("t_end", SceneValue::Float(1.0 + i as f64)).unwrap();
    }
    assert_eq!(
        s.overrides(),
        &[("t_end".into(), SceneValue::Float(20_000.0))]
    );
    s.set("joints.0.drive.omega", 2.0.into()).unwrap();
    s.set("joints.00.drive.omega", 3.0.into()).unwrap();
    let keys: Vec<&str> = s.overrides().iter().map(|(k, _)| k.as_str()).collect();
    assert_eq!(keys, ["t_end", "joints.00.drive.omega"]);
    assert_eq!(s.get("joints.0.drive.omega"), Some(SceneValue::Float(3.0)));
    // The drive as a whole: the key inside it is dropped.
    s.set(
        "joints.0.drive",
        SceneValue::Table(vec![
            ("angle".into(), "constant-rate".into()),
            ("omega".into(), 1.0.into()),
        ]),
    )
    .unwrap();
    let keys: Vec<&str> = s.overrides().iter().map(|(k, _)| k.as_str()).collect();
    assert_eq!(keys, ["t_end", "joints.0.drive"]);
    // The keys named in a message: each once, in the order last set.
    s.set("bodies.beam.params.e", 7e10.into()).unwrap();
    s.set("bodies.beam.elements", 0.into()).unwrap();
    let e = s.spec().unwrap_err().to_string();
    assert!(
        e.ends_with(
            "(with t_end = 20000, joints.0.drive = { angle = \"constant-rate\", omega = 1 }, bodies.beam.params.e = 7e10, bodies.beam.elements = 0)"
        ),
        "{e}"
    );
}

/// At most `MAX_OVERRIDES` distinct keys, the bound named in the refusal;
/// an error message lists 8 of them and counts the rest.
#[test]
fn distinct_keys_are_bounded_and_listed_briefly() {
    use ffr::scene::edit::MAX_OVERRIDES;
    let rows = MAX_OVERRIDES + 10;
    let table = (0..rows)
        .map(|i| format!("[{i}.0, 0.0]"))
        .collect::<Vec<_>>()
        .join(", ");
    let text = format!(
        "t_end = 1.0\ndt = 0.1\n[[forces]]\nkind = \"point\"\nat = \"ground\"\nforce = [1.0, 0.0]\nprofile = {{ table = [{table}] }}\n"
    );
    let mut s = SceneText::parse(&text, "big.toml", Path::new(".")).unwrap();
    for i in 0..MAX_OVERRIDES {
        s.set(&format!("forces.0.profile.table.{i}.1"), 1.0.into())
            .unwrap();
    }
    let e = s
        .set(
            &format!("forces.0.profile.table.{MAX_OVERRIDES}.1"),
            1.0.into(),
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("more than 256 distinct keys") && e.contains("MAX_OVERRIDES"),
        "{e}"
    );
    // A key set before is still replaced; the whole table replaces them all.
    s.set("forces.0.profile.table.0.1", 2.0.into()).unwrap();
    assert_eq!(s.overrides().len(), MAX_OVERRIDES);
    s.set("t_end", 0.0.into()).unwrap_err();
    s.set(
        "forces.0.profile.table",
        SceneValue::Array(vec![SceneValue::Array(vec![0.0.into(), 1.0.into()])]),
    )
    .unwrap();
    assert_eq!(s.overrides().len(), 1);
    for i in 0..20 {
        s.set(&format!("x{i}"), 1.0.into()).unwrap();
    }
    let e = s.spec().unwrap_err().to_string();
    assert!(e.ends_with(", and 13 more)"), "{e}");
    assert!(e.len() < 1000, "{e}");
}

/// `get` of a table and of an array of tables gives them (as the file
/// holds them), not `None`.
#[test]
fn get_gives_tables_and_arrays_of_tables() {
    let s = spin_up();
    let Some(SceneValue::Table(bodies)) = s.get("bodies") else {
        panic!("{:?}", s.get("bodies"))
    };
    assert_eq!(bodies.len(), 1);
    assert_eq!(bodies[0].0, "beam");
    let SceneValue::Table(beam) = &bodies[0].1 else {
        panic!("{bodies:?}")
    };
    assert!(beam.contains(&("elements".into(), SceneValue::Int(8))));
    assert_eq!(s.get("bodies.beam"), Some(bodies[0].1.clone()));
    let Some(SceneValue::Array(joints)) = s.get("joints") else {
        panic!("{:?}", s.get("joints"))
    };
    assert_eq!(joints.len(), 1);
    assert_eq!(s.get("joints.0"), Some(joints[0].clone()));
    let Some(SceneValue::Array(outputs)) = s.get("outputs") else {
        panic!()
    };
    assert_eq!(outputs.len(), 2);
    assert_eq!(s.get("nothing"), None);
}

/// User text in the messages of `set` is escaped (a key with an escape
/// sequence, a bidi override, a newline) and cut.
#[test]
fn keys_in_messages_are_escaped() {
    let mut s = spin_up();
    for key in [
        "bodies.\u{1b}]0;owned\u{7}\u{1b}[2J.e",
        "bodies.beam.position.\u{202e}1",
        "joints.0.drive.omega.x\ny",
        "t_end.\u{1b}[31m",
    ] {
        let e = s.set(key, 1.0.into()).unwrap_err().to_string();
        assert!(
            !e.chars()
                .any(|c| c.is_control() || ('\u{202a}'..='\u{202e}').contains(&c)),
            "{e:?}"
        );
        assert!(e.contains("\\u{") || e.contains("\\n"), "{e}");
    }
    let long = format!("nope.{}", "z".repeat(400));
    let e = s.set(&long, 1.0.into()).unwrap_err().to_string();
    assert!(e.len() < 400, "{e}");
}

/// The values listed in a message are in short form (issue 36: a value of
/// 1e308 printed 309 digits).
#[test]
fn values_in_messages_are_short() {
    let mut s = spin_up();
    s.set("bodies.beam.params.e", 1e308.into()).unwrap();
    s.set("bodies.beam.elements", 0.into()).unwrap();
    let e = s.spec().unwrap_err().to_string();
    assert!(e.contains("bodies.beam.params.e = 1e308"), "{e}");
    assert!(!e.contains("0000000000"), "{e}");
}
