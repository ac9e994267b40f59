//! Shape descriptions: the element shape-function matrix `S` of a flexible
//! body, read from TOML (built-in `beam2`, `beam3` go through the same parser).
//!
//! ```toml
//! name = "bar2"
//! dimension = 2                      # 2: rows x, y; 3: rows x, y, z
//! coordinates = [                    # one per column of S
//!   { name = "u1", node = 0, kind = "ux" },   # node 0 = element start, 1 = end
//!   { name = "u2", node = 1, kind = "ux" },
//! ]
//! [S]                                # rows of S, polynomials in xi, eta, zeta, l
//! x = ["1 - xi", "xi"]
//! y = ["0", "0"]
//! ```

use crate::error::{Error, Location};
use crate::expr::parse_poly;
use crate::limits::{
    MAX_COORDINATES, MAX_COORDINATE_NAME_CHARS, MAX_DESCRIPTION_CHARS, MAX_SHAPE_NAME_CHARS,
    MAX_SHAPE_TERMS, MAX_SOURCE_BYTES,
};
use crate::poly::{Poly, Sym};
use crate::sanitize::{check_name, snippet};
use std::collections::BTreeMap;
use std::path::Path;
use toml::de::DeTable;

mod raw;

use raw::RawShape;

pub use ffr_spec::Kind;

/// One elastic coordinate of an element (a column of `S`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Coordinate {
    /// Name in the shape file (e.g. `v1`).
    pub name: String,
    /// End node: 0 at `ξ = 0`, 1 at `ξ = 1`.
    pub node: u8,
    /// Which nodal quantity it is.
    pub kind: Kind,
}

/// A validated shape: the element `S` (dimension × n_e) with exact entries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Shape {
    /// Shape name.
    pub name: String,
    /// 2 (planar, rows x, y) or 3 (rows x, y, z).
    pub dimension: usize,
    /// One-line description.
    pub description: String,
    /// Columns of `S`.
    pub coordinates: Vec<Coordinate>,
    /// `rows[k][a]`: entry of row `k` (x, y, z) and column `a`.
    pub rows: Vec<Vec<Poly>>,
    /// Where the shape came from: `built-in beam3` or the file path.
    pub origin: String,
    /// FNV-1a hash of the source text (names the input in generated headers).
    pub source_hash: u64,
    /// The file the shape was read from, if any (for `rerun-if-changed`).
    pub path: Option<std::path::PathBuf>,
}

const BUILTINS: [(&str, &str); 2] = [
    ("beam2", include_str!("../../shapes/beam2.toml")),
    ("beam3", include_str!("../../shapes/beam3.toml")),
];

/// Names of the built-in shapes.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTINS.iter().map(|(n, _)| *n).collect()
}

/// FNV-1a, 64 bit: a stable hash of a shape's text for generated headers.
pub fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

