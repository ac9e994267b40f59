//! `report.md`: how the report was measured, and per scene its diagram, the
//! cheapest run at each error level, ffr against the peers at equal error,
//! the method families, every run, and the runs that failed. Every number in
//! it is computed from the runs (and the peers' files) of this report.

use super::analysis::{cheapest, cost_at, families, pareto, LEVELS};
use super::data::{FailedRun, Peers, Point};
use super::grid::{ErrorKind, Grid, Scene};
use super::measure;
use std::fmt::Write;

/// What the report is made of.
pub struct Input<'a> {
    /// The grid that ran.
    pub grid: &'a Grid,
    /// The command line.
    pub command: &'a str,
    /// ffr's points.
    pub points: &'a [Point],
    /// Failed runs.
    pub failures: &'a [FailedRun],
    /// What the peers' directory held.
    pub peers: &'a Peers,
    /// Peers' points of the grid's scenes.
    pub peer_points: &'a [Point],
    /// Wall time of the runs and diagrams (s).
    pub wall_s: f64,
    /// CPU time of all repetitions (s).
    pub sim_cpu_s: f64,
    /// Load average before and after the runs.
    pub load: (Option<String>, Option<String>),
    /// Runs at once.
    pub workers: usize,
}

/// A short statement of a scene's error, for axis labels.
pub fn error_short(scene: Scene) -> &'static str {
    match scene {
        Scene::SpinUp4 | Scene::SpinUp10 => "max |y − y_ref| / max |y_ref|, tip transverse",
        Scene::SpinUp3d => "max |y − y_ref| / max |y_ref|, larger of tip v and w",
        Scene::SliderCrank => "|a₁ − q₁| / |q₁| at 0.1 s",
        Scene::Pendulum => "max |E − E₀| / (m g L/2)",
        Scene::FreeFloating => "max relative drift of p and H",
    }
}

/// The definition of a scene's error (what `error` means in its rows).
fn error_definition(scene: Scene) -> String {
    match scene {
        Scene::SpinUp4 | Scene::SpinUp10 => format!(
            "`reference`: the transverse tip displacement in the hub frame against the geometrically exact Exudyn history (`bench/reference/spin_up_omega{}.csv`, ANCF cable, 64 elements, dt 1e-4 s; `bench/reference/README.md`), `max_k |y(t_k) − y_ref(t_k)| / max_k |y_ref(t_k)|` over every step time `t_k ≤ 20 s` of the run, the reference interpolated linearly (`ffr::reference`). Beam: 8 m, clamped, `beam2` elements (planar).",
            if scene == Scene::SpinUp4 { 4 } else { 10 }
        ),
        Scene::SpinUp3d => format!(
            "`reference`: the tip displacement's two transverse components in the hub frame, `v` (hub y, in the rotation plane) and `w` (hub z, along the spin axis), against the geometrically exact Exudyn history (`bench/reference/spin_up_gravity_omega4.csv`, ANCF cable 3D, 64 elements, dt 1e-4 s; `bench/reference/README.md`): the larger of `max_k |v(t_k) − v_ref(t_k)| / max_k |v_ref(t_k)|` and the same for `w`, over every step time `t_k ≤ 20 s` of the run. Beam: the KRB beam (8 m, clamped, `beam3` elements, the thin tube's torsion data) spun up to 4 rad/s about global z under gravity {} m/s² along −z (`scenes/spin_up_gravity.toml`): it falls about 3.3 m from rest and swings while the spin-up bends it in the rotation plane.",
            measure::SPIN_UP_3D_GRAVITY
        ),
        Scene::SliderCrank => "`published`: the relative error of the rod's first lateral sine-mode amplitude `a₁ = (2/l)∫v sin(πx/l)dx` at `t = 0.1 s` against the published `q₁ = 1.8932e-4 m` of the IVP test set (the quantity the benchmark's `q₁` is; `tests/slider_crank.rs` uses the same values). Rod: `beam2`, pinned reference, prismatic slider, started from the benchmark's initial values. The generated beam carries section rotary inertia, which the benchmark neglects (`tests/slider_crank.rs` measured that it moves `q₁(0.1 s)` by −0.13 %), so the beam rod's error levels off near 1e-3 whatever the mesh and step; `ffr-*-simeon-rod` is the benchmark's own discretization (2 sine modes, `elements` = 2) run in ffr's runtime, whose error is the integration error alone. The benchmark's rod is linear: runs with geometric stiffening (`-2nd`, `-4th`) solve another model, and their error is mostly that difference.".into(),
        Scene::Pendulum => format!(
            "`energy`: `max |E(t) − E(0)| / (m g L/2)` over {} sample times in 0–1 s (the continuous system conserves `E`; generalized-α with ρ∞ < 1 dissipates it on purpose, which counts as error here). It measures the time integration only, not the spatial discretization. Bar: aluminium 1 m, 10 × 10 mm, `beam2`, clamped reference, pinned to the ground at node 0, released horizontal.",
            measure::SAMPLES
        ),
        Scene::FreeFloating => format!(
            "`momentum`: `max(max_t |p − p₀|/|p₀|, max_t |H − H₀|/|H₀|)` (linear and angular momentum about the origin) over {} sample times in 0–0.2 s; it measures the time integration only. Body: polymer bar 1 m, `beam3`, pinned reference, in space, spinning and vibrating in its first two elastic modes (those of the consistent body of the same mesh, for every variant). Generalized-α here uses the scene's Newton tolerance 1e-12.",
            measure::SAMPLES
        ),
    }
}

