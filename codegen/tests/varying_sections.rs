//! Kernels of varying sections (issue 19): element integrals written in the
//! element moments `μ_{P,k}` of the section properties.
//!
//! - With the moments of constant properties (`μ_{P,k} = P/(k+1)`,
//!   `ρJ = ρ(I_y + I_z)`, `ρI_yz = EI_yz = 0`) every kernel of a varying set
//!   gives what the uniform set gives, to round-off.
//! - The exact element invariants of a tapered, twisted beam3 element with a
//!   station inside it agree with an independent quadrature
//!   (`ffr_reference::varying`: Gauss–Legendre on the pieces between
//!   stations, properties interpolated linearly, its own shape functions).

mod common;

use common::{coefficients, pseudo_random, Run};
use ffr_codegen::eom::OutArr;
use ffr_codegen::program::Inputs;
use ffr_codegen::{
    generate_kernels, Formalism, KernelModel, KernelOptions, KernelSet, Params, SectionModel,
    SectionProp, Shape, Stiffening,
};
use ffr_reference as rf;
use ffr_spec::{element_moments, invariant_layout, KernelKind};
use std::collections::BTreeMap;

fn sets(shape: &str, options: KernelOptions) -> (KernelSet, KernelSet) {
    let model = KernelModel::new(Shape::resolve(shape, None).unwrap(), options);
    let uniform = generate_kernels(&model).unwrap();
    let varying = generate_kernels(&model.with_sections(SectionModel::Varying)).unwrap();
    (uniform, varying)
}

/// `c` of a varying set from element moments `mu` and `l`, through the
/// section coefficient program on a tape.
fn section_coefficients(set: &KernelSet, mu: &[f64], l: f64) -> Vec<f64> {
    assert_eq!(mu.len(), set.section_moments.len());
    let mut params = [0.0; 9];
    params[8] = l;
    let mut c = vec![f64::NAN; set.coefficients.len()];
    Run::new(set.section_coefficient_program.as_ref().unwrap()).run(
        &Inputs {
            params: &params,
            mu,
            ..Inputs::default()
        },
        |arr, i, v| {
            assert_eq!(arr, OutArr::Coef);
            c[i] = v;
        },
    );
    assert!(c.iter().all(|x| x.is_finite()), "a coefficient is not set");
    c
}

/// Every output of kernel `kind` of `set` at one state.
fn outputs(set: &KernelSet, kind: KernelKind, c: &[f64]) -> BTreeMap<(OutArr, usize), f64> {
    let n = set.n();
    let l_scale = 0.3;
    let q: Vec<f64> = pseudo_random(n, 11, 0.08)
        .into_iter()
        .zip(set.model().shape.element_coordinates())
        .map(|(x, ec)| {
            if ec.kind.is_translation() {
                x * l_scale
            } else {
                x
            }
        })
        .collect();
    let qd = pseudo_random(n, 12, 1.5);
    let qdd = pseudo_random(n, 13, 20.0);
    let frame = pseudo_random(9, 14, 3.0);
    let mut out = BTreeMap::new();
    Run::new(set.program(kind).unwrap()).run(
        &Inputs {
            coef: c,
            x0: 0.6,
            frame: &frame,
            bp: 4.0e3,
            gp: 60.0,
            q: &q,
            qd: &qd,
            qdd: &qdd,
            xi: 0.37,
            ..Inputs::default()
        },
        |arr, i, v| {
            out.insert((arr, i), v);
        },
    );
    out
}

/// The block an output entry belongs to: its array, and for the flat
/// invariants the invariant (`m`, `S_t0`, `S̄`, …) it is part of.
fn block(key: &(OutArr, usize), n: usize) -> (OutArr, usize) {
    match key.0 {
        OutArr::Inv => {
            let (off, _) = invariant_layout(n);
            (OutArr::Inv, off.iter().rposition(|&o| o <= key.1).unwrap())
        }
        arr => (arr, 0),
    }
}

