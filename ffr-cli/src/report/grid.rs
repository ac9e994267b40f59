//! What the report runs: the benchmark scenes, the method choices that apply
//! to each, and the quick and full grids of (method, elements, dt).

use ffr::runtime::spec::{Formalism, Stiffening};
use ffr::runtime::{GeneralizedAlpha, Integrator, Rk4Baumgarte};
use std::fmt;

/// A benchmark scene of the report (names as in `points.csv`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Scene {
    /// KRB spin-up beam, `ω_s = 4 rad/s`, 0–20 s.
    SpinUp4,
    /// KRB spin-up beam, `ω_s = 10 rad/s`, 0–20 s.
    SpinUp10,
    /// KRB spin-up beam in space (`beam3`), `ω_s = 4 rad/s`, under gravity
    /// along the spin axis (both bending planes), 0–20 s.
    SpinUp3d,
    /// Simeon's flexible slider crank, 0–0.1 s.
    SliderCrank,
    /// Free flexible pendulum under gravity, 0–1 s.
    Pendulum,
    /// Free-floating flexible body in space, 0–0.2 s.
    FreeFloating,
}

impl Scene {
    /// Every scene, in report order.
    pub const ALL: [Scene; 6] = [
        Scene::SpinUp4,
        Scene::SpinUp10,
        Scene::SpinUp3d,
        Scene::SliderCrank,
        Scene::Pendulum,
        Scene::FreeFloating,
    ];

    /// The name in `points.csv` (and of the SVG file).
    pub fn name(self) -> &'static str {
        match self {
            Scene::SpinUp4 => "spin-up-4",
            Scene::SpinUp10 => "spin-up-10",
            Scene::SpinUp3d => "spin-up-3d",
            Scene::SliderCrank => "slider-crank",
            Scene::Pendulum => "pendulum",
            Scene::FreeFloating => "free-floating",
        }
    }

    /// The scene named `name`.
    pub fn from_name(name: &str) -> Option<Scene> {
        Scene::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The kind of error the report measures for this scene.
    pub fn error_kind(self) -> ErrorKind {
        match self {
            Scene::SpinUp4 | Scene::SpinUp10 | Scene::SpinUp3d => ErrorKind::Reference,
            Scene::SliderCrank => ErrorKind::Published,
            Scene::Pendulum => ErrorKind::Energy,
            Scene::FreeFloating => ErrorKind::Momentum,
        }
    }

    /// Simulated time span (s).
    pub fn t_end(self) -> f64 {
        match self {
            Scene::SpinUp4 | Scene::SpinUp10 | Scene::SpinUp3d => 20.0,
            Scene::SliderCrank => crate::benchmarks::slider_crank::T_END,
            Scene::Pendulum => 1.0,
            Scene::FreeFloating => 0.2,
        }
    }

    /// A one-line title.
    pub fn title(self) -> &'static str {
        match self {
            Scene::SpinUp4 => "KRB spin-up beam, ω_s = 4 rad/s (0–20 s)",
            Scene::SpinUp10 => "KRB spin-up beam, ω_s = 10 rad/s (0–20 s)",
            Scene::SpinUp3d => {
                "KRB spin-up beam in space, ω_s = 4 rad/s, gravity along the spin axis (beam3, 0–20 s)"
            }
            Scene::SliderCrank => "Flexible slider crank (Simeon, IVP test set; 0–0.1 s)",
            Scene::Pendulum => "Free flexible pendulum, beam2, under gravity (0–1 s)",
            Scene::FreeFloating => "Free-floating flexible beam3 in space (0–0.2 s)",
        }
    }
}