/// 3 significant digits, plain for 1e-3 ≤ |x| < 1e4.
fn sig(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e4).contains(&a) {
        format!("{x:.2e}")
    } else {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    }
}

fn err(x: f64) -> String {
    format!("{x:.2e}")
}

fn dt(x: f64) -> String {
    crate::output::number(x)
}

fn run_label(p: &Point) -> String {
    format!(
        "`{}`, {} elements, dt = {} s ({} s CPU, error {})",
        p.method,
        p.elements,
        dt(p.dt),
        sig(p.cpu_s),
        err(p.error)
    )
}

/// The peers' tools present among `points`, in order.
fn tools(points: &[Point]) -> Vec<String> {
    let mut t: Vec<String> = Vec::new();
    for p in points {
        if !t.contains(&p.tool) {
            t.push(p.tool.clone());
        }
    }
    t
}

fn tool_title(t: &str) -> String {
    let mut c = t.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}

/// `a / b` as a ratio with three digits.
fn ratio(a: f64, b: f64) -> String {
    format!("{}×", sig(a / b))
}

/// Compare a variant family with its base at equal (elements, dt).
fn variant_reading(points: &[Point], suffix: &str, what: &str) -> Option<String> {
    let mut lines = Vec::new();
    for fam in families(points) {
        let Some(base) = fam.strip_suffix(suffix) else {
            continue;
        };
        let mut ratios = Vec::new();
        let mut max_diff = 0.0f64;
        for v in points.iter().filter(|p| p.method == fam) {
            if let Some(b) = points
                .iter()
                .find(|b| b.method == base && b.elements == v.elements && b.dt == v.dt)
            {
                ratios.push(v.cpu_s / b.cpu_s);
                max_diff = max_diff.max((v.error - b.error).abs() / b.error.abs().max(1e-300));
            }
        }
        if ratios.is_empty() {
            continue;
        }
        ratios.sort_by(f64::total_cmp);
        let med = ratios[ratios.len() / 2];
        let same = if max_diff == 0.0 {
            "identical errors".to_string()
        } else {
            format!("errors differ by up to {} (relative)", err(max_diff))
        };
        lines.push(format!(
            "`{fam}` against `{base}` at the same elements and step ({} pairs): {what} takes {}–{} the CPU time (median {}), {same}.",
            ratios.len(),
            ratio(ratios[0], 1.0),
            ratio(*ratios.last().unwrap(), 1.0),
            ratio(med, 1.0),
        ));
    }
    (!lines.is_empty()).then(|| lines.join(" "))
}