/// `|a − b| ≤ tol · s` for every entry (missing entries are 0), `s` the
/// largest magnitude in the entry's block: round-off of the block's scale
/// (an entry that integrates to an exact 0 in the uniform model, such as
/// `∫(−1 + 4ξ − 3ξ²) dξ`, is a sum of float moments in the varying one).
/// Returns the largest such relative difference.
fn assert_close(
    what: &str,
    n: usize,
    a: &BTreeMap<(OutArr, usize), f64>,
    b: &BTreeMap<(OutArr, usize), f64>,
    tol: f64,
) -> f64 {
    let mut scale: BTreeMap<(OutArr, usize), f64> = BTreeMap::new();
    for (key, x) in a.iter().chain(b.iter()) {
        let s = scale.entry(block(key, n)).or_default();
        *s = s.max(x.abs());
    }
    let mut worst: f64 = 0.0;
    for key in a.keys().chain(b.keys()) {
        let (x, y) = (
            a.get(key).copied().unwrap_or(0.0),
            b.get(key).copied().unwrap_or(0.0),
        );
        let s = scale[&block(key, n)];
        let err = (x - y).abs();
        assert!(
            err <= tol * s,
            "{what} {key:?}: {x:e} vs {y:e} (relative to the block {:e})",
            err / s
        );
        if s > 0.0 {
            worst = worst.max(err / s);
        }
    }
    worst
}

/// The moments of a uniform body's constant properties.
fn constant_moments(set: &KernelSet, p: &Params) -> Vec<f64> {
    set.section_moments
        .iter()
        .map(|&(prop, k)| prop.uniform_value(p) / (k as f64 + 1.0))
        .collect()
}

#[test]
fn varying_kernels_with_constant_moments_match_the_uniform_kernels() {
    let mut worst: f64 = 0.0;
    for (shape, rp) in [
        ("beam2", 0),
        ("beam3", 0),
        ("beam2", 3),
        ("beam3", 2),
        ("beam3", 1),
    ] {
        let p = common::params_of(&common::param_sets()[rp]);
        let l = p.length / 3.0;
        for formalism in [Formalism::Consistent, Formalism::Lumped] {
            for stiffening in [
                Stiffening::Off,
                Stiffening::SecondOrder,
                Stiffening::FourthOrder,
            ] {
                let o = KernelOptions::new()
                    .formalism(formalism)
                    .stiffening(stiffening);
                let (u, v) = sets(shape, o);
                assert!(u.section_moments.is_empty() && u.section_coefficient_program.is_none());
                assert!(!v.section_moments.is_empty());
                if shape == "beam2" {
                    // A planar beam has no torsion and no x–z bending.
                    let out_of_plane = [
                        SectionProp::RhoIy,
                        SectionProp::RhoIyz,
                        SectionProp::RhoJ,
                        SectionProp::EiY,
                        SectionProp::EiYz,
                        SectionProp::Gj,
                    ];
                    assert!(
                        v.section_moments
                            .iter()
                            .all(|(p, _)| !out_of_plane.contains(p)),
                        "{:?}",
                        v.section_moments
                    );
                }
                // No parameter in a varying kernel: only `l` and the moments.
                assert_eq!(
                    v.section_coefficient_program.as_ref().unwrap().params(),
                    vec![ffr_codegen::poly::Param::ElemLength]
                );
                let cu = coefficients(&u, &p, l);
                let cv = section_coefficients(&v, &constant_moments(&v, &p), l);
                // The varying set's own uniform-body coefficients.
                let cv_uniform = coefficients(&v, &p, l);
                for kind in KernelKind::per_call() {
                    let Some(_) = u.program(kind) else {
                        assert!(v.program(kind).is_none());
                        continue;
                    };
                    let what = format!("{shape} {formalism} {stiffening} {}", kind.name());
                    let a = outputs(&u, kind, &cu);
                    worst = worst.max(assert_close(
                        &what,
                        u.n(),
                        &a,
                        &outputs(&v, kind, &cv),
                        1e-13,
                    ));
                    worst = worst.max(assert_close(
                        &what,
                        u.n(),
                        &a,
                        &outputs(&v, kind, &cv_uniform),
                        1e-13,
                    ));
                }
            }
        }
    }
    eprintln!("largest relative difference: {worst:e}");
}