impl fmt::Display for Scene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the error of a point is measured against (`error_kind` in `points.csv`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ErrorKind {
    /// A geometrically exact reference history (`bench/reference/`).
    Reference,
    /// A published solution (the IVP test set's slider-crank values).
    Published,
    /// Drift of a conserved energy.
    Energy,
    /// Drift of conserved momenta.
    Momentum,
}

impl ErrorKind {
    /// Every kind.
    pub const ALL: [ErrorKind; 4] = [
        ErrorKind::Reference,
        ErrorKind::Published,
        ErrorKind::Energy,
        ErrorKind::Momentum,
    ];

    /// The name in `points.csv`.
    pub fn name(self) -> &'static str {
        match self {
            ErrorKind::Reference => "reference",
            ErrorKind::Published => "published",
            ErrorKind::Energy => "energy",
            ErrorKind::Momentum => "momentum",
        }
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Time integrator of a method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// Generalized-α (index 3) with this `ρ∞` and the runtime's default
    /// Newton tolerance (1e-10), except in the free-floating scene, which
    /// uses its own 1e-12 ([`crate::benchmarks::free_floating::DRIFT_RTOL`]).
    Alpha(f64),
    /// Explicit RK4 on the index-1 form, Baumgarte `α = β = 10/s`.
    Rk4,
}

impl Scheme {
    /// The runtime integrator for `scene`.
    pub fn integrator(self, scene: Scene) -> Integrator {
        match self {
            Scheme::Alpha(rho) => {
                let mut g = GeneralizedAlpha::with_rho_inf(rho);
                if scene == Scene::FreeFloating {
                    g.rtol = crate::benchmarks::free_floating::DRIFT_RTOL;
                }
                Integrator::GeneralizedAlpha(g)
            }
            Scheme::Rk4 => Integrator::Rk4(Rk4Baumgarte::default()),
        }
    }

    fn tag(self) -> String {
        match self {
            Scheme::Alpha(rho) => format!("ga{rho}"),
            Scheme::Rk4 => "rk4".into(),
        }
    }
}

/// Which flexible body a method uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyModel {
    /// The generated beam elements (`beam2`, `beam3`): `elements` is their number.
    Beam,
    /// Slider crank only: the benchmark's own rod discretization (2 lateral
    /// sine modes, quadratic axial ansatz), built by hand from its
    /// invariants ([`crate::benchmarks::slider_crank::SimeonRod`], axial mass as
    /// in the benchmark's code). Not an ffr modal body (see [`modal_cases`]):
    /// it measures the published solution with the published discretization.
    /// `elements` is its number of lateral modes, 2.
    SimeonRod,
    /// Spin-ups only: a modal body ([`ffr::modal`]) of the
    /// [`MODAL_MESH`]-element beam: `elements` is its number of normal
    /// modes, with the static modes (inertia loads, modal derivatives).
    Modal,
}

/// The mesh the report's modal bodies are reduced from.
pub const MODAL_MESH: usize = 16;

/// One way of solving a scene, apart from mesh and step: a *method family*
/// (one line in the diagrams).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Method {
    /// Integrator.
    pub scheme: Scheme,
    /// Consistent or lumped inertia.
    pub formalism: Formalism,
    /// Geometric stiffening model.
    pub stiffening: Stiffening,
    /// Kernels run on tapes instead of the compiled code (same numbers).
    pub tape: bool,
    /// Spin-up only: the general body (kernels for a spatial scene and a
    /// free frame) instead of the one specialized for a planar prescribed
    /// frame at rest.
    pub general: bool,
    /// The flexible body.
    pub body: BodyModel,
    /// Spin-ups only: the beam run as this many FFR sub-bodies, each with
    /// its own floating frame (`segments = N` of a scene file, issue 35;
    /// `elements` is the whole beam's, a multiple of it); 1: one body.
    pub segments: usize,
}

impl Method {
    /// Consistent, compiled, specialized where it applies, with this
    /// integrator and stiffening model.
    pub fn new(scheme: Scheme, stiffening: Stiffening) -> Self {
        Self {
            scheme,
            formalism: Formalism::Consistent,
            stiffening,
            tape: false,
            general: false,
            body: BodyModel::Beam,
            segments: 1,
        }
    }
    /// With lumped inertia.
    pub fn lumped(self) -> Self {
        Self {
            formalism: Formalism::Lumped,
            ..self
        }
    }
    /// On tapes.
    pub fn tape(self) -> Self {
        Self { tape: true, ..self }
    }
    /// The general body.
    pub fn general(self) -> Self {
        Self {
            general: true,
            ..self
        }
    }
    /// The beam run as `n` segments.
    pub fn segments(self, n: usize) -> Self {
        Self {
            segments: n,
            ..self
        }
    }

    /// The method's name in `points.csv`: `ffr-<integrator>-<formalism>-<stiffening>`,
    /// then `-seg<N>` (N segments, N > 1), `-tape` and `-general` where
    /// they apply (`ffr-ga0.8-consistent-4th`, `ffr-ga0.8-consistent-4th-seg8`,
    /// `ffr-rk4-consistent-linear-tape`, `ffr-ga0.9-simeon-rod`).
    pub fn name(&self) -> String {
        if self.body == BodyModel::SimeonRod {
            return format!("ffr-{}-simeon-rod", self.scheme.tag());
        }
        let modal = if self.body == BodyModel::Modal {
            format!("-modal{MODAL_MESH}")
        } else {
            String::new()
        };
        let st = match self.stiffening {
            Stiffening::Off => "linear",
            Stiffening::SecondOrder => "2nd",
            Stiffening::FourthOrder => "4th",
        };
        let f = match self.formalism {
            Formalism::Consistent => "consistent",
            Formalism::Lumped => "lumped",
        };
        let mut s = format!("ffr-{}-{f}-{st}{modal}", self.scheme.tag());
        if self.segments > 1 {
            s.push_str(&format!("-seg{}", self.segments));
        }
        if self.tape {
            s.push_str("-tape");
        }
        if self.general {
            s.push_str("-general");
        }
        s
    }
}

