//! Inertia shape integrals of one element and of a body of `N` equal
//! elements, computed exactly (theory: "Inertia shape integrals", "Lumped
//! masses", "A body made of elements").
//!
//! The element integrals are polynomials in the parameters, the element length
//! `l` and the element's offset `x₀` along body x ([`element_invariants`]).
//! Element kernels are generated from them directly; the body's invariants
//! ([`BodySpec::exact_invariants`]) are their exact assembly with `x₀ = e·l`
//! and `l = L/N`.

// Tensor code over coordinate and axis indices (`k`, `l`, `a`, `b` as in
// the theory): index loops read closer to the formulas than iterators.
#![allow(clippy::needless_range_loop)]

use crate::error::Error;
use crate::poly::{rat, Monomial, Param, Poly, Sym};
use crate::shape::Shape;
pub use ffr_spec::{Dof, Formalism, Mesh, Reference, SectionModel, SectionProp, MAX_ELEMENTS};

/// A body: `elements` equal elements of `shape` along body x from 0 to `L`.
#[derive(Clone, Debug)]
pub struct BodySpec {
    /// The element shape.
    pub shape: Shape,
    /// Number of elements `N ≥ 1`.
    pub elements: usize,
    /// Reference condition.
    pub reference: Reference,
    /// Inertia formalism.
    pub formalism: Formalism,
    mesh: Mesh,
}

/// A dense matrix of exact polynomials.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PolyMatrix {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    data: Vec<Poly>,
}

impl PolyMatrix {
    /// All-zero `rows × cols`.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            data: vec![Poly::zero(); rows * cols],
        }
    }

    /// Entry `(i, j)`.
    pub fn get(&self, i: usize, j: usize) -> &Poly {
        &self.data[i * self.cols + j]
    }

    /// Mutable entry `(i, j)`.
    pub fn get_mut(&mut self, i: usize, j: usize) -> &mut Poly {
        &mut self.data[i * self.cols + j]
    }

    fn map(&self, f: impl Fn(&Poly) -> Poly) -> PolyMatrix {
        PolyMatrix {
            rows: self.rows,
            cols: self.cols,
            data: self.data.iter().map(f).collect(),
        }
    }
}

/// Invariants as exact polynomials: of one element (in the parameters, `l`
/// and `x₀`; `n` = element coordinates) or of a body (in the runtime
/// parameters; `n = n_f`). Index order `k, l ∈ {x, y, z}`; a planar shape's z
/// components are zero.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExactInvariants {
    /// 2 or 3.
    pub dim: usize,
    /// Number of (elastic or element) coordinates.
    pub nf: usize,
    /// `m = ∫ρ dV`.
    pub mass: Poly,
    /// `S_t0 = ∫ρ ū₀ dV`.
    pub s_t0: [Poly; 3],
    /// `S̄ = ∫ρ S dV` (3 × n).
    pub s_bar: PolyMatrix,
    /// `S̄_kl = ∫ρ S_kᵀ S_l dV` (n × n each).
    pub s_kl: [[PolyMatrix; 3]; 3],
    /// `Ī_kl = ∫ρ ū₀_k S_l dV` (n each).
    pub i_kl: [[Vec<Poly>; 3]; 3],
    /// `Θ_kl = ∫ρ ū₀_k ū₀_l dV`.
    pub theta: [[Poly; 3]; 3],
    /// `m_ff = S̄_xx + S̄_yy + S̄_zz`.
    pub m_ff: PolyMatrix,
    /// `K_ff = ∫ E ε_xx² dV + ∫ G J φ'² dx`.
    pub k_ff: PolyMatrix,
}

impl ExactInvariants {
    fn zeros(dim: usize, n: usize) -> Self {
        let z3 = || [Poly::zero(), Poly::zero(), Poly::zero()];
        ExactInvariants {
            dim,
            nf: n,
            mass: Poly::zero(),
            s_t0: z3(),
            s_bar: PolyMatrix::zeros(3, n),
            s_kl: std::array::from_fn(|_| std::array::from_fn(|_| PolyMatrix::zeros(n, n))),
            i_kl: std::array::from_fn(|_| std::array::from_fn(|_| vec![Poly::zero(); n])),
            theta: [z3(), z3(), z3()],
            m_ff: PolyMatrix::zeros(n, n),
            k_ff: PolyMatrix::zeros(n, n),
        }
    }

