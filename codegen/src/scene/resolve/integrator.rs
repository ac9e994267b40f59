//! `integrator = { … }`: generalized-α or RK4 with Baumgarte stabilization.

use super::Ctx;
use super::{fin_f64, pos_f64};
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::RawIntegrator;
use ffr_spec::scene::IntegratorSpec;
use toml::Spanned;

pub(super) fn integrator(
    c: &Ctx,
    r: &Option<Spanned<RawIntegrator>>,
) -> Result<IntegratorSpec, Error> {
    let Some(r) = r else {
        return Ok(IntegratorSpec::default());
    };
    let i = r.get_ref();
    match i.kind.get_ref().as_str() {
        "generalized-alpha" => {
            let mut rho_inf = None;
            if let Some(x) = &i.rho_inf {
                let v = fin_f64(c, x, "rho_inf")?;
                if !(0.0..=1.0).contains(&v) {
                    return Err(c.err(
                        x.span(),
                        format!("`rho_inf` must be in [0, 1], found {v:?}"),
                    ));
                }
                rho_inf = Some(v);
            }
            let mut rtol = None;
            if let Some(x) = &i.rtol {
                let v = pos_f64(c, x, "rtol")?;
                if v >= 1.0 {
                    return Err(c.err(
                        x.span(),
                        format!(
                            "`rtol` (the relative Newton tolerance) must be in (0, 1), found {v:?}"
                        ),
                    ));
                }
                rtol = Some(v);
            }
            Ok(IntegratorSpec::GeneralizedAlpha { rho_inf, rtol })
        }
        "rk4" => {
            let alpha = i
                .alpha
                .as_ref()
                .map(|x| fin_f64(c, x, "alpha"))
                .transpose()?;
            let beta = i.beta.as_ref().map(|x| fin_f64(c, x, "beta")).transpose()?;
            Ok(IntegratorSpec::Rk4 { alpha, beta })
        }
        other => Err(c.err(
            i.kind.span(),
            format!(
                "unknown integrator `{other}`: expected generalized-alpha or rk4",
                other = q(other)
            ),
        )),
    }
}
