//! PCG: every preconditioner converges to the direct answer; error paths.

mod common;

use common::*;
use harmonic_solver::{
    PcgOptions, Preconditioner, SolverError, SymmetricCsc, gallery, pcg, solve_direct,
};

const ALL: [Preconditioner; 3] = [
    Preconditioner::None,
    Preconditioner::Jacobi,
    Preconditioner::IncompleteCholesky,
];

#[test]
fn every_preconditioner_converges_to_the_direct_answer() {
    let (a, _) = gallery::triangulated_grid_laplacian(45, 38);
    let b = rhs(a.n(), 9);
    let direct = solve_direct(&a, &b).unwrap();
    let mut iters = vec![];
    for preconditioner in ALL {
        let mut x = vec![0.0; a.n()];
        let opts = PcgOptions {
            preconditioner,
            rel_tol: 1e-12,
            max_iter: 5000,
        };
        let report = pcg(&a, &b, &mut x, &opts).unwrap();
        assert!(
            report.rel_residual <= 1e-12,
            "{preconditioner:?} {report:?}"
        );
        assert!(max_rel_err(&x, &direct) < 1e-9, "{preconditioner:?}");
        iters.push(report.iterations);
    }
    // IC(0) must pay for itself on a Laplacian.
    assert!(iters[2] < iters[0] / 2, "iterations {iters:?}");
}

#[test]
fn random_matrices_with_mixed_signs_converge() {
    for seed in 1..5 {
        let a = random_dd(150, 4, seed);
        let b = rhs(a.n(), seed);
        let reference = dense_solve(&a, &b);
        for preconditioner in ALL {
            let mut x = vec![0.0; a.n()];
            let opts = PcgOptions {
                preconditioner,
                ..Default::default()
            };
            pcg(&a, &b, &mut x, &opts).unwrap();
            assert!(
                max_rel_err(&x, &reference) < 1e-8,
                "{seed} {preconditioner:?}"
            );
        }
    }
}

#[test]
fn initial_guess_is_used() {
    let a = laplacian5(20, 20, 0.01);
    let b = rhs(a.n(), 2);
    let mut x = solve_direct(&a, &b).unwrap();
    let report = pcg(&a, &b, &mut x, &PcgOptions::default()).unwrap();
    assert_eq!(report.iterations, 0);
    let mut zero = vec![0.0; a.n()];
    assert_eq!(
        pcg(&a, &vec![0.0; a.n()], &mut zero, &PcgOptions::default())
            .unwrap()
            .iterations,
        0
    );
}

#[test]
fn iteration_limit_is_not_converged() {
    let (a, _) = gallery::triangulated_grid_laplacian(30, 30);
    let b = rhs(a.n(), 4);
    let mut x = vec![0.0; a.n()];
    let opts = PcgOptions {
        preconditioner: Preconditioner::Jacobi,
        rel_tol: 1e-14,
        max_iter: 5,
    };
    match pcg(&a, &b, &mut x, &opts) {
        Err(SolverError::NotConverged {
            iterations,
            rel_residual,
        }) => {
            assert_eq!(iterations, 5);
            assert!(rel_residual > 1e-14 && rel_residual.is_finite());
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn indefinite_and_singular_are_reported() {
    // diag(1, -1): CG meets negative curvature; Jacobi and IC(0) see the negative pivot.
    let a = SymmetricCsc::try_new(2, vec![0, 1, 2], vec![0, 1], vec![1.0, -1.0]).unwrap();
    for preconditioner in ALL {
        let mut x = vec![0.0; 2];
        let opts = PcgOptions {
            preconditioner,
            ..Default::default()
        };
        let err = pcg(&a, &[1.0, 1.0], &mut x, &opts).unwrap_err();
        assert!(
            matches!(err, SolverError::NotPositiveDefinite { column: 1 }),
            "{preconditioner:?} {err:?}"
        );
    }
    // Missing diagonal at unknown 1.
    let a = SymmetricCsc::try_new(2, vec![0, 1, 1], vec![0], vec![1.0]).unwrap();
    for preconditioner in [Preconditioner::Jacobi, Preconditioner::IncompleteCholesky] {
        let mut x = vec![0.0; 2];
        let opts = PcgOptions {
            preconditioner,
            ..Default::default()
        };
        assert_eq!(
            pcg(&a, &[1.0, 1.0], &mut x, &opts).unwrap_err(),
            SolverError::Singular { column: 1 }
        );
    }
}

#[test]
fn ic0_breakdown_is_repaired_by_a_shift() {
    // SPD but far from an M-matrix: IC(0) without a shift may break down; PCG must still converge.
    // Dense-ish random SPD built as B Bᵀ + small diagonal, stored with its full pattern.
    let n = 40;
    let mut rng = Rng(77);
    let bmat: Vec<Vec<f64>> = (0..n)
        .map(|_| (0..n).map(|_| rng.next_f64() - 0.5).collect())
        .collect();
    let mut t = vec![];
    for i in 0..n {
        for j in 0..=i {
            let mut s: f64 = (0..n).map(|k| bmat[i][k] * bmat[j][k]).sum();
            if i == j {
                s += 1e-2;
            }
            t.push((i, j, s));
        }
    }
    let a = from_triplets(n, &t);
    let b = rhs(n, 8);
    let reference = dense_solve(&a, &b);
    let mut x = vec![0.0; n];
    pcg(&a, &b, &mut x, &PcgOptions::default()).unwrap();
    assert!(max_rel_err(&x, &reference) < 1e-6);
}

#[test]
fn bad_sizes_and_non_finite_input() {
    let a = laplacian5(3, 3, 0.0);
    let mut x = vec![0.0; 9];
    let o = PcgOptions::default();
    assert!(matches!(
        pcg(&a, &[1.0; 8], &mut x, &o),
        Err(SolverError::DimensionMismatch { .. })
    ));
    let mut short = vec![0.0; 2];
    assert!(matches!(
        pcg(&a, &[1.0; 9], &mut short, &o),
        Err(SolverError::DimensionMismatch { .. })
    ));
    let mut b = vec![1.0; 9];
    b[4] = f64::NAN;
    assert_eq!(
        pcg(&a, &b, &mut x, &o).unwrap_err(),
        SolverError::NonFinite {
            what: "right-hand side",
            index: 4
        }
    );
}
