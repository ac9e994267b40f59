//! Rust source from the generated programs: a body type implementing
//! `FlexBody` and `CompiledBody`, flat and unrolled, formatted by prettyplease.

use crate::generate::Generated;
use crate::poly::Param;
use crate::program::{Expr, Input, Program, Target};
use std::fmt::Write;

/// How to emit a body.
#[derive(Clone, Debug)]
pub struct EmitOptions {
    /// Name of the body type (e.g. `Arm`).
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

const AXES: [&str; 3] = ["x", "y", "z"];

/// A one-line description of the generator's input, for headers and docs.
pub fn describe(g: &Generated) -> String {
    let s = &g.spec;
    format!(
        "shape `{}` ({}, fnv1a {:016x}), {} element{}, {}, {} formalism, stiffening {}",
        crate::sanitize::comment_text(&s.shape.name),
        crate::sanitize::comment_text(&s.shape.origin),
        s.shape.source_hash,
        s.elements,
        if s.elements == 1 { "" } else { "s" },
        s.reference,
        s.formalism,
        if g.options.stiffening { "on" } else { "off" }
    )
}

fn lit(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
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

/// `let` bindings of a program's inputs (from `recv` and `q_f`) and temporaries.
fn prelude(p: &Program, recv: &str, out: &mut String) {
    for (slot, input) in &p.inputs {
        let name = &p.names[*slot as usize];
        match input {
            Input::Param(f) => writeln!(out, "let {name} = {recv}.{};", f.field()).unwrap(),
            Input::Q(i) => writeln!(out, "let {name} = q_f[{i}];").unwrap(),
        }
    }
    for (slot, e) in &p.stmts {
        write!(out, "let {} = ", p.names[*slot as usize]).unwrap();
        expr(e, &p.names, out);
        out.push_str(";\n");
    }
}

fn assign(
    p: &Program,
    out: &mut String,
    mut place: impl FnMut(Target) -> (String, Option<String>),
) {
    for (t, e) in &p.outputs {
        let (lhs, mirror) = place(*t);
        write!(out, "{lhs} = ").unwrap();
        expr(e, &p.names, out);
        out.push_str(";\n");
        if let Some(m) = mirror {
            writeln!(out, "{m} = {lhs};").unwrap();
        }
    }
}

fn invariants_fn(g: &Generated, rt: &str) -> String {
    let nf = g.dofs.len();
    let p = &g.invariants;
    let mut s = String::new();
    writeln!(s, "fn invariants(&self) -> {rt}::Invariants {{").unwrap();
    prelude(p, "self", &mut s);
    writeln!(
        s,
        "let mut inv = {rt}::Invariants::zeros({}, {nf});",
        g.exact.dim
    )
    .unwrap();
    assign(p, &mut s, |t| match t {
        Target::Mass => ("inv.mass".into(), None),
        Target::St0(k) => (format!("inv.s_t0[{k}]"), None),
        Target::SBar(k, a) => (format!("inv.s_bar[({k}, {a})]"), None),
        Target::Skl(k, l, a, b) => (format!("inv.s_kl[{k}][{l}][({a}, {b})]"), None),
        Target::Ikl(k, l, a) => (format!("inv.i_kl[{k}][{l}][{a}]"), None),
        Target::Theta(k, l) => (format!("inv.theta[({k}, {l})]"), None),
        Target::Mff(a, b) => (format!("inv.m_ff[({a}, {b})]"), None),
        Target::Kff(a, b) => (format!("inv.k_ff[({a}, {b})]"), None),
        other => unreachable!("{other:?} in invariants"),
    });
    // Each symmetric pair was computed once (upper triangle, k ≤ l): mirror.
    s.push_str(
        "inv.theta.fill_lower_triangle_with_upper_triangle();\n\
         inv.m_ff.fill_lower_triangle_with_upper_triangle();\n\
         inv.k_ff.fill_lower_triangle_with_upper_triangle();\n\
         for k in 0..3 {\n\
             inv.s_kl[k][k].fill_lower_triangle_with_upper_triangle();\n\
             for l in k + 1..3 {\n\
                 inv.s_kl[l][k] = inv.s_kl[k][l].transpose();\n\
             }\n\
         }\n\
         inv\n}\n",
    );
    s
}

fn inertia_fn(g: &Generated, rt: &str) -> String {
    let nf = g.dofs.len();
    let mut s = String::new();
    writeln!(
        s,
        "fn inertia_terms(&self, q_f: &[f64], out: &mut {rt}::InertiaTerms) {{"
    )
    .unwrap();
    writeln!(s, "assert_eq!(q_f.len(), {nf}, \"q_f must have {nf} entries (the body's elastic coordinates)\");").unwrap();
    writeln!(
        s,
        "assert_eq!(out.i_theta_f.ncols(), {nf}, \"out.i_theta_f must be 3 x {nf}\");"
    )
    .unwrap();
    prelude(&g.inertia, "self", &mut s);
    writeln!(
        s,
        "out.s_t.fill(0.0);\nout.i_theta_theta.fill(0.0);\nout.i_theta_f.fill(0.0);"
    )
    .unwrap();
    assign(&g.inertia, &mut s, |t| match t {
        Target::St(k) => (format!("out.s_t[{k}]"), None),
        Target::ItTheta(k, l) => (
            format!("out.i_theta_theta[({k}, {l})]"),
            (k != l).then(|| format!("out.i_theta_theta[({l}, {k})]")),
        ),
        Target::ItF(k, a) => (format!("out.i_theta_f[({k}, {a})]"), None),
        other => unreachable!("{other:?} in inertia terms"),
    });
    s.push_str("}\n");
    s
}

fn stiffening_fn(g: &Generated, rt: &str) -> String {
    let (Some(fp), Some(tp)) = (&g.stiffening_force, &g.stiffening_tangent) else {
        return String::new();
    };
    let nf = g.dofs.len();
    let mut s = String::new();
    writeln!(s, "fn has_stiffening(&self) -> bool {{ true }}").unwrap();
    writeln!(s, "fn stiffening(&self, q_f: &[f64], force: &mut [f64], tangent: ::core::option::Option<&mut {rt}::nalgebra::DMatrix<f64>>) {{").unwrap();
    writeln!(s, "assert_eq!(q_f.len(), {nf}, \"q_f must have {nf} entries (the body's elastic coordinates)\");").unwrap();
    writeln!(
        s,
        "assert_eq!(force.len(), {nf}, \"force must have {nf} entries\");"
    )
    .unwrap();
    s.push_str("{\n");
    prelude(fp, "self", &mut s);
    for (t, e) in &fp.outputs {
        let Target::Force(a) = t else { unreachable!() };
        write!(s, "force[{a}] += ").unwrap();
        expr(e, &fp.names, &mut s);
        s.push_str(";\n");
    }
    s.push_str("}\n");
    writeln!(s, "if let ::core::option::Option::Some(k_t) = tangent {{").unwrap();
    writeln!(
        s,
        "assert_eq!(k_t.shape(), ({nf}, {nf}), \"tangent must be {nf} x {nf}\");"
    )
    .unwrap();
    prelude(tp, "self", &mut s);
    for (t, e) in &tp.outputs {
        let Target::Tangent(a, b) = t else {
            unreachable!()
        };
        if a == b {
            write!(s, "k_t[({a}, {b})] += ").unwrap();
            expr(e, &tp.names, &mut s);
            s.push_str(";\n");
        } else {
            write!(s, "let v = ").unwrap();
            expr(e, &tp.names, &mut s);
            writeln!(s, ";\nk_t[({a}, {b})] += v;\nk_t[({b}, {a})] += v;").unwrap();
        }
    }
    s.push_str("}\n}\n");
    s
}

/// The trait implementations for `opts.type_name` (and the struct itself if
/// `opts.define_struct`), unformatted.
pub fn body_items(g: &Generated, opts: &EmitOptions) -> String {
    let rt = &opts.runtime_path;
    let ty = &opts.type_name;
    let nf = g.dofs.len();
    let dim = g.exact.dim;
    let mut s = String::new();
    let what = describe(g);
    if opts.define_struct {
        let used = g.used_params();
        writeln!(
            s,
            "/// Parameters of an FFR body generated by ffr-codegen from {what}. SI units."
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
            writeln!(s, "/// {}{note}.\npub {}: f64,", param_doc(f), f.field()).unwrap();
        }
        writeln!(s, "}}").unwrap();
        writeln!(s, "impl ::core::convert::From<{rt}::Params> for {ty} {{\nfn from(p: {rt}::Params) -> Self {{\nSelf {{ {} }}\n}}\n}}",
            Param::FIELDS.iter().map(|f| format!("{0}: p.{0}", f.field())).collect::<Vec<_>>().join(", ")).unwrap();
    }
    let dofs = g
        .dofs
        .iter()
        .map(|d| format!("\"{d}\""))
        .collect::<Vec<_>>()
        .join(", ");
    writeln!(s, "impl {rt}::CompiledBody for {ty} {{\nconst NF: usize = {nf};\nconst DIM: usize = {dim};\nconst DOFS: &'static [&'static str] = &[{dofs}];\n}}").unwrap();
    writeln!(s, "#[allow(clippy::all, clippy::pedantic)]").unwrap();
    writeln!(s, "impl {rt}::FlexBody for {ty} {{").unwrap();
    writeln!(
        s,
        "fn nf(&self) -> usize {{ {nf} }}\nfn dim(&self) -> usize {{ {dim} }}"
    )
    .unwrap();
    writeln!(s, "fn dof_labels(&self) -> ::std::vec::Vec<::std::string::String> {{ <Self as {rt}::CompiledBody>::DOFS.iter().map(|d| ::std::string::ToString::to_string(d)).collect() }}").unwrap();
    s.push_str(&invariants_fn(g, rt));
    s.push_str(&inertia_fn(g, rt));
    s.push_str(&stiffening_fn(g, rt));
    s.push_str("}\n");
    s
}

fn param_doc(p: Param) -> &'static str {
    match p {
        Param::ElemLength => "Element length",
        Param::Length => "Body length `L` (m)",
        Param::Rho => "Density `ρ` (kg/m³)",
        Param::Area => "Cross-section area `A` (m²)",
        Param::Iy => "Second moment `I_y = ∫z² dA` (m⁴)",
        Param::Iz => "Second moment `I_z = ∫y² dA` (m⁴)",
        Param::E => "Young's modulus `E` (Pa)",
        Param::G => "Shear modulus `G` (Pa)",
        Param::J => "Torsion constant `J` (m⁴)",
    }
}

/// A complete, formatted Rust file for one body, with a header naming the input.
pub fn emit_file(g: &Generated, opts: &EmitOptions) -> String {
    let items = body_items(g, opts);
    let file = syn::parse_file(&items)
        .unwrap_or_else(|e| panic!("ffr-codegen produced invalid Rust (a bug): {e}\n{items}"));
    let body = prettyplease::unparse(&file);
    let dofs: Vec<String> = g.dofs.iter().map(|d| d.to_string()).collect();
    let mut header = String::new();
    writeln!(
        header,
        "// @generated by ffr-codegen {} — do not edit.",
        env!("CARGO_PKG_VERSION")
    )
    .unwrap();
    writeln!(header, "// Input: {}.", describe(g)).unwrap();
    writeln!(
        header,
        "// Body `{}`: {} elastic coordinates, in this order:",
        crate::sanitize::comment_text(&opts.type_name),
        dofs.len()
    )
    .unwrap();
    for chunk in dofs.chunks(12) {
        writeln!(header, "//   {}", chunk.join(" ")).unwrap();
    }
    writeln!(header, "// Axes: {}.", &AXES[..g.exact.dim].join(", ")).unwrap();
    header.push('\n');
    header + &body
}
