//! `integrator = { … }`: generalized-α or RK4 with Baumgarte stabilization.

use super::Ctx;
use super::{fin_f64, pos_f64};
use crate::codegen::scene::quoted as q;
use crate::codegen::scene::RawIntegrator;
use crate::runtime::{GeneralizedAlpha, Integrator, Rk4Baumgarte};
use crate::scene::SceneError;
use toml::Spanned;

pub(super) fn integrator(
    c: &Ctx,
    r: &Option<Spanned<RawIntegrator>>,
) -> Result<Integrator, SceneError> {
    let Some(r) = r else {
        return Ok(Integrator::default());
    };
    let i = r.get_ref();
    match i.kind.get_ref().as_str() {
        "generalized-alpha" => {
            let mut g = GeneralizedAlpha::default();
            if let Some(x) = &i.rho_inf {
                g.rho_inf = fin_f64(c, x, "rho_inf")?;
                if !(0.0..=1.0).contains(&g.rho_inf) {
                    return Err(c.err(
                        x.span(),
                        format!("`rho_inf` must be in [0, 1], found {:?}", g.rho_inf),
                    ));
                }
            }
            if let Some(x) = &i.rtol {
                g.rtol = pos_f64(c, x, "rtol")?;
                if g.rtol >= 1.0 {
                    return Err(c.err(
                        x.span(),
                        format!(
                            "`rtol` (the relative Newton tolerance) must be in (0, 1), found {:?}",
                            g.rtol
                        ),
                    ));
                }
            }
            Ok(Integrator::GeneralizedAlpha(g))
        }
        "rk4" => {
            let mut k = Rk4Baumgarte::default();
            if let Some(x) = &i.alpha {
                k.alpha = fin_f64(c, x, "alpha")?;
            }
            if let Some(x) = &i.beta {
                k.beta = fin_f64(c, x, "beta")?;
            }
            Ok(Integrator::Rk4(k))
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
