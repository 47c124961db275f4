//! Kim & Khosla (1992), §5.1: the bar-shaped mobile robot (eqs. 43–49) around their concave
//! obstacle-1 in setting (50), on their published panel field and on our FEM potential —
//! the same controller on both. Settings and choices: `harmonic_bench::kim_khosla_control`.
//!
//! ```text
//! cargo run --release --example bar_robot                          # a summary per field
//! cargo run --release --example bar_robot -- --json                # {"runs": [...], ...}
//! cargo run --release --example bar_robot -- --svg docs/bar_robot  # docs/bar_robot_{panel,fem}.svg
//! cargo run --release --example bar_robot -- --side right          # turn right at stagnation points
//! ```

use clap::{Parser, ValueEnum};
use harmonic_bench::kim_khosla_control::{bar_runs, bar_svg};
use harmonic_control::{FemFlow, Side};

#[derive(Clone, Copy, ValueEnum)]
enum SideArg {
    Left,
    Right,
}

/// The bar robot of Kim & Khosla's §5.1 on the panel and FEM fields.
#[derive(Parser)]
struct Args {
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
    /// Write PREFIX_panel.svg and PREFIX_fem.svg.
    #[arg(long, value_name = "PREFIX")]
    svg: Option<String>,
    /// Which way to turn at a stagnation point.
    #[arg(long, value_enum, default_value = "left")]
    side: SideArg,
}

fn main() -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    let args = Args::parse();
    let side = match args.side {
        SideArg::Left => Side::Left,
        SideArg::Right => Side::Right,
    };
    let (out, panel, planner) = bar_runs(side)?;
    if let Some(prefix) = &args.svg {
        let fem = FemFlow::new(planner.potential());
        std::fs::write(
            format!("{prefix}_panel.svg"),
            bar_svg(&out.runs[0], &panel, &out.obstacle),
        )?;
        std::fs::write(
            format!("{prefix}_fem.svg"),
            bar_svg(&out.runs[1], &fem, &out.obstacle),
        )?;
    }
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(());
    }
    println!(
        "bar of {} m, d_max {} m, Δη_max {} rad, δ {} m; FEM mesh {} triangles",
        out.bar_length, out.d_max, out.d_eta_max, out.runs[0].delta, out.fem_triangles
    );
    let rows =
        out.runs
            .iter()
            .map(|r| (r.field.to_string(), r))
            .chain(out.stagnation_demo.iter().map(|d| {
                let name = match d.side {
                    None => "panel from the dividing streamline, no guard".to_string(),
                    Some(s) => format!("panel from the dividing streamline, turning {s:?}"),
                };
                (name, &d.run)
            }));
    for (name, r) in rows {
        let approach: Vec<String> = r
            .stagnation_points
            .iter()
            .zip(&r.closest_approach)
            .map(|(s, d)| format!("({:.2}, {:.2}) passed at {:.2} m", s[0], s[1], d))
            .collect();
        println!(
            "{name}: {:?}, {} periods ({} in the obstacle operation), min distance {:.3} m, {:.1} µs/period, {} turn(s); stagnation points {}",
            r.status,
            r.steps,
            r.obstacle_periods,
            r.min_distance,
            r.microseconds_per_period,
            r.turns.len(),
            approach.join(", ")
        );
    }
    Ok(())
}