/// The segmented families (`…-seg<N>`) against their one-body family at
/// the same elements and step: how much the error falls and the CPU time
/// grows, and the smallest error each family reaches.
fn segments_reading(points: &[Point]) -> Option<String> {
    let mut lines = Vec::new();
    for fam in families(points) {
        let Some((base, n)) = fam.rsplit_once("-seg") else {
            continue;
        };
        if n.parse::<usize>().is_err() {
            continue;
        }
        let (mut errs, mut cpus) = (Vec::new(), Vec::new());
        for v in points.iter().filter(|p| p.method == fam) {
            if let Some(b) = points
                .iter()
                .find(|b| b.method == base && b.elements == v.elements && b.dt == v.dt)
            {
                errs.push(v.error / b.error.max(1e-300));
                cpus.push(v.cpu_s / b.cpu_s);
            }
        }
        let best = points
            .iter()
            .filter(|p| p.method == fam)
            .min_by(|a, b| a.error.total_cmp(&b.error));
        let Some(best) = best else { continue };
        let mut line = format!(
            "`{fam}` ({n} segments): smallest error {} ({} elements, dt = {} s, {} s CPU)",
            err(best.error),
            best.elements,
            dt(best.dt),
            sig(best.cpu_s)
        );
        if !errs.is_empty() {
            errs.sort_by(f64::total_cmp);
            cpus.sort_by(f64::total_cmp);
            line.push_str(&format!(
                "; against `{base}` at the same elements and step ({} pairs) the error is {}–{} of the one body's (median {}) at {}–{} its CPU time (median {})",
                errs.len(),
                ratio(errs[0], 1.0),
                ratio(*errs.last().unwrap(), 1.0),
                ratio(errs[errs.len() / 2], 1.0),
                ratio(cpus[0], 1.0),
                ratio(*cpus.last().unwrap(), 1.0),
                ratio(cpus[cpus.len() / 2], 1.0),
            ));
        }
        lines.push(format!("{line}."));
    }
    (!lines.is_empty()).then(|| format!("Segments: {}", lines.join(" ")))
}

/// ffr's Pareto front at the errors of a peer's front points: at how many
/// ffr's front (interpolated) is as cheap or cheaper, dearer, or out of
/// reach (below ffr's smallest error).
fn front_at_peer_points(ffr: &[&Point], peer: &[&Point], tool: &str) -> Option<String> {
    let (ff, pf) = (pareto(ffr.iter().copied()), pareto(peer.iter().copied()));
    if ff.is_empty() || pf.is_empty() {
        return None;
    }
    let (mut cheaper, mut dearer, mut out) = (Vec::new(), Vec::new(), Vec::new());
    for p in &pf {
        match cost_at(&ff, p.error) {
            Some(c) if c <= p.cpu_s => cheaper.push(c / p.cpu_s),
            Some(c) => dearer.push((p.error, c / p.cpu_s)),
            None => out.push(p.error),
        }
    }
    let mut parts = vec![format!(
        "at the errors of {}'s {} front points ({}–{}) ffr's front is as cheap or cheaper at {}",
        tool_title(tool),
        pf.len(),
        err(pf.iter().map(|p| p.error).fold(f64::INFINITY, f64::min)),
        err(pf.iter().map(|p| p.error).fold(0.0, f64::max)),
        cheaper.len()
    )];
    if !cheaper.is_empty() {
        cheaper.sort_by(f64::total_cmp);
        parts[0].push_str(&format!(
            " ({}–{} of its time)",
            ratio(cheaper[0], 1.0),
            ratio(*cheaper.last().unwrap(), 1.0)
        ));
    }
    if !dearer.is_empty() {
        let worst = dearer.iter().map(|d| d.1).fold(0.0, f64::max);
        parts.push(format!(
            "dearer at {} (errors {}–{}, up to {})",
            dearer.len(),
            err(dearer.iter().map(|d| d.0).fold(f64::INFINITY, f64::min)),
            err(dearer.iter().map(|d| d.0).fold(0.0, f64::max)),
            ratio(worst, 1.0)
        ));
    }
    if !out.is_empty() {
        parts.push(format!(
            "out of reach at {} (errors {}–{}, below ffr's smallest {})",
            out.len(),
            err(out.iter().copied().fold(f64::INFINITY, f64::min)),
            err(out.iter().copied().fold(0.0, f64::max)),
            err(ffr.iter().map(|p| p.error).fold(f64::INFINITY, f64::min))
        ));
    }
    Some(parts.join(", "))
}

