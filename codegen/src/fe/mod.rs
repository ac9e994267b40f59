//! Bodies from finite-element matrices (the nodal-based FFRF): a node file
//! and the consistent mass and stiffness matrices an FE code exports, read
//! and checked ([`FeModel`]), the FFR invariants from the mass matrix and
//! the nodal coordinates with a reference condition ([`FeBody`]), and their
//! reduction with the modal machinery of [`crate::modal`] (the same
//! eigensolver, rigid-body-mode removal and Craig–Bampton as beams).
//!
//! File formats and limits: `docs/fe.md`; the formulas: `docs/theory.md`,
//! "Bodies from finite-element matrices".
//!
//! Scene files take FE bodies (`fe = {…}`; the scene reader records the
//! files, the `ffr` crate reads them when the scene is built), and
//! [`crate::export::ExportBody::from_fe`] writes a reduced one for other
//! engines.

mod body;
mod matrix;
mod model;
mod nodes;
mod reduce;

pub use body::{FeBody, FeReference};
pub use matrix::{read_matrix, read_matrix_str, Storage, MAX_MATRIX_BYTES, SYMMETRY_TOL};
pub use model::{FeModel, DIRECTION_TOL, RIGID_TOL};
pub use nodes::{read_nodes, read_nodes_str, MAX_NODE_BYTES};

use crate::modal::ModalError;
use ffr_spec::Location;

/// The largest FE model read: nodes. The modal pipeline is dense (`m_ff`,
/// `K_ff` and the nine `S̄_kl` are `n_f × n_f` matrices of `f64`), so the
/// bound keeps a body at the scale of the largest beam (6 · 257 = 1542
/// coordinates): 512 nodes, order 1536, about 19 MB per dense matrix.
pub const MAX_FE_NODES: usize = 512;
/// The largest matrix order read, `3 · MAX_FE_NODES`.
pub const MAX_FE_ORDER: usize = 3 * MAX_FE_NODES;

/// What can go wrong with an FE body.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FeError {
    /// A problem at a place in a file (`file:line:col`).
    #[error("{location}: {message}")]
    At {
        /// Where.
        location: Location,
        /// What.
        message: String,
    },
    /// A problem with a whole file (or one the reader does not locate).
    #[error("{}: {message}", ffr_spec::text::path_text(file))]
    File {
        /// The file as shown to the user.
        file: String,
        /// What.
        message: String,
    },
    /// The model as a whole (sizes, reference condition, interface).
    #[error("{0}")]
    Model(String),
    /// The modal reduction.
    #[error(transparent)]
    Modal(#[from] ModalError),
}

impl FeError {
    fn at(file: &str, line: usize, column: usize, message: impl Into<String>) -> Self {
        FeError::At {
            location: Location {
                file: file.to_string(),
                line,
                column,
            },
            message: message.into(),
        }
    }

    fn file(file: &str, message: impl Into<String>) -> Self {
        FeError::File {
            file: file.to_string(),
            message: message.into(),
        }
    }
}

/// At most 40 characters of `s`, printable (for messages quoting a file).
/// The text of the file `path`, at most `max` bytes (`what`, `constant`
/// name the file and the limit in the refusal), UTF-8.
fn read_text(
    path: &std::path::Path,
    shown: &str,
    max: u64,
    what: &str,
    constant: &str,
) -> Result<String, FeError> {
    let bytes = crate::limits::read_input(path, max, what, constant)
        .map_err(|e| FeError::file(shown, e))?;
    String::from_utf8(bytes).map_err(|e| {
        FeError::file(
            shown,
            format!(
                "is not UTF-8 text (at byte {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

fn excerpt(s: &str) -> String {
    let cut: String = s.chars().take(40).collect();
    let more = if cut.len() < s.len() { "…" } else { "" };
    format!("{}{more}", crate::sanitize::comment_text(&cut))
}

/// The direction names of a node's degrees of freedom.
pub const DIRECTIONS: [&str; 3] = ["ux", "uy", "uz"];
