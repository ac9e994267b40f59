//! Matrix Market files (coordinate, real, `symmetric` or `general`) read
//! with `nalgebra-sparse`'s reader into a dense symmetric matrix, checked.
//!
//! The reader parses the file; before it runs, a scan of the lines checks
//! what the reader would take on trust or refuse with a multi-line parser
//! dump: the banner (coordinate real symmetric/general only), the declared
//! size (against the order the node file implies and [`MAX_FE_ORDER`]) and
//! number of entries, and every entry line: three fields `row column
//! value`, whole-number indices in range (the reader unwraps a parse of
//! each integer into `usize` and multiplies row and column indices: an
//! index of 25 digits would panic), a finite value (`NaN`: "NaN is not a
//! finite number"). Each refusal is one line at `file:line:column`, user
//! text escaped. The scan also records each entry's line, so the checks
//! after reading (repeated entries, symmetry of a `general` file) name it.

use super::{FeError, MAX_FE_ORDER};
use nalgebra::DMatrix;
use nalgebra_sparse::io::load_coo_from_matrix_market_str;
use std::path::Path;

/// The largest Matrix Market file read, bytes (a dense symmetric matrix of
/// order [`MAX_FE_ORDER`] in 17 significant digits is about 45 MB).
pub const MAX_MATRIX_BYTES: u64 = 64 << 20;

/// A `general` file is symmetric when `|A_ij − A_ji| ≤ SYMMETRY_TOL ·
/// max|A|` for every pair (an FE code's round-off in assembly); the matrix
/// used is then `(A + Aᵀ)/2` (on the pairs that differ).
pub const SYMMETRY_TOL: f64 = 1e-10;

/// How a file stores its matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// The lower triangle (`symmetric`).
    Symmetric,
    /// Every entry (`general`).
    General,
}

/// What the scan before the reader found.
struct Scan {
    storage: Storage,
    /// The line (from 1) of each entry, in file order.
    entry_lines: Vec<usize>,
}

/// Whether `t` is a non-empty run of ASCII digits (the grammar's
/// `Dimension`).
fn is_integer(t: &str) -> bool {
    !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit())
}

