//! Compares AMD and geometric nested dissection on triangulated-grid Laplacians: factor size and
//! single-threaded symbolic / numeric / solve times (best of `REPS` runs, default 3, since the
//! machine may be shared), plus IC(0)-PCG for reference (skipped when `NOPCG` is set).
//!
//! `cargo run -p harmonic-solver --release --example orderings -- 707` (grid side lengths as
//! arguments; default 39 122 387 707, i.e. about 1.5k, 15k, 150k and 500k unknowns).

use std::time::Instant;

use harmonic_solver::{Ordering, PcgOptions, SymbolicCholesky, gallery, pcg};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sides: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse())
        .collect::<Result<_, _>>()?;
    let sides = if sides.is_empty() {
        vec![39, 122, 387, 707]
    } else {
        sides
    };
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    println!(
        "{:>8} {:>9} {:>5} {:>11} {:>9} {:>9} {:>9} {:>9}",
        "n", "nnz(A)", "order", "len(L)", "symb s", "num s", "solve s", "total s"
    );
    for side in sides {
        let (a, coords) = gallery::triangulated_grid_laplacian(side, side);
        let b: Vec<f64> = (0..a.n()).map(|i| 1.0 + (i % 7) as f64).collect();
        for (name, ord) in [
            ("amd", Ordering::Amd),
            (
                "nd",
                Ordering::NestedDissection {
                    coords: coords.clone(),
                },
            ),
        ] {
            let mut best = [f64::INFINITY; 3];
            let mut len = 0;
            for _ in 0..reps.max(1) {
                let t0 = Instant::now();
                let s = SymbolicCholesky::analyze(&a, ord.clone())?;
                let t1 = Instant::now();
                let c = s.factor(&a)?;
                let t2 = Instant::now();
                std::hint::black_box(c.solve(&b)?);
                let t3 = Instant::now();
                len = s.factor_len();
                for (k, d) in [t1 - t0, t2 - t1, t3 - t2].iter().enumerate() {
                    best[k] = best[k].min(d.as_secs_f64());
                }
            }
            println!(
                "{:>8} {:>9} {:>5} {:>11} {:>9.4} {:>9.4} {:>9.4} {:>9.4}",
                a.n(),
                a.nnz(),
                name,
                len,
                best[0],
                best[1],
                best[2],
                best.iter().sum::<f64>()
            );
        }
        if std::env::var_os("NOPCG").is_some() {
            continue;
        }
        let mut x = vec![0.0; a.n()];
        let t = Instant::now();
        let report = pcg(&a, &b, &mut x, &PcgOptions::default())?;
        println!(
            "{:>8} {:>9} pcg-ic0: {} iterations to {:.1e} in {:.4} s",
            a.n(),
            a.nnz(),
            report.iterations,
            report.rel_residual,
            t.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
