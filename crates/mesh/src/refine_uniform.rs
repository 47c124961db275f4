//! Uniform ("red") refinement: every triangle split into four through its edge midpoints,
//! then Lawson flips back to a constrained Delaunay mesh.
//!
//! ```text
//!         c                       c
//!        / \                     / \
//!       /   \                  m1---m0
//!      /     \      ──►        / \ / \
//!     /       \               /   X   \        (X: the middle child m0 m1 m2)
//!    a─────────b             a----m2---b
//! ```
//!
//! The four children are similar to their parent, so the smallest angle is kept exactly, and
//! a half of a parent edge faces the same angles as the whole edge did: edges that were
//! Delaunay (and boundary edges with an acute angle facing them) stay so. Only the three
//! edges inside a parent with an obtuse angle can fail the Delaunay test (both angles facing
//! them equal the obtuse one); those are flipped, and each flip queues the edges around it
//! (Lawson), which keeps the smallest angle from going down. Boundary edges are never flipped.
//!
//! Each fine vertex remembers the coarse edge it is the midpoint of (or the coarse vertex it
//! is), which is what a geometric multigrid needs to move functions between the levels.

use rayon::prelude::*;

use crate::{BoundaryTag, MeshError};
use crate::{Mesh, MeshHierarchy, NO_NEIGHBOR, Point};

/// A mesh refined once by [`RefineUniformly::refined_uniformly`].
#[derive(Clone, Debug)]
pub struct Refinement {
    /// The refined mesh: four times the triangles of the coarse one.
    pub mesh: Mesh,
    /// For each vertex of the refined mesh, the coarse vertices it lies between: `[a, a]` for
    /// a coarse vertex kept, `[a, b]` for the midpoint of coarse edge `a b`.
    pub parents: Vec<[u32; 2]>,
}

/// Uniform refinement of a triangle mesh (red refinement plus Delaunay flips), the step
/// between the levels of a [`MeshHierarchy`].
pub trait RefineUniformly {
    /// Splits every triangle into four through its edge midpoints and restores the
    /// (constrained) Delaunay property by edge flips. The triangles' smallest angle is kept,
    /// the largest area quartered, the boundary and its tags unchanged (each boundary edge is
    /// split in two with its tag).
    ///
    /// Vertices are numbered in the order the coarse triangles first touch them, which keeps
    /// the coarse mesh's locality (its Hilbert order). Errors with
    /// [`MeshError::TooManyTriangles`] if the refined mesh would not fit 32-bit indices.
    ///
    /// ```
    /// use harmonic_mesh::{BoundaryTag, Mesh, Point, RefineUniformly};
    /// let square = vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)];
    /// let walls = [(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Wall), (2, 3, BoundaryTag::Wall), (3, 0, BoundaryTag::Wall)];
    /// let coarse = Mesh::from_parts(square, vec![[0, 1, 2], [0, 2, 3]], &walls)?;
    /// let fine = coarse.refined_uniformly()?;
    /// assert_eq!(fine.mesh.triangles().len(), 8);
    /// assert_eq!(fine.mesh.vertices().len(), 9); // 4 corners + 5 edge midpoints
    /// assert_eq!(fine.mesh.boundary_edges().len(), 8);
    /// let centre = fine.mesh.vertices().iter().position(|p| *p == Point::new(0.5, 0.5)).unwrap();
    /// assert_eq!(fine.parents[centre], [2, 0]); // the midpoint of the diagonal 0-2
    /// # Ok::<(), harmonic_mesh::MeshError>(())
    /// ```
    fn refined_uniformly(&self) -> Result<Refinement, MeshError>;
}

