//! A loaded scene, ready to run: its system, integrator, steps and output
//! columns, and how its flexible bodies were made.

use crate::runtime::spec::scene::FlexSpec;
pub use crate::runtime::spec::scene::{EnergyPart, OutputKind, MAX_RECORDED_VALUES};
use crate::runtime::{Body, Integrator, Marker, System};

/// An output column.
#[derive(Clone, Debug)]
pub struct Output {
    /// Column name.
    pub name: String,
    /// What it records.
    pub kind: OutputKind,
    /// Where (ground for energies).
    pub marker: Marker,
    /// Reference marker of a relative angle.
    pub relative_to: Option<Marker>,
}

/// A named input of a scene (`[[inputs]]`): a value a caller sets between
/// steps ([`super::Simulation::set_input`]), held constant over each step.
#[derive(Clone)]
#[non_exhaustive]
pub struct Input {
    /// Its name.
    pub name: String,
    /// Its value at `t = 0` (the profile's there, if it has one).
    pub start: f64,
    /// What it does.
    pub kind: crate::runtime::spec::scene::InputKind,
    /// Its value at each step's start when no caller has set it (`profile`).
    pub profile: Option<std::sync::Arc<dyn Fn(f64) -> f64 + Send + Sync>>,
}

impl std::fmt::Debug for Input {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Input")
            .field("name", &self.name)
            .field("start", &self.start)
            .field("kind", &self.kind)
            .field("profile", &self.profile.is_some())
            .finish()
    }
}

/// A loaded scene, ready to run.
pub struct Scene {
    /// The file it came from.
    pub origin: String,
    /// Its description line, if any.
    pub description: Option<String>,
    /// The system.
    pub system: System<Box<dyn Body>>,
    /// End time (s).
    pub t_end: f64,
    /// Step (s).
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Output columns (after `t`).
    pub outputs: Vec<Output>,
    /// Named inputs, in file order.
    pub inputs: Vec<Input>,
    /// The flexible bodies as described (in body order).
    pub flex: Vec<FlexSpec>,
    /// The FE bodies as described (in body order).
    pub fe: Vec<crate::runtime::spec::scene::FeSpec>,
    /// The bodies run as segments, each also as one body (`segments = 1`):
    /// what [`Scene::whole_body`] gives for modes, invariants and export.
    pub unsplit: Vec<(String, Box<dyn Body>)>,
    /// How each body runs: `compiled`, `tape`, `rigid`.
    pub kernels: Vec<(String, String)>,
    /// What the loader folded in or left out (one line each).
    pub notes: Vec<String>,
}

/// The files a scene is read from: the scene file, its shape files, section
/// tables, and FE node and matrix files (as resolved against the scene's
/// directory), each once, in the order met. Commands refuse an output that
/// would replace one of them.
pub fn input_files(
    origin: &str,
    flex: &[FlexSpec],
    fe: &[crate::runtime::spec::scene::FeSpec],
) -> Vec<std::path::PathBuf> {
    let mut files: Vec<std::path::PathBuf> = Vec::new();
    let mut add = |f: &str| {
        let p = std::path::PathBuf::from(f);
        if !f.is_empty() && !files.contains(&p) {
            files.push(p);
        }
    };
    add(origin);
    for f in flex {
        // A built-in shape keeps its name; a shape file is resolved to a path.
        if f.shape != f.shape_name || std::path::Path::new(&f.shape).is_file() {
            add(&f.shape);
        }
        if let Some(t) = &f.sections {
            add(&t.at.file);
        }
    }
    for b in fe {
        add(&b.nodes);
        add(&b.mass);
        add(&b.stiffness);
    }
    files
}

impl Scene {
    /// The files this scene was read from ([`input_files`]).
    pub fn input_files(&self) -> Vec<std::path::PathBuf> {
        input_files(&self.origin, &self.flex, &self.fe)
    }

    /// The flexible body `name` (its id in the system and how it was
    /// made); a rigid or unknown body is an error naming the flexible ones,
    /// prefixed with the scene's file.
    pub fn flex_body(&self, name: &str) -> Result<(crate::runtime::BodyId, &FlexSpec), String> {
        let q = crate::runtime::spec::text::quoted;
        let Some(f) = self.flex.iter().find(|f| f.name == name) else {
            let flexible: Vec<&str> = self
                .flex
                .iter()
                .map(|f| f.name.as_str())
                .chain(self.fe.iter().map(|f| f.name.as_str()))
                .collect();
            return Err(format!(
                "{}: no flexible body `{}`; the scene's flexible bodies are {}",
                self.origin,
                q(name),
                if flexible.is_empty() {
                    "none".to_string()
                } else {
                    flexible.join(", ")
                }
            ));
        };
        let id = self
            .system
            .body_id(name)
            .expect("a flexible body of the scene is in its system");
        Ok((id, f))
    }

    /// The flexible body `name` as one body, and how it was made: the
    /// system's body, or, for a body run as segments, the whole body built
    /// alongside (its modes, invariants and export are the whole body's).
    pub fn whole_body(&self, name: &str) -> Result<(&dyn Body, &FlexSpec), String> {
        let (id, f) = self.flex_body(name)?;
        Ok(match self.unsplit.iter().find(|(n, _)| n == name) {
            Some((_, b)) => (b.as_ref(), f),
            None => (self.system.body(id).as_ref(), f),
        })
    }
}
