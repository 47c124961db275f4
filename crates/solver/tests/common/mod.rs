//! Helpers shared by the solver's integration tests: dense reference solves and random SPD
//! matrices (drawn with `harmonic_fixtures::Rng`, re-exported here for the tests).
#![allow(dead_code)] // each test binary uses a subset
#![allow(clippy::needless_range_loop)] // dense reference code reads best with indices

pub use harmonic_fixtures::Rng;
use harmonic_solver::SymmetricCsc;

/// Dense copy of a sparse symmetric matrix (row-major n×n).
pub fn dense(a: &SymmetricCsc) -> Vec<Vec<f64>> {
    let n = a.n();
    let mut d = vec![vec![0.0; n]; n];
    for j in 0..n {
        let (rows, vals) = a.column(j);
        for (&i, &v) in rows.iter().zip(vals) {
            d[i][j] = v;
        }
    }
    d
}

/// Gaussian elimination with partial pivoting: the reference answer.
pub fn dense_solve(a: &SymmetricCsc, b: &[f64]) -> Vec<f64> {
    let n = a.n();
    let mut m = dense(a);
    let mut x = b.to_vec();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| m[i][k].abs().total_cmp(&m[j][k].abs()))
            .unwrap();
        m.swap(k, p);
        x.swap(k, p);
        for i in k + 1..n {
            let f = m[i][k] / m[k][k];
            if f != 0.0 {
                for j in k..n {
                    m[i][j] -= f * m[k][j];
                }
                x[i] -= f * x[k];
            }
        }
    }
    for k in (0..n).rev() {
        let mut s = x[k];
        for j in k + 1..n {
            s -= m[k][j] * x[j];
        }
        x[k] = s / m[k][k];
    }
    x
}

/// Builds a `SymmetricCsc` from (i, j, v) triplets of the upper or lower triangle (mirrored,
/// duplicates summed).
pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)]) -> SymmetricCsc {
    let mut cols: Vec<std::collections::BTreeMap<usize, f64>> = vec![Default::default(); n];
    for &(i, j, v) in triplets {
        *cols[j].entry(i).or_insert(0.0) += v;
        if i != j {
            *cols[i].entry(j).or_insert(0.0) += v;
        }
    }
    let mut col_ptr = vec![0];
    let (mut row_idx, mut values) = (vec![], vec![]);
    for c in &cols {
        for (&i, &v) in c {
            row_idx.push(i);
            values.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    SymmetricCsc::try_new(n, col_ptr, row_idx, values).unwrap()
}

/// Random sparse strictly diagonally dominant symmetric matrix with positive diagonal (SPD),
/// mixed-sign off-diagonals.
pub fn random_dd(n: usize, per_col: usize, seed: u64) -> SymmetricCsc {
    let mut rng = Rng(seed.max(1));
    let mut t = vec![];
    let mut rowsum = vec![0.0; n];
    for j in 0..n {
        for _ in 0..per_col {
            let i = rng.below(n);
            if i != j {
                let v = rng.next_f64() * 2.0 - 1.0;
                t.push((i, j, v));
                rowsum[i] += v.abs();
                rowsum[j] += v.abs();
            }
        }
    }
    for (j, s) in rowsum.iter().enumerate() {
        t.push((j, j, s + 0.1 + rng.next_f64()));
    }
    from_triplets(n, &t)
}

/// 5-point Laplacian on an nx×ny grid plus `shift` on the diagonal.
pub fn laplacian5(nx: usize, ny: usize, shift: f64) -> SymmetricCsc {
    let mut t = vec![];
    for j in 0..ny {
        for i in 0..nx {
            let me = j * nx + i;
            t.push((me, me, 4.0 + shift));
            if i + 1 < nx {
                t.push((me + 1, me, -1.0));
            }
            if j + 1 < ny {
                t.push((me + nx, me, -1.0));
            }
        }
    }
    from_triplets(nx * ny, &t)
}

pub fn max_rel_err(x: &[f64], reference: &[f64]) -> f64 {
    let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    x.iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

pub fn rhs(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = Rng(seed.max(1));
    (0..n).map(|_| rng.next_f64() - 0.3).collect()
}
