//! Rust source from the generated programs: a kernel type implementing the
//! runtime's `ElementKernels` (and, for a body with a fixed mesh, a parameter
//! struct implementing `CompiledBody`), flat and unrolled within an element,
//! formatted by prettyplease, with a header naming the input, the operation
//! count of every function and what the model leaves out.

use crate::body::BodySpec;
use crate::eom::OutArr;
use crate::kernel::KernelSet;
use crate::poly::Param;
use crate::poly::Sym;
use crate::program::{Expr, Input, Program};
use ffr_spec::KernelKind;
use std::fmt::Write;

/// How to emit.
#[derive(Clone, Debug)]
pub struct EmitOptions {
    /// Name of the body type (e.g. `Arm`); the kernels are `ArmKernels`.
    pub type_name: String,
    /// Also define the parameter struct (build.rs path); the attribute
    /// implements the traits for the user's own struct instead.
    pub define_struct: bool,
    /// Path of the runtime crate as the generated code sees it.
    pub runtime_path: String,
    /// A body's section table, baked as `CompiledBody::SECTIONS` (the
    /// kernels must be generated for varying sections); `None`: uniform.
    pub sections: Option<Vec<ffr_spec::scene::Station>>,
}

impl Default for EmitOptions {
    fn default() -> Self {
        Self {
            type_name: "Body".into(),
            define_struct: true,
            runtime_path: "::ffr::runtime".into(),
            sections: None,
        }
    }
}

pub use crate::sanitize::comment_text;

/// A one-line description of a kernel set's input.
pub fn describe(set: &KernelSet) -> String {
    let m = set.model();
    let text = format!(
        "shape `{}` ({}, fnv1a {:016x}), {}",
        comment_text(&m.shape.name),
        comment_text(&m.shape.origin),
        m.shape.source_hash,
        m.resolved_options().describe()
    );
    match m.sections {
        ffr_spec::SectionModel::Uniform => text,
        ffr_spec::SectionModel::Varying => text + ", varying sections",
    }
}

/// What the model leaves out, and why (one line each).
pub fn omissions(set: &KernelSet) -> Vec<String> {
    let m = set.model();
    let mut v = Vec::new();
    if m.scene() == ffr_spec::SceneDim::Planar {
        v.push(
            "ā_z, α_x, α_y, ω_x, ω_y and their terms: planar scene (motion in the x–y plane)"
                .to_string(),
        );
    }
    if !m.options.frame.is_free() {
        v.push("reference rows f_r, f_θ and the frame derivatives (residual, tangent): frame motion prescribed".to_string());
    }
    if m.options.frame.zero_frame_acceleration() {
        v.push("ā = Aᵀ(R̈ − g) and its terms: frame origin fixed, no gravity".to_string());
    }
    if !m.options.stiffening.is_on() {
        v.push("geometric stiffening energy: stiffening off".to_string());
    }
    v
}

fn lit(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') {
        s
    } else {
        format!("{s}.0")
    }
}

fn prec(e: &Expr) -> u8 {
    match e {
        Expr::Add(..) | Expr::Sub(..) => 1,
        Expr::Mul(..) | Expr::Div(..) => 2,
        Expr::Neg(..) => 3,
        Expr::Lit(x) if *x < 0.0 => 3,
        Expr::Var(_) | Expr::Lit(_) => 4,
    }
}

/// Print an expression with exactly the grouping of its tree.
fn expr(e: &Expr, names: &[String], out: &mut String) {
    let child = |c: &Expr, min: u8, out: &mut String| {
        if prec(c) < min {
            out.push('(');
            expr(c, names, out);
            out.push(')');
        } else {
            expr(c, names, out);
        }
    };
    match e {
        Expr::Var(i) => out.push_str(&names[*i as usize]),
        Expr::Lit(x) => out.push_str(&lit(*x)),
        Expr::Add(a, b) | Expr::Sub(a, b) => {
            child(a, 1, out);
            out.push_str(if matches!(e, Expr::Add(..)) {
                " + "
            } else {
                " - "
            });
            child(b, 2, out);
        }
        Expr::Mul(a, b) | Expr::Div(a, b) => {
            child(a, 2, out);
            out.push_str(if matches!(e, Expr::Mul(..)) {
                " * "
            } else {
                " / "
            });
            child(b, 3, out);
        }
        Expr::Neg(a) => {
            out.push('-');
            child(a, 4, out);
        }
    }
}

/// The Rust expression an input slot reads.
fn input_source(i: Input) -> String {
    match i {
        Input::Param(Param::ElemLength) => "l".into(),
        Input::Param(p) => format!("params.{}", p.field()),
        Input::Coef(c) => format!("c[{c}]"),
        Input::Moment(i) => format!("mu[{i}]"),
        Input::Sym(s) => match s {
            Sym::X0 => "x0".into(),
            Sym::Frame(k) => format!("frame[{k}]"),
            Sym::Bp => "bp".into(),
            Sym::Gp => "gp".into(),
            Sym::Q(i) => format!("q[{i}]"),
            Sym::Qd(i) => format!("qd[{i}]"),
            Sym::Qdd(i) => format!("qdd[{i}]"),
            Sym::Xi => "xi".into(),
            other => unreachable!("{other} is not a kernel input"),
        },
    }
}

/// The local array an output array is written to.
fn out_name(a: OutArr) -> &'static str {
    match a {
        OutArr::Fr => "f_r",
        OutArr::Fth => "f_th",
        OutArr::Fe => "f_e",
        OutArr::Kee => "k_ee",
        OutArr::DeFrame => "d_e_frame",
        OutArr::KrefE => "k_ref_e",
        OutArr::DrefFrame => "d_ref_frame",
        OutArr::St => "s_t",
        OutArr::Mee => "m_ee",
        OutArr::MeFrame => "m_e_frame",
        OutArr::MrefE => "m_ref_e",
        OutArr::MrefFrame => "m_ref_frame",
        OutArr::Energy => "energy",
        OutArr::Inv => "out",
        OutArr::S => "s",
        OutArr::Psi => "psi",
        OutArr::Coef => "c",
        OutArr::Z => "z",
        OutArr::Gz => "g",
        OutArr::Hz => "h",
    }
}

/// A program's statements by section: the input loads, the intermediate
/// terms (one `let` each) and the output assignments (SymForce's layout).
struct Sections {
    inputs: String,
    intermediates: String,
    outputs: String,
}

/// The statements of `p`: inputs after `views.inputs` (the fixed-size views
/// of the slices read), outputs after `views.outputs` (of the slices
/// written). A scalar input already bound under its own name (`x0`) needs no
/// `let x0 = x0;`.
fn sections(p: &Program, views: &Views) -> Sections {
    let mut inputs = views.inputs.clone();
    for (slot, input) in &p.inputs {
        let (name, src) = (&p.names[*slot as usize], input_source(*input));
        if *name != src {
            writeln!(inputs, "let {name} = {src};").unwrap();
        }
    }
    let mut intermediates = String::new();
    for (slot, e) in &p.stmts {
        write!(intermediates, "let {} = ", p.names[*slot as usize]).unwrap();
        expr(e, &p.names, &mut intermediates);
        intermediates.push_str(";\n");
    }
    let mut outputs = views.outputs.clone();
    for ((arr, idx), e) in &p.outputs {
        if *arr == OutArr::Energy {
            outputs.push_str("energy = ");
        } else {
            write!(outputs, "{}[{idx}] = ", out_name(*arr)).unwrap();
        }
        expr(e, &p.names, &mut outputs);
        outputs.push_str(";\n");
    }
    Sections {
        inputs,
        intermediates,
        outputs,
    }
}

/// Which kernel input arrays a program reads.
fn reads(p: &Program, f: impl Fn(Sym) -> bool) -> bool {
    p.inputs
        .iter()
        .any(|(_, i)| matches!(i, Input::Sym(s) if f(*s)))
}

