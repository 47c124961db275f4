//! The error type shared by every solver in this crate.

use thiserror::Error;

/// What is wrong with the compressed-sparse-column structure handed to [`crate::SymmetricCsc::try_new`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StructureIssue {
    /// `col_ptr` does not have `n + 1` entries.
    ColPtrLength {
        /// Required length (`n + 1`).
        expected: usize,
        /// Length given.
        found: usize,
    },
    /// `col_ptr[0]` is not zero.
    ColPtrStart,
    /// `col_ptr` decreases between this column and the next.
    ColPtrDecreasing,
    /// `col_ptr[n]` differs from the number of row indices or values.
    NnzMismatch {
        /// `col_ptr[n]`.
        col_ptr_end: usize,
        /// `row_idx.len()`.
        row_idx_len: usize,
        /// `values.len()`.
        values_len: usize,
    },
    /// A row index is `>= n`.
    RowOutOfBounds {
        /// The offending row index.
        row: usize,
    },
    /// Row indices within the column are not strictly increasing (unsorted or duplicated).
    UnsortedOrDuplicate {
        /// The row index that is out of order or repeated.
        row: usize,
    },
    /// An [`crate::MMatrix`] off-diagonal pattern stores a diagonal entry (the diagonal is implied
    /// by the excesses).
    DiagonalStored,
    /// Entry `(row, column)` is stored but its mirror `(column, row)` is not.
    MissingMirror {
        /// Row of the entry whose mirror is missing.
        row: usize,
    },
}

impl std::fmt::Display for StructureIssue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ColPtrLength { expected, found } => {
                write!(
                    f,
                    "col_ptr has {found} entries, expected n + 1 = {expected}"
                )
            }
            Self::ColPtrStart => write!(f, "col_ptr[0] is not 0"),
            Self::ColPtrDecreasing => write!(f, "col_ptr decreases after this column"),
            Self::NnzMismatch {
                col_ptr_end,
                row_idx_len,
                values_len,
            } => write!(
                f,
                "col_ptr[n] = {col_ptr_end} but row_idx has {row_idx_len} entries and values {values_len}"
            ),
            Self::RowOutOfBounds { row } => write!(f, "row index {row} is out of bounds"),
            Self::UnsortedOrDuplicate { row } => {
                write!(f, "row index {row} is unsorted or duplicated")
            }
            Self::DiagonalStored => write!(
                f,
                "diagonal entry stored in an M-matrix off-diagonal pattern"
            ),
            Self::MissingMirror { row } => write!(
                f,
                "entry in row {row} has no mirror entry (the pattern is not symmetric)"
            ),
        }
    }
}

/// Errors returned by the solvers of this crate. Each names what is wrong and where.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolverError {
    /// The matrix is not (numerically) positive definite: elimination met a pivot `<= 0`
    /// or the iteration met a direction of non-positive curvature. `column` is an index of the
    /// caller's unknowns (original ordering) where it was detected.
    #[error("matrix is not positive definite (non-positive pivot or curvature at column {column})")]
    NotPositiveDefinite {
        /// Column (unknown) in the caller's numbering.
        column: usize,
    },
    /// The matrix is singular: an exactly zero pivot, or an empty column.
    #[error("matrix is singular (zero pivot at column {column})")]
    Singular {
        /// Column (unknown) in the caller's numbering.
        column: usize,
    },
    /// Two sizes that must agree do not.
    #[error("dimension mismatch for {what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// Which argument has the wrong size.
        what: &'static str,
        /// Required size.
        expected: usize,
        /// Size given.
        found: usize,
    },
    /// The sparse structure is invalid.
    #[error("invalid sparse structure at column {column}: {issue}")]
    InvalidStructure {
        /// Column where the problem was found.
        column: usize,
        /// What is wrong.
        issue: StructureIssue,
    },
    /// The matrix handed to a numeric factorisation does not have the sparsity pattern that was analysed.
    #[error("sparsity pattern differs from the analysed one at column {column}")]
    PatternMismatch {
        /// First column whose pattern differs (or `n` if only the size differs).
        column: usize,
    },
    /// A matrix value, right-hand side entry or coordinate is NaN or infinite.
    #[error("non-finite value in {what} at index {index}")]
    NonFinite {
        /// Which input holds the value.
        what: &'static str,
        /// Index of the value within that input.
        index: usize,
    },
    /// A value that must be non-negative is negative (for example an M-matrix off-diagonal magnitude).
    #[error("negative value {value} in {what} at index {index}")]
    Negative {
        /// Which input holds the value.
        what: &'static str,
        /// Index of the value within that input.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Values that must be symmetric differ between `(row, column)` and `(column, row)`.
    #[error("values of entries ({row}, {column}) and ({column}, {row}) differ")]
    Asymmetric {
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        column: usize,
    },
    /// Preconditioned conjugate gradients stopped at `max_iter` before reaching the tolerance.
    #[error("PCG did not converge: {iterations} iterations, relative residual {rel_residual:e}")]
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// Relative residual ‖b − Ax‖₂ / ‖b‖₂ reached.
        rel_residual: f64,
    },
    /// A solve was attempted with a factor whose last [`crate::Cholesky::refactor`] failed.
    #[error("the Cholesky factor is unusable: its last refactorisation failed")]
    StaleFactor,
    /// The factorisation library failed (out of memory or index overflow).
    #[error("sparse factorisation failed: {0}")]
    Backend(String),
}
