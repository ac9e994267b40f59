//! Section tables (issue 19): sections along a flexible body's span, in the
//! material form (`rho, area, iy, iz, e, g, j`) or the resultant form
//! (`mass, ea, ei_y, ei_z, gj, rho_iy, rho_iz`), with optional `rho_j` and
//! `twist`; every quantity varies linearly in x between stations. Read from a
//! CSV file ([`read_csv`]; scene files, `BodyConfig::sections`, the
//! `#[flex_body]` attribute) or from a scene's inline array, and checked into
//! [`SectionTable`] ([`stations`]) with every error at its file, line and
//! column (a CSV's cell).

use crate::error::{Error, Location};
use ffr_spec::scene::{SectionTable, Station};
use ffr_spec::text::quoted as q;
use std::collections::BTreeMap;
use std::path::Path;

/// The most bytes of a section table file.
pub const MAX_TABLE_BYTES: u64 = 4 << 20;

/// The most stations of a section table.
pub const MAX_STATIONS: usize = 100_000;

const MATERIAL: [&str; 7] = ["rho", "area", "iy", "iz", "e", "g", "j"];
const RESULTANT: [&str; 7] = ["mass", "ea", "ei_y", "ei_z", "gj", "rho_iy", "rho_iz"];
const OPTIONAL: [&str; 2] = ["rho_j", "twist"];

/// A row as read: column name → (value, where).
pub type Row = BTreeMap<String, (f64, Location)>;

/// The table of body `name` from a CSV file `path` (named `written` in
/// messages), checked ([`stations`]); a file that cannot be read is an
/// [`Error::Io`].
pub fn read_table(
    path: &Path,
    written: &str,
    name: &str,
) -> Result<(SectionTable, Option<ffr_spec::Params>), Error> {
    let (rows, at, columns) = read_csv(path, written, name, |m| Error::Io {
        path: ffr_spec::text::quoted(written),
        message: format!("the section table of body `{name}`: {m}"),
    })?;
    stations(name, rows, at, columns)
}

