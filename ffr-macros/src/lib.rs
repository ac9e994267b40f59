//! The `#[flex_body]` attribute (see the `ffr` crate, which re-exports it).
//!
//! Thin by design: parse the options and the struct, validate them, call
//! `ffr-codegen` (the same generator as `ffr_codegen::Builder` in a build
//! script), and expand to the struct unchanged plus the generated
//! `FlexBody` and `CompiledBody` implementations. Misuse becomes a
//! `compile_error!` at the offending token.

use ffr_codegen::body::MAX_ELEMENTS;
use ffr_codegen::flex_body::{self, FlexBodyError, FlexBodyInput};
use ffr_codegen::poly::Param;
use ffr_codegen::shape::builtin_names;
use ffr_codegen::{EmitOptions, KernelOptions, Reference, SceneDim, Stiffening};
use proc_macro::TokenStream;
use proc_macro2::{Span, TokenStream as TokenStream2};
use quote::{quote, ToTokens};
use std::path::PathBuf;
use syn::ext::IdentExt;
use syn::{Error, Expr, ExprLit, Fields, Item, ItemStruct, Lit, LitStr, Result, Type};

/// Generate a floating-frame-of-reference body for a struct of `f64`
/// parameter fields: the struct is kept as written and gets implementations
/// of `ffr::runtime::FlexBody` and `ffr::runtime::CompiledBody`, with the
/// invariants and `q_f`-dependent terms unrolled inline.
///
/// ```ignore
/// #[ffr::flex_body(shape = "beam3", elements = 8, reference = "clamped")]
/// pub struct Arm { pub length: f64, pub rho: f64, pub area: f64, pub iy: f64,
///                  pub iz: f64, pub e: f64, pub g: f64, pub j: f64 }
/// ```
///
/// Options:
/// - `shape = "beam3"`: a built-in shape (`beam2`, `beam3`) or a path to a
///   `.toml` shape file, relative to the crate root (`CARGO_MANIFEST_DIR`);
///   the crate is rebuilt when the file changes.
/// - `elements = 8`: number of equal elements, 1 to 256.
/// - `segments = 4`: also `<Name>::segments()`, the body split at nodes
///   into this many segments of `elements / segments` elements for
///   `System::add_segments` (large deflection: each segment has its own
///   floating frame), exactly as a scene file's `segments = 4` splits it,
///   and `<Name>::SEGMENTS`; 1 to 256, a divisor of `elements`. The type
///   itself stays the whole body as one (its `CompiledBody` for modes and
///   invariants). Not with `sections` or `modes` (split those in a scene
///   file). See `docs/scenes.md`, "Segments".
/// - `reference = "clamped" | "pinned" | "free"` (default `"clamped"`).
/// - `formalism = "consistent" | "lumped"` (default `"consistent"`).
/// - `stiffening = true | false | "second-order" | "fourth-order"`: geometric
///   stiffening (default `false`; `true` is the fourth-order model).
/// - `scene = "planar" | "spatial"`: the scene the body moves in (default:
///   the shape's dimension; a planar shape in a spatial scene needs
///   `"spatial"`).
/// - `sections = "data/blade.csv"`: sections that vary along the span, a
///   CSV section table (the columns of a scene's `sections`,
///   `docs/scenes.md`) relative to the crate root; the kernels are
///   generated for varying sections, the table is baked into the type
///   (`CompiledBody::SECTIONS`) and the crate is rebuilt when it changes.
///   The body's length is the last station's x. Needs the feature
///   `sections` of `ffr` (the csv crate in the generator).
/// - `modes = 4` with `params(length = 8.0, rho = …, …)`: also a type
///   `<Name>Modal`, the body at these parameters reduced to modes when the
///   crate is built (the basis and projected invariants as constants;
///   `<Name>Modal::body()`), with the modal keys of a scene file:
///   `reduction = "modal" | "craig-bampton"`, `boundary_nodes = [8]`
///   (default the last node), `static_modes = true | false` (default
///   `true`), `modal_damping = 0.02` or one ratio per normal mode. Needs the
///   feature `modal` of `ffr` (the modal reduction in the generator).
///
/// The struct needs an `f64` field for every parameter the body uses
/// (`length`, `rho`, `area`, `iy`, `iz`, `e`, `g`, `j`; a planar body, for
/// example, does not use `iy`, `g`, `j`; a body with `sections` uses none:
/// `pub struct Blade {}`). Other fields are left alone.
#[proc_macro_attribute]
pub fn flex_body(attr: TokenStream, item: TokenStream) -> TokenStream {
    let item = TokenStream2::from(item);
    match expand(attr.into(), item.clone()) {
        Ok(out) => out.into(),
        // Keep the item so that its other uses do not add errors of their own.
        Err(e) => {
            let mut out = item;
            out.extend(e.to_compile_error());
            out.into()
        }
    }
}

