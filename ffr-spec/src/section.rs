//! Sections that vary along a beam's span (issue 19): the section
//! resultants a varying model integrates ([`SectionProp`]), the choice
//! between a uniform and a varying section model ([`SectionModel`]), and the
//! *element moments* of a property, `μ_{P,k} = ∫₀¹ P(x₀ + ξ l) ξ^k dξ`,
//! computed exactly for a property that is piecewise linear between stations
//! ([`element_moments`]).
//!
//! Kernels of a varying model are written in these moments instead of the
//! uniform parameters (`ρ`, `A`, `I_y`, …): a term `c · ξ^k · P` of an
//! element integral integrates to `c · μ_{P,k}` (theory: "Varying sections").

use crate::text::Num;
use std::fmt;

/// A section resultant: a function of `x` along the beam, in body axes
/// (`y`, `z` the section's coordinates; the section's centres of mass and
/// tension on the x axis, so `∫ρ y dA = ∫ρ z dA = ∫E y dA = ∫E z dA = 0`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SectionProp {
    /// Mass per length `ρA = ∫ρ dA` (kg/m).
    RhoA,
    /// `ρI_y = ∫ρ z² dA` (kg m): rotary inertia of bending in x–z (`w`).
    RhoIy,
    /// `ρI_z = ∫ρ y² dA` (kg m): rotary inertia of bending in x–y (`v`).
    RhoIz,
    /// `ρI_yz = ∫ρ y z dA` (kg m): non-zero for a twisted section.
    RhoIyz,
    /// Polar mass moment per length `ρJ` (kg m); a physical section has
    /// `ρJ = ρI_y + ρI_z` (the uniform model's value).
    RhoJ,
    /// Axial stiffness `EA = ∫E dA` (N).
    Ea,
    /// `EI_y = ∫E z² dA` (N m²): bending in the x–z plane (`w`).
    EiY,
    /// `EI_z = ∫E y² dA` (N m²): bending in the x–y plane (`v`).
    EiZ,
    /// `EI_yz = ∫E y z dA` (N m²): non-zero for a twisted section.
    EiYz,
    /// Torsional stiffness `GJ` (N m²).
    Gj,
}

impl SectionProp {
    /// Every property, in declaration order.
    pub const ALL: [SectionProp; 10] = [
        SectionProp::RhoA,
        SectionProp::RhoIy,
        SectionProp::RhoIz,
        SectionProp::RhoIyz,
        SectionProp::RhoJ,
        SectionProp::Ea,
        SectionProp::EiY,
        SectionProp::EiZ,
        SectionProp::EiYz,
        SectionProp::Gj,
    ];

    /// The name in generated code (`mu_{name}_{k}`) and tables.
    pub const fn name(self) -> &'static str {
        match self {
            SectionProp::RhoA => "rho_a",
            SectionProp::RhoIy => "rho_iy",
            SectionProp::RhoIz => "rho_iz",
            SectionProp::RhoIyz => "rho_iyz",
            SectionProp::RhoJ => "rho_j",
            SectionProp::Ea => "ea",
            SectionProp::EiY => "ei_y",
            SectionProp::EiZ => "ei_z",
            SectionProp::EiYz => "ei_yz",
            SectionProp::Gj => "gj",
        }
    }

    /// The value a uniform body with these parameters has (`rho, area, iy,
    /// iz, e, g, j`): `ρA`, `ρI_y`, `ρI_z`, 0, `ρ(I_y + I_z)`, `EA`, `EI_y`,
    /// `EI_z`, 0, `GJ`.
    pub fn uniform_value(self, p: &crate::Params) -> f64 {
        match self {
            SectionProp::RhoA => p.rho * p.area,
            SectionProp::RhoIy => p.rho * p.iy,
            SectionProp::RhoIz => p.rho * p.iz,
            SectionProp::RhoIyz | SectionProp::EiYz => 0.0,
            SectionProp::RhoJ => p.rho * (p.iy + p.iz),
            SectionProp::Ea => p.e * p.area,
            SectionProp::EiY => p.e * p.iy,
            SectionProp::EiZ => p.e * p.iz,
            SectionProp::Gj => p.g * p.j,
        }
    }
}

