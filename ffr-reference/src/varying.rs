//! Elements whose section varies along the span (issue 19), by quadrature:
//! the section properties are given at stations and interpolated linearly
//! between them; an element is split at the stations inside it and each
//! piece integrated by Gauss–Legendre in `ξ`. Over the section, each
//! distribution (mass, stiffness) is replaced by four points `±a_i e_i`
//! (`e_i` the principal directions of its second-moment tensor in `(y, z)`,
//! weights `w/4`) that reproduce its zeroth, first (zero) and second
//! moments, so every integrand of degree ≤ 2 in `(y, z)` (all of the beam
//! shapes' products) is integrated exactly with the reference's own shape
//! functions `S(ξ, η, ζ)`.
//!
//! The model (`docs/theory.md`, "Varying sections"): the mass distribution
//! has `∫ρ dA = ρA`, `∫ρ y² dA = ρI_z`, `∫ρ z² dA = ρI_y`, `∫ρ yz dA = ρI_yz`,
//! except in a product of two transverse (`y`, `z`) components in `S̄_kl`
//! (of `S`) and `Ī_kl` (of `ū₀` and `S`), where the section turns about x
//! (torsion) and its second moments are the torsional ones
//! `M + ½ (ρJ − tr M) I` (so their trace is `ρJ`); `Θ` uses `M`. The stiffness
//! distribution has `EA`, `EI_z = ∫E y²`, `EI_y = ∫E z²`, `EI_yz = ∫E yz`;
//! torsion `∫GJ φ'² dx`.

use super::{gauss_legendre, Shape};
use nalgebra::{DVector, Vector3};

/// The section resultants at one station `x` (SI units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Station {
    /// Position along the span (m).
    pub x: f64,
    /// `ρA` (kg/m).
    pub rho_a: f64,
    /// `∫ρ z² dA` (kg m).
    pub rho_iy: f64,
    /// `∫ρ y² dA` (kg m).
    pub rho_iz: f64,
    /// `∫ρ yz dA` (kg m).
    pub rho_iyz: f64,
    /// Polar mass moment per length (kg m).
    pub rho_j: f64,
    /// `EA` (N).
    pub ea: f64,
    /// `∫E z² dA` (N m²).
    pub ei_y: f64,
    /// `∫E y² dA` (N m²).
    pub ei_z: f64,
    /// `∫E yz dA` (N m²).
    pub ei_yz: f64,
    /// `GJ` (N m²).
    pub gj: f64,
}

impl Station {
    fn lerp(a: &Station, b: &Station, t: f64) -> Station {
        let f = |p: f64, q: f64| p + (q - p) * t;
        Station {
            x: f(a.x, b.x),
            rho_a: f(a.rho_a, b.rho_a),
            rho_iy: f(a.rho_iy, b.rho_iy),
            rho_iz: f(a.rho_iz, b.rho_iz),
            rho_iyz: f(a.rho_iyz, b.rho_iyz),
            rho_j: f(a.rho_j, b.rho_j),
            ea: f(a.ea, b.ea),
            ei_y: f(a.ei_y, b.ei_y),
            ei_z: f(a.ei_z, b.ei_z),
            ei_yz: f(a.ei_yz, b.ei_yz),
            gj: f(a.gj, b.gj),
        }
    }
}

/// The section at `x`: linear between stations (sorted by `x`), constant
/// beyond the ends.
pub fn section_at(stations: &[Station], x: f64) -> Station {
    let first = stations[0];
    let last = stations[stations.len() - 1];
    if x <= first.x {
        return Station { x, ..first };
    }
    if x >= last.x {
        return Station { x, ..last };
    }
    let i = stations.iter().position(|s| s.x > x).expect("inside");
    let (a, b) = (&stations[i - 1], &stations[i]);
    Station::lerp(a, b, (x - a.x) / (b.x - a.x))
}

/// Four section points `(y, z, weight)` with total weight `w`, zero first
/// moments and second moments `[[∫y², ∫yz], [∫yz, ∫z²]] = m` (positive
/// semi-definite): `±a_i e_i` over the eigenpairs `(λ_i, e_i)` of `m`,
/// `a_i = √(2 λ_i / w)`, weight `w/4` each.
fn section_points(w: f64, m: [[f64; 2]; 2]) -> [(f64, f64, f64); 4] {
    let (a, b, c) = (m[0][0], m[0][1], m[1][1]);
    let mean = 0.5 * (a + c);
    let r = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = (mean + r, (mean - r).max(0.0));
    // Eigenvector of l1: angle θ with tan 2θ = 2b / (a − c).
    let th = 0.5 * (2.0 * b).atan2(a - c);
    let (e1, e2) = ((th.cos(), th.sin()), (-th.sin(), th.cos()));
    let (a1, a2) = ((2.0 * l1 / w).sqrt(), (2.0 * l2 / w).sqrt());
    let q = 0.25 * w;
    [
        (a1 * e1.0, a1 * e1.1, q),
        (-a1 * e1.0, -a1 * e1.1, q),
        (a2 * e2.0, a2 * e2.1, q),
        (-a2 * e2.0, -a2 * e2.1, q),
    ]
}