const OPTIONS: &str = "shape, elements, segments, reference, formalism, stiffening, scene, sections, modes, reduction, boundary_nodes, static_modes, modal_damping, params";

/// The attribute's options as written: the shape and mesh, and the kernel
/// options as one value (the scene's literal kept for its error span).
#[derive(Default)]
struct Args {
    shape: Option<LitStr>,
    elements: Option<(usize, Expr)>,
    /// `segments = N` (its literal for spans).
    segments: Option<(usize, Expr)>,
    reference: Option<Reference>,
    options: KernelOptions,
    scene: Option<LitStr>,
    sections: Option<LitStr>,
    /// `modes = K` (its literal for spans).
    modes: Option<(usize, Expr)>,
    /// `reduction = "…"`: true for Craig–Bampton.
    craig_bampton: Option<(bool, LitStr)>,
    boundary: Option<(Vec<usize>, Expr)>,
    static_modes: Option<bool>,
    modal_damping: Vec<f64>,
    /// `params(name = value, …)` and the option's path for spans.
    params: Option<(ffr_codegen::Params, syn::Path)>,
    /// The modal options written, for "needs `modes`" errors.
    modal_given: Vec<syn::Path>,
}

fn combine(errors: &mut Option<Error>, e: Error) {
    match errors {
        Some(all) => all.combine(e),
        None => *errors = Some(e),
    }
}

