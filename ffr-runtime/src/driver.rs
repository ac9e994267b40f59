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
    pub fn spin_up(omega_s: f64, t_ramp: f64) -> Self {
        Self::new(move |t| {
            if t < t_ramp {
                let k = 2.0 * PI / t_ramp;
                let c = omega_s / t_ramp;
                [
                    c * (t * t / 2.0 + ((k * t).cos() - 1.0) / (k * k)),
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
