//! Accurate LDLᵀ for M-matrices: entrywise accuracy on solutions spanning 1e-200..1, agreement
//! with dense solves on ordinary matrices, and the error paths.

mod common;

use common::*;
use harmonic_solver::{
    AccurateLdlt, LdltAnalysis, MMatrix, Ordering, SolverError, StructureIssue, SymmetricCsc,
    solve_direct,
};

/// Off-diagonal magnitudes from (i, j, w) pairs (i != j), mirrored.
fn offdiag(n: usize, edges: &[(usize, usize, f64)]) -> SymmetricCsc {
    from_triplets(n, edges)
}

/// Short name of an ordering (its Debug form would print every coordinate).
fn label(ord: &Ordering) -> &'static str {
    match ord {
        Ordering::Amd => "amd",
        Ordering::Natural => "natural",
        Ordering::NestedDissection { .. } => "nested dissection",
    }
}

/// Largest entrywise relative error.
fn entrywise(x: &[f64], exact: &[f64]) -> f64 {
    x.iter()
        .zip(exact)
        .fold(0.0f64, |m, (a, e)| m.max(((a - e) / e).abs()))
}

/// Chain / strip with absorption ε at every node, fed at the left end through a unit edge from a
/// ghost node held at 1. The exact solution is λ^(i+1) in column i, where λ + 1/λ = 2 + ε; the
/// last column gets excess 1/λ − 1 (+ ε − ε, i.e. exactly t) so that no wave reflects.
fn decaying_strip(nx: usize, ny: usize, eps: f64) -> (MMatrix, Vec<f64>, Vec<f64>, Vec<[f64; 2]>) {
    let t = eps / 2.0 + (eps + eps * eps / 4.0).sqrt(); // 1/λ = 1 + t
    let idx = |i: usize, y: usize| y * nx + i;
    let mut edges = vec![];
    let mut excess = vec![eps; nx * ny];
    let mut b = vec![0.0; nx * ny];
    let mut coords = vec![[0.0; 2]; nx * ny];
    for y in 0..ny {
        for i in 0..nx {
            coords[idx(i, y)] = [i as f64, y as f64];
            if i + 1 < nx {
                edges.push((idx(i + 1, y), idx(i, y), 1.0));
            }
            if y + 1 < ny {
                edges.push((idx(i, y + 1), idx(i, y), 1.0));
            }
        }
        // Ghost edge at the left (Dirichlet value 1): excess +1, load 1.
        excess[idx(0, y)] += 1.0;
        b[idx(0, y)] = 1.0;
        // Right end: a_ii x_i = x_{i-1} needs a_ii = 1 + t, i.e. excess t (ε replaced).
        excess[idx(nx - 1, y)] = t;
    }
    let m = MMatrix::try_new(offdiag(nx * ny, &edges), excess).unwrap();
    let ln = t.ln_1p();
    let exact: Vec<f64> = (0..nx * ny)
        .map(|k| (-((k % nx + 1) as f64) * ln).exp())
        .collect();
    (m, b, exact, coords)
}

#[test]
fn chain_decaying_to_1e_minus_200_is_entrywise_accurate() {
    let eps = 2f64.powi(-16);
    let (m, b, exact, coords) = decaying_strip(118_500, 1, eps);
    assert!(
        exact[exact.len() - 1] < 1e-199,
        "{}",
        exact[exact.len() - 1]
    );
    for ord in [
        Ordering::Natural,
        Ordering::Amd,
        Ordering::NestedDissection { coords },
    ] {
        let x = AccurateLdlt::factor(&m, ord.clone())
            .unwrap()
            .solve(&b)
            .unwrap();
        let err = entrywise(&x, &exact);
        eprintln!(
            "accurate LDLt, chain, {}: entrywise error {err:e}",
            label(&ord)
        );
        assert!(
            err <= 1e-10,
            "{}: entrywise relative error {err:e}",
            label(&ord)
        );
    }
    // For the record (`--nocapture`): the ordinary Cholesky of the assembled matrix.
    let y = solve_direct(&m.to_csc(), &b).unwrap();
    eprintln!(
        "faer Cholesky on the assembled chain: entrywise error {:e}",
        entrywise(&y, &exact)
    );
}

