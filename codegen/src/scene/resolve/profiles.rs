//! Drive profiles (`angle`/`slide` tables of joints' drives and motor
//! targets): constant, linear, harmonic, spin-up ramps, with their bounds
//! checked up to `t_end`.

use super::Ctx;
use super::{fin_f64, pos_f64};
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::RawProfile;
use ffr_spec::scene::ProfileSpec;
use toml::Spanned;

pub(super) fn profile(
    c: &Ctx,
    p: &Spanned<RawProfile>,
    key: &str,
    t_end: f64,
    who: &str,
) -> Result<ProfileSpec, Error> {
    profile_at(c, p.span(), p.get_ref(), key, t_end, who)
}

/// A profile whose table is at `span`.
pub(super) fn profile_at(
    c: &Ctx,
    span: std::ops::Range<usize>,
    r: &RawProfile,
    key: &str,
    t_end: f64,
    who: &str,
) -> Result<ProfileSpec, Error> {
    // Bounds of |f|, |ḟ|, |f̈| on [0, t_end]: each must be finite, or the
    // prescribed motion overflows during the run.
    let bounded = |bounds: &[(&str, f64)]| -> Result<(), Error> {
        match bounds.iter().find(|(_, b)| !b.is_finite()) {
            None => Ok(()),
            Some((what, b)) => Err(c.err(
                span.clone(),
                format!(
                    "{who}: the profile's {what} reaches {b:?} before t_end = {t_end:?}: beyond the range of f64"
                ),
            )),
        }
    };
    let name = match key {
        "angle" => r.angle.as_ref(),
        _ => r.slide.as_ref(),
    }
    .ok_or_else(|| c.err(span.clone(), format!("the drive needs `{key} = \"…\"`: one of spin-up, constant-rate, constant, harmonic")))?;
    let need = |v: &Option<Spanned<f64>>, what: &str| -> Result<f64, Error> {
        v.as_ref()
            .ok_or_else(|| {
                c.err(
                    name.span(),
                    format!("profile `{}` needs `{what}`", q(name.get_ref())),
                )
            })
            .and_then(|x| fin_f64(c, x, what))
    };
    let opt = |v: &Option<Spanned<f64>>, what: &str, d: f64| -> Result<f64, Error> {
        v.as_ref().map_or(Ok(d), |x| fin_f64(c, x, what))
    };
    match name.get_ref().as_str() {
        "spin-up" => {
            let omega = need(&r.omega, "omega")?;
            let ramp = r
                .ramp
                .as_ref()
                .ok_or_else(|| c.err(name.span(), "profile `spin-up` needs `ramp` (s)"))
                .and_then(|x| pos_f64(c, x, "ramp"))?;
            let start = opt(&r.start, "start", 0.0)?;
            bounded(&[
                (
                    "value (start + omega (t_end + ramp))",
                    start.abs() + omega.abs() * (t_end + ramp),
                ),
                ("rate (2 omega)", 2.0 * omega.abs()),
                ("acceleration (2 omega/ramp)", 2.0 * omega.abs() / ramp),
            ])?;
            Ok(ProfileSpec::SpinUp { omega, ramp, start })
        }
        "constant-rate" => {
            let w = r
                .omega
                .as_ref()
                .or(r.rate.as_ref())
                .ok_or_else(|| {
                    c.err(
                        name.span(),
                        "profile `constant-rate` needs `omega` (rad/s, or m/s for a slide)",
                    )
                })
                .and_then(|x| fin_f64(c, x, "omega"))?;
            let start = opt(&r.start, "start", 0.0)?;
            bounded(&[
                ("value (start + omega t_end)", start.abs() + w.abs() * t_end),
                ("rate (omega)", w.abs()),
            ])?;
            Ok(ProfileSpec::ConstantRate { start, rate: w })
        }
        "constant" => Ok(ProfileSpec::Constant(need(&r.value, "value")?)),
        "harmonic" => {
            let start = opt(&r.start, "start", 0.0)?;
            let a = need(&r.amplitude, "amplitude")?;
            let nu = need(&r.frequency, "frequency")?;
            let phase = opt(&r.phase, "phase", 0.0)?;
            let w = 2.0 * std::f64::consts::PI * nu.abs();
            bounded(&[
                ("value (start + amplitude)", start.abs() + a.abs()),
                ("rate (amplitude 2π frequency)", a.abs() * w),
                ("acceleration (amplitude (2π frequency)²)", a.abs() * w * w),
                (
                    "phase (2π frequency t_end + phase)",
                    w * t_end + phase.abs(),
                ),
            ])?;
            Ok(ProfileSpec::Harmonic {
                start,
                amplitude: a,
                frequency: nu,
                phase,
            })
        }
        other => Err(c.err(
            name.span(),
            format!(
                "unknown profile `{other}`: expected spin-up, constant-rate, constant or harmonic",
                other = q(other)
            ),
        )),
    }
}
