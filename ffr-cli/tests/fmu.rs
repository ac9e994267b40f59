//! `ffr fmu`: what the archive holds (the model description against the
//! scene, the scene and every file it reads under `resources/`, the
//! library), that it is written deterministically, that the packed
//! resources instantiate and step through the FMI functions as the scene
//! does (also when the scene reads a file above its directory), and its
//! refusals (each leaves an existing file alone).

mod common;
use common::cli::{ffr, s, scene, temp_dir};
use ffr_fmu::ffi::*;
use std::ffi::CString;
use std::io::Read;
use std::path::Path;

fn entries(fmu: &Path) -> Vec<String> {
    let z = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let mut names: Vec<String> = z.file_names().map(str::to_string).collect();
    names.sort();
    names
}

fn entry(fmu: &Path, name: &str) -> Vec<u8> {
    let mut z = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let mut out = Vec::new();
    z.by_name(name).unwrap().read_to_end(&mut out).unwrap();
    out
}

/// Unpack `fmu` into `dir`.
fn extract(fmu: &Path, dir: &Path) {
    let mut z = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    z.extract(dir).unwrap();
}

#[test]
fn the_archive_holds_the_description_the_library_and_every_file_the_scene_reads() {
    let dir = temp_dir("fmu", "blade");
    let out = dir.join("blade.fmu");
    let (ok, stdout, err) = ffr(&[
        "fmu",
        &scene("blade_5mw.toml"),
        "--out",
        s(&out),
        "--parameter",
        "joints.0.drive.omega",
    ]);
    assert!(ok, "{err}");
    assert!(
        stdout.contains("FMI 2.0 Co-Simulation (linux64)"),
        "{stdout}"
    );
    assert_eq!(
        entries(&out),
        [
            "binaries/linux64/blade.so",
            "modelDescription.xml",
            "resources/blade_5mw.toml",
            "resources/data/nrel5mw_blade.csv",
            "resources/ffr-fmu.json",
        ]
    );
    assert_eq!(
        entry(&out, "resources/data/nrel5mw_blade.csv"),
        std::fs::read(scene("data/nrel5mw_blade.csv")).unwrap()
    );
    let so = entry(&out, "binaries/linux64/blade.so");
    assert_eq!(&so[..4], b"\x7fELF");
    // The model description against the scene as loaded.
    let loaded = ffr::scene::load(Path::new(&scene("blade_5mw.toml"))).unwrap();
    let xml = String::from_utf8(entry(&out, "modelDescription.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let root = doc.root_element();
    assert_eq!(root.attribute("fmiVersion"), Some("2.0"));
    assert!(root
        .attribute("generationTool")
        .unwrap()
        .starts_with("ffr "));
    let cs = root
        .children()
        .find(|n| n.has_tag_name("CoSimulation"))
        .unwrap();
    assert_eq!(cs.attribute("modelIdentifier"), Some("blade"));
    assert_eq!(cs.attribute("canGetAndSetFMUstate"), Some("true"));
    let de = root
        .children()
        .find(|n| n.has_tag_name("DefaultExperiment"))
        .unwrap();
    assert_eq!(
        de.attribute("stepSize").unwrap().parse::<f64>().unwrap(),
        loaded.dt
    );
    assert_eq!(
        de.attribute("stopTime").unwrap().parse::<f64>().unwrap(),
        loaded.t_end
    );
    let vars: Vec<roxmltree::Node> = root
        .descendants()
        .filter(|n| n.has_tag_name("ScalarVariable"))
        .collect();
    let outputs: Vec<&str> = vars
        .iter()
        .filter(|v| v.attribute("causality") == Some("output"))
        .map(|v| v.attribute("name").unwrap())
        .collect();
    let names: Vec<&str> = loaded.outputs.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(outputs, names);
    let p = vars.last().unwrap();
    assert_eq!(p.attribute("name"), Some("joints.0.drive.omega"));
    assert_eq!(p.attribute("causality"), Some("parameter"));
    let start: f64 = p
        .first_element_child()
        .unwrap()
        .attribute("start")
        .unwrap()
        .parse()
        .unwrap();
    let text = ffr::scene::SceneText::read(Path::new(&scene("blade_5mw.toml"))).unwrap();
    assert_eq!(
        Some(ffr::scene::SceneValue::Float(start)),
        text.get("joints.0.drive.omega")
    );
    // Value references 0, 1, … in order; the outputs' indices in
    // ModelStructure are theirs (1-based).
    for (i, v) in vars.iter().enumerate() {
        assert_eq!(v.attribute("valueReference"), Some(i.to_string().as_str()));
    }
    // Deterministic: the same command writes the same bytes; another
    // parameter list gives another guid.
    let again = dir.join("again.fmu");
    let before = std::fs::read(&out).unwrap();
    let (ok, _, err) = ffr(&[
        "fmu",
        &scene("blade_5mw.toml"),
        "--out",
        s(&out),
        "--parameter",
        "joints.0.drive.omega",
    ]);
    assert!(ok, "{err}");
    assert_eq!(
        std::fs::read(&out).unwrap(),
        before,
        "replacing its own FMU"
    );
    let (ok, _, err) = ffr(&["fmu", &scene("blade_5mw.toml"), "--out", s(&again)]);
    assert!(ok, "{err}");
    let guid = |f: &Path| {
        let x = String::from_utf8(entry(f, "modelDescription.xml")).unwrap();
        let d = roxmltree::Document::parse(&x).unwrap();
        d.root_element().attribute("guid").unwrap().to_string()
    };
    assert_ne!(guid(&out), guid(&again));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_scene_reading_a_file_above_its_directory_is_packed_so_that_it_reads_it_there() {
    // sub/blade.toml reads ../data/nrel5mw_blade.csv: resources/sub/blade.toml
    // and resources/data/…; the unpacked FMU instantiates and steps as the
    // scene does.
    let dir = temp_dir("fmu", "climb");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::create_dir_all(dir.join("data")).unwrap();
    std::fs::copy(
        scene("data/nrel5mw_blade.csv"),
        dir.join("data/nrel5mw_blade.csv"),
    )
    .unwrap();
    let text = std::fs::read_to_string(scene("blade_5mw.toml"))
        .unwrap()
        .replace(
            "\"data/nrel5mw_blade.csv\"",
            "\"../data/nrel5mw_blade.csv\"",
        );
    let sc = dir.join("sub/blade.toml");
    std::fs::write(&sc, text).unwrap();
    let out = dir.join("climb.fmu");
    let (ok, _, err) = ffr(&["fmu", s(&sc), "--out", s(&out)]);
    assert!(ok, "{err}");
    let names = entries(&out);
    assert!(
        names.contains(&"resources/sub/blade.toml".to_string()),
        "{names:?}"
    );
    assert!(
        names.contains(&"resources/data/nrel5mw_blade.csv".to_string()),
        "{names:?}"
    );
    let unz = dir.join("unzipped");
    extract(&out, &unz);
    let manifest = ffr_fmu::description::Manifest::from_json(
        &std::fs::read_to_string(unz.join("resources/ffr-fmu.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(manifest.scene, "sub/blade.toml");
    // Step it through the C functions against the scene's own simulation.
    let mut sim =
        ffr::scene::Simulation::new(std::sync::Arc::new(ffr::scene::load(&sc).unwrap())).unwrap();
    let name = CString::new("climb").unwrap();
    let guid = CString::new(manifest.guid.clone()).unwrap();
    let uri = CString::new(format!("file://{}", unz.join("resources").display())).unwrap();
    let cb = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    let vrs: Vec<u32> = (0..manifest.outputs.len() as u32).collect();
    let mut got = vec![0.0; vrs.len()];
    // SAFETY: valid strings and callbacks; the component as FMI says.
    unsafe {
        let c = fmi2Instantiate(
            name.as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            uri.as_ptr(),
            &cb,
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2OK);
        let dt = manifest.dt;
        for k in 0..5u32 {
            assert_eq!(fmi2DoStep(c, f64::from(k) * 2.0 * dt, 2.0 * dt, 1), fmi2OK);
            sim.step().unwrap();
            sim.step().unwrap();
            assert_eq!(
                fmi2GetReal(c, vrs.as_ptr(), vrs.len(), got.as_mut_ptr()),
                fmi2OK
            );
            assert_eq!(got, sim.outputs());
        }
        fmi2FreeInstance(c);
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn refusals_name_the_problem_and_leave_files_alone() {
    let dir = temp_dir("fmu", "refuse");
    let sc = scene("spin_up.toml");
    let refused = |args: &[&str], says: &str| {
        let (ok, _, err) = ffr(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(err.contains(says), "{args:?}: {err}");
    };
    refused(
        &["fmu", &sc, "--out", s(&dir.join("x.zip"))],
        "--out needs a file name ending in .fmu",
    );
    // A file ffr did not write is not replaced.
    let foreign = dir.join("foreign.fmu");
    std::fs::write(&foreign, b"not a zip").unwrap();
    refused(
        &["fmu", &sc, "--out", s(&foreign)],
        "exists and is not a zip file",
    );
    assert_eq!(std::fs::read(&foreign).unwrap(), b"not a zip");
    let other = dir.join("other.fmu");
    {
        let mut w = zip::ZipWriter::new(std::fs::File::create(&other).unwrap());
        w.start_file(
            "modelDescription.xml",
            zip::write::SimpleFileOptions::default(),
        )
        .unwrap();
        std::io::Write::write_all(&mut w, b"<fmiModelDescription generationTool=\"Dymola\"/>")
            .unwrap();
        w.finish().unwrap();
    }
    let before = std::fs::read(&other).unwrap();
    refused(&["fmu", &sc, "--out", s(&other)], "was not written by ffr");
    assert_eq!(std::fs::read(&other).unwrap(), before);
    // Parameters.
    let out = dir.join("p.fmu");
    refused(
        &[
            "fmu",
            &sc,
            "--out",
            s(&out),
            "--parameter",
            "bodies.beam.params.x",
        ],
        "the scene sets no value at this key",
    );
    refused(
        &[
            "fmu",
            &sc,
            "--out",
            s(&out),
            "--parameter",
            "bodies.beam.shape",
        ],
        "not a number",
    );
    refused(
        &[
            "fmu",
            &sc,
            "--out",
            s(&out),
            "--parameter",
            "t_end",
            "--parameter",
            "t_end",
        ],
        "--parameter t_end is given twice",
    );
    // The library.
    let notlib = dir.join("lib.so");
    std::fs::write(&notlib, b"#!/bin/sh\n").unwrap();
    refused(
        &["fmu", &sc, "--out", s(&out), "--binary", s(&notlib)],
        "not an x86-64 Linux shared library",
    );
    refused(
        &[
            "fmu",
            &sc,
            "--out",
            s(&out),
            "--binary",
            s(&dir.join("none.so")),
        ],
        "cannot be read",
    );
    assert!(!out.exists());
    // An absolute path outside the scene's directory.
    let sub = dir.join("abs");
    std::fs::create_dir_all(&sub).unwrap();
    let text = std::fs::read_to_string(scene("blade_5mw.toml"))
        .unwrap()
        .replace(
            "\"data/nrel5mw_blade.csv\"",
            &format!("{:?}", scene("data/nrel5mw_blade.csv")),
        );
    std::fs::write(sub.join("b.toml"), text).unwrap();
    refused(
        &["fmu", s(&sub.join("b.toml")), "--out", s(&out)],
        "by an absolute path outside its directory",
    );
    let _ = std::fs::remove_dir_all(dir);
}