fn reads_coef(p: &Program) -> bool {
    p.inputs.iter().any(|(_, i)| matches!(i, Input::Coef(_)))
}

fn writes(p: &Program, a: OutArr) -> bool {
    p.outputs.iter().any(|((arr, _), _)| *arr == a)
}

/// Fixed-size views of the slices a kernel reads and writes.
struct Views<'a> {
    p: &'a Program,
    n: usize,
    nc: usize,
    inputs: String,
    outputs: String,
}

impl<'a> Views<'a> {
    fn new(p: &'a Program, n: usize, nc: usize) -> Self {
        Self {
            p,
            n,
            nc,
            inputs: String::new(),
            outputs: String::new(),
        }
    }
    fn coef(&mut self) {
        if reads_coef(self.p) {
            let nc = self.nc;
            writeln!(self.inputs, "let c: &[f64; {nc}] = c.try_into().expect(\"the coefficient array has {nc} entries\");").unwrap();
        }
    }
    fn input(&mut self, name: &str, src: &str, f: impl Fn(Sym) -> bool) {
        if reads(self.p, f) {
            let n = self.n;
            writeln!(
                self.inputs,
                "let {name}: &[f64; {n}] = {src}.try_into().expect(\"`{name}` has {n} entries\");"
            )
            .unwrap();
        }
    }
    fn scalar(&mut self, name: &str, src: &str, f: impl Fn(Sym) -> bool) {
        if reads(self.p, f) && name != src {
            writeln!(self.inputs, "let {name} = {src};").unwrap();
        }
    }
    fn output(&mut self, a: OutArr, src: &str, len: usize) {
        if writes(self.p, a) {
            let name = out_name(a);
            writeln!(self.outputs, "let {name}: &mut [f64; {len}] = (&mut *{src}).try_into().expect(\"`{name}` has {len} entries\");").unwrap();
        }
    }
    /// The outputs of `mass` (`n` coordinates).
    fn mass_outputs(&mut self, n: usize) {
        self.output(OutArr::St, "out.s_t", 3);
        self.output(OutArr::Mee, "out.m_ee", n * n);
        self.output(OutArr::MeFrame, "out.m_e_frame", n * 6);
        self.output(OutArr::MrefE, "out.m_ref_e", 6 * n);
        self.output(OutArr::MrefFrame, "out.m_ref_frame", 36);
    }
    /// The outputs of `residual`.
    fn residual_outputs(&mut self, n: usize) {
        self.output(OutArr::Fr, "out.f_r", 3);
        self.output(OutArr::Fth, "out.f_th", 3);
        self.output(OutArr::Fe, "out.f_e", n);
    }
    /// `bp`, `gp` and the outputs of `tangent`.
    fn tangent_outputs(&mut self, n: usize) {
        self.derivative_weights();
        self.residual_outputs(n);
        self.output(OutArr::Kee, "out.k_ee", n * n);
        self.output(OutArr::DeFrame, "out.d_e_frame", n * 9);
        self.output(OutArr::KrefE, "out.k_ref_e", 6 * n);
        self.output(OutArr::DrefFrame, "out.d_ref_frame", 54);
    }
    /// `bp` and `gp`, the weights of `∂/∂q̈` and `∂/∂q̇` in a tangent.
    fn derivative_weights(&mut self) {
        self.scalar("bp", "bp", |s| s == Sym::Bp);
        self.scalar("gp", "gp", |s| s == Sym::Gp);
    }
    fn kernel_inputs(&mut self, via: &str) {
        self.scalar("x0", &format!("{via}x0"), |s| s == Sym::X0);
        self.input("q", &format!("{via}q"), |s| matches!(s, Sym::Q(_)));
        self.input("qd", &format!("{via}qd"), |s| matches!(s, Sym::Qd(_)));
        self.input("qdd", &format!("{via}qdd"), |s| matches!(s, Sym::Qdd(_)));
        self.scalar("frame", &format!("{via}frame"), |s| {
            matches!(s, Sym::Frame(_))
        });
    }
}

/// Whether emitted text is formatted (files) or left as plain tokens for
/// the compiler (the attribute's expansion).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Layout {
    Pretty,
    Tokens,
}

/// `text` (items, or statements at `depth` 2) formatted by prettyplease at
/// the indentation it has in the file: `depth` 0 top-level items, 1 items of
/// an impl, 2 statements of a function in an impl, 3 statements of a
/// function nested in one.
fn pretty(text: &str, depth: usize) -> String {
    if text.trim().is_empty() {
        return String::new();
    }
    let wrapped = match depth {
        0 => text.to_string(),
        1 => format!("impl __Emit {{\n{text}\n}}"),
        2 => format!("impl __Emit {{\nfn __emit() {{\n{text}\n}}\n}}"),
        _ => format!("impl __Emit {{\nfn __emit() {{\nfn __inner() {{\n{text}\n}}\n}}\n}}"),
    };
    let file = syn::parse_file(&wrapped)
        .unwrap_or_else(|e| panic!("ffr-codegen produced invalid Rust (a bug): {e}\n{text}"));
    let out = prettyplease::unparse(&file);
    let lines: Vec<&str> = out.lines().collect();
    let inner = &lines[depth..lines.len() - depth];
    let mut s = inner.join("\n");
    s.push('\n');
    s
}

/// `signature {`, formatted as in an impl.
fn open_fn(out: &mut String, layout: Layout, signature: &str) {
    match layout {
        Layout::Pretty => {
            let sig = pretty(&format!("{signature} {{}}"), 1);
            let sig = sig
                .trim_end()
                .strip_suffix("{}")
                .expect("prettyplease prints an empty body as {}");
            writeln!(out, "{sig}{{").unwrap();
        }
        Layout::Tokens => writeln!(out, "{signature} {{").unwrap(),
    }
}

/// One kernel function: the operation count, the signature and the body in
/// sections (`// Inputs`, `// Intermediate terms (N)`, `// Outputs (N)`),
/// `tail` after the outputs (a returned value).
fn kernel_fn(
    out: &mut String,
    layout: Layout,
    p: &Program,
    signature: &str,
    views: &Views,
    tail: &str,
) {
    let sec = sections(p, views);
    let (ind, body) = match layout {
        Layout::Pretty => ("    ", "        "),
        Layout::Tokens => ("", ""),
    };
    writeln!(out, "{ind}// operations: {}", p.ops()).unwrap();
    open_fn(out, layout, signature);
    let fmt = |t: &str| match layout {
        Layout::Pretty => pretty(t, 2),
        Layout::Tokens => t.to_string(),
    };
    writeln!(out, "{body}// Inputs").unwrap();
    out.push_str(&fmt(&sec.inputs));
    writeln!(out, "{body}// Intermediate terms ({})", p.stmts.len()).unwrap();
    out.push_str(&fmt(&sec.intermediates));
    writeln!(out, "{body}// Outputs ({})", p.outputs.len()).unwrap();
    out.push_str(&fmt(&(sec.outputs + tail)));
    writeln!(out, "{ind}}}").unwrap();
}

