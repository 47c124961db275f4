//! Goals chosen after the factorisation ([`GoalSolver`]): each field equals a fresh solve of
//! the same goal vertices held, entrywise, and keeps the maximum principle.

use std::sync::Arc;

use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, FemError, GoalSolver,
    SolveMethod, interior_local_extrema_except,
};
use harmonic_fixtures::{max_relative_difference, reference_disc};
use harmonic_mesh::{Domain, DomainSpec, Mesh, MeshOptions, Point};

/// The reference scene (square, five obstacles) with no goal, triangles of area ≤ `max_area`.
fn goal_free_mesh(max_area: f64) -> Arc<Mesh> {
    let spec = DomainSpec {
        goals: Vec::new(),
        ..reference_disc()
    };
    let opts = MeshOptions {
        max_area: Some(max_area),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).expect("valid scene");
    Arc::new(domain.mesh(&opts).expect("meshes").0)
}

/// The vertices of the triangle holding `p`.
fn triangle_at(mesh: &Mesh, p: Point) -> Vec<u32> {
    let t = mesh.locate(p, None).expect("inside the mesh");
    mesh.triangles()[t as usize].to_vec()
}

/// The vertices within `r` of `c`.
fn disc(mesh: &Mesh, c: Point, r: f64) -> Vec<u32> {
    (0..mesh.vertices().len() as u32)
        .filter(|&v| (mesh.vertices()[v as usize] - c).norm() <= r)
        .collect()
}

fn solver(mesh: &Arc<Mesh>, bcs: &BoundaryConditions) -> GoalSolver {
    let assembler =
        Assembler::new(Arc::clone(mesh), bcs, AssemblyOptions::default()).expect("assembles");
    GoalSolver::new(&assembler, bcs, SolveMethod::Auto).expect("factors")
}

/// The goals of these tests: a point's triangle, a region with an inside, one vertex.
fn goals(mesh: &Mesh) -> Vec<Vec<u32>> {
    vec![
        triangle_at(mesh, Point::new(8.5, 1.5)),
        disc(mesh, Point::new(1.0, 9.0), 0.35),
        vec![triangle_at(mesh, Point::new(4.0, 5.5))[0]],
    ]
}

#[test]
fn each_goal_equals_a_fresh_solve_of_its_vertices_entrywise() {
    let mesh = goal_free_mesh(0.02);
    let bcs = BoundaryConditions::default();
    let goals_solver = solver(&mesh, &bcs);
    assert_eq!(goals_solver.method(), SolveMethod::Accurate);
    let goals = goals(&mesh);
    let solutions = goals_solver.solve(&goals).expect("solves");
    for (g, (goal, sol)) in goals.iter().zip(&solutions).enumerate() {
        let fresh = goals_solver.solve_fresh(goal).expect("fresh solve");
        let d = max_relative_difference(&sol.psi, &fresh);
        assert!(d <= 1e-9, "goal {g}: relative difference {d:e}");
        assert!(sol.report.entrywise_accurate, "goal {g}: {:?}", sol.report);
        assert!(
            sol.flux.iter().all(|&f| f >= 0.0),
            "goal {g}: {:?}",
            sol.flux
        );
        for &v in goal {
            assert_eq!(sol.psi[v as usize], 1.0);
        }
        // The far field is small but positive (it has digits to compare).
        let smallest = sol
            .psi
            .iter()
            .copied()
            .filter(|&v| v > 0.0)
            .fold(1.0, f64::min);
        assert!(smallest < 1e-3, "goal {g}: smallest ψ {smallest:e}");
    }
    // The region's inside carries no column.
    assert!(solutions[1].report.columns < solutions[1].report.held);
}

/// Interior vertices off the goal where ψ is a strict local extremum among its neighbours.
fn extrema_off_the_goal(mesh: &Mesh, psi: &[f64], goal: &[u32]) -> usize {
    let e = interior_local_extrema_except(mesh, psi, |v| goal.contains(&v));
    e.minima + e.maxima
}

