//! P1 on a structured grid of right triangles, assembled without a mesh.
//!
//! A grid of `nx × ny` square cells of side `h`, each split into two right triangles along the
//! same diagonal (cell `(i, j)`'s lower-right triangle `(i, j), (i+1, j), (i+1, j+1)` and its
//! upper-left one `(i, j), (i+1, j+1), (i, j+1)`), has the 5-point stencil as its P1 stiffness:
//! a triangle gives each of its two legs the cotangent weight `cot 45° / 2 = 1/2` and its
//! hypotenuse `cot 90° / 2 = 0`, so an axis edge weighs half the number of its kept triangles
//! (1 inside, 1/2 along a removed region) and a diagonal edge nothing, whatever `h`.
//!
//! [`StructuredGrid::system`] builds the reduced Dirichlet system of such a grid from a role per
//! vertex ([`VertexRole`]): unknown, prescribed (its value lifted to the right-hand side) or
//! removed (its triangles are cut out, so the unknowns around it see a homogeneous Neumann
//! boundary, as do those on the grid's border). The system comes as the solver's [`MMatrix`]:
//! off-diagonal magnitudes and row excesses (the weights of the edges to prescribed vertices),
//! exact sums of halves, ready for the entrywise-accurate [`harmonic_solver::AccurateLdlt`].
//! This is what [`crate::Assembler`] computes on the mesh of the kept triangles, without building
//! that mesh, its pattern or its cotangents: a background lattice with obstacles cut in by
//! blocking vertices (`harmonic-dynamic`'s local planner) assembles a new system per replan.
//!
//! ```
//! use harmonic_fem::{StructuredGrid, VertexRole};
//! // 2 × 2 cells: the centre vertex is the only unknown, its four neighbours held at 0 and 1.
//! let grid = StructuredGrid::new(2, 2, 0.5);
//! let mut roles = vec![VertexRole::Prescribed(0.0); grid.vertex_count()];
//! roles[grid.vertex(1, 1)] = VertexRole::Unknown;
//! roles[grid.vertex(0, 1)] = VertexRole::Prescribed(1.0);
//! roles[grid.vertex(2, 1)] = VertexRole::Prescribed(1.0);
//! let system = grid.system(&roles, None)?;
//! assert_eq!(system.unknowns(), &[grid.vertex(1, 1)]);
//! assert_eq!(system.matrix().excess(), &[4.0]);
//! assert_eq!(system.rhs(), &[2.0]);
//! # Ok::<(), harmonic_fem::FemError>(())
//! ```

use harmonic_solver::{MMatrix, Ordering, SymmetricCsc};

use crate::FemError;

/// What a grid vertex is in one system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VertexRole {
    /// Solved for.
    Unknown,
    /// Held at this value, which moves to the right-hand side.
    Prescribed(f64),
    /// Cut out with its triangles: a triangle is kept when none of its vertices is removed.
    Removed,
}

/// A grid of `nx × ny` square cells of side `h` split into right triangles (see the module
/// documentation), its lower-left vertex at the origin. Vertices are numbered row by row from
/// the lower left (`vertex(i, j) = j (nx + 1) + i`), triangles cell by cell in the same order,
/// two per cell (`2 (j nx + i)` the lower-right one, `+ 1` the upper-left one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StructuredGrid {
    nx: usize,
    ny: usize,
    h: f64,
}

/// The reduced system of a [`StructuredGrid`] for one set of [`VertexRole`]s.
#[derive(Clone, Debug)]
pub struct StructuredSystem {
    matrix: MMatrix,
    rhs: Vec<f64>,
    unknowns: Vec<usize>,
}

impl StructuredSystem {
    /// The unknowns' M-matrix: off-diagonal magnitudes (the axis edges' weights between
    /// unknowns) and row excesses (the weights of the edges to prescribed vertices).
    pub fn matrix(&self) -> &MMatrix {
        &self.matrix
    }

    /// The right-hand side: per unknown, the weighted sum of its prescribed neighbours' values.
    pub fn rhs(&self) -> &[f64] {
        &self.rhs
    }

    /// The grid vertex of each unknown, in the system's numbering.
    pub fn unknowns(&self) -> &[usize] {
        &self.unknowns
    }

    /// The matrix, the right-hand side and the unknowns' grid vertices.
    pub fn into_parts(self) -> (MMatrix, Vec<f64>, Vec<usize>) {
        (self.matrix, self.rhs, self.unknowns)
    }
}