/// `scalar_force_batch` from the program of `scalar_force` (`p`, `nz`
/// scalars, `nc` coefficients): the program as a nested `#[inline(always)]`
/// function of one element, called in a loop over the elements whose
/// scalars (forces) are `nz` contiguous columns of `z_all` (`g_all`). With
/// shared coefficients (`c_stride = 0`) their reads are invariant in the
/// loop, so the compiler hoists them and may evaluate several elements per
/// instruction.
fn scalar_batch_fn(out: &mut String, layout: Layout, p: &Program, nz: usize, nc: usize) {
    let sec = sections(p, &Views::new(p, nz, nc));
    let (ind, body, inner) = match layout {
        Layout::Pretty => ("    ", "        ", "            "),
        Layout::Tokens => ("", "", ""),
    };
    let fmt = |t: &str, depth: usize| match layout {
        Layout::Pretty => pretty(t, depth),
        Layout::Tokens => t.to_string(),
    };
    writeln!(out, "{ind}// operations: {} per element", p.ops()).unwrap();
    let signature = "fn scalar_force_batch(&self, c: &[f64], c_stride: usize, z_all: &[f64], g_all: &mut [f64], elements: usize, _scratch: &mut [f64]) -> bool";
    open_fn(out, layout, signature);
    writeln!(out, "{body}// One element: the program of `scalar_force`.").unwrap();
    writeln!(out, "{body}#[inline(always)]").unwrap();
    writeln!(
        out,
        "{body}fn element(c: &[f64; {nc}], q: &[f64; {nz}], g: &mut [f64; {nz}]) {{"
    )
    .unwrap();
    writeln!(out, "{inner}// Inputs").unwrap();
    out.push_str(&fmt(&sec.inputs, 3));
    writeln!(out, "{inner}// Intermediate terms ({})", p.stmts.len()).unwrap();
    out.push_str(&fmt(&sec.intermediates, 3));
    writeln!(out, "{inner}// Outputs ({})", p.outputs.len()).unwrap();
    out.push_str(&fmt(&sec.outputs, 3));
    writeln!(out, "{body}}}").unwrap();
    // The loop: sizes checked, then the columns as slices of `elements`
    // entries each (no bounds checks left in the loop).
    let mut t = String::new();
    writeln!(
        t,
        "if z_all.len() != {nz} * elements || g_all.len() != {nz} * elements {{ return false; }}"
    )
    .unwrap();
    writeln!(t, "if elements == 0 {{ return true; }}").unwrap();
    writeln!(t, "let fits = (elements - 1).checked_mul(c_stride).and_then(|x| x.checked_add({nc})).is_some_and(|len| len <= c.len());").unwrap();
    writeln!(
        t,
        "if !fits || (c_stride != 0 && c_stride < {nc}) {{ return false; }}"
    )
    .unwrap();
    for j in 0..nz {
        let rest = if j + 1 < nz { "z_all" } else { "_" };
        writeln!(t, "let (z{j}, {rest}) = z_all.split_at(elements);").unwrap();
    }
    for j in 0..nz {
        let rest = if j + 1 < nz { "g_all" } else { "_" };
        writeln!(t, "let (g{j}, {rest}) = g_all.split_at_mut(elements);").unwrap();
    }
    let zs = (0..nz)
        .map(|j| format!("z{j}[e]"))
        .collect::<Vec<_>>()
        .join(", ");
    let mut each = String::new();
    writeln!(each, "let mut g = [0.0; {nz}];").unwrap();
    writeln!(each, "element(c, &[{zs}], &mut g);").unwrap();
    for j in 0..nz {
        writeln!(each, "g{j}[e] = g[{j}];").unwrap();
    }
    writeln!(t, "if c_stride == 0 {{").unwrap();
    writeln!(t, "let c: &[f64; {nc}] = c[..{nc}].try_into().expect(\"the coefficient array has {nc} entries\");").unwrap();
    writeln!(t, "for e in 0..elements {{\n{each}}}").unwrap();
    writeln!(t, "}} else {{").unwrap();
    writeln!(t, "for e in 0..elements {{").unwrap();
    writeln!(t, "let c: &[f64; {nc}] = c[e * c_stride..e * c_stride + {nc}].try_into().expect(\"the coefficient array has {nc} entries\");").unwrap();
    writeln!(t, "{each}}}").unwrap();
    writeln!(t, "}}").unwrap();
    writeln!(t, "true").unwrap();
    out.push_str(&fmt(&t, 2));
    writeln!(out, "{ind}}}").unwrap();
}

/// The Rust expression of `o` (a constant of the runtime's `spec` module).
fn options_expr(o: &ffr_spec::KernelOptions, rt: &str) -> String {
    let scene = match o.scene {
        Some(d) => format!("::core::option::Option::Some({rt}::spec::SceneDim::{d:?})"),
        None => "::core::option::Option::None".into(),
    };
    format!(
        "{rt}::spec::KernelOptions {{ formalism: {rt}::spec::Formalism::{:?}, stiffening: {rt}::spec::Stiffening::{:?}, scene: {scene}, frame: {rt}::spec::FrameModel::{:?} }}",
        o.formalism, o.stiffening, o.frame
    )
}

