//! Preconditioned conjugate gradients for systems whose Cholesky factor will not fit.

use crate::csc::SymmetricCsc;
use crate::error::SolverError;

/// Preconditioner for [`pcg`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Preconditioner {
    /// Plain conjugate gradients.
    None,
    /// Diagonal scaling.
    Jacobi,
    /// Zero-fill incomplete Cholesky on the matrix's own lower-triangle pattern, natural ordering.
    /// If it breaks down (possible outside M-matrices) it is recomputed with a growing diagonal
    /// shift (Manteuffel).
    #[default]
    IncompleteCholesky,
}

/// Options for [`pcg`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PcgOptions {
    /// Preconditioner (default IC(0)).
    pub preconditioner: Preconditioner,
    /// Stop when ‖b − Ax‖₂ ≤ rel_tol · ‖b‖₂ (default 1e-10).
    pub rel_tol: f64,
    /// Give up after this many iterations (default 10 000).
    pub max_iter: usize,
}

impl Default for PcgOptions {
    fn default() -> Self {
        Self {
            preconditioner: Preconditioner::default(),
            rel_tol: 1e-10,
            max_iter: 10_000,
        }
    }
}

/// Outcome of a converged [`pcg`] run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PcgReport {
    /// Iterations performed.
    pub iterations: usize,
    /// True relative residual ‖b − Ax‖₂ / ‖b‖₂ of the returned `x` (recomputed, not the recurrence).
    pub rel_residual: f64,
}

/// Solves `A x = b` by preconditioned conjugate gradients, starting from the `x` given
/// (pass zeros for no initial guess; a good guess such as the previous solution saves iterations).
///
/// ```
/// use harmonic_solver::{gallery, pcg, PcgOptions};
/// let (a, _) = gallery::triangulated_grid_laplacian(30, 30);
/// let b = vec![1.0; a.n()];
/// let mut x = vec![0.0; a.n()];
/// let report = pcg(&a, &b, &mut x, &PcgOptions::default())?;
/// assert!(report.rel_residual <= 1e-10);
/// # Ok::<(), harmonic_solver::SolverError>(())
/// ```
pub fn pcg(
    a: &SymmetricCsc,
    b: &[f64],
    x: &mut [f64],
    opts: &PcgOptions,
) -> Result<PcgReport, SolverError> {
    check_inputs(a, b, x)?;
    if let Some(zero) = zero_rhs(b, x) {
        return Ok(zero);
    }
    let precond = Precond::new(a, opts.preconditioner)?;
    let product = |v: &[f64], av: &mut [f64]| a.mul_vec(v, av);
    iterate_with(product, b, x, &precond, opts.rel_tol, opts.max_iter)
}

/// A preconditioner for [`pcg_with`]: `z ≈ A⁻¹ r` by a fixed symmetric positive definite
/// operator (conjugate gradients need the same operator at every iteration).
pub trait Precondition {
    /// Writes the preconditioned residual `z` for the residual `r` (both of the system's size).
    fn precondition(&self, r: &[f64], z: &mut [f64]);
}

/// [`pcg`] with a preconditioner of the caller's, such as [`crate::Multigrid`]: stops when
/// ‖b − Ax‖₂ ≤ `rel_tol` · ‖b‖₂, errors after `max_iter` iterations.
pub fn pcg_with<P: Precondition + ?Sized>(
    a: &SymmetricCsc,
    b: &[f64],
    x: &mut [f64],
    precond: &P,
    rel_tol: f64,
    max_iter: usize,
) -> Result<PcgReport, SolverError> {
    check_inputs(a, b, x)?;
    if let Some(zero) = zero_rhs(b, x) {
        return Ok(zero);
    }
    let product = |v: &[f64], av: &mut [f64]| a.mul_vec(v, av);
    iterate_with(product, b, x, precond, rel_tol, max_iter)
}

/// For `b = 0`, the solution `x = 0` and its report, with no iteration (and no
/// preconditioner built).
pub(crate) fn zero_rhs(b: &[f64], x: &mut [f64]) -> Option<PcgReport> {
    b.iter().all(|&v| v == 0.0).then(|| {
        x.fill(0.0);
        PcgReport {
            iterations: 0,
            rel_residual: 0.0,
        }
    })
}

/// Sizes match and every number is finite.
fn check_inputs(a: &SymmetricCsc, b: &[f64], x: &[f64]) -> Result<(), SolverError> {
    let n = a.n();
    for (what, len) in [("right-hand side", b.len()), ("initial guess", x.len())] {
        if len != n {
            return Err(SolverError::DimensionMismatch {
                what,
                expected: n,
                found: len,
            });
        }
    }
    if let Some(index) = a.first_non_finite() {
        return Err(SolverError::NonFinite {
            what: "matrix values",
            index,
        });
    }
    for (what, v) in [("right-hand side", b), ("initial guess", x)] {
        if let Some(index) = v.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite { what, index });
        }
    }
    Ok(())
}