/// The report.
pub fn report(inp: &Input) -> String {
    let mut s = String::new();
    let scenes = inp.grid.scenes();
    let peer_tools = tools(inp.peer_points);
    let _ = writeln!(s, "# ffr work-precision report\n");
    let _ = writeln!(
        s,
        "Made by `{}` (the {} grid): {} runs on {} scenes, {} points, {} failed runs. Each point is one run (scene, method family, elements, time step): its CPU time against its error. `points.csv` holds ffr's points; the diagrams (`<scene>.svg`) also show the peers'.\n",
        inp.command,
        inp.grid.name,
        inp.grid.cases.len(),
        scenes.len(),
        inp.points.len(),
        inp.failures.len()
    );

    // ---------------------------------------------------------------- method
    let _ = writeln!(s, "## How it was measured\n");
    let reps = if inp.grid.reps <= 1 {
        "One run per point (no repetition: the quick grid's times scatter more)".to_string()
    } else {
        format!(
            "The minimum over up to {} repetitions of the run, each from a freshly built system; a run stops repeating once its repetitions have used {} s of CPU (the `runs` column gives the count)",
            inp.grid.reps, inp.grid.rep_budget
        )
    };
    let _ = writeln!(
        s,
        "- **CPU time** (`cpu_s`): {} around `System::simulate` only — the scene, its bodies and kernels (tapes included) are built before the clock starts, and the error is computed after it stops; the consistent initial state is part of `simulate`. {reps}. The spin-up records the tip displacement at every step (its error is taken over every step); the pendulum and the free-floating body evaluate their conserved quantities at {} sample times, not at every step.",
        measure::clock_name(),
        measure::SAMPLES
    );
    let _ = writeln!(
        s,
        "- **Errors** (`error_kind`; the scenes below define each):"
    );
    for k in ErrorKind::ALL {
        let which: Vec<&str> = scenes
            .iter()
            .filter(|sc| sc.error_kind() == k)
            .map(|sc| sc.name())
            .collect();
        let what = match k {
            ErrorKind::Reference => {
                "against a geometrically exact reference history (Exudyn, `bench/reference/`)"
            }
            ErrorKind::Published => "against a published solution (IVP test set)",
            ErrorKind::Energy => {
                "drift of the conserved total energy (no reference solution exists)"
            }
            ErrorKind::Momentum => {
                "drift of the conserved linear and angular momentum (no reference solution exists)"
            }
        };
        if !which.is_empty() {
            let _ = writeln!(s, "  - `{}`: {what}; {}.", k.name(), which.join(", "));
        }
    }
    let cpus = std::thread::available_parallelism().map_or(0, |n| n.get());
    let load = |l: &Option<String>| l.clone().unwrap_or_else(|| "unknown".into());
    let _ = writeln!(
        s,
        "- **This report**: {} s wall for the runs and diagrams, {} s CPU in the runs (every repetition), {} runs at once (each timed by its own thread's CPU clock); {} CPUs available, load average {} before and {} after (`/proc/loadavg`; other work on a shared machine slows runs and scatters their times).",
        sig(inp.wall_s),
        sig(inp.sim_cpu_s),
        inp.workers,
        cpus,
        load(&inp.load.0),
        load(&inp.load.1)
    );
    if inp.peers.files.is_empty() {
        let _ = writeln!(
            s,
            "- **Peers**: no peer file was found in `{}` (`--peers DIR`); only ffr's points are shown.",
            inp.peers.dir.display()
        );
    } else {
        let names: Vec<String> = inp
            .peers
            .files
            .iter()
            .map(|f| format!("`{}`", f.display()))
            .collect();
        let _ = writeln!(
            s,
            "- **Peers**: {} ({} points for the scenes of this report). Their CPU times are the peers' own measurements as their files give them (Exudyn: `time.process_time()` around the solve, minimum of 3 repetitions, `bench/peers/README.md`), made at another time on the same kind of machine: compare orders of magnitude, not percents.",
            names.join(", "),
            inp.peer_points.len()
        );
    }
    for p in &inp.peers.problems {
        let _ = writeln!(s, "  - peer data skipped: {p}");
    }
    let _ = writeln!(
        s,
        "- **Cheapest at an error level**: the run of least CPU time whose error is at most the level (an actual run, no interpolation)."
    );
    let _ = writeln!(
        s,
        "- **At equal error** (ffr against a peer, and the method families): the Pareto front of the points (those no other point beats in both CPU time and error), and its CPU time at the level by linear interpolation of log CPU time in log error between the two front points that bracket the level; at or above the error of the front's cheapest point, that point's time; below the front's smallest error, none (no extrapolation). The ratio is ffr's interpolated time over the peer's."
    );
    let _ = writeln!(
        s,
        "- **Modal bodies** (`-modal16` families): the spin-ups' 16-element beam reduced to `elements` normal modes (2, 4, 8; in space 4, 8) plus its static modes (inertia loads, modal derivatives; docs/modal.md), `modal_cases` in `src/report/grid.rs`."
    );
    let _ = writeln!(
        s,
        "- **Segmented beams** (`-seg<N>` families, spin-ups only): the beam of `elements` elements run as `N` FFR sub-bodies of `elements / N` elements, each with its own floating frame, joined by exact cut joints (`segments = N` of a scene file, docs/scenes.md). These runs go through the scene module (`spin_up::scene_text`, the same model as the one-body runs: `ffr-cli/tests/report.rs`); their CPU time is that of the scene's run, `System::simulate` with the tip deflections recorded at every step.\n"
    );

    // ---------------------------------------------------------------- summary
    let _ = writeln!(s, "## Summary: cheapest ffr run at each error level\n");
    let _ = writeln!(
        s,
        "| scene | error kind | error ≤ 1e-2 | error ≤ 1e-3 | error ≤ 1e-4 |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    for sc in &scenes {
        let pts: Vec<&Point> = inp.points.iter().filter(|p| p.scene == sc.name()).collect();
        let cells: Vec<String> = LEVELS
            .iter()
            .map(|&l| match cheapest(pts.iter().copied(), l) {
                Some(p) => format!(
                    "`{}` {} el, dt {}: {} s",
                    p.method,
                    p.elements,
                    dt(p.dt),
                    sig(p.cpu_s)
                ),
                None => "not reached".into(),
            })
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} |",
            sc.name(),
            sc.error_kind(),
            cells.join(" | ")
        );
    }
    let _ = writeln!(s);
    for tool in &peer_tools {
        let _ = writeln!(
            s,
            "ffr against {} at equal error (interpolated Pareto fronts of all methods of each; ffr time / {} time):\n",
            tool_title(tool),
            tool_title(tool)
        );
        let _ = writeln!(s, "| scene | 1e-2 | 1e-3 | 1e-4 |");
        let _ = writeln!(s, "|---|---|---|---|");
        for sc in &scenes {
            let ffr: Vec<&Point> = inp.points.iter().filter(|p| p.scene == sc.name()).collect();
            let peer: Vec<&Point> = inp
                .peer_points
                .iter()
                .filter(|p| p.scene == sc.name() && &p.tool == tool)
                .collect();
            if peer.is_empty() {
                continue;
            }
            let (ff, pf) = (pareto(ffr), pareto(peer));
            let cells: Vec<String> = LEVELS
                .iter()
                .map(|&l| match (cost_at(&ff, l), cost_at(&pf, l)) {
                    (Some(a), Some(b)) => format!("{} ({} s / {} s)", ratio(a, b), sig(a), sig(b)),
                    (None, Some(_)) => "ffr does not reach it".into(),
                    (Some(_), None) => format!("{tool} does not reach it"),
                    (None, None) => "neither reaches it".into(),
                })
                .collect();
            let _ = writeln!(s, "| {} | {} |", sc.name(), cells.join(" | "));
        }
        let _ = writeln!(s);
    }

    // ---------------------------------------------------------------- scenes
    for sc in &scenes {
        scene_section(&mut s, inp, *sc, &peer_tools);
    }
    s
}

