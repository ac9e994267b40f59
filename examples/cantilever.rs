//! From `#[flex_body]` to a simulated tip deflection with the library API:
//! an aluminium cantilever (8 planar beam elements, generated at compile
//! time) sags under gravity; Rayleigh damping lets it settle, and the tip
//! deflection is checked against Euler–Bernoulli's static `w = q L⁴ / (8 E I)`.
//! Run: `cargo run --example cantilever` (exit status 1 if the check fails).

use ffr::prelude::*;
use ffr::runtime::nalgebra::Vector3;
use ffr::runtime::Rayleigh;
use std::ops::ControlFlow;

#[flex_body(shape = "beam2", elements = 8, reference = "clamped")]
struct Cantilever {
    length: f64,
    rho: f64,
    area: f64,
    iz: f64,
    e: f64,
}

fn main() -> Result<()> {
    let beam = Cantilever {
        length: 1.0,
        rho: 2700.0,
        area: 1e-4,
        iz: 8.3e-10,
        e: 7e10,
    };
    let mut sys: System<KernelBody<_>> = System::planar();
    let id = sys.add_body(
        "beam",
        KernelBody::compiled(&beam)?,
        Pose::planar(0.0, 0.0, 0.0),
    )?;
    sys.ground(id)?; // the frame is the clamp
    sys.set_gravity(Vector3::new(0.0, -9.81, 0.0))?;
    sys.set_damping(
        id,
        Rayleigh {
            alpha: 20.0,
            beta: 0.0,
        },
    )?;
    let tip = sys.point(id, beam.length)?;
    let mut tip_y = f64::NAN;
    let run = sys.simulate(3.0, 1e-3, &Integrator::default(), |v| {
        tip_y = v.assembly.marker_position(&tip, &v.state.q).y;
        ControlFlow::Continue(())
    })?;
    let q = beam.rho * beam.area * 9.81; // weight per length (N/m)
    let w = q * beam.length.powi(4) / (8.0 * beam.e * beam.iz);
    let error = (tip_y + w).abs() / w;
    println!(
        "{} steps: tip deflection {:.6e} m, static theory {:.6e} m, difference {:.2e}",
        run.steps, -tip_y, w, error
    );
    if error > 1e-6 {
        return Err(Error::Invalid(format!(
            "tip deflection off the static value by {error:.2e}"
        )));
    }
    Ok(())
}