impl StructuredGrid {
    /// A grid of `nx × ny` cells of side `h`.
    ///
    /// # Panics
    /// If `nx` or `ny` is zero or `h` is not a positive finite number.
    pub fn new(nx: usize, ny: usize, h: f64) -> StructuredGrid {
        assert!(
            nx > 0 && ny > 0,
            "a structured grid needs at least one cell"
        );
        assert!(h.is_finite() && h > 0.0, "cell side {h} is not positive");
        StructuredGrid { nx, ny, h }
    }

    /// Cells along x.
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Cells along y.
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// Cell side.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Number of vertices, `(nx + 1)(ny + 1)`.
    pub fn vertex_count(&self) -> usize {
        (self.nx + 1) * (self.ny + 1)
    }

    /// Number of triangles, `2 nx ny`.
    pub fn triangle_count(&self) -> usize {
        2 * self.nx * self.ny
    }

    /// The number of vertex `(i, j)` (column `i ≤ nx`, row `j ≤ ny`).
    pub fn vertex(&self, i: usize, j: usize) -> usize {
        j * (self.nx + 1) + i
    }

    /// Column and row `(i, j)` of vertex `v`.
    pub fn vertex_ij(&self, v: usize) -> (usize, usize) {
        (v % (self.nx + 1), v / (self.nx + 1))
    }

    /// Position of vertex `v`, `(i h, j h)`.
    pub fn position(&self, v: usize) -> [f64; 2] {
        let (i, j) = self.vertex_ij(v);
        [i as f64 * self.h, j as f64 * self.h]
    }

    /// The (up to four) axis neighbours of vertex `v`: below, left, right, above.
    pub fn vertex_neighbors(&self, v: usize) -> impl Iterator<Item = usize> + use<> {
        let side = self.nx + 1;
        let (i, j) = self.vertex_ij(v);
        [
            (j > 0).then(|| v - side),
            (i > 0).then(|| v - 1),
            (i < self.nx).then(|| v + 1),
            (j < self.ny).then(|| v + side),
        ]
        .into_iter()
        .flatten()
    }

    /// Vertices of triangle `t`, counter-clockwise: cell `(i, j)`'s lower-right triangle is
    /// `(i, j), (i+1, j), (i+1, j+1)`, its upper-left `(i, j), (i+1, j+1), (i, j+1)`.
    pub fn triangle_vertices(&self, t: usize) -> [usize; 3] {
        let side = self.nx + 1;
        let cell = t / 2;
        let (i, j) = (cell % self.nx, cell / self.nx);
        let v00 = j * side + i;
        let (v10, v01, v11) = (v00 + 1, v00 + side, v00 + side + 1);
        if t.is_multiple_of(2) {
            [v00, v10, v11]
        } else {
            [v00, v11, v01]
        }
    }

    /// The triangles across the edges opposite each vertex of triangle `t` (in the order of
    /// [`triangle_vertices`](Self::triangle_vertices); `None` at the grid's border).
    pub fn triangle_neighbors(&self, t: usize) -> [Option<usize>; 3] {
        let (nx, ny) = (self.nx, self.ny);
        let cell = t / 2;
        let (i, j) = (cell % nx, cell / nx);
        let lower = |i: usize, j: usize| 2 * (j * nx + i);
        if t.is_multiple_of(2) {
            // Opposite v00: the right side; opposite v10: the diagonal; opposite v11: the bottom.
            [
                (i + 1 < nx).then(|| lower(i + 1, j) + 1),
                Some(t + 1),
                (j > 0).then(|| lower(i, j - 1) + 1),
            ]
        } else {
            // Opposite v00: the top; opposite v11: the left side; opposite v01: the diagonal.
            [
                (j + 1 < ny).then(|| lower(i, j + 1)),
                (i > 0).then(|| lower(i - 1, j)),
                Some(t - 1),
            ]
        }
    }

    /// The triangle holding the point `(x, y)` given in cell units (`x = 1.5` is the middle of
    /// the second column of cells), `None` outside the grid. Points on the diagonal belong to
    /// the lower-right triangle, those on the grid's far sides to the last cells.
    pub fn triangle_at(&self, x: f64, y: f64) -> Option<usize> {
        let (nx, ny) = (self.nx as f64, self.ny as f64);
        if !(x >= 0.0 && y >= 0.0 && x <= nx && y <= ny) {
            return None;
        }
        let (i, j) = (
            (x.floor() as usize).min(self.nx - 1),
            (y.floor() as usize).min(self.ny - 1),
        );
        // Below the diagonal (x − i ≥ y − j): the lower-right triangle.
        let upper = y - j as f64 > x - i as f64;
        Some(2 * (j * self.nx + i) + upper as usize)
    }