fn scene_section(s: &mut String, inp: &Input, sc: Scene, peer_tools: &[String]) {
    let pts: Vec<Point> = inp
        .points
        .iter()
        .filter(|p| p.scene == sc.name())
        .cloned()
        .collect();
    let peers: Vec<Point> = inp
        .peer_points
        .iter()
        .filter(|p| p.scene == sc.name())
        .cloned()
        .collect();
    let fails: Vec<&FailedRun> = inp
        .failures
        .iter()
        .filter(|f| f.scene == sc.name())
        .collect();
    let _ = writeln!(s, "## {}: {}\n", sc.name(), sc.title());
    let _ = writeln!(
        s,
        "![work-precision diagram of {}]({}.svg)\n",
        sc.name(),
        sc.name()
    );
    let _ = writeln!(s, "Error: {}\n", error_definition(sc));
    for p in peers
        .iter()
        .filter(|p| p.error_kind != sc.error_kind().name())
    {
        let _ = writeln!(
            s,
            "Note: the peer point `{}` {} el dt {} has error kind `{}`, not `{}`.\n",
            p.method,
            p.elements,
            dt(p.dt),
            p.error_kind,
            sc.error_kind()
        );
    }

    // Cheapest at each level.
    let _ = writeln!(s, "### Cheapest run at each error level\n");
    let _ = writeln!(
        s,
        "| error ≤ | tool | method | elements | dt (s) | CPU s | error |"
    );
    let _ = writeln!(s, "|---|---|---|---:|---:|---:|---:|");
    let mut all_tools = vec!["ffr".to_string()];
    all_tools.extend(peer_tools.iter().cloned());
    for &l in &LEVELS {
        for t in &all_tools {
            let set: Vec<&Point> = pts
                .iter()
                .chain(peers.iter())
                .filter(|p| &p.tool == t)
                .collect();
            if set.is_empty() {
                continue;
            }
            match cheapest(set.iter().copied(), l) {
                Some(p) => {
                    let _ = writeln!(
                        s,
                        "| {} | {} | `{}` | {} | {} | {} | {} |",
                        err(l),
                        t,
                        p.method,
                        p.elements,
                        dt(p.dt),
                        sig(p.cpu_s),
                        err(p.error)
                    );
                }
                None => {
                    let _ = writeln!(s, "| {} | {} | not reached | | | | |", err(l), t);
                }
            }
        }
    }
    let _ = writeln!(s);

    // Reading.
    let _ = write!(s, "Reading: ");
    let mut parts = Vec::new();
    for &l in &LEVELS {
        match cheapest(pts.iter(), l) {
            Some(p) => parts.push(format!(
                "at ≤ {} the cheapest ffr run is {}",
                err(l),
                run_label(p)
            )),
            None => {
                let best = pts.iter().min_by(|a, b| a.error.total_cmp(&b.error));
                parts.push(match best {
                    Some(b) => format!(
                        "no ffr run reaches ≤ {} (the smallest error is {}: {})",
                        err(l),
                        err(b.error),
                        run_label(b)
                    ),
                    None => format!("no ffr run reaches ≤ {}", err(l)),
                });
            }
        }
    }
    let _ = write!(s, "{}.", parts.join("; "));
    for t in peer_tools {
        let set: Vec<&Point> = peers.iter().filter(|p| &p.tool == t).collect();
        if set.is_empty() {
            continue;
        }
        let (ff, pf) = (pareto(pts.iter()), pareto(set.iter().copied()));
        let mut cmp = Vec::new();
        for &l in &LEVELS {
            match (cost_at(&ff, l), cost_at(&pf, l)) {
                (Some(a), Some(b)) => cmp.push(format!(
                    "at {} ffr needs {} of {}'s CPU time ({} s against {} s)",
                    err(l),
                    ratio(a, b),
                    tool_title(t),
                    sig(a),
                    sig(b)
                )),
                (None, Some(_)) => {
                    cmp.push(format!("at {} only {} has a run", err(l), tool_title(t)))
                }
                (Some(_), None) => cmp.push(format!("at {} only ffr has a run", err(l))),
                (None, None) => {}
            }
        }
        if !cmp.is_empty() {
            let _ = write!(s, " Interpolated fronts: {}.", cmp.join("; "));
        }
        let mine: Vec<&Point> = pts.iter().collect();
        if let Some(r) = front_at_peer_points(&mine, &set, t) {
            let _ = write!(s, " Pareto fronts: {r}.");
        }
    }
    if let Some(r) = segments_reading(&pts) {
        let _ = write!(s, " {r}");
    }
    if let Some(r) = variant_reading(&pts, "-tape", "the tape") {
        let _ = write!(s, " {r}");
    }
    if let Some(r) = variant_reading(&pts, "-general", "the general body") {
        let _ = write!(s, " {r}");
    }
    let _ = writeln!(s, "\n");

    // Families.
    let _ = writeln!(s, "### Method families\n");
    let _ = writeln!(
        s,
        "Interpolated CPU time of each family's Pareto front at each level (s; — where the family does not reach it).\n"
    );
    let _ = writeln!(
        s,
        "| tool | method | points | smallest error | at 1e-2 | at 1e-3 | at 1e-4 |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|");
    let both: Vec<Point> = pts.iter().chain(peers.iter()).cloned().collect();
    for fam in families(&both) {
        let set: Vec<&Point> = both.iter().filter(|p| p.method == fam).collect();
        let front = pareto(set.iter().copied());
        let best = set.iter().map(|p| p.error).fold(f64::INFINITY, f64::min);
        let cells: Vec<String> = LEVELS
            .iter()
            .map(|&l| cost_at(&front, l).map_or("—".into(), sig))
            .collect();
        let _ = writeln!(
            s,
            "| {} | `{fam}` | {} | {} | {} |",
            set[0].tool,
            set.len(),
            err(best),
            cells.join(" | ")
        );
    }
    let _ = writeln!(s);

    // Every run.
    let front = pareto(pts.iter().chain(peers.iter()));
    let on_front = |p: &Point| front.iter().any(|f| std::ptr::eq(*f, p) || *f == p);
    let _ = writeln!(s, "### Every ffr run\n");
    let _ = writeln!(
        s,
        "`front`: on the Pareto front of all methods (peers included) of this scene.\n"
    );
    let _ = writeln!(
        s,
        "| method | elements | dt (s) | CPU s | error | runs | front |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---|");
    for p in &pts {
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} | {} | {} | {} |",
            p.method,
            p.elements,
            dt(p.dt),
            sig(p.cpu_s),
            err(p.error),
            p.reps,
            if on_front(p) { "★" } else { "" }
        );
    }
    let _ = writeln!(s);
    let peer_front: Vec<&&Point> = front.iter().filter(|p| p.tool != "ffr").collect();
    if !peers.is_empty() {
        let _ = writeln!(
            s,
            "Peer runs on the front of all methods: {}.\n",
            if peer_front.is_empty() {
                "none".to_string()
            } else {
                peer_front
                    .iter()
                    .map(|p| {
                        format!(
                            "`{}` {} el dt {} ({} s, {})",
                            p.method,
                            p.elements,
                            dt(p.dt),
                            sig(p.cpu_s),
                            err(p.error)
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("; ")
            }
        );
    }

    // Failures.
    let _ = writeln!(s, "### Failed runs\n");
    if fails.is_empty() {
        let _ = writeln!(s, "None.\n");
    } else {
        let _ = writeln!(
            s,
            "Runs that did not reach the end or gave no usable error: no point, not in points.csv.\n"
        );
        let _ = writeln!(
            s,
            "| method | elements | dt (s) | stopped at t (s) | reason |"
        );
        let _ = writeln!(s, "|---|---:|---:|---:|---|");
        for f in fails {
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {} | {} |",
                f.method,
                f.elements,
                dt(f.dt),
                f.t.map_or("—".into(), |t| format!("{t:.4}")),
                f.reason.replace('|', "\\|").replace('\n', " ")
            );
        }
        let _ = writeln!(s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_three_significant_digits() {
        assert_eq!(sig(0.012345), "0.0123");
        assert_eq!(sig(1.2345), "1.23");
        assert_eq!(sig(123.45), "123");
        assert_eq!(sig(2.5e-5), "2.50e-5");
        assert_eq!(err(1.5e-3), "1.50e-3");
    }
}
