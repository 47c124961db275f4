//! Dynamic replanning on a local map of 3200 triangles (Garrido et al. 2010, §6: a 40 × 40
//! map "in less than one second"): one full replan — local goal, mesh, assembly,
//! factorisation, solve and trace — of the reference scene with a sensed obstacle in the
//! window: on the fixed lattice with the obstacles cut in (the default) from one point, and
//! from a robot moving 5 cm per replan up and down the corridor (so the window and its
//! unknowns change, and the kept elimination order is refreshed as it would be on the move);
//! remeshed from scratch; then the remeshed replan's stages on their own.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_dynamic::{DynamicPlanner, LocalMapMode, LocalMapOptions};
use harmonic_planner::Scene;
use harmonic_planner::fem::{Assembler, AssemblyOptions, SolveMethod, Solver};
use harmonic_planner::mesh::Domain;
use harmonic_planner::solver::Ordering;

fn reference() -> Scene {
    Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/reference.json"
    ))
    .expect("the reference scene is valid")
}

fn replan(c: &mut Criterion) {
    let scene = reference();
    let obstacle = vec![[4.0, 4.6], [4.5, 4.6], [4.5, 5.1], [4.0, 5.1]];
    let robot = [3.7, 6.0];
    let mut group = c.benchmark_group("replan");
    let mut local = None;
    for (name, mode) in [
        ("full_replan_lattice_3200_triangles", LocalMapMode::Lattice),
        ("full_replan_remesh_3200_triangles", LocalMapMode::Remesh),
    ] {
        let options = LocalMapOptions {
            mode,
            ..LocalMapOptions::default()
        };
        let mut planner = DynamicPlanner::new(&scene, options).expect("reference scene");
        planner.set_obstacle(0, obstacle.clone());
        let plan = planner.replan(robot).expect("replan");
        assert_eq!(plan.path.status.as_str(), "reached_goal");
        assert_eq!(plan.method, mode);
        eprintln!(
            "{name}: {} triangles; one replan: {:?}",
            plan.triangles, plan.timings
        );
        local = local.or(plan.scene);
        group.bench_function(name, |b| {
            b.iter(|| black_box(planner.replan(black_box(robot)).expect("replan")))
        });
    }
    let local = local.expect("the remeshed replan keeps its scene");

    let mut planner =
        DynamicPlanner::new(&scene, LocalMapOptions::default()).expect("reference scene");
    planner.set_obstacle(0, obstacle.clone());
    let up: Vec<[f64; 2]> = (0..=20).map(|k| [3.7, 5.5 + 0.05 * k as f64]).collect();
    let route: Vec<[f64; 2]> = up.iter().chain(up.iter().rev()).copied().collect();
    for &p in &route {
        let plan = planner.replan(p).expect("replan");
        assert_eq!(plan.method, LocalMapMode::Lattice, "{p:?}");
        assert_eq!(plan.path.status.as_str(), "reached_goal", "{p:?}");
    }
    let mut k = 0;
    group.bench_function("full_replan_lattice_moving_5cm", |b| {
        b.iter(|| {
            k = (k + 1) % route.len();
            black_box(planner.replan(black_box(route[k])).expect("replan"))
        })
    });

    let mesh_options = local.mesh_options();
    group.bench_function("stage_mesh", |b| {
        b.iter(|| {
            let domain = Domain::new(&local.domain_spec(), &mesh_options).expect("domain");
            black_box(domain.mesh(&mesh_options).expect("mesh"))
        })
    });
    let domain = Domain::new(&local.domain_spec(), &mesh_options).expect("domain");
    let mesh = Arc::new(domain.mesh(&mesh_options).expect("mesh").0);
    let bcs = local.boundary_conditions();
    group.bench_function("stage_assemble", |b| {
        b.iter(|| {
            let assembler = Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default())
                .expect("assembler");
            black_box(assembler.assemble(&bcs).expect("system"))
        })
    });
    let assembler =
        Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("assembler");
    let system = assembler.assemble(&bcs).expect("system");
    // What the planner does (nested dissection, the accurate solve at this size) against
    // plain AMD + supernodal Cholesky.
    for (name, ordering, method) in [
        (
            "stage_factor_solve_planner",
            assembler.nested_dissection(),
            SolveMethod::Auto,
        ),
        (
            "stage_factor_solve_amd_cholesky",
            Ordering::Amd,
            SolveMethod::Cholesky,
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let solver =
                    Solver::with_method(&system, ordering.clone(), method).expect("factor");
                black_box(solver.potential(Arc::clone(&mesh), &system).expect("solve"))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, replan);
criterion_main!(benches);
