//! Kim & Khosla (1992), §5.1: their setting (50) — U = 1, λ_g = 30, V_i = 0.5, start
//! (1.2, 8.5), goal (8, 2) — on the published (unbounded) panel method, our panel strengths
//! beside their Table 1, λ_o and eq. 39, the stagnation points of eq. 41, the remedy and the
//! point robot's path; then §5.2's setting (51), our 24 strengths beside their Table 2. The
//! obstacles (their Figures 8 and 10) are reconstructions: see `harmonic_bench::kim_khosla`
//! and `harmonic_bench::kim_khosla_arm`.
//!
//! ```text
//! cargo run --release -p harmonic-bench --example kim_khosla            # Markdown
//! cargo run --release -p harmonic-bench --example kim_khosla -- --json  # {"table1": …, "table2": …}
//! ```

use harmonic_bench::kim_khosla::kim_khosla_table1;
use harmonic_bench::kim_khosla_arm::kim_khosla_table2;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let json = std::env::args().any(|a| a == "--json");
    let t = kim_khosla_table1()?;
    let t2 = kim_khosla_table2()?;
    if json {
        println!("{}", serde_json::json!({"table1": t, "table2": t2}));
        return Ok(());
    }
    println!(
        "Panel method variant: **{}** (unbounded plane, no wall panels). Obstacle-1 (their Figure 8, \
         not in the text) reconstructed as a 4 m square without the 2 m quadrant toward the start, \
         inner corner fitted at ({:.3}, {:.3}) (RMS misfit from Table 1 {:.1e}).\n",
        t.variant, t.inner_corner[0], t.inner_corner[1], t.rms_misfit
    );
    println!("| panel | centre | paper λ | ours | difference |");
    println!("|---:|---|---:|---:|---:|");
    for r in &t.rows {
        println!(
            "| {} | ({:.1}, {:.1}) | {:.3} | {:.3} | {:+.3} |",
            r.panel,
            r.centre[0],
            r.centre[1],
            r.paper,
            r.ours,
            r.ours - r.paper
        );
    }
    println!(
        "\n| quantity | paper | ours |\n|---|---|---|\n| λ_o (eq. 40) | {:.3} | {:.3} |\n| eq. 39, −λ_g < λ_o < 0 | satisfied | {:?} |",
        t.paper_lambda_o, t.lambda_o, t.lambda_o_check
    );
    let near: Vec<String> = t
        .stagnation_points
        .iter()
        .map(|s| {
            format!(
                "({:.2}, {:.2}) [{}]",
                s.at.x,
                s.at.y,
                s.obstacle
                    .map_or("goal sink".to_string(), |o| format!("obstacle {o}"))
            )
        })
        .collect();
    println!(
        "| stagnation points (eq. 41) | one, around ({}, {}) | {} |",
        t.paper_stagnation_point[0],
        t.paper_stagnation_point[1],
        near.join(", ")
    );
    let rounds: Vec<String> = t
        .remedy_rounds
        .iter()
        .map(|r| {
            format!(
                "V = {}: {} point(s), λ_o {:.2} ({:?})",
                r.normal_velocities[0],
                r.stagnation_counts[0],
                r.strengths[0].lambda_o,
                r.strengths[0].check
            )
        })
        .collect();
    println!(
        "| remedy (§4.3): raise V_i while an obstacle has more than one | not needed | {}; outcome {:?}, kept V = {} |",
        rounds.join("; "),
        t.remedy_outcome,
        t.remedy_normal_velocity
    );
    println!(
        "| point robot on the remedy's field | — | {}, length {:.2} m |",
        t.remedy_path_status, t.remedy_path_length
    );
    println!(
        "| point robot from (1.2, 8.5) | reaches the goal (bar robot, Fig. 9) | {}, length {:.2} m (straight {:.2} m), clearance {:.3} m |",
        t.path_status, t.path_length, t.straight_distance, t.path_clearance
    );
    let f = t2.fit;
    println!(
        "\nSetting (51), obstacle-2 (their Figure 10, not in the text) reconstructed as two \
         {:.3} m × 5 m rectangles with lower-left corners ({:.3}, {:.3}) and ({:.3}, {:.3}) \
         (fitted; RMS misfit from Table 2 {:.1e}).\n",
        f.width, f.lower[0], f.lower[1], f.upper[0], f.upper[1], t2.rms_misfit
    );
    println!("| panel | centre | paper λ | ours | difference |");
    println!("|---:|---|---:|---:|---:|");
    for r in &t2.rows {
        println!(
            "| {} | ({:.2}, {:.1}) | {:.3} | {:.3} | {:+.3} |",
            r.panel,
            r.centre[0],
            r.centre[1],
            r.paper,
            r.ours,
            r.ours - r.paper
        );
    }
    println!(
        "\n| quantity | paper | ours |\n|---|---|---|\n| λ_o lower, upper | {:.3}, {:.3} | {:.3}, {:.3} |\n| eq. 39 | satisfied | {:?} |",
        t2.paper_lambda_o[0],
        t2.paper_lambda_o[1],
        t2.lambda_o[0],
        t2.lambda_o[1],
        t2.lambda_o_check
    );
    Ok(())
}
