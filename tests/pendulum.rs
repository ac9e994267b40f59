//! The free flexible pendulum (generated `beam2` in the plane, `beam3` in
//! space; aluminium bar 1 m, 10 × 10 mm, 4 elements, clamped reference),
//! pinned at node 0 by a revolute joint, released from the horizontal under
//! gravity, no damping, integrated by generalized-α with `ρ∞ = 1` (no
//! numerical dissipation) for 1 s (the bar swings through the vertical).
//!
//! The continuous system conserves energy exactly and stays on `Φ = 0`; the
//! bounds below are the integrator's errors:
//! - energy: generalized-α is second order, so `max |E − E(0)| / (m g L/2)`
//!   is `O(dt²)`; at dt = 1e-3 s (~30 steps per period of the first bending
//!   mode, ≈ 230 rad/s) measured 1.2e-6 (plane) and 4.2e-6 (space), and
//!   halving dt divides it by 4.0 and 5.6 (2e-3 → 1e-3 s);
//! - `Φ`: the index-3 scheme solves `Φ(q_{n+1}) = 0` in each step, so `‖Φ‖` is
//!   the Newton tolerance (increments ≤ 1e-11 + 1e-9 |q|), not a
//!   discretization error; in the plane the joint at the frame origin of a
//!   clamped body is linear (`R = 0`) and holds exactly;
//! - `Φ̇ = Φ_q q̇`: not enforced by the index-3 scheme; in space (the
//!   perpendicularity equations are nonlinear) it is an `O(dt²)` error,
//!   measured 6.1e-5 at dt = 1e-3 s, 2.3e-4 at 2e-3 s.

use ffr::pendulum::{run, Beam, Method, PendulumArgs, PendulumReport};

fn pendulum(beam: Beam, dt: f64) -> PendulumReport {
    let args = PendulumArgs {
        beam,
        elements: 4,
        t_end: 1.0,
        dt,
        method: Method::Alpha,
    };
    let r = run(&args).unwrap();
    println!(
        "{beam:?} dt {dt:e}: {} steps, {:.2} s, ΔE/E_ref {:.3e}, ‖Φ‖ {:.2e}, ‖Φ̇‖ {:.2e}, tip y_min {:.4} m, elastic tip {:.3e} m",
        r.steps, r.wall, r.energy_drift, r.max_phi, r.max_phi_dot, r.min_tip_y, r.max_tip_deflection
    );
    r
}

#[test]
fn planar_pendulum_conserves_energy_to_second_order_and_holds_the_joint() {
    let (coarse, fine) = (pendulum(Beam::Beam2, 2e-3), pendulum(Beam::Beam2, 1e-3));
    // The bar swings down through the vertical and bends (about 1 mm).
    assert!(fine.min_tip_y < -0.99, "{fine:?}");
    assert!((5e-4..5e-3).contains(&fine.max_tip_deflection), "{fine:?}");
    assert!(fine.energy_drift < 5e-6, "{fine:?}");
    let ratio = coarse.energy_drift / fine.energy_drift;
    assert!((3.0..6.0).contains(&ratio), "second order: ratio {ratio}");
    // R = 0 is linear: one Newton correction satisfies it exactly, and q̇ with it.
    assert!(fine.max_phi == 0.0 && fine.max_phi_dot == 0.0, "{fine:?}");
}

#[test]
fn spatial_pendulum_conserves_energy_to_second_order_and_holds_the_joint() {
    let (coarse, fine) = (pendulum(Beam::Beam3, 2e-3), pendulum(Beam::Beam3, 1e-3));
    assert!(fine.min_tip_y < -0.99, "{fine:?}");
    assert!((5e-4..5e-3).contains(&fine.max_tip_deflection), "{fine:?}");
    assert!(fine.energy_drift < 1e-5, "{fine:?}");
    let ratio = coarse.energy_drift / fine.energy_drift;
    assert!((3.0..8.0).contains(&ratio), "second order: ratio {ratio}");
    // Newton tolerance (measured ≤ 5e-13).
    assert!(fine.max_phi < 1e-9, "{fine:?}");
    // Velocity constraints: O(dt²) integration error.
    assert!(fine.max_phi_dot < 2e-4, "{fine:?}");
    let ratio = coarse.max_phi_dot / fine.max_phi_dot;
    assert!((3.0..6.0).contains(&ratio), "Φ̇ second order: ratio {ratio}");
}
