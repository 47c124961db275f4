//! Structure validation: every kind of bad input is a typed error, never a panic, and every
//! accepted random structure goes through the solvers without panicking.

mod common;

use harmonic_solver::{
    AccurateLdlt, MMatrix, Ordering, PcgOptions, Preconditioner, SolverError, StructureIssue,
    SymbolicCholesky, SymmetricCsc, pcg,
};
use proptest::prelude::*;

fn issue(r: Result<SymmetricCsc, SolverError>) -> (usize, StructureIssue) {
    match r {
        Err(SolverError::InvalidStructure { column, issue }) => (column, issue),
        other => panic!("expected InvalidStructure, got {other:?}"),
    }
}

#[test]
fn each_structure_error_is_named() {
    use StructureIssue::*;
    let t = |n, c: Vec<usize>, r: Vec<usize>, v: Vec<f64>| issue(SymmetricCsc::try_new(n, c, r, v));
    assert_eq!(
        t(2, vec![0, 1], vec![0], vec![1.0]),
        (
            0,
            ColPtrLength {
                expected: 3,
                found: 2
            }
        )
    );
    assert_eq!(t(1, vec![1, 1], vec![0], vec![1.0]), (0, ColPtrStart));
    assert_eq!(
        t(2, vec![0, 2, 1], vec![0, 1], vec![1.0, 1.0]),
        (1, ColPtrDecreasing)
    );
    assert_eq!(
        t(1, vec![0, 1], vec![0], vec![]),
        (
            1,
            NnzMismatch {
                col_ptr_end: 1,
                row_idx_len: 1,
                values_len: 0
            }
        )
    );
    assert_eq!(
        t(1, vec![0, 1], vec![3], vec![1.0]),
        (0, RowOutOfBounds { row: 3 })
    );
    assert_eq!(
        t(2, vec![0, 2, 4], vec![1, 0, 0, 1], vec![1.0; 4]),
        (0, UnsortedOrDuplicate { row: 0 })
    );
    assert_eq!(
        t(2, vec![0, 2, 4], vec![0, 0, 0, 1], vec![1.0; 4]),
        (0, UnsortedOrDuplicate { row: 0 })
    );
    assert_eq!(
        t(2, vec![0, 2, 3], vec![0, 1, 1], vec![1.0; 3]),
        (0, MissingMirror { row: 1 })
    );
    // The message names the column and the problem.
    let msg = SymmetricCsc::try_new(2, vec![0, 2, 3], vec![0, 1, 1], vec![1.0; 3])
        .unwrap_err()
        .to_string();
    assert!(msg.contains("column 0") && msg.contains("row 1"), "{msg}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Arbitrary (mostly invalid) CSC arrays: try_new never panics; whatever it accepts, the
    /// direct and iterative solvers handle with a result, never a panic.
    #[test]
    fn random_structures_never_panic(
        n in 0usize..8,
        col_ptr in proptest::collection::vec(0usize..20, 0..10),
        row_idx in proptest::collection::vec(0usize..9, 0..20),
        values in proptest::collection::vec(-3.0f64..3.0, 0..20),
    ) {
        if let Ok(a) = SymmetricCsc::try_new(n, col_ptr, row_idx, values) {
            exercise(&a);
        }
    }

    /// Random symmetric patterns with random values (valid structure, arbitrary numerics).
    #[test]
    fn random_symmetric_matrices_never_panic(
        n in 1usize..10,
        entries in proptest::collection::vec((0usize..10, 0usize..10, -3.0f64..3.0), 0..30),
    ) {
        let t: Vec<_> = entries.into_iter().filter(|&(i, j, _)| i < n && j < n).collect();
        let a = common::from_triplets(n, &t);
        exercise(&a);
    }

    /// Random M-matrices (off-diagonal magnitudes, some zero excesses): factor and solve give a
    /// result or a typed error (Singular for ungrounded components), never a panic.
    #[test]
    fn random_m_matrices_never_panic(
        n in 1usize..10,
        entries in proptest::collection::vec((0usize..10, 0usize..10, 0.0f64..3.0), 0..30),
        excess in proptest::collection::vec(prop_oneof![Just(0.0), 0.0f64..2.0], 10),
    ) {
        let t: Vec<_> = entries.into_iter().filter(|&(i, j, _)| i < n && j < n && i != j).collect();
        let w = common::from_triplets(n, &t);
        let m = MMatrix::try_new(w, excess[..n].to_vec()).unwrap();
        let coords: Vec<[f64; 2]> = (0..n).map(|i| [i as f64, 0.5 * i as f64]).collect();
        for ord in [Ordering::Amd, Ordering::Natural, Ordering::NestedDissection { coords }] {
            match AccurateLdlt::factor(&m, ord) {
                Ok(f) => {
                    let x = f.solve(&vec![1.0; n]).unwrap();
                    prop_assert!(x.iter().all(|v| *v > 0.0 && v.is_finite()));
                }
                Err(e) => prop_assert!(matches!(e, SolverError::Singular { .. }), "{e:?}"),
            }
        }
    }
}

fn exercise(a: &SymmetricCsc) {
    let n = a.n();
    let b = vec![1.0; n];
    let coords: Vec<[f64; 2]> = (0..n).map(|i| [i as f64, (i * i) as f64]).collect();
    for ord in [
        Ordering::Amd,
        Ordering::Natural,
        Ordering::NestedDissection { coords },
    ] {
        if let Ok(c) = SymbolicCholesky::analyze(a, ord).and_then(|s| s.factor(a)) {
            let _ = c.solve(&b);
        }
    }
    for preconditioner in [
        Preconditioner::None,
        Preconditioner::Jacobi,
        Preconditioner::IncompleteCholesky,
    ] {
        let mut x = vec![0.0; n];
        let _ = pcg(
            a,
            &b,
            &mut x,
            &PcgOptions {
                preconditioner,
                rel_tol: 1e-8,
                max_iter: 50,
            },
        );
    }
}

#[test]
fn a_large_product_split_over_threads_equals_the_serial_one_bit_for_bit() {
    // 300 × 300 five-point Laplacian: about 450 k stored entries, above the parallel
    // threshold; each row is summed alone, so any number of threads gives the same bits.
    let a = common::laplacian5(300, 300, 0.01);
    let x = common::rhs(a.n(), 3);
    let product = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut y = vec![0.0; a.n()];
        pool.install(|| a.mul_vec(&x, &mut y));
        y
    };
    let one = product(1);
    for threads in [2, 3] {
        assert_eq!(product(threads), one, "{threads} threads");
    }
    // And a row checked by hand: row 0 of the shifted Laplacian.
    let (rows, vals) = a.column(0);
    let want: f64 = rows.iter().zip(vals).map(|(&k, &v)| v * x[k]).sum();
    assert!((one[0] - want).abs() <= 1e-12 * want.abs().max(1.0));
}
