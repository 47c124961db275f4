//! Smoothed aggregation: a multigrid hierarchy built from the matrix alone, for meshes that
//! come with no coarser levels (stuffed tetrahedra, configuration-space slabs, meshes made
//! elsewhere).
//!
//! The steps are Vaněk, Mandel and Brezina's smoothed aggregation as PyAMG's
//! `smoothed_aggregation_solver` does it for a scalar problem; [`Multigrid::aggregation`]
//! lists them. The cycle itself is [`Multigrid`]'s: Gauss–Seidel smoothing, symmetric, a
//! preconditioner for conjugate gradients.

use rayon::prelude::*;

use crate::csc::SymmetricCsc;
use crate::error::SolverError;
use crate::multigrid::{Multigrid, MultigridOptions, Prolongation, SparseRows};
use crate::{Ordering, SymbolicCholesky};

/// How [`Multigrid::aggregation`] coarsens.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AggregationOptions {
    /// The strength threshold θ (step 1 in [`Multigrid::aggregation`]). Default 0, PyAMG's
    /// default: every neighbour is strong. On the stuffed tetrahedral meshes θ = 0.08 left
    /// the second level barely coarsened and dense (13 k unknowns → 9.7 k with 340 entries a
    /// row, setup 1.1 s against 0.16 s at θ = 0, for 12 iterations against 14).
    pub strength: f64,
    /// Coarsen until a level has at most this many unknowns. Default 2 000.
    pub coarsest: usize,
    /// At most this many levels, the finest included. Default 12.
    pub max_levels: usize,
    /// The cycle's smoothing.
    pub cycle: MultigridOptions,
}

impl Default for AggregationOptions {
    fn default() -> Self {
        Self {
            strength: 0.0,
            coarsest: 2_000,
            max_levels: 12,
            cycle: MultigridOptions { sweeps: 1 },
        }
    }
}

/// A level stops coarsening when the next would keep more than this share of its unknowns.
const MIN_SHRINK: f64 = 0.8;

const FREE: u32 = u32::MAX;

impl Multigrid {
    /// The V-cycle of a smoothed-aggregation hierarchy built from `a`, which must be
    /// symmetric with a positive diagonal. Each level is coarsened in four steps:
    ///
    /// 1. **Strength.** `j` is a strong neighbour of `i` when `|a_ij| ≥ θ √(a_ii a_jj)`.
    /// 2. **Aggregates.** Greedy, in the unknowns' order: an unknown whose strong neighbours
    ///    are all still free roots an aggregate with them; a free one left over joins its
    ///    strongest aggregated neighbour's; what is still free then roots its own.
    /// 3. **Prolongation.** Piecewise constant, smoothed by one damped Jacobi step,
    ///    `P = (I − ω D⁻¹A) P₀`, `ω = 4 / (3ρ)` with `ρ` Gershgorin's bound of `D⁻¹A`.
    /// 4. **Coarse matrix.** The Galerkin product `Pᵀ A P`, on rayon's pool.
    ///
    /// Coarsening stops at [`AggregationOptions::coarsest`] unknowns (factored by Cholesky)
    /// or when a level no longer shrinks; the cycle is the Gauss–Seidel V-cycle of
    /// [`Multigrid::new`].
    ///
    /// ```
    /// use harmonic_solver::{AggregationOptions, Multigrid, gallery};
    /// let a = gallery::triangulated_grid_laplacian(60, 60).0;
    /// let mg = Multigrid::aggregation(&a, AggregationOptions { coarsest: 100, ..Default::default() })?;
    /// assert!(mg.level_count() > 2);
    /// let b = vec![1.0; a.n()];
    /// let mut x = vec![0.0; a.n()];
    /// let report = mg.solve(&b, &mut x, 1e-10, 100)?;
    /// assert!(report.iterations < 30);
    /// # Ok::<(), harmonic_solver::SolverError>(())
    /// ```
    pub fn aggregation(a: &SymmetricCsc, opts: AggregationOptions) -> Result<Self, SolverError> {
        let mut coarse: Vec<SymmetricCsc> = Vec::new();
        let mut prolongations: Vec<Prolongation> = Vec::new();
        loop {
            let current = coarse.last().unwrap_or(a);
            let n = current.n();
            if n <= opts.coarsest || coarse.len() + 1 >= opts.max_levels.max(1) {
                break;
            }
            let diagonal = positive_diagonal(current)?;
            let (aggregate_of, aggregates) = aggregate(current, &diagonal, opts.strength);
            if aggregates == 0 || aggregates as f64 > MIN_SHRINK * n as f64 {
                break;
            }
            let p = smoothed_prolongation(current, &diagonal, &aggregate_of, aggregates)?;
            let next = galerkin_product(current, &p)?;
            prolongations.push(p);
            coarse.push(next);
        }
        let coarsest = coarse.last().unwrap_or(a);
        let factor = SymbolicCholesky::analyze(coarsest, Ordering::Amd)?.factor(coarsest)?;
        // Coarse to fine: level k's matrix with the prolongation from level k + 1 into it.
        let matrices: Vec<&SymmetricCsc> = std::iter::once(a).chain(&coarse).collect();
        let levels = matrices
            .into_iter()
            .zip(prolongations)
            .rev()
            .collect::<Vec<_>>();
        Multigrid::new(factor, levels, opts.cycle)
    }
}

