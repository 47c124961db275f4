//! Checks shared by the mesh crate's integration tests: the invariants every mesh must
//! satisfy, and whether a boundary edge lies on an input ring. Scenes, rectangles and areas
//! are `harmonic_fixtures`'s, distances `harmonic_mesh::geom`'s.
#![allow(dead_code)] // each test binary uses a subset

use harmonic_mesh::geom::{point_segment_distance, ring_edges};
use harmonic_mesh::{MIN_VERTEX_BUDGET, Mesh, MeshOptions, MeshReport, Point};

/// Whether the segment `ab` lies on one edge of the closed `ring` (both ends within 1e-9 of
/// it).
pub fn on_ring_edge(a: Point, b: Point, ring: &[Point]) -> bool {
    ring_edges(ring).any(|(u, v)| {
        point_segment_distance(a, u, v) < 1e-9 && point_segment_distance(b, u, v) < 1e-9
    })
}

/// Checks the invariants every mesh must satisfy, returning a description of the first failure.
pub fn check_invariants(mesh: &Mesh, expected_area: f64, rel_tol: f64) -> Result<(), String> {
    check_invariants_with_bridges(mesh, expected_area, rel_tol, 0)
}

/// Like [`check_invariants`], with `bridges` interior edges joining two boundary vertices allowed.
pub fn check_invariants_with_bridges(
    mesh: &Mesh,
    expected_area: f64,
    rel_tol: f64,
    bridges: usize,
) -> Result<(), String> {
    let q = mesh.quality();
    let rel = (q.area - expected_area).abs() / expected_area;
    if rel > rel_tol {
        return Err(format!(
            "area {} vs {} (rel {rel:e})",
            q.area, expected_area
        ));
    }
    // Euler per component: V - E + T = 1 - holes; summed: V - E + T = C - H (plus pinches).
    let v = mesh.vertices().len() as i64;
    let t = mesh.triangles().len() as i64;
    let nb = mesh.boundary_edges().len() as i64;
    let e = (3 * t + nb) / 2;
    if (3 * t + nb) % 2 != 0 {
        return Err("odd edge count".into());
    }
    // Vertices where the boundary touches itself count once per extra wedge of free space.
    let mut leaving = vec![0i64; mesh.vertices().len()];
    for b in mesh.boundary_edges() {
        leaving[b.vertices[0] as usize] += 1;
    }
    let pinch: i64 = leaving.iter().map(|&w| (w - 1).max(0)).sum();
    if pinch != q.pinch_vertices as i64 {
        return Err(format!(
            "{pinch} pinch wedges, report says {}",
            q.pinch_vertices
        ));
    }
    if v - e + t + pinch != q.components as i64 - q.holes as i64 {
        return Err(format!(
            "Euler: V-E+T+P = {} but C-H = {}",
            v - e + t + pinch,
            q.components as i64 - q.holes as i64
        ));
    }
    for (t, tri) in mesh.triangles().iter().enumerate() {
        if mesh.triangle_area(t as u32) <= 0.0 {
            return Err(format!("triangle {t} {tri:?} not CCW"));
        }
    }
    // No interior edge joins two boundary vertices, ears aside (MeshOptions::bridges).
    let mut found = 0;
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            let u = mesh.neighbors()[t][k];
            // An ear: the other two edges of the triangle are boundary edges.
            let ear = |s: usize, j: usize| {
                let n = mesh.neighbors()[s];
                n[(j + 1) % 3] == harmonic_mesh::NO_NEIGHBOR
                    && n[(j + 2) % 3] == harmonic_mesh::NO_NEIGHBOR
            };
            if u != harmonic_mesh::NO_NEIGHBOR
                && mesh.vertex_tags()[a].is_some()
                && mesh.vertex_tags()[b].is_some()
            {
                let j = mesh.neighbors()[u as usize]
                    .iter()
                    .position(|&x| x == t as u32)
                    .unwrap();
                if !ear(t, k) && !ear(u as usize, j) {
                    found += 1;
                }
            }
        }
    }
    // Each interior edge is seen from both sides.
    if found != 2 * bridges {
        return Err(format!(
            "{} interior edges join two boundary vertices, {bridges} reported",
            found / 2
        ));
    }
    Ok(())
}

/// Refinement finished, or stopped at its vertex budget (bounded work for any input) and
/// only there: where free space has a sliver far narrower than the target edge that the
/// triangle estimate does not see (a box edge 2e-4 from the wall asks for thousands of
/// vertices along it at 30°). The mesh must be valid either way.
pub fn refined_or_budget_spent(report: &MeshReport, opts: &MeshOptions) -> Result<(), String> {
    let cap = (opts.max_triangles / 2 + 1).min(
        report
            .estimated_triangles
            .saturating_mul(2)
            .max(MIN_VERTEX_BUDGET),
    );
    if report.refinement_complete || report.added_vertices >= cap {
        Ok(())
    } else {
        Err(format!(
            "refinement stopped at {} added vertices, below its budget of {cap}",
            report.added_vertices
        ))
    }
}