fn parse_args(attr: TokenStream2) -> Result<Args> {
    let mut args = Args::default();
    let mut errors = None;
    // Options written (valid or not), to tell a missing option from a wrong one.
    let mut given: Vec<String> = Vec::new();
    let parser = syn::meta::parser(|meta| {
        let path = &meta.path;
        let name = path
            .get_ident()
            .map(|i| i.unraw().to_string())
            .unwrap_or_else(|| path.to_token_stream().to_string().replace(' ', ""));
        let known = matches!(
            name.as_str(),
            "shape"
                | "elements"
                | "segments"
                | "reference"
                | "formalism"
                | "stiffening"
                | "scene"
                | "sections"
                | "modes"
                | "reduction"
                | "boundary_nodes"
                | "static_modes"
                | "modal_damping"
                | "params"
        );
        if !known {
            combine(
                &mut errors,
                Error::new_spanned(path, format!("unknown option `{name}`: expected {OPTIONS}")),
            );
            // Skip its value, if any, and go on with the others.
            if meta.input.peek(syn::Token![=]) {
                meta.value()?.parse::<Expr>()?;
            }
            return Ok(());
        }
        if given.contains(&name) {
            combine(
                &mut errors,
                Error::new_spanned(path, format!("option `{name}` is given twice")),
            );
            if meta.input.peek(syn::Token![=]) {
                meta.value()?.parse::<Expr>()?;
            } else if meta.input.peek(syn::token::Paren) {
                meta.parse_nested_meta(|m| {
                    m.value()?.parse::<Expr>()?;
                    Ok(())
                })?;
            }
            return Ok(());
        }
        if name == "params" {
            given.push(name.clone());
            args.modal_given.push(path.clone());
            let mut p = ffr_codegen::Params::from_array([0.0; 8]);
            let mut seen: Vec<String> = Vec::new();
            meta.parse_nested_meta(|m| {
                let field = m
                    .path
                    .get_ident()
                    .map(|i| i.unraw().to_string())
                    .unwrap_or_default();
                let value: Expr = m.value()?.parse()?;
                let Some(param) = Param::FIELDS.iter().find(|f| f.field() == field) else {
                    combine(
                        &mut errors,
                        Error::new_spanned(
                            &m.path,
                            format!(
                                "unknown parameter `{}`: expected {}",
                                m.path.to_token_stream(),
                                Param::FIELDS
                                    .iter()
                                    .map(|f| f.field())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        ),
                    );
                    return Ok(());
                };
                if seen.contains(&field) {
                    combine(
                        &mut errors,
                        Error::new_spanned(&m.path, format!("parameter `{field}` is given twice")),
                    );
                    return Ok(());
                }
                seen.push(field);
                match number(&value) {
                    Some(x) => {
                        let mut a = p.to_array();
                        a[param.field_index().expect("a field")] = x;
                        p = ffr_codegen::Params::from_array(a);
                    }
                    None => combine(
                        &mut errors,
                        Error::new_spanned(
                            &value,
                            format!(
                                "parameter `{}` expects a number (SI units), found `{}`",
                                param.field(),
                                value.to_token_stream()
                            ),
                        ),
                    ),
                }
                Ok(())
            })?;
            args.params = Some((p, path.clone()));
            return Ok(());
        }
        let value: Expr = meta.value()?.parse()?;
        if given.contains(&name) {
            combine(
                &mut errors,
                Error::new_spanned(path, format!("option `{name}` is given twice")),
            );
            return Ok(());
        }
        given.push(name.clone());
        let result = match name.as_str() {
            "shape" => string(&value, &name, &shape_help()).map(|s| args.shape = Some(s)),
            "sections" => string(&value, &name, "a CSV section table's path, relative to the crate root")
                .map(|s| args.sections = Some(s)),
            "elements" => elements(&value).map(|n| args.elements = Some((n, value.clone()))),
            "modes" => modes(&value).map(|n| args.modes = Some((n, value.clone()))),
            "segments" => segments(&value).map(|n| args.segments = Some((n, value.clone()))),
            "reduction" => string(&value, &name, "\"modal\" or \"craig-bampton\"").and_then(|s| {
                args.modal_given.push(path.clone());
                let cb = match s.value().as_str() {
                    "modal" => false,
                    "craig-bampton" => true,
                    other => {
                        return Err(Error::new_spanned(
                            &s,
                            format!("unknown reduction `{other}`: expected \"modal\" or \"craig-bampton\""),
                        ))
                    }
                };
                args.craig_bampton = Some((cb, s));
                Ok(())
            }),
            "boundary_nodes" => {
                args.modal_given.push(path.clone());
                node_list(&value).map(|b| args.boundary = Some((b, value.clone())))
            }
            "modal_damping" => {
                args.modal_given.push(path.clone());
                let ratios = match &value {
                    Expr::Array(a) => a.elems.iter().map(number).collect::<Option<Vec<f64>>>(),
                    other => number(other).map(|z| vec![z]),
                };
                match ratios {
                    Some(z) => {
                        args.modal_damping = z;
                        Ok(())
                    }
                    None => Err(Error::new_spanned(
                        &value,
                        format!(
                            "`modal_damping` expects a ratio or a list of ratios (one per normal mode), found `{}`",
                            value.to_token_stream()
                        ),
                    )),
                }
            }
            "static_modes" => {
                args.modal_given.push(path.clone());
                match &value {
                    Expr::Lit(ExprLit { lit: Lit::Bool(b), .. }) => {
                        args.static_modes = Some(b.value);
                        Ok(())
                    }
                    other => Err(Error::new_spanned(
                        other,
                        format!("`static_modes` expects `true` or `false`, found `{}`", other.to_token_stream()),
                    )),
                }
            }
            "reference" => {
                string(&value, &name, "\"clamped\", \"pinned\" or \"free\"").and_then(|s| {
                    let r = s.value().parse().map_err(|e| Error::new_spanned(&s, e))?;
                    args.reference = Some(r);
                    Ok(())
                })
            }
            "formalism" => string(&value, &name, "\"consistent\" or \"lumped\"").and_then(|s| {
                args.options.formalism =
                    s.value().parse().map_err(|e| Error::new_spanned(&s, e))?;
                Ok(())
            }),
            "scene" => string(&value, &name, "\"planar\" or \"spatial\"").and_then(|s| {
                let d = s.value().parse::<SceneDim>().map_err(|_| {
                    Error::new_spanned(
                        &s,
                        format!(
                            "unknown scene `{}`: expected \"planar\" or \"spatial\"",
                            s.value()
                        ),
                    )
                })?;
                args.options.scene = Some(d);
                args.scene = Some(s);
                Ok(())
            }),
            _ => match &value {
                Expr::Lit(ExprLit {
                    lit: Lit::Bool(b), ..
                }) => {
                    args.options.stiffening = Stiffening::from_bool(b.value);
                    Ok(())
                }
                Expr::Lit(ExprLit {
                    lit: Lit::Str(st), ..
                }) if matches!(st.value().as_str(), "second-order" | "fourth-order" | "off") => {
                    args.options.stiffening = st.value().parse().expect("checked");
                    Ok(())
                }
                other => Err(Error::new_spanned(
                    other,
                    format!(
                        "`stiffening` expects `true`, `false`, \"second-order\" or \"fourth-order\", found `{}`",
                        other.to_token_stream()
                    ),
                )),
            },
        };
        if let Err(e) = result {
            combine(&mut errors, e);
        }
        Ok(())
    });
    syn::parse::Parser::parse2(parser, attr)?;
    let missing: Vec<&str> = ["shape", "elements"]
        .into_iter()
        .filter(|n| !given.iter().any(|g| g == n))
        .collect();
    if !missing.is_empty() {
        let missing: Vec<String> = missing.iter().map(|m| format!("`{m}`")).collect();
        combine(
            &mut errors,
            Error::new(
                Span::call_site(),
                format!(
                    "#[flex_body] needs {}: e.g. #[flex_body(shape = \"beam3\", elements = 8, reference = \"clamped\")]",
                    missing.join(" and ")
                ),
            ),
        );
    }
    if args.modes.is_none() && !given.iter().any(|g| g == "modes") {
        for p in &args.modal_given {
            combine(
                &mut errors,
                Error::new_spanned(
                    p,
                    format!(
                        "option `{}` belongs to a modal body: give `modes = K` too",
                        p.to_token_stream()
                    ),
                ),
            );
        }
    } else if let Some((_, expr)) = &args.modes {
        if args.params.is_none() {
            combine(
                &mut errors,
                Error::new_spanned(
                    expr,
                    "a modal body is reduced at build time: give its parameters, e.g. `params(length = 8.0, rho = 2766.67, area = 7.3e-5, iz = 8.2e-9, e = 6.9e10)`",
                ),
            );
        }
        let cb = args.craig_bampton.as_ref().is_some_and(|(cb, _)| *cb);
        if let (Some((_, e)), false) = (&args.boundary, cb) {
            combine(
                &mut errors,
                Error::new_spanned(e, "`boundary_nodes` needs `reduction = \"craig-bampton\"`"),
            );
        }
    }
    match errors {
        Some(e) => Err(e),
        None => Ok(args),
    }
}

/// A number literal, possibly negative.
fn number(value: &Expr) -> Option<f64> {
    match value {
        Expr::Lit(ExprLit {
            lit: Lit::Float(f), ..
        }) => f.base10_parse().ok(),
        Expr::Lit(ExprLit {
            lit: Lit::Int(i), ..
        }) => i.base10_parse::<f64>().ok(),
        Expr::Unary(syn::ExprUnary {
            op: syn::UnOp::Neg(_),
            expr,
            ..
        }) => number(expr).map(|x| -x),
        _ => None,
    }
}

fn modes(value: &Expr) -> Result<usize> {
    match value {
        Expr::Lit(ExprLit {
            lit: Lit::Int(i), ..
        }) => match i.base10_parse::<usize>() {
            Ok(n) if n >= 1 => Ok(n),
            _ => Err(Error::new_spanned(
                value,
                format!(
                    "`modes` must be a positive integer, found `{}`",
                    value.to_token_stream()
                ),
            )),
        },
        _ => Err(Error::new_spanned(
            value,
            format!(
                "`modes` must be a positive integer, found `{}`",
                value.to_token_stream()
            ),
        )),
    }
}

/// `segments = N`: an integer literal (its range and whether it divides
/// `elements` are checked with the body, `ffr_spec::check_segments`).
fn segments(value: &Expr) -> Result<usize> {
    let n = match value {
        Expr::Lit(ExprLit {
            lit: Lit::Int(i), ..
        }) => i.base10_parse::<usize>().ok(),
        _ => None,
    };
    n.ok_or_else(|| {
        Error::new_spanned(
            value,
            format!(
                "`segments` must be an integer from 1 to {} (the number of segments, a divisor of `elements`), found `{}`",
                ffr_codegen::MAX_SEGMENTS,
                value.to_token_stream()
            ),
        )
    })
}

/// `[0, 4]`: body node indices.
fn node_list(value: &Expr) -> Result<Vec<usize>> {
    let bad = || {
        Error::new_spanned(
            value,
            format!(
                "`boundary_nodes` expects a list of node indices, e.g. `[8]`, found `{}`",
                value.to_token_stream()
            ),
        )
    };
    let Expr::Array(a) = value else {
        return Err(bad());
    };
    a.elems
        .iter()
        .map(|e| match e {
            Expr::Lit(ExprLit {
                lit: Lit::Int(i), ..
            }) => i.base10_parse::<usize>().map_err(|_| bad()),
            _ => Err(bad()),
        })
        .collect()
}

fn shape_help() -> String {
    format!(
        "a built-in shape ({}) or a path to a .toml shape file",
        builtin_names().join(", ")
    )
}

fn string(value: &Expr, name: &str, allowed: &str) -> Result<LitStr> {
    match value {
        Expr::Lit(ExprLit {
            lit: Lit::Str(s), ..
        }) => Ok(s.clone()),
        other => Err(Error::new_spanned(
            other,
            format!(
                "`{name}` expects a string: {allowed}, found `{}`",
                other.to_token_stream()
            ),
        )),
    }
}

fn elements(value: &Expr) -> Result<usize> {
    let n = match value {
        Expr::Lit(ExprLit {
            lit: Lit::Int(i), ..
        }) => i.base10_parse::<usize>().ok(),
        _ => None,
    };
    match n {
        Some(n) if (1..=MAX_ELEMENTS).contains(&n) => Ok(n),
        _ => Err(Error::new_spanned(
            value,
            format!(
                "`elements` must be an integer from 1 to {MAX_ELEMENTS} (the number of equal elements), found `{}`",
                value.to_token_stream()
            ),
        )),
    }
}

fn parse_struct(item: TokenStream2) -> Result<ItemStruct> {
    const WANT: &str =
        "#[flex_body] applies to a struct with named `f64` fields (the body's parameters)";
    match syn::parse2::<Item>(item.clone()) {
        Ok(Item::Struct(s)) => match &s.fields {
            Fields::Named(_) => Ok(s),
            Fields::Unnamed(f) => Err(Error::new_spanned(f, format!("{WANT}, not a tuple struct"))),
            Fields::Unit => Err(Error::new_spanned(
                &s.ident,
                format!("{WANT}, not a unit struct"),
            )),
        },
        Ok(Item::Enum(e)) => Err(Error::new_spanned(
            e.enum_token,
            format!("{WANT}, not an enum"),
        )),
        Ok(Item::Union(u)) => Err(Error::new_spanned(
            u.union_token,
            format!("{WANT}, not a union"),
        )),
        _ => Err(Error::new_spanned(item, WANT)),
    }
}

/// Whether `ty` is written as `f64` (or `core::primitive::f64`, `std::primitive::f64`).
fn is_f64(ty: &Type) -> bool {
    match ty {
        Type::Group(g) => is_f64(&g.elem),
        Type::Paren(p) => is_f64(&p.elem),
        Type::Path(p) if p.qself.is_none() => {
            let segs: Vec<String> = p
                .path
                .segments
                .iter()
                .map(|s| {
                    if s.arguments.is_none() {
                        s.ident.to_string()
                    } else {
                        String::new()
                    }
                })
                .collect();
            let segs: Vec<&str> = segs.iter().map(String::as_str).collect();
            match segs.as_slice() {
                ["f64"] => p.path.leading_colon.is_none(),
                ["core" | "std", "primitive", "f64"] => true,
                _ => false,
            }
        }
        _ => false,
    }
}

fn expand(attr: TokenStream2, item: TokenStream2) -> Result<TokenStream2> {
    // Report problems with the options and with the item together.
    let (args, strukt) = match (parse_args(attr), parse_struct(item.clone())) {
        (Ok(a), Ok(s)) => (a, s),
        (Err(mut a), Err(s)) => {
            a.combine(s);
            return Err(a);
        }
        (Err(e), _) | (_, Err(e)) => return Err(e),
    };
    let shape_lit = args.shape.expect("checked");
    let (elements, elements_expr) = args.elements.expect("checked");
    let reference = args.reference.unwrap_or(Reference::Clamped);

    let manifest_dir = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("."));
    let type_name = strukt.ident.to_string();
    let body = flex_body::expand(&FlexBodyInput {
        shape: &shape_lit.value(),
        base: &manifest_dir,
        elements,
        reference,
        sections: args.sections.as_ref().map(LitStr::value).as_deref(),
        options: args.options,
        type_name: &type_name,
        runtime_path: &EmitOptions::default().runtime_path,
        modal: args.modes.as_ref().map(|(k, _)| {
            (
                args.params.as_ref().expect("checked").0,
                ffr_codegen::ModalSettings {
                    modes: *k,
                    // Craig–Bampton's boundary: the last node unless given.
                    boundary: match (&args.boundary, &args.craig_bampton) {
                        (Some((b, _)), _) => b.clone(),
                        (None, Some((true, _))) => vec![elements],
                        _ => Vec::new(),
                    },
                    static_modes: args.static_modes.unwrap_or(true),
                    damping: args.modal_damping.clone(),
                },
            )
        }),
        segments: args.segments.as_ref().map(|(n, _)| *n),
    })
    .map_err(|e| match e {
        FlexBodyError::Shape(e) => {
            let extra = match &e {
                ffr_codegen::Error::Shape { .. } => "shape file does not parse: ",
                ffr_codegen::Error::Io { .. } => "cannot read shape file: ",
                _ => "",
            };
            Error::new_spanned(&shape_lit, format!("{extra}{e}"))
        }
        e @ FlexBodyError::Scene(_) => Error::new_spanned(
            args.scene
                .as_ref()
                .expect("only an explicit scene can be too small"),
            e,
        ),
        FlexBodyError::Kernels(e) => Error::new_spanned(&shape_lit, e),
        FlexBodyError::Elements(e) => Error::new_spanned(&elements_expr, e),
        FlexBodyError::Sections(e) => Error::new_spanned(
            args.sections.as_ref().expect("only a given table can fail"),
            e,
        ),
        e @ FlexBodyError::Segments(_) => Error::new_spanned(
            &args
                .segments
                .as_ref()
                .expect("only a split body can fail so")
                .1,
            e,
        ),
        e @ FlexBodyError::Modal(_) => Error::new_spanned(
            &args
                .modes
                .as_ref()
                .expect("only a modal body can fail so")
                .1,
            e,
        ),
    })?;
    check_fields(&strukt, &body.params_used, &body.shape_name)?;
    let code = body.items;
    let impls = if strukt.generics.params.is_empty() && strukt.generics.where_clause.is_none() {
        code.parse::<TokenStream2>().map_err(|e| {
            Error::new(
                Span::call_site(),
                format!("ffr-codegen produced invalid Rust (a bug): {e}"),
            )
        })?
    } else {
        with_generics(&code, &strukt)?
    };
    let rebuild = body
        .shape_file
        .into_iter()
        .chain(body.sections_file)
        .map(|p| {
            let p = p.canonicalize().unwrap_or(p);
            let p = p.to_string_lossy();
            quote!(
                const _: &[u8] = ::core::include_bytes!(#p);
            )
        });
    // The item exactly as written.
    Ok(quote! {
        #item
        #(#rebuild)*
        #impls
    })
}

/// A type as written, without the spaces between tokens that `to_string` adds.
fn show_type(ty: &Type) -> String {
    let s = ty.to_token_stream().to_string();
    let mut out = String::with_capacity(s.len());
    let chars: Vec<char> = s.chars().collect();
    for (i, &c) in chars.iter().enumerate() {
        let prev = i.checked_sub(1).map(|j| chars[j]);
        let next = chars.get(i + 1).copied();
        let glue = |x: Option<char>| {
            matches!(
                x,
                Some('<' | '>' | ':' | '&' | '(' | ')' | '[' | ']' | ',' | '\'')
            )
        };
        if c == ' ' && (glue(prev) || glue(next)) && prev != Some(',') && next != Some('=') {
            continue;
        }
        out.push(c);
    }
    out
}

/// Every parameter the body uses must be a field of type `f64`.
fn check_fields(strukt: &ItemStruct, used: &[Param], shape: &str) -> Result<()> {
    let mut errors = None;
    let mut missing = Vec::new();
    for &p in used {
        let name = p.field();
        match strukt
            .fields
            .iter()
            .find(|f| f.ident.as_ref().is_some_and(|i| i.unraw() == name))
        {
            None => missing.push(name),
            Some(f) if !is_f64(&f.ty) => combine(
                &mut errors,
                Error::new_spanned(
                    &f.ty,
                    format!(
                        "field `{name}` is a parameter of shape `{shape}` and must be `f64`, found `{}`",
                        show_type(&f.ty)
                    ),
                ),
            ),
            Some(_) => {}
        }
    }
    if !missing.is_empty() {
        let all: Vec<&str> = used.iter().map(|p| p.field()).collect();
        combine(
            &mut errors,
            Error::new_spanned(
                &strukt.ident,
                format!(
                    "struct `{}` is missing the field{} {}: shape `{shape}` needs the `f64` fields {} (other fields are allowed)",
                    strukt.ident,
                    if missing.len() == 1 { "" } else { "s" },
                    missing.iter().map(|m| format!("`{m}: f64`")).collect::<Vec<_>>().join(", "),
                    all.join(", ")
                ),
            ),
        );
    }
    match errors {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The generated impls for a generic struct: each `impl Trait for Name` becomes
/// `impl<..> Trait for Name<..> where ..`.
fn with_generics(code: &str, strukt: &ItemStruct) -> Result<TokenStream2> {
    let mut file = syn::parse_file(code).map_err(|e| {
        Error::new(
            Span::call_site(),
            format!("ffr-codegen produced invalid Rust (a bug): {e}"),
        )
    })?;
    let ident = &strukt.ident;
    let (_, ty_generics, _) = strukt.generics.split_for_impl();
    let self_ty: Type = syn::parse_quote!(#ident #ty_generics);
    let plain: Type = syn::parse_quote!(#ident);
    for item in &mut file.items {
        if let Item::Impl(imp) = item {
            // Only the impls for the user's struct (not its kernel type).
            if imp.self_ty.to_token_stream().to_string() == plain.to_token_stream().to_string() {
                imp.generics = strukt.generics.clone();
                *imp.self_ty = self_ty.clone();
            }
        }
    }
    Ok(file.into_token_stream())
}