/// One element's invariants (theory names), `n_e` element coordinates: the
/// body's type over an element's coordinates.
pub type ElementInvariants = super::RefInvariants;

/// Gauss points per piece: `S_kᵀ S_l` is of degree 6 in `ξ`, times a linear
/// property 7; 6 points integrate degree ≤ 11.
const NXI: usize = 6;

/// `(ξ, weight)` over `[0, 1]`, split at the stations inside the element
/// `[x₀, x₀ + l]`, Gauss–Legendre on each piece.
fn element_points(stations: &[Station], x0: f64, l: f64) -> Vec<(f64, f64)> {
    let mut cuts = vec![0.0];
    cuts.extend(
        stations
            .iter()
            .map(|s| (s.x - x0) / l)
            .filter(|&t| t > 0.0 && t < 1.0),
    );
    cuts.push(1.0);
    cuts.windows(2)
        .flat_map(|w| gauss_legendre(NXI, w[0], w[1]))
        .collect()
}

/// The consistent invariants and stiffness of one element `[x₀, x₀ + l]`
/// of `shape` with the section varying through `stations`.
pub fn element_invariants(
    shape: Shape,
    stations: &[Station],
    x0: f64,
    l: f64,
) -> ElementInvariants {
    let ne = shape.elem_dofs();
    let mut r = ElementInvariants::zeros(ne);
    let planar = shape == Shape::Beam2;
    for (xi, wx) in element_points(stations, x0, l) {
        let s = section_at(stations, x0 + xi * l);
        let bend = [[s.rho_iz, s.rho_iyz], [s.rho_iyz, s.rho_iy]];
        let extra = 0.5 * (s.rho_j - s.rho_iy - s.rho_iz);
        let tors = [[s.rho_iz + extra, s.rho_iyz], [s.rho_iyz, s.rho_iy + extra]];
        // Mass distribution: bending points, and torsional points for the
        // products of two transverse components.
        for (set, transverse) in [(bend, false), (tors, true)] {
            for (y, z, w) in section_points(s.rho_a, set) {
                let w = w * l * wx;
                let sm = shape.elem_s(l, xi, y / l, z / l);
                let u0 = Vector3::new(x0 + xi * l, y, if planar { 0.0 } else { z });
                if !transverse {
                    r.mass += w;
                    r.s_t0 += w * u0;
                    r.s_bar += w * &sm;
                }
                for k in 0..3 {
                    for kk in 0..3 {
                        if !transverse {
                            // Θ: the undeformed body's inertia, bending moments.
                            r.theta[(k, kk)] += w * u0[k] * u0[kk];
                        }
                        if (k > 0 && kk > 0) != transverse {
                            continue;
                        }
                        let sk = sm.row(k).transpose();
                        let sl = sm.row(kk);
                        r.s_kl[k][kk] += w * &sk * sl;
                        r.i_kl[k][kk] += (w * u0[k]) * sl.transpose();
                    }
                }
            }
        }
        // Stiffness distribution.
        let stiff = [[s.ei_z, s.ei_yz], [s.ei_yz, s.ei_y]];
        for (y, z, w) in section_points(s.ea, stiff) {
            let g = shape.elem_dsx_dx(l, xi, y / l, z / l);
            r.k_ff += (w * l * wx) * &g * g.transpose();
        }
        if shape == Shape::Beam3 {
            let mut t = DVector::zeros(ne);
            t[3] = -1.0 / l;
            t[9] = 1.0 / l;
            r.k_ff += (s.gj * l * wx) * &t * t.transpose();
        }
    }
    r.m_ff = &r.s_kl[0][0] + &r.s_kl[1][1] + &r.s_kl[2][2];
    r
}

/// A section of principal stiffnesses and inertias turned by `twist` about
/// +x (the principal axes `y' = cos θ y + sin θ z`, `z' = −sin θ y + cos θ z`):
/// `∫E y² = EI_z' cos²θ + EI_y' sin²θ`, `∫E z² = EI_z' sin²θ + EI_y' cos²θ`,
/// `∫E yz = (EI_z' − EI_y') sin θ cos θ`, and the same for the mass moments.
/// Arguments: `(x, ρA, ρI_y', ρI_z', ρJ, EA, EI_y', EI_z', GJ, θ)`.
#[allow(clippy::too_many_arguments)]
pub fn twisted_station(
    x: f64,
    rho_a: f64,
    rho_iy: f64,
    rho_iz: f64,
    rho_j: f64,
    ea: f64,
    ei_y: f64,
    ei_z: f64,
    gj: f64,
    twist: f64,
) -> Station {
    let (s, c) = twist.sin_cos();
    // Rotate the tensor diag(∫y'², ∫z'²) into (y, z): y = c y' − s z', z = s y' + c z'.
    let rot = |iy: f64, iz: f64| {
        (
            iz * c * c + iy * s * s, // ∫ y²
            iz * s * s + iy * c * c, // ∫ z²
            (iz - iy) * s * c,       // ∫ y z
        )
    };
    let (rz, ry, ryz) = rot(rho_iy, rho_iz);
    let (ez, ey, eyz) = rot(ei_y, ei_z);
    Station {
        x,
        rho_a,
        rho_iy: ry,
        rho_iz: rz,
        rho_iyz: ryz,
        rho_j,
        ea,
        ei_y: ey,
        ei_z: ez,
        ei_yz: eyz,
        gj,
    }
}

