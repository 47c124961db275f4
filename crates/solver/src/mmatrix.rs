//! Entrywise-accurate LDLᵀ for symmetric diagonally dominant M-matrices (GTH-style elimination).
//!
//! A potential far from the goal can be 1e-17 or 1e-300 of its goal value. An ordinary Cholesky
//! computes each pivot as `a_jj − Σ l_jk² d_k`, a difference of nearly equal numbers when the row
//! sums are tiny, so the small entries of the solution lose all their digits. Here the matrix is
//! given by the magnitudes `w_ij = −a_ij ≥ 0` of its off-diagonal entries and by its row excesses
//! `s_i = a_ii − Σ_j w_ij ≥ 0` as *separate primary data* (the caller computes them as sums of
//! non-negative terms, e.g. the Robin or Dirichlet-lifting contributions). Elimination then only
//! adds non-negative numbers (Grassmann–Taksar–Heyman):
//!
//! * Schur complement magnitudes grow: `w_ij ← w_ij + w_ik w_jk / d_k`;
//! * excesses grow: `s_i ← s_i + w_ik s_k / d_k`;
//! * the pivot is recomputed as `d_k = s_k + Σ_j w_jk` over the not yet eliminated `j`,
//!
//! and so do the triangular solves when `b ≥ 0`. Every quantity is a sum of products of
//! non-negative numbers, so the computed solution has a small *entrywise* relative error,
//! whatever its dynamic range (down to the floating-point underflow threshold).

mod block;
mod multifrontal;

pub(crate) use multifrontal::numeric;

use std::sync::Arc;

use crate::csc::{Pattern, SymmetricCsc};
use crate::error::{SolverError, StructureIssue};
use crate::ordering::{Ordering, permutation};

/// A symmetric diagonally dominant M-matrix `A = diag(s + W·1) − W`, held as its off-diagonal
/// magnitudes `W ≥ 0` (full symmetric pattern, no diagonal entries) and its row excesses `s ≥ 0`.
///
/// ```
/// use harmonic_solver::{AccurateLdlt, MMatrix, Ordering, SymmetricCsc};
/// // Chain 0 – 1 – 2 with unit conductances, grounded only at unknown 0 (excess 1).
/// let w = SymmetricCsc::try_new(3, vec![0, 1, 3, 4], vec![1, 0, 2, 1], vec![1.0; 4])?;
/// let m = MMatrix::try_new(w, vec![1.0, 0.0, 0.0])?;
/// let x = AccurateLdlt::factor(&m, Ordering::Amd)?.solve(&[0.0, 0.0, 1.0])?;
/// // A = [2 -1 0; -1 2 -1; 0 -1 1]: x = (1, 2, 3).
/// assert!((x[0] - 1.0).abs() < 1e-15 && (x[2] - 3.0).abs() < 1e-15);
/// # Ok::<(), harmonic_solver::SolverError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MMatrix {
    offdiag: SymmetricCsc,
    excess: Vec<f64>,
}

