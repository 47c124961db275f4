//! Helpers of the trajectory tests on `harmonic_fixtures` grids (cells removed as obstacles
//! and goals): potentials solved without the FEM crate, nodal gradients, and grid queries
//! (segments against obstacle cells, clearance, random free points).
#![allow(dead_code)] // each test binary uses a different part of this module

use harmonic_fixtures::{Cell, Grid, Rng};
use harmonic_mesh::{BoundaryTag, Mesh, Point};

/// Solves the discrete Laplace problem on the mesh (P1 stiffness, Gauss–Seidel) with ψ = 1 on
/// goal vertices and ψ = 0 on wall and obstacle vertices; returns ψ (increases toward goals).
pub fn laplace_psi(mesh: &Mesh, sweeps: usize) -> Vec<f64> {
    let n = mesh.vertices().len();
    let mut rows: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n];
    let mut diag = vec![0.0; n];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let p = mesh.triangle_points(t as u32);
        let area = mesh.triangle_area(t as u32);
        for a in 0..3 {
            for b in 0..3 {
                let ea = p[(a + 2) % 3] - p[(a + 1) % 3];
                let eb = p[(b + 2) % 3] - p[(b + 1) % 3];
                let k = ea.dot(&eb) / (4.0 * area);
                if a == b {
                    diag[tri[a] as usize] += k;
                } else {
                    rows[tri[a] as usize].push((tri[b], k));
                }
            }
        }
    }
    let fixed: Vec<Option<f64>> = mesh
        .vertex_tags()
        .iter()
        .map(|t| match t {
            Some(BoundaryTag::Goal(_)) => Some(1.0),
            Some(_) => Some(0.0),
            None => None,
        })
        .collect();
    let mut psi: Vec<f64> = fixed.iter().map(|f| f.unwrap_or(0.0)).collect();
    // Successive over-relaxation; the tests' meshes are small.
    let omega = 1.9;
    for _ in 0..sweeps {
        for i in 0..n {
            if fixed[i].is_some() || diag[i] == 0.0 {
                continue;
            }
            let s: f64 = rows[i].iter().map(|&(j, k)| k * psi[j as usize]).sum();
            psi[i] += omega * (-s / diag[i] - psi[i]);
        }
    }
    psi
}

/// Whether the open segment `a → b` passes through the open interior of the axis-aligned
/// rectangle `[x0, x1] × [y0, y1]` (touching its boundary is allowed). Liang–Barsky clipping.
pub fn segment_enters_rect(a: Point, b: Point, x0: f64, y0: f64, x1: f64, y1: f64) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - x0),
        (d.x, x1 - a.x),
        (-d.y, a.y - y0),
        (d.y, y1 - a.y),
    ] {
        if p == 0.0 {
            if q <= 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t1 - t0 <= 1e-12 {
        return false;
    }
    // The clipped piece lies in the closed rectangle; it enters the interior unless it runs
    // along the boundary.
    let m = a + d * (0.5 * (t0 + t1));
    m.x > x0 && m.x < x1 && m.y > y0 && m.y < y1
}

/// Queries the trajectory tests ask of a grid scene (corner at the origin, as they build it).
pub trait GridQueries {
    /// Whether segment `a → b` passes through the interior of an obstacle cell.
    fn segment_hits_obstacle(&self, a: Point, b: Point) -> bool;
    /// `count` random points in free cells.
    fn random_free(&self, rng: &mut Rng, count: usize) -> Vec<Point>;
    /// Distance from `p` to the nearest obstacle cell or the outer wall.
    fn clearance(&self, p: Point) -> f64;
}

impl GridQueries for Grid {
    fn segment_hits_obstacle(&self, a: Point, b: Point) -> bool {
        (0..self.ny).any(|j| {
            (0..self.nx).any(|i| {
                matches!(self.cells[j * self.nx + i], Cell::Obstacle(_))
                    && segment_enters_rect(
                        a,
                        b,
                        i as f64 * self.h,
                        j as f64 * self.h,
                        (i + 1) as f64 * self.h,
                        (j + 1) as f64 * self.h,
                    )
            })
        })
    }

    fn random_free(&self, rng: &mut Rng, count: usize) -> Vec<Point> {
        let w = self.nx as f64 * self.h;
        let hgt = self.ny as f64 * self.h;
        let mut out = Vec::new();
        while out.len() < count {
            let p = Point::new(rng.next_f64() * w, rng.next_f64() * hgt);
            if self.cell_at(p) == Some(Cell::Free) {
                out.push(p);
            }
        }
        out
    }

    fn clearance(&self, p: Point) -> f64 {
        let (w, hgt) = (self.nx as f64 * self.h, self.ny as f64 * self.h);
        let mut d = p.x.min(w - p.x).min(p.y).min(hgt - p.y);
        for j in 0..self.ny {
            for i in 0..self.nx {
                if let Cell::Obstacle(_) = self.cells[j * self.nx + i] {
                    let (x0, y0) = (i as f64 * self.h, j as f64 * self.h);
                    let dx = (x0 - p.x).max(p.x - x0 - self.h).max(0.0);
                    let dy = (y0 - p.y).max(p.y - y0 - self.h).max(0.0);
                    d = d.min(dx.hypot(dy));
                }
            }
        }
        d
    }
}

/// Recovered nodal gradients of `values`: area-weighted averages of the triangle gradients.
pub fn nodal_gradients(mesh: &Mesh, values: &[f64]) -> Vec<harmonic_mesh::Vector> {
    let mut g = vec![harmonic_mesh::Vector::zeros(); mesh.vertices().len()];
    let mut w = vec![0.0; mesh.vertices().len()];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = mesh.triangle_points(t as u32);
        let [fa, fb, fc] = tri.map(|v| values[v as usize]);
        let area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        let gx = (fa * (b.y - c.y) + fb * (c.y - a.y) + fc * (a.y - b.y)) / area2;
        let gy = (fa * (c.x - b.x) + fb * (a.x - c.x) + fc * (b.x - a.x)) / area2;
        for &v in tri {
            g[v as usize] += harmonic_mesh::Vector::new(gx, gy) * area2;
            w[v as usize] += area2;
        }
    }
    g.iter()
        .zip(w)
        .map(|(g, w)| if w > 0.0 { g / w } else { *g })
        .collect()
}
