//! The spin-up beam (Kane, Ryan & Banerjee 1987) with a generated beam2 body:
//! the published peak, divergence of the linear model, convergence in
//! elements and step size, and the files the job writes.

use ffr::spin_up::{run, SpinUpArgs, Switch};

fn args(omega: f64, elements: u16, stiff: bool, t_end: f64, dt: f64, name: &str) -> SpinUpArgs {
    let dir = std::env::temp_dir().join(format!("ffr-spin-up-{}", std::process::id()));
    SpinUpArgs {
        omega,
        elements,
        stiffening: if stiff { Switch::On } else { Switch::Off },
        t_end,
        dt,
        csv: Some(dir.join(format!("{name}.csv"))),
        svg: None,
    }
}

/// Published (geometrically exact) peak transverse tip deflection at
/// 4 rad/s: about −0.53 m near t ≈ 6–7 s.
#[test]
fn stiffened_beam_matches_the_published_peak_and_writes_csv_and_svg() {
    let r = run(&args(4.0, 8, true, 20.0, 0.01, "omega4")).unwrap();
    let (t, y) = r.result.min_transverse().unwrap();
    assert!(r.result.diverged.is_none());
    assert!(
        (-0.55..-0.51).contains(&y) && (6.0..7.5).contains(&t),
        "peak {y} at {t}"
    );
    // After the ramp the beam keeps only a small residual vibration.
    assert!(r.result.max_abs_transverse_after(15.0) < 0.02);
    assert_eq!(r.steps, 2000);
    let csv = std::fs::read_to_string(&r.csv).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("t,tip_axial,tip_transverse"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2001);
    assert!(rows.iter().all(|r| r.len() == 3));
    assert!(rows.iter().any(|r| (r[2] - y).abs() < 1e-15));
    let svg = std::fs::read_to_string(&r.svg).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("tip_transverse"));
}

#[test]
fn linear_model_diverges_at_ten_rad_per_second_and_the_stiffened_one_does_not() {
    let lin = run(&args(10.0, 8, false, 20.0, 0.01, "linear10")).unwrap();
    let d = lin
        .result
        .diverged
        .expect("the linear FFR model must diverge");
    assert!(d.t < 15.0, "diverged only at {}", d.t);
    let stiff = run(&args(10.0, 8, true, 20.0, 0.01, "stiff10")).unwrap();
    assert!(stiff.result.diverged.is_none());
    let (t, y) = stiff.result.min_transverse().unwrap();
    // Published peak about −1.08 m; 8 elements give −1.106 m at t ≈ 6.2 s.
    assert!(
        (-1.12..-1.04).contains(&y) && (5.5..7.5).contains(&t),
        "peak {y} at {t}"
    );
}

/// Tip deflection at t = 7 s against element count and step size: the
/// differences between successive refinements shrink (2, 4, 8, 16 elements
/// at dt = 0.01 s; dt = 0.02, 0.01, 0.005 s at 8 elements).
#[test]
fn tip_deflection_converges_in_elements_and_step_size() {
    let at7 = |n: u16, dt: f64| {
        let r = run(&args(4.0, n, true, 7.0, dt, &format!("conv_{n}_{dt}"))).unwrap();
        assert!(r.result.diverged.is_none());
        *r.result.tip_transverse.last().unwrap()
    };
    let by_n: Vec<f64> = [2, 4, 8, 16].iter().map(|&n| at7(n, 0.01)).collect();
    let dn: Vec<f64> = by_n.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    assert!(
        dn[1] < dn[0] && dn[2] < dn[1],
        "element refinement {by_n:?}"
    );
    assert!(dn[2] < 2e-3, "16 vs 8 elements differ by {} m", dn[2]);
    let by_dt: Vec<f64> = [0.02, 0.01, 0.005].iter().map(|&dt| at7(8, dt)).collect();
    let dd: Vec<f64> = by_dt.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    assert!(dd[1] < dd[0], "step refinement {by_dt:?}");
    assert!(dd[1] < 1e-4, "dt 0.005 vs 0.01 differ by {} m", dd[1]);
    println!("tip at 7 s, elements 2/4/8/16: {by_n:?}; dt 0.02/0.01/0.005: {by_dt:?}");
}
