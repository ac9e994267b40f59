//! A scene compiled by `build.rs` (`Builder::scene`) carries the resolved
//! scene as data (nothing is parsed at start-up: the crate depends on `ffr`
//! without the `scene-files` feature) and simulates bit for bit like `ffr
//! run` on the same file, which loads it at run time with the built-in
//! kernels.

use arm_crate::scenes::TwoLinksScene;
use std::path::Path;

#[test]
fn compiled_scene_runs_bit_for_bit_like_ffr_run() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/two_links.toml");
    // The generated data is the scene the file resolves to, field for field
    // (floats bit for bit: `SceneSpec`'s `PartialEq` compares them exactly,
    // and the file's values are finite).
    let base = path.parent().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let resolved = ffr_codegen::scene::resolve_str(&text, TwoLinksScene::ORIGIN, base).unwrap();
    assert_eq!(TwoLinksScene::spec(), resolved);
    let compiled = TwoLinksScene::load().unwrap();
    let loaded = ffr::scene::load(&path).unwrap();
    // The compiled scene runs its own kernels.
    assert!(
        compiled
            .kernels
            .iter()
            .any(|(_, k)| k == "compiled (scene)"),
        "{:?}",
        compiled.kernels
    );
    assert!(loaded.kernels.iter().all(|(_, k)| k != "compiled (scene)"));
    let a = ffr::scene::run(&compiled).unwrap();
    let b = ffr::scene::run(&loaded).unwrap();
    assert!(a.failed.is_none() && b.failed.is_none());
    assert_eq!(a.names, ["hand_x", "hand_y", "elbow_bend"]);
    assert_eq!(a.t.len(), 501);
    let bits = |r: &ffr::scene::SceneRun| -> Vec<u64> {
        r.t.iter()
            .chain(r.columns.iter().flatten())
            .map(|x| x.to_bits())
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));
    // The arm moved (the comparison is not of two resting arms).
    let hand_x = &a.columns[0];
    assert!(hand_x.iter().fold(0.0f64, |m, x| m.max(x.abs())) > 0.1);
}

/// Every scene shipped with ffr, compiled by `build.rs`: its generated data
/// is the scene the file resolves to, its bodies run the scene's own
/// kernels (a modal body its reduction made when compiled and generated
/// kernels of its inertia equations), and its first 0.2 s are bit for bit
/// those of `ffr run` (which runs the 5-MW blade's varying sections on
/// tapes: the compiled varying kernels give the tape's numbers exactly),
/// except the modal scene's: `ffr run` evaluates that body's inertia
/// equations at run time, in another order, so its outputs agree to 1e-9
/// of each column's peak.
#[test]
fn built_in_scenes_compile_to_their_files() {
    use arm_crate::scenes::*;
    type Compiled = (
        &'static str,
        fn() -> ffr::runtime::spec::scene::SceneSpec,
        fn() -> Result<ffr::scene::Scene, ffr::SceneError>,
    );
    let scenes: [Compiled; 10] = [
        (
            BuiltinFreeFloatingScene::ORIGIN,
            BuiltinFreeFloatingScene::spec,
            BuiltinFreeFloatingScene::load,
        ),
        (
            BuiltinPendulumScene::ORIGIN,
            BuiltinPendulumScene::spec,
            BuiltinPendulumScene::load,
        ),
        (
            BuiltinPreconeScene::ORIGIN,
            BuiltinPreconeScene::spec,
            BuiltinPreconeScene::load,
        ),
        (
            BuiltinSliderCrankScene::ORIGIN,
            BuiltinSliderCrankScene::spec,
            BuiltinSliderCrankScene::load,
        ),
        (
            BuiltinSpinUpScene::ORIGIN,
            BuiltinSpinUpScene::spec,
            BuiltinSpinUpScene::load,
        ),
        (
            BuiltinSpinUpModalScene::ORIGIN,
            BuiltinSpinUpModalScene::spec,
            BuiltinSpinUpModalScene::load,
        ),
        (
            BuiltinTwoLinkArmScene::ORIGIN,
            BuiltinTwoLinkArmScene::spec,
            BuiltinTwoLinkArmScene::load,
        ),
        (
            BuiltinBlade5mwScene::ORIGIN,
            BuiltinBlade5mwScene::spec,
            BuiltinBlade5mwScene::load,
        ),
        (
            BuiltinBoomPayloadScene::ORIGIN,
            BuiltinBoomPayloadScene::spec,
            BuiltinBoomPayloadScene::load,
        ),
        (
            BuiltinLFrameScene::ORIGIN,
            BuiltinLFrameScene::spec,
            BuiltinLFrameScene::load,
        ),
    ];
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (origin, spec, load) in scenes {
        let path = root.join(origin);
        let text = std::fs::read_to_string(&path).unwrap();
        let resolved =
            ffr_codegen::scene::resolve_str(&text, origin, path.parent().unwrap()).unwrap();
        assert_eq!(spec(), resolved, "{origin}");
        let mut compiled = load().unwrap();
        assert!(
            compiled
                .kernels
                .iter()
                .any(|(_, k)| k.contains("compiled (scene)")),
            "{origin}: {:?}",
            compiled.kernels
        );
        // A modal body's reduction is baked into the compiled scene, and
        // its inertia equations are generated kernels.
        let modal = origin.ends_with("spin_up_modal.toml");
        if modal {
            assert!(
                compiled
                    .kernels
                    .iter()
                    .any(|(_, k)| k.contains("reduced when compiled, generated inertia kernels")),
                "{:?}",
                compiled.kernels
            );
        }
        let mut loaded = ffr::scene::from_str(
            &text,
            origin,
            path.parent().unwrap(),
            &ffr::scene::DefaultKernels,
        )
        .unwrap();
        for s in [&mut compiled, &mut loaded] {
            s.t_end = s.t_end.min(0.2);
        }
        let a = ffr::scene::run(&compiled).unwrap();
        let b = ffr::scene::run(&loaded).unwrap();
        assert!(a.failed.is_none() && b.failed.is_none(), "{origin}");
        assert!(a.t.len() > 10, "{origin}");
        let bits = |r: &ffr::scene::SceneRun| -> Vec<u64> {
            r.t.iter()
                .chain(r.columns.iter().flatten())
                .map(|x| x.to_bits())
                .collect()
        };
        if !modal {
            assert_eq!(bits(&a), bits(&b), "{origin}");
            continue;
        }
        // The generated kernels add in another order than the run-time
        // equations the loaded scene runs: the same history to round-off.
        assert_eq!(a.t, b.t, "{origin}");
        for (ca, cb) in a.columns.iter().zip(&b.columns) {
            let peak = cb.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let diff = ca
                .iter()
                .zip(cb)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            eprintln!("{origin}: largest difference {diff:e}, peak {peak:e}");
            assert!(diff <= 1e-9 * peak, "{origin}: {diff:e} of {peak:e}");
        }
    }
}