impl Shape {
    /// A built-in shape by name (`beam2`, `beam3`).
    pub fn builtin(name: &str) -> Option<Result<Shape, Error>> {
        BUILTINS
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(n, text)| Shape::parse(text, &format!("built-in {n}")))
    }

    /// Read a shape file (at most [`MAX_SOURCE_BYTES`], UTF-8).
    pub fn from_file(path: &Path) -> Result<Shape, Error> {
        let text = read_source(path)?;
        let mut shape = Shape::parse(&text, &path.display().to_string())?;
        shape.path = Some(path.to_path_buf());
        Ok(shape)
    }

    /// A built-in name, or else a path to a shape file (relative paths
    /// against `base`).
    pub fn resolve(name_or_path: &str, base: Option<&Path>) -> Result<Shape, Error> {
        if let Some(s) = Shape::builtin(name_or_path) {
            return s;
        }
        let looks_like_path = name_or_path.ends_with(".toml")
            || name_or_path.contains('/')
            || name_or_path.contains('\\');
        if !looks_like_path {
            return Err(Error::UnknownShape {
                name: name_or_path.to_string(),
                known: builtin_names().join(", "),
            });
        }
        let p = Path::new(name_or_path);
        let full = match base {
            Some(b) if p.is_relative() => b.join(p),
            _ => p.to_path_buf(),
        };
        Shape::from_file(&full)
    }

    /// Parse and validate a shape description; `origin` names it in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Shape, Error> {
        let shown_origin = snippet(origin, usize::MAX);
        let at = |offset: usize, message: String| Error::Shape {
            location: Location::of(&shown_origin, text, offset),
            message,
        };
        if text.len() as u64 > MAX_SOURCE_BYTES {
            return Err(at(
                0,
                format!(
                    "the shape description is {} bytes long: more than the limit of {MAX_SOURCE_BYTES} bytes (MAX_SOURCE_BYTES)",
                    text.len()
                ),
            ));
        }
        let doc = DeTable::parse(text).map_err(|e| {
            let offset = e.span().map_or(text.len(), |s| s.start);
            at(
                offset,
                toml_message(&parser_message(&e, text), text, offset),
            )
        })?;
        let raw = RawShape::read(&doc)
            .map_err(|(offset, message)| at(offset, toml_message(&message, text, offset)))?;
        let name = raw.name.get_ref();
        check_name(name, "shape name", MAX_SHAPE_NAME_CHARS).map_err(|(i, m)| {
            at(
                string_content_offset(text, raw.name.span().start, name) + i,
                m,
            )
        })?;
        if raw.description.chars().count() > MAX_DESCRIPTION_CHARS {
            return Err(at(
                0,
                format!(
                    "the description is {} characters long: at most {MAX_DESCRIPTION_CHARS} are allowed (MAX_DESCRIPTION_CHARS)",
                    raw.description.chars().count()
                ),
            ));
        }

        let dimension = *raw.dimension.get_ref();
        if dimension != 2 && dimension != 3 {
            return Err(at(
                raw.dimension.span().start,
                format!("dimension must be 2 (planar) or 3 (spatial), found {dimension}"),
            ));
        }
        let dimension = dimension as usize;

        if raw.coordinates.get_ref().len() > MAX_COORDINATES {
            return Err(at(
                raw.coordinates.span().start,
                format!(
                    "{} coordinates: a shape has at most {MAX_COORDINATES} (each of the two nodes at most once each of ux, uy, uz, rx, ry, rz)",
                    raw.coordinates.get_ref().len()
                ),
            ));
        }
        let mut coordinates = Vec::new();
        let mut seen_names = BTreeMap::new();
        let mut seen_slots = BTreeMap::new();
        for c in raw.coordinates.get_ref() {
            let name = c.name.get_ref().clone();
            check_name(&name, "coordinate name", MAX_COORDINATE_NAME_CHARS).map_err(|(i, m)| {
                at(
                    string_content_offset(text, c.name.span().start, &name) + i,
                    m,
                )
            })?;
            if seen_names.insert(name.clone(), ()).is_some() {
                return Err(at(
                    c.name.span().start,
                    format!("coordinate `{name}` appears twice"),
                ));
            }
            let node = *c.node.get_ref();
            if node != 0 && node != 1 {
                return Err(at(
                    c.node.span().start,
                    format!("node must be 0 (element start) or 1 (element end), found {node}"),
                ));
            }
            let kind_name = c.kind.get_ref().as_str();
            let kind = Kind::ALL
                .iter()
                .find(|(_, n)| *n == kind_name)
                .map(|(k, _)| *k)
                .ok_or_else(|| {
                    at(
                        c.kind.span().start,
                        format!(
                            "unknown kind `{kind_name}`: expected one of ux, uy, uz, rx, ry, rz"
                        ),
                    )
                })?;
            if dimension == 2 && !kind.is_planar() {
                return Err(at(
                    c.kind.span().start,
                    format!(
                        "kind `{kind}` does not exist in a planar shape: expected ux, uy or rz"
                    ),
                ));
            }
            if let Some(other) = seen_slots.insert((node, kind), name.clone()) {
                return Err(at(
                    c.kind.span().start,
                    format!("node {node} has two `{kind}` coordinates (`{other}` and `{name}`)"),
                ));
            }
            coordinates.push(Coordinate {
                name,
                node: node as u8,
                kind,
            });
        }
        if coordinates.is_empty() {
            return Err(at(
                raw.coordinates.span().start,
                "a shape needs at least one coordinate".into(),
            ));
        }
        let kinds_at = |n: u8| -> Vec<Kind> {
            let mut k: Vec<Kind> = coordinates
                .iter()
                .filter(|c| c.node == n)
                .map(|c| c.kind)
                .collect();
            k.sort();
            k
        };
        if kinds_at(0) != kinds_at(1) {
            let show = |v: Vec<Kind>| v.iter().map(|k| k.name()).collect::<Vec<_>>().join(", ");
            return Err(at(
                raw.coordinates.span().start,
                format!(
                    "node 0 has kinds [{}] and node 1 has [{}]: elements share nodes, so both ends need the same kinds",
                    show(kinds_at(0)),
                    show(kinds_at(1))
                ),
            ));
        }

        let row_names = &["x", "y", "z"][..dimension];
        let table = raw.s.get_ref();
        for (key, _) in table.iter() {
            if !row_names.contains(&key.get_ref().as_str()) {
                return Err(at(
                    key.span().start,
                    format!(
                        "unexpected row `{}`: a shape of dimension {dimension} has rows {}",
                        key.get_ref(),
                        row_names.join(", ")
                    ),
                ));
            }
        }
        let mut rows = Vec::new();
        let mut shape_terms = 0usize;
        for &r in row_names {
            let (_, entries) = table
                .iter()
                .find(|(k, _)| k.get_ref() == r)
                .ok_or_else(|| {
                    at(
                        raw.s.span().start,
                        format!(
                        "row `{r}` of S is missing: a shape of dimension {dimension} has rows {}",
                        row_names.join(", ")
                    ),
                    )
                })?;
            if entries.get_ref().len() != coordinates.len() {
                return Err(at(
                    entries.span().start,
                    format!(
                        "row `{r}` has {} entries, expected {} (one per coordinate)",
                        entries.get_ref().len(),
                        coordinates.len()
                    ),
                ));
            }
            let mut row = Vec::new();
            for (a, entry) in entries.get_ref().iter().enumerate() {
                let content_start =
                    string_content_offset(text, entry.span().start, entry.get_ref());
                let shown = snippet(entry.get_ref(), 60);
                let poly = parse_poly(entry.get_ref()).map_err(|e| {
                    at(
                        content_start + e.offset,
                        format!("S[{r}][{}] (`{shown}`): {}", coordinates[a].name, e.message),
                    )
                })?;
                check_units(&poly, coordinates[a].kind).map_err(|m| {
                    at(
                        content_start,
                        format!("S[{r}][{}] (`{shown}`): {m}", coordinates[a].name),
                    )
                })?;
                check_entry(&poly, dimension).map_err(|m| {
                    at(
                        content_start,
                        format!("S[{r}][{}] (`{shown}`): {m}", coordinates[a].name),
                    )
                })?;
                shape_terms += poly.len();
                if shape_terms > MAX_SHAPE_TERMS {
                    return Err(at(
                        content_start,
                        format!(
                            "S[{r}][{}] (`{shown}`): the entries of S have {shape_terms} terms together up to here, more than the limit of {MAX_SHAPE_TERMS} (MAX_SHAPE_TERMS)",
                            coordinates[a].name
                        ),
                    ));
                }
                row.push(poly);
            }
            rows.push(row);
        }
        // A coordinate whose column of S is zero moves nothing: it would have
        // no mass and no stiffness.
        for (a, c) in raw.coordinates.get_ref().iter().enumerate() {
            if rows.iter().all(|row| row[a].is_zero()) {
                return Err(at(
                    c.name.span().start,
                    format!(
                        "coordinate `{}` has a zero column in S: it moves nothing, so it would have no mass and no stiffness",
                        coordinates[a].name
                    ),
                ));
            }
        }
        Ok(Shape {
            name: raw.name.into_inner(),
            dimension,
            description: raw.description,
            coordinates,
            rows,
            origin: origin.to_string(),
            source_hash: fnv1a(text),
            path: None,
        })
    }

    /// Number of element coordinates `n_e`.
    pub fn n_elem(&self) -> usize {
        self.coordinates.len()
    }

    /// The element coordinates as the mesh numbering sees them.
    pub fn element_coordinates(&self) -> Vec<ffr_spec::ElementCoordinate> {
        self.coordinates
            .iter()
            .map(|c| ffr_spec::ElementCoordinate {
                node: c.node,
                kind: c.kind,
            })
            .collect()
    }

    /// Kinds of one node in the order of the node-0 coordinates.
    pub fn node_kinds(&self) -> Vec<Kind> {
        self.coordinates
            .iter()
            .filter(|c| c.node == 0)
            .map(|c| c.kind)
            .collect()
    }
}