/// One run of the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// Scene.
    pub scene: Scene,
    /// Method family.
    pub method: Method,
    /// Number of elements (lateral modes for [`BodyModel::SimeonRod`],
    /// normal modes for [`BodyModel::Modal`]).
    pub elements: usize,
    /// Time step (s).
    pub dt: f64,
}

/// The runs of a report and how often each is repeated.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// `"quick"`, `"full"` or a caller's name.
    pub name: String,
    /// The runs, in order.
    pub cases: Vec<Case>,
    /// Repetitions per run (the CPU time is their minimum).
    pub reps: usize,
    /// Stop repeating a run once its repetitions have used this much CPU
    /// time (s): long runs scatter little and are not worth repeating.
    pub rep_budget: f64,
}

fn add(cases: &mut Vec<Case>, scene: Scene, method: Method, elements: &[usize], steps: &[f64]) {
    for &n in elements {
        for &dt in steps {
            cases.push(Case {
                scene,
                method,
                elements: n,
                dt,
            });
        }
    }
}

use Stiffening::{FourthOrder, Off, SecondOrder};

/// The spin-up's cases (for `ω_s = 4` or `10`).
fn spin_up(cases: &mut Vec<Case>, scene: Scene, full: bool) {
    let ga = Method::new(Scheme::Alpha(0.8), FourthOrder);
    if full {
        let els = [2, 4, 8, 16, 32];
        add(
            cases,
            scene,
            ga,
            &els,
            &[2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4],
        );
        // Where the model's own error (not the mesh's) sets the floor.
        add(cases, scene, ga, &[64], &[1e-2, 5e-3, 2e-3]);
        let coarse = [1e-2, 2e-3, 5e-4];
        add(
            cases,
            scene,
            Method::new(Scheme::Alpha(0.8), SecondOrder),
            &els,
            &coarse,
        );
        for rho in [0.5, 1.0] {
            let m = Method::new(Scheme::Alpha(rho), FourthOrder);
            add(cases, scene, m, &[4, 8, 16, 32], &coarse);
        }
        let rk4 = Method::new(Scheme::Rk4, FourthOrder);
        add(cases, scene, rk4, &[2, 4], &[5e-4, 2.5e-4, 1.25e-4]);
        add(cases, scene, rk4, &[8], &[2.5e-4, 1.25e-4]);
        add(cases, scene, ga.tape(), &[2, 8, 32], &[1e-2, 2e-3]);
        add(cases, scene, ga.general(), &[2, 8, 32], &[1e-2, 2e-3]);
        // Lumped inertia converges as h² (docs/theory.md §7): a family of its own.
        add(
            cases,
            scene,
            ga.lumped(),
            &[4, 8, 16, 32, 64],
            &[1e-2, 2e-3],
        );
        // The linear model diverges on both spin-ups (above the first bending
        // frequency, 2.9 rad/s): one run records how.
        add(
            cases,
            scene,
            Method::new(Scheme::Alpha(0.8), Off),
            &[8],
            &[1e-2],
        );
        // Segmented beams (issue 35): the error below the one frame's
        // floor, at the cost of the cut joints.
        for n in [2, 4, 8] {
            add(cases, scene, ga.segments(n), &[8, 16], &[1e-2, 5e-3, 2e-3]);
        }
        add(cases, scene, ga.segments(8), &[16], &[1e-3]);
    } else {
        add(cases, scene, ga, &[2, 4, 8, 16, 32], &[1e-2, 2e-3]);
        add(
            cases,
            scene,
            Method::new(Scheme::Alpha(0.8), SecondOrder),
            &[8, 32],
            &[1e-2],
        );
        add(
            cases,
            scene,
            Method::new(Scheme::Rk4, FourthOrder),
            &[2],
            &[5e-4],
        );
        add(cases, scene, ga.tape(), &[8], &[1e-2]);
        add(cases, scene, ga.general(), &[8], &[1e-2]);
        add(cases, scene, ga.lumped(), &[8], &[1e-2]);
        add(cases, scene, ga.segments(4), &[8], &[1e-2]);
    }
}

