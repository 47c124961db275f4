//! Structural properties: discrete maximum principle, M-matrix sign pattern, reuse of the
//! pattern and the symbolic factorisation, errors for ill-posed conditions.

mod common;

use std::sync::Arc;

use common::{square_with_hole, three_part_tags};
use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, FemError, Ordering,
    Potential, RobinMass, Solver, blend, offdiagonal_sign_violations, solve_potential,
};
use harmonic_fixtures::{Diagonals, Grid, Side};
use harmonic_mesh::{BoundaryTag, Mesh, Point, Vector};

fn grid(n: usize) -> Arc<Mesh> {
    Arc::new(square_with_hole(n, 0.0, 0.0, three_part_tags))
}

fn robin_walls() -> BoundaryConditions {
    BoundaryConditions::uniform(BoundaryCondition::Robin {
        a: 1.0,
        b: 1.0,
        g: 1.0,
    })
}

#[test]
fn maximum_principle_on_delaunay_grid() {
    let mesh = grid(32);
    for bcs in [BoundaryConditions::default(), robin_walls()] {
        let assembler =
            Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("pattern");
        let system = assembler.assemble(&bcs).expect("assembly");
        assert_eq!(offdiagonal_sign_violations(&system), 0);
        let solver = Solver::new(&system, Ordering::Amd).expect("symbolic");
        let p = solver.potential(Arc::clone(&mesh), &system).expect("solve");
        assert_eq!(p.interior_local_extrema(), 0);
        // φ between the goal value and the reference value everywhere.
        assert!(p.psi().iter().all(|&s| (-1e-14..=1.0 + 1e-14).contains(&s)));
    }
}

#[test]
fn consistent_robin_mass_breaks_the_sign_pattern() {
    // Boundary edges face 45° angles (stiffness −1/2); the consistent mass adds (b/a)h/6 =
    // 50·0.125/6 > 1/2 to them at n = 16.
    let bcs = BoundaryConditions::uniform(BoundaryCondition::Robin {
        a: 1.0,
        b: 50.0,
        g: 50.0,
    });
    let options = AssemblyOptions {
        robin_mass: RobinMass::Consistent,
    };
    let mut diffs = Vec::new();
    for n in [16, 64] {
        let mesh = grid(n);
        let system = Assembler::new(Arc::clone(&mesh), &bcs, options)
            .expect("pattern")
            .assemble(&bcs)
            .expect("assembly");
        if n == 16 {
            assert!(offdiagonal_sign_violations(&system) > 0);
        }
        // Still SPD, and both quadratures converge to the same solution.
        let consistent = Solver::new(&system, Ordering::Amd)
            .expect("symbolic")
            .potential(Arc::clone(&mesh), &system)
            .expect("solve");
        let lumped = solve_potential(Arc::clone(&mesh), &bcs).expect("solve");
        let diff = consistent
            .psi()
            .iter()
            .zip(lumped.psi())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        diffs.push(diff);
    }
    assert!(diffs[0] > 0.0 && diffs[1] < diffs[0] / 2.0, "{diffs:?}");
}

/// A mesh with a long obtuse-angle pair (not Delaunay) has a positive off-diagonal.
#[test]
fn non_delaunay_mesh_is_detected() {
    // Rhombus flattened so the shared edge faces two angles of ~160°.
    // The long edge 0–2 is shared by triangles (0,1,2) and (0,2,3) whose angles at 1 and 3
    // are about 170°; the Delaunay choice would be the short edge 1–3.
    let vertices = vec![
        Point::new(0.0, 0.0),
        Point::new(1.0, -0.1),
        Point::new(2.0, 0.0),
        Point::new(1.0, 0.1),
        Point::new(1.0, -1.0),
        Point::new(1.0, 1.0),
    ];
    let triangles = vec![
        [0, 1, 2],
        [0, 2, 3],
        [0, 4, 1],
        [1, 4, 2],
        [2, 5, 3],
        [3, 5, 0],
    ];
    let boundary = [
        (0, 4, BoundaryTag::Wall),
        (4, 2, BoundaryTag::Wall),
        (2, 5, BoundaryTag::Goal(0)),
        (5, 0, BoundaryTag::Wall),
    ];
    let mesh = Arc::new(Mesh::from_parts(vertices, triangles, &boundary).expect("mesh"));
    // Neumann on the walls so vertices 0 and 2 stay unknowns and edge 0–2 (opposite the two
    // obtuse angles at 1 and 3) couples two unknowns.
    let bcs = BoundaryConditions {
        walls: BoundaryCondition::Neumann(0.5),
        ..BoundaryConditions::default()
    };
    let system = Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default())
        .expect("pattern")
        .assemble(&bcs)
        .expect("assembly");
    assert!(offdiagonal_sign_violations(&system) >= 1);
}

