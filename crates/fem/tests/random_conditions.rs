//! Property tests over random boundary values: maximum principle, bounds, equality of
//! re-assembled (pattern and symbolic reused) and fresh solutions, and the multigrid solve
//! against the direct one.

mod common;

use std::sync::Arc;

use common::{max_abs_diff, square_with_hole, three_part_tags};
use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, MULTIGRID_REL_TOL,
    MultigridOptions, MultilevelSystem, Ordering, Solver, offdiagonal_sign_violations,
    solve_potential,
};
use proptest::prelude::*;

/// Dirichlet goal, Dirichlet or Robin (no flux) walls and obstacle.
fn conditions() -> impl Strategy<Value = BoundaryConditions> {
    let part = prop_oneof![
        (-5.0..5.0f64).prop_map(BoundaryCondition::Dirichlet),
        (0.1..10.0f64, 0.1..10.0f64, -5.0..5.0f64).prop_map(|(a, beta, level)| {
            BoundaryCondition::Robin {
                a,
                b: a * beta,
                g: a * beta * level,
            }
        }),
    ];
    (part.clone(), part, -5.0..5.0f64).prop_map(|(walls, obstacles, goal)| BoundaryConditions {
        walls,
        obstacles,
        goals: BoundaryCondition::Dirichlet(goal),
        ..BoundaryConditions::default()
    })
}

/// The Dirichlet values and Robin equilibria g/b: φ must stay within their range.
fn levels(bcs: &BoundaryConditions) -> (f64, f64) {
    let level = |bc: BoundaryCondition| match bc {
        BoundaryCondition::Dirichlet(v) => v,
        BoundaryCondition::Robin { b, g, .. } => g / b,
        BoundaryCondition::Neumann(_) => unreachable!("no Neumann parts here"),
    };
    let l = [level(bcs.walls), level(bcs.obstacles), level(bcs.goals)];
    (
        l.iter().copied().fold(f64::INFINITY, f64::min),
        l.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn maximum_principle_and_reuse(first in conditions(), second in conditions()) {
        let mesh = Arc::new(square_with_hole(12, 0.0, 0.0, three_part_tags));
        let Ok(fresh) = solve_potential(Arc::clone(&mesh), &first) else {
            // Only a constant problem (all levels equal) may be refused.
            let (lo, hi) = levels(&first);
            prop_assert!(hi - lo <= 1e-12 * hi.abs().max(1.0));
            return Ok(());
        };
        let (lo, hi) = levels(&first);
        let tol = 1e-12 * (hi - lo).max(1.0);
        prop_assert!(fresh.phi_at_vertices().iter().all(|&p| p >= lo - tol && p <= hi + tol));
        prop_assert_eq!(fresh.interior_local_extrema(), 0);

        // Re-assembling `second` into a system built for `first` (when the kinds agree) and
        // reusing the symbolic factorisation gives the fresh solution of `second`.
        let assembler = Assembler::new(Arc::clone(&mesh), &first, AssemblyOptions::default())
            .expect("pattern");
        let mut system = assembler.assemble(&first).expect("assembly");
        prop_assert_eq!(offdiagonal_sign_violations(&system), 0);
        let solver = Solver::new(&system, Ordering::Amd).expect("symbolic");
        if first.walls.kind() == second.walls.kind()
            && first.obstacles.kind() == second.obstacles.kind()
            && let (Ok(()), Ok(direct)) = (
                assembler.assemble_into(&second, None, &mut system),
                solve_potential(Arc::clone(&mesh), &second),
            )
        {
            let reused = solver.potential(Arc::clone(&mesh), &system).expect("solve");
            let scale = direct.psi().iter().fold(1.0f64, |m, &s| m.max(s.abs()));
            for (a, b) in reused.psi().iter().zip(direct.psi()) {
                prop_assert!((a - b).abs() <= 1e-12 * scale);
            }
        }
    }

    /// Multigrid on the square with a hole refined twice (8 → 32 cells a side) gives the
    /// direct solution to 1e-8 of ψ's scale, within the maximum principle's bounds.
    #[test]
    fn multigrid_agrees_with_the_direct_solve(bcs in conditions()) {
        let coarse = square_with_hole(8, 0.0, 0.0, three_part_tags);
        let hierarchy = harmonic_mesh::uniform_hierarchy(coarse, 2).expect("refine");
        let Ok(direct) = solve_potential(Arc::clone(hierarchy.finest()), &bcs) else {
            return Ok(()); // a constant problem, refused by both (checked above)
        };
        let system = MultilevelSystem::assemble(&hierarchy, &bcs).expect("assemble");
        let cycle = system.multigrid(MultigridOptions::default()).expect("multigrid");
        let (mg, report) = system.solve(&cycle, MULTIGRID_REL_TOL).expect("solve");
        prop_assert!(report.iterations <= 12, "{report:?}");
        let scale = direct.psi().iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let diff = max_abs_diff(mg.psi(), direct.psi());
        prop_assert!(diff <= 1e-8 * scale, "max |Δψ| = {diff:e}, scale {scale}");
        let (lo, hi) = levels(&bcs);
        let tol = 1e-8 * (hi - lo).abs().max(1.0);
        for phi in mg.phi_at_vertices() {
            prop_assert!(phi >= lo - tol && phi <= hi + tol, "φ = {phi} outside [{lo}, {hi}]");
        }
    }
}
