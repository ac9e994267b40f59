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
}

impl Default for EmitOptions {
    fn default() -> Self {
        Self {
            type_name: "Body".into(),
            define_struct: true,
            runtime_path: "::ffr::runtime".into(),
        }
    }
}

pub use crate::sanitize::comment_text;

/// A one-line description of a kernel set's input.
pub fn describe(set: &KernelSet) -> String {
    let m = set.model();
    format!(
        "shape `{}` ({}, fnv1a {:016x}), {}",
        comment_text(&m.shape.name),
        comment_text(&m.shape.origin),
        m.shape.source_hash,
        m.resolved_options().describe()
    )
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
    }
}

/// `let` bindings of the inputs and temporaries, then the output assignments.
fn program_body(p: &Program, out: &mut String) {
    for (slot, input) in &p.inputs {
        let (name, src) = (&p.names[*slot as usize], input_source(*input));
        // A scalar input already bound under its own name (`x0`) needs no
        // `let x0 = x0;`.
        if *name != src {
            writeln!(out, "let {name} = {src};").unwrap();
        }
    }
    for (slot, e) in &p.stmts {
        write!(out, "let {} = ", p.names[*slot as usize]).unwrap();
        expr(e, &p.names, out);
        out.push_str(";\n");
    }
    for ((arr, idx), e) in &p.outputs {
        if *arr == OutArr::Energy {
            out.push_str("energy = ");
        } else {
            write!(out, "{}[{idx}] = ", out_name(*arr)).unwrap();
        }
        expr(e, &p.names, out);
        out.push_str(";\n");
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
    s: String,
}

impl Views<'_> {
    fn coef(&mut self) {
        if reads_coef(self.p) {
            let nc = self.nc;
            writeln!(self.s, "let c: &[f64; {nc}] = c.try_into().expect(\"the coefficient array has {nc} entries\");").unwrap();
        }
    }
    fn input(&mut self, name: &str, src: &str, f: impl Fn(Sym) -> bool) {
        if reads(self.p, f) {
            let n = self.n;
            writeln!(
                self.s,
                "let {name}: &[f64; {n}] = {src}.try_into().expect(\"`{name}` has {n} entries\");"
            )
            .unwrap();
        }
    }
    fn scalar(&mut self, name: &str, src: &str, f: impl Fn(Sym) -> bool) {
        if reads(self.p, f) && name != src {
            writeln!(self.s, "let {name} = {src};").unwrap();
        }
    }
    fn output(&mut self, a: OutArr, src: &str, len: usize) {
        if writes(self.p, a) {
            let name = out_name(a);
            writeln!(self.s, "let {name}: &mut [f64; {len}] = (&mut *{src}).try_into().expect(\"`{name}` has {len} entries\");").unwrap();
        }
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

/// The operation-count line of a function (turned into a plain `//`
/// comment after formatting).
fn ops_doc(p: &Program) -> String {
    format!("#[doc = \" operations: {}\"]\n", p.ops())
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

fn kernel_impl(set: &KernelSet, kt: &str, rt: &str) -> String {
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
    writeln!(
        s,
        "#[doc = \" Element kernels generated by ffr-codegen from {}.\"]",
        describe(set).replace('\\', "\\\\").replace('"', "\\\"")
    )
    .unwrap();
    writeln!(
        s,
        "#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]\npub struct {kt};"
    )
    .unwrap();
    writeln!(s, "#[allow(clippy::all, clippy::pedantic, unused_variables)]\nimpl {rt}::ElementKernels for {kt} {{").unwrap();
    writeln!(
        s,
        "fn info(&self) -> &{rt}::KernelInfo {{ const INFO: {rt}::KernelInfo = {rt}::KernelInfo {{ shape: ::std::borrow::Cow::Borrowed({:?}), dim: {}, n_local: {n}, coordinates: ::std::borrow::Cow::Borrowed(&[{coords}]), options: {}, n_coefficients: {nc}, params_used: ::std::borrow::Cow::Borrowed(&[{params}]), scratch: 0 }}; &INFO }}",
        comment_text(&m.shape.name),
        m.shape.dimension,
        options_expr(&m.resolved_options(), rt),
    )
    .unwrap();

    // Coefficients.
    let cp = &set.coefficient_program;
    s.push_str(&ops_doc(cp));
    writeln!(
        s,
        "fn coefficients(&self, params: &{rt}::spec::Params, l: f64, c: &mut [f64]) {{"
    )
    .unwrap();
    writeln!(s, "let c: &mut [f64; {nc}] = c.try_into().expect(\"the coefficient array has {nc} entries\");").unwrap();
    program_body(cp, &mut s);
    s.push_str("}\n");

    // mass
    let p = &set.mass;
    let mut v = Views {
        p,
        n,
        nc,
        s: String::new(),
    };
    v.coef();
    v.scalar("x0", "x0", |s| s == Sym::X0);
    v.input("q", "q", |s| matches!(s, Sym::Q(_)));
    v.output(OutArr::St, "out.s_t", 3);
    v.output(OutArr::Mee, "out.m_ee", n * n);
    v.output(OutArr::MeFrame, "out.m_e_frame", n * 6);
    v.output(OutArr::MrefE, "out.m_ref_e", 6 * n);
    v.output(OutArr::MrefFrame, "out.m_ref_frame", 36);
    s.push_str(&ops_doc(p));
    writeln!(s, "fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut {rt}::MassOut, _scratch: &mut [f64]) {{").unwrap();
    s.push_str(&v.s);
    program_body(p, &mut s);
    s.push_str("}\n");

    // residual / tangent (free frame)
    if let (Some(rp), Some(tp)) = (&set.residual, &set.tangent) {
        let mut v = Views {
            p: rp,
            n,
            nc,
            s: String::new(),
        };
        v.coef();
        v.kernel_inputs("x.");
        v.output(OutArr::Fr, "out.f_r", 3);
        v.output(OutArr::Fth, "out.f_th", 3);
        v.output(OutArr::Fe, "out.f_e", n);
        s.push_str(&ops_doc(rp));
        writeln!(s, "fn residual(&self, c: &[f64], x: &{rt}::KernelInput, out: &mut {rt}::ResidualOut, _scratch: &mut [f64]) {{").unwrap();
        s.push_str(&v.s);
        program_body(rp, &mut s);
        s.push_str("}\n");

        let mut v = Views {
            p: tp,
            n,
            nc,
            s: String::new(),
        };
        v.coef();
        v.kernel_inputs("x.");
        v.scalar("bp", "bp", |s| s == Sym::Bp);
        v.scalar("gp", "gp", |s| s == Sym::Gp);
        v.output(OutArr::Fr, "out.f_r", 3);
        v.output(OutArr::Fth, "out.f_th", 3);
        v.output(OutArr::Fe, "out.f_e", n);
        v.output(OutArr::Kee, "out.k_ee", n * n);
        v.output(OutArr::DeFrame, "out.d_e_frame", n * 9);
        v.output(OutArr::KrefE, "out.k_ref_e", 6 * n);
        v.output(OutArr::DrefFrame, "out.d_ref_frame", 54);
        s.push_str(&ops_doc(tp));
        writeln!(s, "fn tangent(&self, c: &[f64], x: &{rt}::KernelInput, bp: f64, gp: f64, out: &mut {rt}::TangentOut, _scratch: &mut [f64]) {{").unwrap();
        s.push_str(&v.s);
        program_body(tp, &mut s);
        s.push_str("}\n");
    }

    // elastic-only kernels
    let p = &set.residual_elastic;
    let mut v = Views {
        p,
        n,
        nc,
        s: String::new(),
    };
    v.coef();
    v.kernel_inputs("x.");
    v.output(OutArr::Fe, "f_e", n);
    s.push_str(&ops_doc(p));
    writeln!(s, "fn residual_elastic(&self, c: &[f64], x: &{rt}::KernelInput, f_e: &mut [f64], _scratch: &mut [f64]) {{").unwrap();
    s.push_str(&v.s);
    program_body(p, &mut s);
    s.push_str("}\n");

    let p = &set.tangent_elastic;
    let mut v = Views {
        p,
        n,
        nc,
        s: String::new(),
    };
    v.coef();
    v.kernel_inputs("x.");
    v.scalar("bp", "bp", |s| s == Sym::Bp);
    v.scalar("gp", "gp", |s| s == Sym::Gp);
    v.output(OutArr::Fe, "f_e", n);
    v.output(OutArr::Kee, "k_ee", n * n);
    s.push_str(&ops_doc(p));
    writeln!(s, "fn tangent_elastic(&self, c: &[f64], x: &{rt}::KernelInput, bp: f64, gp: f64, f_e: &mut [f64], k_ee: &mut [f64], _scratch: &mut [f64]) {{").unwrap();
    s.push_str(&v.s);
    program_body(p, &mut s);
    s.push_str("}\n");

    // energy
    let p = &set.energy;
    let mut v = Views {
        p,
        n,
        nc,
        s: String::new(),
    };
    v.coef();
    v.input("q", "q", |s| matches!(s, Sym::Q(_)));
    s.push_str(&ops_doc(p));
    writeln!(
        s,
        "fn energy(&self, c: &[f64], q: &[f64], _scratch: &mut [f64]) -> f64 {{"
    )
    .unwrap();
    s.push_str(&v.s);
    s.push_str("let energy;\n");
    program_body(p, &mut s);
    s.push_str("energy\n}\n");

    // element invariants
    let p = &set.element_invariants;
    let (_, inv_len) = ffr_spec::invariant_layout(n);
    let mut v = Views {
        p,
        n,
        nc,
        s: String::new(),
    };
    v.coef();
    v.scalar("x0", "x0", |s| s == Sym::X0);
    v.output(OutArr::Inv, "out", inv_len);
    s.push_str(&ops_doc(p));
    writeln!(s, "fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], _scratch: &mut [f64]) {{").unwrap();
    s.push_str(&v.s);
    program_body(p, &mut s);
    s.push_str("}\n");

    // point shape
    let p = &set.point_shape;
    let mut v = Views {
        p,
        n,
        nc,
        s: String::new(),
    };
    v.coef();
    v.scalar("xi", "xi", |s| s == Sym::Xi);
    v.output(OutArr::S, "s", 3 * n);
    v.output(OutArr::Psi, "psi", 3 * n);
    s.push_str(&ops_doc(p));
    writeln!(s, "fn point_shape(&self, c: &[f64], xi: f64, s: &mut [f64], psi: &mut [f64], _scratch: &mut [f64]) {{").unwrap();
    s.push_str(&v.s);
    program_body(p, &mut s);
    s.push_str("}\n}\n");
    s
}

/// The kernel type `kt` (unformatted items).
pub fn kernel_items(set: &KernelSet, kt: &str, runtime_path: &str) -> String {
    kernel_impl(set, kt, runtime_path)
}

/// The kernels plus, for a body with a fixed mesh, the `CompiledBody`
/// implementation for `opts.type_name` (and the parameter struct itself if
/// `opts.define_struct`), unformatted.
pub fn body_items(set: &KernelSet, spec: &BodySpec, opts: &EmitOptions) -> String {
    let rt = &opts.runtime_path;
    let ty = &opts.type_name;
    let kt = format!("{ty}Kernels");
    let mut s = kernel_impl(set, &kt, rt);
    let used = set.params_used();
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
            } else {
                format!("{}: 0.0", f.field())
            }
        })
        .collect::<Vec<_>>()
        .join(", ");
    writeln!(
        s,
        "impl {rt}::CompiledBody for {ty} {{\ntype Kernels = {kt};\nconst ELEMENTS: usize = {};\nconst REFERENCE: {rt}::spec::Reference = {rt}::spec::Reference::{:?};\nconst NF: usize = {};\nconst DIM: usize = {};\nconst DOFS: &'static [&'static str] = &[{dofs}];\nfn params(&self) -> {rt}::spec::Params {{ {rt}::spec::Params {{ {fields} }} }}\n}}",
        spec.elements,
        spec.reference,
        spec.nf(),
        spec.shape.dimension
    )
    .unwrap();
    s
}

