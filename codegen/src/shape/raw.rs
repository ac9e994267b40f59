//! A shape file as written, read from toml's span-keeping tables without
//! serde: unknown keys refused, wrong types and missing fields named in
//! serde's words, every place at its `line:col`.

use std::collections::BTreeMap;
use std::num::IntErrorKind;
use toml::de::{DeArray, DeInteger, DeString, DeTable, DeValue};
use toml::Spanned;

/// A shape file as written: every value keeps its span for the errors.
pub(super) struct RawShape {
    pub(super) name: Spanned<String>,
    pub(super) dimension: Spanned<i64>,
    pub(super) description: String,
    pub(super) coordinates: Spanned<Vec<RawCoordinate>>,
    pub(super) s: Spanned<RawRows>,
}

/// The rows of `S` as written: by row name, the entries of each.
pub(super) type RawRows = BTreeMap<Spanned<String>, Spanned<Vec<Spanned<String>>>>;

/// One entry of `coordinates` as written.
pub(super) struct RawCoordinate {
    pub(super) name: Spanned<String>,
    pub(super) node: Spanned<i64>,
    pub(super) kind: Spanned<String>,
}

/// A refusal while reading the document: where (byte offset) and what.
pub(super) type Refusal = (usize, String);

/// A TOML value with its span, as the parser gives it.
pub(super) type Value<'i> = Spanned<DeValue<'i>>;

impl RawShape {
    const FIELDS: &'static [&'static str] =
        &["name", "dimension", "description", "coordinates", "S"];

    /// The shape's fields from the document's top table: unknown keys are
    /// refused, `description` may be left out.
    pub(super) fn read(doc: &Spanned<DeTable<'_>>) -> Result<RawShape, Refusal> {
        let (mut name, mut dimension, mut description, mut coordinates, mut s) =
            (None, None, None, None, None);
        for (key, value) in in_document_order(doc.get_ref()) {
            match key.get_ref().as_ref() {
                "name" => name = Some(string(value)?),
                "dimension" => dimension = Some(integer(value)?),
                "description" => description = Some(string(value)?.into_inner()),
                "coordinates" => {
                    let items = array(value, "a sequence")?;
                    let read: Result<Vec<_>, _> = items.iter().map(RawCoordinate::read).collect();
                    coordinates = Some(Spanned::new(value.span(), read?));
                }
                "S" => s = Some(rows(value)?),
                _ => return Err(unknown_field(key, Self::FIELDS)),
            }
        }
        let at = doc.span().start;
        Ok(RawShape {
            name: name.ok_or_else(|| missing_field(at, "name"))?,
            dimension: dimension.ok_or_else(|| missing_field(at, "dimension"))?,
            description: description.unwrap_or_default(),
            coordinates: coordinates.ok_or_else(|| missing_field(at, "coordinates"))?,
            s: s.ok_or_else(|| missing_field(at, "S"))?,
        })
    }
}

impl RawCoordinate {
    const FIELDS: &'static [&'static str] = &["name", "node", "kind"];

    /// A coordinate from its (inline) table.
    pub(super) fn read(value: &Value<'_>) -> Result<RawCoordinate, Refusal> {
        let DeValue::Table(table) = value.get_ref() else {
            return Err(invalid_type(value, "struct RawCoordinate"));
        };
        let (mut name, mut node, mut kind) = (None, None, None);
        for (key, value) in in_document_order(table) {
            match key.get_ref().as_ref() {
                "name" => name = Some(string(value)?),
                "node" => node = Some(integer(value)?),
                "kind" => kind = Some(string(value)?),
                _ => return Err(unknown_field(key, Self::FIELDS)),
            }
        }
        let at = value.span().start;
        Ok(RawCoordinate {
            name: name.ok_or_else(|| missing_field(at, "name"))?,
            node: node.ok_or_else(|| missing_field(at, "node"))?,
            kind: kind.ok_or_else(|| missing_field(at, "kind"))?,
        })
    }
}

