//! Prints a table of the grid baselines on the reference scene for grid sizes given on the
//! command line (default 64 128 256 512): SOR sweeps and time, residual, Connolly's flat-cell
//! count for ψ and for φ, and the paths from (1, 9) by the shared tracer and by the wavefront.
//! `tol=X` sets the residual tolerance (default 1e-13), `rel=X` a relative residual
//! tolerance instead.
//!
//! `cargo run --release -p harmonic-baselines --example grid_table -- 64 128 256 tol=1e-13`

use std::time::Instant;

use harmonic_baselines::{
    Cell, Connectivity, GridHarmonic, Raster, Relaxation, SorOptions, StopRule, Unknown, Wavefront,
};
use harmonic_fixtures::{ScenePolygons, reference_polygons};
use harmonic_mesh::Point;
use harmonic_trajectory::{SmoothOptions, trace_smooth};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut stop = StopRule::Residual(1e-13);
    let mut sizes: Vec<usize> = Vec::new();
    for arg in std::env::args().skip(1) {
        if let Some(t) = arg.strip_prefix("tol=") {
            stop = StopRule::Residual(t.parse()?);
        } else if let Some(t) = arg.strip_prefix("rel=") {
            stop = StopRule::RelativeResidual(t.parse()?);
        } else {
            sizes.push(arg.parse()?);
        }
    }
    let sizes = if sizes.is_empty() {
        vec![64, 128, 256, 512]
    } else {
        sizes
    };
    let ScenePolygons {
        workspace: ws,
        obstacles,
        goals,
    } = reference_polygons();
    let start = Point::new(1.0, 9.0);
    println!(
        "| n | free cells | method | sweeps | solve ms | residual | rel. residual | min ψ | flat ψ | flat φ | traced | length | wavefront8 length | brushfire ms |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for n in sizes {
        let raster = Raster::from_polygons(&ws, &obstacles, &goals, n)?;
        let mut methods = vec![("sor", Relaxation::RedBlackSor { omega: None })];
        if n <= 128 {
            methods.push(("gauss-seidel", Relaxation::GaussSeidel));
        }
        for (name, relaxation) in methods {
            let opts = SorOptions {
                relaxation,
                stop,
                max_iterations: 1_000_000,
                ..SorOptions::default()
            };
            let psi = GridHarmonic::solve(raster.clone(), &opts)?;
            let phi = GridHarmonic::solve(
                raster.clone(),
                &SorOptions {
                    unknown: Unknown::Phi,
                    ..opts
                },
            )?;
            let path = trace_smooth(&psi, start, &SmoothOptions::for_scale(10.0))?;
            let clock = Instant::now();
            let wave = Wavefront::new(raster.clone(), Connectivity::Eight);
            let wave_path = wave.plan(start);
            let r = psi.report();
            let min_psi = raster
                .cells()
                .iter()
                .zip(psi.values())
                .filter(|(c, _)| **c == Cell::Free)
                .fold(f64::INFINITY, |m, (_, v)| m.min(*v));
            println!(
                "| {n} | {} | {name} | {} | {:.1} | {:.1e} | {:.1e} | {:.1e} | {} | {} | {} | {:.3} | {:.3} | {:.2} |",
                raster.counts().0,
                r.iterations,
                r.time.as_secs_f64() * 1e3,
                r.residual,
                r.relative_residual,
                min_psi,
                psi.flat_cells(),
                phi.flat_cells(),
                path.status,
                path.length,
                wave_path.length,
                clock.elapsed().as_secs_f64() * 1e3,
            );
        }
    }
    Ok(())
}
