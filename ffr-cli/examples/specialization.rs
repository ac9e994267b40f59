//! What specialization saves, per built-in scene: every flexible body run on
//! the kernels `ffr run` picks for the scene, and on the general kernels
//! (spatial scene, free frame: what every scene could use, `ffr run
//! --general`). Operations per step are counted, not estimated: each kernel
//! call is counted during the run and weighted by that kernel's operation
//! count from the generator (the numbers in the generated file's header).
//! Time per step is the CPU time of the whole run over its steps, the
//! minimum of `--reps` runs, specialized and general interleaved.
//!
//! ```sh
//! cargo run --release --example specialization [-- --reps 5]
//! ```

use ffr::codegen::{generate_kernels, KernelModel, Shape};
use ffr::runtime::spec::Params;
use ffr::runtime::{ElementKernels, KernelInfo, KernelInput, MassOut, ResidualOut, TangentOut};
use ffr::scene::{self, DefaultKernels, FlexSpec, GeneralKernels, KernelProvider};
use ffr_cli::report::measure::thread_cpu_seconds;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex};

/// The kernels called per element (`KernelKind::per_call`).
const KERNELS: [&str; 12] = [
    "mass",
    "residual",
    "tangent",
    "residual_elastic",
    "tangent_elastic",
    "energy",
    "element_invariants",
    "point_shape",
    "force_elastic",
    "elastic_scalars",
    "scalar_force",
    "scalar_tangent",
];

/// Kernels that count their calls (index into `KERNELS`).
struct Counting {
    inner: Box<dyn ElementKernels>,
    calls: Arc<[AtomicU64; 12]>,
}

impl Counting {
    fn hit(&self, k: usize) {
        self.calls[k].fetch_add(1, Relaxed);
    }
}

impl ElementKernels for Counting {
    fn info(&self) -> &KernelInfo {
        self.inner.info()
    }
    fn coefficients(&self, params: &Params, l: f64, c: &mut [f64]) {
        self.inner.coefficients(params, l, c)
    }
    fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut MassOut, scratch: &mut [f64]) {
        self.hit(0);
        self.inner.mass(c, x0, q, out, scratch)
    }
    fn residual(&self, c: &[f64], x: &KernelInput, out: &mut ResidualOut, scratch: &mut [f64]) {
        self.hit(1);
        self.inner.residual(c, x, out, scratch)
    }
    fn tangent(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        out: &mut TangentOut,
        scratch: &mut [f64],
    ) {
        self.hit(2);
        self.inner.tangent(c, x, bp, gp, out, scratch)
    }
    fn residual_elastic(&self, c: &[f64], x: &KernelInput, f_e: &mut [f64], scratch: &mut [f64]) {
        self.hit(3);
        self.inner.residual_elastic(c, x, f_e, scratch)
    }
    #[allow(clippy::too_many_arguments)]
    fn tangent_elastic(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        f_e: &mut [f64],
        k_ee: &mut [f64],
        scratch: &mut [f64],
    ) {
        self.hit(4);
        self.inner.tangent_elastic(c, x, bp, gp, f_e, k_ee, scratch)
    }
    fn energy(&self, c: &[f64], q: &[f64], scratch: &mut [f64]) -> f64 {
        self.hit(5);
        self.inner.energy(c, q, scratch)
    }
    fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], scratch: &mut [f64]) {
        self.hit(6);
        self.inner.element_invariants(c, x0, out, scratch)
    }
    fn point_shape(&self, c: &[f64], xi: f64, s: &mut [f64], psi: &mut [f64], scratch: &mut [f64]) {
        self.hit(7);
        self.inner.point_shape(c, xi, s, psi, scratch)
    }
    fn section_moments(&self) -> &[(ffr::runtime::spec::SectionProp, u8)] {
        self.inner.section_moments()
    }
    fn section_coefficients(&self, mu: &[f64], l: f64, c: &mut [f64]) {
        self.inner.section_coefficients(mu, l, c)
    }
    fn force_elastic(&self, c: &[f64], q: &[f64], f_e: &mut [f64], scratch: &mut [f64]) -> bool {
        self.hit(8);
        self.inner.force_elastic(c, q, f_e, scratch)
    }
    fn elastic_scalars(&self, c: &[f64], q: &[f64], z: &mut [f64], scratch: &mut [f64]) -> usize {
        self.hit(9);
        self.inner.elastic_scalars(c, q, z, scratch)
    }
    fn scalar_force(&self, c: &[f64], z: &[f64], g: &mut [f64], scratch: &mut [f64]) -> bool {
        self.hit(10);
        self.inner.scalar_force(c, z, g, scratch)
    }
    /// Counted as one `scalar_force` per element (the same program).
    fn scalar_force_batch(
        &self,
        c: &[f64],
        c_stride: usize,
        z_all: &[f64],
        g_all: &mut [f64],
        elements: usize,
        scratch: &mut [f64],
    ) -> bool {
        self.calls[10].fetch_add(elements as u64, Relaxed);
        self.inner
            .scalar_force_batch(c, c_stride, z_all, g_all, elements, scratch)
    }
    fn scalar_tangent(
        &self,
        c: &[f64],
        z: &[f64],
        g: &mut [f64],
        h: &mut [f64],
        scratch: &mut [f64],
    ) -> bool {
        self.hit(11);
        self.inner.scalar_tangent(c, z, g, h, scratch)
    }
}