    /// Every entry mapped through `f` (same sizes).
    pub fn map(&self, f: impl Fn(&Poly) -> Poly) -> ExactInvariants {
        let fm = |m: &PolyMatrix| m.map(&f);
        ExactInvariants {
            dim: self.dim,
            nf: self.nf,
            mass: f(&self.mass),
            s_t0: self.s_t0.each_ref().map(&f),
            s_bar: fm(&self.s_bar),
            s_kl: self.s_kl.each_ref().map(|r| r.each_ref().map(fm)),
            i_kl: self
                .i_kl
                .each_ref()
                .map(|r| r.each_ref().map(|v| v.iter().map(&f).collect())),
            theta: self.theta.each_ref().map(|r| r.each_ref().map(&f)),
            m_ff: fm(&self.m_ff),
            k_ff: fm(&self.k_ff),
        }
    }
}

fn p(param: Param) -> Poly {
    Poly::var(Sym::Param(param))
}

fn l_pow(e: i32) -> Monomial {
    Monomial::var(Sym::Param(Param::ElemLength), e)
}

/// `∫ f dA` over the section by the model's rules (`∫dA = A`,
/// `∫y dA = ∫z dA = ∫yz dA = 0`, `∫y² dA = I_z`, `∫z² dA = I_y`, with
/// `η = y/l`, `ζ = z/l`).
fn section(shape: &Shape, f: &Poly) -> Result<Poly, Error> {
    let mut out = Poly::zero();
    for (m, c) in f.terms() {
        let (a, b) = (m.exp(Sym::Eta), m.exp(Sym::Zeta));
        let (rest, _) = m.without(Sym::Eta);
        let (rest, _) = rest.without(Sym::Zeta);
        let moment = match (a, b) {
            (0, 0) => Monomial::var(Sym::Param(Param::Area), 1),
            (1, 0) | (0, 1) | (1, 1) => continue,
            (2, 0) => Monomial::var(Sym::Param(Param::Iz), 1).mul(&l_pow(-2)),
            (0, 2) => Monomial::var(Sym::Param(Param::Iy), 1).mul(&l_pow(-2)),
            _ => {
                return Err(Error::Section {
                    shape: shape.name.clone(),
                    term: m.to_string(),
                })
            }
        };
        out.add_term(rest.mul(&moment), c.clone());
    }
    Ok(out)
}

/// `∫ f dV` over one element: `l ∫₀¹ ∫ f dA dξ`.
fn volume(shape: &Shape, f: &Poly) -> Result<Poly, Error> {
    Ok(section(shape, f)?.mul_monomial(&l_pow(1)).integrate_xi())
}

/// What a varying section integral weighs with: the mass (`ρ`) or the
/// stiffness (`E`) distribution of the section.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Density {
    /// `ρ`; `transverse`: the integrand is a product of two transverse
    /// (`y`, `z`) components, of `S` (`S̄_kl`) or of `ū₀` and `S` (`Ī_kl`),
    /// where the section's second moments come from its rotation about x
    /// (torsion) and are the torsional ones (see [`varying_section_moment`]).
    /// `Θ_kl`, the undeformed body's own inertia, and every product with an
    /// axial component use `ρI_y`, `ρI_z`.
    Mass { transverse: bool },
    /// `E`.
    Elastic,
}

fn mu(prop: SectionProp, k: u8) -> Poly {
    Poly::var(Sym::Moment(prop, k))
}

