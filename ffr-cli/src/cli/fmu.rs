//! `ffr fmu SCENE.toml --out NAME.fmu [--parameter KEY …]`: the scene as an
//! FMI 2.0 Co-Simulation unit for Linux x86-64 (see docs/in-the-loop.md,
//! "FMU").

use crate::output;
use ffr_fmu::description::{
    c_identifier, Fingerprint, Manifest, Parameter, GENERATION_TOOL, MANIFEST,
};
use std::error::Error;
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};

/// The shared library's file name beside the `ffr` executable.
pub const LIBRARY: &str = "libffr_fmu.so";

/// The largest `modelDescription.xml` read back from an existing `.fmu`
/// (to see whether ffr wrote it).
const MAX_DESCRIPTION_BYTES: u64 = 16 << 20;

/// Arguments of `ffr fmu`.
#[derive(clap::Args, Debug)]
pub struct FmuArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The FMU to write (NAME.fmu; NAME, as a C identifier, is its
    /// modelIdentifier). An existing file is replaced only if ffr wrote it.
    #[arg(long, value_name = "NAME.fmu")]
    pub out: PathBuf,
    /// A real parameter of the FMU: a dotted scene key with a number
    /// (`bodies.arm.params.e`, `joints.0.drive.omega`), set before
    /// initialization; the scene is re-resolved with it at
    /// fmi2ExitInitializationMode. Repeat for more.
    #[arg(long = "parameter", value_name = "KEY")]
    pub parameters: Vec<String>,
    /// The shared library to pack (default: libffr_fmu.so of the build of
    /// this ffr executable, beside it or in its deps/; `cargo build
    /// --release -p ffr-cli -p ffr-fmu` builds both).
    #[arg(long, value_name = "PATH")]
    pub binary: Option<PathBuf>,
}

/// What `ffr fmu` wrote.
#[derive(Debug)]
pub struct FmuWritten {
    /// The manifest (variables, guid).
    pub manifest: Manifest,
    /// The files packed under `resources/` (their names there).
    pub resources: Vec<String>,
}