/// Format items with prettyplease and turn the operation-count doc lines
/// into plain `// operations: N` comments.
fn format(items: &str) -> String {
    let file = syn::parse_file(items)
        .unwrap_or_else(|e| panic!("ffr-codegen produced invalid Rust (a bug): {e}\n{items}"));
    prettyplease::unparse(&file).replace("/// operations: ", "// operations: ")
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
        writeln!(h, "// {ind}Operations per call:").unwrap();
        writeln!(
            h,
            "// {ind}  {:<20} {}",
            "coefficients",
            set.coefficient_program.ops()
        )
        .unwrap();
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
    ) + &format(&kernel_items(set, kernels_type, runtime_path))
}

/// A complete, formatted file for one body with a fixed mesh.
pub fn emit_body_file(set: &KernelSet, spec: &BodySpec, opts: &EmitOptions) -> String {
    let dofs: Vec<String> = spec.dofs().iter().map(|d| d.to_string()).collect();
    let mut extra = vec!["Elastic coordinates, in this order:".to_string()];
    extra.extend(
        dofs.chunks(12)
            .map(|chunk| format!("  {}", chunk.join(" "))),
    );
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
    h + &format(&body_items(set, spec, opts))
}

/// A scene file and the kernels of its flexible bodies, ready to emit
/// (read, checked and generated by [`crate::builder::generate_scene`]).
#[derive(Clone, Debug)]
pub struct SceneKernels<'a> {
    /// The file as it was named (headers, errors).
    pub origin: &'a str,
    /// Its text (embedded in the generated type).
    pub text: &'a str,
    /// Each flexible body's name and kernel set, in body-name order.
    pub bodies: Vec<(String, KernelSet)>,
}

