//! The arguments several commands share: which kernels, which body, which
//! parameters, and the enums of the command line's choices.

use clap::Args;
use ffr::codegen::builder::KernelConfig;
use ffr::kernels::BeamSpec;
use ffr::runtime::spec::{
    Formalism, FrameModel, KernelOptions, Params, Reference, SceneDim, Stiffening,
};

/// Which element kernels: shape and model options.
#[derive(Args, Debug, Clone)]
pub struct KernelArgs {
    /// Built-in shape name (beam2, beam3) or path to a shape .toml file.
    #[arg(long, default_value = "beam3")]
    pub shape: String,
    /// Inertia formalism: consistent or lumped.
    #[arg(long, value_enum, default_value_t = Formalism::Consistent)]
    pub formalism: Formalism,
    /// Geometric stiffening: off, on (= fourth-order), second-order, fourth-order.
    #[arg(long, value_enum, default_value_t = Stiffening::Off)]
    pub stiffening: Stiffening,
    /// The scene the body moves in: planar or spatial (default: the shape's).
    #[arg(long = "scene-dim", value_enum)]
    pub scene_dim: Option<SceneDim>,
    /// Only prescribed frame motion (no reference rows).
    #[arg(long)]
    pub prescribed_frame: bool,
}

impl KernelArgs {
    /// The kernel options these arguments give.
    pub fn options(&self) -> KernelOptions {
        KernelOptions {
            formalism: self.formalism,
            stiffening: self.stiffening,
            scene: self.scene_dim,
            frame: if self.prescribed_frame {
                FrameModel::Prescribed
            } else {
                FrameModel::Free
            },
        }
    }

    /// The kernel set `name` these arguments describe.
    pub fn config(&self, name: &str) -> KernelConfig {
        KernelConfig::new(name, &self.shape).options(self.options())
    }
}

/// Which body: shape, mesh, reference condition, formalism.
#[derive(Args, Debug, Clone)]
pub struct BodyArgs {
    /// Built-in shape name (beam2, beam3) or path to a shape .toml file.
    #[arg(long, default_value = "beam3")]
    pub shape: String,
    /// Number of equal elements (1 to 256).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub elements: u16,
    /// Reference condition: clamped, pinned or free.
    #[arg(long, value_enum, default_value_t = Reference::Clamped)]
    pub reference: Reference,
    /// Inertia formalism: consistent or lumped.
    #[arg(long, value_enum, default_value_t = Formalism::Consistent)]
    pub formalism: Formalism,
    /// Run the kernels on tapes even for a built-in shape (comparisons).
    #[arg(long)]
    pub tape: bool,
}

/// A flexible body of a scene file instead of the body and parameter flags:
/// `--scene FILE --body NAME`.
#[derive(Args, Debug, Clone)]
pub struct SceneBodyArgs {
    /// Take the body from this scene file (with `--body`): its shape, mesh
    /// (equal or graded), reference, formalism and parameters.
    #[arg(
        long,
        requires = "body_name",
        conflicts_with_all = ["shape", "elements", "reference", "formalism", "tape", "length", "rho", "area", "iy", "iz", "e", "g", "j"]
    )]
    pub scene: Option<std::path::PathBuf>,
    /// The flexible body of `--scene` by name (`[bodies.NAME]`).
    #[arg(long = "body", value_name = "NAME", requires = "scene")]
    pub body_name: Option<String>,
}

/// Parameter values (SI units); a shape that does not use one ignores it.
/// Defaults: a 1 m steel bar of 10 mm × 10 mm square section
/// ([`Params::STEEL_BAR`]).
#[derive(Args, Debug, Clone)]
pub struct ParamArgs {
    /// Body length L (m).
    #[arg(long, default_value_t = Params::STEEL_BAR.length, allow_hyphen_values = true)]
    pub length: f64,
    /// Density ρ (kg/m³).
    #[arg(long, default_value_t = Params::STEEL_BAR.rho, allow_hyphen_values = true)]
    pub rho: f64,
    /// Area A (m²).
    #[arg(long, default_value_t = Params::STEEL_BAR.area, allow_hyphen_values = true)]
    pub area: f64,
    /// I_y = ∫z² dA (m⁴).
    #[arg(long, default_value_t = Params::STEEL_BAR.iy, allow_hyphen_values = true)]
    pub iy: f64,
    /// I_z = ∫y² dA (m⁴).
    #[arg(long, default_value_t = Params::STEEL_BAR.iz, allow_hyphen_values = true)]
    pub iz: f64,
    /// Young's modulus E (Pa).
    #[arg(long, default_value_t = Params::STEEL_BAR.e, allow_hyphen_values = true)]
    pub e: f64,
    /// Shear modulus G (Pa).
    #[arg(long, default_value_t = Params::STEEL_BAR.g, allow_hyphen_values = true)]
    pub g: f64,
    /// Torsion constant J (m⁴).
    #[arg(long, default_value_t = Params::STEEL_BAR.j, allow_hyphen_values = true)]
    pub j: f64,
}

impl ParamArgs {
    /// The flags' defaults (clap's, so that they are written once).
    pub fn parse_defaults() -> Self {
        use clap::{Args, FromArgMatches};
        let cmd = Self::augment_args(clap::Command::new("defaults"));
        let matches = cmd.get_matches_from(["defaults"]);
        Self::from_arg_matches(&matches).expect("every parameter flag has a default")
    }

    /// As parameter values.
    pub fn values(&self) -> Params {
        Params {
            length: self.length,
            rho: self.rho,
            area: self.area,
            iy: self.iy,
            iz: self.iz,
            e: self.e,
            g: self.g,
            j: self.j,
        }
    }
}

impl BodyArgs {
    /// The body these arguments describe.
    pub fn beam(&self, params: Params) -> Result<BeamSpec, Box<dyn std::error::Error>> {
        Ok(BeamSpec {
            shape: self.shape.clone(),
            elements: self.elements as usize,
            reference: self.reference,
            options: KernelOptions::new().formalism(self.formalism),
            params,
            force_tape: self.tape,
        })
    }
}

/// The integrator of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum IntegratorKind {
    /// Implicit generalized-α (`--rho-inf`).
    GeneralizedAlpha,
    /// Explicit RK4 with Baumgarte stabilization.
    Rk4,
}

/// How `--modes` reduces the spin-up beam.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ReductionKind {
    /// The lowest clamped modes.
    Modal,
    /// Craig–Bampton with the tip node as boundary.
    CraigBampton,
}

/// The file format of `ffr export`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ExportFormat {
    /// MBDyn's modal element file (`.fem`).
    MbdynFem,
    /// The standard input data (SID) of flexible bodies.
    Sid,
}