/// `∫₀¹ ξ^k ∫ w η^a ζ^b dA dξ · l^{a+b}` for a varying section, as element
/// moments (`y = lη`, `z = lζ`; centres of mass and tension on the x axis, so
/// first moments vanish; `None` for those):
///
/// - mass: `(0,0)` `μ_{ρA,k}`; `(1,1)` `μ_{ρI_yz,k}`; `(2,0)` `μ_{ρI_z,k}`
///   and `(0,2)` `μ_{ρI_y,k}`, except in a product of two transverse
///   components of `S̄_kl` or `Ī_kl`, where the section turns about x
///   (torsion): there `(2,0)` is `½ (μ_{ρJ} − μ_{ρI_y} + μ_{ρI_z})` and
///   `(0,2)` `½ (μ_{ρJ} + μ_{ρI_y} − μ_{ρI_z})`, which sum to `μ_{ρJ}` and
///   equal `μ_{ρI_z}`, `μ_{ρI_y}` when `ρJ = ρI_y + ρI_z`;
/// - stiffness: `(0,0)` `μ_{EA,k}`, `(2,0)` `μ_{EI_z,k}`, `(0,2)`
///   `μ_{EI_y,k}`, `(1,1)` `μ_{EI_yz,k}`.
fn varying_section_moment(density: Density, a: i32, b: i32, k: u8) -> Option<Option<Poly>> {
    use SectionProp as P;
    let half = |p: P, s: i64, q: P, t: i64, r: P, u: i64| {
        mu(p, k)
            .scale(&rat(s, 2))
            .add(&mu(q, k).scale(&rat(t, 2)))
            .add(&mu(r, k).scale(&rat(u, 2)))
    };
    Some(match (density, a, b) {
        (_, 1, 0) | (_, 0, 1) => None,
        (Density::Mass { .. }, 0, 0) => Some(mu(P::RhoA, k)),
        (Density::Mass { .. }, 1, 1) => Some(mu(P::RhoIyz, k)),
        (Density::Mass { transverse: false }, 2, 0) => Some(mu(P::RhoIz, k)),
        (Density::Mass { transverse: false }, 0, 2) => Some(mu(P::RhoIy, k)),
        (Density::Mass { transverse: true }, 2, 0) => {
            Some(half(P::RhoJ, 1, P::RhoIy, -1, P::RhoIz, 1))
        }
        (Density::Mass { transverse: true }, 0, 2) => {
            Some(half(P::RhoJ, 1, P::RhoIy, 1, P::RhoIz, -1))
        }
        (Density::Elastic, 0, 0) => Some(mu(P::Ea, k)),
        (Density::Elastic, 2, 0) => Some(mu(P::EiZ, k)),
        (Density::Elastic, 0, 2) => Some(mu(P::EiY, k)),
        (Density::Elastic, 1, 1) => Some(mu(P::EiYz, k)),
        _ => return None,
    })
}

fn xi_power(shape: &Shape, k: i32) -> Result<u8, Error> {
    u8::try_from(k).map_err(|_| {
        Error::Body(format!(
            "shape `{}`: an element integral has ξ^{k}; varying sections integrate powers up to ξ^255",
            shape.name
        ))
    })
}

/// `∫ w f dV` over one element of a varying section (`w` = `ρ` or `E` by
/// `density`): each term `c · ξ^k η^a ζ^b · r` becomes
/// `c · r · l^{1 − a − b} · μ(a, b, k)` ([`varying_section_moment`]).
fn varying_volume(shape: &Shape, f: &Poly, density: Density) -> Result<Poly, Error> {
    let mut out = Poly::zero();
    for (m, c) in f.terms() {
        let (a, b) = (m.exp(Sym::Eta), m.exp(Sym::Zeta));
        let (rest, k) = m.without(Sym::Xi);
        let (rest, _) = rest.without(Sym::Eta);
        let (rest, _) = rest.without(Sym::Zeta);
        let moment = match varying_section_moment(density, a, b, xi_power(shape, k)?) {
            Some(Some(mp)) => mp,
            Some(None) => continue,
            None => {
                return Err(Error::Section {
                    shape: shape.name.clone(),
                    term: m.to_string(),
                })
            }
        };
        let scaled = moment.mul_monomial(&rest.mul(&l_pow(1 - a - b)));
        out.add_assign(&scaled.scale(c));
    }
    Ok(out)
}

/// `∫₀¹ P(ξ) f(ξ) dξ` in the moments of `P`: each term `c · ξ^k · r` of `f`
/// (no `η`, `ζ`) becomes `c · r · μ_{P,k}`.
pub(crate) fn moment_integral(shape: &Shape, f: &Poly, prop: SectionProp) -> Result<Poly, Error> {
    let mut out = Poly::zero();
    for (m, c) in f.terms() {
        let (rest, k) = m.without(Sym::Xi);
        out.add_assign(&mu(prop, xi_power(shape, k)?).mul_monomial(&rest).scale(c));
    }
    Ok(out)
}