/// Corridor of `ny` rows between two Dirichlet walls (ψ = 0), 5-point Laplacian, fed at the left
/// by ψ = sin(θ(y+1)) with θ = π/(ny+1). Interior rows have zero excess, as in a real Dirichlet
/// problem. Exact solution: λ^(i+1) sin(θ(y+1)), λ + 1/λ = 2 + μ, μ = 2 − 2cos θ (the right end
/// gets the extra excess 1/λ − 1 − μ that makes the truncation exact).
fn corridor(nx: usize, ny: usize) -> (MMatrix, Vec<f64>, Vec<f64>, Vec<[f64; 2]>) {
    let theta = std::f64::consts::PI / (ny + 1) as f64;
    let mu = 4.0 * (theta / 2.0).sin().powi(2); // 2 − 2cos θ without cancellation
    let t = mu / 2.0 + (mu + mu * mu / 4.0).sqrt();
    let idx = |i: usize, y: usize| y * nx + i;
    let n = nx * ny;
    let (mut edges, mut excess, mut b, mut coords) =
        (vec![], vec![0.0; n], vec![0.0; n], vec![[0.0; 2]; n]);
    for y in 0..ny {
        for i in 0..nx {
            let k = idx(i, y);
            coords[k] = [i as f64, y as f64];
            if i + 1 < nx {
                edges.push((idx(i + 1, y), k, 1.0));
            }
            if y + 1 < ny {
                edges.push((idx(i, y + 1), k, 1.0));
            }
            if y == 0 || y + 1 == ny {
                excess[k] += 1.0; // edge to the wall
            }
        }
        excess[idx(0, y)] += 1.0; // edge to the feeding boundary
        b[idx(0, y)] = (theta * (y + 1) as f64).sin();
        excess[idx(nx - 1, y)] += mu / t; // = 1/λ − 1 − μ, the no-reflection condition
    }
    let m = MMatrix::try_new(offdiag(n, &edges), excess).unwrap();
    let ln = t.ln_1p();
    let exact = (0..n)
        .map(|k| (-((k % nx + 1) as f64) * ln).exp() * (theta * (k / nx + 1) as f64).sin())
        .collect();
    (m, b, exact, coords)
}

/// The multifrontal factor splits its tree into tasks by the thread count and updates a
/// front's columns in parallel; every number is computed by the same operations in the same
/// order however the work is split.
#[test]
fn the_factor_is_the_same_bit_for_bit_at_any_thread_count() {
    let (m, b, exact, coords) = corridor(200, 150);
    let solve_in = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let f = AccurateLdlt::factor(
                &m,
                Ordering::NestedDissection {
                    coords: coords.clone(),
                },
            )
            .unwrap();
            f.solve(&b).unwrap()
        })
    };
    let one = solve_in(1);
    assert!(
        entrywise(&one, &exact) <= 1e-10,
        "{:e}",
        entrywise(&one, &exact)
    );
    for threads in [2, 3, 4] {
        let x = solve_in(threads);
        assert!(
            x.iter().zip(&one).all(|(a, b)| a.to_bits() == b.to_bits()),
            "{threads} threads"
        );
    }
}

#[test]
fn corridor_2d_decaying_to_1e_minus_200_is_entrywise_accurate() {
    let (m, b, exact, coords) = corridor(1200, 7);
    let smallest = exact.iter().cloned().fold(1.0, f64::min);
    assert!(smallest < 1e-200 && smallest > 0.0, "{smallest:e}");
    for ord in [Ordering::Amd, Ordering::NestedDissection { coords }] {
        let x = AccurateLdlt::factor(&m, ord.clone())
            .unwrap()
            .solve(&b)
            .unwrap();
        let err = entrywise(&x, &exact);
        assert!(
            err <= 1e-10,
            "{}: entrywise relative error {err:e}",
            label(&ord)
        );
    }
    let y = solve_direct(&m.to_csc(), &b).unwrap();
    eprintln!(
        "faer Cholesky on the assembled corridor: entrywise error {:e}",
        entrywise(&y, &exact)
    );
}

