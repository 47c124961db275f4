//! Direct Cholesky: answers against dense solves, symbolic reuse, and the error paths.

mod common;

use common::*;
use harmonic_solver::{
    Ordering, SolverError, SymbolicCholesky, SymmetricCsc, gallery, solve_direct,
};

fn orderings(n: usize, coords: Option<Vec<[f64; 2]>>) -> Vec<Ordering> {
    let mut v = vec![Ordering::Amd, Ordering::Natural];
    if let Some(coords) = coords {
        assert_eq!(coords.len(), n);
        v.push(Ordering::NestedDissection { coords });
    }
    v
}

#[test]
fn laplacian_with_shift_matches_dense_for_every_ordering() {
    let (nx, ny) = (13, 11);
    let a = laplacian5(nx, ny, 0.05);
    let coords: Vec<[f64; 2]> = (0..nx * ny)
        .map(|k| [(k % nx) as f64, (k / nx) as f64])
        .collect();
    let b = rhs(a.n(), 7);
    let reference = dense_solve(&a, &b);
    for ord in orderings(a.n(), Some(coords)) {
        let x = SymbolicCholesky::analyze(&a, ord.clone())
            .unwrap()
            .factor(&a)
            .unwrap()
            .solve(&b)
            .unwrap();
        assert!(max_rel_err(&x, &reference) < 1e-12, "{ord:?}");
    }
}

#[test]
fn random_diagonally_dominant_matches_dense() {
    for seed in 1..6 {
        let a = random_dd(120, 3, seed);
        let b = rhs(a.n(), seed + 100);
        let reference = dense_solve(&a, &b);
        let x = solve_direct(&a, &b).unwrap();
        assert!(max_rel_err(&x, &reference) < 1e-12, "seed {seed}");
    }
}

#[test]
fn grid_nested_dissection_matches_amd_and_has_less_fill_than_natural() {
    let (a, coords) = gallery::triangulated_grid_laplacian(40, 35);
    let b = rhs(a.n(), 3);
    let amd = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
    let nd = SymbolicCholesky::analyze(&a, Ordering::NestedDissection { coords }).unwrap();
    let nat = SymbolicCholesky::analyze(&a, Ordering::Natural).unwrap();
    let x_amd = amd.factor(&a).unwrap().solve(&b).unwrap();
    let x_nd = nd.factor(&a).unwrap().solve(&b).unwrap();
    assert!(max_rel_err(&x_nd, &x_amd) < 1e-12);
    // A valid permutation.
    let mut p = nd.permutation().to_vec();
    p.sort_unstable();
    assert!(p.iter().enumerate().all(|(i, &v)| i == v));
    assert!(
        nd.factor_len() < nat.factor_len(),
        "{} vs {}",
        nd.factor_len(),
        nat.factor_len()
    );
}

#[test]
fn refactor_with_new_values_reuses_the_symbolic_analysis() {
    let mut a = random_dd(90, 4, 11);
    let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
    let mut chol = symbolic.factor(&a).unwrap();
    let b = rhs(a.n(), 5);
    assert!(max_rel_err(&chol.solve(&b).unwrap(), &dense_solve(&a, &b)) < 1e-12);
    // Change every value (keep it SPD: scale off-diagonals, bump the diagonal).
    let n = a.n();
    let col_ptr = a.col_ptr().to_vec();
    let row_idx = a.row_idx().to_vec();
    let vals = a.values_mut();
    for j in 0..n {
        for p in col_ptr[j]..col_ptr[j + 1] {
            vals[p] = if row_idx[p] == j {
                vals[p] * 1.5 + 0.3
            } else {
                vals[p] * 0.7
            };
        }
    }
    let reference = dense_solve(&a, &b);
    let x1 = symbolic.factor(&a).unwrap().solve(&b).unwrap();
    chol.refactor(&a).unwrap();
    let mut x2 = b.clone();
    chol.solve_in_place(&mut x2).unwrap();
    assert!(max_rel_err(&x1, &reference) < 1e-12);
    assert_eq!(x1, x2);
}

#[test]
fn failed_refactor_leaves_a_stale_factor_until_the_next_success() {
    let mut a = laplacian5(5, 5, 0.0);
    let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
    let mut chol = symbolic.factor(&a).unwrap();
    let good = a.clone();
    for v in a.values_mut() {
        *v = -*v;
    }
    assert!(matches!(
        chol.refactor(&a),
        Err(SolverError::NotPositiveDefinite { .. })
    ));
    assert_eq!(
        chol.solve(&[1.0; 25]).unwrap_err(),
        SolverError::StaleFactor
    );
    chol.refactor(&good).unwrap();
    let b = rhs(25, 1);
    assert!(max_rel_err(&chol.solve(&b).unwrap(), &dense_solve(&good, &b)) < 1e-12);
}