/// A provider whose kernels count their calls; remembers what it handed out.
struct Counted<'a> {
    inner: &'a dyn KernelProvider,
    handed: Mutex<Vec<(KernelInfo, Arc<[AtomicU64; 12]>)>>,
}

impl KernelProvider for Counted<'_> {
    fn kernels(&self, spec: &FlexSpec) -> ffr::Result<(Box<dyn ElementKernels>, &'static str)> {
        let (inner, path) = self.inner.kernels(spec)?;
        let calls: Arc<[AtomicU64; 12]> = Arc::new(Default::default());
        self.handed
            .lock()
            .unwrap()
            .push((inner.info().clone(), calls.clone()));
        Ok((Box::new(Counting { inner, calls }), path))
    }
}

/// Operation count of every kernel of the set described by `info`.
fn ops(info: &KernelInfo) -> [u64; 12] {
    let model = KernelModel::new(
        Shape::resolve(&info.shape, None).expect("a built-in shape"),
        info.options,
    );
    let set = generate_kernels(&model).expect("the kernels generate");
    let mut out = [0; 12];
    for (name, p) in set.programs() {
        let k = KERNELS.iter().position(|n| *n == name).unwrap();
        out[k] = p.ops() as u64;
    }
    out
}

struct Measured {
    steps: usize,
    cpu_per_step: f64,
    ops_per_step: f64,
    kernels: String,
}

fn measure(path: &Path, provider: &dyn KernelProvider, reps: usize) -> Measured {
    let mut best = f64::INFINITY;
    let mut ops_per_step = 0.0;
    let mut steps = 0;
    let mut kernels = String::new();
    for rep in 0..reps {
        let counted = Counted {
            inner: provider,
            handed: Mutex::new(Vec::new()),
        };
        let s = scene::load_with(path, &counted).unwrap_or_else(|e| panic!("{e}"));
        let t0 = thread_cpu_seconds();
        let r = scene::run(&s).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let cpu = thread_cpu_seconds() - t0;
        assert!(r.failed.is_none(), "{:?}", r.failed);
        steps = r.steps;
        best = best.min(cpu / r.steps as f64);
        if rep == 0 {
            let handed = counted.handed.lock().unwrap();
            let mut total = 0u64;
            for (info, calls) in handed.iter() {
                let o = ops(info);
                total += (0..KERNELS.len())
                    .map(|k| calls[k].load(Relaxed) * o[k])
                    .sum::<u64>();
            }
            ops_per_step = total as f64 / r.steps as f64;
            kernels = s
                .kernels
                .iter()
                .map(|(b, k)| format!("{b}: {k}"))
                .collect::<Vec<_>>()
                .join("; ");
        }
    }
    Measured {
        steps,
        cpu_per_step: best,
        ops_per_step,
        kernels,
    }
}

fn main() {
    let reps = std::env::args()
        .skip_while(|a| a != "--reps")
        .nth(1)
        .map_or(3, |r| r.parse().expect("--reps N"));
    let root = ffr::scene::load::builtin_dir();
    println!("| scene | steps | kernels (specialized) | operations / step, specialized | general | × | CPU µs / step, specialized | general | × |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for name in [
        "spin_up",
        "precone",
        "slider_crank",
        "pendulum",
        "free_floating",
        "two_link_arm",
    ] {
        let path = root.join(format!("{name}.toml"));
        let s = measure(&path, &DefaultKernels, reps);
        let g = measure(&path, &GeneralKernels, reps);
        assert_eq!(s.steps, g.steps);
        println!(
            "| `{name}.toml` | {} | {} | {:.0} | {:.0} | {:.2} | {:.2} | {:.2} | {:.2} |",
            s.steps,
            s.kernels,
            s.ops_per_step,
            g.ops_per_step,
            g.ops_per_step / s.ops_per_step,
            s.cpu_per_step * 1e6,
            g.cpu_per_step * 1e6,
            g.cpu_per_step / s.cpu_per_step
        );
    }
}