impl RefineUniformly for Mesh {
    fn refined_uniformly(&self) -> Result<Refinement, MeshError> {
        let coarse = self.triangles();
        let fine_count = coarse.len().saturating_mul(4);
        if fine_count >= NO_NEIGHBOR as usize {
            return Err(MeshError::TooManyTriangles {
                estimated: fine_count,
                limit: NO_NEIGHBOR as usize - 1,
            });
        }
        let numbering = Numbering::of(self);
        let (mut triangles, mut neighbors) = children(self, &numbering);
        let vertices: Vec<Point> = numbering
            .parents
            .par_iter()
            .map(|&[a, b]| {
                let (p, q) = (self.vertices()[a as usize], self.vertices()[b as usize]);
                if a == b {
                    p
                } else {
                    Point::new(0.5 * (p.x + q.x), 0.5 * (p.y + q.y))
                }
            })
            .collect();
        flip_to_delaunay(self, &vertices, &mut triangles, &mut neighbors);
        let boundary = split_boundary(self, &numbering);
        // The adjacency is right by construction (the tests compare it with the one
        // `Mesh::from_parts` computes), so it is not checked again here. Each child lies in
        // its parent's component, and a flip joins two triangles of one component, so the
        // components (numbered by their smallest triangles, whose children come first) are
        // the parents'.
        let parent_component = self.triangle_components();
        let components = (0..triangles.len())
            .into_par_iter()
            .map(|c| parent_component[c / 4])
            .collect();
        let mesh = Mesh::with_adjacency_and_components(
            vertices,
            triangles,
            neighbors,
            &boundary,
            Some((components, self.component_count())),
        )?;
        Ok(Refinement {
            mesh,
            parents: numbering.parents,
        })
    }
}

/// Fine vertex numbers of the coarse vertices and of the coarse edges' midpoints.
struct Numbering {
    /// Fine number of each coarse vertex.
    vertex: Vec<u32>,
    /// Fine number of the midpoint of edge `k` (opposite local vertex `k`) of each coarse triangle.
    midpoint: Vec<[u32; 3]>,
    /// Coarse end vertices of each fine vertex (see [`Refinement::parents`]).
    parents: Vec<[u32; 2]>,
}

impl Numbering {
    /// Numbers in the order the coarse triangles first touch each vertex and edge.
    fn of(mesh: &Mesh) -> Self {
        let (tris, nbrs) = (mesh.triangles(), mesh.neighbors());
        let mut vertex = vec![u32::MAX; mesh.vertices().len()];
        let mut midpoint = vec![[u32::MAX; 3]; tris.len()];
        let mut parents = Vec::with_capacity(mesh.vertices().len() + 3 * tris.len() / 2 + 1);
        for (t, &tri) in tris.iter().enumerate() {
            for &v in &tri {
                if vertex[v as usize] == u32::MAX {
                    vertex[v as usize] = parents.len() as u32;
                    parents.push([v, v]);
                }
            }
            for k in 0..3 {
                if midpoint[t][k] != u32::MAX {
                    continue;
                }
                let (a, b) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let m = parents.len() as u32;
                parents.push([a, b]);
                midpoint[t][k] = m;
                let u = nbrs[t][k];
                if u != NO_NEIGHBOR {
                    // The neighbour holds the same edge as b -> a.
                    if let Some(j) = local_edge(tris[u as usize], b, a) {
                        midpoint[u as usize][j] = m;
                    }
                }
            }
        }
        Numbering {
            vertex,
            midpoint,
            parents,
        }
    }
}

/// Local index `j` of the edge `a -> b` in `tri` (the edge opposite local vertex `j`).
fn local_edge(tri: [u32; 3], a: u32, b: u32) -> Option<usize> {
    (0..3).find(|&j| tri[(j + 1) % 3] == a && tri[(j + 2) % 3] == b)
}

