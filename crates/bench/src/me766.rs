//! The ME766 term paper (*harmonic path planning*): the Dirichlet/Neumann blend
//! `k·φ_D + (1 − k)·φ_N` swept over k, and its parabolic relaxation's iteration counts on
//! 100 × 100 reconstructions of its two workcells, beside Gauss–Seidel and SOR.
//!
//! **The workcells are reconstructions.** The paper's figures are not in the text; it gives
//! the grid (100 × 100), the sink and boundary values (−10⁸ and 1; −0.5 with Neumann walls),
//! the accuracies and iteration counts. Problem 1 below is a square cell with three
//! rectangular obstacles between the start corner and the goal, Problem 2 one with a
//! partition and two blocks.

use harmonic_baselines::{
    GridHarmonic, Parabolic, ParabolicOptions, ParabolicWalls, Raster, Relaxation, SorOptions,
    StopRule, Unknown,
};
use harmonic_mesh::Point;
use harmonic_planner::scene::{BlendSpec, Scene};
use harmonic_planner::{PlanError, Planner};
use serde::Serialize;

use crate::paper::ME766_RUNS;

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
    vec![
        Point::new(x0, y0),
        Point::new(x1, y0),
        Point::new(x1, y1),
        Point::new(x0, y1),
    ]
}

/// Problem `p` (1 or 2) of the paper as a 100 × 100 raster (a 10 × 10 cell).
pub fn workcell(p: u8) -> Result<Raster, harmonic_baselines::BaselineError> {
    let ws = rect(0.0, 0.0, 10.0, 10.0);
    let (obstacles, goal) = if p == 1 {
        (
            vec![
                rect(2.0, 5.5, 6.0, 6.5),
                rect(6.5, 2.0, 7.5, 7.0),
                rect(3.0, 1.5, 5.0, 3.5),
            ],
            rect(8.5, 8.5, 9.0, 9.0),
        )
    } else {
        (
            vec![
                rect(4.5, 0.0, 5.5, 7.0),
                rect(1.5, 6.0, 3.0, 8.5),
                rect(7.0, 3.0, 8.5, 4.5),
            ],
            rect(8.5, 1.0, 9.0, 1.5),
        )
    };
    Raster::from_polygons(&ws, &obstacles, &[goal], 100)
}

/// One of the paper's 2D runs beside ours.
#[derive(Clone, Debug, Serialize)]
pub struct Me766Row {
    /// Problem 1 or 2.
    pub problem: u8,
    /// `"dirichlet"` or `"neumann"` walls.
    pub walls: &'static str,
    /// The stopping accuracy (largest change in a step).
    pub accuracy: f64,
    /// The sink value.
    pub sink: f64,
    /// The paper's iterations.
    pub paper_iterations: usize,
    /// Ours, parabolic at the stability bound r = 1/4.
    pub parabolic_steps: usize,
    /// Ours, parabolic at r = 1/8.
    pub parabolic_steps_r_eighth: usize,
    /// Gauss–Seidel sweeps to the same accuracy (Dirichlet runs).
    pub gauss_seidel_sweeps: Option<usize>,
    /// Red–black SOR (optimal ω) sweeps to the same accuracy (Dirichlet runs).
    pub sor_sweeps: Option<usize>,
}

/// The paper's three 2D runs on the reconstructions.
pub fn me766_iterations() -> Result<Vec<Me766Row>, harmonic_baselines::BaselineError> {
    let mut rows = Vec::new();
    for run in ME766_RUNS.iter().filter(|r| r.dimension == 2) {
        let raster = workcell(run.problem)?;
        let dirichlet = run.walls == "dirichlet";
        let sink = if dirichlet { -1e8 } else { -0.5 };
        let opts = ParabolicOptions {
            sink,
            walls: if dirichlet {
                ParabolicWalls::Dirichlet(1.0)
            } else {
                ParabolicWalls::Neumann
            },
            accuracy: run.accuracy,
            ..ParabolicOptions::default()
        };
        let full = Parabolic::solve(raster.clone(), &opts)?.steps(&opts);
        let eighth_opts = ParabolicOptions { r: 0.125, ..opts };
        let eighth = Parabolic::solve(raster.clone(), &eighth_opts)?.steps(&eighth_opts);
        let (gs, sor) = if dirichlet {
            // u = 1 + (sink − 1)(1 − φ) with φ goal 0, walls 1: a change of ε in u is one
            // of ε / (1 − sink) in φ.
            let tol = run.accuracy / (1.0 - sink);
            let solve = |relaxation| {
                GridHarmonic::solve(
                    raster.clone(),
                    &SorOptions {
                        relaxation,
                        stop: StopRule::MaxUpdate(tol),
                        max_iterations: 1_000_000,
                        unknown: Unknown::Phi,
                        ..SorOptions::default()
                    },
                )
                .map(|g| g.report().iterations)
            };
            (
                Some(solve(Relaxation::GaussSeidel)?),
                Some(solve(Relaxation::RedBlackSor { omega: None })?),
            )
        } else {
            (None, None)
        };
        rows.push(Me766Row {
            problem: run.problem,
            walls: run.walls,
            accuracy: run.accuracy,
            sink,
            paper_iterations: run.iterations,
            parabolic_steps: full,
            parabolic_steps_r_eighth: eighth,
            gauss_seidel_sweeps: gs,
            sor_sweeps: sor,
        });
    }
    Ok(rows)
}

/// One k of the blend sweep.
#[derive(Clone, Debug, Serialize)]
pub struct BlendRow {
    /// The Dirichlet weight.
    pub k: f64,
    /// Per start: path length.
    pub length: Vec<f64>,
    /// Per start: smallest distance to walls and obstacles.
    pub clearance: Vec<f64>,
    /// Per start: smallest |∇φ| along the path.
    pub min_gradient: Vec<f64>,
    /// Per start: reached the goal.
    pub reached: Vec<bool>,
    /// Interior local minima of the blended potential (0: harmonic, maximum principle).
    pub interior_minima: usize,
}

/// Plans on `scene` with `"boundary": {"blend": {"k": k}}` for each k.
pub fn blend_sweep(
    scene: &Scene,
    starts: &[[f64; 2]],
    ks: &[f64],
) -> Result<Vec<BlendRow>, PlanError> {
    ks.iter()
        .map(|&k| {
            let mut s = scene.clone();
            s.boundary.blend = Some(BlendSpec { k, neumann: 1.0 });
            let planner = Planner::new(&s)?;
            let paths: Vec<_> = starts.iter().map(|&p| planner.plan(p)).collect();
            Ok(BlendRow {
                k,
                length: paths.iter().map(|p| p.length).collect(),
                clearance: paths.iter().map(|p| p.min_clearance).collect(),
                min_gradient: paths.iter().map(|p| p.min_gradient).collect(),
                reached: paths.iter().map(|p| p.status.reached_goal()).collect(),
                interior_minima: harmonic_planner::fem::interior_local_extrema(
                    planner.mesh(),
                    planner.potential().psi(),
                )
                .minima,
            })
        })
        .collect()
}
