//! Time per evaluation of the `q_f`-dependent inertia terms `S_t`, `Ī_θθ`,
//! `Ī_θf` of a clamped beam3 body (1, 8, 32 elements): the compiled generated
//! code, the same programs evaluated on a tape (`EvaluatedBody`), and the
//! Gauss–Legendre quadrature of the cross-check (`ffr-reference`).
//!
//! `cargo bench -p ffr-bench`

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use ffr_bench::{Beam3N1, Beam3N32, Beam3N8};
use ffr_codegen::{BodySpec, Options, ParamValues, Reference, Shape};
use ffr_reference::{RefBody, RefParams, Reference as RefReference, Shape as RefShape};
use ffr_runtime::{FlexBody, InertiaTerms, Params};

const RP: RefParams = RefParams {
    length: 2.0,
    rho: 7850.0,
    wy: 0.02,
    wz: 0.01,
    e: 2.1e11,
    g: 8.1e10,
    j: 1.2e-8,
};

fn params() -> Params {
    Params {
        length: RP.length,
        rho: RP.rho,
        area: RP.area(),
        iy: RP.iy(),
        iz: RP.iz(),
        e: RP.e,
        g: RP.g,
        j: RP.j,
    }
}

fn bench_body<B: FlexBody>(c: &mut Criterion, n: usize, body: B) {
    let nf = body.nf();
    let q: Vec<f64> = (0..nf).map(|i| 1e-3 * ((i as f64) * 0.37).sin()).collect();
    let mut group = c.benchmark_group(format!("inertia_terms/beam3/{n}"));
    let mut out = InertiaTerms::zeros(nf);
    group.bench_function(BenchmarkId::new("generated", nf), |b| {
        b.iter(|| body.inertia_terms(black_box(&q), &mut out))
    });
    let p = params();
    let spec = BodySpec::new(
        Shape::resolve("beam3", None).unwrap(),
        n,
        Reference::Clamped,
    )
    .unwrap();
    let g = ffr_codegen::generate(&spec, Options::default()).unwrap();
    let tape = g.inertia.tape();
    let values = ParamValues {
        length: p.length,
        rho: p.rho,
        area: p.area,
        iy: p.iy,
        iz: p.iz,
        e: p.e,
        g: p.g,
        j: p.j,
    }
    .to_array();
    let mut slots = Vec::new();
    group.bench_function(BenchmarkId::new("tape", nf), |b| {
        b.iter(|| tape.run(&values, black_box(&q), &mut slots))
    });
    let reference = RefBody {
        shape: RefShape::Beam3,
        elements: n,
        reference: RefReference::Clamped,
        params: RP,
    };
    group.bench_function(BenchmarkId::new("quadrature", nf), |b| {
        b.iter(|| {
            (
                reference.s_t(black_box(&q)),
                reference.i_theta_theta(black_box(&q)),
                reference.i_theta_f(black_box(&q)),
            )
        })
    });
    group.finish();
}

fn inertia_terms(c: &mut Criterion) {
    bench_body(c, 1, Beam3N1::from(params()));
    bench_body(c, 8, Beam3N8::from(params()));
    bench_body(c, 32, Beam3N32::from(params()));
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(2)).warm_up_time(std::time::Duration::from_millis(500));
    targets = inertia_terms
}
criterion_main!(benches);