/// The geometric-stiffening energy `U_nl` of one element `[x₀, x₀ + l]` of
/// a varying section at element coordinates `q_e`, by quadrature on the
/// pieces between stations (`docs/theory.md` §14): the element means
/// `ū' = ∫₀¹ u' dξ`, `s̄ = ∫₀¹ (v'² + w'²) dξ` and `EA_mean = ∫₀¹ EA dξ`;
/// second order `EA_mean l (½ ū' s̄ + ⅛ s̄²)`; fourth order
/// `½ EA_mean l (ε̄² − ū'²)`, `ε̄ = ū' + ½ ū'² + ½ s̄`, plus
/// `½ l ∫₀¹ g [EI_z v''v' + EI_y w''w' + EI_yz (v''w' + v'w'')] dξ`,
/// `g = v'v'' + w'w''`.
pub fn stiffening_energy(
    shape: Shape,
    stations: &[Station],
    x0: f64,
    l: f64,
    model: super::StiffeningModel,
    qe: &[f64],
) -> f64 {
    let q = DVector::from_column_slice(qe);
    let (mut ea, mut du, mut s_bar, mut bend) = (0.0, 0.0, 0.0, 0.0);
    for (xi, w) in element_points(stations, x0, l) {
        let s = section_at(stations, x0 + xi * l);
        let (a, b, c) = shape.centerline_grad(l, xi);
        let (b2, c2) = shape.centerline_curv(l, xi);
        let (u1, v1, w1) = (a.dot(&q), b.dot(&q), c.dot(&q));
        let (v2, w2) = (b2.dot(&q), c2.dot(&q));
        ea += w * s.ea;
        du += w * u1;
        s_bar += w * (v1 * v1 + w1 * w1);
        let g = v1 * v2 + w1 * w2;
        bend += w * g * (s.ei_z * v2 * v1 + s.ei_y * w2 * w1 + s.ei_yz * (v2 * w1 + v1 * w2));
    }
    match model {
        super::StiffeningModel::SecondOrder => ea * l * (0.5 * du * s_bar + 0.125 * s_bar * s_bar),
        super::StiffeningModel::FourthOrder => {
            let eps = du + 0.5 * du * du + 0.5 * s_bar;
            0.5 * ea * l * (eps * eps - du * du) + 0.5 * l * bend
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn section_points_reproduce_the_moments() {
        let m = [[3.0, -1.0], [-1.0, 0.5]];
        let pts = section_points(2.0, m);
        let sum =
            |f: &dyn Fn(f64, f64) -> f64| pts.iter().map(|&(y, z, w)| w * f(y, z)).sum::<f64>();
        assert!((sum(&|_, _| 1.0) - 2.0).abs() < 1e-15);
        assert!(sum(&|y, _| y).abs() < 1e-15);
        assert!(sum(&|_, z| z).abs() < 1e-15);
        assert!((sum(&|y, _| y * y) - 3.0).abs() < 1e-14);
        assert!((sum(&|y, z| y * z) + 1.0).abs() < 1e-14);
        assert!((sum(&|_, z| z * z) - 0.5).abs() < 1e-14);
    }

    #[test]
    fn a_twisted_section_keeps_its_invariants() {
        // Trace and determinant of the stiffness tensor do not depend on the twist.
        let s = twisted_station(0.0, 1.0, 2.0, 5.0, 7.0, 1.0, 3.0, 11.0, 1.0, 0.4);
        assert!((s.ei_y + s.ei_z - 14.0).abs() < 1e-13);
        assert!((s.ei_y * s.ei_z - s.ei_yz * s.ei_yz - 33.0).abs() < 1e-12);
        assert!((s.rho_iy + s.rho_iz - 7.0).abs() < 1e-13);
        // Principal axis of ei_z: y' = (cos θ, sin θ); ∫E (y'·r)² = EI_z'.
        let (sn, c) = 0.4f64.sin_cos();
        let along = s.ei_z * c * c + s.ei_y * sn * sn + 2.0 * s.ei_yz * sn * c;
        assert!((along - 11.0).abs() < 1e-12, "{along}");
    }
}