/// The compiled form of a scene file: the specialized kernels of each of its
/// flexible bodies (`{Type}{Body}Kernels`), a kernel provider and the scene
/// type `type_name` whose `load()` builds the scene from the embedded file
/// text with these kernels (`ffr::scene::from_str`). The runtime path must
/// end in `::runtime` (its parent is the `ffr` crate).
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
    let mut items = String::new();
    let mut titled = Vec::new();
    let mut arms = String::new();
    for (name, set) in &scene.bodies {
        let body_type = crate::scene::body_type_name(name);
        let kt = format!("{type_name}{body_type}Kernels");
        titled.push((
            Some(format!("Body `{}` → `{kt}`:", comment_text(name))),
            set,
        ));
        items.push_str(&kernel_impl(set, &kt, runtime_path));
        writeln!(
            arms,
            "{name:?} => ::core::result::Result::Ok((::std::boxed::Box::new({kt}), \"compiled (scene)\")),"
        )
        .unwrap();
    }
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
        "impl {root}::scene::KernelProvider for {type_name}Kernels {{\nfn kernels(&self, spec: &{root}::scene::FlexSpec) -> ::core::result::Result<(::std::boxed::Box<dyn {runtime_path}::ElementKernels>, &'static str), ::std::boxed::Box<dyn ::std::error::Error>> {{\nmatch spec.model.name.as_str() {{\n{arms}other => ::core::result::Result::Err(::std::format!(\"no compiled kernels for body `{{other}}`\").into()),\n}}\n}}\n}}"
    )
    .unwrap();
    writeln!(
        items,
        "#[doc = \" The scene `{}`, compiled: its flexible bodies run the specialized kernels above.\"]\n#[derive(Clone, Copy, Debug, Default)]\npub struct {type_name};\nimpl {type_name} {{\n#[doc = \" The scene file's text.\"]\npub const SOURCE: &'static str = {:?};\n#[doc = \" The scene file as it was named.\"]\npub const ORIGIN: &'static str = {:?};\n#[doc = \" Build the scene with the compiled kernels.\"]\npub fn load() -> ::core::result::Result<{root}::scene::Scene, {root}::scene::SceneError> {{\n{root}::scene::from_str(Self::SOURCE, Self::ORIGIN, ::std::path::Path::new(\".\"), &{type_name}Kernels)\n}}\n}}",
        comment_text(origin).replace('"', "\\\""),
        text,
        origin
    )
    .unwrap();
    Ok(header(&what, &titled, &[]) + &format(&items))
}
