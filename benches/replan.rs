//! Dynamic replanning on a local map of about 3200 triangles (Garrido et al. 2010, §6: a
//! 40 × 40 map "in less than one second"): one full replan — local scene, mesh, assembly,
//! factorisation, solve and trace — from a point of the reference scene with a sensed
//! obstacle in the window, and the stages on their own.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_planner::Scene;
use harmonic_planner::dynamic::{DynamicPlanner, LocalMapOptions};
use harmonic_planner::fem::{Assembler, AssemblyOptions, SolveMethod, Solver};
use harmonic_planner::mesh::Domain;
use harmonic_planner::solver::Ordering;

fn reference() -> Scene {
    Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/meshes/reference.json"
    ))
    .expect("the reference scene is valid")
}

fn replan(c: &mut Criterion) {
    let scene = reference();
    let mut planner =
        DynamicPlanner::new(&scene, LocalMapOptions::default()).expect("reference scene");
    planner.set_obstacle(0, vec![[4.0, 4.6], [4.5, 4.6], [4.5, 5.1], [4.0, 5.1]]);
    let robot = [3.7, 6.0];
    let plan = planner.replan(robot).expect("replan");
    assert_eq!(plan.path.status, "reached_goal");
    eprintln!(
        "local map: {} triangles; one replan: {:?}",
        plan.triangles, plan.timings
    );
    let local = plan.scene.clone();
    let mut group = c.benchmark_group("replan");
    group.bench_function("full_replan_3200_triangles", |b| {
        b.iter(|| black_box(planner.replan(black_box(robot)).expect("replan")))
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