/// The iteration itself, on checked inputs with `b ≠ 0`, `A` given by its product
/// `a(v, av)` (`av = A v`).
pub(crate) fn iterate_with<A: Fn(&[f64], &mut [f64]), P: Precondition + ?Sized>(
    a: A,
    b: &[f64],
    x: &mut [f64],
    precond: &P,
    rel_tol: f64,
    max_iter: usize,
) -> Result<PcgReport, SolverError> {
    let n = b.len();
    let b_norm = norm(b);
    let tol = rel_tol * b_norm;

    let mut r = vec![0.0; n];
    let mut z = vec![0.0; n];
    let mut p = vec![0.0; n];
    let mut ap = vec![0.0; n];
    let mut iterations = 0;
    // Outer loop: restarts from the true residual when the recurrence claims convergence but the
    // true residual disagrees (rounding drift).
    loop {
        a(x, &mut r);
        for (ri, bi) in r.iter_mut().zip(b) {
            *ri = bi - *ri;
        }
        let true_res = norm(&r);
        if true_res <= tol {
            return Ok(PcgReport {
                iterations,
                rel_residual: true_res / b_norm,
            });
        }
        if iterations >= max_iter {
            return Err(SolverError::NotConverged {
                iterations,
                rel_residual: true_res / b_norm,
            });
        }
        precond.precondition(&r, &mut z);
        p.copy_from_slice(&z);
        let mut rz = dot(&r, &z);
        while iterations < max_iter {
            iterations += 1;
            a(&p, &mut ap);
            let pap = dot(&p, &ap);
            if pap <= 0.0 || !pap.is_finite() {
                // Name the unknown contributing the most negative curvature pᵢ (Ap)ᵢ.
                let column = most_negative_product(&p, &ap);
                return Err(SolverError::NotPositiveDefinite { column });
            }
            let alpha = rz / pap;
            for i in 0..n {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
            }
            if norm(&r) <= tol {
                break;
            }
            precond.precondition(&r, &mut z);
            let rz_new = dot(&r, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for (pi, zi) in p.iter_mut().zip(&z) {
                *pi = zi + beta * *pi;
            }
        }
    }
}

/// Lanes of [`dot`]'s partial sums.
const LANES: usize = 8;

/// `a · b` in [`LANES`] partial sums (entry i into lane i mod 8) added pairwise at the end:
/// one running sum waits on each addition before the next (four cycles an entry), eight are
/// independent and fill the vector units. The order is fixed, so the result does not depend
/// on the machine or the thread count.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0; LANES];
    let (a_rest, b_rest) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let tail = a_rest.remainder().iter().zip(b_rest.remainder());
    for (x, y) in a_rest.zip(b_rest) {
        for k in 0..LANES {
            lanes[k] += x[k] * y[k];
        }
    }
    for (k, (x, y)) in tail.enumerate() {
        lanes[k] += x * y;
    }
    let [l0, l1, l2, l3, l4, l5, l6, l7] = lanes;
    ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7))
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

fn most_negative_product(p: &[f64], ap: &[f64]) -> usize {
    let mut best = (0, f64::INFINITY);
    for (i, (x, y)) in p.iter().zip(ap).enumerate() {
        let c = x * y;
        if c < best.1 {
            best = (i, c);
        }
    }
    best.0
}

enum Precond {
    Identity,
    InvDiag(Vec<f64>),
    Ic0(Ic0),
}

impl Precond {
    fn new(a: &SymmetricCsc, kind: Preconditioner) -> Result<Self, SolverError> {
        Ok(match kind {
            Preconditioner::None => Self::Identity,
            Preconditioner::Jacobi => {
                let d = a.diagonal();
                if let Some(column) = d.iter().position(|&v| v <= 0.0) {
                    return Err(if d[column] == 0.0 {
                        SolverError::Singular { column }
                    } else {
                        SolverError::NotPositiveDefinite { column }
                    });
                }
                Self::InvDiag(d.iter().map(|v| 1.0 / v).collect())
            }
            Preconditioner::IncompleteCholesky => Self::Ic0(Ic0::new(a)?),
        })
    }
}

impl Precondition for Precond {
    fn precondition(&self, r: &[f64], z: &mut [f64]) {
        match self {
            Self::Identity => z.copy_from_slice(r),
            Self::InvDiag(d) => {
                for ((zi, ri), di) in z.iter_mut().zip(r).zip(d) {
                    *zi = ri * di;
                }
            }
            Self::Ic0(ic) => ic.solve(r, z),
        }
    }
}