/// `∫ρ f dV` over one element: `ρ ∫ f dV` (uniform) or in the moments of
/// the mass distribution (varying; `transverse`: see [`Density::Mass`]).
fn mass_integral(
    shape: &Shape,
    sections: SectionModel,
    f: &Poly,
    transverse: bool,
) -> Result<Poly, Error> {
    match sections {
        SectionModel::Uniform => Ok(p(Param::Rho).mul(&volume(shape, f)?)),
        SectionModel::Varying => varying_volume(shape, f, Density::Mass { transverse }),
    }
}

/// Element rows of `S` padded to three (zero z row in a planar shape).
pub fn rows3(shape: &Shape) -> [Vec<Poly>; 3] {
    let n = shape.n_elem();
    let r = &shape.rows;
    let z = if shape.dimension == 3 {
        r[2].clone()
    } else {
        vec![Poly::zero(); n]
    };
    [r[0].clone(), r[1].clone(), z]
}

/// `S` on the element's centre line (`η = ζ = 0`), padded to three rows.
pub fn centre_rows(shape: &Shape) -> [Vec<Poly>; 3] {
    rows3(shape).map(|row| {
        row.iter()
            .map(|f| {
                f.substitute(Sym::Eta, &Poly::zero())
                    .substitute(Sym::Zeta, &Poly::zero())
            })
            .collect()
    })
}

/// Undeformed position `ū₀ = [x₀ + lξ, lη, lζ]` of an element (`lζ` only in space).
fn u0(shape: &Shape) -> [Poly; 3] {
    let l = p(Param::ElemLength);
    let x = Poly::var(Sym::X0).add(&l.mul(&Poly::var(Sym::Xi)));
    let y = l.mul(&Poly::var(Sym::Eta));
    let z = if shape.dimension == 3 {
        l.mul(&Poly::var(Sym::Zeta))
    } else {
        Poly::zero()
    };
    [x, y, z]
}

/// The element stiffness `K_e = ∫ E (∂S_x/∂x)ᵀ(∂S_x/∂x) dV + ∫ G J φ'ᵀ φ' dx`,
/// with the Saint-Venant torsion angle `φ = ½ (∂S_z/∂y − ∂S_y/∂z)`
/// (uniform section).
pub fn element_stiffness(shape: &Shape) -> Result<PolyMatrix, Error> {
    element_stiffness_with(shape, SectionModel::Uniform)
}

/// [`element_stiffness`] for a uniform or a varying section (varying: `E`
/// weighs by the moments of `EA`, `EI_z`, `EI_y`, `EI_yz`, and `GJ` by its
/// moments).
pub fn element_stiffness_with(shape: &Shape, sections: SectionModel) -> Result<PolyMatrix, Error> {
    let [sx, sy, sz] = rows3(shape);
    let n = sx.len();
    let inv_l = l_pow(-1);
    let d_dx = |f: &Poly| f.diff(Sym::Xi).mul_monomial(&inv_l);
    let strain: Vec<Poly> = sx.iter().map(d_dx).collect();
    let mut phi_prime = Vec::with_capacity(n);
    for a in 0..n {
        let phi = sz[a]
            .diff(Sym::Eta)
            .sub(&sy[a].diff(Sym::Zeta))
            .mul_monomial(&inv_l)
            .scale(&rat(1, 2));
        if phi.contains(Sym::Eta) || phi.contains(Sym::Zeta) {
            return Err(Error::Body(format!(
                "shape `{}`: the torsion angle ½(∂S_z/∂y − ∂S_y/∂z) of coordinate `{}` is `{phi}`, which varies over the section; Saint-Venant torsion needs it constant over the section",
                shape.name, shape.coordinates[a].name
            )));
        }
        phi_prime.push(d_dx(&phi));
    }
    let e = p(Param::E);
    let gj = p(Param::G).mul(&p(Param::J));
    let mut k = PolyMatrix::zeros(n, n);
    for a in 0..n {
        for b in a..n {
            let v = match sections {
                SectionModel::Uniform => {
                    let axial = e.mul(&volume(shape, &strain[a].mul(&strain[b]))?);
                    let torsion = gj.mul(
                        &phi_prime[a]
                            .mul(&phi_prime[b])
                            .mul_monomial(&l_pow(1))
                            .integrate_xi(),
                    );
                    axial.add(&torsion)
                }
                SectionModel::Varying => {
                    let axial =
                        varying_volume(shape, &strain[a].mul(&strain[b]), Density::Elastic)?;
                    let torsion = moment_integral(
                        shape,
                        &phi_prime[a].mul(&phi_prime[b]).mul_monomial(&l_pow(1)),
                        SectionProp::Gj,
                    )?;
                    axial.add(&torsion)
                }
            };
            *k.get_mut(a, b) = v.clone();
            *k.get_mut(b, a) = v;
        }
    }
    Ok(k)
}