/// The spatial spin-up's cases: consistent and lumped bodies over elements
/// and steps, the second-order model at a few, segmented beams (2–16
/// segments), and the modal bodies ([`modal_cases`]).
fn spin_up_3d(cases: &mut Vec<Case>, full: bool) {
    let scene = Scene::SpinUp3d;
    let ga = Method::new(Scheme::Alpha(0.8), FourthOrder);
    if full {
        add(
            cases,
            scene,
            ga,
            &[2, 4, 8, 16, 32],
            &[1e-2, 5e-3, 2e-3, 1e-3, 5e-4],
        );
        add(
            cases,
            scene,
            ga.lumped(),
            &[4, 8, 16, 32],
            &[1e-2, 2e-3, 1e-3],
        );
        add(
            cases,
            scene,
            Method::new(Scheme::Alpha(0.8), SecondOrder),
            &[8, 16],
            &[1e-2, 2e-3],
        );
        // Segmented beams (issue 35): below the one frame's floor (0.14).
        add(cases, scene, ga.segments(2), &[16], &[2e-3]);
        let steps = [5e-3, 2e-3, 1e-3];
        add(cases, scene, ga.segments(4), &[16], &steps);
        add(cases, scene, ga.segments(8), &[8, 16], &steps);
        add(cases, scene, ga.segments(16), &[16], &steps);
    } else {
        add(cases, scene, ga, &[4], &[1e-2]);
        add(cases, scene, ga.lumped(), &[4], &[1e-2]);
        add(cases, scene, ga.segments(2), &[4], &[1e-2]);
    }
}

fn slider_crank(cases: &mut Vec<Case>, full: bool) {
    let scene = Scene::SliderCrank;
    let ga = Method::new(Scheme::Alpha(0.9), Off);
    let simeon = Method {
        body: BodyModel::SimeonRod,
        ..ga
    };
    if full {
        let steps = [1e-4, 5e-5, 2.5e-5, 1.25e-5];
        add(cases, scene, ga, &[2, 4, 8, 16], &steps);
        for rho in [0.5, 1.0] {
            add(
                cases,
                scene,
                Method::new(Scheme::Alpha(rho), Off),
                &[4, 8],
                &steps[..3],
            );
        }
        // The benchmark's rod is linear: with stiffening it is another model.
        for st in [SecondOrder, FourthOrder] {
            let m = Method::new(Scheme::Alpha(0.9), st);
            add(cases, scene, m, &[4, 8], &steps[1..3]);
        }
        add(
            cases,
            scene,
            Method::new(Scheme::Rk4, Off),
            &[2, 4, 8],
            &[1e-5, 5e-6, 2.5e-6],
        );
        add(cases, scene, ga.tape(), &[4, 8], &steps[1..3]);
        add(cases, scene, simeon, &[2], &steps);
        add(cases, scene, ga.lumped(), &[4], &[5e-5]);
    } else {
        add(cases, scene, ga, &[2, 4, 8], &[1e-4, 5e-5, 2.5e-5]);
        add(cases, scene, Method::new(Scheme::Rk4, Off), &[2], &[5e-6]);
        add(cases, scene, ga.tape(), &[4], &[5e-5]);
        add(cases, scene, simeon, &[2], &[1e-4, 2.5e-5]);
        add(cases, scene, ga.lumped(), &[4], &[5e-5]);
    }
}

fn pendulum(cases: &mut Vec<Case>, full: bool) {
    let scene = Scene::Pendulum;
    let ga = Method::new(Scheme::Alpha(1.0), Off);
    if full {
        let steps = [2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2.5e-4];
        add(cases, scene, ga, &[2, 4, 8], &steps);
        add(
            cases,
            scene,
            Method::new(Scheme::Alpha(0.8), Off),
            &[2, 4, 8],
            &[1e-3, 2.5e-4],
        );
        add(
            cases,
            scene,
            Method::new(Scheme::Rk4, Off),
            &[2, 4, 8],
            &[4e-5, 2e-5, 1e-5],
        );
        add(
            cases,
            scene,
            Method::new(Scheme::Alpha(1.0), FourthOrder),
            &[2, 4, 8],
            &[1e-3],
        );
        add(cases, scene, ga.tape(), &[4], &[1e-3, 2.5e-4]);
        add(cases, scene, ga.lumped(), &[4], &[1e-3]);
    } else {
        add(cases, scene, ga, &[2, 4, 8], &[1e-2, 2e-3, 5e-4]);
        add(cases, scene, Method::new(Scheme::Rk4, Off), &[2], &[4e-5]);
        add(cases, scene, ga.tape(), &[4], &[1e-3]);
        add(cases, scene, ga.lumped(), &[4], &[1e-3]);
    }
}

