//! Triangles crossed per second by the exact tracer (and steps per second of the smooth one)
//! on 1M-triangle meshes: a structured 1000 × 500 grid (cells split into two triangles along
//! alternating diagonals) with a square goal hole carrying the harmonic log potential of the
//! goal, and the bundled reference scene meshed by `Domain` with ψ solved by `harmonic_fem`.

use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use harmonic_fem::{BoundaryConditions, solve_potential};
use harmonic_fixtures::{Cell, Grid, plane_scene};
use harmonic_mesh::{Domain, Mesh, MeshOptions, Point};
use harmonic_trajectory::{
    ExactOptions, Field, Locate, P1Field, SmoothOptions, SmoothP1Field, trace_exact, trace_smooth,
};

const NX: usize = 1000;
const NY: usize = 500;
const GOAL: (usize, usize) = (900, 250);

fn grid_mesh() -> Mesh {
    let mut grid = Grid::new(NX, NY, 1.0);
    grid.mark_cells(
        GOAL.0 - 1..GOAL.0 + 2,
        GOAL.1 - 1..GOAL.1 + 2,
        Cell::Goal(0),
    );
    grid.mesh()
}

fn bench(c: &mut Criterion) {
    let mesh = grid_mesh();
    let g = Point::new(GOAL.0 as f64 + 0.5, GOAL.1 as f64 + 0.5);
    // ψ = 1 − ln(r / r₀) / ln(R / r₀): harmonic, 1 on the goal, increasing toward it.
    let (r0, big_r) = (1.5f64, 1200.0f64);
    let psi: Vec<f64> = mesh
        .vertices()
        .iter()
        .map(|p| 1.0 - ((p - g).norm().max(r0) / r0).ln() / (big_r / r0).ln())
        .collect();
    let field = P1Field::ascending(&mesh, &psi).expect("one value per vertex");
    let starts: Vec<Point> = (0..16)
        .map(|k| Point::new(10.3 + 37.1 * k as f64, 5.7 + 30.9 * k as f64))
        .collect();
    let opts = ExactOptions::default();
    let crossed: usize = starts
        .iter()
        .map(|&s| trace_exact(&field, s, &opts).cells_crossed)
        .sum();
    let mut group = c.benchmark_group("trace");
    group.sample_size(20);
    group.throughput(Throughput::Elements(crossed as u64));
    group.bench_function("exact_1M_triangles", |b| {
        b.iter(|| {
            starts
                .iter()
                .map(|&s| trace_exact(&field, s, &opts).cells_crossed)
                .sum::<usize>()
        })
    });
    let sopts = SmoothOptions::for_scale(1000.0);
    let smooth_crossed: usize = starts
        .iter()
        .map(|&s| trace_smooth(&field, s, &sopts).map_or(0, |p| p.points.len()))
        .sum();
    group.throughput(Throughput::Elements(smooth_crossed as u64));
    group.bench_function("smooth_1M_triangles_steps", |b| {
        b.iter(|| {
            starts
                .iter()
                .map(|&s| trace_smooth(&field, s, &sopts).map_or(0, |p| p.points.len()))
                .sum::<usize>()
        })
    });
    group.finish();
}

fn bench_reference(c: &mut Criterion) {
    let opts = MeshOptions {
        max_area: Some(1.5e-4),
        ..MeshOptions::default()
    };
    let domain =
        Domain::new(&plane_scene("reference").spec, &opts).expect("the reference scene is valid");
    let (mesh, _) = domain.mesh(&opts).expect("the reference scene meshes");
    let triangles = mesh.triangles().len();
    let potential = solve_potential(Arc::new(mesh), &BoundaryConditions::default())
        .expect("the reference scene solves");
    let mesh: &Mesh = potential.mesh();
    let field = P1Field::ascending(mesh, potential.psi()).expect("one value per vertex");
    let smooth = SmoothP1Field::ascending(mesh, potential.psi(), potential.nodal_gradients_psi())
        .expect("one gradient per vertex");
    // Free starts spread over the scene.
    let starts: Vec<Point> = (0..64)
        .map(|k| Point::new(0.3 + 0.61 * (k % 16) as f64, 0.4 + 2.9 * (k / 16) as f64))
        .filter(|&p| matches!(field.locate(p, None), Locate::Inside(_)))
        .collect();
    let opts = ExactOptions::default();
    let crossed: usize = starts
        .iter()
        .map(|&s| trace_exact(&field, s, &opts).cells_crossed)
        .sum();
    eprintln!(
        "reference scene: {triangles} triangles, {} starts, {crossed} triangles crossed per batch",
        starts.len()
    );
    let mut group = c.benchmark_group("trace");
    group.sample_size(10);
    group.throughput(Throughput::Elements(crossed as u64));
    group.bench_function("exact_reference_1M_triangles", |b| {
        b.iter(|| {
            starts
                .iter()
                .map(|&s| trace_exact(&field, s, &opts).cells_crossed)
                .sum::<usize>()
        })
    });
    let sopts = SmoothOptions::for_scale(10.0);
    let steps: usize = starts
        .iter()
        .map(|&s| trace_smooth(&smooth, s, &sopts).map_or(0, |p| p.points.len()))
        .sum();
    group.throughput(Throughput::Elements(steps as u64));
    group.bench_function("smooth_reference_1M_triangles_steps", |b| {
        b.iter(|| {
            starts
                .iter()
                .map(|&s| trace_smooth(&smooth, s, &sopts).map_or(0, |p| p.points.len()))
                .sum::<usize>()
        })
    });
    group.finish();
}

criterion_group!(benches, bench, bench_reference);
criterion_main!(benches);
