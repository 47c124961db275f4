//! Kim & Khosla (1992), §5.2: the 3-dof redundant manipulator (eqs. 52–58) reaching through
//! the aperture of their obstacle-2 in setting (51), on their published panel field and on
//! our FEM potential — the same controller on both. Settings and choices:
//! `harmonic_bench::kim_khosla_control`.
//!
//! ```text
//! cargo run --release --example manipulator                            # a summary per field
//! cargo run --release --example manipulator -- --json                  # {"runs": [...], ...}
//! cargo run --release --example manipulator -- --svg docs/manipulator  # docs/manipulator_{panel,fem}.svg
//! cargo run --release --example manipulator -- --links 4.5,4,3 --null none
//! ```

use clap::{Parser, ValueEnum};
use harmonic_bench::kim_khosla_control::{ARM_LINKS, arm_runs, arm_svg};
use harmonic_control::{FemFlow, NullMotion};

#[derive(Clone, Copy, ValueEnum)]
enum NullArg {
    /// The inner links' end points follow the flow (the paper's choice).
    Flow,
    /// No null motion in the potential operation.
    None,
}

/// The arm of Kim & Khosla's §5.2 on the panel and FEM fields.
#[derive(Parser)]
struct Args {
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
    /// Write PREFIX_panel.svg and PREFIX_fem.svg.
    #[arg(long, value_name = "PREFIX")]
    svg: Option<String>,
    /// Link lengths (m), comma-separated: three links.
    #[arg(
        long,
        value_delimiter = ',',
        num_args = 3,
        allow_negative_numbers = true
    )]
    links: Option<Vec<f64>>,
    /// The potential operation's null motion.
    #[arg(long, value_enum, default_value = "flow")]
    null: NullArg,
}

fn main() -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    let args = Args::parse();
    let links = args.links.unwrap_or(ARM_LINKS.to_vec());
    let null = match args.null {
        NullArg::Flow => NullMotion::FollowFlow,
        NullArg::None => NullMotion::None,
    };
    let (out, panel, planner) = arm_runs(&links, null)?;
    if let Some(prefix) = &args.svg {
        let fem = FemFlow::new(planner.potential());
        std::fs::write(
            format!("{prefix}_panel.svg"),
            arm_svg(&out.runs[0], &panel, &out),
        )?;
        std::fs::write(
            format!("{prefix}_fem.svg"),
            arm_svg(&out.runs[1], &fem, &out),
        )?;
    }
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
        return Ok(());
    }
    println!(
        "links {:?} m, start joints {:.4?} rad, d_e {} m, Δθ_max {} rad, δ {} m, null motion {:?}; FEM mesh {} triangles",
        out.links,
        out.start_joints,
        out.d_e,
        out.d_theta_max,
        out.runs[0].delta,
        out.null_motion,
        out.fem_triangles
    );
    for r in &out.runs {
        let last = r.end_effector.last().copied().unwrap_or([f64::NAN; 2]);
        println!(
            "{}: {:?}, {} periods ({} in the obstacle operation), min distance {:.3} m at period {}, end effector at ({:.2}, {:.2}), {:.1} µs/period",
            r.field,
            r.status,
            r.steps,
            r.obstacle_periods,
            r.min_distance,
            r.min_distance_step,
            last[0],
            last[1],
            r.microseconds_per_period
        );
    }
    Ok(())
}
