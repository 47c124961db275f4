//! The multigrid solve (`MultilevelSystem`) against the direct one on the same refined mesh,
//! for Dirichlet and Robin walls, with its iteration count independent of the levels.

mod common;

use std::sync::Arc;

use common::max_abs_diff;

use harmonic_fem::{
    BoundaryCondition, BoundaryConditions, MULTIGRID_REL_TOL, MultigridOptions, MultilevelSystem,
    solve_potential,
};
use harmonic_fixtures::reference_mesh;

/// Largest |ψ_multigrid − ψ_direct| over the finest mesh's vertices, and the iterations taken.
fn compare(coarse_area: f64, refinements: usize, bcs: &BoundaryConditions) -> (f64, usize) {
    let hierarchy =
        harmonic_mesh::uniform_hierarchy(reference_mesh(coarse_area), refinements).expect("refine");
    let levels = MultilevelSystem::assemble(&hierarchy, bcs).expect("assemble");
    let cycle = levels
        .multigrid(MultigridOptions::default())
        .expect("multigrid");
    assert_eq!(cycle.level_count(), refinements + 1);
    let (mg, report) = levels.solve(&cycle, MULTIGRID_REL_TOL).expect("solve");
    assert!(report.rel_residual <= MULTIGRID_REL_TOL);
    let direct = solve_potential(Arc::clone(hierarchy.finest()), bcs).expect("direct solve");
    let diff = max_abs_diff(mg.psi(), direct.psi());
    (diff, report.iterations)
}

#[test]
fn dirichlet_walls_agree_with_the_direct_solve() {
    let (diff, iterations) = compare(0.05, 2, &BoundaryConditions::default());
    assert!(diff <= 1e-8, "max |ψ_mg − ψ_direct| = {diff:e}");
    assert!(iterations <= 10, "{iterations} iterations");
}

#[test]
fn robin_walls_agree_with_the_direct_solve() {
    let bcs = BoundaryConditions::uniform(BoundaryCondition::Robin {
        a: 1.0,
        b: 1.0,
        g: 1.0,
    });
    let (diff, iterations) = compare(0.05, 2, &bcs);
    assert!(diff <= 1e-8, "max |ψ_mg − ψ_direct| = {diff:e}");
    assert!(iterations <= 10, "{iterations} iterations");
}

#[test]
fn iterations_stay_flat_as_levels_are_added() {
    // About 1.5k coarse triangles refined 1, 2 and 3 times (6k to 100k triangles).
    let counts: Vec<usize> = (1..=3)
        .map(|k| compare(0.1, k, &BoundaryConditions::default()).1)
        .collect();
    eprintln!("iterations with 1, 2, 3 refinements: {counts:?}");
    // 7, 8, 8 when written.
    assert!(counts.iter().all(|&c| c <= 10), "{counts:?}");
    assert!(counts[2] <= counts[0] + 2, "{counts:?}");
}

#[test]
fn a_single_level_is_the_direct_solve() {
    let (diff, iterations) = compare(0.05, 0, &BoundaryConditions::default());
    assert_eq!(iterations, 0);
    assert!(diff <= 1e-12, "{diff:e}");
}
