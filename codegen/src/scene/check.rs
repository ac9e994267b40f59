//! Every key of a scene file checked against its table's kind (a key that
//! does not apply is a located error), drive profiles and motors checked
//! before anything is built.

use super::{
    body_type_name, scene_err, RawForceProfile, RawMarker, RawProfile, RawScene, RawTarget,
};
use crate::error::Error;
use std::collections::BTreeMap;
use std::ops::Range;
use toml::Spanned;

/// The span of the key whose value is at `value` (the text before it reads
/// `key =`, bare or quoted); the value's own span otherwise.
fn key_span(text: &str, value: Range<usize>) -> Range<usize> {
    let Some(before) = text.get(..value.start) else {
        return value;
    };
    let Some(t) = before.trim_end().strip_suffix('=') else {
        return value;
    };
    let t = t.trim_end();
    let end = t.len();
    let start = match t.chars().last() {
        Some(q @ ('"' | '\'')) => t[..end - 1].rfind(q).unwrap_or(end),
        _ => t
            .char_indices()
            .rev()
            .find(|(_, c)| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-')))
            .map_or(0, |(i, c)| i + c.len_utf8()),
    };
    if start < end {
        start..end
    } else {
        value
    }
}

/// The keys of a table that are present, with their values' spans.
type Keys = Vec<(&'static str, Range<usize>)>;

fn keys<const N: usize>(list: [(&'static str, Option<Range<usize>>); N]) -> Keys {
    let mut out: Keys = list
        .into_iter()
        .filter_map(|(k, s)| s.map(|s| (k, s)))
        .collect();
    out.sort_by_key(|(_, s)| s.start);
    out
}

fn sp<T>(v: &Option<Spanned<T>>) -> Option<Range<usize>> {
    v.as_ref().map(|x| x.span())
}

/// The first key of `present` that `takes` does not list, as the error
/// `` `key` does not apply to WHAT: it takes `a`, `b`, … `` (and the hint for
/// that key, if any), at the key.
fn applies(
    text: &str,
    file: &str,
    present: &Keys,
    takes: &[&str],
    what: &str,
    hints: &[(&str, &str)],
) -> Result<(), Error> {
    for (k, span) in present {
        if !takes.contains(k) {
            let list: Vec<String> = takes.iter().map(|t| format!("`{t}`")).collect();
            let hint = hints
                .iter()
                .find(|(h, _)| h == k)
                .map_or(String::new(), |(_, h)| format!(" ({h})"));
            return Err(scene_err(
                text,
                file,
                key_span(text, span.clone()),
                format!(
                    "`{k}` does not apply to {what}: it takes {}{hint}",
                    list.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// A drive's (or a motor target's) profile table: `key` (`angle` or `slide`)
/// names the profile, and each profile takes its own keys.
fn check_profile(
    text: &str,
    file: &str,
    p: &RawProfile,
    key: &str,
    owner: &str,
) -> Result<(), Error> {
    check_profile_as(text, file, p, key, key, owner)
}

/// [`check_profile`], the key that names the profile shown as `label` in
/// the list of keys that apply (a force's profile is named by `kind`).
fn check_profile_as(
    text: &str,
    file: &str,
    p: &RawProfile,
    key: &str,
    label: &str,
    owner: &str,
) -> Result<(), Error> {
    let all = keys([
        ("angle", sp(&p.angle)),
        ("slide", sp(&p.slide)),
        ("omega", sp(&p.omega)),
        ("ramp", sp(&p.ramp)),
        ("value", sp(&p.value)),
        ("start", sp(&p.start)),
        ("rate", sp(&p.rate)),
        ("amplitude", sp(&p.amplitude)),
        ("frequency", sp(&p.frequency)),
        ("phase", sp(&p.phase)),
    ]);
    let other = if key == "angle" { "slide" } else { "angle" };
    if let Some((_, span)) = all.iter().find(|(k, _)| *k == other) {
        return Err(scene_err(
            text,
            file,
            key_span(text, span.clone()),
            format!(
                "`{other}` does not apply to {owner}: it takes `{key} = \"PROFILE\"` ({})",
                if key == "angle" {
                    "the relative angle; `slide` is for prismatic joints"
                } else {
                    "the relative displacement along `a`'s x axis; `angle` is for revolute joints and motors"
                }
            ),
        ));
    }
    let name = if key == "angle" { &p.angle } else { &p.slide };
    let Some(name) = name else { return Ok(()) };
    let takes: &[&str] = match name.get_ref().as_str() {
        "spin-up" => &["omega", "ramp", "start"],
        "constant-rate" => {
            if let (Some(_), Some(r)) = (&p.omega, &p.rate) {
                return Err(scene_err(
                    text,
                    file,
                    key_span(text, r.span()),
                    "`rate` and `omega` both give the rate of profile `constant-rate`: give one"
                        .into(),
                ));
            }
            &["omega", "rate", "start"]
        }
        "constant" => &["value"],
        "harmonic" => &["amplitude", "frequency", "start", "phase"],
        // Reported by the loader with the list of profiles.
        _ => return Ok(()),
    };
    let takes: Vec<&str> = std::iter::once(label)
        .chain(takes.iter().copied())
        .collect();
    let present: Keys = all.into_iter().filter(|(k, _)| *k != key).collect();
    applies(
        text,
        file,
        &present,
        &takes,
        &format!("profile `{}` ({owner})", name.get_ref()),
        &[
            ("start", "`value` is the value of a constant profile"),
            ("ramp", "`ramp` is the ramp time of profile `spin-up`"),
        ],
    )
}

/// A point force's `profile`: `kind = "PROFILE"` with that drive
/// profile's keys, or `table` alone.
fn check_force_profile(text: &str, file: &str, p: &RawForceProfile) -> Result<(), Error> {
    let all = keys([
        ("kind", sp(&p.kind)),
        ("table", sp(&p.table)),
        ("omega", sp(&p.omega)),
        ("ramp", sp(&p.ramp)),
        ("value", sp(&p.value)),
        ("start", sp(&p.start)),
        ("rate", sp(&p.rate)),
        ("amplitude", sp(&p.amplitude)),
        ("frequency", sp(&p.frequency)),
        ("phase", sp(&p.phase)),
    ]);
    if let (Some(_), Some(_)) = (&p.kind, &p.table) {
        // At the second of the two keys.
        let (k, span) = all
            .iter()
            .filter(|(k, _)| *k == "kind" || *k == "table")
            .nth(1)
            .expect("both present");
        let other = if *k == "kind" { "table" } else { "kind" };
        return Err(scene_err(
            text,
            file,
            key_span(text, span.clone()),
            format!(
                "`{k}` and `{other}` both give the force's profile: give `kind = \"PROFILE\"` (a drive profile with its keys) or `table = [[t0, f0], …]`, not both"
            ),
        ));
    }
    if p.table.is_some() {
        return applies(
            text,
            file,
            &all,
            &["table"],
            "a table profile (`table`)",
            &[],
        );
    }
    check_profile_as(
        text,
        file,
        &p.as_drive(),
        "angle",
        "kind",
        "a point force's profile",
    )
}

/// A marker table's `axes`: a planar scene's turn about z and take no
/// `axis`.
fn check_marker(
    text: &str,
    file: &str,
    m: &Spanned<RawMarker>,
    spatial: bool,
) -> Result<(), Error> {
    let RawMarker::Table(t) = m.get_ref() else {
        return Ok(());
    };
    let Some(a) = &t.axes else { return Ok(()) };
    let a = a.get_ref();
    let present = keys([("axis", sp(&a.axis)), ("angle", sp(&a.angle))]);
    let takes: &[&str] = if spatial {
        &["axis", "angle"]
    } else {
        &["angle"]
    };
    applies(
        text,
        file,
        &present,
        takes,
        "a marker's `axes` in a planar scene (a rotation about z)",
        &[],
    )
}

/// Check what the deserializer cannot: body names (they become generated
/// identifiers: ASCII Rust identifiers of at most 64 characters, not
/// keywords, distinct after conversion to CamelCase; `ground` reserved),
/// and that every key present applies to its table's kind (an integrator's,
/// body's, joint's, drive profile's, motor's, force's or output's): a key
/// that would do nothing is an error at the key, naming the keys that
/// apply. Kinds that do not exist are left to the loader, which lists them.
pub fn check(raw: &RawScene, text: &str, file: &str) -> Result<(), Error> {
    // Body names.
    let mut types: BTreeMap<String, &str> = BTreeMap::new();
    for name in raw.bodies.keys() {
        let n = name.get_ref().as_str();
        let at = name.span();
        if n == "ground" {
            return Err(scene_err(
                text,
                file,
                at,
                "`ground` cannot name a body: it is the fixed frame of markers `ground@[…]`".into(),
            ));
        }
        crate::builder::type_name_of(n).map_err(|e| {
            let m = match e {
                Error::Name(m) => m,
                other => other.to_string(),
            };
            scene_err(text, file, at.clone(), m)
        })?;
        let ty = body_type_name(n);
        if let Some(first) = types.get(&ty) {
            return Err(scene_err(
                text,
                file,
                at,
                format!(
                    "bodies `{first}` and `{n}` both give the generated name `{ty}` (a compiled scene's kernel type `…{ty}Kernels`): body names must differ after conversion to CamelCase"
                ),
            ));
        }
        types.insert(ty, n);
    }
    // The integrator.
    if let Some(i) = &raw.integrator {
        let i = i.get_ref();
        let present = keys([
            ("rho_inf", sp(&i.rho_inf)),
            ("rtol", sp(&i.rtol)),
            ("alpha", sp(&i.alpha)),
            ("beta", sp(&i.beta)),
        ]);
        let hints = [
            ("alpha", "`alpha` and `beta` are the Baumgarte gains of `kind = \"rk4\"`"),
            ("beta", "`alpha` and `beta` are the Baumgarte gains of `kind = \"rk4\"`"),
            ("rho_inf", "`rho_inf` and `rtol` are for `kind = \"generalized-alpha\"`"),
            ("rtol", "`rho_inf` and `rtol` are for `kind = \"generalized-alpha\"`: RK4 has no Newton iteration"),
        ];
        match i.kind.get_ref().as_str() {
            "generalized-alpha" => applies(
                text,
                file,
                &present,
                &["kind", "rho_inf", "rtol"],
                "the generalized-alpha integrator",
                &hints,
            )?,
            "rk4" => applies(
                text,
                file,
                &present,
                &["kind", "alpha", "beta"],
                "the rk4 integrator",
                &hints,
            )?,
            _ => {}
        }
    }
    // Bodies: rigid (`mass`) or flexible (`shape`).
    let spatial = *raw.dimension.get_ref() == 3;
    let orientation = if spatial { "orientation" } else { "angle" };
    for (name, rb) in &raw.bodies {
        let n = name.get_ref();
        // The planar/spatial pose keys have their own messages (the loader).
        let present: Keys = keys([
            ("shape", sp(&rb.shape)),
            ("elements", sp(&rb.elements)),
            ("nodes", sp(&rb.nodes)),
            ("segments", sp(&rb.segments)),
            ("sections", sp(&rb.sections)),
            ("reference", sp(&rb.reference)),
            ("stiffening", sp(&rb.stiffening)),
            ("formalism", sp(&rb.formalism)),
            ("params", sp(&rb.params)),
            ("damping", sp(&rb.damping)),
            ("modes", sp(&rb.modes)),
            ("reduction", sp(&rb.reduction)),
            ("boundary_nodes", sp(&rb.boundary_nodes)),
            ("modal_damping", sp(&rb.modal_damping)),
            ("static_modes", sp(&rb.static_modes)),
            ("elastic", sp(&rb.elastic)),
            ("mass", sp(&rb.mass)),
            ("inertia", sp(&rb.inertia)),
            ("centre", sp(&rb.centre)),
            ("fe", sp(&rb.fe)),
            ("interface", sp(&rb.interface)),
        ]);
        let both = ["position", orientation, "velocity", "omega"];
        if rb.mass.is_some() {
            let takes: Vec<&str> = ["mass", "inertia", "centre"]
                .into_iter()
                .chain(both)
                .collect();
            applies(
                text,
                file,
                &present,
                &takes,
                &format!("rigid body `{n}` (it has `mass`)"),
                &[
                    (
                        "damping",
                        "Rayleigh `damping` is for the elastic coordinates of a flexible body",
                    ),
                    (
                        "elastic",
                        "`elastic` is the initial state of a flexible body",
                    ),
                    (
                        "segments",
                        "`segments` splits a flexible beam into FFR sub-bodies; a rigid body has one frame",
                    ),
                ],
            )?;
        } else if rb.fe.is_some() {
            let takes: Vec<&str> = [
                "fe",
                "reference",
                "interface",
                "modes",
                "reduction",
                "boundary_nodes",
                "static_modes",
                "modal_damping",
                "damping",
                "elastic",
            ]
            .into_iter()
            .chain(both)
            .collect();
            applies(
                text,
                file,
                &present,
                &takes,
                &format!("FE body `{n}` (it has `fe`)"),
                &[
                    ("shape", "an FE body's geometry is its mesh (`fe`): give `shape` (a beam) or `fe`, not both"),
                    ("stiffening", "geometric stiffening is not available from M and K alone: it needs the stress-dependent geometric stiffness of the elements, which the mass and stiffness matrices do not carry, so an FE body is linear elastic in its frame"),
                    ("elements", "an FE body's mesh is its node file (`fe.nodes`)"),
                    ("segments", "`segments` splits a beam at nodes of its axis; an FE body is reduced as one body"),
                    ("nodes", "an FE body's nodes are its node file (`fe.nodes`); `nodes` is a beam's graded mesh"),
                    ("params", "an FE body's properties are in its mass and stiffness matrices"),
                    ("sections", "an FE body's properties are in its mass and stiffness matrices"),
                    ("formalism", "an FE body's mass matrix is the one the FE code exported (consistent or lumped)"),
                    ("inertia", "an FE body's inertia follows from its mass matrix"),
                    ("centre", "an FE body's centre of mass follows from its mass matrix"),
                ],
            )?;
        } else if rb.shape.is_some() {
            let takes: Vec<&str> = [
                "shape",
                "elements",
                "nodes",
                "segments",
                "sections",
                "reference",
                "stiffening",
                "formalism",
                "params",
                "damping",
                "modes",
                "reduction",
                "boundary_nodes",
                "static_modes",
                "modal_damping",
                "elastic",
            ]
            .into_iter()
            .chain(both)
            .collect();
            applies(
                text,
                file,
                &present,
                &takes,
                &format!("flexible body `{n}` (it has `shape`)"),
                &[
                    (
                        "inertia",
                        "a flexible body's inertia follows from its shape and `params`",
                    ),
                    (
                        "centre",
                        "a flexible body's centre of mass follows from its shape and `params`",
                    ),
                ],
            )?;
        }
    }
    // Markers with their own axes.
    let markers = raw
        .joints
        .iter()
        .flat_map(|j| [j.a.as_ref(), Some(&j.b)])
        .chain(
            raw.forces
                .iter()
                .flat_map(|f| [f.at.as_ref(), f.a.as_ref(), f.b.as_ref()]),
        )
        .chain(
            raw.outputs
                .iter()
                .flat_map(|o| [o.at.as_ref(), o.a.as_ref()]),
        );
    for m in markers.flatten() {
        check_marker(text, file, m, spatial)?;
    }
    // Joints, their drives and motors.
    for j in &raw.joints {
        let kind = j.kind.get_ref().as_str();
        let present = keys([
            ("a", sp(&j.a)),
            ("b", Some(j.b.span())),
            ("drive", sp(&j.drive)),
            ("motor", sp(&j.motor)),
        ]);
        let takes: &[&str] = match kind {
            "ground" => &["kind", "b"],
            "fixed" | "spherical" => &["kind", "a", "b"],
            "revolute" => &["kind", "a", "b", "drive", "motor"],
            "prismatic" => &["kind", "a", "b", "drive"],
            _ => continue,
        };
        applies(
            text,
            file,
            &present,
            takes,
            &format!("a `{kind}` joint"),
            &[
                ("a", "a `ground` joint fixes body `b` where it starts"),
                (
                    "drive",
                    "drives are for revolute (angle) and prismatic (slide) joints",
                ),
                (
                    "motor",
                    "motors act in revolute joints (a torque about the joint axis)",
                ),
            ],
        )?;
        if let (Some(_), Some(m)) = (&j.drive, &j.motor) {
            return Err(scene_err(
                text,
                file,
                key_span(text, m.span()),
                "`motor` does not apply to a driven revolute joint: its `drive` prescribes the angle, so a motor's torque would change nothing; give `drive` or `motor`".into(),
            ));
        }
        if let Some(d) = &j.drive {
            let key = if kind == "prismatic" {
                "slide"
            } else {
                "angle"
            };
            check_profile(
                text,
                file,
                d.get_ref(),
                key,
                &format!("the drive of a `{kind}` joint"),
            )?;
        }
        if let Some(m) = &j.motor {
            let m = m.get_ref();
            let present = keys([
                ("torque", sp(&m.torque)),
                ("target", sp(&m.target)),
                ("kp", sp(&m.kp)),
                ("kd", sp(&m.kd)),
            ]);
            if m.torque.is_some() {
                applies(
                    text,
                    file,
                    &present,
                    &["torque"],
                    "a constant-torque motor (`torque`)",
                    &[
                        (
                            "target",
                            "a PD motor is `{ target = φ, kp = …, kd = … }`, without `torque`",
                        ),
                        ("kp", "`kp` and `kd` are the gains of a PD motor (`target`)"),
                        ("kd", "`kp` and `kd` are the gains of a PD motor (`target`)"),
                    ],
                )?;
            }
            if let Some(t) = &m.target {
                if let RawTarget::Profile(p) = t.get_ref() {
                    check_profile(text, file, p, "angle", "a motor's target")?;
                }
            }
        }
    }
    // Forces.
    for f in &raw.forces {
        let kind = f.kind.get_ref().as_str();
        let present = keys([
            ("at", sp(&f.at)),
            ("a", sp(&f.a)),
            ("b", sp(&f.b)),
            ("force", sp(&f.force)),
            ("axes", sp(&f.axes)),
            ("stiffness", sp(&f.stiffness)),
            ("damping", sp(&f.damping)),
            ("rest_length", sp(&f.rest_length)),
            ("rest_angle", sp(&f.rest_angle)),
            ("torque", sp(&f.torque)),
            ("profile", sp(&f.profile)),
        ]);
        let takes: &[&str] = match kind {
            "point" => &["kind", "at", "force", "axes", "profile"],
            "spring-damper" => &["kind", "a", "b", "stiffness", "rest_length", "damping"],
            "rotational-spring-damper" => &["kind", "a", "b", "stiffness", "damping", "rest_angle"],
            "torque" => &["kind", "a", "b", "torque"],
            _ => continue,
        };
        applies(
            text,
            file,
            &present,
            takes,
            &format!("a `{kind}` force"),
            &[
                (
                    "rest_angle",
                    "`rest_angle` is for a `rotational-spring-damper`",
                ),
                ("rest_length", "`rest_length` is for a `spring-damper`"),
                (
                    "profile",
                    "a time function `profile` scales the vector of a `point` force",
                ),
            ],
        )?;
        if let (Some(p), "point") = (&f.profile, kind) {
            check_force_profile(text, file, p.get_ref())?;
        }
    }
    // Outputs.
    for o in &raw.outputs {
        let kind = o.kind.get_ref().as_str();
        let present = keys([
            ("at", sp(&o.at)),
            ("a", sp(&o.a)),
            ("component", sp(&o.component)),
        ]);
        let takes: &[&str] = match kind {
            "position" | "velocity" | "deflection" => &["name", "kind", "at", "component"],
            "angle" => &["name", "kind", "at", "a"],
            "energy" => &["name", "kind", "component"],
            _ => continue,
        };
        applies(
            text,
            file,
            &present,
            takes,
            &format!(
                "{} `{kind}` output",
                if kind.starts_with(['a', 'e']) {
                    "an"
                } else {
                    "a"
                }
            ),
            &[
                ("a", "`a` is the reference marker of an angle output"),
                ("at", "an energy is the whole system's"),
                (
                    "component",
                    "an angle output has one value (the angle about z)",
                ),
            ],
        )?;
    }
    Ok(())
}
