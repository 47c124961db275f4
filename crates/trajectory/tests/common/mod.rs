//! Hand-built test meshes: structured triangulated grids with cells removed as obstacles
//! and goals, and potentials on them.
#![allow(dead_code)] // each test binary uses a different part of this module

use harmonic_mesh::{BoundaryTag, Mesh, Point};

/// What a grid cell is.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Cell {
    Free,
    Obstacle(u32),
    Goal(u32),
}

/// A grid of `nx × ny` square cells of side `h` with origin (0, 0).
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub h: f64,
    pub cells: Vec<Cell>,
}

impl Grid {
    pub fn new(nx: usize, ny: usize, h: f64) -> Self {
        Grid {
            nx,
            ny,
            h,
            cells: vec![Cell::Free; nx * ny],
        }
    }
    /// Marks the cells whose centres lie in `[x0, x1] × [y0, y1]`.
    pub fn mark(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, c: Cell) {
        for j in 0..self.ny {
            for i in 0..self.nx {
                let (cx, cy) = ((i as f64 + 0.5) * self.h, (j as f64 + 0.5) * self.h);
                if cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1 {
                    self.cells[j * self.nx + i] = c;
                }
            }
        }
    }
    pub fn cell(&self, i: isize, j: isize) -> Option<Cell> {
        if i < 0 || j < 0 || i as usize >= self.nx || j as usize >= self.ny {
            None
        } else {
            Some(self.cells[j as usize * self.nx + i as usize])
        }
    }
    /// The cell holding `p` (None outside).
    pub fn cell_at(&self, p: Point) -> Option<Cell> {
        let i = (p.x / self.h).floor() as isize;
        let j = (p.y / self.h).floor() as isize;
        self.cell(i, j)
    }
    /// Triangulates the free cells (each split along alternating diagonals so the mesh is
    /// not all one way) and tags their boundary edges.
    pub fn mesh(&self) -> Mesh {
        let vid = |i: usize, j: usize| (j * (self.nx + 1) + i) as u32;
        let mut vertices = Vec::new();
        for j in 0..=self.ny {
            for i in 0..=self.nx {
                vertices.push(Point::new(i as f64 * self.h, j as f64 * self.h));
            }
        }
        let mut triangles = Vec::new();
        let mut boundary = Vec::new();
        for j in 0..self.ny {
            for i in 0..self.nx {
                if self.cells[j * self.nx + i] != Cell::Free {
                    continue;
                }
                let (a, b, c, d) = (vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1));
                if (i + j) % 2 == 0 {
                    triangles.push([a, b, c]);
                    triangles.push([a, c, d]);
                } else {
                    triangles.push([a, b, d]);
                    triangles.push([b, c, d]);
                }
                let (ii, jj) = (i as isize, j as isize);
                for (edge, nb) in [
                    ((a, b), self.cell(ii, jj - 1)),
                    ((b, c), self.cell(ii + 1, jj)),
                    ((c, d), self.cell(ii, jj + 1)),
                    ((d, a), self.cell(ii - 1, jj)),
                ] {
                    let tag = match nb {
                        None => BoundaryTag::Wall,
                        Some(Cell::Free) => continue,
                        Some(Cell::Obstacle(k)) => BoundaryTag::Obstacle(k),
                        Some(Cell::Goal(g)) => BoundaryTag::Goal(g),
                    };
                    boundary.push((edge.0, edge.1, tag));
                }
            }
        }
        // Drop vertices no triangle uses? Keep them: from_parts accepts isolated vertices.
        Mesh::from_parts(vertices, triangles, &boundary).expect("grid mesh is valid")
    }
}

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
    for _ in 0..sweeps {
        for i in 0..n {
            if fixed[i].is_some() || diag[i] == 0.0 {
                continue;
            }
            let s: f64 = rows[i].iter().map(|&(j, k)| k * psi[j as usize]).sum();
            psi[i] = -s / diag[i];
        }
    }
    psi
}

/// A tiny deterministic generator (xorshift) so tests need no extra dependency.
pub struct Rng(pub u64);
impl Rng {
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
