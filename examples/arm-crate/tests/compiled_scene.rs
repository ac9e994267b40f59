//! A scene compiled by `build.rs` (`Builder::scene`) simulates bit for bit
//! like `ffr run` on the same file, which loads it at run time with the
//! built-in kernels.

use arm_crate::scenes::TwoLinksScene;
use std::path::Path;

#[test]
fn compiled_scene_runs_bit_for_bit_like_ffr_run() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/two_links.toml");
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        TwoLinksScene::SOURCE,
        "the compiled scene embeds the file"
    );
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
