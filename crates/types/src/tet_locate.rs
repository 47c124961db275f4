//! Point location's fallback: a uniform bucket grid over the mesh, each cell listing the
//! tetrahedra whose bounding boxes overlap it (built on first use).

use crate::tet_mesh::TetMesh;
use crate::{Point3 as Point, Vector3 as Vector};

/// The bucket grid.
#[derive(Debug)]
pub(crate) struct Locator {
    lo: Point,
    cell: f64,
    n: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Locator {
    pub(crate) fn new(mesh: &TetMesh) -> Self {
        let (lo, hi) = mesh.bounds();
        let tets = mesh.tetrahedra().len().max(1);
        let extent = (hi - lo).sup(&Vector::repeat(1e-300));
        // About eight tetrahedra per cell: each is listed in fewer cells than at two, which
        // is what the build pays for; a lookup (the fallback of a walk) checks a few more.
        let cell = (extent.product() * 8.0 / tets as f64)
            .cbrt()
            .max(extent.max() / 1024.0);
        let n = [0, 1, 2].map(|a| ((extent[a] / cell).ceil() as usize).clamp(1, 1024));
        let cells = n[0] * n[1] * n[2];
        let range = |t: u32| {
            let p = mesh.tet_points(t);
            let (mut a, mut b) = (p[0], p[0]);
            for q in &p[1..] {
                a = a.inf(q);
                b = b.sup(q);
            }
            // Cell indices fit 16 bits (at most 1024 cells an axis).
            // Truncation is the floor of a non-negative number (without SSE4.1 `floor` is a
            // library call, and this runs six times per tetrahedron).
            let idx = |x: f64, axis: usize| {
                ((((x - lo[axis]) / cell).max(0.0)) as usize).min(n[axis] - 1) as u16
            };
            [0, 1, 2].map(|axis| (idx(a[axis], axis), idx(b[axis], axis)))
        };
        // Each tetrahedron's cell range once (in parallel: it is most of the work), then
        // the counts and the fill in tetrahedron order, so each cell lists its tetrahedra
        // ascending at any thread count.
        use rayon::prelude::*;
        let ranges: Vec<[(u16, u16); 3]> = (0..mesh.tetrahedra().len() as u32)
            .into_par_iter()
            .map(range)
            .collect();
        let visit = |r: &[(u16, u16); 3], f: &mut dyn FnMut(usize)| {
            for k in r[2].0 as usize..=r[2].1 as usize {
                for j in r[1].0 as usize..=r[1].1 as usize {
                    for i in r[0].0 as usize..=r[0].1 as usize {
                        f(i + n[0] * (j + n[1] * k));
                    }
                }
            }
        };
        let mut count = vec![0u32; cells + 1];
        for r in &ranges {
            visit(r, &mut |c| count[c + 1] += 1);
        }
        for c in 0..cells {
            count[c + 1] += count[c];
        }
        let mut next = count.clone();
        let mut items = vec![0u32; count[cells] as usize];
        for (t, r) in ranges.iter().enumerate() {
            visit(r, &mut |c| {
                items[next[c] as usize] = t as u32;
                next[c] += 1;
            });
        }
        Locator {
            lo,
            cell,
            n,
            start: count,
            items,
        }
    }

    pub(crate) fn locate(&self, mesh: &TetMesh, p: &Point) -> Option<u32> {
        let mut idx = [0usize; 3];
        for a in 0..3 {
            let x = ((p[a] - self.lo[a]) / self.cell).floor();
            if x < -1.0 || x > self.n[a] as f64 {
                return None;
            }
            idx[a] = (x.max(0.0) as usize).min(self.n[a] - 1);
        }
        let c = idx[0] + self.n[0] * (idx[1] + self.n[1] * idx[2]);
        let items = &self.items[self.start[c] as usize..self.start[c + 1] as usize];
        // The tetrahedron whose smallest barycentric coordinate is largest (robust on faces).
        let mut best: Option<(f64, u32)> = None;
        for &t in items {
            let m = mesh
                .barycentric(t, p)
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            if best.is_none_or(|(b, _)| m > b) {
                best = Some((m, t));
            }
        }
        best.filter(|&(m, _)| m >= -1e-12).map(|(_, t)| t)
    }
}