/// The whitespace-separated fields of a line, each with its column (from
/// 1, in characters).
fn fields(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, ch) in line.char_indices() {
        match (ch.is_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(b)) => {
                out.push((line[..b].chars().count() + 1, &line[b..i]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(b) = start {
        out.push((line[..b].chars().count() + 1, &line[b..]));
    }
    out
}

fn scan(text: &str, file: &str, order: usize, what: &str) -> Result<Scan, FeError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((banner_line, banner)) = lines.next() else {
        return Err(FeError::file(file, "is empty, not a Matrix Market file"));
    };
    let words: Vec<String> = banner
        .split_whitespace()
        .map(str::to_ascii_lowercase)
        .collect();
    let storage = match words.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["%%matrixmarket", "matrix", "coordinate", "real", "symmetric"] => Storage::Symmetric,
        ["%%matrixmarket", "matrix", "coordinate", "real", "general"] => Storage::General,
        _ => {
            return Err(FeError::at(
                file,
                banner_line,
                1,
                format!(
                    "the {what} matrix must be a Matrix Market file `%%MatrixMarket matrix coordinate real symmetric` (or `general`), found `{}`",
                    super::excerpt(banner.trim())
                ),
            ))
        }
    };
    let mut lines = lines.skip_while(|(_, l)| l.trim_start().starts_with('%'));
    let Some((size_line, size)) = lines.next() else {
        return Err(FeError::file(file, "has no size line"));
    };
    let tokens: Vec<&str> = size.split_whitespace().collect();
    let declared: Vec<u64> = tokens.iter().filter_map(|t| t.parse().ok()).collect();
    if tokens.len() != 3 || declared.len() != 3 || !tokens.iter().all(|t| is_integer(t)) {
        return Err(FeError::at(
            file,
            size_line,
            1,
            format!(
                "the size line must be three integers `rows columns entries` of at most 20 digits, found `{}`",
                super::excerpt(size.trim())
            ),
        ));
    }
    let (rows, cols, nnz) = (declared[0], declared[1], declared[2]);
    if rows as u128 > MAX_FE_ORDER as u128 || cols as u128 > MAX_FE_ORDER as u128 {
        return Err(FeError::at(
            file,
            size_line,
            1,
            format!(
                "declares a {rows} × {cols} {what} matrix: larger than order {MAX_FE_ORDER}, the limit (MAX_FE_ORDER, 3 × MAX_FE_NODES); not read"
            ),
        ));
    }
    if rows != order as u64 || cols != order as u64 {
        return Err(FeError::at(
            file,
            size_line,
            1,
            format!(
                "declares a {rows} × {cols} {what} matrix; the node file has {} nodes, so it must be {order} × {order} (3 per node)",
                order / 3
            ),
        ));
    }
    let n = order as u64;
    let most = match storage {
        Storage::Symmetric => n * (n + 1) / 2,
        Storage::General => n * n,
    };
    if nnz > most {
        return Err(FeError::at(
            file,
            size_line,
            1,
            format!("declares {nnz} entries; a {order} × {order} {what} matrix stored this way has at most {most}"),
        ));
    }
    let mut entry_lines = Vec::new();
    for (line, l) in lines {
        if entry_lines.len() as u64 == nnz {
            return Err(FeError::at(
                file,
                line,
                1,
                format!("more entries than the {nnz} the size line declares"),
            ));
        }
        // Each entry is `row column value`, read here before the reader
        // sees it: a located one-line error instead of its parser's dump.
        let f = fields(l);
        if f.len() != 3 {
            return Err(FeError::at(
                file,
                line,
                1,
                format!(
                    "an entry is `row column value`, three fields; found {} in `{}`",
                    f.len(),
                    super::excerpt(l.trim())
                ),
            ));
        }
        let mut index = [0u64; 2];
        for (k, &(col, t)) in f[..2].iter().enumerate() {
            let v: u64 = if is_integer(t) {
                t.parse().unwrap_or(u64::MAX)
            } else {
                return Err(FeError::at(
                    file,
                    line,
                    col,
                    format!(
                        "{} index `{}` is not a whole number",
                        ["row", "column"][k],
                        super::excerpt(t)
                    ),
                ));
            };
            if v == 0 || v > n {
                return Err(FeError::at(
                    file,
                    line,
                    col,
                    format!(
                        "{} index `{}` out of range: must be 1 to {order} (1-based)",
                        ["row", "column"][k],
                        super::excerpt(t)
                    ),
                ));
            }
            index[k] = v;
        }
        let (col, t) = f[2];
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => {}
            Ok(v) => {
                return Err(FeError::at(
                    file,
                    line,
                    col,
                    format!(
                        "{what} matrix entry ({}, {}) is {v} (`{}`): {v} is not a finite number",
                        index[0],
                        index[1],
                        super::excerpt(t),
                    ),
                ))
            }
            Err(_) => {
                return Err(FeError::at(
                    file,
                    line,
                    col,
                    format!(
                        "{what} matrix entry ({}, {}): `{}` is not a number",
                        index[0],
                        index[1],
                        super::excerpt(t)
                    ),
                ))
            }
        }
        if storage == Storage::Symmetric && index[1] > index[0] {
            return Err(FeError::at(
                file,
                line,
                1,
                format!(
                    "entry ({}, {}) above the diagonal: a `symmetric` file stores the lower triangle",
                    index[0], index[1]
                ),
            ));
        }
        entry_lines.push(line);
    }
    if (entry_lines.len() as u64) < nnz {
        return Err(FeError::file(
            file,
            format!(
                "has {} entries, the size line declares {nnz}",
                entry_lines.len()
            ),
        ));
    }
    Ok(Scan {
        storage,
        entry_lines,
    })
}

