//! A free-floating flexible body (generated `beam2` in the plane, `beam3` in
//! space; no joints, no forces): linear and angular momentum.
//!
//! - Round-off: the runtime's equations of motion conserve `p` and `H`
//!   exactly; at random states the analytic `ṗ`, `Ḣ` of the solved
//!   accelerations vanish to a few ulps of the terms that cancel.
//! - Integrator accuracy: along trajectories `p` and `H` drift by the global
//!   error of the integrator, `O(dt²)` for generalized-α and `O(dt⁴)` for RK4,
//!   until RK4 reaches the round-off floor of the accumulated steps.

use ffr::free_floating::{
    check_rates, drift_study, free_body, FreeFloatingArgs, Lcg, Method, StateScales,
};
use ffr::pendulum::Beam;
use ffr::runtime::nalgebra::DVector;
use ffr::runtime::{Pose, System};

/// Round-off bound for `|ṗ|/scale` and `|Ḣ|/scale`: about 500 ulps. The
/// scale is the sum of the norms of the terms that cancel; the accelerations
/// come from a backward-stable LU solve of a system of about 30 unknowns, and
/// each term is a few dozen flops. Measured: at most 5e-16.
const ROUND_OFF: f64 = 1e-13;

#[test]
fn equations_of_motion_conserve_momentum_to_round_off() {
    let stiff_states = StateScales::elastic();
    for beam in [Beam::Beam2, Beam::Beam3] {
        for (stiff, scales) in [
            // K_ff = 0 (E = G = 0): purely inertial, large deformations (5 % of L).
            (false, StateScales::default()),
            (true, stiff_states),
        ] {
            let c = check_rates(beam, 4, stiff, &scales, 10, 3).unwrap();
            println!(
                "{beam:?} stiff {stiff}: |ṗ|/scale {:.2e}, |Ḣ|/scale {:.2e} (|ṗ| ≤ {:.1e} N, |Ḣ| ≤ {:.1e} N m); without Q_v {:.2e} {:.2e}; formula vs differences {:.1e} {:.1e}",
                c.worst_p, c.worst_h, c.worst_abs.0, c.worst_abs.1, c.without_qv.0, c.without_qv.1,
                c.formula_vs_differences.0, c.formula_vs_differences.1
            );
            assert!(
                c.worst_p < ROUND_OFF && c.worst_h < ROUND_OFF,
                "{beam:?} stiff {stiff}: {c:?}"
            );
            // The check sees the velocity terms: leaving Q_v out gives rates at
            // least 1e-5 of the scale (measured ≥ 2.6e-5), 8 orders above the bound.
            assert!(
                c.without_qv.0 > 1e-5 && c.without_qv.1 > 1e-5,
                "{beam:?} stiff {stiff}: {c:?}"
            );
            // The rate formulas agree with central differences (h = 1e-5 s,
            // truncation ~h² = 1e-10) of the runtime's momenta: measured ≤ 9e-10.
            assert!(
                c.formula_vs_differences.0 < 1e-8 && c.formula_vs_differences.1 < 1e-8,
                "{beam:?} stiff {stiff}: {c:?}"
            );
        }
    }
}

/// `γ` of the Euler-parameter normalization `½(eᵀe − 1)` is `−ėᵀė` to
/// round-off (it was a central difference with ~1e-10 relative error, which
/// held a Baumgarte-stabilized `eᵀe − 1` at ~1e-13 and with it the momenta).
#[test]
fn euler_normalization_gamma_is_exact() {
    let mut sys = System::spatial();
    let b = sys
        .add_body(
            Box::new(free_body(Beam::Beam3, 2, true).unwrap()),
            Pose::identity(3),
        )
        .unwrap();
    let mut rng = Lcg(5);
    for _ in 0..5 {
        let (q, v) =
            ffr::free_floating::random_state(sys.body(b), &mut rng, &StateScales::default());
        let (q, v) = (DVector::from_vec(q), DVector::from_vec(v));
        let g = sys.gamma(0.0, &q, &v);
        let exact = -v.rows(3, 4).norm_squared();
        assert!(
            (g[0] - exact).abs() <= 4.0 * f64::EPSILON * exact.abs(),
            "{} {exact}",
            g[0]
        );
    }
}

