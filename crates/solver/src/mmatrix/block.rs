//! Blocked triangular solves with an [`AccurateLdlt`]: `k` right-hand sides at once.
//!
//! A block is stored row-major (`x[i * k + c]` is row `i` of column `c`), so each entry of the
//! factor is read once per block and applied to `k` contiguous numbers: `k = 16` costs a few
//! single solves, not sixteen. The forward pass skips rows that are still zero in every column,
//! so unit right-hand sides (the columns of `A⁻¹` a goal needs) pay only for their elimination
//! tree paths there. Every operation is that of [`AccurateLdlt::solve`], column by column:
//! additions and products of the factor's non-negative magnitudes, so each column with `b ≥ 0`
//! is entrywise accurate as a single solve is.

use super::AccurateLdlt;
use crate::error::SolverError;

impl AccurateLdlt {
    /// Solves `A X = B` for a block of `k` right-hand sides in place; `x` holds `B` row-major
    /// (`x[i * k + c]`: unknown `i` of column `c`) on entry and `X` on return. Each column is
    /// entrywise accurate when it is non-negative, as with [`AccurateLdlt::solve`].
    ///
    /// ```
    /// use harmonic_solver::{AccurateLdlt, MMatrix, Ordering, SymmetricCsc};
    /// let w = SymmetricCsc::try_new(3, vec![0, 1, 3, 4], vec![1, 0, 2, 1], vec![1.0; 4])?;
    /// let f = AccurateLdlt::factor(&MMatrix::try_new(w, vec![1.0, 0.0, 0.0])?, Ordering::Amd)?;
    /// // Two columns: e_2 and e_0, interleaved row by row.
    /// let mut x = vec![0.0, 1.0, 0.0, 0.0, 1.0, 0.0];
    /// f.solve_block_in_place(&mut x, 2)?;
    /// assert_eq!(x.iter().map(|v| v.round()).collect::<Vec<_>>(), [1.0, 1.0, 2.0, 1.0, 3.0, 1.0]);
    /// # Ok::<(), harmonic_solver::SolverError>(())
    /// ```
    pub fn solve_block_in_place(&self, x: &mut [f64], k: usize) -> Result<(), SolverError> {
        let n = self.n();
        if k == 0 {
            return Ok(());
        }
        if Some(x.len()) != n.checked_mul(k) {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand side block (n × k, row-major)",
                expected: n.saturating_mul(k),
                found: x.len(),
            });
        }
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "right-hand side block",
                index,
            });
        }
        let mut y = vec![0.0; n * k];
        for (new, &old) in self.perm.iter().enumerate() {
            y[new * k..(new + 1) * k].copy_from_slice(&x[old * k..(old + 1) * k]);
        }
        let column = |j: usize| {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            self.row_idx[range.clone()].iter().zip(&self.l[range])
        };
        // L Y = B with L = I − (magnitudes): y_i += l_ij y_j, row j applied to k columns.
        let mut yj = vec![0.0; k];
        for j in 0..n {
            yj.copy_from_slice(&y[j * k..(j + 1) * k]);
            if yj.iter().all(|&v| v == 0.0) {
                continue;
            }
            for (&i, &lij) in column(j) {
                let row = &mut y[i as usize * k..(i as usize + 1) * k];
                for (r, &v) in row.iter_mut().zip(&yj) {
                    *r += lij * v;
                }
            }
        }
        // D Z = Y, then Lᵀ X = Z: x_j = z_j + Σ_i l_ij x_i.
        let mut acc = vec![0.0; k];
        for j in (0..n).rev() {
            let dj = self.d[j];
            for (a, &v) in acc.iter_mut().zip(&y[j * k..(j + 1) * k]) {
                *a = v / dj;
            }
            for (&i, &lij) in column(j) {
                let row = &y[i as usize * k..(i as usize + 1) * k];
                for (a, &v) in acc.iter_mut().zip(row) {
                    *a += lij * v;
                }
            }
            y[j * k..(j + 1) * k].copy_from_slice(&acc);
        }
        for (new, &old) in self.perm.iter().enumerate() {
            x[old * k..(old + 1) * k].copy_from_slice(&y[new * k..(new + 1) * k]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::gallery::triangulated_grid_laplacian;
    use crate::{AccurateLdlt, MMatrix, Ordering, SymmetricCsc};

    /// The grid Laplacian as an M-matrix grounded along its first row.
    fn grounded_grid(nx: usize, ny: usize) -> MMatrix {
        let (a, _) = triangulated_grid_laplacian(nx, ny);
        let n = a.n();
        let mut col_ptr = vec![0];
        let (mut rows, mut vals) = (Vec::new(), Vec::new());
        let mut excess = Vec::with_capacity(n);
        for j in 0..n {
            let (r, v) = a.column(j);
            let (mut diagonal, mut sum) = (0.0, 0.0);
            for (&i, &x) in r.iter().zip(v) {
                if i != j {
                    rows.push(i);
                    vals.push(-x);
                    sum += -x;
                } else {
                    diagonal = x;
                }
            }
            let ground = if j < nx { 1.0 } else { 0.0 };
            excess.push(f64::max(diagonal - sum, 0.0) + ground);
            col_ptr.push(rows.len());
        }
        let w = SymmetricCsc::try_new(n, col_ptr, rows, vals).expect("valid pattern");
        MMatrix::try_new(w, excess).expect("non-negative data")
    }

    #[test]
    fn a_block_equals_its_columns_solved_one_by_one() {
        let m = grounded_grid(12, 9);
        let f = AccurateLdlt::factor(&m, Ordering::Amd).expect("factors");
        let n = f.n();
        let k = 5;
        // Unit columns, a dense positive column and a mixed-sign one.
        let columns: Vec<Vec<f64>> = (0..k)
            .map(|c| match c {
                0..=2 => (0..n)
                    .map(|i| f64::from(u8::from(i == 17 * c + 3)))
                    .collect(),
                3 => (0..n).map(|i| 1.0 + i as f64).collect(),
                _ => (0..n)
                    .map(|i| if i % 2 == 0 { 1.0 } else { -0.5 })
                    .collect(),
            })
            .collect();
        let mut block = vec![0.0; n * k];
        for (c, col) in columns.iter().enumerate() {
            for i in 0..n {
                block[i * k + c] = col[i];
            }
        }
        f.solve_block_in_place(&mut block, k).expect("solves");
        for (c, col) in columns.iter().enumerate() {
            let single = f.solve(col).expect("solves");
            for i in 0..n {
                assert_eq!(block[i * k + c], single[i], "column {c}, row {i}");
            }
        }
    }

    #[test]
    fn a_block_of_the_wrong_size_is_refused() {
        let f = AccurateLdlt::factor(&grounded_grid(4, 4), Ordering::Amd).expect("factors");
        let mut x = vec![0.0; 7];
        assert!(f.solve_block_in_place(&mut x, 2).is_err());
        let mut x = vec![f64::NAN; 2 * f.n()];
        assert!(f.solve_block_in_place(&mut x, 2).is_err());
    }
}
