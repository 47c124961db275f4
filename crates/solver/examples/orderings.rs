//! Compares AMD and geometric nested dissection on triangulated-grid Laplacians: factor size and
//! single-threaded symbolic / numeric / solve times (best of `REPS` runs, default 3, since the
//! machine may be shared; `cpu s` is the process CPU time of the best total, from /proc, which a
//! loaded machine inflates less than wall time), the accurate M-matrix LDLᵀ with the nested
//! dissection ordering (skipped, with the PCG, when `NOGTH` is set), and IC(0)-PCG (skipped when
//! `NOPCG` is set). `SHUFFLE` renumbers the unknowns randomly first, as an unstructured mesh would.
//!
//! `cargo run -p harmonic-solver --release --example orderings -- 707` (grid side lengths as
//! arguments; default 39 122 387 707, i.e. about 1.5k, 15k, 150k and 500k unknowns).

use std::time::Instant;

use harmonic_solver::{
    AccurateLdlt, MMatrix, Ordering, PcgOptions, SymbolicCholesky, SymmetricCsc, gallery, pcg,
};

/// Renumbers the unknowns randomly (deterministic), as an unstructured mesh generator would.
fn shuffled(a: &SymmetricCsc, coords: &[[f64; 2]]) -> (SymmetricCsc, Vec<[f64; 2]>) {
    let n = a.n();
    let mut perm: Vec<usize> = (0..n).collect();
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    for i in (1..n).rev() {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        perm.swap(i, (state % (i as u64 + 1)) as usize);
    }
    let mut inv = vec![0; n];
    for (new, &old) in perm.iter().enumerate() {
        inv[old] = new;
    }
    let (mut col_ptr, mut row_idx, mut values) = (vec![0], vec![], vec![]);
    for &old in &perm {
        let (rows, vals) = a.column(old);
        let mut col: Vec<(usize, f64)> = rows
            .iter()
            .map(|&r| inv[r])
            .zip(vals.iter().copied())
            .collect();
        col.sort_unstable_by_key(|e| e.0);
        for (r, v) in col {
            row_idx.push(r);
            values.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    let coords = perm.iter().map(|&old| coords[old]).collect();
    (
        SymmetricCsc::try_new(n, col_ptr, row_idx, values)
            .expect("a permutation keeps the structure valid"),
        coords,
    )
}

/// Process CPU time (user + system) in seconds, from /proc/self/stat; `None` off Linux.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0) // USER_HZ is 100 on Linux
}

/// The grid matrix as an M-matrix: off-diagonal magnitudes and row excesses (the excess of a
/// Dirichlet-eliminated grid is the weight of the eliminated boundary edges).
fn as_mmatrix(a: &SymmetricCsc) -> Result<MMatrix, harmonic_solver::SolverError> {
    let n = a.n();
    let (mut col_ptr, mut row_idx, mut values, mut excess) = (vec![0], vec![], vec![], vec![]);
    for j in 0..n {
        let (rows, vals) = a.column(j);
        let mut s = 0.0;
        for (&i, &v) in rows.iter().zip(vals) {
            s += v;
            if i != j {
                row_idx.push(i);
                values.push(-v);
            }
        }
        excess.push(s.max(0.0));
        col_ptr.push(row_idx.len());
    }
    MMatrix::try_new(SymmetricCsc::try_new(n, col_ptr, row_idx, values)?, excess)
}

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
        "{:>8} {:>9} {:>5} {:>11} {:>9} {:>9} {:>9} {:>9} {:>7}",
        "n", "nnz(A)", "order", "len(L)", "symb s", "num s", "solve s", "total s", "cpu s"
    );
    for side in sides {
        let (a, coords) = gallery::triangulated_grid_laplacian(side, side);
        let (a, coords) = if std::env::var_os("SHUFFLE").is_some() {
            shuffled(&a, &coords)
        } else {
            (a, coords)
        };
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
            let (mut len, mut best_total, mut cpu) = (0, f64::INFINITY, f64::NAN);
            for _ in 0..reps.max(1) {
                let c0 = cpu_seconds();
                let t0 = Instant::now();
                let s = SymbolicCholesky::analyze(&a, ord.clone())?;
                let t1 = Instant::now();
                let c = s.factor(&a)?;
                let t2 = Instant::now();
                std::hint::black_box(c.solve(&b)?);
                let t3 = Instant::now();
                if (t3 - t0).as_secs_f64() < best_total {
                    best_total = (t3 - t0).as_secs_f64();
                    cpu = match (c0, cpu_seconds()) {
                        (Some(a), Some(b)) => b - a,
                        _ => f64::NAN,
                    };
                }
                len = s.factor_len();
                for (k, d) in [t1 - t0, t2 - t1, t3 - t2].iter().enumerate() {
                    best[k] = best[k].min(d.as_secs_f64());
                }
            }
            println!(
                "{:>8} {:>9} {:>5} {:>11} {:>9.4} {:>9.4} {:>9.4} {:>9.4} {:>7.2}",
                a.n(),
                a.nnz(),
                name,
                len,
                best[0],
                best[1],
                best[2],
                best.iter().sum::<f64>(),
                cpu
            );
        }
        if std::env::var_os("NOGTH").is_some() {
            continue;
        }
        let m = as_mmatrix(&a)?;
        let mut best = [f64::INFINITY; 2];
        let mut nnz_l = 0;
        for _ in 0..reps.max(1) {
            let t0 = Instant::now();
            let f = AccurateLdlt::factor(
                &m,
                Ordering::NestedDissection {
                    coords: coords.clone(),
                },
            )?;
            let t1 = Instant::now();
            std::hint::black_box(f.solve(&b)?);
            let t2 = Instant::now();
            nnz_l = f.factor_nnz();
            best[0] = best[0].min((t1 - t0).as_secs_f64());
            best[1] = best[1].min((t2 - t1).as_secs_f64());
        }
        println!(
            "{:>8} {:>9} {:>5} {:>11} {:>9} {:>9.4} {:>9.4} {:>9.4}   (accurate LDLt: order+factor, solve)",
            a.n(),
            a.nnz(),
            "gth",
            nnz_l,
            "",
            best[0],
            best[1],
            best[0] + best[1]
        );
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