/// Run `ffr fmu`.
pub fn fmu(args: &FmuArgs) -> Result<FmuWritten, Box<dyn Error>> {
    let out = &args.out;
    let is_fmu = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("fmu"));
    if !is_fmu {
        return Err(output::OutputError {
            path: out.clone(),
            message: "--out needs a file name ending in .fmu (NAME.fmu)".into(),
        }
        .into());
    }
    output::check_output(out, "--out")?;
    let binary = match &args.binary {
        Some(p) => p.clone(),
        None => default_binary()?,
    };
    output::check_not_inputs(
        &[("--out", out)],
        &[
            ("the scene file", &args.scene),
            ("the --binary library", &binary),
        ],
    )?;
    check_ours(out)?;
    let so = read_library(&binary)?;

    // The parameters: dotted keys with numbers in the scene file.
    let text = ffr::scene::SceneText::read(&args.scene)?;
    let mut parameters: Vec<Parameter> = Vec::new();
    for key in &args.parameters {
        if parameters.iter().any(|p| &p.key == key) {
            return Err(format!("--parameter {key} is given twice").into());
        }
        let start = match text.get(key) {
            Some(ffr::scene::SceneValue::Float(x)) => x,
            Some(ffr::scene::SceneValue::Int(i)) => i as f64,
            Some(other) => {
                return Err(format!(
                    "{}: --parameter {key}: the scene's value there is {other}, not a number: an FMU parameter is a real",
                    args.scene.display()
                )
                .into())
            }
            None => {
                return Err(format!(
                    "{}: --parameter {key}: the scene sets no value at this key; write the value in the scene file to make it a parameter (keys as in `ffr sweep`: bodies.NAME.params.e, joints.0.drive.omega, …)",
                    args.scene.display()
                )
                .into())
            }
        };
        parameters.push(Parameter {
            key: key.clone(),
            start,
        });
    }

    // The scene as `ffr run` loads it, and its simulation at t = 0 (an
    // initial state `ffr run` refuses is refused here, before writing).
    let scene = std::sync::Arc::new(ffr::scene::load(&args.scene)?);
    let files = scene.input_files();
    output::check_not_scene_files(&[("--out", out)], &files)?;
    let sim = ffr::scene::Simulation::new(scene.clone())?;
    let mut inputs = Vec::new();
    for name in sim.input_names() {
        inputs.push((name.to_string(), sim.input(name)?));
    }
    let outputs: Vec<(String, String)> = scene
        .outputs
        .iter()
        .map(|o| (o.name.clone(), describe(&o.kind)))
        .collect();

    let (scene_rel, packed) = layout(&args.scene, &files)?;
    let stem = |p: &Path| {
        p.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let mut manifest = Manifest {
        guid: String::new(),
        model_identifier: c_identifier(&stem(out)),
        model_name: stem(&args.scene),
        description: scene.description.clone(),
        scene: scene_rel,
        inputs,
        outputs,
        parameters,
        dt: scene.dt,
        t_end: scene.t_end,
    };
    manifest
        .check()
        .map_err(|e| format!("{}: {e}", args.scene.display()))?;

    // The guid: a hash of the declarations, every packed file (name and
    // contents) and the binary.
    let mut contents: Vec<(String, Vec<u8>)> = Vec::new();
    for (src, dest) in &packed {
        let bytes =
            std::fs::read(src).map_err(|e| format!("{}: cannot be read: {e}", src.display()))?;
        contents.push((dest.clone(), bytes));
    }
    let mut fp = Fingerprint::default();
    fp.add(manifest.to_json().as_bytes());
    for (name, bytes) in &contents {
        fp.add(name.as_bytes());
        fp.add(bytes);
    }
    fp.add(&so);
    manifest.guid = fp.guid();

    let zip = pack(&manifest, &contents, &so)?;
    output::write_atomic(out, &zip)?;
    crate::outln!(
        "wrote {}: FMI 2.0 Co-Simulation (linux64), {} input{}, {} output{}, {} parameter{}; step {} s, guid {}",
        out.display(),
        manifest.inputs.len(),
        plural(manifest.inputs.len()),
        manifest.outputs.len(),
        plural(manifest.outputs.len()),
        manifest.parameters.len(),
        plural(manifest.parameters.len()),
        manifest.dt,
        manifest.guid
    )?;
    Ok(FmuWritten {
        manifest,
        resources: contents.into_iter().map(|(n, _)| n).collect(),
    })
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// An output's description in the model description: what and the unit.
fn describe(kind: &ffr::scene::OutputKind) -> String {
    use ffr::scene::OutputKind;
    let what = match kind {
        OutputKind::Position(_) => "position",
        OutputKind::Deflection(_) => "deflection",
        OutputKind::Velocity(_) => "velocity",
        OutputKind::Angle => "angle",
        OutputKind::Energy(_) => "energy",
    };
    format!("{what} ({})", super::run::unit(kind))
}

/// The FMU library of the build the running `ffr` belongs to: `libffr_fmu.so`
/// beside it (`cargo build --release -p ffr-cli -p ffr-fmu` puts it there)
/// or in `deps/` beside it (where cargo builds it with `ffr` itself, which
/// links its rlib), the newer of the two; an error saying how to build it
/// when there is none.
fn default_binary() -> Result<PathBuf, Box<dyn Error>> {
    let exe =
        std::env::current_exe().map_err(|e| format!("cannot find the ffr executable: {e}"))?;
    let dir = exe.parent().map(Path::to_path_buf).unwrap_or_default();
    let candidates = [dir.join(LIBRARY), dir.join("deps").join(LIBRARY)];
    let newest = candidates
        .iter()
        .filter_map(|p| Some((std::fs::metadata(p).ok()?.modified().ok()?, p)))
        .filter(|(_, p)| p.is_file())
        .max_by_key(|(t, _)| *t)
        .map(|(_, p)| p.clone());
    newest.ok_or_else(|| {
        format!(
            "{}: no FMU library beside the ffr executable: build it with `cargo build --release -p ffr-cli -p ffr-fmu` (it lands beside a release `ffr`), or give one with --binary PATH",
            candidates[0].display()
        )
        .into()
    })
}

/// The library's bytes, checked to be a 64-bit x86-64 ELF shared object
/// with the FMI 2.0 functions (what `binaries/linux64` needs).
fn read_library(path: &Path) -> Result<Vec<u8>, Box<dyn Error>> {
    let bytes = std::fs::read(path).map_err(|e| {
        format!(
            "{}: cannot be read ({e}): build the FMU library with `cargo build --release -p ffr-cli -p ffr-fmu` or give --binary PATH",
            path.display()
        )
    })?;
    let elf = bytes.len() > 20 && &bytes[..4] == b"\x7fELF";
    // ELFCLASS64, little-endian, ET_DYN, EM_X86_64
    let fits = elf
        && bytes[4] == 2
        && bytes[5] == 1
        && u16::from_le_bytes([bytes[16], bytes[17]]) == 3
        && u16::from_le_bytes([bytes[18], bytes[19]]) == 62;
    if !fits {
        return Err(format!(
            "{}: not an x86-64 Linux shared library (an FMU's binaries/linux64 needs one): build it with `cargo build --release -p ffr-cli -p ffr-fmu`",
            path.display()
        )
        .into());
    }
    if !bytes.windows(11).any(|w| w == b"fmi2DoStep\0") {
        return Err(format!(
            "{}: exports no fmi2DoStep: not the FMU library of `cargo build --release -p ffr-fmu`",
            path.display()
        )
        .into());
    }
    Ok(bytes)
}

/// Refuse to replace an existing file unless it is an FMU ffr wrote (a zip
/// whose `modelDescription.xml` has ffr's `generationTool`).
fn check_ours(path: &Path) -> Result<(), Box<dyn Error>> {
    let not_ours = |why: &str| -> Box<dyn Error> {
        output::OutputError {
            path: path.to_path_buf(),
            message: format!("exists and {why}: --out replaces only FMUs that `ffr fmu` wrote; remove it or give another path"),
        }
        .into()
    };
    let file = match std::fs::File::open(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(format!("{}: cannot be read: {e}", path.display()).into()),
        Ok(f) => f,
    };
    let Ok(mut z) = zip::ZipArchive::new(file) else {
        return Err(not_ours("is not a zip file"));
    };
    let Ok(entry) = z.by_name("modelDescription.xml") else {
        return Err(not_ours("has no modelDescription.xml"));
    };
    let mut text = String::new();
    if entry
        .take(MAX_DESCRIPTION_BYTES)
        .read_to_string(&mut text)
        .is_err()
    {
        return Err(not_ours("has a modelDescription.xml that cannot be read"));
    }
    let tool = format!(
        "generationTool=\"{}",
        GENERATION_TOOL.split(' ').next().unwrap_or("ffr")
    );
    if !text.contains(&format!("{tool} ")) {
        return Err(not_ours(
            "was not written by ffr (its modelDescription.xml names another generationTool)",
        ));
    }
    Ok(())
}

/// The scene's path inside `resources/` and each file to pack with its
/// name there.
type Layout = (String, Vec<(PathBuf, String)>);

/// Where the scene's files go under `resources/`: the paths the scene names
/// relative to its own directory, kept (a file beside the scene beside it,
/// `shapes/x.toml` in `shapes/`); a path that climbs out of the scene's
/// directory (`../data/m.mtx`) puts the scene as many directories deep as
/// it climbs (named as on disk), so that it reads the same from there. An
/// absolute path the scene names is refused (the FMU would read the
/// machine's file, not its own).
fn layout(scene: &Path, files: &[PathBuf]) -> Result<Layout, Box<dyn Error>> {
    let dir = scene.parent().map(Path::to_path_buf).unwrap_or_default();
    // Each file relative to the scene's directory, lexically normalized.
    let mut rels: Vec<(PathBuf, Vec<String>, usize)> = Vec::new();
    let mut climb = 0usize;
    for f in files {
        let absolute = || -> Box<dyn Error> {
            format!(
                "{}: the scene names the file {} by an absolute path outside its directory: an FMU carries the scene's files under resources/ at the paths the scene names; give it relative to the scene's directory",
                scene.display(),
                f.display()
            )
            .into()
        };
        let rel: PathBuf = if f == scene {
            PathBuf::from(scene.file_name().unwrap_or_default())
        } else if f.is_absolute() && dir.is_relative() {
            return Err(absolute());
        } else if dir.as_os_str().is_empty() {
            f.clone()
        } else {
            f.strip_prefix(&dir).map_err(|_| absolute())?.to_path_buf()
        };
        let mut parts: Vec<String> = Vec::new();
        let mut up = 0usize;
        for c in rel.components() {
            match c {
                Component::Normal(s) => parts.push(
                    s.to_str()
                        .ok_or_else(|| format!("{}: the file name is not UTF-8", f.display()))?
                        .to_string(),
                ),
                Component::ParentDir => {
                    if parts.pop().is_none() {
                        up += 1;
                    }
                }
                Component::CurDir => {}
                _ => return Err(absolute()),
            }
        }
        climb = climb.max(up);
        rels.push((f.clone(), parts, up));
    }
    // The scene's directory's last `climb` names.
    let canon = std::fs::canonicalize(if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        &dir
    })
    .map_err(|e| format!("{}: cannot be resolved: {e}", dir.display()))?;
    let names: Vec<String> = canon
        .components()
        .filter_map(|c| match c {
            Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
            _ => None,
        })
        .collect();
    if climb > names.len() {
        return Err(format!(
            "{}: a file path climbs above the file system's root",
            scene.display()
        )
        .into());
    }
    let prefix = &names[names.len() - climb..];
    let mut packed: Vec<(PathBuf, String)> = Vec::new();
    let mut scene_rel = String::new();
    for (f, parts, up) in rels {
        let mut p: Vec<String> = prefix[..climb - up].to_vec();
        p.extend(parts);
        let name = p.join("/");
        if name.is_empty() || name == MANIFEST {
            return Err(format!(
                "{}: the file {} would be resources/{name} in the FMU, a name the FMU needs itself",
                scene.display(),
                f.display()
            )
            .into());
        }
        if f == scene {
            scene_rel = name.clone();
        }
        if !packed.iter().any(|(_, n)| *n == name) {
            packed.push((f, name));
        }
    }
    Ok((scene_rel, packed))
}

/// The FMU as zip bytes.
fn pack(
    manifest: &Manifest,
    resources: &[(String, Vec<u8>)],
    so: &[u8],
) -> Result<Vec<u8>, Box<dyn Error>> {
    use zip::write::SimpleFileOptions;
    let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let opts = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    w.start_file("modelDescription.xml", opts)?;
    w.write_all(manifest.model_description().as_bytes())?;
    w.start_file(
        format!("binaries/linux64/{}.so", manifest.model_identifier),
        opts.unix_permissions(0o755),
    )?;
    w.write_all(so)?;
    w.start_file(format!("resources/{MANIFEST}"), opts)?;
    w.write_all(manifest.to_json().as_bytes())?;
    for (name, bytes) in resources {
        w.start_file(format!("resources/{name}"), opts)?;
        w.write_all(bytes)?;
    }
    Ok(w.finish()?.into_inner())
}