#[test]
fn tiny_excess_lost_by_the_assembled_diagonal_is_kept() {
    // Excess 1e-20 next to unit conductances: 2 + 1e-20 == 2 in floating point, so the assembled
    // matrix has lost it; the accurate factorisation still sees it. With a single node the exact
    // answer is b / s.
    let m = MMatrix::try_new(offdiag(2, &[(1, 0, 1.0)]), vec![1e-20, 0.0]).unwrap();
    let x = AccurateLdlt::factor(&m, Ordering::Natural)
        .unwrap()
        .solve(&[1.0, 0.0])
        .unwrap();
    // Both unknowns equal 1e20 (the pair is a single node grounded by 1e-20).
    assert!(entrywise(&x, &[1e20, 1e20]) < 1e-14, "{x:?}");
    // The assembled matrix [1 -1; -1 1] is exactly singular: an ordinary Cholesky cannot do it.
    assert!(solve_direct(&m.to_csc(), &[1.0, 0.0]).is_err());
}

#[test]
fn general_m_matrices_match_dense_solves() {
    for seed in 1..6 {
        let n = 80;
        let mut rng = Rng(seed);
        let mut edges = vec![];
        for j in 0..n {
            for _ in 0..3 {
                let i = rng.below(n);
                if i != j {
                    edges.push((i, j, rng.next_f64()));
                }
            }
        }
        let excess: Vec<f64> = (0..n)
            .map(|_| {
                if rng.next_f64() < 0.3 {
                    rng.next_f64()
                } else {
                    0.0
                }
            })
            .collect();
        let mut excess = excess;
        excess[0] += 0.5; // at least one grounded node (the graph may still be disconnected)
        for e in excess.iter_mut() {
            *e += 1e-3;
        }
        let m = MMatrix::try_new(offdiag(n, &edges), excess).unwrap();
        let b: Vec<f64> = (0..n).map(|_| rng.next_f64()).collect();
        let reference = dense_solve(&m.to_csc(), &b);
        for ord in [Ordering::Amd, Ordering::Natural] {
            let x = AccurateLdlt::factor(&m, ord).unwrap().solve(&b).unwrap();
            assert!(entrywise(&x, &reference) < 1e-11, "seed {seed}");
        }
        let y = solve_direct(&m.to_csc(), &b).unwrap();
        assert!(max_rel_err(&y, &reference) < 1e-11);
    }
}

#[test]
fn refactor_reuses_the_analysis_and_checks_the_pattern() {
    let (m1, b, exact, coords) = corridor(300, 5);
    let mut f = AccurateLdlt::factor(&m1, Ordering::NestedDissection { coords }).unwrap();
    assert!(entrywise(&f.solve(&b).unwrap(), &exact) < 1e-10);
    // Same pattern, every conductance and excess doubled: the solution halves.
    let w2 = {
        let mut w = m1.offdiag().clone();
        for v in w.values_mut() {
            *v *= 2.0;
        }
        w
    };
    let m2 = MMatrix::try_new(w2, m1.excess().iter().map(|s| 2.0 * s).collect()).unwrap();
    f.refactor(&m2).unwrap();
    let half: Vec<f64> = exact.iter().map(|e| e / 2.0).collect();
    assert!(entrywise(&f.solve(&b).unwrap(), &half) < 1e-10);
    // A different pattern is refused and leaves the factor as it was.
    let (m3, ..) = corridor(300, 4);
    assert!(matches!(
        f.refactor(&m3),
        Err(SolverError::PatternMismatch { .. })
    ));
    assert!(entrywise(&f.solve(&b).unwrap(), &half) < 1e-10);
}