impl fmt::Display for SectionProp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How the generator integrates the section along an element.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SectionModel {
    /// One section for the whole body, in the parameters `ρ, A, I_y, I_z,
    /// E, G, J` (today's kernels).
    #[default]
    Uniform,
    /// Section resultants that vary along the element: kernels read the
    /// element moments `μ_{P,k}` through per-element coefficients
    /// (`section_coefficients`).
    Varying,
}

impl fmt::Display for SectionModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SectionModel::Uniform => "uniform",
            SectionModel::Varying => "varying",
        })
    }
}

/// Stations of a property that cannot be integrated.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionError(pub String);

impl fmt::Display for SectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SectionError {}

/// `μ_k = ∫₀¹ P(x₀ + ξ l) ξ^k dξ` for `k = 0 … out.len() − 1`, exactly (one
/// closed-form polynomial integral per piece), for the property `P` that is
/// linear in `x` between the stations `(x_i, P_i)` (strictly increasing `x`)
/// and constant beyond the first and last one. The element `[x₀, x₀ + l]`
/// is split at the stations inside it: on a piece `ξ ∈ [a, b]` with
/// `P = α + β ξ`, `∫_a^b P ξ^k dξ = α (b^{k+1} − a^{k+1})/(k+1) +
/// β (b^{k+2} − a^{k+2})/(k+2)`.
pub fn element_moments(
    stations: &[(f64, f64)],
    x0: f64,
    l: f64,
    out: &mut [f64],
) -> Result<(), SectionError> {
    if stations.is_empty() {
        return Err(SectionError(
            "a section property needs at least one station".into(),
        ));
    }
    if !(l.is_finite() && l > 0.0 && x0.is_finite()) {
        return Err(SectionError(format!(
            "element [x0 = {x0}, l = {l}]: the length must be positive and both finite"
        )));
    }
    for (i, &(x, p)) in stations.iter().enumerate() {
        if !(x.is_finite() && p.is_finite()) {
            return Err(SectionError(format!(
                "station {i} (x = {}, value {}) is not finite",
                Num(x),
                Num(p)
            )));
        }
        if i > 0 && x <= stations[i - 1].0 {
            return Err(SectionError(format!(
                "station {i} at x = {} does not follow station {} at x = {}: stations must be strictly increasing in x",
                Num(x),
                i - 1,
                Num(stations[i - 1].0)
            )));
        }
    }
    out.iter_mut().for_each(|m| *m = 0.0);
    // The value at body x.
    let value = |x: f64| -> f64 {
        let (first, last) = (stations[0], stations[stations.len() - 1]);
        if x <= first.0 {
            return first.1;
        }
        if x >= last.0 {
            return last.1;
        }
        let i = stations.partition_point(|s| s.0 <= x);
        let ((xa, pa), (xb, pb)) = (stations[i - 1], stations[i]);
        pa + (pb - pa) * (x - xa) / (xb - xa)
    };
    // Break points in ξ: 0, the stations strictly inside, 1.
    let mut cuts = vec![0.0];
    for &(x, _) in stations {
        let xi = (x - x0) / l;
        if xi > 0.0 && xi < 1.0 {
            cuts.push(xi);
        }
    }
    cuts.push(1.0);
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (pa, pb) = (value(x0 + a * l), value(x0 + b * l));
        let beta = (pb - pa) / (b - a);
        let alpha = pa - beta * a;
        let (mut ak, mut bk) = (a, b); // a^{k+1}, b^{k+1}
        for (k, m) in out.iter_mut().enumerate() {
            let k = k as f64;
            let (ak2, bk2) = (ak * a, bk * b);
            *m += alpha * (bk - ak) / (k + 1.0) + beta * (bk2 - ak2) / (k + 2.0);
            ak = ak2;
            bk = bk2;
        }
    }
    Ok(())
}

