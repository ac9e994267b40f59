//! `ffr stability`: the quick suite through the library and through the
//! binary (as CI runs it), and the runner's verdicts on cases that panic,
//! give a non-finite figure, hit their CPU limit or return an error.

use ffr_cli::stability::{cases, run_cases, run_suite, Case, Outcome, Progress, Verdict};
use std::path::PathBuf;
use std::process::Command;

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ffr-stability-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every quick case passes; the cases that must be refused (the singular
/// mass matrices, RK4 far above its stability limit) are refusals, not runs;
/// every run that passed shows figures, all finite; stability.md has a row
/// per case.
#[test]
fn quick_suite_passes_with_the_expected_refusals() {
    let out = temp_dir("lib");
    let quick = cases::quick();
    let s = run_cases(&quick, &out, "quick (test)", Progress::Silent).unwrap();
    assert_eq!(s.results.len(), quick.len());
    for r in &s.results {
        println!("{}: {:?} {:?}", r.name, r.verdict, r.figures);
        assert!(r.verdict.passed(), "{}: {:?}", r.name, r.verdict);
        let refusal_expected =
            r.name.starts_with("stiff-spin-up-rk4") || r.name == "free-reference";
        assert_eq!(
            matches!(r.verdict, Verdict::Refused(_)),
            refusal_expected,
            "{}: {:?}",
            r.name,
            r.verdict
        );
        if r.verdict == Verdict::Pass {
            assert!(!r.figures.is_empty(), "{}: no figures", r.name);
        }
        assert!(r.figures.iter().all(|(_, x)| x.is_finite()), "{}", r.name);
    }
    let md = std::fs::read_to_string(out.join("stability.md")).unwrap();
    for c in &quick {
        assert_eq!(
            md.matches(&format!("| `{}` |", c.name)).count(),
            1,
            "{} not listed once",
            c.name
        );
    }
    assert!(!md.contains("FAIL"), "{md}");
}

/// `ffr stability --quick` exits 0 and writes stability.md listing every
/// quick case as passed.
#[test]
fn quick_command_exits_zero_and_lists_every_case() {
    let out = temp_dir("bin");
    let run = Command::new(env!("CARGO_BIN_EXE_ffr"))
        .args(["stability", "--quick", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let n = cases::quick().len();
    assert!(
        stdout.contains(&format!("{n} cases: {n} passed, 0 failed")),
        "{stdout}"
    );
    let md = std::fs::read_to_string(out.join("stability.md")).unwrap();
    for c in cases::quick() {
        let row = md
            .lines()
            .find(|l| l.starts_with(&format!("| `{}` |", c.name)))
            .unwrap_or_else(|| panic!("{} not listed", c.name));
        assert!(row.contains("| pass"), "{row}");
    }
}

/// A panic, a silent NaN, a run stopped by its CPU limit (and not reporting
/// it) and an error are failures; a passing case next to them still
/// passes; the suite reports failure (the command's non-zero exit) naming
/// the failed cases, and stability.md marks them.
#[test]
fn failing_cases_fail_the_suite() {
    let out = temp_dir("fail");
    let list = vec![
        Case::new("ok", "nothing", "none", 5.0, |_| {
            Ok(Outcome::pass(vec![("x".into(), 1.0)]))
        }),
        Case::new("nan", "a silent NaN", "none", 5.0, |_| {
            Ok(Outcome::pass(vec![("energy drift".into(), f64::NAN)]))
        }),
        Case::new("blow-up", "a silent infinity", "none", 5.0, |_| {
            Ok(Outcome::pass(vec![("tip".into(), f64::INFINITY)]))
        }),
        Case::new(
            "panic",
            "a panic",
            "none",
            5.0,
            |_| -> Result<Outcome, String> { panic!("injected panic") },
        ),
        Case::new("hang", "a run that would not end", "none", 0.2, |b| {
            let mut t = 0.0;
            while b.tick(t).is_continue() {
                t += 1.0;
            }
            Ok(Outcome::pass(vec![("t".into(), t)]))
        }),
        Case::new("error", "an error", "none", 5.0, |_| {
            Err("injected error".into())
        }),
    ];
    let err = run_suite(&list, &out, "injected", Progress::Silent)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("5 case(s) failed: nan, blow-up, panic, hang, error"),
        "{err}"
    );
    let s = run_cases(&list, &out, "injected", Progress::Silent).unwrap();
    let verdict = |name: &str| {
        s.results
            .iter()
            .find(|r| r.name == name)
            .unwrap()
            .verdict
            .clone()
    };
    assert_eq!(verdict("ok"), Verdict::Pass);
    let fail = |name: &str, needle: &str| match verdict(name) {
        Verdict::Fail(m) => assert!(m.contains(needle), "{name}: {m}"),
        v => panic!("{name}: {v:?}"),
    };
    fail("nan", "`energy drift` is NaN");
    fail("blow-up", "`tip` is inf");
    fail("panic", "panic: injected panic");
    fail("hang", "CPU limit of 0.2 s");
    fail("error", "injected error");
    let md = std::fs::read_to_string(out.join("stability.md")).unwrap();
    assert_eq!(md.matches("**FAIL**").count(), 5, "{md}");
    assert!(md.contains("6 cases, 1 passed, 5 failed"), "{md}");
}