/// The section table of body `name` from its rows (each with every column
/// of `columns`; `at`: where the table is), and, when the table is one
/// uniform section in the material form (every station the same `rho, area,
/// iy, iz, e, g, j`, no `rho_j` or `twist` column), the `params` it means:
/// such a body is the uniform body of those parameters, on the same kernels,
/// bit for bit.
pub fn stations(
    name: &str,
    rows: Vec<Row>,
    at: Location,
    columns: Vec<String>,
) -> Result<(SectionTable, Option<ffr_spec::Params>), Error> {
    let err = |at: &Location, msg: String| Error::Scene {
        location: at.clone(),
        message: format!("body `{name}`: {msg}"),
    };
    // The form, from the columns.
    for col in &columns {
        if col != "x"
            && !MATERIAL.contains(&col.as_str())
            && !RESULTANT.contains(&col.as_str())
            && !OPTIONAL.contains(&col.as_str())
        {
            return Err(err(
                &at,
                format!(
                    "unknown section column `{}`: a table has `x` and either {} (material form) or {} (resultant form), optionally `rho_j` and `twist`",
                    q(col),
                    MATERIAL.join(", "),
                    RESULTANT.join(", ")
                ),
            ));
        }
    }
    let has = |set: &[&str]| set.iter().any(|k| columns.iter().any(|c| c == k));
    let material = match (has(&MATERIAL), has(&RESULTANT)) {
        (true, true) => {
            return Err(err(
                &at,
                format!(
                    "the section columns mix the material form ({}) and the resultant form ({}): give one",
                    MATERIAL.join(", "),
                    RESULTANT.join(", ")
                ),
            ))
        }
        (true, false) => true,
        (false, true) => false,
        (false, false) => {
            return Err(err(
                &at,
                format!(
                    "a section table needs `x` and either {} (material form) or {} (resultant form)",
                    MATERIAL.join(", "),
                    RESULTANT.join(", ")
                ),
            ))
        }
    };
    let needed: &[&str] = if material { &MATERIAL } else { &RESULTANT };
    for k in std::iter::once(&"x").chain(needed) {
        if !columns.iter().any(|c| c == k) {
            return Err(err(
                &at,
                format!(
                    "the section table has no column `{k}`: the {} form needs x, {}",
                    if material { "material" } else { "resultant" },
                    needed.join(", ")
                ),
            ));
        }
    }
    if rows.len() < 2 {
        return Err(err(
            &at,
            format!(
                "a section table needs at least two stations (x = 0 and x = the length), found {}",
                rows.len()
            ),
        ));
    }
    let mut stations: Vec<Station> = Vec::with_capacity(rows.len());
    // The material values `rho, area, iy, iz, e, g, j` of every station.
    let mut materials: Vec<[f64; 7]> = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        let get = |k: &str| row.get(k).cloned();
        let need = |k: &str| get(k).expect("checked: every row has every column");
        // Positive, or not negative.
        let positive = |k: &str| -> Result<f64, Error> {
            let (x, at) = need(k);
            if x > 0.0 {
                Ok(x)
            } else {
                Err(err(
                    &at,
                    format!("station {i}: `{k}` must be > 0, found {x:?}"),
                ))
            }
        };
        let nonneg = |k: &str| -> Result<f64, Error> {
            let (x, at) = need(k);
            if x >= 0.0 {
                Ok(x)
            } else {
                Err(err(
                    &at,
                    format!("station {i}: `{k}` must be ≥ 0, found {x:?}"),
                ))
            }
        };
        let (x, x_at) = need("x");
        let mut st = if material {
            let (rho, area, e) = (positive("rho")?, positive("area")?, positive("e")?);
            let (iy, iz, g, j) = (nonneg("iy")?, nonneg("iz")?, nonneg("g")?, nonneg("j")?);
            materials.push([rho, area, iy, iz, e, g, j]);
            Station {
                x,
                mass: rho * area,
                ea: e * area,
                ei_y: e * iy,
                ei_z: e * iz,
                gj: g * j,
                rho_iy: rho * iy,
                rho_iz: rho * iz,
                rho_j: rho * (iy + iz),
                twist: 0.0,
            }
        } else {
            let (rho_iy, rho_iz) = (nonneg("rho_iy")?, nonneg("rho_iz")?);
            Station {
                x,
                mass: positive("mass")?,
                ea: positive("ea")?,
                ei_y: nonneg("ei_y")?,
                ei_z: positive("ei_z")?,
                gj: nonneg("gj")?,
                rho_iy,
                rho_iz,
                rho_j: rho_iy + rho_iz,
                twist: 0.0,
            }
        };
        if get("rho_j").is_some() {
            st.rho_j = nonneg("rho_j")?;
        }
        if let Some((t, _)) = get("twist") {
            st.twist = t;
        }
        let products = [
            st.mass, st.ea, st.ei_y, st.ei_z, st.gj, st.rho_iy, st.rho_iz, st.rho_j,
        ];
        if products.iter().any(|p| !p.is_finite()) {
            return Err(err(
                &x_at,
                format!("station {i}: a product of the material values is beyond the range of f64"),
            ));
        }
        match stations.last() {
            None if x != 0.0 => {
                return Err(err(
                    &x_at,
                    format!("the first station is at x = {x:?}: a table starts at the body's root, x = 0"),
                ))
            }
            Some(prev) if x <= prev.x => {
                return Err(err(
                    &x_at,
                    format!(
                        "station {i} is at x = {x:?}, not after station {} at x = {:?}: `x` must increase strictly",
                        i - 1,
                        prev.x
                    ),
                ))
            }
            _ => {}
        }
        stations.push(st);
    }
    let uniform = material
        && !columns.iter().any(|c| OPTIONAL.contains(&c.as_str()))
        && materials.windows(2).all(|w| w[0] == w[1]);
    let params = uniform.then(|| {
        let [rho, area, iy, iz, e, g, j] = materials[0];
        ffr_spec::Params {
            length: stations.last().expect("two stations or more").x,
            rho,
            area,
            iy,
            iz,
            e,
            g,
            j,
        }
    });
    Ok((SectionTable { stations, at }, params))
}

