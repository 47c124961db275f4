//! The extended-exponent LDLᵀ (issue #19): a Dirichlet corridor of 1000 widths, whose
//! solution falls to 1e-1300, solved to an entrywise relative error ≤ 1e-10 against the exact
//! solution of the discrete system (where the ordinary accurate solve underflows to 0); and
//! bit-for-bit agreement with the ordinary accurate solve where nothing underflows.

mod common;

use common::*;
use harmonic_solver::{AccurateLdlt, MMatrix, Ordering, Wide, WideLdlt};

/// A corridor of `ny` rows between two Dirichlet walls (ψ = 0), 5-point Laplacian, fed at the
/// left by ψ = sin(θ(y+1)), θ = π/(ny+1); interior rows have zero excess, as in a real
/// Dirichlet problem. The exact discrete solution is λ^(i+1) sin(θ(y+1)) with
/// λ + 1/λ = 2 + μ, μ = 2 − 2cos θ (the right end gets the excess 1/λ − 1 − μ that makes the
/// truncation exact). Returned as log₂ of the exact solution, for any length.
fn corridor(nx: usize, ny: usize) -> (MMatrix, Vec<f64>, Vec<f64>, Vec<[f64; 2]>) {
    let theta = std::f64::consts::PI / (ny + 1) as f64;
    let mu = 4.0 * (theta / 2.0).sin().powi(2);
    let t = mu / 2.0 + (mu + mu * mu / 4.0).sqrt();
    // Numbered across the corridor first, so the natural order has bandwidth `ny`.
    let idx = |i: usize, y: usize| i * ny + y;
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
                excess[k] += 1.0;
            }
        }
        excess[idx(0, y)] += 1.0;
        b[idx(0, y)] = (theta * (y + 1) as f64).sin();
        excess[idx(nx - 1, y)] += mu / t;
    }
    let m = MMatrix::try_new(from_triplets(n, &edges), excess).unwrap();
    let log2_lambda = -t.ln_1p() / std::f64::consts::LN_2;
    let log2_exact = (0..n)
        .map(|k| (k / ny + 1) as f64 * log2_lambda + (theta * (k % ny + 1) as f64).sin().log2())
        .collect();
    (m, b, log2_exact, coords)
}

/// Largest entrywise relative error of `x` against 2^`log2_exact` over the entries where the
/// exact value is below `below`, and how many there are.
fn entrywise_below(x: &[Wide], log2_exact: &[f64], below: f64) -> (f64, usize) {
    let limit = below.log2();
    let mut worst = 0.0f64;
    let mut count = 0;
    for (xi, &le) in x.iter().zip(log2_exact) {
        if le < limit {
            count += 1;
            // x / exact − 1 = 2^(log2 x − log2 exact) − 1, with log2 x from the mantissa and
            // exponent (no rounding of the tiny numbers themselves).
            let ratio = Wide::exp2(-le) * *xi;
            worst = worst.max((ratio.to_f64() - 1.0).abs());
        }
    }
    (worst, count)
}

#[test]
fn corridor_of_1000_widths_is_entrywise_accurate_below_1e_minus_300() {
    // Four unknown rows between the walls: the corridor is 5 lattice steps wide, so 5000
    // columns are 1000 widths; λ ≈ 0.544 per column, ψ ≈ 1e-1320 at the far end.
    let (nx, ny) = (5000, 4);
    let (m, b, log2_exact, coords) = corridor(nx, ny);
    let n = nx * ny;
    let smallest = log2_exact.iter().copied().fold(0.0, f64::min) * std::f64::consts::LOG10_2;
    assert!(smallest < -1300.0, "log10 of the smallest ψ: {smallest}");
    for (name, ord) in [
        ("natural", Ordering::Natural),
        ("amd", Ordering::Amd),
        ("nested dissection", Ordering::NestedDissection { coords }),
    ] {
        let x = WideLdlt::factor(&m, ord.clone())
            .unwrap()
            .solve(&b)
            .unwrap();
        let (err, count) = entrywise_below(&x, &log2_exact, 1e-300);
        eprintln!("wide LDLt, {name}: {count} entries below 1e-300, entrywise error {err:e}");
        assert!(count > 15_000, "{name}: {count}");
        assert!(err <= 1e-10, "{name}: entrywise relative error {err:e}");
        // Everywhere else too.
        let (all, _) = entrywise_below(&x, &log2_exact, f64::INFINITY);
        assert!(all <= 1e-10, "{name}: entrywise relative error {all:e}");
        // The ordinary accurate solve has nothing there: it underflows.
        let plain = AccurateLdlt::factor(&m, ord).unwrap().solve(&b).unwrap();
        assert_eq!(plain[n - 1], 0.0, "{name}");
    }
}

#[test]
fn agrees_bit_for_bit_with_the_ordinary_solve_in_range() {
    // 150 columns: ψ ≥ 1e-40, nothing underflows, so every operation rounds as in f64.
    let (m, b, _, coords) = corridor(150, 6);
    let ord = Ordering::NestedDissection { coords };
    let plain_factor = AccurateLdlt::factor(&m, ord.clone()).unwrap();
    let plain = plain_factor.solve(&b).unwrap();
    let wide = WideLdlt::factor(&m, ord).unwrap();
    assert_eq!(wide.permutation(), plain_factor.permutation());
    let like = WideLdlt::factor_like(&plain_factor, &m).unwrap();
    for x in [wide.solve(&b).unwrap(), like.solve(&b).unwrap()] {
        let floats: Vec<f64> = x.iter().map(|w| w.to_f64()).collect();
        assert_eq!(floats, plain);
    }
}

#[test]
fn refuses_singular_and_foreign_matrices() {
    // Two unknowns coupled to each other only: no excess anywhere, so singular.
    let w = from_triplets(2, &[(1, 0, 1.0)]);
    let m = MMatrix::try_new(w, vec![0.0, 0.0]).unwrap();
    assert!(matches!(
        WideLdlt::factor(&m, Ordering::Amd),
        Err(harmonic_solver::SolverError::Singular { .. })
    ));
    // A factor refuses a matrix of another pattern and a right-hand side of the wrong size.
    let (a, b, _, _) = corridor(10, 2);
    let (other, _, _, _) = corridor(10, 3);
    let mut f = WideLdlt::factor(&a, Ordering::Amd).unwrap();
    assert!(f.refactor(&other).is_err());
    assert!(f.solve(&b[1..]).is_err());
    let mut nan = b.clone();
    nan[0] = f64::NAN;
    assert!(f.solve(&nan).is_err());
    // ... and is unchanged by the refusal.
    f.refactor(&a).unwrap();
    assert_eq!(f.solve(&b).unwrap().len(), 20);
}