/// Read a shape file through a bound of [`MAX_SOURCE_BYTES`] (so that a
/// device or a huge file fails at once), as UTF-8.
fn read_source(path: &Path) -> Result<String, Error> {
    let shown = snippet(&path.display().to_string(), usize::MAX);
    let io = |message: String| Error::Io {
        path: shown.clone(),
        message,
    };
    let bytes = crate::limits::read_input(path, MAX_SOURCE_BYTES, "shape file", "MAX_SOURCE_BYTES")
        .map_err(io)?;
    String::from_utf8(bytes).map_err(|e| {
        let good = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let valid = std::str::from_utf8(&bytes[..good]).unwrap_or_default();
        Error::Shape {
            location: Location::of(&shown, valid, good),
            message: format!(
                "the file is not UTF-8 text (byte 0x{:02x} at byte offset {good})",
                bytes[good]
            ),
        }
    })
}

/// The TOML parser's message, with the key named where it says only
/// `duplicate key` (its span is the repeated key).
pub(crate) fn parser_message(e: &toml::de::Error, text: &str) -> String {
    let m = e.message().trim();
    let key = e.span().and_then(|s| text.get(s)).map(str::trim);
    match key {
        Some(k) if m == "duplicate key" && !k.is_empty() => {
            format!("duplicate key `{}`", snippet(k, 64))
        }
        _ => m.to_string(),
    }
}