/// Zero-fill incomplete Cholesky factor `L` (lower triangle of A's pattern, CSC, diagonal first).
/// Row numbers are `u32`: the two triangular solves of every iteration stream the whole
/// factor, and the narrower indices are a quarter less of it.
struct Ic0 {
    col_ptr: Vec<usize>,
    row_idx: Vec<u32>,
    values: Vec<f64>,
}

impl Ic0 {
    fn new(a: &SymmetricCsc) -> Result<Self, SolverError> {
        let n = a.n();
        if u32::try_from(n).is_err() {
            return Err(SolverError::DimensionMismatch {
                what: "IC(0) unknowns (numbered in 32 bits)",
                expected: u32::MAX as usize,
                found: n,
            });
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(a.nnz() / 2 + n);
        let mut orig = Vec::with_capacity(a.nnz() / 2 + n);
        col_ptr.push(0);
        for j in 0..n {
            let (rows, vals) = a.column(j);
            let start = rows.partition_point(|&i| i < j);
            if rows.get(start) != Some(&j) {
                // No stored diagonal: a zero diagonal entry.
                return Err(SolverError::Singular { column: j });
            }
            row_idx.extend(rows[start..].iter().map(|&i| i as u32));
            orig.extend_from_slice(&vals[start..]);
            col_ptr.push(row_idx.len());
        }
        let mut ic = Self {
            col_ptr,
            row_idx,
            values: orig.clone(),
        };
        let max_diag = (0..n)
            .map(|j| orig[ic.col_ptr[j]].abs())
            .fold(0.0, f64::max);
        let mut shift = 0.0;
        let mut pos = vec![usize::MAX; n];
        loop {
            match ic.factor(&orig, shift, &mut pos) {
                Ok(()) => return Ok(ic),
                Err(column) => {
                    let d = orig[ic.col_ptr[column]];
                    if d <= 0.0 {
                        return Err(if d == 0.0 {
                            SolverError::Singular { column }
                        } else {
                            SolverError::NotPositiveDefinite { column }
                        });
                    }
                    shift = if shift == 0.0 { 1e-3 } else { shift * 4.0 };
                    if shift > 1e3 || max_diag == 0.0 {
                        return Err(SolverError::NotPositiveDefinite { column });
                    }
                }
            }
        }
    }

    /// Right-looking IC(0) of `orig` with the diagonal scaled by `1 + shift`; on breakdown returns
    /// the column whose pivot was not positive.
    fn factor(&mut self, orig: &[f64], shift: f64, pos: &mut [usize]) -> Result<(), usize> {
        let n = self.col_ptr.len() - 1;
        self.values.copy_from_slice(orig);
        for j in 0..n {
            let d = self.col_ptr[j];
            self.values[d] *= 1.0 + shift;
        }
        for k in 0..n {
            let (start, end) = (self.col_ptr[k], self.col_ptr[k + 1]);
            let pivot = self.values[start];
            if pivot <= 0.0 || !pivot.is_finite() {
                return Err(k);
            }
            let lkk = pivot.sqrt();
            self.values[start] = lkk;
            for v in &mut self.values[start + 1..end] {
                *v /= lkk;
            }
            // Update the later columns j in column k's pattern, only where (i, j) is stored.
            for jj in start + 1..end {
                let j = self.row_idx[jj] as usize;
                let ljk = self.values[jj];
                let (js, je) = (self.col_ptr[j], self.col_ptr[j + 1]);
                for p in js..je {
                    pos[self.row_idx[p] as usize] = p;
                }
                for ii in jj..end {
                    let p = pos[self.row_idx[ii] as usize];
                    if p != usize::MAX {
                        self.values[p] -= self.values[ii] * ljk;
                    }
                }
                for p in js..je {
                    pos[self.row_idx[p] as usize] = usize::MAX;
                }
            }
        }
        Ok(())
    }

    /// `z = (L Lᵀ)⁻¹ r`.
    fn solve(&self, r: &[f64], z: &mut [f64]) {
        let n = self.col_ptr.len() - 1;
        z.copy_from_slice(r);
        for j in 0..n {
            let (s, e) = (self.col_ptr[j], self.col_ptr[j + 1]);
            let zj = z[j] / self.values[s];
            z[j] = zj;
            for (&i, &l) in self.row_idx[s + 1..e].iter().zip(&self.values[s + 1..e]) {
                z[i as usize] -= l * zj;
            }
        }
        for j in (0..n).rev() {
            let (s, e) = (self.col_ptr[j], self.col_ptr[j + 1]);
            let mut acc = z[j];
            for (&i, &l) in self.row_idx[s + 1..e].iter().zip(&self.values[s + 1..e]) {
                acc -= l * z[i as usize];
            }
            z[j] = acc / self.values[s];
        }
    }
}