fn free_floating(cases: &mut Vec<Case>, full: bool) {
    let scene = Scene::FreeFloating;
    let rk4 = Method::new(Scheme::Rk4, Off);
    let ga = Method::new(Scheme::Alpha(1.0), Off);
    if full {
        let steps = [2e-4, 1e-4, 5e-5, 2.5e-5];
        add(cases, scene, rk4, &[2, 4, 8], &steps);
        let coarse = [2e-3, 1e-3, 5e-4];
        add(
            cases,
            scene,
            ga,
            &[2, 4, 8],
            &[&coarse[..], &steps[..]].concat(),
        );
        add(
            cases,
            scene,
            Method::new(Scheme::Rk4, FourthOrder),
            &[4],
            &steps[1..3],
        );
        add(cases, scene, rk4.tape(), &[4], &steps[1..2]);
        add(cases, scene, ga.tape(), &[4], &steps[1..2]);
        add(cases, scene, rk4.lumped(), &[4], &[1e-4]);
    } else {
        add(cases, scene, rk4, &[2, 4], &[2e-4, 1e-4]);
        add(cases, scene, ga, &[2, 4], &[1e-3, 1e-4]);
        add(cases, scene, rk4.tape(), &[2], &[1e-4]);
        add(cases, scene, rk4.lumped(), &[2], &[1e-4]);
    }
}

/// Modal bodies: the spin-ups with the [`MODAL_MESH`]-element beam reduced
/// to 2, 4 and 8 normal modes (in space, where each bending mode comes in
/// both planes, 4 and 8) plus static modes (`elements` = the number of
/// normal modes), generalized-α ρ∞ = 0.8, fourth-order stiffening — the
/// method family `ffr-ga0.8-consistent-4th-modal16`, beside the nodal
/// bodies of the same scene. Other scenes have none.
pub fn modal_cases(scene: Scene, full: bool) -> Vec<Case> {
    let mut cases = Vec::new();
    let m = Method {
        body: BodyModel::Modal,
        ..Method::new(Scheme::Alpha(0.8), FourthOrder)
    };
    let steps = [1e-2, 5e-3, 2e-3, 1e-3];
    match (scene, full) {
        (Scene::SpinUp4 | Scene::SpinUp10, true) => add(&mut cases, scene, m, &[2, 4, 8], &steps),
        (Scene::SpinUp4 | Scene::SpinUp10, false) => add(&mut cases, scene, m, &[2, 4], &[1e-2]),
        (Scene::SpinUp3d, true) => add(&mut cases, scene, m, &[4, 8], &steps),
        (Scene::SpinUp3d, false) => add(&mut cases, scene, m, &[4], &[1e-2]),
        _ => {}
    }
    cases
}

impl Grid {
    fn build(name: &str, full: bool, reps: usize, rep_budget: f64) -> Grid {
        let mut cases = Vec::new();
        for scene in Scene::ALL {
            match scene {
                Scene::SpinUp4 | Scene::SpinUp10 => spin_up(&mut cases, scene, full),
                Scene::SpinUp3d => spin_up_3d(&mut cases, full),
                Scene::SliderCrank => slider_crank(&mut cases, full),
                Scene::Pendulum => pendulum(&mut cases, full),
                Scene::FreeFloating => free_floating(&mut cases, full),
            }
            cases.extend(modal_cases(scene, full));
        }
        Grid {
            name: name.into(),
            cases,
            reps,
            rep_budget,
        }
    }

    /// The full grid: every choice that applies, up to 3 repetitions per
    /// run (fewer once a run's repetitions used 3 s of CPU).
    pub fn full() -> Grid {
        Grid::build("full", true, 3, 3.0)
    }

    /// A small grid (every scene, every kind of choice once), one run each.
    pub fn quick() -> Grid {
        Grid::build("quick", false, 1, 0.0)
    }

    /// Only the runs of these scenes.
    pub fn only(mut self, scenes: &[Scene]) -> Grid {
        self.cases.retain(|c| scenes.contains(&c.scene));
        self
    }

    /// The scenes with at least one run, in report order.
    pub fn scenes(&self) -> Vec<Scene> {
        Scene::ALL
            .into_iter()
            .filter(|s| self.cases.iter().any(|c| c.scene == *s))
            .collect()
    }
}
