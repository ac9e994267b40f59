//! The cases of a study: the product of its axes, numbered from 0 with the
//! last axis varying fastest; and the values of ranges and seeded samples.

use ffr::scene::SceneValue;
use rand::SeedableRng;
use rand_distr::Distribution;

/// The most cases a study may have (the product of its axes' lengths).
pub const MAX_CASES: usize = 100_000;

/// One axis: a dotted scene key and its values.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The key as written in the study (`joints.0.drive.omega`).
    pub key: String,
    /// Its values, in order.
    pub values: Vec<SceneValue>,
}

/// Number of cases of `axes` (1 without axes); the study reader checked it
/// is at most [`MAX_CASES`].
pub fn count(axes: &[Axis]) -> usize {
    axes.iter().map(|a| a.values.len()).product()
}

/// The value index on each axis of case `case` (the last axis fastest).
pub fn indices(axes: &[Axis], case: usize) -> Vec<usize> {
    let mut rest = case;
    let mut out = vec![0; axes.len()];
    for (i, a) in axes.iter().enumerate().rev() {
        let n = a.values.len();
        out[i] = rest % n;
        rest /= n;
    }
    out
}

/// The values of case `case`, one per axis.
pub fn values(axes: &[Axis], case: usize) -> Vec<&SceneValue> {
    indices(axes, case)
        .into_iter()
        .zip(axes)
        .map(|(i, a)| &a.values[i])
        .collect()
}

/// A value as the results table writes it: numbers in the shortest form
/// that reads back to the same `f64`, integers and strings as they are,
/// anything else as TOML.
pub fn cell(v: &SceneValue) -> String {
    match v {
        SceneValue::Float(x) => crate::output::number(*x),
        SceneValue::Int(i) => i.to_string(),
        SceneValue::Bool(b) => b.to_string(),
        SceneValue::Str(s) => s.clone(),
        other => other.to_string(),
    }
}

/// `n` values from `a` to `b`, both included (`a + (b − a) i / (n − 1)`,
/// the last exactly `b`). Where `b − a` overflows (finite ends more than
/// `f64::MAX` apart), `a (1 − s) + b s` with `s = i / (n − 1)`, which
/// stays between the ends.
pub fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    if n == 1 {
        return vec![a];
    }
    let width = b - a;
    (0..n)
        .map(|i| {
            let s = i as f64 / (n - 1) as f64;
            if i + 1 == n {
                b
            } else if width.is_finite() {
                a + width * s
            } else {
                a * (1.0 - s) + b * s
            }
        })
        .collect()
}

/// The generator of seeded samples: ChaCha8, a fixed algorithm, so that a
/// seed gives the same stream on every platform and release.
fn rng(seed: u64) -> rand_chacha::ChaCha8Rng {
    rand_chacha::ChaCha8Rng::seed_from_u64(seed)
}

/// `n` samples uniform in `[a, b)` from `seed`, or why there are none
/// (`rand_distr` refuses ends that are not finite, not in order, or whose
/// width `b − a` overflows).
pub fn uniform(a: f64, b: f64, n: usize, seed: u64) -> Result<Vec<f64>, String> {
    let d = rand_distr::Uniform::new(a, b).map_err(|e| match e {
        rand_distr::uniform::Error::NonFinite => format!(
            "high − low = {} − ({}) is not a finite number; give ends at most {:e} apart",
            crate::output::number(b),
            crate::output::number(a),
            f64::MAX
        ),
        e => format!("{e}"),
    })?;
    let mut g = rng(seed);
    Ok((0..n).map(|_| d.sample(&mut g)).collect())
}

/// `n` samples of a normal distribution from `seed`.
pub fn normal(mean: f64, sd: f64, n: usize, seed: u64) -> Result<Vec<f64>, String> {
    let d = rand_distr::Normal::new(mean, sd).map_err(|e| format!("{e}"))?;
    let mut g = rng(seed);
    Ok((0..n).map(|_| d.sample(&mut g)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_last_axis_varies_fastest() {
        let axes = vec![
            Axis {
                key: "a".into(),
                values: vec![1.0.into(), 2.0.into()],
            },
            Axis {
                key: "b".into(),
                values: vec![SceneValue::Int(4), SceneValue::Int(8), SceneValue::Int(16)],
            },
        ];
        assert_eq!(count(&axes), 6);
        assert_eq!(indices(&axes, 0), [0, 0]);
        assert_eq!(indices(&axes, 2), [0, 2]);
        assert_eq!(indices(&axes, 3), [1, 0]);
        assert_eq!(indices(&axes, 5), [1, 2]);
        assert_eq!(count(&[]), 1);
        assert!(indices(&[], 0).is_empty());
    }

    #[test]
    fn ranges_include_their_ends() {
        let v = linspace(1.0, 4.0, 7);
        assert_eq!(v, [1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]);
        let v = linspace(0.1, 0.7, 7);
        assert_eq!(v[0], 0.1);
        assert_eq!(v[6], 0.7);
    }

    #[test]
    fn ranges_whose_width_overflows_stay_finite() {
        // b − a = 2e308 overflows; the values are the ends and the points
        // between them (here symmetric about 0).
        let v = linspace(-1e308, 1e308, 5);
        assert_eq!(v, [-1e308, -5e307, 0.0, 5e307, 1e308]);
        let v = linspace(f64::MAX, -f64::MAX, 3);
        assert_eq!(v, [f64::MAX, 0.0, -f64::MAX]);
        // Seeded samples over such a range are refused, with the reason.
        let e = uniform(-1e308, 1e308, 3, 1).unwrap_err();
        assert!(e.contains("not a finite number"), "{e}");
    }

    #[test]
    fn samples_depend_on_the_seed_only() {
        let a = uniform(1.0, 2.0, 50, 7).unwrap();
        assert_eq!(a, uniform(1.0, 2.0, 50, 7).unwrap());
        assert_ne!(a, uniform(1.0, 2.0, 50, 8).unwrap());
        assert!(a.iter().all(|x| (1.0..2.0).contains(x)));
        let g = normal(5.0, 0.5, 2000, 3).unwrap();
        let mean = g.iter().sum::<f64>() / g.len() as f64;
        assert!((mean - 5.0).abs() < 0.05, "{mean}");
        assert_eq!(normal(0.0, 0.0, 3, 1).unwrap(), [0.0, 0.0, 0.0]);
    }
}
