//! `#[flex_body(segments = N)]`: the constructor `segments()` splits the
//! body as a scene file's `segments = N` does, so a system built by hand
//! from it with `System::add_segments` runs bit for bit like the scene.

use arm_crate::attr::ThrownBeam;
use ffr::runtime::nalgebra::{UnitQuaternion, Vector3};
use ffr::runtime::{Body, CompiledBody, Marker, Pose, System};
use std::path::Path;

/// The scene's beam, field for field.
fn beam() -> ThrownBeam {
    ThrownBeam {
        length: 2.0,
        rho: 2700.0,
        area: 1e-4,
        iy: 8.333333333333334e-10,
        iz: 8.333333333333334e-10,
        e: 7e10,
        g: 2.6e10,
        j: 1.406e-9,
    }
}

#[test]
fn attribute_segments_run_like_the_scene_file() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thrown_segments.toml");
    let loaded = ffr::scene::load(&path).unwrap();
    assert_eq!(ThrownBeam::SEGMENTS, 4);
    assert_eq!(<ThrownBeam as CompiledBody>::ELEMENTS, 8);
    let (root, others, bounds) = beam().segments().unwrap();
    assert_eq!(others.len(), 3);
    assert_eq!(bounds, [0.0, 0.5, 1.0, 1.5, 2.0]);
    // The same split as the scene's (section positions bit for bit).
    let (id, _) = loaded.flex_body("beam").unwrap();
    let group = loaded.system.segment_group(id).unwrap();
    assert_eq!(group.bounds, bounds);
    // Each segment is the scene's segment, to the last bit.
    let mine: Vec<&dyn Body> = std::iter::once(&root as &dyn Body)
        .chain(others.iter().map(|b| b as &dyn Body))
        .collect();
    for (k, (b, &sid)) in mine.iter().zip(&group.bodies).enumerate() {
        let theirs = &**loaded.system.body(sid);
        assert_eq!(
            ffr::runtime::sample_bits(*b, 1e-3),
            ffr::runtime::sample_bits(theirs, 1e-3),
            "segment {}",
            k + 1
        );
    }
    // The system by hand: the root added as the body, the others as its
    // segments, the initial velocities on the root (the whole body).
    let mut sys: System<Box<dyn Body>> = System::with_dim(3);
    let id = sys
        .add_body(
            "beam",
            Box::new(root),
            Pose::spatial(Vector3::zeros(), UnitQuaternion::identity()),
        )
        .unwrap();
    let others: Vec<Box<dyn Body>> = others
        .into_iter()
        .map(|b| Box::new(b) as Box<dyn Body>)
        .collect();
    sys.add_segments(id, others, &bounds).unwrap();
    sys.set_velocity(id, Vector3::zeros(), Vector3::new(0.0, 0.0, 2.0))
        .unwrap();
    // Then gravity and the joint, as the scene adds them.
    sys.set_gravity(Vector3::new(0.0, 0.0, -9.81)).unwrap();
    sys.spherical(Marker::ground(Vector3::zeros()), Marker::origin(id))
        .unwrap();
    sys.initial_state(0.0).unwrap();
    let mut hand = ffr::scene::load(&path).unwrap();
    hand.system = sys;
    let a = ffr::scene::run(&hand).unwrap();
    let b = ffr::scene::run(&loaded).unwrap();
    assert!(a.failed.is_none() && b.failed.is_none());
    assert_eq!(a.t.len(), 501);
    let bits = |r: &ffr::scene::SceneRun| -> Vec<u64> {
        r.t.iter()
            .chain(r.columns.iter().flatten())
            .map(|x| x.to_bits())
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));
    // The beam fell and bent (the comparison is not of two resting beams).
    let peak = |c: &[f64]| c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(peak(&a.columns[1]) > 0.1, "tip_z");
    assert!(
        peak(&a.columns[2]) > 1e-3,
        "tip_deflection {}",
        peak(&a.columns[2])
    );
}