/// The diagonal of `a`, every entry positive (an error names the first that is not).
fn positive_diagonal(a: &SymmetricCsc) -> Result<Vec<f64>, SolverError> {
    let d = a.diagonal();
    match d.iter().position(|&v| v.is_nan() || v <= 0.0) {
        Some(column) if d[column] == 0.0 => Err(SolverError::Singular { column }),
        Some(column) => Err(SolverError::NotPositiveDefinite { column }),
        None => Ok(d),
    }
}

/// Steps 1 and 2: each unknown's aggregate, and the number of aggregates.
fn aggregate(a: &SymmetricCsc, diagonal: &[f64], theta: f64) -> (Vec<u32>, usize) {
    let n = a.n();
    let theta2 = theta * theta;
    // Strong neighbours of i, with their strength a_ij² / (a_jj) (a_ii is common to a row).
    let strong = |i: usize| {
        let (rows, vals) = a.column(i);
        rows.iter()
            .zip(vals)
            .filter(move |&(&j, &v)| j != i && v * v >= theta2 * diagonal[i] * diagonal[j])
            .map(|(&j, &v)| (j, v * v / diagonal[j]))
    };
    let mut aggregate_of = vec![FREE; n];
    let mut rooted = vec![false; n];
    let mut count: u32 = 0;
    // Pass 1: roots whose strong neighbourhood is all free.
    for i in 0..n {
        if aggregate_of[i] != FREE || strong(i).any(|(j, _)| aggregate_of[j] != FREE) {
            continue;
        }
        aggregate_of[i] = count;
        rooted[i] = true;
        for (j, _) in strong(i) {
            aggregate_of[j] = count;
            rooted[j] = true;
        }
        count += 1;
    }
    // Pass 2: the rest joins its strongest neighbour's aggregate of pass 1.
    for i in 0..n {
        if aggregate_of[i] != FREE {
            continue;
        }
        let best = strong(i)
            .filter(|&(j, _)| rooted[j])
            .max_by(|x, y| x.1.total_cmp(&y.1));
        if let Some((j, _)) = best {
            aggregate_of[i] = aggregate_of[j];
        }
    }
    // Pass 3: what is still free (no strong neighbour aggregated in pass 1) roots its own.
    for i in 0..n {
        if aggregate_of[i] != FREE {
            continue;
        }
        aggregate_of[i] = count;
        for (j, _) in strong(i) {
            if aggregate_of[j] == FREE {
                aggregate_of[j] = count;
            }
        }
        count += 1;
    }
    (aggregate_of, count as usize)
}