/// The table `S`: rows by name, each an array of strings.
fn rows(value: &Value<'_>) -> Result<Spanned<RawRows>, Refusal> {
    let DeValue::Table(table) = value.get_ref() else {
        return Err(invalid_type(value, "a map"));
    };
    let mut rows = BTreeMap::new();
    for (key, row) in in_document_order(table) {
        let entries: Result<Vec<_>, _> = array(row, "a sequence")?.iter().map(string).collect();
        rows.insert(
            Spanned::new(key.span(), key.get_ref().to_string()),
            Spanned::new(row.span(), entries?),
        );
    }
    Ok(Spanned::new(value.span(), rows))
}

/// A table's entries in the order they appear in the file (so the first
/// refusal is the first in the file).
fn in_document_order<'a, 'i>(
    table: &'a DeTable<'i>,
) -> Vec<(&'a Spanned<DeString<'i>>, &'a Value<'i>)> {
    let mut entries: Vec<_> = table.iter().collect();
    entries.sort_by_key(|(key, _)| key.span().start);
    entries
}

/// A string value.
fn string(value: &Value<'_>) -> Result<Spanned<String>, Refusal> {
    match value.get_ref() {
        DeValue::String(s) => Ok(Spanned::new(value.span(), s.to_string())),
        _ => Err(invalid_type(value, "a string")),
    }
}

/// An integer value that fits `i64`.
fn integer(value: &Value<'_>) -> Result<Spanned<i64>, Refusal> {
    match value.get_ref() {
        DeValue::Integer(i) => Ok(Spanned::new(value.span(), to_i64(value, i)?)),
        _ => Err(invalid_type(value, "i64")),
    }
}

/// An array value (`expected` names it in the refusal).
fn array<'a, 'i>(value: &'a Value<'i>, expected: &str) -> Result<&'a DeArray<'i>, Refusal> {
    match value.get_ref() {
        DeValue::Array(a) => Ok(a),
        _ => Err(invalid_type(value, expected)),
    }
}

/// The integer's value, refused when it does not fit `i64` (or has no
/// digits: toml takes `0x` for an integer).
fn to_i64(value: &Value<'_>, i: &DeInteger<'_>) -> Result<i64, Refusal> {
    i64::from_str_radix(i.as_str(), i.radix()).map_err(|e| {
        let message = match e.kind() {
            IntErrorKind::PosOverflow | IntErrorKind::NegOverflow => {
                "number too large to fit in target type".to_string()
            }
            _ => format!("invalid integer `{i}`"),
        };
        (value.span().start, message)
    })
}

/// ``invalid type: integer `3`, expected a string``, at the value.
fn invalid_type(value: &Value<'_>, expected: &str) -> Refusal {
    let found = match value.get_ref() {
        DeValue::String(s) => format!("string {s:?}"),
        DeValue::Integer(i) => match to_i64(value, i) {
            Ok(n) => format!("integer `{n}`"),
            Err(refusal) => return refusal,
        },
        DeValue::Float(f) => format!("floating point `{}`", float_text(f.as_str())),
        DeValue::Boolean(b) => format!("boolean `{b}`"),
        DeValue::Datetime(d) => format!("datetime `{d}`"),
        DeValue::Array(_) => "sequence".to_string(),
        DeValue::Table(_) => "map".to_string(),
    };
    (
        value.span().start,
        format!("invalid type: {found}, expected {expected}"),
    )
}

/// A float as Rust prints it, with a decimal point when finite (`2.0`,
/// `1.5`, `inf`, `NaN`).
fn float_text(text: &str) -> String {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x.fract() == 0.0 => format!("{x}.0"),
        Ok(x) => x.to_string(),
        Err(_) => text.to_string(),
    }
}

/// ``unknown field `colour`, expected one of `name`, …``, at the key.
fn unknown_field(key: &Spanned<DeString<'_>>, fields: &[&str]) -> Refusal {
    let one_of: Vec<String> = fields.iter().map(|f| format!("`{f}`")).collect();
    (
        key.span().start,
        format!(
            "unknown field `{}`, expected one of {}",
            key.get_ref(),
            one_of.join(", ")
        ),
    )
}

/// ``missing field `name` `` at the start of the table that lacks it.
fn missing_field(at: usize, field: &str) -> Refusal {
    (at, format!("missing field `{field}`"))
}