/// The invariants of one element of `shape` at offset `x₀` (symbol
/// [`Sym::X0`]), exact polynomials in the parameters and the element length
/// `l`, for the consistent or lumped formalism. `K_ff` is the element
/// stiffness in both.
pub fn element_invariants(shape: &Shape, formalism: Formalism) -> Result<ExactInvariants, Error> {
    element_invariants_with(shape, formalism, SectionModel::Uniform)
}

/// [`element_invariants`] for a uniform or a varying section: varying,
/// the invariants are polynomials in the element moments `μ_{P,k}`
/// ([`Sym::Moment`]), `l` and `x₀` (theory: "Varying sections").
pub fn element_invariants_with(
    shape: &Shape,
    formalism: Formalism,
    sections: SectionModel,
) -> Result<ExactInvariants, Error> {
    let mut inv = match formalism {
        Formalism::Consistent => consistent_element(shape, sections)?,
        Formalism::Lumped => lumped_element(shape, sections)?,
    };
    inv.k_ff = element_stiffness_with(shape, sections)?;
    Ok(inv)
}

fn consistent_element(shape: &Shape, sections: SectionModel) -> Result<ExactInvariants, Error> {
    let rho = |f: &Poly, transverse: bool| mass_integral(shape, sections, f, transverse);
    let rows = rows3(shape);
    let n = shape.n_elem();
    let u0 = u0(shape);
    let mut inv = ExactInvariants::zeros(shape.dimension, n);
    inv.mass = rho(&Poly::int(1), false)?;
    for k in 0..3 {
        inv.s_t0[k] = rho(&u0[k], false)?;
        for kk in 0..3 {
            inv.theta[k][kk] = rho(&u0[k].mul(&u0[kk]), false)?;
        }
        for a in 0..n {
            *inv.s_bar.get_mut(k, a) = rho(&rows[k][a], false)?;
            for ll in 0..3 {
                inv.i_kl[k][ll][a] = rho(&u0[k].mul(&rows[ll][a]), k > 0 && ll > 0)?;
            }
        }
    }
    for k in 0..3 {
        for ll in k..3 {
            for a in 0..n {
                for b in 0..n {
                    let v = rho(&rows[k][a].mul(&rows[ll][b]), k > 0 && ll > 0)?;
                    *inv.s_kl[ll][k].get_mut(b, a) = v.clone();
                    *inv.s_kl[k][ll].get_mut(a, b) = v;
                }
            }
        }
    }
    for a in 0..n {
        for b in 0..n {
            let mut v = Poly::zero();
            for k in 0..3 {
                v.add_assign(inv.s_kl[k][k].get(a, b));
            }
            *inv.m_ff.get_mut(a, b) = v;
        }
    }
    Ok(inv)
}

