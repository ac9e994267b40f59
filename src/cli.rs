//! The `ffr` command line: invariants, generated code, and the default
//! simulation.

use clap::{Args, Parser, Subcommand};
use ffr_codegen::limits::{check_invariants, check_literals, check_params};
use ffr_codegen::numeric::NumericInvariants;
use ffr_codegen::sanitize::check_type_name;
use ffr_codegen::{BodySpec, EmitOptions, Formalism, Options, ParamValues, Reference, Shape};
use serde_json::{json, Value};

/// Floating frame of reference (FFR) code generation and simulation.
#[derive(Parser, Debug)]
#[command(name = "ffr", version, about)]
pub struct Cli {
    /// What to do; without a command, the default scene runs (see `spin-up`).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Evaluate a body's invariants from the generated expressions.
    Invariants {
        #[command(flatten)]
        body: BodyArgs,
        #[command(flatten)]
        params: ParamArgs,
        /// Print one JSON object (otherwise a short text summary).
        #[arg(long)]
        json: bool,
    },
    /// Run the spin-up beam benchmark (the default job).
    SpinUp(crate::spin_up::SpinUpArgs),
    /// Print the generated Rust for a body.
    Emit {
        #[command(flatten)]
        body: BodyArgs,
        /// Name of the generated body type.
        #[arg(long, default_value = "Body")]
        type_name: String,
    },
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
    #[arg(long, default_value = "clamped", value_parser = ["clamped", "pinned", "free"])]
    pub reference: String,
    /// Inertia formalism: consistent or lumped.
    #[arg(long, default_value = "consistent", value_parser = ["consistent", "lumped"])]
    pub formalism: String,
    /// Also generate geometric stiffening.
    #[arg(long)]
    pub stiffening: bool,
}

/// Parameter values (SI units); a shape that does not use one ignores it.
/// Defaults: a 1 m steel bar of 10 mm × 10 mm square section.
#[derive(Args, Debug, Clone)]
pub struct ParamArgs {
    /// Body length L (m).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub length: f64,
    /// Density ρ (kg/m³).
    #[arg(long, default_value_t = 7850.0, allow_hyphen_values = true)]
    pub rho: f64,
    /// Area A (m²).
    #[arg(long, default_value_t = 1e-4, allow_hyphen_values = true)]
    pub area: f64,
    /// I_y = ∫z² dA (m⁴).
    #[arg(long, default_value_t = 1e-8 / 12.0, allow_hyphen_values = true)]
    pub iy: f64,
    /// I_z = ∫y² dA (m⁴).
    #[arg(long, default_value_t = 1e-8 / 12.0, allow_hyphen_values = true)]
    pub iz: f64,
    /// Young's modulus E (Pa).
    #[arg(long, default_value_t = 2.1e11, allow_hyphen_values = true)]
    pub e: f64,
    /// Shear modulus G (Pa).
    #[arg(long, default_value_t = 8.1e10, allow_hyphen_values = true)]
    pub g: f64,
    /// Torsion constant J (m⁴).
    #[arg(long, default_value_t = 1.406e-8, allow_hyphen_values = true)]
    pub j: f64,
}

impl ParamArgs {
    /// As codegen parameter values.
    pub fn values(&self) -> ParamValues {
        ParamValues {
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
    /// The body these arguments describe (shape paths relative to the working directory).
    pub fn spec(&self) -> Result<BodySpec, ffr_codegen::Error> {
        let shape = Shape::resolve(&self.shape, None)?;
        let reference: Reference = self.reference.parse()?;
        let formalism: Formalism = self.formalism.parse()?;
        Ok(BodySpec::new(shape, self.elements as usize, reference)?.with_formalism(formalism))
    }

    /// Generator options.
    pub fn options(&self) -> Options {
        Options {
            stiffening: self.stiffening,
        }
    }
}

/// Run a parsed command line.
pub fn run(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    match cli.command {
        Some(Command::Invariants { body, params, json }) => {
            let p = params.values();
            // What can be checked without the body first, then against the
            // parameters the body uses; results are checked before printing.
            check_params(&p, &[])?;
            let spec = body.spec()?;
            let formalism = spec.formalism;
            let g = ffr_codegen::generate(&spec, body.options())?;
            check_params(&p, &g.used_params())?;
            let inv = g.eval_invariants(&p);
            check_invariants(&inv, formalism)?;
            if json {
                println!("{}", serde_json::to_string(&invariants_json(&inv))?);
            } else {
                print_summary(&g, &inv);
            }
            Ok(())
        }
        Some(Command::Emit { body, type_name }) => {
            check_type_name(&type_name, "--type-name")?;
            let g = ffr_codegen::generate(&body.spec()?, body.options())?;
            check_literals(&g)?;
            let opts = EmitOptions {
                type_name,
                ..EmitOptions::default()
            };
            print!("{}", ffr_codegen::emit_file(&g, &opts));
            Ok(())
        }
        Some(Command::SpinUp(args)) => crate::spin_up::run(&args).map(|_| ()),
        None => crate::default_scene(),
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The invariants as the JSON object of `ffr invariants --json`.
pub fn invariants_json(inv: &NumericInvariants) -> Value {
    let d = inv.dim;
    let keyed = |f: &dyn Fn(usize, usize) -> Value| {
        let mut m = serde_json::Map::new();
        for k in 0..d {
            for l in 0..d {
                m.insert(format!("{}{}", AXES[k], AXES[l]), f(k, l));
            }
        }
        Value::Object(m)
    };
    json!({
        "mass": inv.mass,
        "St0": inv.s_t0[..d].to_vec(),
        "Sbar": inv.s_bar[..d].to_vec(),
        "Skl": keyed(&|k, l| json!(inv.s_kl[k][l])),
        "Ikl": keyed(&|k, l| json!(inv.i_kl[k][l])),
        "theta": keyed(&|k, l| json!(inv.theta[k][l])),
        "mff": inv.m_ff,
        "Kff": inv.k_ff,
        "dofs": inv.dofs,
    })
}

fn print_summary(g: &ffr_codegen::Generated, inv: &NumericInvariants) {
    println!("{}", ffr_codegen::emit::describe(g));
    println!(
        "elastic coordinates ({}): {}",
        inv.dofs.len(),
        inv.dofs.join(" ")
    );
    println!("mass m = {:e}", inv.mass);
    let d = inv.dim;
    println!("S_t0 = {:?}", &inv.s_t0[..d]);
    for k in 0..d {
        println!("Θ_{}· = {:?}", AXES[k], &inv.theta[k][..d]);
    }
    let diag = |m: &Vec<Vec<f64>>| (0..m.len()).map(|i| m[i][i]).collect::<Vec<_>>();
    println!("diag m_ff = {:?}", diag(&inv.m_ff));
    println!("diag K_ff = {:?}", diag(&inv.k_ff));
}