impl MMatrix {
    /// Checks that `offdiag` stores no diagonal entry and holds finite, non-negative, exactly
    /// symmetric magnitudes, and that `excess` has one finite non-negative entry per unknown.
    pub fn try_new(offdiag: SymmetricCsc, excess: Vec<f64>) -> Result<Self, SolverError> {
        let n = offdiag.n();
        if excess.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "M-matrix excess vector",
                expected: n,
                found: excess.len(),
            });
        }
        for (what, values) in [
            ("M-matrix off-diagonal magnitudes", offdiag.values()),
            ("M-matrix excess", &excess),
        ] {
            if let Some(index) = values.iter().position(|v| !v.is_finite()) {
                return Err(SolverError::NonFinite { what, index });
            }
            if let Some(index) = values.iter().position(|&v| v < 0.0) {
                return Err(SolverError::Negative {
                    what,
                    index,
                    value: values[index],
                });
            }
        }
        // Columns in increasing order meet the entries of column i above its diagonal in
        // increasing row order too: each entry below the diagonal finds its mirror at column
        // i's cursor, without a search.
        let mut mirror: Vec<usize> = (0..n).map(|i| offdiag.col_ptr()[i]).collect();
        for j in 0..n {
            let (rows, vals) = offdiag.column(j);
            for (&i, &v) in rows.iter().zip(vals) {
                if i == j {
                    return Err(SolverError::InvalidStructure {
                        column: j,
                        issue: StructureIssue::DiagonalStored,
                    });
                }
                if i < j {
                    continue;
                }
                // The pattern is symmetric (checked by SymmetricCsc), so the mirror exists.
                let k = mirror[i];
                if k >= offdiag.col_ptr()[i + 1] || offdiag.row_idx()[k] != j {
                    return Err(SolverError::InvalidStructure {
                        column: j,
                        issue: StructureIssue::MissingMirror { row: i },
                    });
                }
                mirror[i] += 1;
                if offdiag.values()[k] != v {
                    return Err(SolverError::Asymmetric { row: i, column: j });
                }
            }
        }
        Ok(Self { offdiag, excess })
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.offdiag.n()
    }

    /// Off-diagonal magnitudes `w_ij = −a_ij`.
    pub fn offdiag(&self) -> &SymmetricCsc {
        &self.offdiag
    }

    /// Row excesses `s_i = a_ii − Σ_j w_ij`.
    pub fn excess(&self) -> &[f64] {
        &self.excess
    }

    /// The ordinary matrix `A` (diagonal added, off-diagonals negated), e.g. to compare with
    /// [`crate::solve_direct`] or to compute residuals.
    pub fn to_csc(&self) -> SymmetricCsc {
        let n = self.n();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(self.offdiag.nnz() + n);
        let mut values = Vec::with_capacity(self.offdiag.nnz() + n);
        col_ptr.push(0);
        for j in 0..n {
            let (rows, vals) = self.offdiag.column(j);
            let split = rows.partition_point(|&i| i < j);
            let diag = self.excess[j] + vals.iter().sum::<f64>();
            row_idx.extend_from_slice(&rows[..split]);
            values.extend(vals[..split].iter().map(|v| -v));
            row_idx.push(j);
            values.push(diag);
            row_idx.extend_from_slice(&rows[split..]);
            values.extend(vals[split..].iter().map(|v| -v));
            col_ptr.push(row_idx.len());
        }
        SymmetricCsc::try_new(n, col_ptr, row_idx, values)
            .expect("adding the diagonal to a valid symmetric pattern keeps it valid")
    }
}

/// The symbolic half of an [`AccurateLdlt`]: the fill-reducing order and the pattern of `L`,
/// from a matrix's pattern alone (its diagonal, stored or not, plays no part). Made from the
/// assembled matrix, it can run while the [`MMatrix`] is being built from that matrix, then
/// [`LdltAnalysis::factor`] eliminates; [`AccurateLdlt::factor`] does both in turn.
///
/// ```
/// use harmonic_solver::{AccurateLdlt, LdltAnalysis, MMatrix, Ordering, SymmetricCsc};
/// // The path graph 0 - 1 - 2 with the ends tied to the boundary.
/// let a = SymmetricCsc::try_new(3, vec![0, 2, 5, 7], vec![0, 1, 0, 1, 2, 1, 2],
///     vec![2.0, -1.0, -1.0, 2.0, -1.0, -1.0, 2.0])?;
/// let w = SymmetricCsc::try_new(3, vec![0, 1, 3, 4], vec![1, 0, 2, 1], vec![1.0; 4])?;
/// let m = MMatrix::try_new(w, vec![1.0, 0.0, 1.0])?;
/// let f = LdltAnalysis::of(&a, Ordering::Amd)?.factor(&m)?;
/// let g = AccurateLdlt::factor(&m, Ordering::Amd)?;
/// assert_eq!(f.solve(&[1.0, 0.0, 1.0])?, g.solve(&[1.0, 0.0, 1.0])?);
/// # Ok::<(), harmonic_solver::SolverError>(())
/// ```
#[derive(Debug, Clone)]
pub struct LdltAnalysis {
    /// The analysed pattern (shared), to check the matrix eliminated.
    analysed: Arc<Pattern>,
    pub(crate) perm: Vec<usize>,
    pub(crate) inv: Vec<usize>,
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) row_idx: Vec<u32>,
}