    /// A nested-dissection order (`perm[new] = old`) of all the grid's vertices for the
    /// 5-point graph, from their positions in cell units. Subsets of unknowns numbered in this
    /// order factor with little fill without an ordering of their own.
    pub fn nested_dissection(&self) -> Vec<usize> {
        let n = self.vertex_count();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(4 * n);
        col_ptr.push(0);
        for v in 0..n {
            row_idx.extend(self.vertex_neighbors(v));
            col_ptr.push(row_idx.len());
        }
        let nnz = row_idx.len();
        let pattern = SymmetricCsc::try_from_symmetric_pattern(n, col_ptr, row_idx, vec![0.0; nnz])
            .expect("the 5-point pattern is valid: sorted rows, mirrored by construction");
        let coords = (0..n).map(|v| {
            let (i, j) = self.vertex_ij(v);
            [i as f64, j as f64]
        });
        Ordering::NestedDissection {
            coords: coords.collect(),
        }
        .permutation(&pattern)
        .expect("one coordinate pair per grid vertex")
    }

    /// Whether triangle `t` is kept (none of its vertices removed).
    fn kept(&self, roles: &[VertexRole], t: usize) -> bool {
        self.triangle_vertices(t)
            .iter()
            .all(|&v| roles[v] != VertexRole::Removed)
    }

    /// The P1 weight of the axis edge from vertex `v` to its neighbour `u`: half the number
    /// of its kept triangles (0 for a diagonal or a non-adjacent pair).
    fn edge_weight(&self, roles: &[VertexRole], v: usize, u: usize) -> f64 {
        let (a, b) = (v.min(u), v.max(u));
        let (i, j) = self.vertex_ij(a);
        let lower = |i: usize, j: usize| 2 * (j * self.nx + i);
        // A horizontal edge (i, j)–(i+1, j) has cell (i, j)'s lower-right triangle above it
        // and cell (i, j−1)'s upper-left one below; a vertical edge (i, j)–(i, j+1) has cell
        // (i, j)'s upper-left triangle on its right and cell (i−1, j)'s lower-right on its left.
        let triangles = if b == a + 1 && i < self.nx {
            [
                (j < self.ny).then(|| lower(i, j)),
                (j > 0).then(|| lower(i, j - 1) + 1),
            ]
        } else if b == a + self.nx + 1 {
            [
                (i < self.nx).then(|| lower(i, j) + 1),
                (i > 0).then(|| lower(i - 1, j)),
            ]
        } else {
            return 0.0;
        };
        let kept = triangles
            .into_iter()
            .flatten()
            .filter(|&t| self.kept(roles, t))
            .count();
        0.5 * kept as f64
    }