/// The value of `prop` at a reference station.
fn station_value(s: &rf::varying::Station, prop: SectionProp) -> f64 {
    match prop {
        SectionProp::RhoA => s.rho_a,
        SectionProp::RhoIy => s.rho_iy,
        SectionProp::RhoIz => s.rho_iz,
        SectionProp::RhoIyz => s.rho_iyz,
        SectionProp::RhoJ => s.rho_j,
        SectionProp::Ea => s.ea,
        SectionProp::EiY => s.ei_y,
        SectionProp::EiZ => s.ei_z,
        SectionProp::EiYz => s.ei_yz,
        SectionProp::Gj => s.gj,
    }
}

/// A tapered, twisted blade-like section table on `[0, 2]` m: every
/// resultant changes along the span, the twist turns the principal axes from
/// 0.35 rad to −0.1 rad, and the polar mass moment is not `ρI_y + ρI_z`.
fn stations() -> Vec<rf::varying::Station> {
    [0.0, 0.8, 1.45, 2.0]
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let t = 1.0 - 0.3 * x; // taper
            let f = 1.0 + 0.1 * i as f64 * (-1f64).powi(i as i32); // not linear in x
            rf::varying::twisted_station(
                x,
                120.0 * t * f,
                0.8 * t * t * t,
                0.15 * t * t * f,
                1.2 * (0.8 * t * t * t + 0.15 * t * t * f),
                2.0e9 * t * f,
                4.0e7 * t.powi(3),
                6.0e6 * t.powi(3) * f,
                3.0e6 * t.powi(4),
                0.35 - 0.225 * x,
            )
        })
        .collect()
}

/// The element invariants of `set` for one element `[x0, x0 + l]` of the
/// table, through the moments (`ffr_spec::element_moments`), the section
/// coefficient program and the `element_invariants` program.
fn generated_invariants(set: &KernelSet, st: &[rf::varying::Station], x0: f64, l: f64) -> Vec<f64> {
    let mu: Vec<f64> = set
        .section_moments
        .iter()
        .map(|&(prop, k)| {
            let table: Vec<(f64, f64)> = st.iter().map(|s| (s.x, station_value(s, prop))).collect();
            let mut m = vec![0.0; k as usize + 1];
            element_moments(&table, x0, l, &mut m).unwrap();
            m[k as usize]
        })
        .collect();
    let c = section_coefficients(set, &mu, l);
    let (_, len) = invariant_layout(set.n());
    let mut out = vec![0.0; len];
    Run::new(set.program(KernelKind::ElementInvariants).unwrap()).run(
        &Inputs {
            coef: &c,
            x0,
            ..Inputs::default()
        },
        |_, i, v| out[i] = v,
    );
    out
}

/// The reference's element invariants in the flat layout.
fn reference_flat(r: &rf::varying::ElementInvariants, n: usize) -> Vec<f64> {
    let mut v = vec![r.mass];
    v.extend(r.s_t0.iter());
    for k in 0..3 {
        v.extend((0..n).map(|a| r.s_bar[(k, a)]));
    }
    for k in 0..3 {
        for l in 0..3 {
            for a in 0..n {
                v.extend((0..n).map(|b| r.s_kl[k][l][(a, b)]));
            }
        }
    }
    for k in 0..3 {
        for l in 0..3 {
            v.extend(r.i_kl[k][l].iter());
        }
    }
    for k in 0..3 {
        v.extend((0..3).map(|l| r.theta[(k, l)]));
    }
    v.extend(
        (0..n)
            .flat_map(|a| (0..n).map(move |b| (a, b)))
            .map(|ab| r.m_ff[ab]),
    );
    v.extend(
        (0..n)
            .flat_map(|a| (0..n).map(move |b| (a, b)))
            .map(|ab| r.k_ff[ab]),
    );
    v
}

