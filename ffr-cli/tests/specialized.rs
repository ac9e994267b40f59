//! Kernels specialized for a prescribed frame at rest without gravity
//! (`FrameModel::PrescribedAtRest`: no reference rows, no `ā` terms): fewer
//! operations, the same motion as the general body, and refused where their
//! assumption does not hold.

use ffr::codegen::{generate_kernels, KernelModel, Shape};
use ffr::kernels::{BeamSpec, FrameModel};
use ffr::runtime::nalgebra::Vector3;
use ffr::runtime::spec::{KernelOptions, SceneDim, Stiffening};
use ffr::runtime::{Driver, Marker, Pose, System};
use ffr_cli::benchmarks::spin_up::{run, SpinUp, KRB};

fn model(shape: &str, scene_dim: usize, frame: FrameModel) -> KernelModel {
    let options = KernelOptions::new()
        .stiffening(Stiffening::FourthOrder)
        .scene(SceneDim::from_dim(scene_dim).unwrap())
        .frame(frame);
    KernelModel::new(Shape::resolve(shape, None).unwrap(), options)
}

/// The specialized elastic kernels do strictly less work and have no
/// reference-row programs at all.
#[test]
fn specialized_kernels_leave_out_the_frame_terms() {
    for (shape, dim) in [("beam2", 2), ("beam3", 3)] {
        let general = generate_kernels(&model(shape, dim, FrameModel::Free)).unwrap();
        let special = generate_kernels(&model(shape, dim, FrameModel::PrescribedAtRest)).unwrap();
        assert!(general.residual.is_some() && general.tangent.is_some());
        assert!(special.residual.is_none() && special.tangent.is_none());
        for (g, s, what) in [
            (
                &general.residual_elastic,
                &special.residual_elastic,
                "residual_elastic",
            ),
            (
                &general.tangent_elastic,
                &special.tangent_elastic,
                "tangent_elastic",
            ),
        ] {
            println!("{shape}: {what} {} → {} operations", g.ops(), s.ops());
            assert!(
                s.ops() < g.ops(),
                "{shape} {what}: {} vs {}",
                s.ops(),
                g.ops()
            );
        }
    }
}

/// The spin-up with the specialized kernels follows the general body's
/// (spatial scene, free frame) motion to round-off: the terms left out are
/// exactly zero here.
#[test]
fn specialized_spin_up_equals_the_general_body() {
    for spatial in [false, true] {
        let special = run(&SpinUp {
            spatial,
            t_end: 8.0,
            ..SpinUp::new(4.0)
        })
        .unwrap();
        let general = run(&SpinUp {
            spatial,
            t_end: 8.0,
            general: true,
            ..SpinUp::new(4.0)
        })
        .unwrap();
        assert!(
            special.kernels.contains("prescribed frame at rest"),
            "{}",
            special.kernels
        );
        assert_eq!(general.kernels, "compiled");
        let diff = special
            .tip_transverse
            .iter()
            .zip(&general.tip_transverse)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!("spatial {spatial}: largest difference {diff:.2e} m");
        assert!(diff < 1e-10, "spatial {spatial}: {diff}");
    }
}

/// A body generated for `ā ≡ 0` is refused under gravity and with a frame
/// origin that can accelerate, naming the body and the reason.
#[test]
fn specialized_kernels_are_refused_where_the_frame_can_accelerate() {
    let body = || {
        BeamSpec::new("beam2", 4, KRB)
            .frame(FrameModel::PrescribedAtRest)
            .body()
            .unwrap()
    };
    // Prescribed hub at rest, but gravity.
    let mut sys = System::planar();
    let b = sys.add_body("beam", body(), Pose::identity(2)).unwrap();
    sys.prescribe_rotation_about_z(b, Driver::linear(0.0, 1.0))
        .unwrap();
    sys.set_gravity(Vector3::new(0.0, -9.81, 0.0)).unwrap();
    let err = sys.initial_state(0.0).unwrap_err().to_string();
    assert!(err.contains("`beam`") && err.contains("gravity"), "{err}");
    // The hub moves sideways: its origin accelerates.
    let mut sys = System::planar();
    let b = sys.add_body("beam", body(), Pose::identity(2)).unwrap();
    sys.prescribe_coordinate(b, 0, Driver::harmonic(0.0, 0.1, 1.0, 0.0))
        .unwrap();
    sys.prescribe_coordinate(b, 1, Driver::constant(0.0))
        .unwrap();
    sys.prescribe_coordinate(b, 2, Driver::linear(0.0, 1.0))
        .unwrap();
    let err = sys.initial_state(0.0).unwrap_err().to_string();
    assert!(err.contains("`beam`") && err.contains("not held"), "{err}");
    // Pinned to the ground, free to swing: the frame is not prescribed.
    let mut sys = System::planar();
    let b = sys.add_body("beam", body(), Pose::identity(2)).unwrap();
    sys.revolute(Marker::ground(Vector3::zeros()), Marker::origin(b))
        .unwrap();
    let err = sys.initial_state(0.0).unwrap_err().to_string();
    assert!(err.contains("`beam`"), "{err}");
    // The same body with the hub at rest runs.
    let mut sys = System::planar();
    let b = sys.add_body("beam", body(), Pose::identity(2)).unwrap();
    sys.prescribe_rotation_about_z(b, Driver::linear(0.0, 1.0))
        .unwrap();
    sys.initial_state(0.0).unwrap();
}

/// Every built-in scene run on the kernels `ffr run` picks for it and on the
/// general kernels (spatial scene, free frame; `ffr run --general`) gives
/// the same outputs to round-off: what specialization leaves out is exactly
/// zero in that scene (measured: identical bits). Each output is compared
/// relative to its largest magnitude over the run.
#[test]
fn built_in_scenes_give_the_general_kernels_results() {
    use ffr::scene::{self, DefaultKernels, GeneralKernels};
    let root = ffr::scene::load::builtin_dir();
    for name in ["spin_up", "pendulum", "free_floating", "two_link_arm"] {
        let path = root.join(format!("{name}.toml"));
        let mut special = scene::load_with(&path, &DefaultKernels).unwrap();
        let mut general = scene::load_with(&path, &GeneralKernels).unwrap();
        // A short stretch of each scene is enough to exercise every term.
        for s in [&mut special, &mut general] {
            s.t_end = s.t_end.min(200.0 * s.dt);
        }
        assert!(
            general
                .kernels
                .iter()
                .all(|(_, k)| k != "compiled" && (k == "rigid" || k == "compiled, general")),
            "{:?}",
            general.kernels
        );
        let (a, b) = (scene::run(&special).unwrap(), scene::run(&general).unwrap());
        assert!(a.failed.is_none() && b.failed.is_none());
        assert_eq!(a.t.len(), b.t.len());
        for ((n, x), y) in a.names.iter().zip(&a.columns).zip(&b.columns) {
            let scale = x
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()))
                .max(f64::MIN_POSITIVE);
            let diff = x
                .iter()
                .zip(y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            println!("{name} {n}: {:.1e} of {scale:.3e}", diff / scale);
            assert!(diff <= 1e-8 * scale, "{name} {n}: {diff:e} of {scale:e}");
        }
    }
}
