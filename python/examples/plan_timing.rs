//! The Rust side of the call-overhead comparison: `Planner::plan` from (1, 9) on
//! meshes/reference.json, timed in a plain loop (compare with `examples/overhead.py`).
//!
//! ```text
//! cargo run --release --manifest-path python/Cargo.toml --features extension-module \
//!     --example plan_timing
//! ```

use std::time::Instant;

use harmonic_planner::{Planner, Point, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/../meshes/reference.json");
    let planner = Planner::new(&Scene::from_file(file)?)?;
    let best_of = |what: &str, n: usize, f: &dyn Fn()| {
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let t = Instant::now();
            for _ in 0..n {
                f();
            }
            best = best.min(t.elapsed().as_secs_f64() / n as f64);
        }
        println!("{what}: {:.2} µs per call (best of 5 × {n})", best * 1e6);
    };
    best_of("Planner::plan([1, 9])", 200, &|| {
        std::hint::black_box(planner.plan(std::hint::black_box([1.0, 9.0])));
    });
    best_of("phi_at(8, 3)", 100_000, &|| {
        std::hint::black_box(
            planner
                .potential()
                .phi_at(std::hint::black_box(Point::new(8.0, 3.0)), None)
                .ok(),
        );
    });
    Ok(())
}