#[test]
fn tapered_twisted_beam3_element_matches_quadrature() {
    let (_, set) = sets("beam3", KernelOptions::new());
    let st = stations();
    let n = set.n();
    let (off, len) = invariant_layout(n);
    let names = ["m", "S_t0", "S̄", "S̄_kl", "Ī_kl", "Θ", "m_ff", "K_ff"];
    // A station inside the element, an element between stations, and the
    // element ending on one.
    for (x0, l) in [(0.5, 0.7), (0.85, 0.5), (1.45, 0.55), (0.0, 2.0)] {
        let got = generated_invariants(&set, &st, x0, l);
        let want = reference_flat(
            &rf::varying::element_invariants(rf::Shape::Beam3, &st, x0, l),
            n,
        );
        assert_eq!(want.len(), len);
        // Round-off, relative to the largest entry of each block (the
        // blocks mix entries of different units: translations, rotations).
        for (b, name) in names.iter().enumerate() {
            let end = if b + 1 < off.len() { off[b + 1] } else { len };
            let block = off[b]..end;
            let scale = want[block.clone()]
                .iter()
                .fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(scale > 0.0, "{name} is zero");
            for i in block {
                let err = (got[i] - want[i]).abs();
                assert!(
                    err <= 1e-13 * scale,
                    "element [{x0}, {}]: {name} entry {} : generated {:e}, quadrature {:e} (relative to the block {:e})",
                    x0 + l,
                    i - off[b],
                    got[i],
                    want[i],
                    err / scale
                );
            }
        }
        // The twist couples the bending planes: S̄_yz and K_ff have y–z terms.
        let k_vw = got[off[7] + n + 2]; // K_ff[uy_0][uz_0]
        assert!(
            k_vw.abs() > 1e-6 * got[off[7] + n + 1].abs(),
            "no EI_yz coupling"
        );
    }
}

/// Element coordinates with slopes of order `a` (translations `a·l`).
fn element_state(set: &KernelSet, l: f64, seed: u64, a: f64) -> Vec<f64> {
    pseudo_random(set.n(), seed, a)
        .into_iter()
        .zip(set.model().shape.element_coordinates())
        .map(|(x, ec)| if ec.kind.is_translation() { x * l } else { x })
        .collect()
}

/// One run of `kind` with `q` (frame at rest, no velocities or accelerations).
fn run_at_rest(
    set: &KernelSet,
    kind: KernelKind,
    c: &[f64],
    q: &[f64],
) -> BTreeMap<(OutArr, usize), f64> {
    let zeros = vec![0.0; q.len()];
    let frame = [0.0; 9];
    let mut out = BTreeMap::new();
    Run::new(set.program(kind).unwrap()).run(
        &Inputs {
            coef: c,
            x0: 0.0,
            frame: &frame,
            q,
            qd: &zeros,
            qdd: &zeros,
            ..Inputs::default()
        },
        |arr, i, v| {
            out.insert((arr, i), v);
        },
    );
    out
}

/// The element's moments from the table, then its coefficients.
fn element_coefficients(set: &KernelSet, st: &[rf::varying::Station], x0: f64, l: f64) -> Vec<f64> {
    let mu: Vec<f64> = set
        .section_moments
        .iter()
        .map(|&(prop, k)| {
            let table: Vec<(f64, f64)> = st.iter().map(|s| (s.x, station_value(s, prop))).collect();
            let mut m = vec![0.0; k as usize + 1];
            element_moments(&table, x0, l, &mut m).unwrap();
            m[k as usize]
        })
        .collect();
    section_coefficients(set, &mu, l)
}

#[test]
fn stiffening_energy_of_a_twisted_element_matches_quadrature() {
    let st = stations();
    let untwisted: Vec<rf::varying::Station> = st
        .iter()
        .map(|s| rf::varying::Station { ei_yz: 0.0, ..*s })
        .collect();
    let (x0, l) = (0.5, 0.7);
    for (model, rmodel) in [
        (Stiffening::SecondOrder, rf::StiffeningModel::SecondOrder),
        (Stiffening::FourthOrder, rf::StiffeningModel::FourthOrder),
    ] {
        let (_, set) = sets("beam3", KernelOptions::new().stiffening(model));
        let n = set.n();
        let c = element_coefficients(&set, &st, x0, l);
        let (off, _) = invariant_layout(n);
        let k = &generated_invariants(&set, &st, x0, l)[off[7]..off[7] + n * n];
        for seed in 1..4 {
            let q = element_state(&set, l, seed, 0.1);
            let e = run_at_rest(&set, KernelKind::Energy, &c, &q)[&(OutArr::Energy, 0)];
            let quad: f64 = (0..n)
                .flat_map(|a| (0..n).map(move |b| (a, b)))
                .map(|(a, b)| 0.5 * q[a] * k[a * n + b] * q[b])
                .sum();
            let u = rf::varying::stiffening_energy(rf::Shape::Beam3, &st, x0, l, rmodel, &q);
            // U_nl is ~1e-2 of the quadratic energy: compare it to round-off
            // of the total.
            let err = (e - quad - u).abs();
            assert!(
                err <= 1e-13 * e.abs(),
                "{model} seed {seed}: U_nl generated {:e}, quadrature {u:e} (relative to the energy {:e})",
                e - quad,
                err / e.abs()
            );
            if model == Stiffening::FourthOrder {
                // The twist's EI_yz term is in it, and it is not negligible.
                let u0 =
                    rf::varying::stiffening_energy(rf::Shape::Beam3, &untwisted, x0, l, rmodel, &q);
                assert!(
                    (u - u0).abs() > 1e3 * 1e-13 * e.abs(),
                    "EI_yz term {:e} vs the tolerance {:e}",
                    u - u0,
                    1e-13 * e.abs()
                );
            }
        }
    }
}