fn kernel_impl(set: &KernelSet, kt: &str, rt: &str, layout: Layout) -> String {
    let n = set.n();
    let nc = set.coefficients.len();
    let m = set.model();
    let mut s = String::new();
    let coords = m
        .shape
        .coordinates
        .iter()
        .map(|c| {
            format!(
                "{rt}::spec::ElementCoordinate {{ node: {}, kind: {rt}::spec::Kind::{} }}",
                c.node,
                match c.kind.name() {
                    "ux" => "Ux",
                    "uy" => "Uy",
                    "uz" => "Uz",
                    "rx" => "Rx",
                    "ry" => "Ry",
                    _ => "Rz",
                }
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    let params = set
        .params_used()
        .iter()
        .map(|p| format!("{rt}::spec::Param::{p:?}"))
        .collect::<Vec<_>>()
        .join(", ");
    let mut top = String::new();
    writeln!(
        top,
        "#[doc = \" Element kernels generated by ffr-codegen from {}.\"]",
        describe(set).replace('\\', "\\\\").replace('"', "\\\"")
    )
    .unwrap();
    writeln!(
        top,
        "#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]\npub struct {kt};"
    )
    .unwrap();
    let info = format!(
        "fn info(&self) -> &{rt}::KernelInfo {{ const INFO: {rt}::KernelInfo = {rt}::KernelInfo {{ shape: ::std::borrow::Cow::Borrowed({:?}), dim: {}, n_local: {n}, coordinates: ::std::borrow::Cow::Borrowed(&[{coords}]), options: {}, n_coefficients: {nc}, params_used: ::std::borrow::Cow::Borrowed(&[{params}]), scratch: 0 }}; &INFO }}",
        comment_text(&m.shape.name),
        m.shape.dimension,
        options_expr(&m.resolved_options(), rt),
    );
    let (top, info) = match layout {
        Layout::Pretty => (pretty(&top, 0), pretty(&info, 1)),
        Layout::Tokens => (top, info + "\n"),
    };
    s.push_str(&top);
    writeln!(
        s,
        "#[allow(clippy::all, clippy::pedantic, unused_variables)]\nimpl {rt}::ElementKernels for {kt} {{"
    )
    .unwrap();
    s.push_str(&info);
    for kind in KernelKind::ALL {
        let Some(p) = set.program(kind) else {
            continue;
        };
        let mut v = Views::new(p, n, nc);
        // `elastic_scalars` returns how many scalars it writes.
        let scalar_count = format!(
            "{}\n",
            set.polys
                .energy_form
                .as_ref()
                .map_or(0, |e| e.scalars.len())
        );
        let (signature, tail) = match kind {
            KernelKind::Coefficients => {
                writeln!(v.outputs, "let c: &mut [f64; {nc}] = c.try_into().expect(\"the coefficient array has {nc} entries\");").unwrap();
                (format!("fn coefficients(&self, params: &{rt}::spec::Params, l: f64, c: &mut [f64])"), "")
            }
            KernelKind::SectionCoefficients => {
                let nm = set.section_moments.len();
                writeln!(v.inputs, "let mu: &[f64; {nm}] = mu.try_into().expect(\"the moment array has {nm} entries\");").unwrap();
                writeln!(v.outputs, "let c: &mut [f64; {nc}] = c.try_into().expect(\"the coefficient array has {nc} entries\");").unwrap();
                let list = set
                    .section_moments
                    .iter()
                    .map(|(p, k)| format!("({rt}::spec::SectionProp::{p:?}, {k})"))
                    .collect::<Vec<_>>()
                    .join(", ");
                let moments = format!(
                    "fn section_moments(&self) -> &[({rt}::spec::SectionProp, u8)] {{ &[{list}] }}"
                );
                match layout {
                    Layout::Pretty => s.push_str(&pretty(&moments, 1)),
                    Layout::Tokens => writeln!(s, "{moments}").unwrap(),
                }
                (
                    "fn section_coefficients(&self, mu: &[f64], l: f64, c: &mut [f64])".to_string(),
                    "",
                )
            }
            KernelKind::Mass => {
                v.coef();
                v.scalar("x0", "x0", |s| s == Sym::X0);
                v.input("q", "q", |s| matches!(s, Sym::Q(_)));
                v.mass_outputs(n);
                (format!("fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut {rt}::MassOut, _scratch: &mut [f64])"), "")
            }
            KernelKind::Residual => {
                v.coef();
                v.kernel_inputs("x.");
                v.residual_outputs(n);
                (format!("fn residual(&self, c: &[f64], x: &{rt}::KernelInput, out: &mut {rt}::ResidualOut, _scratch: &mut [f64])"), "")
            }
            KernelKind::Tangent => {
                v.coef();
                v.kernel_inputs("x.");
                v.tangent_outputs(n);
                (format!("fn tangent(&self, c: &[f64], x: &{rt}::KernelInput, bp: f64, gp: f64, out: &mut {rt}::TangentOut, _scratch: &mut [f64])"), "")
            }
            KernelKind::ResidualElastic => {
                v.coef();
                v.kernel_inputs("x.");
                v.output(OutArr::Fe, "f_e", n);
                (format!("fn residual_elastic(&self, c: &[f64], x: &{rt}::KernelInput, f_e: &mut [f64], _scratch: &mut [f64])"), "")
            }
            KernelKind::TangentElastic => {
                v.coef();
                v.kernel_inputs("x.");
                v.derivative_weights();
                v.output(OutArr::Fe, "f_e", n);
                v.output(OutArr::Kee, "k_ee", n * n);
                (format!("fn tangent_elastic(&self, c: &[f64], x: &{rt}::KernelInput, bp: f64, gp: f64, f_e: &mut [f64], k_ee: &mut [f64], _scratch: &mut [f64])"), "")
            }
            KernelKind::Energy => {
                v.coef();
                v.input("q", "q", |s| matches!(s, Sym::Q(_)));
                v.outputs.push_str("let energy;\n");
                (
                    "fn energy(&self, c: &[f64], q: &[f64], _scratch: &mut [f64]) -> f64"
                        .to_string(),
                    "energy\n",
                )
            }
            KernelKind::ElementInvariants => {
                let (_, inv_len) = ffr_spec::invariant_layout(n);
                v.coef();
                v.scalar("x0", "x0", |s| s == Sym::X0);
                v.output(OutArr::Inv, "out", inv_len);
                ("fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], _scratch: &mut [f64])".to_string(), "")
            }
            KernelKind::PointShape => {
                v.coef();
                v.scalar("xi", "xi", |s| s == Sym::Xi);
                v.output(OutArr::S, "s", 3 * n);
                v.output(OutArr::Psi, "psi", 3 * n);
                ("fn point_shape(&self, c: &[f64], xi: f64, s: &mut [f64], psi: &mut [f64], _scratch: &mut [f64])".to_string(), "")
            }
            KernelKind::ForceElastic => {
                v.coef();
                v.input("q", "q", |s| matches!(s, Sym::Q(_)));
                v.output(OutArr::Fe, "f_e", n);
                ("fn force_elastic(&self, c: &[f64], q: &[f64], f_e: &mut [f64], _scratch: &mut [f64]) -> bool".to_string(), "true\n")
            }
            KernelKind::ElasticScalars => {
                v.coef();
                v.input("q", "q", |s| matches!(s, Sym::Q(_)));
                v.output(OutArr::Z, "z", n);
                ("fn elastic_scalars(&self, c: &[f64], q: &[f64], z: &mut [f64], _scratch: &mut [f64]) -> usize".to_string(), scalar_count.as_str())
            }
            KernelKind::ScalarForce => {
                v.coef();
                // The scalars are this kernel's inputs: `q{j}` reads `z[j]`.
                v.input("q", "z", |s| matches!(s, Sym::Q(_)));
                v.output(OutArr::Gz, "g", n);
                ("fn scalar_force(&self, c: &[f64], z: &[f64], g: &mut [f64], _scratch: &mut [f64]) -> bool".to_string(), "true\n")
            }
            KernelKind::ScalarTangent => {
                v.coef();
                v.input("q", "z", |s| matches!(s, Sym::Q(_)));
                v.output(OutArr::Gz, "g", n);
                v.output(OutArr::Hz, "h", n * n);
                ("fn scalar_tangent(&self, c: &[f64], z: &[f64], g: &mut [f64], h: &mut [f64], _scratch: &mut [f64]) -> bool".to_string(), "true\n")
            }
        };
        kernel_fn(&mut s, layout, p, &signature, &v, tail);
        if kind == KernelKind::ScalarForce {
            let nz = set
                .polys
                .energy_form
                .as_ref()
                .map_or(0, |e| e.scalars.len());
            // Every scalar read and force written lies within the `nz`
            // scalars (the energy form's); a wider program keeps the
            // per-element default.
            let within = p.inputs.iter().all(|(_, i)| match i {
                Input::Sym(Sym::Q(j)) => (*j as usize) < nz,
                _ => true,
            }) && p.outputs.iter().all(|((_, idx), _)| (*idx as usize) < nz);
            if nz > 0 && within {
                scalar_batch_fn(&mut s, layout, p, nz, nc);
            }
        }
    }
    s.push_str("}\n");
    s
}

/// The kernel type `kt` (unformatted items).
pub fn kernel_items(set: &KernelSet, kt: &str, runtime_path: &str) -> String {
    kernel_impl(set, kt, runtime_path, Layout::Tokens)
}

/// The kernels plus, for a body with a fixed mesh, the `CompiledBody`
/// implementation for `opts.type_name` (and the parameter struct itself if
/// `opts.define_struct`), unformatted.
pub fn body_items(set: &KernelSet, spec: &BodySpec, opts: &EmitOptions) -> String {
    body_text(set, spec, opts, Layout::Tokens)
}

fn body_text(set: &KernelSet, spec: &BodySpec, opts: &EmitOptions, layout: Layout) -> String {
    let rt = &opts.runtime_path;
    let ty = &opts.type_name;
    let kt = format!("{ty}Kernels");
    let kernels = kernel_impl(set, &kt, rt, layout);
    let mut s = String::new();
    // A body of a section table reads its sections, not the parameters.
    let used = if opts.sections.is_some() {
        Vec::new()
    } else {
        set.params_used()
    };
    if opts.define_struct {
        writeln!(
            s,
            "#[doc = \" Parameters of an FFR body generated by ffr-codegen from {}, {} elements, {} reference. SI units.\"]",
            describe(set).replace('\\', "\\\\").replace('"', "\\\""),
            spec.elements,
            spec.reference
        )
        .unwrap();
        writeln!(
            s,
            "#[derive(Clone, Copy, Debug, Default, PartialEq)]\npub struct {ty} {{"
        )
        .unwrap();
        for f in Param::FIELDS {
            let note = if used.contains(&f) {
                ""
            } else {
                " (not used by this shape)"
            };
            writeln!(
                s,
                "#[doc = \" {}{note}.\"]\npub {}: f64,",
                f.doc(),
                f.field()
            )
            .unwrap();
        }
        writeln!(s, "}}").unwrap();
        writeln!(s, "impl ::core::convert::From<{rt}::spec::Params> for {ty} {{\nfn from(p: {rt}::spec::Params) -> Self {{\nSelf {{ {} }}\n}}\n}}",
            Param::FIELDS.iter().map(|f| format!("{0}: p.{0}", f.field())).collect::<Vec<_>>().join(", ")).unwrap();
    }
    let dofs = spec
        .dofs()
        .iter()
        .map(|d| format!("\"{d}\""))
        .collect::<Vec<_>>()
        .join(", ");
    let fields = Param::FIELDS
        .iter()
        .map(|f| {
            if used.contains(f) {
                format!("{0}: self.{0}", f.field())
            } else if let (Param::Length, Some(st)) = (f, &opts.sections) {
                // A section table's body: its length is the last station's x.
                format!("length: {}", lit(st.last().map_or(0.0, |s| s.x)))
            } else {
                format!("{}: 0.0", f.field())
            }
        })
        .collect::<Vec<_>>()
        .join(", ");
    let sections = match &opts.sections {
        None => String::new(),
        Some(st) => {
            let rows: Vec<String> = st
                .iter()
                .map(|s| {
                    format!(
                        "{rt}::spec::scene::Station {{ x: {}, mass: {}, ea: {}, ei_y: {}, ei_z: {}, gj: {}, rho_iy: {}, rho_iz: {}, rho_j: {}, twist: {} }}",
                        lit(s.x), lit(s.mass), lit(s.ea), lit(s.ei_y), lit(s.ei_z), lit(s.gj),
                        lit(s.rho_iy), lit(s.rho_iz), lit(s.rho_j), lit(s.twist)
                    )
                })
                .collect();
            format!(
                "\nconst SECTIONS: ::core::option::Option<&'static [{rt}::spec::scene::Station]> = ::core::option::Option::Some(&[{}]);",
                rows.join(", ")
            )
        }
    };
    writeln!(
        s,
        "impl {rt}::CompiledBody for {ty} {{\ntype Kernels = {kt};\nconst ELEMENTS: usize = {};\nconst REFERENCE: {rt}::spec::Reference = {rt}::spec::Reference::{:?};\nconst NF: usize = {};\nconst DIM: usize = {};\nconst DOFS: &'static [&'static str] = &[{dofs}];\nfn params(&self) -> {rt}::spec::Params {{ {rt}::spec::Params {{ {fields} }} }}{sections}\n}}",
        spec.elements,
        spec.reference,
        spec.nf(),
        spec.shape.dimension
    )
    .unwrap();
    match layout {
        Layout::Pretty => kernels + &pretty(&s, 0),
        Layout::Tokens => kernels + &s,
    }
}

/// The header of every generated file: the banner, what the file defines,
/// then for each kernel set (under its title, if any) its input, element
/// coordinates, coefficients, operation counts and what its model leaves
/// out, then `extra` lines.
fn header(what: &str, sets: &[(Option<String>, &KernelSet)], extra: &[String]) -> String {
    let mut h = String::new();
    writeln!(
        h,
        "// @generated by ffr-codegen {} — do not edit.",
        env!("CARGO_PKG_VERSION")
    )
    .unwrap();
    writeln!(h, "// {what}").unwrap();
    for (title, set) in sets {
        let ind = match title {
            Some(t) => {
                writeln!(h, "// {t}").unwrap();
                "  "
            }
            None => "",
        };
        writeln!(h, "// {ind}Input: {}.", describe(set)).unwrap();
        let coords: Vec<String> = set
            .model()
            .shape
            .coordinates
            .iter()
            .map(|c| format!("{}_{}", c.kind, c.node))
            .collect();
        writeln!(
            h,
            "// {ind}Element coordinates ({}): {}.",
            coords.len(),
            coords.join(" ")
        )
        .unwrap();
        writeln!(
            h,
            "// {ind}Coefficients: {} (computed once per body).",
            set.coefficients.len()
        )
        .unwrap();
        if !set.section_moments.is_empty() {
            let names: Vec<String> = set
                .section_moments
                .iter()
                .map(|(p, k)| format!("mu_{}_{k}", p.name()))
                .collect();
            writeln!(
                h,
                "// {ind}Varying sections: the coefficients of an element from its {} moments ({}).",
                names.len(),
                names.join(" ")
            )
            .unwrap();
        }
        writeln!(h, "// {ind}Operations per call:").unwrap();
        writeln!(
            h,
            "// {ind}  {:<20} {}",
            "coefficients",
            set.coefficient_program.ops()
        )
        .unwrap();
        if let Some(p) = &set.section_coefficient_program {
            writeln!(h, "// {ind}  {:<20} {}", "section_coefficients", p.ops()).unwrap();
        }
        for (name, p) in set.programs() {
            writeln!(h, "// {ind}  {name:<20} {}", p.ops()).unwrap();
        }
        let omitted = omissions(set);
        if !omitted.is_empty() {
            writeln!(h, "// {ind}Left out:").unwrap();
            for o in omitted {
                writeln!(h, "// {ind}  - {o}").unwrap();
            }
        }
    }
    for line in extra {
        writeln!(h, "// {line}").unwrap();
    }
    h.push('\n');
    h
}

/// A complete, formatted file with the kernel type `kernels_type`.
pub fn emit_kernels_file(set: &KernelSet, kernels_type: &str, runtime_path: &str) -> String {
    header(
        &format!("Element kernels `{kernels_type}`."),
        &[(None, set)],
        &[],
    ) + &kernel_impl(set, kernels_type, runtime_path, Layout::Pretty)
}

/// A complete, formatted file for one body with a fixed mesh.
pub fn emit_body_file(set: &KernelSet, spec: &BodySpec, opts: &EmitOptions) -> String {
    body_file(set, spec, opts, &[])
}

/// [`emit_body_file`] with `more` header lines after the coordinates.
fn body_file(set: &KernelSet, spec: &BodySpec, opts: &EmitOptions, more: &[String]) -> String {
    let dofs: Vec<String> = spec.dofs().iter().map(|d| d.to_string()).collect();
    let mut extra = vec!["Elastic coordinates, in this order:".to_string()];
    extra.extend(
        dofs.chunks(12)
            .map(|chunk| format!("  {}", chunk.join(" "))),
    );
    extra.extend(more.iter().cloned());
    let h = header(
        &format!(
            "Body `{}`: {} element{}, {} reference, {} elastic coordinates.",
            opts.type_name,
            spec.elements,
            if spec.elements == 1 { "" } else { "s" },
            spec.reference,
            dofs.len()
        ),
        &[(None, set)],
        &extra,
    );
    h + &body_text(set, spec, opts, Layout::Pretty)
}

/// A scene file and the kernels of its flexible bodies, ready to emit
/// (read, checked and generated by [`crate::builder::generate_scene`]).
#[derive(Clone, Debug)]
pub struct SceneKernels<'a> {
    /// The file as it was named (headers, errors).
    pub origin: &'a str,
    /// Its text (named in the banner by its hash).
    pub text: &'a str,
    /// The scene, resolved (carried by the generated type as data).
    pub spec: &'a ffr_spec::scene::SceneSpec,
    /// Each flexible body's name and kernel set, in body-name order.
    pub bodies: Vec<(String, KernelSet)>,
    /// The outboard segments of each body run as segments (`segments = N`).
    pub segments: Vec<SceneSegments>,
    /// The modal reductions made when the scene is compiled, in the order
    /// their match arms are tried.
    pub modal: Vec<SceneModal>,
}

/// The outboard segments `NAME[2]` … `NAME[N]` of a body run as segments:
/// they share one kernel set (equal segments, clamped, free frames).
#[derive(Clone, Debug)]
pub struct SceneSegments {
    /// The body's name (its root segment's).
    pub body: String,
    /// The outboard segments' names, `NAME[2]` … `NAME[N]`.
    pub names: Vec<String>,
    /// Their kernels (type [`scene_segment_kernels_type`]), or `None`: the
    /// body's own (its frame is free as theirs are).
    pub kernels: Option<KernelSet>,
}

/// A modal reduction made when the scene is compiled, served to the bodies
/// named `names` (with `elements` elements, when given: the whole body of a
/// body run as segments has the root segment's name).
#[derive(Clone, Debug)]
pub struct SceneModal {
    /// The body whose kernel type holds the constant.
    pub body: String,
    /// The name of the constant (`MODAL` for the body's own reduction,
    /// `MODAL_SEGMENT_k` for its segment `k`'s).
    pub konst: String,
    /// The names of the `FlexSpec`s it is for.
    pub names: Vec<String>,
    /// Only for a `FlexSpec` of this many elements, or `None`: any.
    pub elements: Option<usize>,
    /// The `ModalConsts` expression ([`modal_consts`]).
    pub consts: String,
    /// Its generated inertia kernels when it has at most
    /// `MAX_GENERATED_MODES` modes: the type's name and its items.
    pub kernels: Option<(String, String)>,
}

/// The kernels of the outboard segments of body `body` of the compiled
/// scene `type_name`, when they differ from the body's (not ending in
/// `Kernels`, so no body's name can give it).
#[cfg(feature = "scene")]
pub fn scene_segment_kernels_type(type_name: &str, body: &str) -> String {
    format!(
        "{type_name}{}KernelsOutboard",
        crate::scene::body_type_name(body)
    )
}

/// The generated inertia kernels of segment `k` (1-based, as in `NAME[k]`)
/// of body `body` of the compiled scene `type_name`.
#[cfg(feature = "scene")]
pub fn scene_segment_modal_kernels_type(type_name: &str, body: &str, k: usize) -> String {
    format!(
        "{type_name}{}ModalKernelsSegment{k}",
        crate::scene::body_type_name(body)
    )
}

/// The name of the generated inertia kernels of body `body` of the compiled
/// scene `type_name`.
#[cfg(feature = "scene")]
pub fn scene_modal_kernels_type(type_name: &str, body: &str) -> String {
    format!(
        "{type_name}{}ModalKernels",
        crate::scene::body_type_name(body)
    )
}

/// The generated inertia kernels `kt` of `what` (a body or a segment of
/// the compiled scene `type_name`; formatted items).
#[cfg(all(feature = "scene", feature = "modal"))]
pub fn scene_modal_kernel_items(
    set: &crate::modal::ModalKernelSet,
    type_name: &str,
    what: &str,
    kt: &str,
    runtime_path: &str,
) -> String {
    let what = format!(
        "{} of `{type_name}`",
        comment_text(what).replace('"', "\\\"")
    );
    modal_kernel_impl(set, kt, &what, runtime_path, Layout::Pretty)
}

/// The compiled form of a scene file: the specialized kernels of each of its
/// flexible bodies (`{Type}{Body}Kernels`), a kernel provider and the scene
/// type `type_name` whose `spec()` is the resolved scene as data and whose
/// `load()` builds it with these kernels (`ffr::scene::build`): nothing is
/// parsed at start-up. The runtime path must end in `::runtime` (its parent
/// is the `ffr` crate).
#[cfg(feature = "scene")]
pub fn emit_scene_file(
    scene: &SceneKernels,
    type_name: &str,
    runtime_path: &str,
) -> Result<String, crate::error::Error> {
    let root = runtime_path.strip_suffix("::runtime").ok_or_else(|| {
        crate::error::Error::Body(format!(
            "a compiled scene needs the runtime path of the `ffr` crate (`…::runtime`), found `{runtime_path}`"
        ))
    })?;
    let (origin, text) = (scene.origin, scene.text);
    let mut kernels = String::new();
    let mut items = String::new();
    let mut titled = Vec::new();
    let mut arms = String::new();
    let mut modal_arms = String::new();
    let mut modal_kernel_arms = String::new();
    let quoted = |names: &[String]| {
        names
            .iter()
            .map(|n| format!("{n:?}"))
            .collect::<Vec<_>>()
            .join(" | ")
    };
    let kernels_arm = |arms: &mut String, names: &[String], kt: &str| {
        writeln!(
            arms,
            "{} => ::core::result::Result::Ok((::std::boxed::Box::new({kt}), \"compiled (scene)\")),",
            quoted(names)
        )
        .unwrap();
    };
    for (name, set) in &scene.bodies {
        let body_type = crate::scene::body_type_name(name);
        let kt = format!("{type_name}{body_type}Kernels");
        titled.push((
            Some(format!("Body `{}` → `{kt}`:", comment_text(name))),
            set,
        ));
        kernels.push_str(&kernel_impl(set, &kt, runtime_path, Layout::Pretty));
        // The body, and its outboard segments when they run its kernels.
        let mut names = vec![name.clone()];
        for s in scene.segments.iter().filter(|s| &s.body == name) {
            if s.kernels.is_none() {
                names.extend(s.names.iter().cloned());
            }
        }
        kernels_arm(&mut arms, &names, &kt);
        for m in scene.modal.iter().filter(|m| &m.body == name) {
            let what = if m.names.len() == 1 {
                format!("Body `{}`", comment_text(&m.names[0]))
            } else {
                format!(
                    "Bodies {}",
                    m.names
                        .iter()
                        .map(|n| format!("`{}`", comment_text(n)))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            };
            let what = match m.elements {
                Some(e) => format!("{what} ({e} elements)"),
                None => what,
            };
            writeln!(
                items,
                "impl {kt} {{\n#[doc = \" {} reduced when the scene was compiled: the basis and the projected invariants.\"]\n#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal)]\npub const {}: {runtime_path}::ModalConsts = {};\n}}",
                what.replace('"', "\\\""),
                m.konst,
                m.consts
            )
            .unwrap();
            let guard = match m.elements {
                Some(e) => format!(" if spec.elements == {e}"),
                None => String::new(),
            };
            writeln!(
                modal_arms,
                "{}{guard} => ::core::option::Option::Some(&{kt}::{}),",
                quoted(&m.names),
                m.konst
            )
            .unwrap();
            if let Some((mkt, text)) = &m.kernels {
                kernels.push_str(text);
                writeln!(
                    modal_kernel_arms,
                    "{}{guard} => ::core::option::Option::Some(::std::boxed::Box::new({mkt})),",
                    quoted(&m.names),
                )
                .unwrap();
            }
        }
    }
    // The outboard segments' own kernels (free frames where the body's is
    // prescribed).
    for s in &scene.segments {
        let Some(set) = &s.kernels else { continue };
        let kt = scene_segment_kernels_type(type_name, &s.body);
        titled.push((
            Some(format!(
                "Segments {} of body `{}` → `{kt}`:",
                s.names
                    .iter()
                    .map(|n| format!("`{}`", comment_text(n)))
                    .collect::<Vec<_>>()
                    .join(", "),
                comment_text(&s.body)
            )),
            set,
        ));
        kernels.push_str(&kernel_impl(set, &kt, runtime_path, Layout::Pretty));
        kernels_arm(&mut arms, &s.names, &kt);
    }
    let modal_fn = if modal_arms.is_empty() {
        String::new()
    } else {
        format!(
            "\nfn modal(&self, spec: &{root}::scene::FlexSpec) -> ::core::option::Option<&'static {runtime_path}::ModalConsts> {{\nmatch spec.name.as_str() {{\n{modal_arms}_ => ::core::option::Option::None,\n}}\n}}"
        )
    };
    let modal_kernels_fn = if modal_kernel_arms.is_empty() {
        String::new()
    } else {
        format!(
            "\nfn modal_kernels(&self, spec: &{root}::scene::FlexSpec) -> ::core::option::Option<::std::boxed::Box<dyn {runtime_path}::ModalKernels>> {{\nmatch spec.name.as_str() {{\n{modal_kernel_arms}_ => ::core::option::Option::None,\n}}\n}}"
        )
    };
    let n = scene.bodies.len();
    let what = format!(
        "Scene `{}` compiled as `{type_name}` (fnv1a {:016x}): {n} flexible bod{}.",
        comment_text(origin),
        crate::shape::fnv1a(text),
        if n == 1 { "y" } else { "ies" }
    );
    writeln!(
        items,
        "#[doc = \" The element kernels of the scene's flexible bodies.\"]\n#[derive(Clone, Copy, Debug, Default)]\npub struct {type_name}Kernels;"
    )
    .unwrap();
    writeln!(
        items,
        "impl {root}::scene::KernelProvider for {type_name}Kernels {{\nfn kernels(&self, spec: &{root}::scene::FlexSpec) -> ::core::result::Result<(::std::boxed::Box<dyn {runtime_path}::ElementKernels>, &'static str), {root}::Error> {{\nmatch spec.name.as_str() {{\n{arms}other => ::core::result::Result::Err({root}::Error::Invalid(::std::format!(\"no compiled kernels for body `{{other}}`\"))),\n}}\n}}{modal_fn}{modal_kernels_fn}\n}}"
    )
    .unwrap();
    writeln!(
        items,
        "#[doc = \" The scene `{}`, compiled: its flexible bodies run the specialized kernels above.\"]\n#[derive(Clone, Copy, Debug, Default)]\npub struct {type_name};\nimpl {type_name} {{\n#[doc = \" The scene file as it was named.\"]\npub const ORIGIN: &'static str = {:?};\n#[doc = \" The scene, resolved when it was compiled (checked, names looked up, defaults filled in).\"]\n#[doc = \" Its numbers are the file's, written to read back to the same bits.\"]\n#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal)]\npub fn spec() -> {runtime_path}::spec::scene::SceneSpec {{\n{}\n}}\n#[doc = \" Build the scene with the compiled kernels (no file is read or parsed).\"]\npub fn load() -> ::core::result::Result<{root}::scene::Scene, {root}::scene::SceneError> {{\n{root}::scene::build(&Self::spec(), &{type_name}Kernels)\n}}\n}}",
        comment_text(origin).replace('"', "\\\""),
        origin,
        crate::scene::scene_expr(scene.spec, &format!("{runtime_path}::spec"), "Self::ORIGIN"),
    )
    .unwrap();
    Ok(header(&what, &titled, &[]) + &kernels + &pretty(&items, 0))
}

/// The modal body type `{type_name}Modal` of a body file (after
/// [`emit_body_file`]'s `{type_name}` and its kernels): `model`'s numbers as
/// [`ModalConsts`](../../ffr_runtime/modal/struct.ModalConsts.html)
/// (each the shortest literal that reads back to the same bits), the
/// parameters `p` they were computed at, and `body()`, the runtime's modal
/// body over the full body `{type_name}` at `p` (its point shapes place
/// markers; with stiffening its elastic kernels give the force at `Φ η`).
/// With at most [`MAX_GENERATED_MODES`](crate::modal::MAX_GENERATED_MODES)
/// modes, also `{type_name}ModalKernels`, the generated kernels of its
/// inertia equations in a `scene` ([`crate::modal::generate_modal_kernels`]),
/// which `body()` uses. Unformatted; an error if a number is not finite.
#[cfg(feature = "modal")]
pub fn modal_items(
    model: &crate::modal::ModalModel,
    p: &ffr_spec::Params,
    description: &str,
    type_name: &str,
    runtime_path: &str,
    scene: ffr_spec::SceneDim,
) -> Result<String, crate::Error> {
    let kernels = crate::modal::generate_modal_kernels(model, scene)?;
    let (items, kernel_text) = modal_text(
        model,
        p,
        description,
        type_name,
        runtime_path,
        kernels.as_ref(),
        Layout::Tokens,
    )?;
    Ok(items + &kernel_text)
}

/// The generated kernels `kt` of a modal body (`ModalKernels`), each
/// function with its operation count and its sections.
#[cfg(feature = "modal")]
fn modal_kernel_impl(
    set: &crate::modal::ModalKernelSet,
    kt: &str,
    what: &str,
    rt: &str,
    layout: Layout,
) -> String {
    let k = set.modes;
    let mut top = String::new();
    writeln!(
        top,
        "#[doc = \" The inertia equations of {what} ({k} modes, {} scene) generated by ffr-codegen: the projected invariants as constants{}.\"]\n#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]\npub struct {kt};",
        if set.scene == ffr_spec::SceneDim::Planar { "planar" } else { "spatial" },
        if set.linear_elastic { ", with the linear elastic force" } else { "; the runtime adds the elastic force" },
    )
    .unwrap();
    let info = format!(
        "fn modes(&self) -> usize {{ {k} }}\nfn scene_dim(&self) -> usize {{ {} }}\nfn linear_elastic(&self) -> bool {{ {} }}\n",
        set.scene.dim(),
        set.linear_elastic
    );
    let mut s = match layout {
        Layout::Pretty => pretty(&top, 0),
        Layout::Tokens => top,
    };
    writeln!(
        s,
        "#[allow(clippy::all, clippy::pedantic, unused_variables)]\nimpl {rt}::ModalKernels for {kt} {{"
    )
    .unwrap();
    match layout {
        Layout::Pretty => s.push_str(&pretty(&info, 1)),
        Layout::Tokens => s.push_str(&info),
    }
    for (name, p) in set.programs() {
        let mut v = Views::new(p, k, 0);
        let signature = match name {
            "mass" => {
                v.input("q", "q", |s| matches!(s, Sym::Q(_)));
                v.mass_outputs(k);
                format!("fn mass(&self, q: &[f64], out: &mut {rt}::MassOut, _scratch: &mut [f64])")
            }
            "residual" => {
                v.kernel_inputs("x.");
                v.residual_outputs(k);
                format!("fn residual(&self, x: &{rt}::KernelInput, out: &mut {rt}::ResidualOut, _scratch: &mut [f64])")
            }
            "tangent" => {
                v.kernel_inputs("x.");
                v.tangent_outputs(k);
                format!("fn tangent(&self, x: &{rt}::KernelInput, bp: f64, gp: f64, out: &mut {rt}::TangentOut, _scratch: &mut [f64])")
            }
            "residual_elastic" => {
                v.kernel_inputs("x.");
                v.output(OutArr::Fe, "f_e", k);
                format!("fn residual_elastic(&self, x: &{rt}::KernelInput, f_e: &mut [f64], _scratch: &mut [f64])")
            }
            _ => {
                v.kernel_inputs("x.");
                v.derivative_weights();
                v.output(OutArr::Fe, "f_e", k);
                v.output(OutArr::Kee, "k_ee", k * k);
                format!("fn tangent_elastic(&self, x: &{rt}::KernelInput, bp: f64, gp: f64, f_e: &mut [f64], k_ee: &mut [f64], _scratch: &mut [f64])")
            }
        };
        kernel_fn(&mut s, layout, p, &signature, &v, "");
    }
    s.push_str("}\n");
    s
}

/// The `{type_name}Modal` items (unformatted) and, with `kernels`, the
/// kernel type `{type_name}ModalKernels` in `layout`.
#[cfg(feature = "modal")]
fn modal_text(
    model: &crate::modal::ModalModel,
    p: &ffr_spec::Params,
    description: &str,
    type_name: &str,
    runtime_path: &str,
    kernels: Option<&crate::modal::ModalKernelSet>,
    layout: Layout,
) -> Result<(String, String), crate::Error> {
    let (rt, ty) = (runtime_path, type_name);
    let k = model.len();
    let consts = modal_consts(model, description, rt)?;
    let mut bad = None;
    let params: Vec<String> = p
        .to_array()
        .iter()
        .map(|&x| {
            if !x.is_finite() {
                bad = Some(format!("modal body: a parameter is {x}"));
            }
            lit(x)
        })
        .collect();
    if let Some(msg) = bad {
        return Err(crate::Error::Body(msg));
    }
    let freqs: Vec<String> = model
        .basis
        .frequencies
        .iter()
        .map(|w| format!("{w:.6e}"))
        .collect();
    let esc = |t: &str| t.replace('\\', "\\\\").replace('"', "\\\"");
    let (make, how) = match kernels {
        Some(_) => (
            format!("{rt}::ModalBody::with_kernels(::std::boxed::Box::new(full), Self::CONSTS.data()?, ::std::boxed::Box::new({ty}ModalKernels))"),
            format!(" Its inertia equations run through the generated `{ty}ModalKernels`."),
        ),
        None => (
            format!("{rt}::ModalBody::new(::std::boxed::Box::new(full), Self::CONSTS.data()?)"),
            String::new(),
        ),
    };
    let kernel_text = kernels.map_or(String::new(), |set| {
        modal_kernel_impl(
            set,
            &format!("{ty}ModalKernels"),
            &format!("`{ty}Modal`"),
            rt,
            layout,
        )
    });
    let items = format!(
        "#[doc = \" The body `{ty}` at fixed parameters, reduced: {}.\"]
#[doc = \"\"]
#[doc = \" Normal-mode frequencies (rad/s): {}. The numbers are baked in; `body()` is\"]
#[doc = \" the runtime's modal body over the full body `{ty}` at `params()`.\"]
#[derive(Clone, Copy, Debug, Default)]
pub struct {ty}Modal;
impl {ty}Modal {{
#[doc = \" Number of modes.\"]
pub const MODES: usize = {k};
#[doc = \" The parameters the modes were computed at.\"]
#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal)]
pub fn params() -> {rt}::spec::Params {{ {rt}::spec::Params::from_array([{}]) }}
#[doc = \" The projected invariants, `Φ` and the damping.\"]
#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal)]
pub const CONSTS: {rt}::ModalConsts = {consts};
#[doc = \" The modal body: `CONSTS` over the full body `{ty}` at `params()`.{how}\"]
pub fn body() -> {rt}::Result<{rt}::ModalBody> {{
let full = {rt}::KernelBody::new({ty}Kernels, Self::params(), <{ty} as {rt}::CompiledBody>::ELEMENTS, <{ty} as {rt}::CompiledBody>::REFERENCE)?;
{make}
}}
}}
",
        esc(description),
        freqs.join(", "),
        params.join(", "),
    );
    Ok((items, kernel_text))
}

/// `model` as a `ModalConsts` expression (unformatted; each number the
/// shortest literal that reads back to the same bits); an error if a number
/// is not finite.
#[cfg(feature = "modal")]
pub fn modal_consts(
    model: &crate::modal::ModalModel,
    description: &str,
    rt: &str,
) -> Result<String, crate::Error> {
    use nalgebra::DMatrix;
    let inv = &model.projected;
    let k = model.len();
    let nf = model.basis.phi.nrows();
    let mut bad: Option<String> = None;
    let mut num = |name: &str, x: f64| {
        if !x.is_finite() && bad.is_none() {
            bad = Some(format!("modal body: `{name}` is {x}"));
        }
        lit(x)
    };
    let mut rows = |name: &str, m: &DMatrix<f64>| {
        let v: Vec<String> = (0..m.nrows())
            .flat_map(|i| (0..m.ncols()).map(move |j| (i, j)))
            .map(|(i, j)| num(name, m[(i, j)]))
            .collect();
        format!("&[{}]", v.join(", "))
    };
    let s_bar = rows("s_bar", &inv.s_bar);
    let pair = |f: &mut dyn FnMut(usize, usize) -> String| {
        let r: Vec<String> = (0..3)
            .map(|a| {
                let c: Vec<String> = (0..3).map(|b| f(a, b)).collect();
                format!("[{}]", c.join(", "))
            })
            .collect();
        format!("[{}]", r.join(", "))
    };
    let s_kl = pair(&mut |a, b| rows("s_kl", &inv.s_kl[a][b]));
    let i_kl = pair(&mut |a, b| {
        let v = &inv.i_kl[a][b];
        rows(
            "i_kl",
            &DMatrix::from_column_slice(1, v.len(), v.as_slice()),
        )
    });
    let m_ff = rows("m_ff", &inv.m_ff);
    let k_ff = rows("k_ff", &inv.k_ff);
    let phi = rows("phi", &model.basis.phi);
    let damping = match &model.damping {
        None => "::core::option::Option::None".to_string(),
        Some(d) => format!("::core::option::Option::Some({})", rows("damping", d)),
    };
    let mass = num("mass", inv.mass);
    let s_t0: Vec<String> = (0..3).map(|a| num("s_t0", inv.s_t0[a])).collect();
    let theta = {
        let r: Vec<String> = (0..3)
            .map(|a| {
                let c: Vec<String> = (0..3).map(|b| num("theta", inv.theta[(a, b)])).collect();
                format!("[{}]", c.join(", "))
            })
            .collect();
        format!("[{}]", r.join(", "))
    };
    if let Some(msg) = bad {
        return Err(crate::Error::Body(msg));
    }
    let labels: Vec<String> = model
        .basis
        .labels
        .iter()
        .map(|l| format!("{l:?}"))
        .collect();
    Ok(format!(
        "{rt}::ModalConsts {{ dim: {}, modes: {k}, nf: {nf}, mass: {mass}, s_t0: [{}], s_bar: {s_bar}, s_kl: {s_kl}, i_kl: {i_kl}, theta: {theta}, m_ff: {m_ff}, k_ff: {k_ff}, phi: {phi}, stiffening: {}, damping: {damping}, labels: &[{}], description: {description:?} }}",
        inv.dim,
        s_t0.join(", "),
        model.stiffening.is_on(),
        labels.join(", "),
    ))
}

/// One line saying what the modal body of `spec` is.
#[cfg(feature = "modal")]
pub fn modal_description(
    model: &crate::modal::ModalModel,
    spec: &BodySpec,
    p: &ffr_spec::Params,
) -> String {
    use crate::modal::{describe_body, elastic_modes};
    model.describe(&describe_body(
        spec,
        false,
        false,
        elastic_modes(spec, p.length),
    ))
}

/// [`emit_body_file`] followed by the formatted [`modal_items`].
#[cfg(feature = "modal")]
pub fn emit_modal_body_file(
    set: &KernelSet,
    spec: &BodySpec,
    opts: &EmitOptions,
    model: &crate::modal::ModalModel,
    p: &ffr_spec::Params,
) -> Result<String, crate::Error> {
    let description = modal_description(model, spec, p);
    let scene = set.model().scene();
    let kernels = crate::modal::generate_modal_kernels(model, scene)?;
    let (items, kernel_text) = modal_text(
        model,
        p,
        &description,
        &opts.type_name,
        &opts.runtime_path,
        kernels.as_ref(),
        Layout::Pretty,
    )?;
    let ty = &opts.type_name;
    let mut more = vec![format!(
        "Modal body `{ty}Modal`: {} modes ({}), {} constants.",
        model.len(),
        model.basis.labels.join(" "),
        modal_constants(model)
    )];
    match &kernels {
        Some(k) => {
            more.push(format!(
                "  Inertia equations generated: `{ty}ModalKernels` ({} scene, {}).",
                if scene == ffr_spec::SceneDim::Planar {
                    "planar"
                } else {
                    "spatial"
                },
                if k.linear_elastic {
                    "with the linear elastic force K̃ η"
                } else {
                    "the elastic force K̃ η + stiffening added by the runtime"
                }
            ));
            more.push("  Operations per call:".to_string());
            for (name, prog) in k.programs() {
                more.push(format!("    {name:<20} {}", prog.ops()));
            }
        }
        None => more.push(format!(
            "  More than {} modes: its inertia equations are the runtime's from these constants (ffr-runtime/src/inertia.rs, O(k²) per evaluation), not generated.",
            crate::modal::MAX_GENERATED_MODES
        )),
    }
    Ok(body_file(set, spec, opts, &more) + "\n" + &pretty(&items, 0) + &kernel_text)
}

/// How many numbers [`modal_items`] bakes in.
#[cfg(feature = "modal")]
fn modal_constants(model: &crate::modal::ModalModel) -> usize {
    let (k, nf) = (model.len(), model.basis.phi.nrows());
    1 + 3
        + 3 * k
        + 9 * k * k
        + 9 * k
        + 9
        + 2 * k * k
        + nf * k
        + model.damping.as_ref().map_or(0, |_| k * k)
}