impl LdltAnalysis {
    /// Orders `pattern_of`'s unknowns and finds the pattern of `L`.
    pub fn of(pattern_of: &SymmetricCsc, ordering: Ordering) -> Result<Self, SolverError> {
        let n = pattern_of.n();
        if u32::try_from(n).is_err() {
            return Err(SolverError::Backend(format!(
                "{n} unknowns: the accurate LDLᵀ numbers rows with 32 bits"
            )));
        }
        let perm = permutation(pattern_of, &ordering)?;
        let mut inv = vec![0; n];
        for (new, &old) in perm.iter().enumerate() {
            inv[old] = new;
        }
        let (col_ptr, row_idx) = symbolic(pattern_of, &perm, &inv);
        Ok(LdltAnalysis {
            analysed: Arc::clone(pattern_of.pattern()),
            perm,
            inv,
            col_ptr,
            row_idx,
        })
    }

    /// Eliminates `m`, whose off-diagonal pattern must be the analysed one less its
    /// diagonal (checked).
    ///
    /// Fails with [`SolverError::Singular`] as [`AccurateLdlt::factor`] does, with
    /// [`SolverError::DimensionMismatch`] for a matrix of another size and with
    /// [`SolverError::PatternMismatch`] (the first column that differs) for another pattern.
    pub fn factor(self, m: &MMatrix) -> Result<AccurateLdlt, SolverError> {
        if m.n() != self.perm.len() {
            return Err(SolverError::DimensionMismatch {
                what: "M-matrix of an analysed pattern",
                expected: self.perm.len(),
                found: m.n(),
            });
        }
        let w = m.offdiag.pattern();
        if !Arc::ptr_eq(w, &self.analysed) {
            let a = &self.analysed;
            let differs = |j: usize| {
                let own = &a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]];
                let theirs = &w.row_idx[w.col_ptr[j]..w.col_ptr[j + 1]];
                !own.iter()
                    .copied()
                    .filter(|&i| i != j)
                    .eq(theirs.iter().copied())
            };
            if let Some(column) = (0..m.n()).find(|&j| differs(j)) {
                return Err(SolverError::PatternMismatch { column });
            }
        }
        let mut f = AccurateLdlt {
            perm: self.perm,
            inv: self.inv,
            w_pattern: Arc::clone(m.offdiag.pattern()),
            col_ptr: self.col_ptr,
            row_idx: self.row_idx,
            l: Vec::new(),
            d: Vec::new(),
        };
        let (l, d) = f.numeric(m)?;
        (f.l, f.d) = (l, d);
        Ok(f)
    }
}

/// An [`AccurateLdlt`]'s `perm`, `inv`, factored pattern, and column pointers and rows of `L`.
pub(crate) type Structure<'a> = (
    &'a [usize],
    &'a [usize],
    &'a Arc<Pattern>,
    &'a [usize],
    &'a [u32],
);

/// Entrywise-accurate `A = L D Lᵀ` of an [`MMatrix`] (multifrontal: dense fronts over relaxed
/// supernodes, subtrees on rayon's pool; `L` is kept column by column for the solves). See the
/// module documentation for why it is accurate; it costs about as many flops as a Cholesky with
/// the same ordering, and returns the same factor bit for bit at any thread count.
#[derive(Debug, Clone)]
pub struct AccurateLdlt {
    /// `perm[new] = old`.
    perm: Vec<usize>,
    /// `inv[old] = new`.
    inv: Vec<usize>,
    /// Pattern of the factored matrix's off-diagonals (shared), to check refactorisations.
    w_pattern: Arc<Pattern>,
    /// Columns of `−L` (magnitudes `w_ij / d_j ≥ 0`), permuted numbering, rows sorted.
    col_ptr: Vec<usize>,
    /// Row numbers as `u32` (half the memory traffic of the elimination's inner loops).
    row_idx: Vec<u32>,
    l: Vec<f64>,
    /// Pivots `d_j > 0`.
    d: Vec<f64>,
}

impl AccurateLdlt {
    /// Factors `m` with the given fill-reducing ordering.
    ///
    /// Fails with [`SolverError::Singular`] when a pivot is zero: a connected block of unknowns
    /// with no excess anywhere (no Dirichlet or Robin contact) — the column named belongs to it.
    pub fn factor(m: &MMatrix, ordering: Ordering) -> Result<Self, SolverError> {
        LdltAnalysis::of(&m.offdiag, ordering)?.factor(m)
    }

    /// Refactors for new values of an M-matrix with the same off-diagonal pattern, reusing the
    /// ordering and the pattern of `L`. On error `self` is unchanged.
    pub fn refactor(&mut self, m: &MMatrix) -> Result<(), SolverError> {
        m.offdiag.check_pattern(&self.w_pattern)?;
        let (l, d) = self.numeric(m)?;
        (self.l, self.d) = (l, d);
        Ok(())
    }