#[test]
fn reassembly_reuses_pattern_and_symbolic() {
    let mesh = grid(16);
    let bcs = robin_walls();
    let assembler =
        Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("pattern");
    let mut system = assembler.assemble(&bcs).expect("assembly");
    let solver = Solver::new(&system, Ordering::Amd).expect("symbolic");
    let first = solver.solve(&system).expect("solve");
    // New values, same kinds: Robin with a stronger coefficient, goal at another value.
    let mut stronger = robin_walls();
    stronger.walls = BoundaryCondition::Robin {
        a: 1.0,
        b: 4.0,
        g: 4.0,
    };
    stronger.goals = BoundaryCondition::Dirichlet(-1.0);
    assembler
        .assemble_into(&stronger, None, &mut system)
        .expect("re-assembly");
    let second = solver.potential(Arc::clone(&mesh), &system).expect("solve");
    let fresh = solve_potential(Arc::clone(&mesh), &stronger).expect("fresh solve");
    assert_eq!(second.reference(), 1.0);
    let diff = second
        .psi()
        .iter()
        .zip(fresh.psi())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-13, "diff {diff}");
    assert!(
        first
            .iter()
            .zip(second.psi())
            .any(|(a, b)| (a - b).abs() > 1e-3)
    );
    // Changing a part from Dirichlet to Neumann needs a new assembler.
    let mut neumann_goal = stronger.clone();
    neumann_goal.goals = BoundaryCondition::Neumann(1.0);
    assert!(matches!(
        assembler.assemble(&neumann_goal),
        Err(FemError::KindChanged { .. })
    ));
}

#[test]
fn pure_neumann_is_rejected_with_a_reason() {
    let mesh = grid(8);
    let bcs = BoundaryConditions {
        walls: BoundaryCondition::Neumann(1.0),
        obstacles: BoundaryCondition::Neumann(0.0),
        goals: BoundaryCondition::Neumann(-1.0),
        ..BoundaryConditions::default()
    };
    let err = solve_potential(mesh, &bcs).unwrap_err();
    assert!(matches!(err, FemError::OnlyNeumann { .. }), "{err}");
    assert!(
        err.to_string().contains("defined up to a constant"),
        "{err}"
    );
}

#[test]
fn constant_potential_is_rejected_with_a_reason() {
    let mesh = grid(8);
    let mut bcs = BoundaryConditions {
        goals: BoundaryCondition::Dirichlet(1.0),
        ..BoundaryConditions::default()
    };
    let err = solve_potential(Arc::clone(&mesh), &bcs).unwrap_err();
    assert!(
        matches!(err, FemError::ConstantPotential { value } if value == 1.0),
        "{err}"
    );
    assert!(err.to_string().contains("nothing drives the flow"), "{err}");
    // A Neumann flux drives it again.
    bcs.obstacles = BoundaryCondition::Neumann(0.25);
    assert!(solve_potential(mesh, &bcs).is_ok());
}

#[test]
fn robin_only_is_well_posed() {
    // Robin with b/a > 0 everywhere anchors the potential without any Dirichlet part.
    let mesh = Arc::new(square_with_hole(8, 0.0, 0.0, |_| BoundaryTag::Wall));
    let bcs = BoundaryConditions {
        walls: BoundaryCondition::Robin {
            a: 1.0,
            b: 2.0,
            g: 0.0,
        },
        obstacles: BoundaryCondition::Robin {
            a: 1.0,
            b: 1.0,
            g: 1.0,
        },
        ..BoundaryConditions::default()
    };
    let p = solve_potential(mesh, &bcs).expect("solve");
    assert_eq!(p.reference(), 1.0);
    assert_eq!(p.interior_local_extrema(), 0);
}