    /// The reduced system for `roles` (one per vertex): its unknowns are the
    /// [`VertexRole::Unknown`] vertices, numbered as listed in `order` (which must list each of
    /// them once, e.g. in an elimination order the caller keeps) or else in vertex order.
    /// Column by column, the unknown's axis edges of nonzero weight to other unknowns become
    /// off-diagonal magnitudes (rows sorted), those to prescribed vertices add their weight to
    /// its excess and weight × value to its right-hand side, in the order below, left, right,
    /// above.
    ///
    /// An unknown all of whose triangles are removed has an empty row and column, and a
    /// connected set of unknowns with no prescribed neighbour a singular block: the
    /// factorisation reports them.
    pub fn system(
        &self,
        roles: &[VertexRole],
        order: Option<&[usize]>,
    ) -> Result<StructuredSystem, FemError> {
        let n = self.vertex_count();
        if roles.len() != n {
            return Err(FemError::LengthMismatch {
                what: "vertex roles of the structured grid",
                expected: n,
                got: roles.len(),
            });
        }
        let unknowns: Vec<usize> = match order {
            Some(order) => order.to_vec(),
            None => (0..n)
                .filter(|&v| roles[v] == VertexRole::Unknown)
                .collect(),
        };
        let m = unknowns.len();
        let bad_order = || {
            let count = roles.iter().filter(|&&r| r == VertexRole::Unknown).count();
            FemError::LengthMismatch {
                what: "order of the unknowns (each unknown vertex once, nothing else)",
                expected: count,
                got: m,
            }
        };
        let mut position = vec![u32::MAX; n];
        for (k, &v) in unknowns.iter().enumerate() {
            if v >= n || roles[v] != VertexRole::Unknown || position[v] != u32::MAX {
                return Err(bad_order());
            }
            position[v] = k as u32;
        }
        // Every listed vertex is a distinct unknown: all are listed when the counts agree.
        if order.is_some() && roles.iter().filter(|&&r| r == VertexRole::Unknown).count() != m {
            return Err(bad_order());
        }
        let mut col_ptr = Vec::with_capacity(m + 1);
        let mut row_idx = Vec::with_capacity(4 * m);
        let mut values = Vec::with_capacity(4 * m);
        let mut excess = vec![0.0; m];
        let mut rhs = vec![0.0; m];
        col_ptr.push(0);
        let mut column: Vec<(usize, f64)> = Vec::with_capacity(4);
        for (c, &v) in unknowns.iter().enumerate() {
            column.clear();
            for u in self.vertex_neighbors(v) {
                let w = self.edge_weight(roles, v, u);
                if w == 0.0 {
                    continue;
                }
                match roles[u] {
                    VertexRole::Unknown => column.push((position[u] as usize, w)),
                    VertexRole::Prescribed(value) => {
                        excess[c] += w;
                        rhs[c] += w * value;
                    }
                    VertexRole::Removed => {}
                }
            }
            column.sort_unstable_by_key(|&(r, _)| r);
            row_idx.extend(column.iter().map(|&(r, _)| r));
            values.extend(column.iter().map(|&(_, w)| w));
            col_ptr.push(row_idx.len());
        }
        // Built from undirected edges with one weight each: symmetric by construction.
        let offdiag = SymmetricCsc::try_from_symmetric_pattern(m, col_ptr, row_idx, values)?;
        let matrix = MMatrix::try_new(offdiag, excess)?;
        Ok(StructuredSystem {
            matrix,
            rhs,
            unknowns,
        })
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use harmonic_types::{BoundaryTag, Mesh, NO_NEIGHBOR, Point};

    use super::*;
    use crate::{Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions};

    /// A 7 × 5 grid of cells of side 0.37 with a 2 × 1 block of vertices removed (a hole with
    /// Neumann sides), the left side prescribed at 1 (the goal), the rest of the border at 0.
    fn roles(grid: &StructuredGrid) -> Vec<VertexRole> {
        (0..grid.vertex_count())
            .map(|v| {
                let (i, j) = grid.vertex_ij(v);
                if i == 0 {
                    VertexRole::Prescribed(1.0)
                } else if i == grid.nx() || j == 0 || j == grid.ny() {
                    VertexRole::Prescribed(0.0)
                } else if (3..=4).contains(&i) && j == 2 {
                    VertexRole::Removed
                } else {
                    VertexRole::Unknown
                }
            })
            .collect()
    }

    /// The mesh of the kept triangles (vertices in grid order, so the assembler numbers its
    /// unknowns as the grid does), the left side tagged as goal, the border as walls and the
    /// hole's sides as an obstacle.
    fn kept_mesh(grid: &StructuredGrid, roles: &[VertexRole]) -> Mesh {
        let kept: Vec<usize> = (0..grid.triangle_count())
            .filter(|&t| grid.kept(roles, t))
            .collect();
        let mut used = vec![false; grid.vertex_count()];
        for &t in &kept {
            for v in grid.triangle_vertices(t) {
                used[v] = true;
            }
        }
        let mut index = vec![u32::MAX; grid.vertex_count()];
        let mut vertices = Vec::new();
        for v in (0..grid.vertex_count()).filter(|&v| used[v]) {
            index[v] = vertices.len() as u32;
            let [x, y] = grid.position(v);
            vertices.push(Point::new(x, y));
        }
        let mut triangles = Vec::new();
        let mut boundary = Vec::new();
        for &t in &kept {
            let verts = grid.triangle_vertices(t);
            let local = verts.map(|v| index[v]);
            for (k, across) in grid.triangle_neighbors(t).into_iter().enumerate() {
                if across.is_some_and(|u| grid.kept(roles, u)) {
                    continue;
                }
                let (a, b) = (verts[(k + 1) % 3], verts[(k + 2) % 3]);
                let tag = match across {
                    Some(_) => BoundaryTag::Obstacle(0),
                    None if grid.vertex_ij(a).0 == 0 && grid.vertex_ij(b).0 == 0 => {
                        BoundaryTag::Goal(0)
                    }
                    None => BoundaryTag::Wall,
                };
                boundary.push((local[(k + 1) % 3], local[(k + 2) % 3], tag));
            }
            triangles.push(local);
        }
        let mesh = Mesh::from_parts(vertices, triangles, &boundary).expect("a valid mesh");
        assert!(mesh.neighbors().iter().flatten().any(|&n| n == NO_NEIGHBOR));
        mesh
    }

    #[test]
    fn the_structured_system_is_the_assembled_one() {
        let grid = StructuredGrid::new(7, 5, 0.37);
        let roles = roles(&grid);
        let system = grid.system(&roles, None).expect("a valid system");
        let mesh = Arc::new(kept_mesh(&grid, &roles));
        // Goal ψ = 1, walls ψ = 0, the hole's sides Neumann: the roles' problem.
        let bcs = BoundaryConditions {
            obstacles: BoundaryCondition::Neumann(0.0),
            ..BoundaryConditions::default()
        };
        let assembler =
            Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("assembler");
        let assembled = assembler.assemble(&bcs).expect("assembly");
        let m = system.unknowns().len();
        assert_eq!(assembled.unknown_count(), m);
        // Same unknowns in the same order: the mesh numbers the used grid vertices in order.
        let used: Vec<usize> = (0..grid.vertex_count())
            .filter(|&v| roles[v] != VertexRole::Removed)
            .collect();
        for (k, &v) in assembled.free_vertices().iter().enumerate() {
            assert_eq!(used[v as usize], system.unknowns()[k]);
        }
        let dense = |a: &SymmetricCsc| {
            let mut d = vec![0.0; m * m];
            for j in 0..m {
                let (rows, vals) = a.column(j);
                for (&i, &v) in rows.iter().zip(vals) {
                    d[i * m + j] = v;
                }
            }
            d
        };
        let relative = |a: &[f64], b: &[f64]| {
            let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            a.iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max)
                / scale
        };
        let mine = system.matrix();
        let theirs = assembled.m_matrix().expect("an M-matrix");
        let worst = [
            relative(&dense(mine.offdiag()), &dense(theirs.offdiag())),
            relative(mine.excess(), theirs.excess()),
            relative(system.rhs(), assembled.rhs()),
            relative(&dense(&mine.to_csc()), &dense(assembled.matrix())),
        ];
        assert!(worst.iter().all(|&w| w < 1e-12), "{worst:?}");
        // The hole's sides weigh one half, the goal's column its full weights.
        assert!(mine.offdiag().values().contains(&0.5));
        assert!(system.rhs().iter().any(|&b| b >= 1.0));
    }