/// The TOML parser's message, completed where it is empty or says only
/// that the input ended.
fn toml_message(message: &str, text: &str, offset: usize) -> String {
    let lines: Vec<&str> = message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let joined = lines.join(": ");
    let m = joined.as_str();
    let at_end = text.get(offset..).is_none_or(|rest| rest.trim().is_empty());
    if m.contains("recursion") {
        return format!("{m}: arrays or tables nest too deeply");
    }
    if m.is_empty() {
        if at_end {
            "the file ends too early: a string, array, inline table or value is not finished (is the file truncated?)".into()
        } else {
            "invalid TOML here".into()
        }
    } else if at_end && !m.contains("missing field") {
        format!("{m} (the file ends here: is it truncated?)")
    } else {
        m.to_string()
    }
}

/// Every term of a column of `S` must have the units of the displacement
/// per unit of its coordinate: `ξ`, `η = y/l`, `ζ = z/l` and the numbers are
/// dimensionless, so a translation's entries have no factor `l` and a
/// rotation's (radians) exactly one. Beyond physics this matters for the
/// numbers: a column that mixes powers of `l` (`ξη(1 − l)`) has a mass that
/// cancels in floating point (exactly zero at `l = 1`), while a homogeneous
/// column's mass is a sum of non-negative terms, positive when evaluated.
fn check_units(p: &Poly, kind: Kind) -> Result<(), String> {
    let want = if kind.is_translation() { 0 } else { 1 };
    for (m, _) in p.terms() {
        let got = m.exp(Sym::Param(crate::poly::Param::ElemLength));
        if got != want {
            return Err(if want == 0 {
                format!(
                    "the term `{m}` has the factor l^{got}, but the shape of a translation coordinate ({kind}) is dimensionless: no factor l (xi, eta = y/l and zeta = z/l are dimensionless)"
                )
            } else {
                format!(
                    "the term `{m}` has {}, but every term of the shape of a rotation coordinate ({kind}) needs exactly one factor l (a rotation moves points by a length, e.g. `l*(xi - 2*xi^2 + xi^3)`)",
                    if got == 0 { "no factor l".to_string() } else { format!("the factor l^{got}") }
                )
            });
        }
    }
    Ok(())
}

/// An entry may use only section moments the model has: every monomial is at
/// most linear in `η, ζ` together (products of two entries then need at most
/// `∫y² dA`, `∫z² dA`, `∫yz dA`), and a planar shape has no `ζ`.
fn check_entry(p: &Poly, dimension: usize) -> Result<(), String> {
    for (m, _) in p.terms() {
        let (a, b) = (m.exp(Sym::Eta), m.exp(Sym::Zeta));
        if dimension == 2 && b != 0 {
            return Err(format!(
                "the term `{m}` uses zeta, which a planar shape does not have"
            ));
        }
        if a + b > 1 {
            let moment = match (a, b) {
                (a, 0) => format!("∫y^{} dA", 2 * a),
                (0, b) => format!("∫z^{} dA", 2 * b),
                (a, b) => format!("∫y^{} z^{} dA", 2 * a, 2 * b),
            };
            return Err(format!(
                "the term `{m}` needs the section moment {moment}, which the model does not have (only A, I_y = ∫z² dA, I_z = ∫y² dA): entries may be at most linear in eta and zeta"
            ));
        }
    }
    Ok(())
}