/// A linear φ is reproduced exactly (P1 contains it): values, gradients, recovery and a
/// zero error indicator.
#[test]
fn linear_field_is_exact() {
    let mesh = grid(8);
    let exact = |p: Point| 0.3 + 0.2 * p.x - 0.1 * p.y;
    let bcs = BoundaryConditions {
        walls: BoundaryCondition::Robin {
            a: 1.0,
            b: 3.0,
            g: 0.0,
        },
        obstacles: BoundaryCondition::Neumann(0.0),
        goals: BoundaryCondition::Dirichlet(0.0),
        ..BoundaryConditions::default()
    };
    let grad = Vector::new(0.2, -0.1);
    let data = |e: &harmonic_mesh::BoundaryEdge, p: Point| {
        let d = mesh.vertices()[e.vertices[1] as usize] - mesh.vertices()[e.vertices[0] as usize];
        let n = Vector::new(d.y, -d.x) / d.norm();
        match bcs.for_tag(e.tag) {
            BoundaryCondition::Dirichlet(_) => exact(p),
            BoundaryCondition::Neumann(_) => grad.dot(&n),
            BoundaryCondition::Robin { a, b, .. } => a * grad.dot(&n) + b * exact(p),
        }
    };
    // The lumped Robin mass is not exact for a linear ψ; the consistent one is.
    let consistent = Assembler::new(
        Arc::clone(&mesh),
        &bcs,
        AssemblyOptions {
            robin_mass: RobinMass::Consistent,
        },
    )
    .expect("pattern");
    let system = consistent.assemble_with(&bcs, &data).expect("assembly");
    let p: Potential = Solver::new(&system, Ordering::Amd)
        .expect("symbolic")
        .potential(Arc::clone(&mesh), &system)
        .expect("solve");
    for (v, phi) in p.phi_at_vertices().iter().enumerate() {
        assert!((phi - exact(mesh.vertices()[v])).abs() < 1e-12);
    }
    let q = Point::new(0.3, 1.7);
    let e = p.evaluate(q, None).expect("inside");
    assert!((e.phi - exact(q)).abs() < 1e-12);
    assert!((e.grad_psi + grad).norm() < 1e-11);
    assert!(
        (p.recovered_gradient_psi_at(q, Some(e.triangle))
            .expect("inside")
            + grad)
            .norm()
            < 1e-11
    );
    assert!(p.error_indicator().iter().all(|&eta| eta < 1e-10));
    assert!(matches!(
        p.phi_at(Point::new(1.0, 1.0), None),
        Err(FemError::OutsideMesh { .. })
    ));
}

#[test]
fn extrema_and_indicator_see_a_bump() {
    let mesh = grid(8);
    let mut psi = vec![0.0; mesh.vertices().len()];
    let bump = mesh
        .vertex_tags()
        .iter()
        .position(|t| t.is_none())
        .expect("an interior vertex");
    psi[bump] = 1.0;
    let p = Potential::new(Arc::clone(&mesh), psi, 1.0).expect("potential");
    assert_eq!(p.interior_local_extrema(), 1);
    let eta = p.error_indicator();
    assert!(eta.iter().any(|&e| e > 0.1));
    assert!(eta.iter().filter(|&&e| e == 0.0).count() > eta.len() / 2);
}