/// The four children of every coarse triangle with their adjacency: child `4t + i` for
/// `i < 3` is the corner at local vertex `i` (`[c0, m2, m1]`, `[m2, c1, m0]`, `[m1, m0, c2]`,
/// with `m_k` the midpoint of the edge opposite `c_k`), child `4t + 3` the middle triangle
/// `[m0, m1, m2]` (the parent turned half a turn, so counter-clockwise too).
fn children(mesh: &Mesh, numbering: &Numbering) -> (Vec<[u32; 3]>, Vec<[u32; 3]>) {
    let (tris, nbrs) = (mesh.triangles(), mesh.neighbors());
    let mut triangles = vec![[0; 3]; 4 * tris.len()];
    let mut neighbors = vec![[0; 3]; 4 * tris.len()];
    // The corner child of coarse triangle `u` at coarse vertex `v`.
    let corner = |u: u32, v: u32| -> u32 {
        if u == NO_NEIGHBOR {
            return NO_NEIGHBOR;
        }
        let at = tris[u as usize].iter().position(|&w| w == v).unwrap_or(0);
        4 * u + at as u32
    };
    // Each coarse triangle writes its own four children: on every core.
    triangles
        .par_chunks_mut(4)
        .zip(neighbors.par_chunks_mut(4))
        .enumerate()
        .for_each(|(t, (kids, across_kids))| {
            let tri = tris[t];
            let c = tri.map(|v| numbering.vertex[v as usize]);
            let m = numbering.midpoint[t];
            for i in 0..3 {
                let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
                let mut child = [0; 3];
                child[i] = c[i];
                child[i1] = m[i2];
                child[i2] = m[i1];
                let mut across = [0; 3];
                across[i] = 4 * t as u32 + 3;
                // The edge opposite position i1 runs m_{i1} -> c_i along the parent's edge
                // i1, the one opposite i2 runs c_i -> m_{i2} along the parent's edge i2.
                across[i1] = corner(nbrs[t][i1], tri[i]);
                across[i2] = corner(nbrs[t][i2], tri[i]);
                kids[i] = child;
                across_kids[i] = across;
            }
            let base = 4 * t as u32;
            kids[3] = m;
            across_kids[3] = [base, base + 1, base + 2];
        });
    (triangles, neighbors)
}

/// Sum of the cotangents of the two angles facing the edge opposite local vertex `k` of
/// triangle `t`; negative when the angles sum to more than π (the edge is not Delaunay).
fn cotangent_sum(vertices: &[Point], tri: [u32; 3], k: usize, opposite: Point) -> f64 {
    let p = vertices[tri[k] as usize];
    let a = vertices[tri[(k + 1) % 3] as usize];
    let b = vertices[tri[(k + 2) % 3] as usize];
    let cot = |apex: Point, u: Point, v: Point| {
        let (du, dv) = (u - apex, v - apex);
        du.dot(&dv) / (du.x * dv.y - du.y * dv.x).abs()
    };
    cot(p, a, b) + cot(opposite, b, a)
}

/// How far below zero a cotangent sum must be before its edge is flipped: keeps cocircular
/// quadrilaterals (a split square) from flipping back and forth on rounding.
const FLIP_TOLERANCE: f64 = 1e-10;

/// Lawson flips from the edges that can fail the Delaunay test after the split: the edge
/// between the middle child and the corner child at an obtuse corner.
fn flip_to_delaunay(
    coarse: &Mesh,
    vertices: &[Point],
    triangles: &mut [[u32; 3]],
    neighbors: &mut [[u32; 3]],
) {
    // The corners found on every core, kept in triangle order (the flips' order).
    let mut stack: Vec<(u32, usize)> = (0..coarse.triangles().len())
        .into_par_iter()
        .flat_map_iter(|t| {
            let corners = coarse.triangle_points(t as u32);
            (0..3).filter_map(move |i| {
                let (u, v) = (
                    corners[(i + 1) % 3] - corners[i],
                    corners[(i + 2) % 3] - corners[i],
                );
                (u.dot(&v) < 0.0).then_some((4 * t as u32 + i as u32, i))
            })
        })
        .collect();
    while let Some((t, k)) = stack.pop() {
        let u = neighbors[t as usize][k];
        if u == NO_NEIGHBOR {
            continue;
        }
        let tri = triangles[t as usize];
        let (p, a, b) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
        let Some(j) = local_edge(triangles[u as usize], b, a) else {
            continue;
        };
        let q = triangles[u as usize][j];
        if cotangent_sum(vertices, tri, k, vertices[q as usize]) >= -FLIP_TOLERANCE
            || !counter_clockwise(vertices, [p, a, q])
            || !counter_clockwise(vertices, [q, b, p])
        {
            continue;
        }
        // t = (p, a, b) and u = (q, b, a) become t = (p, a, q) and u = (q, b, p).
        let nt = neighbors[t as usize];
        let nu = neighbors[u as usize];
        let (t_across_a, t_across_b) = (nt[(k + 1) % 3], nt[(k + 2) % 3]);
        let (u_across_b, u_across_a) = (nu[(j + 1) % 3], nu[(j + 2) % 3]);
        triangles[t as usize] = [p, a, q];
        neighbors[t as usize] = [u_across_b, u, t_across_b];
        triangles[u as usize] = [q, b, p];
        neighbors[u as usize] = [t_across_a, t, u_across_a];
        // The triangles that looked at t across b -> p, and at u across a -> q, now look at
        // the other one.
        repoint(neighbors, t_across_a, t, u);
        repoint(neighbors, u_across_b, u, t);
        stack.extend([(t, 0), (t, 2), (u, 0), (u, 2)]);
    }
}

