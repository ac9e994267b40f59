//! Prescribed motions `f(t)` with their first two derivatives.

use std::f64::consts::PI;
use std::fmt;
use std::sync::Arc;

/// A map of `[f, ḟ, f̈]` (the chain rule of [`Driver::map`]).
type Post = Arc<dyn Fn([f64; 3]) -> [f64; 3] + Send + Sync>;

/// A prescribed function of time returning `[f, ḟ, f̈]`: a base function,
/// optionally perturbed by an input's drive perturbation `δ` (added to the
/// base, [`Driver::with_input`]), then mapped ([`Driver::map`]).
#[derive(Clone)]
pub struct Driver {
    f: Arc<dyn Fn(f64) -> [f64; 3] + Send + Sync>,
    post: Option<Post>,
    /// Known to have `f̈ ≡ 0` (constant or linear).
    uniform: bool,
    /// The input whose perturbation `[δ, δ̇, δ̈]` is added to the base.
    input: Option<usize>,
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
            post: None,
            uniform: false,
            input: None,
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
    /// `[f(t), ḟ(t), f̈(t)]` (unperturbed).
    pub fn eval(&self, t: f64) -> [f64; 3] {
        match &self.post {
            None => (self.f)(t),
            Some(p) => p((self.f)(t)),
        }
    }
    /// `[f, ḟ, f̈]` at `t` with the perturbation `d = [δ, δ̇, δ̈]` added to
    /// the base function before the map.
    pub fn eval_perturbed(&self, t: f64, d: [f64; 3]) -> [f64; 3] {
        let [f, fd, fdd] = (self.f)(t);
        let x = [f + d[0], fd + d[1], fdd + d[2]];
        match &self.post {
            None => x,
            Some(p) => p(x),
        }
    }
    /// The input whose drive perturbation this driver takes, if any.
    pub fn input(&self) -> Option<usize> {
        self.input
    }
    /// This driver perturbed by input `k`'s drive perturbation `δ(t)`
    /// (`δ̈` = the input's value, held over each step; the assembly
    /// integrates `δ` and `δ̇`). Not uniform any more.
    pub fn with_input(&self, k: usize) -> Self {
        Self {
            uniform: false,
            input: Some(k),
            ..self.clone()
        }
    }
    /// `g([f, ḟ, f̈])`: a new driver from this one's value and derivatives
    /// (the caller supplies the chain rule).
    pub fn map(&self, g: impl Fn([f64; 3]) -> [f64; 3] + Send + Sync + 'static) -> Self {
        let post: Post = match &self.post {
            None => Arc::new(g),
            Some(p) => {
                let p = p.clone();
                Arc::new(move |x| g(p(x)))
            }
        };
        Self {
            f: self.f.clone(),
            post: Some(post),
            uniform: false,
            input: self.input,
        }
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