/// The `what` matrix (`"mass"`, `"stiffness"`) of order `order` from the
/// Matrix Market file `path` (`shown` names it in errors): checked as the
/// module says, then symmetric (mirrored from the lower triangle, or
/// `(A + Aᵀ)/2` of a `general` file within [`SYMMETRY_TOL`]) and finite.
/// Repeated entries are refused (the format has none; summing them would
/// hide an error).
pub fn read_matrix(
    path: &Path,
    shown: &str,
    what: &str,
    order: usize,
) -> Result<(DMatrix<f64>, Storage), FeError> {
    let text = super::read_text(
        path,
        shown,
        MAX_MATRIX_BYTES,
        "Matrix Market file",
        "MAX_MATRIX_BYTES",
    )?;
    read_matrix_str(&text, shown, what, order)
}

/// [`read_matrix`] of the text of a file.
pub fn read_matrix_str(
    text: &str,
    shown: &str,
    what: &str,
    order: usize,
) -> Result<(DMatrix<f64>, Storage), FeError> {
    let scan = scan(text, shown, order, what)?;
    // The scan read every entry; a refusal of the reader still left is
    // given as the first line of its message, escaped.
    let coo = load_coo_from_matrix_market_str::<f64>(text).map_err(|e| {
        FeError::file(
            shown,
            format!(
                "not a valid Matrix Market {what} matrix: {}",
                super::excerpt(e.message().trim().lines().next().unwrap_or(""))
            ),
        )
    })?;
    if coo.nrows() != order || coo.ncols() != order {
        return Err(FeError::file(
            shown,
            format!(
                "the reader gives a {} × {} matrix, expected {order} × {order}",
                coo.nrows(),
                coo.ncols()
            ),
        ));
    }
    let mut a = DMatrix::<f64>::zeros(order, order);
    let mut seen = vec![false; order * order];
    let mut triplets = coo.triplet_iter();
    let mut entry = 0;
    while let Some((r, c, &v)) = triplets.next() {
        let line = scan.entry_lines.get(entry).copied().unwrap_or(0);
        if !v.is_finite() {
            return Err(FeError::at(
                shown,
                line,
                1,
                format!(
                    "{what} matrix entry ({}, {}) is {v}, not a finite number",
                    r + 1,
                    c + 1
                ),
            ));
        }
        if seen[r * order + c] {
            return Err(FeError::at(
                shown,
                line,
                1,
                format!("{what} matrix entry ({}, {}) given twice", r + 1, c + 1),
            ));
        }
        seen[r * order + c] = true;
        a[(r, c)] = v;
        if scan.storage == Storage::Symmetric && r != c {
            // The reader pushes the mirrored entry right after.
            triplets.next();
            seen[c * order + r] = true;
            a[(c, r)] = v;
        }
        entry += 1;
    }
    if scan.storage == Storage::General {
        let big = a.amax();
        let mut worst = (0.0, 0, 0);
        for j in 0..order {
            for i in j + 1..order {
                let d = (a[(i, j)] - a[(j, i)]).abs();
                if d > worst.0 {
                    worst = (d, i, j);
                }
            }
        }
        if worst.0 > SYMMETRY_TOL * big {
            let (d, i, j) = worst;
            return Err(FeError::file(
                shown,
                format!(
                    "the {what} matrix is not symmetric: entries ({}, {}) = {:e} and ({}, {}) = {:e} differ by {d:e}, more than {SYMMETRY_TOL:e} (SYMMETRY_TOL) of its largest entry {big:e}",
                    i + 1,
                    j + 1,
                    a[(i, j)],
                    j + 1,
                    i + 1,
                    a[(j, i)]
                ),
            ));
        }
        symmetrize(&mut a);
    }
    Ok((a, scan.storage))
}

/// Each pair `A_ij ≠ A_ji` replaced by its mean (`½A_ij + ½A_ji`, which
/// cannot overflow); an exactly symmetric matrix is left as it is.
pub(crate) fn symmetrize(a: &mut DMatrix<f64>) {
    for j in 0..a.ncols() {
        for i in j + 1..a.nrows() {
            if a[(i, j)] != a[(j, i)] {
                let v = 0.5 * a[(i, j)] + 0.5 * a[(j, i)];
                a[(i, j)] = v;
                a[(j, i)] = v;
            }
        }
    }
}
