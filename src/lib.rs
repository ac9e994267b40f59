//! **ffr**: floating frame of reference (FFR) code generation and simulation
//! for flexible multibody dynamics.
//!
//! - [`codegen`]: exact symbolic generator of FFR terms from shape functions.
//! - [`flex_body`]: the attribute that generates a body at compile time.
//! - [`runtime`]: the dynamics (mass matrix, forces, joints, integrators, scenes).

pub use ffr_codegen as codegen;
pub use ffr_macros::*;
pub use ffr_runtime as runtime;
pub use nalgebra;

pub mod cli;

/// The main job of `cargo run --release`.
pub fn default_scene() -> Result<(), Box<dyn std::error::Error>> {
    let g = codegen::generate(
        &codegen::BodySpec::new(
            codegen::Shape::resolve("beam3", None)?,
            4,
            codegen::Reference::Clamped,
        )?,
        codegen::Options::default(),
    )?;
    let p = codegen::ParamValues {
        length: 1.0,
        rho: 7850.0,
        area: 1e-4,
        iy: 1e-8 / 12.0,
        iz: 1e-8 / 12.0,
        e: 2.1e11,
        g: 8.1e10,
        j: 1.406e-8,
    };
    let inv = g.eval_invariants(&p);
    println!("{}: mass {:e} kg", codegen::emit::describe(&g), inv.mass);
    Ok(())
}