#[test]
fn blend_mixes_dirichlet_and_neumann_fields() {
    let mesh = grid(16);
    let dirichlet = solve_potential(Arc::clone(&mesh), &BoundaryConditions::default()).expect("D");
    // Neumann variant: walls and obstacles emit a unit flux towards the goal.
    let neumann = solve_potential(
        Arc::clone(&mesh),
        &BoundaryConditions::uniform(BoundaryCondition::Neumann(1.0)),
    )
    .expect("N");
    let k = 0.3;
    let mixed = blend(k, &dirichlet, &neumann).expect("blend");
    let (pd, pn, pm) = (
        dirichlet.phi_at_vertices(),
        neumann.phi_at_vertices(),
        mixed.phi_at_vertices(),
    );
    for v in 0..pm.len() {
        assert!((pm[v] - (k * pd[v] + (1.0 - k) * pn[v])).abs() < 1e-12);
    }
    assert_eq!(mixed.interior_local_extrema(), 0);
    assert!(matches!(
        blend(1.5, &dirichlet, &neumann),
        Err(FemError::BadWeight { .. })
    ));
    let other = grid(8);
    let elsewhere = solve_potential(other, &BoundaryConditions::default()).expect("D");
    assert!(matches!(
        blend(0.5, &dirichlet, &elsewhere),
        Err(FemError::DifferentMeshes)
    ));
}

/// A vertex on both a Dirichlet wall (φ = 1) and the Dirichlet goal (φ = 0) takes the goal's
/// lower value.
#[test]
fn goal_wins_at_shared_corners() {
    let mesh = grid(8);
    let p = solve_potential(Arc::clone(&mesh), &BoundaryConditions::default()).expect("solve");
    let phi = p.phi_at_vertices();
    for corner in [Point::new(0.0, 0.0), Point::new(0.0, 2.0)] {
        let v = mesh
            .vertices()
            .iter()
            .position(|&q| q == corner)
            .expect("corner vertex");
        assert_eq!(phi[v], 0.0, "corner {corner:?}");
    }
}

#[test]
fn systems_and_solutions_are_checked_against_their_assembler() {
    let bcs = BoundaryConditions::default();
    let a = Assembler::new(grid(8), &bcs, AssemblyOptions::default()).expect("pattern");
    let b = Assembler::new(grid(8), &bcs, AssemblyOptions::default()).expect("pattern");
    let mut system = a.assemble(&bcs).expect("assembly");
    assert!(matches!(
        b.assemble_into(&bcs, None, &mut system),
        Err(FemError::ForeignSystem)
    ));
    assert!(matches!(
        system.expand(&[0.0; 3]),
        Err(FemError::LengthMismatch { .. })
    ));
    let nan = |_: &harmonic_mesh::BoundaryEdge, _: Point| f64::NAN;
    assert!(matches!(
        a.assemble_with(&bcs, &nan),
        Err(FemError::NonFiniteData { .. })
    ));
}

/// ψ = c − φ keeps its relative precision where φ is within 1e-17 of the wall value: along a
/// long corridor with the goal at one end, ψ decays like e^(−πx) far below f64 resolution of
/// φ, yet stays positive and decreasing, at the rate of the exact first mode.
#[test]
fn psi_keeps_precision_in_a_long_corridor() {
    let (len, per_unit) = (20usize, 8usize);
    let (nx, ny) = (len * per_unit, per_unit);
    let grid = Grid::new(nx, ny, 1.0 / per_unit as f64).with_diagonals(Diagonals::Rising);
    let id = |i: usize, j: usize| grid.vertex(i, j);
    let mesh = Arc::new(
        grid.parts(|side| match side {
            Side::Left => BoundaryTag::Goal(0),
            _ => BoundaryTag::Wall,
        })
        .mesh(),
    );
    let p = solve_potential(Arc::clone(&mesh), &BoundaryConditions::default()).expect("solve");
    let centre: Vec<f64> = (0..=nx).map(|i| p.psi()[id(i, ny / 2) as usize]).collect();
    assert!(centre[1..nx].iter().all(|&s| s > 0.0));
    assert!(centre.windows(2).all(|w| w[1] < w[0]));
    // φ has no digits left there...
    assert_eq!(p.phi_at_vertices()[id(nx - per_unit, ny / 2) as usize], 1.0);
    // ...but ψ decays per unit length by about e^(−π) (first mode sin(πy)e^(−πx)).
    let per_unit_decay = (centre[10 * per_unit] / centre[11 * per_unit]).ln();
    assert!(
        (per_unit_decay - std::f64::consts::PI).abs() < 0.05,
        "decay {per_unit_decay}, ψ(19) = {}",
        centre[19 * per_unit]
    );
    assert!(centre[19 * per_unit] < 1e-20);
}