/// Byte offset of a TOML string value's content, given the span start of the
/// value (at its opening quote). Exact when the string has no escapes.
fn string_content_offset(text: &str, start: usize, content: &str) -> usize {
    let rest = &text[start.min(text.len())..];
    let q = if rest.starts_with("\"\"\"") || rest.starts_with("'''") {
        3
    } else {
        1
    };
    let body = start + q;
    if text.get(body..body + content.len()) == Some(content) {
        body
    } else {
        start
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BAR: &str = "name = \"bar\"\ndimension = 2\ncoordinates = [\n  { name = \"u1\", node = 0, kind = \"ux\" },\n  { name = \"u2\", node = 1, kind = \"ux\" },\n]\n[S]\nx = [\"1 - xi\", \"xi\"]\ny = [\"0\", \"0\"]\n";

    /// The error for `BAR` with `from` replaced by `to`.
    fn refused(from: &str, to: &str) -> String {
        assert!(BAR.contains(from), "test setup: `{from}`");
        match Shape::parse(&BAR.replacen(from, to, 1), "bar.toml") {
            Ok(_) => panic!("`{to}` was accepted"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn wrong_types_are_named_at_the_value() {
        let cases = [
            (
                "name = \"bar\"",
                "name = 3",
                "bar.toml:1:8: invalid type: integer `3`, expected a string",
            ),
            (
                "dimension = 2",
                "dimension = 2.0",
                "bar.toml:2:13: invalid type: floating point `2.0`, expected i64",
            ),
            (
                "dimension = 2",
                "dimension = \"2\"",
                "bar.toml:2:13: invalid type: string \"2\", expected i64",
            ),
            (
                "dimension = 2",
                "dimension = 99999999999999999999",
                "bar.toml:2:13: number too large to fit in target type",
            ),
            (
                "node = 0,",
                "node = 0x,",
                "bar.toml:4:25: invalid integer `0x`",
            ),
            (
                "node = 0,",
                "node = true,",
                "bar.toml:4:25: invalid type: boolean `true`, expected i64",
            ),
            (
                "coordinates = [",
                "coordinates = 3\nc = [",
                "bar.toml:3:15: invalid type: integer `3`, expected a sequence",
            ),
            (
                "{ name = \"u1\", node = 0, kind = \"ux\" }",
                "[\"u1\", 0, \"ux\"]",
                "bar.toml:4:3: invalid type: sequence, expected struct RawCoordinate",
            ),
            (
                "[S]\n",
                "S = [1]\n[T]\n",
                "bar.toml:7:5: invalid type: sequence, expected a map",
            ),
            (
                "x = [\"1 - xi\", \"xi\"]",
                "x = \"xi\"",
                "bar.toml:8:5: invalid type: string \"xi\", expected a sequence",
            ),
            (
                "x = [\"1 - xi\", \"xi\"]",
                "x = [\"1 - xi\", 1979-05-27]",
                "bar.toml:8:16: invalid type: datetime `1979-05-27`, expected a string",
            ),
        ];
        for (from, to, want) in cases {
            assert_eq!(refused(from, to), want);
        }
    }

    #[test]
    fn unknown_and_missing_fields_are_refused_where_they_are() {
        assert_eq!(
            refused("dimension = 2", "dimension = 2\ncolour = 3"),
            "bar.toml:3:1: unknown field `colour`, expected one of `name`, `dimension`, `description`, `coordinates`, `S`"
        );
        assert_eq!(
            refused("kind = \"ux\" }", "kind = \"ux\", mass = 1 }"),
            "bar.toml:4:41: unknown field `mass`, expected one of `name`, `node`, `kind`"
        );
        assert_eq!(
            refused(", kind = \"ux\" }", " }"),
            "bar.toml:4:3: missing field `kind`"
        );
        assert_eq!(refused("[S]\nx", "[T]\nx"), "bar.toml:7:2: unknown field `T`, expected one of `name`, `dimension`, `description`, `coordinates`, `S`");
        assert_eq!(
            refused("name = \"bar\"\n", ""),
            "bar.toml:1:1: missing field `name`"
        );
    }

    #[test]
    fn the_first_refusal_in_the_file_is_reported() {
        // `zeta` sorts after `name`, but comes first in the file.
        let e = refused("name = \"bar\"", "zeta = 1\nname = 3");
        assert!(e.starts_with("bar.toml:1:1: unknown field `zeta`"), "{e}");
    }
}
