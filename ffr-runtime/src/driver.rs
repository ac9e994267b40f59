//! Prescribed motions `f(t)` with their first two derivatives.

use std::f64::consts::PI;
use std::fmt;
use std::sync::Arc;

/// A prescribed function of time returning `[f, ḟ, f̈]`.
#[derive(Clone)]
pub struct Driver {
    f: Arc<dyn Fn(f64) -> [f64; 3] + Send + Sync>,
    /// Known to have `f̈ ≡ 0` (constant or linear).
    uniform: bool,
}

impl fmt::Debug for Driver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Driver(f(0) = {:?})", self.eval(0.0))
    }
}

impl Driver {
    /// From a closure returning `[f(t), ḟ(t), f̈(t)]`.
    pub fn new(f: impl Fn(f64) -> [f64; 3] + Send + Sync + 'static) -> Self {
        Self {
            f: Arc::new(f),
            uniform: false,
        }
    }
    /// `f(t) = c`.
    pub fn constant(c: f64) -> Self {
        Self {
            uniform: true,
            ..Self::new(move |_| [c, 0.0, 0.0])
        }
    }
    /// `f(t) = f0 + rate · t`.
    pub fn linear(f0: f64, rate: f64) -> Self {
        Self {
            uniform: true,
            ..Self::new(move |t| [f0 + rate * t, rate, 0.0])
        }
    }
    /// Whether `f̈ ≡ 0` is known (built by [`Driver::constant`] or
    /// [`Driver::linear`]).
    pub fn is_uniform(&self) -> bool {
        self.uniform
    }
    /// The Kane–Ryan–Banerjee spin-up angle:
    /// `θ = (ω_s/T)(t²/2 + (T/2π)²(cos(2πt/T) − 1))` for `t < T`, `ω_s (t − T/2)` after.
    /// `(cos(kt) − 1)/k²` is evaluated as `−2 (sin(kt/2)/k)²`: the same
    /// value without `k²`, which underflows to 0 for a ramp beyond about
    /// 1e154 s (and `0/0` was NaN at t = 0), and without the cancellation of
    /// `cos(kt) − 1` at small `kt`.
    pub fn spin_up(omega_s: f64, t_ramp: f64) -> Self {
        Self::new(move |t| {
            if t < t_ramp {
                let k = 2.0 * PI / t_ramp;
                let c = omega_s / t_ramp;
                let s = (0.5 * k * t).sin() / k;
                [
                    c * (t * t / 2.0 - 2.0 * s * s),
                    c * (t - (k * t).sin() / k),
                    c * (1.0 - (k * t).cos()),
                ]
            } else {
                [omega_s * (t - t_ramp / 2.0), omega_s, 0.0]
            }
        })
    }
    /// `f(t) = f0 + a sin(2π ν t + φ)`.
    pub fn harmonic(f0: f64, amplitude: f64, frequency: f64, phase: f64) -> Self {
        Self::new(move |t| {
            let w = 2.0 * PI * frequency;
            let (s, c) = (w * t + phase).sin_cos();
            [
                f0 + amplitude * s,
                amplitude * w * c,
                -amplitude * w * w * s,
            ]
        })
    }
    /// `[f(t), ḟ(t), f̈(t)]`.
    pub fn eval(&self, t: f64) -> [f64; 3] {
        (self.f)(t)
    }
    /// `g([f, ḟ, f̈])`: a new driver from this one's value and derivatives
    /// (the caller supplies the chain rule).
    pub fn map(&self, g: impl Fn([f64; 3]) -> [f64; 3] + Send + Sync + 'static) -> Self {
        let f = self.f.clone();
        Self::new(move |t| g(f(t)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spin-up angle against its textbook form where that form is
    /// accurate, and finite (and ≈ 0) for a ramp so long that `k²` would
    /// underflow (issue 36: a ramp of 1e200 s was NaN at t = 0).
    #[test]
    fn spin_up_matches_its_formula_and_stays_finite_for_long_ramps() {
        let (w, tr) = (4.0, 15.0);
        let d = Driver::spin_up(w, tr);
        let k = 2.0 * PI / tr;
        for i in 0..=40 {
            let t = 0.5 * i as f64;
            let textbook = if t < tr {
                (w / tr) * (t * t / 2.0 + ((k * t).cos() - 1.0) / (k * k))
            } else {
                w * (t - tr / 2.0)
            };
            let v = d.eval(t);
            assert!(
                (v[0] - textbook).abs() <= 1e-12 * (1.0 + textbook.abs()),
                "{t}"
            );
            // The rate is the derivative of the angle.
            let h = 1e-6;
            if (t - tr).abs() > 2.0 * h && t > h {
                let fd = (d.eval(t + h)[0] - d.eval(t - h)[0]) / (2.0 * h);
                assert!(
                    (fd - v[1]).abs() < 1e-6 * (1.0 + v[1].abs()),
                    "{t}: {fd} {}",
                    v[1]
                );
            }
        }
        let long = Driver::spin_up(4.0, 1e200);
        for t in [0.0, 1.0, 20.0] {
            let v = long.eval(t);
            assert!(v.iter().all(|x| x.is_finite()), "{t}: {v:?}");
            assert!(v[0].abs() < 1e-150 && v[1].abs() < 1e-150, "{t}: {v:?}");
        }
    }
}
