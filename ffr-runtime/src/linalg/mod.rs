//! Structured linear algebra for the Newton iteration matrix: a banded LU with
//! partial pivoting ([`BandMatrix`]), a small dense LU ([`DenseLu`]) and the
//! bordered block-banded system built from them ([`BorderedSystem`]).
//!
//! Everything here allocates only in its constructor (`new`); `clear`,
//! filling, `factor` and `solve` work in preallocated storage (checked by the
//! counting-allocator test `tests/linalg_alloc.rs`).
//!
//! # The matrix
//!
//! After a permutation, the iteration matrix of a scene is
//!
//! ```text
//! [ B_1                 C_1 P_1 ]
//! [       B_2           C_2 P_2 ]
//! [             ...       ...   ]
//! [ P_1ᵀE_1  P_2ᵀE_2 ...   D    ]
//! ```
//!
//! with `B_i` (`n_i × n_i`) banded (half-bandwidths `kl_i`, `ku_i`), the
//! border of `k` unknowns, `C_i` (`n_i × m_i`) and `E_i` (`m_i × n_i`) dense,
//! `P_i` the `m_i × k` selection of the sorted border indices `border_i` that
//! block `i` couples to (`(P_i x)_l = x[border_i[l]]`), and `D` (`k × k`)
//! dense. [`BorderedSystem`] solves it by block elimination:
//!
//! - factor: `B_i = Π_i L_i U_i` (banded, partial pivoting), `W_i = B_i⁻¹ C_i`,
//!   `S = D − Σ_i P_iᵀ E_i W_i P_i`, `S = Π_S L_S U_S` (dense, partial pivoting);
//! - solve: `y_i = B_i⁻¹ b_i`, `x_b = S⁻¹ (b_b − Σ_i P_iᵀ E_i y_i)`,
//!   `x_i = y_i − W_i P_i x_b`.
//!
//! Cost per factorization `O(Σ n_i (kl_i+ku_i)(kl_i+m_i) + Σ n_i m_i² + k³)`,
//! per solve `O(Σ n_i (kl_i+ku_i+m_i) + k²)`: linear in the number of beam
//! elements.
//!
//! # Accuracy
//!
//! Each LU is backward stable (partial pivoting, growth reported). Block
//! elimination as a whole pivots only within `B_i` and within `S`, never
//! between a block and the border, so its backward error is that of the
//! factors times about `cond(B_i)` (through `W_i = B_i⁻¹ C_i`): fine for the
//! elastic blocks of the iteration matrix (`M/(βh²) + K + …`, well
//! conditioned), and the Newton iteration corrects the rest. In the random
//! tests the relative residual `‖A x − b‖ / (‖A‖ ‖x‖)` is ≤ 1e-16 for
//! well-conditioned blocks and 2.8e-15 for a block with `cond(B) = 1e5`
//! (nalgebra's LU of the whole matrix: 1.5e-17).
//!
//! # Singular and near-singular matrices
//!
//! `factor` fails with [`Singular`] on an exactly zero pivot or on a
//! non-finite value (in the input or created by the elimination); it never
//! leaves a factorization with a NaN or infinity behind. A tiny but nonzero
//! pivot is not an error (the scaling of the FFR iteration matrix varies by
//! many orders of magnitude between coordinates, so no absolute or relative
//! threshold is right for every scene): every factorization records a
//! [`PivotInfo`] (smallest and largest |pivot|, largest input entry, largest
//! entry of `U`), and [`BorderedSystem::pivot_report`] gives the worst pivot
//! ratio `min |u_jj| / max |a_ij|` over all factors and where it is, so the
//! caller can reject a near-singular matrix (e.g. a ratio below `1e3·ε`).
//!
//! # Why not a crate
//!
//! Searched crates.io / docs.rs (November 2026) for a pure-Rust banded LU with
//! partial pivoting: `nalgebra` and `faer` have dense and sparse LU but no
//! banded storage; `ndarray-linalg` and `sundials-sys` bind LAPACK/SUNDIALS
//! (C/Fortran, not pure Rust); `trigivs` is tridiagonal only; `RustedSciThe`
//! (a large symbolic/ODE/BVP framework depending on `faer`) contains a
//! LAPACK-style banded LU in an internal module, not a focused, well-kept
//! linear-algebra crate one would depend on for this; `gam-solve` has an
//! "arrow Schur" bordered solver for dense blocks with Cholesky (statistics,
//! `ndarray`). None does banded blocks with a dense border without
//! allocating, so the ~LAPACK `dgbtf2`/`dgbtrs` algorithms are written here.

mod band;
mod bordered;
mod dense;
mod ordering;

pub use band::BandMatrix;
pub use bordered::{BlockShape, BorderedSystem, MatMut, PivotReport};
pub use dense::DenseLu;
pub use ordering::{bandwidth, reverse_cuthill_mckee};

/// Which factor of a [`BorderedSystem`] (or which stand-alone matrix) failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// A stand-alone [`BandMatrix`] or [`DenseLu`].
    Matrix,
    /// The band block `B_i` of block `i`.
    Block(usize),
    /// The Schur complement `S = D − Σ_i P_iᵀ E_i B_i⁻¹ C_i P_i` (`k × k`).
    Schur,
}

/// Why a factorization failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// The pivot (largest |entry| of the column at or below the diagonal,
    /// within the band) is exactly zero: the matrix is singular.
    ZeroPivot,
    /// An entry of the matrix, or of its factors, is NaN or infinite.
    NonFinite,
}

/// A factorization failed: the matrix is singular or not finite.
///
/// `column` is the column of the elimination step (0-based, within the block
/// for [`Part::Block`], the border index `0..k` for [`Part::Schur`]) at which
/// the zero pivot was met, or the first column holding a non-finite value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("{failure:?} in {part:?} at column {column}")]
pub struct Singular {
    /// Which matrix.
    pub part: Part,
    /// The column (see above).
    pub column: usize,
    /// Zero pivot or non-finite value.
    pub failure: Failure,
}

impl Singular {
    fn with_part(self, part: Part) -> Self {
        Singular { part, ..self }
    }
}

/// Pivot statistics of one LU factorization `Π L U = A`, for diagnosing
/// near-singular matrices. All zero for an empty matrix.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PivotInfo {
    /// `min_j |u_jj|`.
    pub min_pivot: f64,
    /// `max_j |u_jj|`.
    pub max_pivot: f64,
    /// `max_ij |a_ij|` of the matrix before factoring.
    pub max_entry: f64,
    /// `max_ij |u_ij|` of the upper factor.
    pub max_u: f64,
}

impl PivotInfo {
    /// `min_j |u_jj| / max_ij |a_ij|`: about `1/cond(A)` for a well-scaled
    /// matrix; near `ε` the solution has no correct digits. `1` for an
    /// empty matrix.
    pub fn pivot_ratio(&self) -> f64 {
        if self.max_entry > 0.0 {
            self.min_pivot / self.max_entry
        } else {
            1.0
        }
    }

    /// Pivot growth `max |u_ij| / max |a_ij|` (≤ `2^(n-1)` with partial
    /// pivoting, usually small; a large value means lost accuracy). `1` for
    /// an empty matrix.
    pub fn growth(&self) -> f64 {
        if self.max_entry > 0.0 {
            self.max_u / self.max_entry
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests;