/// Lumped element: each end node `p` (`ξ_p = 0, 1`) is a small rigid body,
/// fixed to the section there, that carries the element's inertia lumped
/// with the weights `w_0 = 1 − ξ`, `w_1 = ξ` (HRZ-consistent: the halves of
/// a uniform element, and the element's mass and first moment exact for a
/// varying one):
///
/// - the section at the node: every integrand `F` of the consistent
///   formalism taken at `ξ_p` and weighed with `∫ρ w_p dV` (uniform:
///   `ρ (l/2) ∫F dA`): the node's mass `m_p` (`ρ A l/2`) on the centre line
///   and the sections' rotary inertia (`ρ I_y l/2`, `ρ I_z l/2`, `ρ J l/2`);
/// - the element's rotational inertia of bending, as the HRZ diagonal
///   lumping gives it (the consistent rotational diagonal `4 l²·ρAl/420`
///   scaled by `ρAl / (2·156·ρAl/420)`): `D_p = m_p l²/39` (uniform
///   `ρ A l³/78`), a spread of the node's mass along the axis whose points
///   `d_x` from the node move with the axis' slope, `S = N_p + d_x t_p`,
///   `t_p = ∂(S_y, S_z)/∂x` at the node: `S̄_kl += D_p t_k t_lᵀ`,
///   `Ī_xl += D_p t_l`, `Θ_xx += D_p`.
///
/// So the node's rotations have inertia and a lumped beam integrates
/// (`docs/theory.md` §7). `S̄ = Σ m_p N_p`, `S_t0` and the total mass are
/// those of the point masses before.
fn lumped_element(shape: &Shape, sections: SectionModel) -> Result<ExactInvariants, Error> {
    let n = shape.n_elem();
    let rows = rows3(shape);
    let centre = centre_rows(shape);
    let l = p(Param::ElemLength);
    let inv_l = l_pow(-1);
    let xi = Poly::var(Sym::Xi);
    let mut inv = ExactInvariants::zeros(shape.dimension, n);
    let u0 = u0(shape);
    for node in [0i64, 1] {
        // ∫ρ w_p F(ξ_p) dV: the integrand at the node, weighed.
        let w = if node == 0 {
            Poly::int(1).sub(&xi)
        } else {
            xi.clone()
        };
        let at = |f: &Poly| f.substitute(Sym::Xi, &Poly::int(node));
        let rho =
            |f: &Poly, transverse: bool| mass_integral(shape, sections, &at(f).mul(&w), transverse);
        let m_p = rho(&Poly::int(1), false)?;
        inv.mass.add_assign(&m_p);
        for k in 0..3 {
            inv.s_t0[k].add_assign(&rho(&u0[k], false)?);
            for kk in 0..3 {
                inv.theta[k][kk].add_assign(&rho(&u0[k].mul(&u0[kk]), false)?);
            }
            for a in 0..n {
                inv.s_bar
                    .get_mut(k, a)
                    .add_assign(&rho(&rows[k][a], false)?);
                for ll in 0..3 {
                    inv.i_kl[k][ll][a].add_assign(&rho(&u0[k].mul(&rows[ll][a]), k > 0 && ll > 0)?);
                }
            }
        }
        for k in 0..3 {
            for ll in k..3 {
                for a in 0..n {
                    for b in 0..n {
                        let f = rows[k][a].mul(&rows[ll][b]);
                        if at(&f).is_zero() {
                            continue;
                        }
                        let v = rho(&f, k > 0 && ll > 0)?;
                        // S̄_lk = S̄_klᵀ; a diagonal block visits (a, b) and (b, a).
                        inv.s_kl[ll][k].get_mut(b, a).add_assign(&v);
                        if ll != k {
                            inv.s_kl[k][ll].get_mut(a, b).add_assign(&v);
                        }
                    }
                }
            }
        }
        // The element's rotational inertia of bending: D_p t_k t_lᵀ.
        let d_p = m_p.mul(&l).mul(&l).scale(&rat(1, 39));
        let slope: Vec<Vec<Poly>> = (0..3)
            .map(|k| {
                centre[k]
                    .iter()
                    .map(|f| {
                        if k == 0 {
                            Poly::zero()
                        } else {
                            at(&f.diff(Sym::Xi).mul_monomial(&inv_l))
                        }
                    })
                    .collect()
            })
            .collect();
        inv.theta[0][0].add_assign(&d_p);
        for k in 1..3 {
            for a in 0..n {
                if slope[k][a].is_zero() {
                    continue;
                }
                inv.i_kl[0][k][a].add_assign(&d_p.mul(&slope[k][a]));
                for ll in 1..3 {
                    for b in 0..n {
                        if slope[ll][b].is_zero() {
                            continue;
                        }
                        inv.s_kl[k][ll]
                            .get_mut(a, b)
                            .add_assign(&d_p.mul(&slope[k][a]).mul(&slope[ll][b]));
                    }
                }
            }
        }
    }
    for a in 0..n {
        for b in 0..n {
            let mut v = Poly::zero();
            for k in 0..3 {
                v.add_assign(inv.s_kl[k][k].get(a, b));
            }
            *inv.m_ff.get_mut(a, b) = v;
        }
    }
    Ok(inv)
}