/// The history of a run, bit for bit.
fn bits(r: &ffr::scene::SceneRun) -> Vec<u64> {
    r.t.iter()
        .chain(r.columns.iter().flatten())
        .map(|x| x.to_bits())
        .collect()
}

/// A body run as segments (`segments = 4`), compiled: the root segment
/// `beam` runs kernels for its prescribed frame (the driven hub joint
/// folds), `beam[2]` … `beam[4]` one shared set for free frames, and the
/// whole body (`modes`, `invariants`) the root's. Bit for bit like
/// `ffr::scene::load` of the same file.
#[test]
fn segmented_scene_runs_bit_for_bit_like_ffr_run() {
    use arm_crate::scenes::SpinUpSegmentsScene;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/spin_up_segments.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let resolved =
        ffr_codegen::scene::resolve_str(&text, SpinUpSegmentsScene::ORIGIN, path.parent().unwrap())
            .unwrap();
    assert_eq!(SpinUpSegmentsScene::spec(), resolved);
    let compiled = SpinUpSegmentsScene::load().unwrap();
    let loaded = ffr::scene::load(&path).unwrap();
    let names: Vec<&str> = compiled.kernels.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["beam", "beam[2]", "beam[3]", "beam[4]"]);
    assert!(
        compiled
            .kernels
            .iter()
            .all(|(_, k)| k == "compiled (scene)"),
        "{:?}",
        compiled.kernels
    );
    assert!(loaded.kernels.iter().all(|(_, k)| k != "compiled (scene)"));
    let a = ffr::scene::run(&compiled).unwrap();
    let b = ffr::scene::run(&loaded).unwrap();
    assert!(a.failed.is_none() && b.failed.is_none());
    assert_eq!(a.names, ["tip_u", "tip_v", "tip_w", "mid_w"]);
    assert_eq!(a.t.len(), 301);
    assert_eq!(bits(&a), bits(&b));
    // The beam fell under gravity (not two resting beams compared).
    let tip_w = &a.columns[2];
    assert!(tip_w.iter().fold(0.0f64, |m, x| m.max(x.abs())) > 0.1);
}

/// Modal segments, compiled: each segment's Craig–Bampton reduction (the
/// root's and the last's differ) and the whole body's are baked in, with
/// generated inertia kernels; the run agrees with `ffr::scene::load`
/// (which reduces at load and runs the run-time inertia equations, adding
/// in another order) to 1e-9 of each column's peak, as the unsegmented
/// modal scene does.
#[test]
fn modal_segments_compile() {
    use arm_crate::scenes::SpinUpModalSegmentsScene;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/spin_up_modal_segments.toml");
    let compiled = SpinUpModalSegmentsScene::load().unwrap();
    let loaded = ffr::scene::load(&path).unwrap();
    let names: Vec<&str> = compiled.kernels.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["beam", "beam[2]"]);
    for (name, k) in &compiled.kernels {
        assert!(
            k.contains("reduced when compiled, generated inertia kernels"),
            "{name}: {k}"
        );
    }
    for (name, k) in &loaded.kernels {
        assert!(k.contains("reduced at load"), "{name}: {k}");
    }
    // The whole body (one frame, for `modes` and `invariants`) is reduced
    // as the file says: the same modes whether compiled or loaded.
    let (wa, wb) = (&compiled.unsplit, &loaded.unsplit);
    assert_eq!(wa.len(), 1);
    assert_eq!(wa[0].0, "beam");
    assert_eq!(wa[0].1.layout().nf, wb[0].1.layout().nf);
    assert_eq!(wa[0].1.layout().labels, wb[0].1.layout().labels);
    let a = ffr::scene::run(&compiled).unwrap();
    let b = ffr::scene::run(&loaded).unwrap();
    assert!(a.failed.is_none() && b.failed.is_none());
    assert_eq!(a.t, b.t);
    for (name, (ca, cb)) in a.names.iter().zip(a.columns.iter().zip(&b.columns)) {
        let peak = cb.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = ca
            .iter()
            .zip(cb)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        eprintln!("{name}: largest difference {diff:e}, peak {peak:e}");
        if name.ends_with("transverse") {
            assert!(peak > 1e-3, "{name}: the beam bent");
        }
        assert!(diff <= 1e-9 * peak, "{name}: {diff:e} of {peak:e}");
    }
}