#[test]
fn goal_fields_keep_the_maximum_principle_apart_from_the_goal() {
    let mesh = goal_free_mesh(0.02);
    let goals_solver = solver(&mesh, &BoundaryConditions::default());
    let goals = goals(&mesh);
    for (goal, sol) in goals
        .iter()
        .zip(goals_solver.solve(&goals).expect("solves"))
    {
        assert_eq!(extrema_off_the_goal(&mesh, &sol.psi, goal), 0);
        // The count sees extrema: a one-vertex goal is a strict maximum when not excused.
        if goal.len() == 1 {
            assert_eq!(extrema_off_the_goal(&mesh, &sol.psi, &[]), 1);
        }
        let max = sol.psi.iter().copied().fold(0.0, f64::max);
        assert_eq!(max, 1.0);
    }
}

#[test]
fn robin_walls_and_neumann_beside_a_held_part_are_allowed() {
    let mesh = goal_free_mesh(0.05);
    let goal = triangle_at(&mesh, Point::new(8.5, 1.5));
    // Robin walls at equilibrium with the reference: no wall flux, still entrywise accurate.
    let robin = BoundaryConditions {
        walls: BoundaryCondition::Robin {
            a: 1.0,
            b: 10.0,
            g: 10.0,
        },
        ..BoundaryConditions::default()
    };
    // Neumann walls with an inflow, obstacles held: the walls drive a flow of their own.
    let flux = BoundaryConditions {
        walls: BoundaryCondition::Neumann(0.05),
        ..BoundaryConditions::default()
    };
    for (name, bcs, entrywise) in [("robin", robin, true), ("neumann inflow", flux, false)] {
        let s = solver(&mesh, &bcs);
        let sol = s
            .solve(std::slice::from_ref(&goal))
            .expect("solves")
            .remove(0);
        let fresh = s.solve_fresh(&goal).expect("fresh");
        assert_eq!(sol.report.entrywise_accurate, entrywise, "{name}");
        let scale = fresh.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let worst = sol
            .psi
            .iter()
            .zip(&fresh)
            .map(|(a, b)| {
                (a - b).abs()
                    / if entrywise {
                        a.abs().max(b.abs()).max(1e-300)
                    } else {
                        scale
                    }
            })
            .fold(0.0, f64::max);
        assert!(worst <= 1e-9, "{name}: difference {worst:e}");
    }
}

#[test]
fn only_neumann_walls_are_refused_with_the_reason() {
    let mesh = goal_free_mesh(0.2);
    let bcs = BoundaryConditions {
        walls: BoundaryCondition::Neumann(0.0),
        obstacles: BoundaryCondition::Neumann(0.0),
        ..BoundaryConditions::default()
    };
    let assembler =
        Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("assembler");
    let err = GoalSolver::new(&assembler, &bcs, SolveMethod::Auto).expect_err("singular");
    assert!(matches!(err, FemError::WallsHoldNothing { .. }), "{err}");
    assert!(err.to_string().contains("Neumann"), "{err}");
}

#[test]
fn bad_goals_are_named() {
    let mesh = goal_free_mesh(0.2);
    let s = solver(&mesh, &BoundaryConditions::default());
    let wall_vertex = 0; // a corner of the square: on the Dirichlet wall
    let err = s.solve(&[vec![]]).expect_err("empty");
    assert!(matches!(err, FemError::EmptyGoal { goal: 0 }), "{err}");
    let inside = triangle_at(&mesh, Point::new(8.5, 1.5));
    let err = s
        .solve(&[inside, vec![wall_vertex]])
        .expect_err("on a wall");
    assert!(
        matches!(err, FemError::GoalVertexNotFree { goal: 1, vertex: 0 }),
        "{err}"
    );
    let err = s.solve(&[vec![u32::MAX]]).expect_err("no such vertex");
    assert!(err.to_string().contains("not free"), "{err}");
}