/// The element moments a kernel set reads (`list`, as its
/// `section_moments()` gives them) for the element `[x₀, x₀ + l]`, each
/// property `P` piecewise linear through `stations(P)` ([`element_moments`]);
/// `mu[i]` is the moment of `list[i]`. No allocation.
pub fn fill_moments<'t>(
    list: &[(SectionProp, u8)],
    stations: impl Fn(SectionProp) -> &'t [(f64, f64)],
    x0: f64,
    l: f64,
    mu: &mut [f64],
) -> Result<(), SectionError> {
    if mu.len() != list.len() {
        return Err(SectionError(format!(
            "{} moments requested into an array of {}",
            list.len(),
            mu.len()
        )));
    }
    let mut buf = [0.0; 256];
    let mut current: Option<SectionProp> = None;
    for (i, &(prop, k)) in list.iter().enumerate() {
        if current != Some(prop) {
            // All moments of `prop` up to the highest `k` the list asks for.
            let kmax = list
                .iter()
                .filter(|(p, _)| *p == prop)
                .map(|&(_, k)| k as usize)
                .max()
                .unwrap_or(0);
            element_moments(stations(prop), x0, l, &mut buf[..=kmax])
                .map_err(|e| SectionError(format!("{prop}: {e}")))?;
            current = Some(prop);
        }
        mu[i] = buf[k as usize];
    }
    Ok(())
}

