//! The extended-exponent solve (issue #19) as the FEM solver uses it: a Dirichlet corridor of
//! 400 widths (ψ ≈ 1e-546 at the far end) comes back with exponents, its float ψ agreeing
//! bit for bit with the ordinary accurate solve wherever that did not underflow; a corridor of
//! 50 widths takes the ordinary path and is not extended.

use std::sync::Arc;

use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryConditions, EXTENDED_BELOW, Ordering, SolveMethod, Solver,
};
use harmonic_mesh::{Domain, DomainSpec, GoalShape, Mesh, MeshOptions, Point};
use harmonic_solver::AccurateLdlt;

fn corridor(length: f64) -> Arc<Mesh> {
    let spec = DomainSpec {
        workspace: vec![
            Point::new(0.0, 0.0),
            Point::new(length, 0.0),
            Point::new(length, 1.0),
            Point::new(0.0, 1.0),
        ],
        obstacles: vec![],
        goals: vec![GoalShape::Polygon(vec![
            Point::new(0.2, 0.3),
            Point::new(0.2, 0.7),
            Point::new(0.6, 0.7),
            Point::new(0.6, 0.3),
        ])],
        robot_radius: 0.0,
    };
    let opts = MeshOptions {
        max_area: Some(0.05),
        ..MeshOptions::default()
    };
    let (mesh, _) = Domain::new(&spec, &opts).unwrap().mesh(&opts).unwrap();
    Arc::new(mesh)
}

fn solver_for(mesh: &Arc<Mesh>) -> (Solver, harmonic_fem::LinearSystem, Ordering) {
    let bcs = BoundaryConditions::default();
    let assembler = Assembler::new(Arc::clone(mesh), &bcs, AssemblyOptions::default()).unwrap();
    let system = assembler.assemble(&bcs).unwrap();
    let solver = Solver::with_method(
        &system,
        assembler.nested_dissection(),
        SolveMethod::Accurate,
    )
    .unwrap();
    (solver, system, assembler.nested_dissection())
}

#[test]
fn a_corridor_of_400_widths_is_solved_with_exponents() {
    let mesh = corridor(400.0);
    let (solver, system, ordering) = solver_for(&mesh);
    let (wide, report) = solver.solve_wide(&system).unwrap();
    assert!(report.extended);
    // The ordinary accurate solve of the same system, at the unknowns.
    let m = system.m_matrix().unwrap();
    let plain = AccurateLdlt::factor(&m, ordering)
        .unwrap()
        .solve(system.rhs())
        .unwrap();
    let floats = system.expand(&plain).unwrap();
    let smallest = wide
        .iter()
        .filter(|w| !w.is_zero())
        .map(|w| w.log10())
        .fold(0.0, f64::min);
    assert!(smallest < -500.0, "{smallest}");
    // Where ψ is well inside the double range the extended solve rounds as the ordinary one;
    // below, the ordinary one has lost entries to underflow.
    let mut lost = 0;
    for (w, &f) in wide.iter().zip(&floats) {
        if f > 1e-290 {
            assert_eq!(w.to_f64(), f);
        } else if !w.is_zero() && f == 0.0 {
            lost += 1;
        }
    }
    assert!(lost > 100, "{lost}");
    let potential = solver.potential(Arc::clone(&mesh), &system).unwrap();
    assert!(potential.is_extended());
    assert_eq!(potential.local_extrema().minima, 0);
    assert_eq!(potential.local_extrema().maxima, 0);
    let (m, e) = potential.psi_extended().unwrap();
    assert_eq!(m.len(), mesh.vertices().len());
    assert_eq!(e.len(), m.len());
    let (g, ge) = potential.nodal_gradients_extended().unwrap();
    assert_eq!((g.len(), ge.len()), (m.len(), m.len()));
    // Every non-zero ψ decreases along the corridor: the far end is the smallest.
    let far = (0..mesh.vertices().len())
        .filter(|&v| !potential.psi_wide(v as u32).is_zero())
        .max_by(|&a, &b| mesh.vertices()[a].x.total_cmp(&mesh.vertices()[b].x))
        .unwrap();
    let lg = potential.psi_wide(far as u32).log10();
    assert!((lg - smallest).abs() < 5.0, "{lg} vs {smallest}");
    // An interior vertex at the far end: φ's recovered gradient points along the corridor.
    assert!(g[far].x.abs() > 0.0 || g[far].y.abs() > 0.0);
}

#[test]
fn a_short_corridor_takes_the_ordinary_path() {
    let mesh = corridor(50.0);
    let (solver, system, _) = solver_for(&mesh);
    let (wide, report) = solver.solve_wide(&system).unwrap();
    assert!(!report.extended);
    assert!(
        wide.iter()
            .all(|w| w.is_zero() || w.to_f64() > EXTENDED_BELOW)
    );
    let potential = solver.potential(Arc::clone(&mesh), &system).unwrap();
    assert!(!potential.is_extended());
    assert!(potential.psi_extended().is_none());
    assert!(potential.nodal_gradients_extended().is_none());
}