/// Every value of the row must be a finite number.
fn number(text: &str) -> Option<f64> {
    text.trim().parse::<f64>().ok().filter(|x| x.is_finite())
}

/// The rows of the CSV file `path` of body `name`: a header row, `#`
/// comments, every field a finite number (an error at its cell, in the file
/// named `shown`, otherwise); `file_err` makes the error of a file that
/// cannot be read (too large, not UTF-8) from what is wrong with it.
#[allow(clippy::type_complexity)]
pub fn read_csv(
    path: &Path,
    shown: &str,
    name: &str,
    file_err: impl Fn(String) -> Error,
) -> Result<(Vec<Row>, Location, Vec<String>), Error> {
    let file = crate::sanitize::snippet(shown, usize::MAX);
    let bytes =
        crate::limits::read_input(path, MAX_TABLE_BYTES, "section table", "MAX_TABLE_BYTES")
            .map_err(&file_err)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        file_err(format!(
            "is not UTF-8 text (at byte {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    let at = |line: u64, column: usize| Location {
        file: file.clone(),
        line: line as usize,
        column,
    };
    let mut reader = crate::csv_table::reader(&text);
    let csv_err = |e: csv::Error| {
        let (line, message) = crate::csv_table::error_at(&e);
        Error::Scene {
            location: at(line, 1),
            message: format!("body `{name}`: {message}"),
        }
    };
    let header: Vec<String> = reader
        .headers()
        .map_err(csv_err)?
        .iter()
        .map(|h| h.trim().to_string())
        .collect();
    if let Some(dup) = header
        .iter()
        .enumerate()
        .find(|(i, h)| header[..*i].contains(h))
    {
        return Err(Error::Scene {
            location: at(1, 1),
            message: format!("body `{name}`: column `{}` appears twice", q(dup.1)),
        });
    }
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(csv_err)?;
        let line = record.position().map_or(1, |p| p.line());
        if rows.len() == MAX_STATIONS {
            return Err(Error::Scene {
                location: at(line, 1),
                message: format!("body `{name}`: more than {MAX_STATIONS} stations (MAX_STATIONS)"),
            });
        }
        let line_text = text
            .lines()
            .nth(line.saturating_sub(1) as usize)
            .unwrap_or("");
        let mut row = Row::new();
        let mut from = 0;
        for (h, field) in header.iter().zip(record.iter()) {
            // The field's column in its line (characters, from 1).
            let col = line_text[from.min(line_text.len())..]
                .find(field.trim())
                .map_or(1, |i| line_text[..from + i].chars().count() + 1);
            from = line_text[from.min(line_text.len())..]
                .find(',')
                .map_or(line_text.len(), |i| from + i + 1);
            let v = number(field).ok_or_else(|| Error::Scene {
                location: at(line, col),
                message: format!(
                    "body `{name}`: column `{}` must be a finite number, found `{}`",
                    q(h),
                    q(field.trim())
                ),
            })?;
            row.insert(h.clone(), (v, at(line, col)));
        }
        rows.push(row);
    }
    Ok((rows, at(1, 1), header))
}

/// The stations of a generated body's section table: the CSV file `path`
/// (relative to `base`, the crate root) of body `name`, whose shape has
/// dimension `dim` (a planar shape bends in x–y only: no `twist`). Every
/// table runs the varying-section kernels (also one uniform section: a
/// body of one section is `params`).
pub fn body_stations(
    base: &Path,
    path: &str,
    name: &str,
    dim: usize,
) -> Result<Vec<Station>, Error> {
    let (table, _) = read_table(&base.join(path), path, name)?;
    if dim == 2 {
        if let Some((i, s)) = table
            .stations
            .iter()
            .enumerate()
            .find(|(_, s)| s.twist != 0.0)
        {
            return Err(Error::Scene {
                location: table.at.clone(),
                message: format!(
                    "body `{name}`: station {i} has twist {:?}: a planar shape bends in x–y only, so its sections cannot be twisted",
                    s.twist
                ),
            });
        }
    }
    Ok(table.stations)
}