/// Step 3: `P = (I − ω D⁻¹ A) P₀` by rows.
fn smoothed_prolongation(
    a: &SymmetricCsc,
    diagonal: &[f64],
    aggregate_of: &[u32],
    aggregates: usize,
) -> Result<Prolongation, SolverError> {
    let n = a.n();
    // Gershgorin: ρ(D⁻¹A) ≤ max_i Σ_j |a_ij| / a_ii.
    let rho = (0..n)
        .into_par_iter()
        .map(|i| a.column(i).1.iter().map(|v| v.abs()).sum::<f64>() / diagonal[i])
        .reduce(|| 0.0, f64::max);
    let omega = 4.0 / (3.0 * rho.max(1.0));
    let chunk = n
        .div_ceil(4 * rayon::current_num_threads().max(1))
        .max(1024);
    let rows = rows_by_chunks(n, aggregates, chunk, |i, acc| {
        let (cols, vals) = a.column(i);
        let scale = omega / diagonal[i];
        for (&j, &v) in cols.iter().zip(vals) {
            let w = if j == i { 1.0 - omega } else { -scale * v };
            acc.add(aggregate_of[j], w);
        }
    });
    Prolongation::try_new(aggregates, rows.row_ptr, rows.columns, rows.values)
}

/// Step 4: `Pᵀ A P`, symmetric by construction of its pattern.
fn galerkin_product(a: &SymmetricCsc, p: &Prolongation) -> Result<SymmetricCsc, SolverError> {
    let (n, nc) = (a.n(), p.coarse_len());
    let chunk = n
        .div_ceil(4 * rayon::current_num_threads().max(1))
        .max(1024);
    // A P by rows (a sparse accumulator per chunk of rows).
    let ap = rows_by_chunks(n, nc, chunk, |i, acc| {
        let (cols, vals) = a.column(i);
        for (&j, &v) in cols.iter().zip(vals) {
            let (pc, pv) = p.row(j);
            for (&c, &w) in pc.iter().zip(pv) {
                acc.add(c, v * w);
            }
        }
    });
    // Pᵀ by rows: for each aggregate, the fine rows that reach it.
    let pt = p.transpose();
    let coarse = rows_by_chunks(nc, nc, chunk.min(nc.div_ceil(8)).max(64), |c, acc| {
        let (fine, weights) = pt.row(c);
        for (&i, &w) in fine.iter().zip(weights) {
            let (cols, vals) = ap.row(i as usize);
            for (&d, &v) in cols.iter().zip(vals) {
                acc.add(d, w * v);
            }
        }
    });
    let SparseRows {
        row_ptr,
        columns,
        values,
    } = coarse;
    let row_idx = columns.into_iter().map(|c| c as usize).collect();
    SymmetricCsc::try_from_symmetric_pattern(nc, row_ptr, row_idx, values)
}

/// A dense accumulator over `width` columns that remembers which it touched.
struct Accumulator {
    values: Vec<f64>,
    touched: Vec<u32>,
    seen: Vec<bool>,
}

impl Accumulator {
    fn new(width: usize) -> Self {
        Self {
            values: vec![0.0; width],
            touched: Vec::new(),
            seen: vec![false; width],
        }
    }

    #[inline]
    fn add(&mut self, c: u32, v: f64) {
        let k = c as usize;
        if !self.seen[k] {
            self.seen[k] = true;
            self.touched.push(c);
        }
        self.values[k] += v;
    }

    /// Appends the row (sorted, every touched column kept so patterns stay symmetric) and
    /// clears.
    fn drain_into(&mut self, columns: &mut Vec<u32>, values: &mut Vec<f64>) {
        self.touched.sort_unstable();
        for &c in &self.touched {
            let k = c as usize;
            columns.push(c);
            values.push(self.values[k]);
            self.values[k] = 0.0;
            self.seen[k] = false;
        }
        self.touched.clear();
    }
}

