//! Limits on the input and checks on the output of the generator.
//!
//! The generator works in exact arithmetic, so an unusual shape file can ask
//! for an unbounded amount of work (`((1+xi)^8)^64`), memory (`/dev/zero`),
//! stack (50 000 nested parentheses) or exponents that no longer fit
//! (`xi^(64^5)` squared). Every limit below is checked *before* the work it
//! bounds is done, and a violation is an [`Error`] at
//! `file:line:column` naming the limit. The values keep every legitimate
//! beam shape far inside them (the built-in `beam3` uses degree 3 in `ξ`,
//! degree 1 in `l`, `η`, `ζ`, at most 4 terms and 12 coordinates), and keep
//! what the generator does with a shape afterwards (products of two entries
//! of `S`, fourth powers of derivative fields for stiffening energies) within
//! `i32` exponents and seconds of work.
//!
//! The checks on results: parameter values that are physically invalid
//! ([`check_params`]) and literals of generated code that are not finite
//! ([`check_literals`]). The generator evaluates nothing in floating point;
//! numbers that are not finite or a mass matrix whose diagonal is not
//! positive are checked where a body is evaluated at given parameters (the
//! runtime refuses coefficients that are not finite, `ffr invariants`
//! checks every invariant).

use crate::error::Error;
use crate::kernel::KernelSet;
use crate::poly::Param;
use crate::program::{Expr, Program};
use ffr_spec::Params;

/// Largest shape file read, in bytes (1 MiB). A shape file is a few hundred
/// bytes to a few kilobytes; the file is read through a bound, so
/// `--shape /dev/zero` fails at once instead of filling memory.
pub const MAX_SOURCE_BYTES: u64 = 1 << 20;

/// Deepest nesting of parentheses in a polynomial string. Shape functions
/// need two or three levels; the parser recurses once per level (unary signs
/// are read in a loop and cost no depth), so this bounds its stack use,
/// also inside `rustc` when `#[flex_body]` reads the file.
pub const MAX_NESTING_DEPTH: usize = 32;

/// Largest exponent written after `^`. Together with
/// [`MAX_SYMBOL_DEGREE`], [`MAX_L_DEGREE`] and [`MAX_COEFFICIENT_BITS`]
/// (which nested powers must also respect, checked before a power is
/// expanded) it only matters for
/// constants (`2^64` is fine, `xi^9` is refused by the degree limit).
pub const MAX_EXPONENT: u32 = 64;

/// Highest power of `xi`, `eta` or `zeta` in an entry of `S` and in every
/// intermediate result while it is parsed (a final entry is moreover at most
/// linear in `eta` and `zeta`, see [`crate::shape`]). With two nodes and at
/// most a value and a slope per node, beam shapes are at most cubic in `ξ`
/// (Hermite); 8 leaves room for bubble enrichments. Downstream the generator
/// multiplies entries pairwise (degree 16) and raises derivative fields to
/// the fourth power for stiffening energies (degree 32): far inside `i32`,
/// and the cost of those products stays bounded.
pub const MAX_SYMBOL_DEGREE: u32 = 8;

/// Highest power of the element length `l` in every intermediate result
/// while an entry is parsed. A finished entry has the units of its
/// coordinate (checked in [`crate::shape`]): every term of a translation's
/// column has `l⁰`, every term of a rotation's `l¹` (`l·(ξ − 2ξ² + ξ³)`).
/// The number of distinct powers of `l` multiplies the size of the
/// stiffening energy, whose exact expansion grows with its square.
pub const MAX_L_DEGREE: u32 = 2;

/// Highest total degree (sum of the exponents of `xi, eta, zeta, l`) of a
/// term of an entry and of every intermediate result (`beam3`: 4).
pub const MAX_TOTAL_DEGREE: u32 = 12;

/// Most terms of an entry of `S` after expansion, and of every intermediate
/// result while it is parsed. A power is refused *before* it is expanded when
/// the number of terms it could have (the smaller of the multinomial count
/// and the product of the degree bounds per symbol) exceeds this. A Hermite
/// cubic has 4 terms, the longest entry of `beam3` 3.
pub const MAX_ENTRY_TERMS: usize = 32;

/// Most terms of all entries of `S` together (`beam3` has 47). The
/// invariants multiply entries pairwise, so their cost grows with the square
/// of this number (and with [`MAX_COEFFICIENT_BITS`]): at the limits, the
/// exact invariants of a 2-element body of a spatial shape of 12
/// coordinates take about half a second in the test profile, all of its
/// element kernels 2–4 s with or without stiffening (the costliest-shape
/// tests of `codegen/tests/regressions.rs`).
pub const MAX_SHAPE_TERMS: usize = 128;

/// Most bits of the numerator and of the denominator of any coefficient of an
/// entry, of a number literal and of every intermediate result: 128 bits,
/// about 38 significant decimal digits, more than twice what `f64` holds.
/// Exact sums of fractions cost a gcd each, whose time grows with the square
/// of the size; this bound keeps the pairwise products of the invariants fast.
/// A larger coefficient (`1e300`) is refused where it is written.
pub const MAX_COEFFICIENT_BITS: u64 = 128;

/// Most coordinates (columns of `S`) of a shape: each of the two nodes has
/// at most the six kinds `ux uy uz rx ry rz`, each once.
pub const MAX_COORDINATES: usize = 12;