/// Whether the three vertices turn left (a flip that would fold a triangle is not made).
fn counter_clockwise(vertices: &[Point], [a, b, c]: [u32; 3]) -> bool {
    let (a, b, c) = (
        vertices[a as usize],
        vertices[b as usize],
        vertices[c as usize],
    );
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) > 0.0
}

/// In triangle `w` (if any), the neighbour `from` becomes `to`.
fn repoint(neighbors: &mut [[u32; 3]], w: u32, from: u32, to: u32) {
    if w == NO_NEIGHBOR {
        return;
    }
    for n in &mut neighbors[w as usize] {
        if *n == from {
            *n = to;
        }
    }
}

/// Each boundary edge split at its midpoint, both halves with its tag.
fn split_boundary(coarse: &Mesh, numbering: &Numbering) -> Vec<(u32, u32, BoundaryTag)> {
    let mut halves = Vec::with_capacity(2 * coarse.boundary_edges().len());
    for e in coarse.boundary_edges() {
        let m = numbering.midpoint[e.triangle as usize][e.local_edge as usize];
        let [a, b] = e.vertices.map(|v| numbering.vertex[v as usize]);
        halves.push((a, m, e.tag));
        halves.push((m, b, e.tag));
    }
    halves
}

/// The hierarchy of `coarse` and `refinements` successive
/// [`refined_uniformly`](RefineUniformly::refined_uniformly) of it: the finest
/// level has `4^refinements` times the triangles, with the same smallest angle.
///
/// Refuses up front, with [`MeshError::TooManyTriangles`], a finest level above the
/// mesher's default budget ([`crate::MeshOptions`]'s `max_triangles`, 20 M triangles),
/// before any memory is spent on it.
///
/// ```
/// use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Point, uniform_hierarchy};
/// let spec = DomainSpec {
///     workspace: vec![Point::new(0.0, 0.0), Point::new(4.0, 0.0), Point::new(4.0, 4.0), Point::new(0.0, 4.0)],
///     obstacles: vec![],
///     goals: vec![GoalShape::Point(Point::new(3.5, 3.5))],
///     robot_radius: 0.0,
/// };
/// let opts = MeshOptions { max_area: Some(0.2), ..MeshOptions::default() };
/// let (coarse, _) = Domain::new(&spec, &opts)?.mesh(&opts)?;
/// let coarse_triangles = coarse.triangles().len();
/// let hierarchy = uniform_hierarchy(coarse, 2)?;
/// assert_eq!(hierarchy.levels().len(), 3);
/// assert_eq!(hierarchy.finest().triangles().len(), 16 * coarse_triangles);
/// // A quarter of a quarter of the coarse bound, to rounding.
/// assert!(hierarchy.finest().quality().max_triangle_area <= 0.2 / 16.0 * (1.0 + 1e-12));
/// # Ok::<(), harmonic_mesh::MeshError>(())
/// ```
pub fn uniform_hierarchy(coarse: Mesh, refinements: usize) -> Result<MeshHierarchy, MeshError> {
    let limit = crate::MeshOptions::default().max_triangles;
    let finest = u32::try_from(refinements)
        .ok()
        .and_then(|k| 4usize.checked_pow(k))
        .and_then(|f| coarse.triangles().len().checked_mul(f))
        .unwrap_or(usize::MAX);
    if finest > limit {
        return Err(MeshError::TooManyTriangles {
            estimated: finest,
            limit,
        });
    }
    let mut levels = vec![std::sync::Arc::new(coarse)];
    let mut parents = Vec::with_capacity(refinements);
    for _ in 0..refinements {
        let step = levels[levels.len() - 1].refined_uniformly()?;
        levels.push(std::sync::Arc::new(step.mesh));
        parents.push(step.parents);
    }
    Ok(MeshHierarchy::from_levels(levels, parents)?)
}
