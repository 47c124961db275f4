//! The shape of Garrido et al. (2010), Table 1, on a coarse mesh: clearance rises from the
//! Neumann row through Robin K = 1, 2, 3, 10 toward Dirichlet, and K = 100, 1000 come within
//! 5 % of it; every path arrives.

use harmonic_bench::tables::{LiteralResult, PAPER_ROWS, bc_table, bc_table_literal};
use harmonic_planner::Scene;

#[test]
fn boundary_condition_table_has_the_papers_shape() {
    let mut scene = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/garrido_fig1.json"
    ))
    .expect("bundled scene");
    scene.mesh.max_area = Some(0.001);
    let rows = bc_table(&scene, &[[0.5, 0.8], [0.2, 0.8]], &PAPER_ROWS).expect("table runs");
    assert_eq!(rows.len(), 8);
    for r in &rows {
        assert!(
            r.reached.iter().all(|&x| x),
            "{:?} did not reach the goal",
            r.row
        );
    }
    for start in 0..2 {
        let d: Vec<f64> = rows.iter().map(|r| r.d[start]).collect();
        // Neumann < K=1 < K=2 < K=3 < K=10 < Dirichlet = 100.
        for w in d[..6].windows(2) {
            assert!(w[0] < w[1], "start {start}: d not rising: {d:?}");
        }
        assert!((d[5] - 100.0).abs() < 1e-9, "{d:?}");
        assert!(
            (d[6] - 100.0).abs() < 5.0 && (d[7] - 100.0).abs() < 5.0,
            "{d:?}"
        );
        assert!(
            (d[7] - 100.0).abs() <= (d[6] - 100.0).abs() + 1e-9,
            "K = 1000 is nearer Dirichlet: {d:?}"
        );
    }
}

/// The literal reading of the printed triples is linear in K with the goal at φ = 0: every
/// row with a = b = 1 and K > 0 gives the same paths (the same d), and the rows with K = 0
/// give φ ≡ 0 and no path — which is why the documented reading is what the table runs.
#[test]
fn the_literal_reading_collapses_to_one_path_and_two_empty_rows() {
    let mut scene = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/garrido_fig1.json"
    ))
    .expect("bundled scene");
    scene.mesh.max_area = Some(0.001);
    let starts = [[0.5, 0.8], [0.2, 0.8]];
    let reference = [1.0, 1.0];
    let rows = bc_table_literal(&scene, &starts, &PAPER_ROWS, &reference);
    let positive: Vec<&LiteralResult> = rows.iter().filter(|r| r.row.k > 0.0).collect();
    assert_eq!(positive.len(), 6);
    for r in &positive {
        assert!(r.no_path.is_none(), "{:?}: {:?}", r.row, r.no_path);
        for s in 0..2 {
            let d = r.d[s].expect("a path");
            let first = positive[0].d[s].expect("a path");
            assert!(
                (d - first).abs() <= 1e-9 * first,
                "{:?}: {d} vs {first}",
                r.row
            );
        }
    }
    for r in rows.iter().filter(|r| r.row.k == 0.0) {
        assert!(r.d.iter().all(Option::is_none), "{:?} has a path", r.row);
        assert!(r.no_path.is_some());
    }
}