/// Longest shape name, in characters (from `[A-Za-z0-9_.-]`).
pub const MAX_SHAPE_NAME_CHARS: usize = 64;

/// Longest coordinate name, in characters (from `[A-Za-z0-9_.-]`).
pub const MAX_COORDINATE_NAME_CHARS: usize = 32;

/// Longest shape description, in characters (any text; it is escaped with
/// [`crate::sanitize::comment_text`] wherever it is shown in a comment).
pub const MAX_DESCRIPTION_CHARS: usize = 1024;

/// Longest type name (`--type-name`) or body name (`Builder::body`).
pub const MAX_IDENTIFIER_CHARS: usize = 64;

/// Most elements of a body (also the `elements` range of the command line
/// and of `#[flex_body]`).
pub const MAX_ELEMENTS: usize = crate::body::MAX_ELEMENTS;

/// What a parameter is, for messages.
fn param_meaning(p: Param) -> &'static str {
    match p {
        Param::ElemLength => "element length l",
        Param::Length => "body length L, m",
        Param::Rho => "density ρ, kg/m³",
        Param::Area => "cross-section area A, m²",
        Param::Iy => "second moment I_y = ∫z² dA, m⁴",
        Param::Iz => "second moment I_z = ∫y² dA, m⁴",
        Param::E => "Young's modulus E, Pa",
        Param::G => "shear modulus G, Pa",
        Param::J => "torsion constant J, m⁴",
    }
}

/// Check parameter values before they are used: every value finite;
/// `length`, `rho`, `area`, `e` strictly positive; `iy`, `iz`, `g`, `j` not
/// negative ([`Params::validate`]), and strictly positive when the body uses
/// them ([`Params::validate_only`], `used` e.g. [`KernelSet::params_used`];
/// `&[]` checks only the first part). The error names the parameter.
pub fn check_params(p: &Params, used: &[Param]) -> Result<(), Error> {
    p.validate()
        .and_then(|()| p.validate_only(used))
        .map_err(|e| Error::Parameter {
            name: e.param.field().to_string(),
            message: format!("{} ({})", e.reason(), param_meaning(e.param)),
        })
}

/// Check every literal of the generated programs: a literal that is not
/// finite (an exact coefficient beyond the range of `f64`) would be emitted
/// as `inf` or `NaN`, which is not Rust. The error names the quantity the
/// literal belongs to (the program's output, or the temporary).
pub fn check_literals(set: &KernelSet) -> Result<(), Error> {
    check_program(&set.coefficient_program, "coefficients()")?;
    if let Some(p) = &set.section_coefficient_program {
        check_program(p, "section_coefficients()")?;
    }
    for (function, p) in set.programs() {
        check_program(p, function)?;
    }
    Ok(())
}

fn check_program(p: &Program, function: &str) -> Result<(), Error> {
    let bad = |what: String, x: f64| {
        Error::Invalid {
        quantity: what,
        message: format!(
            "has the coefficient {x} in {function}: an exact coefficient of the shape's integrals is beyond the range of f64, and generated code cannot contain it (scale the shape's coefficients)"
        ),
    }
    };
    for (slot, e) in &p.stmts {
        if let Some(x) = non_finite_literal(e) {
            let name = p.names.get(*slot as usize).cloned().unwrap_or_default();
            return Err(bad(format!("the temporary `{name}`"), x));
        }
    }
    for (t, e) in &p.outputs {
        if let Some(x) = non_finite_literal(e) {
            return Err(bad(format!("{t:?}"), x));
        }
    }
    Ok(())
}

/// The first literal of `e` that is not finite (iteratively: sums of many
/// terms are deep left-leaning trees).
fn non_finite_literal(e: &Expr) -> Option<f64> {
    let mut stack = vec![e];
    while let Some(e) = stack.pop() {
        match e {
            Expr::Lit(x) if !x.is_finite() => return Some(*x),
            Expr::Var(_) | Expr::Lit(_) => {}
            Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) | Expr::Div(a, b) => {
                stack.push(a);
                stack.push(b);
            }
            Expr::Neg(a) => stack.push(a),
        }
    }
    None
}

/// Read an input file (shape, scene, data) through a bound of `max_bytes`.
/// Only a regular file (or a symbolic link to one) is read: a directory, a
/// FIFO, a device or a socket is refused from its metadata, before it is
/// opened (so a FIFO cannot block the reader and `/dev/zero` cannot fill
/// memory), and the file is read with `take(max_bytes + 1)`, so a file that
/// grows while it is read is refused too. `what` names the kind of file
/// (`"shape file"`) and `limit` the bound (`"MAX_SOURCE_BYTES"`) in messages;
/// the error is the message only (the caller adds the path).
pub fn read_input(
    path: &std::path::Path,
    max_bytes: u64,
    what: &str,
    limit: &str,
) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if meta.is_dir() {
        return Err(format!("is a directory, not a {what}"));
    }
    if !meta.is_file() {
        return Err(format!(
            "is {}, not a regular file: a {what} must be a regular file (not read)",
            special_kind(&meta.file_type())
        ));
    }
    let too_large =
        || format!("larger than {max_bytes} bytes, the limit for {what}s ({limit}): not read");
    if meta.len() > max_bytes {
        return Err(too_large());
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut bytes = Vec::new();
    file.take(max_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}

/// What a file that is neither a regular file nor a directory is.
pub fn special_kind(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    let _ = t;
    "a special file"
}