fn study(
    beam: Beam,
    method: Method,
    steps: &[f64],
) -> (Vec<ffr::free_floating::Drift>, Vec<(f64, f64)>) {
    let args = FreeFloatingArgs {
        beam,
        method,
        elements: 2,
        t_end: 0.2,
        amplitude: 1e-3,
        ..FreeFloatingArgs::default()
    };
    let ffr::free_floating::DriftStudy { runs, orders } = drift_study(&args, steps).unwrap();
    for r in &runs {
        println!(
            "{beam:?} {method:?} dt {:e} (ω_max dt {:.2}, {} steps, {:.2} s): |Δp|/|p₀| {:.2e}, |ΔH|/|H₀| {:.2e}, |ΔE|/E₀ {:.2e}, ‖Φ‖ {:.1e}",
            r.dt, r.omega_max_dt.1, r.steps, r.wall, r.dp, r.dh, r.de, r.max_phi
        );
    }
    println!("{beam:?} {method:?} observed orders (p, H): {orders:?}");
    (runs, orders)
}

/// Generalized-α (ρ∞ = 1, Newton rtol 1e-12), 2 elements, 0.2 s, body
/// spinning at |ω| ≈ 2.3 rad/s in its first elastic mode (1 mm): the drift is
/// the integrator's global error, second order. Measured at dt = 2.5e-4 s:
/// 5.5e-7 (p) and 1.8e-7 (H) in the plane, 4.8e-7 and 3.1e-7 in space; orders
/// 1.95–2.15 between 1e-3, 5e-4 and 2.5e-4 s. The unresolved axial and
/// rotary modes (ω_max dt ≈ 2–8) are not excited by the initial state.
#[test]
fn generalized_alpha_momentum_drift_is_second_order() {
    for beam in [Beam::Beam2, Beam::Beam3] {
        let (runs, orders) = study(beam, Method::Alpha, &[1e-3, 5e-4, 2.5e-4]);
        let last = runs.last().unwrap();
        assert!(last.dp < 1e-6 && last.dh < 1e-6, "{beam:?}: {last:?}");
        for (op, oh) in orders {
            assert!(
                (1.7..2.4).contains(&op) && (1.7..2.4).contains(&oh),
                "{beam:?}: orders {op} {oh}"
            );
        }
    }
}

/// RK4 (Baumgarte α = β = 10/s on the normalization in space), 2 elements,
/// 0.2 s: fourth order while the truncation error dominates (dt = 1e-4 and
/// 5e-5 s, measured orders 3.8–4.1), then the round-off floor: at
/// dt = 2.5e-5 s (8000 steps) the drift is 7e-15 / 4e-15 in the plane and
/// 2e-14 / 2e-14 in space, no longer decreasing as dt⁴ (extrapolating the
/// truncation error from 5e-5 s would give 2e-15 / 3e-15). This is the one
/// setting where p and H are conserved along the trajectory to round-off; it
/// comes from a small explicit step (ω_max dt ≈ 0.2), not from a conserving
/// integrator.
#[test]
fn rk4_momentum_drift_is_fourth_order_down_to_round_off() {
    for beam in [Beam::Beam2, Beam::Beam3] {
        let (runs, orders) = study(beam, Method::Rk4, &[1e-4, 5e-5, 2.5e-5]);
        let (op, oh) = orders[0];
        assert!(op > 3.5 && oh > 3.5, "{beam:?}: orders {op} {oh}");
        assert!(
            runs[0].dp < 2e-12 && runs[0].dh < 2e-12,
            "{beam:?}: {:?}",
            runs[0]
        );
        // Round-off floor: ≤ 5e-14 relative, i.e. a few hundred ulps after 8000 steps.
        let last = runs.last().unwrap();
        assert!(last.dp < 5e-14 && last.dh < 5e-14, "{beam:?}: {last:?}");
    }
}

/// RK4 above its stability limit (`ω_max·dt` well above 2.8) blows up; the
/// runtime must say so (`Error::Unstable`), not report a singular matrix.
#[test]
fn explicit_integrator_above_its_stability_limit_is_reported_unstable() {
    let base = FreeFloatingArgs {
        beam: Beam::Beam2,
        t_end: 0.2,
        ..FreeFloatingArgs::default()
    };
    let body = free_body(Beam::Beam2, base.elements as usize, true).unwrap();
    let omega_max = ffr::free_floating::elastic_modes(&body).last().unwrap().0;
    let args = FreeFloatingArgs {
        dt: 6.0 / omega_max,
        ..base
    };
    let (sys, _) = ffr::free_floating::system(&args).unwrap();
    let run = sys.simulate(args.t_end, args.dt, &args.method.integrator(), |_| {
        std::ops::ControlFlow::Continue(())
    });
    match run {
        Err(e @ ffr::runtime::Error::Unstable { .. }) => {
            assert!(e.to_string().contains("try a smaller step"), "{e}");
        }
        Err(other) => panic!("misreported blow-up: {other}"),
        Ok(_) => panic!("RK4 at ω_max·dt = 6 did not blow up"),
    }
}