#[test]
fn pattern_mismatch_is_an_error() {
    let a = laplacian5(6, 5, 0.0);
    let symbolic = SymbolicCholesky::analyze(&a, Ordering::Amd).unwrap();
    // Same size, one extra symmetric pair (0, 29).
    let mut t = vec![];
    for j in 0..a.n() {
        let (rows, vals) = a.column(j);
        for (&i, &v) in rows.iter().zip(vals) {
            if i >= j {
                t.push((i, j, v));
            }
        }
    }
    t.push((29, 0, -0.01));
    let b = from_triplets(a.n(), &t);
    assert_eq!(
        symbolic.factor(&b).unwrap_err(),
        SolverError::PatternMismatch { column: 0 }
    );
    let c = laplacian5(5, 5, 0.0);
    assert!(matches!(
        symbolic.factor(&c),
        Err(SolverError::PatternMismatch { .. })
    ));
    // An equal pattern built separately (not shared with the analysed matrix) is accepted.
    let same = laplacian5(6, 5, 0.0);
    assert!(!same.shares_pattern(&a));
    assert!(symbolic.factor(&same).is_ok());
}

#[test]
fn indefinite_matrix_is_not_positive_definite_in_callers_numbering() {
    // SPD except for one strongly negative diagonal entry. Every pivot eliminated before it
    // comes from an SPD principal submatrix, so the failure is at exactly that unknown, whatever
    // the ordering and whether faer picks the simplicial (small) or supernodal (large) kernel.
    for (side, bad) in [(6, 17), (60, 1234)] {
        let (mut a, coords) = gallery::triangulated_grid_laplacian(side, side);
        let (rows, _) = a.column(bad);
        let k = a.col_ptr()[bad] + rows.binary_search(&bad).unwrap();
        a.values_mut()[k] = -100.0;
        for ord in orderings(a.n(), Some(coords.clone())) {
            let err = SymbolicCholesky::analyze(&a, ord.clone())
                .unwrap()
                .factor(&a)
                .unwrap_err();
            assert_eq!(
                err,
                SolverError::NotPositiveDefinite { column: bad },
                "{side} {ord:?}"
            );
        }
    }
}

#[test]
fn empty_column_is_singular_and_nan_is_rejected() {
    let a = SymmetricCsc::try_new(3, vec![0, 1, 1, 2], vec![0, 2], vec![1.0, 1.0]).unwrap();
    assert_eq!(
        solve_direct(&a, &[1.0; 3]).unwrap_err(),
        SolverError::Singular { column: 1 }
    );
    let a = SymmetricCsc::try_new(1, vec![0, 1], vec![0], vec![f64::NAN]).unwrap();
    assert!(matches!(
        solve_direct(&a, &[1.0]),
        Err(SolverError::NonFinite { .. })
    ));
    let a = SymmetricCsc::try_new(1, vec![0, 1], vec![0], vec![2.0]).unwrap();
    assert!(matches!(
        solve_direct(&a, &[f64::INFINITY]),
        Err(SolverError::NonFinite { .. })
    ));
}

#[test]
fn wrong_sizes_are_dimension_mismatches() {
    let (a, coords) = gallery::triangulated_grid_laplacian(4, 4);
    assert!(matches!(
        solve_direct(&a, &[1.0; 3]),
        Err(SolverError::DimensionMismatch { .. })
    ));
    let chol = SymbolicCholesky::analyze(&a, Ordering::Amd)
        .unwrap()
        .factor(&a)
        .unwrap();
    assert!(matches!(
        chol.solve(&[1.0; 17]),
        Err(SolverError::DimensionMismatch { .. })
    ));
    let short = coords[..5].to_vec();
    assert!(matches!(
        SymbolicCholesky::analyze(&a, Ordering::NestedDissection { coords: short }),
        Err(SolverError::DimensionMismatch { .. })
    ));
    let mut bad = coords;
    bad[3][1] = f64::NAN;
    assert!(matches!(
        SymbolicCholesky::analyze(&a, Ordering::NestedDissection { coords: bad }),
        Err(SolverError::NonFinite { index: 3, .. })
    ));
}

#[test]
fn empty_system_solves_to_empty() {
    let a = SymmetricCsc::try_new(0, vec![0], vec![], vec![]).unwrap();
    assert_eq!(solve_direct(&a, &[]).unwrap(), Vec::<f64>::new());
}

/// The parallel path (forced on a small system, in a two-thread pool) orders the unknowns
/// exactly as the sequential one and solves to rounding.
#[test]
fn parallel_and_sequential_factorisations_agree() {
    use harmonic_solver::Parallelism;
    let (a, coords) = gallery::triangulated_grid_laplacian(90, 70);
    let b = rhs(a.n(), 3);
    let ordering = Ordering::NestedDissection { coords };
    let run = |parallelism| {
        let symbolic = SymbolicCholesky::analyze_with(&a, ordering.clone(), parallelism).unwrap();
        let x = symbolic.factor(&a).unwrap().solve(&b).unwrap();
        (symbolic.permutation().to_vec(), x)
    };
    let (perm_seq, x_seq) = run(Parallelism::Sequential);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let (perm_par, x_par) = pool.install(|| {
        run(Parallelism::Rayon {
            from_unknowns: 0,
            dense_kernels: true,
        })
    });
    assert_eq!(perm_seq, perm_par);
    assert!(max_rel_err(&x_par, &x_seq) < 1e-12);
    let mut ax = vec![0.0; a.n()];
    a.mul_vec(&x_par, &mut ax);
    assert!(max_rel_err(&ax, &b) < 1e-10);
}