/// Second moments of a section whose principal axes are turned by `twist`
/// (rad) about +x, in body axes: the principal axes are
/// `y' = cos θ y + sin θ z` (moment `i_z' = ∫ y'²`) and
/// `z' = −sin θ y + cos θ z` (`i_y' = ∫ z'²`), the convention of
/// `scenes/data/README.md` (`twist = −StrcTwst`). Returns
/// `(∫z², ∫y², ∫yz) = (i_y' cos²θ + i_z' sin²θ, i_y' sin²θ + i_z' cos²θ,
/// (i_z' − i_y') sin θ cos θ)`: for stiffnesses `(EI_y, EI_z, EI_yz)`, for
/// mass moments `(ρI_y, ρI_z, ρI_yz)`.
pub fn twisted_moments(i_y: f64, i_z: f64, twist: f64) -> (f64, f64, f64) {
    let (s, c) = twist.sin_cos();
    (
        i_y * c * c + i_z * s * s,
        i_y * s * s + i_z * c * c,
        (i_z - i_y) * s * c,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `∫₀¹ f` by composite Gauss–Legendre (3 points) on `n` equal cells.
    fn numeric(f: impl Fn(f64) -> f64, n: usize) -> f64 {
        let g = [
            (-(0.6f64).sqrt(), 5.0 / 9.0),
            (0.0, 8.0 / 9.0),
            ((0.6f64).sqrt(), 5.0 / 9.0),
        ];
        let h = 1.0 / n as f64;
        (0..n)
            .map(|i| {
                let mid = (i as f64 + 0.5) * h;
                g.iter()
                    .map(|&(t, w)| 0.5 * h * w * f(mid + 0.5 * h * t))
                    .sum::<f64>()
            })
            .sum()
    }

    fn interp(st: &[(f64, f64)], x: f64) -> f64 {
        if x <= st[0].0 {
            return st[0].1;
        }
        for w in st.windows(2) {
            if x <= w[1].0 {
                return w[0].1 + (w[1].1 - w[0].1) * (x - w[0].0) / (w[1].0 - w[0].0);
            }
        }
        st[st.len() - 1].1
    }

    #[test]
    fn moments_match_numerical_integration() {
        let st = [(0.0, 3.0), (0.7, 1.5), (1.1, 2.5), (1.13, 0.25), (2.0, 1.0)];
        // Elements: containing several stations, one, none, reaching beyond.
        for (x0, l) in [(0.0, 2.0), (0.5, 0.4), (0.2, 0.3), (1.0, 0.5), (1.8, 0.5)] {
            let mut mu = [0.0; 8];
            element_moments(&st, x0, l, &mut mu).unwrap();
            for (k, m) in mu.iter().enumerate() {
                // 3-point Gauss on cells that do not align with the stations:
                // a kink inside a cell costs O(h³); 20000 cells give ~1e-12.
                let r = numeric(|xi| interp(&st, x0 + xi * l) * xi.powi(k as i32), 20000);
                assert!((m - r).abs() < 1e-10, "x0 {x0} l {l} k {k}: {m} vs {r}");
            }
        }
    }

    #[test]
    fn constant_and_linear_properties_have_closed_forms() {
        let mut mu = [0.0; 5];
        element_moments(&[(0.0, 2.0), (10.0, 2.0)], 3.0, 1.5, &mut mu).unwrap();
        for (k, m) in mu.iter().enumerate() {
            assert!((m - 2.0 / (k as f64 + 1.0)).abs() < 1e-15);
        }
        // P = x on [1, 3]: ∫₀¹ (1 + 2ξ) ξ^k = 1/(k+1) + 2/(k+2).
        element_moments(&[(0.0, 0.0), (4.0, 4.0)], 1.0, 2.0, &mut mu).unwrap();
        for (k, m) in mu.iter().enumerate() {
            let k = k as f64;
            assert!((m - (1.0 / (k + 1.0) + 2.0 / (k + 2.0))).abs() < 1e-14);
        }
        // One station: a constant.
        element_moments(&[(0.5, 7.0)], 0.0, 1.0, &mut mu).unwrap();
        assert!((mu[0] - 7.0).abs() < 1e-15);
    }

    #[test]
    fn bad_stations_are_named() {
        let mut mu = [0.0; 2];
        let e = element_moments(&[(0.0, 1.0), (0.0, 2.0)], 0.0, 1.0, &mut mu).unwrap_err();
        assert!(e.to_string().contains("station 1 at x = 0"), "{e}");
        let e = element_moments(&[(0.0, f64::NAN)], 0.0, 1.0, &mut mu).unwrap_err();
        assert!(e.to_string().contains("not finite"), "{e}");
        assert!(element_moments(&[], 0.0, 1.0, &mut mu).is_err());
        assert!(element_moments(&[(0.0, 1.0)], 0.0, 0.0, &mut mu).is_err());
    }

    #[test]
    fn uniform_values() {
        let p = crate::Params::from_array([1.0, 2.0, 3.0, 5.0, 7.0, 11.0, 13.0, 17.0]);
        assert_eq!(SectionProp::RhoJ.uniform_value(&p), 24.0);
        assert_eq!(SectionProp::EiY.uniform_value(&p), 55.0);
        assert_eq!(SectionProp::EiYz.uniform_value(&p), 0.0);
        let mut names: Vec<_> = SectionProp::ALL.iter().map(|p| p.name()).collect();
        names.dedup();
        assert_eq!(names.len(), 10);
    }

    #[test]
    fn fill_moments_follows_the_list() {
        let a = [(0.0, 1.0), (1.0, 3.0)];
        let b = [(0.0, 2.0), (0.5, 0.0), (1.0, 2.0)];
        let list = [
            (SectionProp::RhoA, 0),
            (SectionProp::RhoA, 3),
            (SectionProp::EiZ, 1),
        ];
        let table = |p: SectionProp| -> &[(f64, f64)] {
            if p == SectionProp::RhoA {
                &a
            } else {
                &b
            }
        };
        let mut mu = [0.0; 3];
        fill_moments(&list, table, 0.0, 1.0, &mut mu).unwrap();
        // ∫(1 + 2ξ) = 2, ∫(1 + 2ξ) ξ³ = 1/4 + 2/5; ∫|4ξ − 2| ξ = 1/2.
        assert!((mu[0] - 2.0).abs() < 1e-15);
        assert!((mu[1] - 0.65).abs() < 1e-15);
        assert!((mu[2] - 0.5).abs() < 1e-15);
        let e = fill_moments(&list, table, 0.0, 1.0, &mut [0.0; 2]).unwrap_err();
        assert!(e.to_string().contains("3 moments"), "{e}");
    }

    #[test]
    fn twisted_moments_keep_the_principal_values() {
        let (iy, iz, iyz) = twisted_moments(3.0, 11.0, 0.4);
        assert!((iy + iz - 14.0).abs() < 1e-13);
        assert!((iy * iz - iyz * iyz - 33.0).abs() < 1e-12);
        // ∫(y'·r)² along y' = (cos θ, sin θ) is i_z'; along z' it is i_y'.
        let (s, c) = 0.4f64.sin_cos();
        assert!((iz * c * c + iy * s * s + 2.0 * iyz * s * c - 11.0).abs() < 1e-12);
        assert!((iz * s * s + iy * c * c - 2.0 * iyz * s * c - 3.0).abs() < 1e-12);
        assert_eq!(twisted_moments(3.0, 11.0, 0.0), (3.0, 11.0, 0.0));
    }
}