/// `rows` rows of width `width`, each filled by `fill(i, accumulator)`, in chunks of `chunk`
/// rows on rayon's pool.
fn rows_by_chunks(
    rows: usize,
    width: usize,
    chunk: usize,
    fill: impl Fn(usize, &mut Accumulator) + Sync,
) -> SparseRows {
    let starts: Vec<usize> = (0..rows).step_by(chunk.max(1)).collect();
    let pieces: Vec<(Vec<usize>, Vec<u32>, Vec<f64>)> = starts
        .par_iter()
        .map_init(
            || Accumulator::new(width),
            |acc, &start| {
                let end = (start + chunk).min(rows);
                let (mut lens, mut columns, mut values) =
                    (Vec::with_capacity(end - start), Vec::new(), Vec::new());
                for i in start..end {
                    fill(i, acc);
                    let before = columns.len();
                    acc.drain_into(&mut columns, &mut values);
                    lens.push(columns.len() - before);
                }
                (lens, columns, values)
            },
        )
        .collect();
    let nnz = pieces.iter().map(|p| p.1.len()).sum();
    let mut out = SparseRows {
        row_ptr: Vec::with_capacity(rows + 1),
        columns: Vec::with_capacity(nnz),
        values: Vec::with_capacity(nnz),
    };
    out.row_ptr.push(0);
    for (lens, columns, values) in pieces {
        for l in lens {
            out.row_ptr
                .push(out.row_ptr.last().copied().unwrap_or(0) + l);
        }
        out.columns.extend(columns);
        out.values.extend(values);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gallery;

    #[test]
    fn a_diagonal_that_is_not_positive_is_refused_by_name() {
        let (a, _) = gallery::triangulated_grid_laplacian(60, 60);
        let mut bad = a.clone();
        let (rows, _) = a.column(17);
        let k = a.col_ptr()[17] + rows.iter().position(|&r| r == 17).expect("diagonal");
        bad.values_mut()[k] = -1.0;
        let opts = AggregationOptions {
            coarsest: 100,
            ..Default::default()
        };
        assert!(matches!(
            Multigrid::aggregation(&bad, opts),
            Err(SolverError::NotPositiveDefinite { column: 17 })
        ));
    }

    #[test]
    fn aggregates_cover_every_unknown_and_coarsen() {
        let a = gallery::triangulated_grid_laplacian(40, 40).0;
        let d = a.diagonal();
        let (of, count) = aggregate(&a, &d, 0.08);
        assert!(of.iter().all(|&c| (c as usize) < count));
        // Seven-point stencil: aggregates of about 4–12 points.
        assert!(
            count * 4 < a.n() && count * 12 > a.n(),
            "{count} of {}",
            a.n()
        );
    }

    #[test]
    fn galerkin_product_matches_dense_arithmetic() {
        let a = gallery::triangulated_grid_laplacian(7, 6).0;
        let d = a.diagonal();
        let (of, count) = aggregate(&a, &d, 0.08);
        let p = smoothed_prolongation(&a, &d, &of, count).expect("P");
        let c = galerkin_product(&a, &p).expect("PᵀAP");
        let n = a.n();
        let dense_p = |i: usize, k: usize| {
            let (cols, vals) = p.row(i);
            cols.iter()
                .zip(vals)
                .find(|e| *e.0 as usize == k)
                .map_or(0.0, |e| *e.1)
        };
        let dense_a = |i: usize, j: usize| {
            let (rows, vals) = a.column(j);
            rows.iter()
                .zip(vals)
                .find(|e| *e.0 == i)
                .map_or(0.0, |e| *e.1)
        };
        for k in 0..count {
            for l in 0..count {
                let mut s = 0.0;
                for i in 0..n {
                    for j in 0..n {
                        s += dense_p(i, k) * dense_a(i, j) * dense_p(j, l);
                    }
                }
                let (rows, vals) = c.column(l);
                let got = rows
                    .iter()
                    .zip(vals)
                    .find(|e| *e.0 == k)
                    .map_or(0.0, |e| *e.1);
                assert!((got - s).abs() < 1e-12, "({k}, {l}): {got} vs {s}");
            }
        }
    }

    #[test]
    fn the_cycle_converges_in_few_iterations_whatever_the_size() {
        for side in [40, 120] {
            let a = gallery::triangulated_grid_laplacian(side, side).0;
            let mg = Multigrid::aggregation(
                &a,
                AggregationOptions {
                    coarsest: 50,
                    ..Default::default()
                },
            )
            .expect("hierarchy");
            let b: Vec<f64> = (0..a.n()).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let mut x = vec![0.0; a.n()];
            let report = mg.solve(&b, &mut x, 1e-10, 200).expect("converges");
            assert!(
                report.iterations <= 25,
                "{side}²: {} iterations",
                report.iterations
            );
            let mut ax = vec![0.0; a.n()];
            a.mul_vec(&x, &mut ax);
            let r: f64 = ax
                .iter()
                .zip(&b)
                .map(|(p, q)| (p - q) * (p - q))
                .sum::<f64>()
                .sqrt();
            let bn: f64 = b.iter().map(|v| v * v).sum::<f64>().sqrt();
            assert!(r <= 1e-9 * bn);
        }
    }
}