#[test]
fn elastic_forces_and_tangent_are_the_energy_derivatives() {
    let st = stations();
    let (x0, l) = (0.5, 0.7);
    let (_, set) = sets(
        "beam3",
        KernelOptions::new().stiffening(Stiffening::FourthOrder),
    );
    let n = set.n();
    let c = element_coefficients(&set, &st, x0, l);
    let q = element_state(&set, l, 5, 0.1);
    let energy = |q: &[f64]| run_at_rest(&set, KernelKind::Energy, &c, q)[&(OutArr::Energy, 0)];
    let force = |q: &[f64]| {
        let r = run_at_rest(&set, KernelKind::ResidualElastic, &c, q);
        (0..n)
            .map(|a| r.get(&(OutArr::Fe, a)).copied().unwrap_or(0.0))
            .collect::<Vec<f64>>()
    };
    let f = force(&q);
    let tangent = run_at_rest(&set, KernelKind::TangentElastic, &c, &q);
    let fscale = f.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for a in 0..n {
        // Central differences, step relative to the coordinate's scale.
        let h = if set.model().shape.element_coordinates()[a]
            .kind
            .is_translation()
        {
            1e-6 * l
        } else {
            1e-6
        };
        let (mut qp, mut qm) = (q.clone(), q.clone());
        qp[a] += h;
        qm[a] -= h;
        let fd = (energy(&qp) - energy(&qm)) / (2.0 * h);
        assert!(
            (fd - f[a]).abs() <= 1e-6 * fscale,
            "f_e[{a}] = {:e}, dE/dq = {fd:e}",
            f[a]
        );
        let (fp, fm) = (force(&qp), force(&qm));
        for b in 0..n {
            let kd = (fp[b] - fm[b]) / (2.0 * h);
            let kt = tangent
                .get(&(OutArr::Kee, b * n + a))
                .copied()
                .unwrap_or(0.0);
            let kscale = (0..n * n)
                .map(|i| tangent.get(&(OutArr::Kee, i)).copied().unwrap_or(0.0).abs())
                .fold(0.0f64, f64::max);
            assert!(
                (kd - kt).abs() <= 1e-6 * kscale,
                "K[{b}][{a}] = {kt:e}, df/dq = {kd:e}"
            );
        }
    }
}

#[test]
fn the_twist_convention_of_spec_and_reference_agree() {
    for twist in [-0.2323, 0.0, 0.35, 1.1] {
        let s = rf::varying::twisted_station(0.0, 1.0, 2.0, 5.0, 7.0, 1.0, 3.0, 11.0, 1.0, twist);
        let (ey, ez, eyz) = ffr_spec::twisted_moments(3.0, 11.0, twist);
        let (ry, rz, ryz) = ffr_spec::twisted_moments(2.0, 5.0, twist);
        for (a, b) in [
            (ey, s.ei_y),
            (ez, s.ei_z),
            (eyz, s.ei_yz),
            (ry, s.rho_iy),
            (rz, s.rho_iz),
            (ryz, s.rho_iyz),
        ] {
            assert!((a - b).abs() < 1e-14 * 11.0, "twist {twist}: {a} vs {b}");
        }
    }
}