    /// The numeric elimination on the stored pattern: returns (magnitudes of L, pivots).
    fn numeric(&self, m: &MMatrix) -> Result<(Vec<f64>, Vec<f64>), SolverError> {
        numeric(m, &self.perm, &self.inv, &self.col_ptr, &self.row_idx)
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.d.len()
    }

    /// The symbolic structure (`perm`, `inv`, pattern of the factored matrix, column pointers
    /// and rows of `L`), for the extended-exponent factorisation on the same elimination.
    pub(crate) fn structure(&self) -> Structure<'_> {
        (
            &self.perm,
            &self.inv,
            &self.w_pattern,
            &self.col_ptr,
            &self.row_idx,
        )
    }

    /// The elimination order used: `perm[new] = old` (the fill-reducing ordering's choice,
    /// for callers that keep it to number similar systems later).
    pub fn permutation(&self) -> &[usize] {
        &self.perm
    }

    /// Number of off-diagonal entries of `L` (fill measure).
    pub fn factor_nnz(&self) -> usize {
        self.l.len()
    }

    /// Solves `A x = b`. Entrywise accurate when `b ≥ 0` (then `x ≥ 0`); any finite `b` is accepted.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>, SolverError> {
        let mut x = b.to_vec();
        self.solve_in_place(&mut x)?;
        Ok(x)
    }

    /// Solves `A x = b` in place (`x` holds `b` on entry).
    pub fn solve_in_place(&self, x: &mut [f64]) -> Result<(), SolverError> {
        let n = self.n();
        if x.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand side",
                expected: n,
                found: x.len(),
            });
        }
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "right-hand side",
                index,
            });
        }
        let mut y: Vec<f64> = self.perm.iter().map(|&old| x[old]).collect();
        // L y = b with L = I − (magnitudes): y_i += l_ij y_j.
        let column = |j: usize| {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            self.row_idx[range.clone()].iter().zip(&self.l[range])
        };
        for j in 0..n {
            let yj = y[j];
            for (&i, &lij) in column(j) {
                y[i as usize] += lij * yj;
            }
        }
        // D z = y, then Lᵀ x = z: x_j = z_j + Σ_i l_ij x_i.
        for j in (0..n).rev() {
            let mut acc = y[j] / self.d[j];
            for (&i, &lij) in column(j) {
                acc += lij * y[i as usize];
            }
            y[j] = acc;
        }
        for (new, &old) in self.perm.iter().enumerate() {
            x[old] = y[new];
        }
        Ok(())
    }
}

