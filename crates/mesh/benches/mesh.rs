//! Meshing the reference scene at the peers' sizes (Triangle `pq30a<A>`: 3k, 30k, 300k, 1M
//! triangles for A = 0.045, 0.0044, 0.00044, 0.000132), with and without the lattice prefill.
//!
//! `cargo bench -p harmonic-mesh --bench mesh`

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Point, Shape};
use std::hint::black_box;

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
    vec![p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y1)]
}

fn reference() -> DomainSpec {
    DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 10.0),
        obstacles: vec![
            Shape::Polygon(rect(2.0, 2.0, 3.0, 8.0)),
            Shape::Polygon(rect(5.0, 4.0, 9.0, 5.0)),
            Shape::Polygon(vec![p(4.0, 7.0), p(7.0, 7.0), p(6.0, 9.0)]),
            Shape::Polygon(vec![
                p(5.5, 1.0),
                p(7.0, 1.0),
                p(7.0, 3.0),
                p(6.5, 3.0),
                p(6.5, 1.5),
                p(5.5, 1.5),
            ]),
            Shape::Polygon(vec![
                p(3.6, 2.4),
                p(4.6, 2.2),
                p(4.9, 3.1),
                p(4.2, 3.7),
                p(3.5, 3.2),
            ]),
        ],
        goals: vec![GoalShape::Circle {
            center: p(8.5, 1.5),
            radius: 0.15,
        }],
        robot_radius: 0.0,
    }
}

fn bench(c: &mut Criterion) {
    let spec = reference();
    let sizes = [
        ("3k", 0.045),
        ("30k", 0.0044),
        ("300k", 0.00044),
        ("1M", 0.000132),
    ];
    let mut group = c.benchmark_group("mesh");
    group.sample_size(10);
    for (name, max_area) in sizes {
        for prefill in [false, true] {
            let opts = MeshOptions {
                max_area: Some(max_area),
                prefill,
                ..MeshOptions::default()
            };
            let id = format!("{name}{}", if prefill { "_lattice" } else { "" });
            group.bench_function(id, |b| {
                b.iter(|| {
                    let domain = Domain::new(black_box(&spec), &opts).expect("valid scene");
                    domain.mesh(&opts).expect("mesh")
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
