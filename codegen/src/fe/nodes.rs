//! The node file: CSV with the header `x,y,z`, one row per node (node `i`
//! is data row `i`, from 0), coordinates in the body frame, metres.

use super::{excerpt, FeError, MAX_FE_NODES};
use nalgebra::Vector3;
use std::path::Path;

/// The largest node file read, bytes.
pub const MAX_NODE_BYTES: u64 = 1 << 20;

/// The nodes of the CSV file `path` (`shown` names it in errors): header
/// exactly `x,y,z` (spaces around names allowed), lines starting with `#`
/// are comments, every field a finite number, 1 to [`MAX_FE_NODES`] rows.
pub fn read_nodes(path: &Path, shown: &str) -> Result<Vec<Vector3<f64>>, FeError> {
    let text = super::read_text(path, shown, MAX_NODE_BYTES, "node file", "MAX_NODE_BYTES")?;
    read_nodes_str(&text, shown)
}

/// [`read_nodes`] of the text of a file.
pub fn read_nodes_str(text: &str, shown: &str) -> Result<Vec<Vector3<f64>>, FeError> {
    let mut reader = crate::csv_table::reader(text);
    let csv_err = |e: csv::Error| {
        let (line, message) = crate::csv_table::error_at(&e);
        FeError::at(shown, line as usize, 1, message)
    };
    let header: Vec<String> = reader
        .headers()
        .map_err(csv_err)?
        .iter()
        .map(|h| h.trim().to_string())
        .collect();
    if header != ["x", "y", "z"] {
        return Err(FeError::at(
            shown,
            1,
            1,
            format!(
                "the node file's header must be `x,y,z`, found `{}`",
                excerpt(&header.join(","))
            ),
        ));
    }
    let mut nodes = Vec::new();
    for record in reader.records() {
        let record = record.map_err(csv_err)?;
        let line = record.position().map_or(1, |p| p.line()) as usize;
        if nodes.len() == MAX_FE_NODES {
            return Err(FeError::at(
                shown,
                line,
                1,
                format!("more than {MAX_FE_NODES} nodes (MAX_FE_NODES)"),
            ));
        }
        let mut p = Vector3::zeros();
        for (k, field) in record.iter().enumerate() {
            let v = field
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    FeError::at(
                        shown,
                        line,
                        1,
                        format!(
                            "node {}: `{}` must be a finite number, found `{}`",
                            nodes.len(),
                            header[k],
                            excerpt(field.trim())
                        ),
                    )
                })?;
            p[k] = v;
        }
        nodes.push(p);
    }
    if nodes.is_empty() {
        return Err(FeError::file(shown, "has no nodes"));
    }
    Ok(nodes)
}