#[test]
fn an_analysis_of_the_assembled_pattern_factors_as_the_m_matrix_does() {
    // The analysis reads only a pattern, with the diagonal stored or not: made from the
    // assembled matrix (diagonal included) it gives the factor of the M-matrix bit for bit.
    let (m, b, exact, coords) = corridor(120, 40);
    let assembled = m.to_csc();
    let ordering = Ordering::NestedDissection { coords };
    let direct = AccurateLdlt::factor(&m, ordering.clone()).unwrap();
    let analysed = LdltAnalysis::of(&assembled, ordering.clone())
        .unwrap()
        .factor(&m)
        .unwrap();
    let (x, y) = (direct.solve(&b).unwrap(), analysed.solve(&b).unwrap());
    assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
    assert!(entrywise(&y, &exact) < 1e-10);
    // Another pattern, or another size, is refused by name.
    let (other, ..) = corridor(120, 39);
    let analysis = LdltAnalysis::of(&assembled, ordering).unwrap();
    assert!(matches!(
        analysis.clone().factor(&other),
        Err(SolverError::DimensionMismatch { .. })
    ));
    let mut w = m.offdiag().clone();
    let (n, mut col_ptr, mut rows, mut vals) = (w.n(), vec![0], vec![], vec![]);
    // The same size without the edge between unknowns 0 and 1.
    for j in 0..n {
        let (r, v) = w.column(j);
        for (&i, &x) in r.iter().zip(v) {
            if (i.min(j), i.max(j)) != (0, 1) {
                rows.push(i);
                vals.push(x);
            }
        }
        col_ptr.push(rows.len());
    }
    w = SymmetricCsc::try_new(n, col_ptr, rows, vals).unwrap();
    let cut = MMatrix::try_new(w, m.excess().to_vec()).unwrap();
    assert!(matches!(
        analysis.factor(&cut),
        Err(SolverError::PatternMismatch { column: 0 })
    ));
}

#[test]
fn ungrounded_component_is_singular() {
    // Components {0,1} (grounded) and {2,3} (no excess anywhere): singular, named in {2,3}.
    let m = MMatrix::try_new(
        offdiag(4, &[(1, 0, 1.0), (3, 2, 1.0)]),
        vec![1.0, 0.0, 0.0, 0.0],
    )
    .unwrap();
    for ord in [Ordering::Natural, Ordering::Amd] {
        match AccurateLdlt::factor(&m, ord) {
            Err(SolverError::Singular { column }) => assert!(column == 2 || column == 3),
            other => panic!("{other:?}"),
        }
    }
}

#[test]
fn invalid_m_matrices_are_rejected() {
    let w = offdiag(2, &[(1, 0, 1.0)]);
    assert!(matches!(
        MMatrix::try_new(w.clone(), vec![1.0]),
        Err(SolverError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        MMatrix::try_new(w.clone(), vec![1.0, -1.0]),
        Err(SolverError::Negative { index: 1, .. })
    ));
    assert!(matches!(
        MMatrix::try_new(w, vec![1.0, f64::NAN]),
        Err(SolverError::NonFinite { index: 1, .. })
    ));
    let neg = offdiag(2, &[(1, 0, -1.0)]);
    assert!(matches!(
        MMatrix::try_new(neg, vec![1.0, 1.0]),
        Err(SolverError::Negative { .. })
    ));
    let diag = SymmetricCsc::try_new(1, vec![0, 1], vec![0], vec![1.0]).unwrap();
    assert_eq!(
        MMatrix::try_new(diag, vec![1.0]).unwrap_err(),
        SolverError::InvalidStructure {
            column: 0,
            issue: StructureIssue::DiagonalStored
        }
    );
    let asym = SymmetricCsc::try_new(2, vec![0, 1, 2], vec![1, 0], vec![1.0, 2.0]).unwrap();
    assert!(matches!(
        MMatrix::try_new(asym, vec![1.0, 1.0]),
        Err(SolverError::Asymmetric { .. })
    ));
    let m = MMatrix::try_new(offdiag(2, &[(1, 0, 1.0)]), vec![1.0, 1.0]).unwrap();
    let f = AccurateLdlt::factor(&m, Ordering::Amd).unwrap();
    assert!(matches!(
        f.solve(&[1.0]),
        Err(SolverError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        f.solve(&[1.0, f64::INFINITY]),
        Err(SolverError::NonFinite { index: 1, .. })
    ));
}