/// Pattern of `L` (strictly lower, permuted numbering, rows sorted within each column): each
/// column's own entries merged with its elimination-tree children's patterns less itself.
///
/// Most columns have one child (the chains of a nested dissection's pieces and separators):
/// the child's pattern less its first row (this column) is sorted, so it is copied as it is
/// and the column's own entries not in it (a few, found by binary search) are merged in from
/// the back — no mark array and no sort, about half the time of a marked union and a sort
/// for every column (7.4 against 16–17 ms on a 300 × 300 grid's 3.6 M entries, warm). Columns
/// with several children take the marked union and a sort.
pub(crate) fn symbolic(w: &SymmetricCsc, perm: &[usize], inv: &[usize]) -> (Vec<usize>, Vec<u32>) {
    const NONE: usize = usize::MAX;
    let n = perm.len();
    let mut col_ptr = Vec::with_capacity(n + 1);
    // Room for a plane mesh's fill (about 3 entries of L per entry of A under a nested
    // dissection) without growing; pages not written are never touched.
    let mut row_idx: Vec<u32> = Vec::with_capacity(4 * w.nnz() + n);
    // Children lists of the elimination tree as linked lists.
    let mut first_child = vec![NONE; n];
    let mut sibling = vec![NONE; n];
    let mut mark = vec![NONE; n];
    let mut own: Vec<u32> = Vec::new();
    col_ptr.push(0);
    for j in 0..n {
        own.clear();
        own.extend(
            w.column(perm[j])
                .0
                .iter()
                .map(|&old_i| inv[old_i])
                .filter(|&i| i > j)
                .map(|i| i as u32),
        );
        own.sort_unstable();
        let start = row_idx.len();
        let c = first_child[j];
        if c == NONE {
            row_idx.extend_from_slice(&own);
        } else if sibling[c] == NONE {
            row_idx.extend_from_within(col_ptr[c] + 1..col_ptr[c + 1]);
            let copied = &row_idx[start..];
            own.retain(|i| copied.binary_search(i).is_err());
            // Merge from the back: the copied rows at [start, m), the new ones in `own`.
            let (m, k) = (row_idx.len(), own.len());
            row_idx.resize(m + k, 0);
            let (mut a, mut b) = (m, k);
            while b > 0 {
                if a > start && row_idx[a - 1] > own[b - 1] {
                    row_idx[a + b - 1] = row_idx[a - 1];
                    a -= 1;
                } else {
                    row_idx[a + b - 1] = own[b - 1];
                    b -= 1;
                }
            }
        } else {
            mark[j] = j;
            let mut c = c;
            while c != NONE {
                for q in col_ptr[c]..col_ptr[c + 1] {
                    let i = row_idx[q] as usize;
                    if i > j && mark[i] != j {
                        mark[i] = j;
                        row_idx.push(i as u32);
                    }
                }
                c = sibling[c];
            }
            for &i in &own {
                if mark[i as usize] != j {
                    mark[i as usize] = j;
                    row_idx.push(i);
                }
            }
            row_idx[start..].sort_unstable();
        }
        col_ptr.push(row_idx.len());
        if let Some(&parent) = row_idx.get(start) {
            let parent = parent as usize;
            sibling[j] = first_child[parent];
            first_child[parent] = j;
        }
    }
    (col_ptr, row_idx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gallery::triangulated_grid_laplacian;

    /// The pattern of `L` the plain way: every column the marked union of its own entries
    /// and its children's patterns, sorted.
    fn marked_union(w: &SymmetricCsc, perm: &[usize], inv: &[usize]) -> (Vec<usize>, Vec<u32>) {
        let n = perm.len();
        let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut mark = vec![usize::MAX; n];
        for j in 0..n {
            let start = row_idx.len();
            let own = w.column(perm[j]).0.iter().map(|&o| inv[o]);
            let inherited: Vec<usize> = children[j]
                .iter()
                .flat_map(|&c| {
                    row_idx[col_ptr[c]..col_ptr[c + 1]]
                        .iter()
                        .map(|&i| i as usize)
                })
                .collect();
            for i in own.chain(inherited) {
                if i > j && mark[i] != j {
                    mark[i] = j;
                    row_idx.push(i as u32);
                }
            }
            row_idx[start..].sort_unstable();
            col_ptr.push(row_idx.len());
            if let Some(&p) = row_idx.get(start) {
                children[p as usize].push(j);
            }
        }
        (col_ptr, row_idx)
    }

    /// The merging symbolic factorisation gives the plain union's pattern under orderings
    /// with long chains (nested dissection), many branches (AMD), none (the natural order of
    /// a grid) and random ones, on a grid and on a path.
    #[test]
    fn merged_chains_give_the_marked_union_pattern() {
        let (grid, coords) = triangulated_grid_laplacian(37, 23);
        let (path, _) = triangulated_grid_laplacian(1, 40);
        let mut rng = harmonic_fixtures::Rng(0x9e37_79b9_7f4a_7c15);
        let mut random_perm = |n: usize| {
            let mut p: Vec<usize> = (0..n).collect();
            for k in (1..n).rev() {
                p.swap(k, rng.below(k + 1));
            }
            p
        };
        let orderings = [
            Ordering::NestedDissection { coords },
            Ordering::Amd,
            Ordering::Natural,
        ];
        let mut cases: Vec<(&SymmetricCsc, Vec<usize>)> = orderings
            .iter()
            .map(|o| (&grid, permutation(&grid, o).expect("an ordering")))
            .collect();
        cases.push((&grid, random_perm(grid.n())));
        cases.push((&grid, random_perm(grid.n())));
        cases.push((&path, random_perm(path.n())));
        for (k, (a, perm)) in cases.iter().enumerate() {
            let mut inv = vec![0; perm.len()];
            for (new, &old) in perm.iter().enumerate() {
                inv[old] = new;
            }
            let merged = symbolic(a, perm, &inv);
            assert_eq!(merged, marked_union(a, perm, &inv), "case {k}");
            assert!(merged.1.len() > a.nnz() / 3, "case {k}: some fill");
        }
    }
}