    #[test]
    fn an_order_numbers_the_unknowns_and_is_checked() {
        let grid = StructuredGrid::new(4, 3, 1.0);
        let roles = roles(&grid);
        let natural = grid.system(&roles, None).expect("natural");
        let mut order = natural.unknowns().to_vec();
        order.reverse();
        let reversed = grid.system(&roles, Some(&order)).expect("reversed");
        assert_eq!(reversed.unknowns(), &order[..]);
        let m = order.len();
        for k in 0..m {
            assert_eq!(reversed.rhs()[k], natural.rhs()[m - 1 - k]);
            assert_eq!(
                reversed.matrix().excess()[k],
                natural.matrix().excess()[m - 1 - k]
            );
        }
        // A prescribed vertex, a repeated one or a missing one is refused.
        let bad = [
            vec![0],
            [order.clone(), vec![order[0]]].concat(),
            order[1..].to_vec(),
        ];
        for o in bad {
            assert!(grid.system(&roles, Some(&o)).is_err(), "{o:?}");
        }
    }

    #[test]
    fn triangles_are_located_and_adjacent() {
        let grid = StructuredGrid::new(3, 2, 0.5);
        assert_eq!(grid.triangle_at(0.7, 0.2), Some(0));
        assert_eq!(grid.triangle_at(0.2, 0.7), Some(1));
        assert_eq!(grid.triangle_at(3.0, 2.0), Some(10));
        assert_eq!(grid.triangle_at(-0.1, 1.0), None);
        for t in 0..grid.triangle_count() {
            let verts = grid.triangle_vertices(t);
            for (k, across) in grid.triangle_neighbors(t).into_iter().enumerate() {
                let Some(u) = across else { continue };
                // The edge opposite vertex k is shared with the neighbour.
                let edge = [verts[(k + 1) % 3], verts[(k + 2) % 3]];
                let other = grid.triangle_vertices(u);
                assert!(edge.iter().all(|v| other.contains(v)), "{t} {u}");
            }
        }
        let mut order = grid.nested_dissection();
        order.sort_unstable();
        assert_eq!(order, (0..grid.vertex_count()).collect::<Vec<_>>());
    }
}
