//! `sections = "blade.csv"` or `sections = [{ x = 0.0, … }, …]` in a scene
//! file: the table read from the file or the inline array, then checked by
//! [`crate::sections::stations`].

use super::Ctx;
use crate::error::{Error, Location};
use crate::scene::quoted as q;
use crate::sections::{read_csv, stations, Row, MAX_STATIONS};
use ffr_spec::scene::SectionTable;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// The section table of body `name` from the value of its `sections` key
/// (a CSV path relative to `base`, the scene's directory, or an inline
/// array of tables), and, when the table is one uniform section in the
/// material form (every station the same `rho, area, iy, iz, e, g, j`, no
/// `rho_j` or `twist` column), the `params` it means: such a body is the
/// uniform body of those parameters, on the same kernels, bit for bit.
pub(super) fn sections(
    c: &Ctx,
    name: &str,
    v: &Spanned<toml::Value>,
    base: &Path,
) -> Result<(SectionTable, Option<ffr_spec::Params>), Error> {
    let (rows, at, columns) = match v.get_ref() {
        toml::Value::String(path) => {
            let file = base.join(path);
            read_csv(&file, &file.display().to_string(), name, |m| {
                c.err(
                    v.span(),
                    format!("body `{name}`: the section table `{}`: {m}", q(path)),
                )
            })?
        }
        toml::Value::Array(items) => inline(c, name, v.span(), items)?,
        other => {
            return Err(c.err(
                v.span(),
                format!(
                    "body `{name}`: `sections` is a CSV file's path (relative to the scene file) or an array of tables `[{{ x = 0.0, mass = …, … }}, …]`, found a {}",
                    other.type_str()
                ),
            ))
        }
    };
    stations(name, rows, at, columns)
}

#[allow(clippy::type_complexity)]
fn inline(
    c: &Ctx,
    name: &str,
    span: Range<usize>,
    items: &[toml::Value],
) -> Result<(Vec<Row>, Location, Vec<String>), Error> {
    let at = c.loc(span.clone());
    if items.len() > MAX_STATIONS {
        return Err(c.err(
            span,
            format!("body `{name}`: more than {MAX_STATIONS} stations (MAX_STATIONS)"),
        ));
    }
    let mut rows = Vec::new();
    let mut columns: Option<Vec<String>> = None;
    for (i, item) in items.iter().enumerate() {
        let Some(t) = item.as_table() else {
            return Err(c.err(
                span,
                format!("body `{name}`: station {i} of `sections` is not a table `{{ x = …, … }}`"),
            ));
        };
        let keys: Vec<String> = t.keys().cloned().collect();
        match &columns {
            None => columns = Some(keys.clone()),
            Some(first) if *first != keys => {
                return Err(c.err(
                    span,
                    format!(
                        "body `{name}`: station {i} of `sections` has the keys {}, station 0 {}: every station gives the same quantities",
                        keys.join(", "),
                        first.join(", ")
                    ),
                ))
            }
            _ => {}
        }
        let mut row = Row::new();
        for (k, v) in t {
            let x = v
                .as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    c.err(
                        span.clone(),
                        format!(
                            "body `{name}`: station {i}: `{}` must be a finite number",
                            q(k)
                        ),
                    )
                })?;
            row.insert(k.clone(), (x, at.clone()));
        }
        rows.push(row);
    }
    Ok((rows, at, columns.unwrap_or_default()))
}