impl BodySpec {
    /// A body of `elements` elements of `shape`, consistent formalism.
    pub fn new(shape: Shape, elements: usize, reference: Reference) -> Result<Self, Error> {
        let mesh = Mesh::new(
            &shape.element_coordinates(),
            shape.dimension,
            elements,
            reference,
        )
        .map_err(|e| Error::Body(e.0))?;
        Ok(Self {
            shape,
            elements,
            reference,
            formalism: Formalism::Consistent,
            mesh,
        })
    }

    /// The same body with another inertia formalism.
    pub fn with_formalism(mut self, formalism: Formalism) -> Self {
        self.formalism = formalism;
        self
    }

    /// The numbering of the elastic coordinates.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The elastic coordinates in body order.
    pub fn dofs(&self) -> Vec<Dof> {
        self.mesh.dofs().to_vec()
    }

    /// Number of elastic coordinates.
    pub fn nf(&self) -> usize {
        self.mesh.nf()
    }

    /// For element `e`, the body index of each element coordinate (`None` if removed).
    pub fn element_map(&self, e: usize) -> Vec<Option<usize>> {
        self.mesh.element_map(e).collect()
    }

    /// The invariants of the body, exact, as polynomials in the runtime
    /// parameters: the element invariants at `x₀ = e·l` assembled over the
    /// elements, then `l = L/N`.
    pub fn exact_invariants(&self) -> Result<ExactInvariants, Error> {
        Ok(self
            .exact_invariants_in_element_length()?
            .map(|f| self.to_body_length(f)))
    }

    /// [`BodySpec::exact_invariants`] as polynomials in the element length
    /// `l` (`Param::ElemLength`) instead of `L`: the same values at `l = L/N`
    /// without rescaling every entry (evaluate them with
    /// `modal::Invariants::from_exact_elements`).
    pub fn exact_invariants_in_element_length(&self) -> Result<ExactInvariants, Error> {
        let elem = element_invariants(&self.shape, self.formalism)?;
        let nf = self.nf();
        let mut inv = ExactInvariants::zeros(self.shape.dimension, nf);
        let l = p(Param::ElemLength);
        for e in 0..self.elements {
            let x0 = l.scale(&rat(e as i64, 1));
            let el = elem.map(|f| f.substitute(Sym::X0, &x0));
            let map = self.element_map(e);
            inv.mass.add_assign(&el.mass);
            for k in 0..3 {
                inv.s_t0[k].add_assign(&el.s_t0[k]);
                for kk in 0..3 {
                    inv.theta[k][kk].add_assign(&el.theta[k][kk]);
                }
            }
            for (a, ia) in map.iter().enumerate() {
                let Some(i) = *ia else { continue };
                for k in 0..3 {
                    inv.s_bar.get_mut(k, i).add_assign(el.s_bar.get(k, a));
                    for kk in 0..3 {
                        inv.i_kl[k][kk][i].add_assign(&el.i_kl[k][kk][a]);
                    }
                }
                for (b, ib) in map.iter().enumerate() {
                    let Some(j) = *ib else { continue };
                    for k in 0..3 {
                        for kk in 0..3 {
                            inv.s_kl[k][kk]
                                .get_mut(i, j)
                                .add_assign(el.s_kl[k][kk].get(a, b));
                        }
                    }
                    inv.m_ff.get_mut(i, j).add_assign(el.m_ff.get(a, b));
                    inv.k_ff.get_mut(i, j).add_assign(el.k_ff.get(a, b));
                }
            }
        }
        Ok(inv)
    }

    /// Replace the element length `l` by `L / N`.
    pub fn to_body_length(&self, f: &Poly) -> Poly {
        f.rescale(
            Sym::Param(Param::ElemLength),
            &rat(1, self.elements as i64),
            Sym::Param(Param::Length),
        )
    }
}
