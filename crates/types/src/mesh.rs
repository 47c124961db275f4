//! The triangle mesh of free space: vertices, counter-clockwise triangles, adjacency,
//! tagged boundary edges and connected components.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Element, MeshDataError};
use crate::geom::twice_signed_area;
use crate::{BoundaryTag, Point};

/// Marks "no element across this edge or face": a boundary edge of a triangle, a boundary
/// face of a tetrahedron.
pub const NO_NEIGHBOR: u32 = u32::MAX;

/// One boundary edge of the mesh.
///
/// `vertices` are ordered counter-clockwise with respect to `triangle`, so free space lies to
/// the left of `vertices[0] → vertices[1]` and the outward normal of free space (pointing
/// into the wall, obstacle or goal) lies to the right.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundaryEdge {
    /// The edge's two end vertices (indices into [`Mesh::vertices`]), counter-clockwise
    /// with respect to `triangle`.
    pub vertices: [u32; 2],
    /// The one triangle of the mesh that has this edge (index into [`Mesh::triangles`]).
    pub triangle: u32,
    /// The local index `k` of the edge in `triangle` (the edge opposite local vertex `k`).
    pub local_edge: u8,
    /// What the edge lies on: a wall, an obstacle or a goal.
    pub tag: BoundaryTag,
}

/// A triangulation of free space.
///
/// Invariants (checked by [`Mesh::from_parts`]): triangles are counter-clockwise with
/// positive area; `neighbors[t][k]` is the triangle across the edge opposite local vertex `k`
/// (the edge `triangles[t][(k+1)%3] → triangles[t][(k+2)%3]`) or [`NO_NEIGHBOR`]; every
/// edge without a neighbour is exactly one [`BoundaryEdge`].
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Mesh {
    vertices: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    neighbors: Vec<[u32; 3]>,
    /// For each triangle edge, the index into `boundary_edges`, or `NO_NEIGHBOR`.
    edge_boundary: Vec<[u32; 3]>,
    boundary_edges: Vec<BoundaryEdge>,
    /// First boundary tag met at each vertex (goal before obstacle before wall), if any.
    vertex_tags: Vec<Option<BoundaryTag>>,
    /// Connected component (through shared edges) of each triangle.
    triangle_component: Vec<u32>,
    component_count: u32,
    /// Bucket grid for point location, built once [`SCANS_BEFORE_GRID`] locations have been
    /// answered by scanning.
    #[serde(skip)]
    locator: std::sync::OnceLock<Locator>,
    /// Locations answered by a scan so far.
    #[serde(skip)]
    scans: Scans,
}

/// Point locations (that no walk from a hint answered) made by testing every triangle before
/// the bucket grid is built: a scan costs one containment test per triangle, building the
/// grid several, so a mesh asked only a few times (a map's first plan locates its start
/// once) never builds it, and one asked many times builds it early.
const SCANS_BEFORE_GRID: u32 = 4;

/// A counter that clones by value (a clone of a mesh starts where the mesh was).
#[derive(Debug, Default)]
struct Scans(std::sync::atomic::AtomicU32);

impl Clone for Scans {
    fn clone(&self) -> Self {
        Scans(std::sync::atomic::AtomicU32::new(
            self.0.load(std::sync::atomic::Ordering::Relaxed),
        ))
    }
}

/// Mesh statistics, including the conditions under which the P1 stiffness matrix is an
/// M-matrix (no non-Delaunay interior edge, no obtuse angle opposite a boundary edge).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct QualityReport {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of triangles.
    pub triangles: usize,
    /// Smallest interior angle of any triangle, degrees.
    pub min_angle_deg: f64,
    /// Largest interior angle of any triangle, degrees.
    pub max_angle_deg: f64,
    /// Total area of the triangles.
    pub area: f64,
    /// Area of the largest triangle.
    #[serde(default)]
    pub max_triangle_area: f64,
    /// Holes: boundary loops minus connected components. Loops are followed within the
    /// triangle fans, so two holes touching at a vertex (or a hole touching the outer
    /// boundary) form one loop, as in the free space seen as an open set.
    pub holes: usize,
    /// Extra wedges of free space at vertices where the boundary touches itself (a vertex
    /// with `w` boundary edges leaving it counts `w − 1`). Euler's formula for the mesh is
    /// `V − E + T + pinch_vertices = components − holes`.
    pub pinch_vertices: usize,
    /// Connected components.
    pub components: usize,
    /// Interior edges whose two opposite angles sum to more than π (+1e-9).
    pub non_delaunay_edges: usize,
    /// Boundary edges whose opposite angle exceeds π/2 (+1e-9).
    pub obtuse_boundary_edges: usize,
}

/// A uniform bucket grid of triangle bounding boxes (compressed rows).
#[derive(Clone, Debug)]
struct Locator {
    lo: Point,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Locator {
    fn new(vertices: &[Point], triangles: &[[u32; 3]]) -> Self {
        let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in vertices {
            lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        let w = (hi.x - lo.x).max(f64::MIN_POSITIVE);
        let h = (hi.y - lo.y).max(f64::MIN_POSITIVE);
        let target = (triangles.len() / 2).max(1) as f64;
        let cell = (w * h / target).sqrt().max(w.max(h) / 4096.0);
        let nx = ((w / cell).ceil() as usize).max(1);
        let ny = ((h / cell).ceil() as usize).max(1);
        let range = |t: &[u32; 3]| {
            let ps = t.map(|v| vertices[v as usize]);
            // Truncating a non-negative value is its floor (and `as` makes NaN 0).
            let fx = |x: f64| (((x - lo.x) / cell).max(0.0) as usize).min(nx - 1);
            let fy = |y: f64| (((y - lo.y) / cell).max(0.0) as usize).min(ny - 1);
            let x0 = fx(ps[0].x.min(ps[1].x).min(ps[2].x));
            let x1 = fx(ps[0].x.max(ps[1].x).max(ps[2].x));
            let y0 = fy(ps[0].y.min(ps[1].y).min(ps[2].y));
            let y1 = fy(ps[0].y.max(ps[1].y).max(ps[2].y));
            (x0, x1, y0, y1)
        };
        let mut count = vec![0u32; nx * ny + 1];
        for t in triangles {
            let (x0, x1, y0, y1) = range(t);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    count[y * nx + x + 1] += 1;
                }
            }
        }
        for i in 1..count.len() {
            count[i] += count[i - 1];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[nx * ny] as usize];
        for (ti, t) in triangles.iter().enumerate() {
            let (x0, x1, y0, y1) = range(t);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let c = y * nx + x;
                    items[fill[c] as usize] = ti as u32;
                    fill[c] += 1;
                }
            }
        }
        Locator {
            lo,
            cell,
            nx,
            ny,
            start: count,
            items,
        }
    }

    fn candidates(&self, p: Point) -> &[u32] {
        let x = (p.x - self.lo.x) / self.cell;
        let y = (p.y - self.lo.y) / self.cell;
        // A point just outside the box may still be on a boundary edge (tolerance).
        if x < -1e-9 || y < -1e-9 || x > self.nx as f64 + 1e-9 || y > self.ny as f64 + 1e-9 {
            return &[];
        }
        let cx = (x.floor().max(0.0) as usize).min(self.nx - 1);
        let cy = (y.floor().max(0.0) as usize).min(self.ny - 1);
        let c = cy * self.nx + cx;
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}

/// Errors unless every triangle refers to existing vertices and is counter-clockwise.
fn check_triangles(vertices: &[Point], triangles: &[[u32; 3]]) -> Result<(), MeshDataError> {
    let nv = vertices.len();
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&vertex) = tri.iter().find(|&&v| v as usize >= nv) {
            return Err(MeshDataError::VertexOutOfRange {
                element: Element::Triangle,
                index: t,
                vertex,
                vertices: nv,
            });
        }
        let [a, b, c] = tri.map(|v| vertices[v as usize]);
        if twice_signed_area(a, b, c) <= 0.0 {
            return Err(MeshDataError::NotPositive {
                element: Element::Triangle,
                index: t,
                vertices: [tri[0], tri[1], tri[2], u32::MAX],
            });
        }
    }
    Ok(())
}

/// Length from which [`map_in_two`] uses a second thread.
const TWO_THREADS_FROM: usize = 200_000;

/// Runs `f` over `input` and the matching `output` — for long slices as two halves on two
/// threads of rayon's pool (one after the other in a pool of one thread), for the meshing of
/// large meshes: neighbours, renumbering.
pub fn map_in_two<T: Sync, U: Send>(
    input: &[T],
    output: &mut [U],
    f: impl Fn(&[T], &mut [U]) + Sync,
) {
    if input.len() >= TWO_THREADS_FROM {
        let mid = input.len() / 2;
        let (i0, i1) = input.split_at(mid);
        let (o0, o1) = output.split_at_mut(mid);
        rayon::join(|| f(i0, o0), || f(i1, o1));
    } else {
        f(input, output);
    }
}

impl Mesh {
    /// Builds a mesh from vertices, counter-clockwise triangles and tagged boundary edges
    /// given as `(a, b, tag)` in any orientation. Computes adjacency, the boundary edge
    /// table, per-vertex tags and connected components.
    ///
    /// Errors if a triangle is degenerate or clockwise, refers to a missing vertex, an edge
    /// is shared by more than two triangles, or a boundary edge has no tag (or a tag is
    /// given for an interior edge).
    pub fn from_parts(
        vertices: Vec<Point>,
        triangles: Vec<[u32; 3]>,
        boundary: &[(u32, u32, BoundaryTag)],
    ) -> Result<Self, MeshDataError> {
        let nv = vertices.len();
        check_triangles(&vertices, &triangles)?;
        // Adjacency through the triangle stars of the vertices (compressed rows): for each
        // triangle at vertex v, the triangle and the vertex after v in it (so star entry
        // (u, w) of v is the directed edge v -> w of triangle u). The triangle across
        // directed edge a -> b is the entry of b's star whose edge is b -> a.
        let mut start = vec![0u32; nv + 1];
        for tri in &triangles {
            for &v in tri {
                start[v as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut star = vec![(0u32, 0u32); 3 * triangles.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for i in 0..3 {
                let v = tri[i] as usize;
                star[fill[v] as usize] = (t as u32, tri[(i + 1) % 3]);
                fill[v] += 1;
            }
        }
        drop(fill);
        let star_of = |v: u32| &star[start[v as usize] as usize..start[v as usize + 1] as usize];
        // No directed edge may appear twice: the edges leaving each vertex are distinct.
        let mut leaving: Vec<(u32, u32)> = Vec::new();
        for v in 0..nv as u32 {
            let s = star_of(v);
            let twice = if s.len() <= 16 {
                (1..s.len()).find_map(|i| s[..i].iter().find(|e| e.1 == s[i].1).map(|_| s[i]))
            } else {
                leaving.clear();
                leaving.extend(s.iter().map(|&(u, w)| (w, u)));
                leaving.sort_unstable();
                leaving
                    .windows(2)
                    .find(|p| p[0].0 == p[1].0)
                    .map(|p| (p[1].1, p[1].0))
            };
            if let Some((t, w)) = twice {
                return Err(MeshDataError::EdgeUsedTwice {
                    edge: [v, w],
                    triangle: t as usize,
                });
            }
        }
        let mut neighbors = vec![[NO_NEIGHBOR; 3]; triangles.len()];
        let find = |tris: &[[u32; 3]], out: &mut [[u32; 3]]| {
            for (tri, nbs) in tris.iter().zip(out.iter_mut()) {
                for (k, nb) in nbs.iter_mut().enumerate() {
                    let a = tri[(k + 1) % 3];
                    let b = tri[(k + 2) % 3];
                    if let Some(&(u, _)) = star_of(b).iter().find(|e| e.1 == a) {
                        *nb = u;
                    }
                }
            }
        };
        // Large meshes: two threads, one per half of the triangles (the stars are shared).
        map_in_two(&triangles, &mut neighbors, find);
        drop(star);
        Self::with_adjacency(vertices, triangles, neighbors, boundary)
    }

    /// [`Mesh::from_parts`] for a caller that already knows the adjacency (a structured
    /// mesh): `neighbors[t][k]` is the triangle across the edge opposite local vertex `k` of
    /// triangle `t`, or [`NO_NEIGHBOR`] on the boundary. The adjacency is checked (each
    /// neighbour refers back across the same edge, reversed) instead of computed.
    ///
    /// ```
    /// use harmonic_types::{BoundaryTag, Mesh, NO_NEIGHBOR, Point};
    /// let square = vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)];
    /// let triangles = vec![[0, 1, 2], [0, 2, 3]];
    /// let walls = [(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Wall),
    ///              (2, 3, BoundaryTag::Goal(0)), (3, 0, BoundaryTag::Wall)];
    /// let neighbors = vec![[NO_NEIGHBOR, 1, NO_NEIGHBOR], [NO_NEIGHBOR, NO_NEIGHBOR, 0]];
    /// let mesh = Mesh::from_parts_with_neighbors(square.clone(), triangles.clone(), neighbors, &walls)?;
    /// let computed = Mesh::from_parts(square.clone(), triangles.clone(), &walls)?;
    /// assert_eq!(mesh.neighbors(), computed.neighbors());
    /// assert_eq!(mesh.boundary_edges(), computed.boundary_edges());
    /// // A neighbour that does not share the edge is refused.
    /// let wrong = vec![[1, NO_NEIGHBOR, NO_NEIGHBOR], [NO_NEIGHBOR, NO_NEIGHBOR, 0]];
    /// assert!(Mesh::from_parts_with_neighbors(square, triangles, wrong, &walls).is_err());
    /// # Ok::<(), harmonic_types::MeshDataError>(())
    /// ```
    pub fn from_parts_with_neighbors(
        vertices: Vec<Point>,
        triangles: Vec<[u32; 3]>,
        neighbors: Vec<[u32; 3]>,
        boundary: &[(u32, u32, BoundaryTag)],
    ) -> Result<Self, MeshDataError> {
        if neighbors.len() != triangles.len() {
            return Err(MeshDataError::NeighborCount {
                element: Element::Triangle,
                given: neighbors.len(),
                elements: triangles.len(),
            });
        }
        check_triangles(&vertices, &triangles)?;
        for (t, (tri, nbs)) in triangles.iter().zip(&neighbors).enumerate() {
            for (k, &u) in nbs.iter().enumerate() {
                if u == NO_NEIGHBOR {
                    continue;
                }
                let (a, b) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                // Across edge a -> b, triangle u has the edge b -> a and refers back.
                let back = triangles.get(u as usize).and_then(|other| {
                    (0..3).find(|&j| other[(j + 1) % 3] == b && other[(j + 2) % 3] == a)
                });
                if back.is_none_or(|j| neighbors[u as usize][j] != t as u32) {
                    return Err(MeshDataError::NeighborMismatch {
                        triangle: t,
                        neighbor: u,
                        edge: [a, b],
                    });
                }
            }
        }
        Self::with_adjacency(vertices, triangles, neighbors, boundary)
    }

    /// The rest of a mesh once its triangles and (consistent) adjacency are known: boundary
    /// edges with their tags, vertex tags and components.
    pub fn with_adjacency(
        vertices: Vec<Point>,
        triangles: Vec<[u32; 3]>,
        neighbors: Vec<[u32; 3]>,
        boundary: &[(u32, u32, BoundaryTag)],
    ) -> Result<Self, MeshDataError> {
        Self::with_adjacency_and_components(vertices, triangles, neighbors, boundary, None)
    }

    /// [`Mesh::with_adjacency`] with each triangle's component already known (numbered in
    /// order of each component's smallest triangle, as the mesh numbers them: a refinement
    /// knows its children's from their parents'); `None` finds them. Components of the
    /// wrong length are found again.
    pub fn with_adjacency_and_components(
        vertices: Vec<Point>,
        triangles: Vec<[u32; 3]>,
        neighbors: Vec<[u32; 3]>,
        boundary: &[(u32, u32, BoundaryTag)],
        known: Option<(Vec<u32>, u32)>,
    ) -> Result<Self, MeshDataError> {
        let nv = vertices.len();
        // Tags by undirected edge, sorted for binary search (the last of duplicates wins).
        let key = |a: u32, b: u32| (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
        let mut tag_of: Vec<(u64, BoundaryTag)> = boundary
            .iter()
            .map(|&(a, b, tag)| (key(a, b), tag))
            .collect();
        tag_of.reverse();
        tag_of.sort_by_key(|e| e.0);
        tag_of.dedup_by_key(|e| e.0);
        let tag_at = |a: u32, b: u32| {
            tag_of
                .binary_search_by_key(&key(a, b), |e| e.0)
                .ok()
                .map(|i| tag_of[i].1)
        };
        let mut edge_boundary = vec![[NO_NEIGHBOR; 3]; triangles.len()];
        let mut boundary_edges = Vec::with_capacity(boundary.len());
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                if neighbors[t][k] != NO_NEIGHBOR {
                    continue;
                }
                let a = tri[(k + 1) % 3];
                let b = tri[(k + 2) % 3];
                let tag = tag_at(a, b).ok_or(MeshDataError::UntaggedEdge {
                    edge: [a, b],
                    triangle: t,
                })?;
                edge_boundary[t][k] = boundary_edges.len() as u32;
                boundary_edges.push(BoundaryEdge {
                    vertices: [a, b],
                    triangle: t as u32,
                    local_edge: k as u8,
                    tag,
                });
            }
        }
        if boundary_edges.len() != tag_of.len() {
            return Err(MeshDataError::TagCount {
                given: tag_of.len(),
                boundary: boundary_edges.len(),
            });
        }
        let mut vertex_tags: Vec<Option<BoundaryTag>> = vec![None; nv];
        for e in &boundary_edges {
            for &v in &e.vertices {
                let slot = &mut vertex_tags[v as usize];
                *slot = Some(match *slot {
                    None => e.tag,
                    Some(old) => tag_priority(old, e.tag),
                });
            }
        }
        let (triangle_component, component_count) = match known {
            Some((c, count)) if c.len() == triangles.len() => (c, count),
            _ => components(&neighbors),
        };
        Ok(Mesh {
            vertices,
            triangles,
            neighbors,
            edge_boundary,
            boundary_edges,
            vertex_tags,
            triangle_component,
            component_count,
            locator: std::sync::OnceLock::new(),
            scans: Scans::default(),
        })
    }

    /// Whether the closed triangle `t` contains `p` (with a relative tolerance of 1e-12 of
    /// the edge length, so points on shared edges are found from both sides).
    pub fn triangle_contains(&self, t: u32, p: Point) -> bool {
        let [a, b, c] = self.triangle_points(t);
        [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, v)| twice_signed_area(u, v, p) >= -1e-12 * (v - u).norm_squared())
    }

    /// The triangle containing `p` (closed triangles), or `None` if `p` is outside free space.
    ///
    /// Walks from `hint` (a triangle index, e.g. the last answer) towards `p`; if the walk
    /// meets the boundary or takes too long, falls back to testing every triangle for the
    /// first few such locations and to a bucket grid (built then) after, so it always
    /// terminates and is exact.
    pub fn locate(&self, p: Point, hint: Option<u32>) -> Option<u32> {
        if !p.x.is_finite() || !p.y.is_finite() || self.triangles.is_empty() {
            return None;
        }
        if let Some(mut t) = hint.filter(|&h| (h as usize) < self.triangles.len()) {
            let mut found = false;
            for step in 0..256usize {
                let tri = self.triangles[t as usize];
                let mut next = None;
                for i in 0..3 {
                    let k = (i + step) % 3;
                    let u = self.vertices[tri[(k + 1) % 3] as usize];
                    let v = self.vertices[tri[(k + 2) % 3] as usize];
                    if twice_signed_area(u, v, p) < -1e-12 * (v - u).norm_squared() {
                        next = Some(self.neighbors[t as usize][k]);
                        break;
                    }
                }
                match next {
                    None => {
                        found = true;
                        break;
                    }
                    Some(NO_NEIGHBOR) => break,
                    Some(n) => t = n,
                }
            }
            if found {
                return Some(t);
            }
        }
        if self.locator.get().is_none()
            && self
                .scans
                .0
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed)
                < SCANS_BEFORE_GRID
        {
            // The grid's candidates of a cell are in triangle order, so the first triangle
            // holding `p` is the grid's answer too.
            return (0..self.triangles.len() as u32).find(|&t| self.triangle_contains(t, p));
        }
        let locator = self
            .locator
            .get_or_init(|| Locator::new(&self.vertices, &self.triangles));
        locator
            .candidates(p)
            .iter()
            .copied()
            .find(|&t| self.triangle_contains(t, p))
    }

    /// The three interior angles of triangle `t` (radians; angle `k` at local vertex `k`).
    pub fn triangle_angles(&self, t: u32) -> [f64; 3] {
        let p = self.triangle_points(t);
        std::array::from_fn(|k| {
            let u = p[(k + 1) % 3] - p[k];
            let v = p[(k + 2) % 3] - p[k];
            (u.x * v.y - u.y * v.x).abs().atan2(u.dot(&v))
        })
    }

    /// Angles, area, topology and the M-matrix conditions of the mesh.
    ///
    /// One arctangent per obtuse corner and two for the whole mesh: corners are compared by a
    /// pseudo-angle that orders them as their angles do (`pseudo_angle`), the extreme ones
    /// measured at the end, and a pair of angles can only exceed π (a non-Delaunay edge), or
    /// a boundary corner π/2, where a corner is obtuse. (With an arctangent at every corner,
    /// this report took 140 M of the 2.07 G instructions of a whole `hplan plan` on a
    /// 2.5 M-cell map; 80 M now.)
    pub fn quality(&self) -> QualityReport {
        use std::f64::consts::{FRAC_PI_2, PI};
        let tol = 1e-9;
        // Per triangle, the arctangent's arguments at its corners.
        let corners: Vec<(f64, [f64; 3])> = (0..self.triangles.len())
            .map(|t| self.corner_arguments(t))
            .collect();
        let angle = |t: usize, k: usize| {
            let (y, x) = corners[t];
            y.atan2(x[k])
        };
        let mut smallest: Option<(f64, usize, usize)> = None;
        let mut largest: Option<(f64, usize, usize)> = None;
        let mut area = 0.0;
        let mut max_triangle_area: f64 = 0.0;
        let mut non_delaunay = 0;
        let mut obtuse_boundary = 0;
        // Whether a corner (y, x) may be wider than a right angle (a right one's dot product
        // may be −0; a corner with no width at all, or NaN, is measured).
        let obtuse =
            |y: f64, x: f64| x < 0.0 || x.is_nan() || (x == 0.0 && (y <= 0.0 || y.is_nan()));
        for (t, &(y, dots)) in corners.iter().enumerate() {
            let triangle_area = self.triangle_area(t as u32);
            area += triangle_area;
            max_triangle_area = max_triangle_area.max(triangle_area);
            for (k, &x) in dots.iter().enumerate() {
                let key = pseudo_angle(y, x);
                // A NaN angle is skipped, as `f64::min` and `max` skip it.
                if !key.is_nan() {
                    if smallest.is_none_or(|(m, _, _)| key < m) {
                        smallest = Some((key, t, k));
                    }
                    if largest.is_none_or(|(m, _, _)| key > m) {
                        largest = Some((key, t, k));
                    }
                }
                let u = self.neighbors[t][k];
                if u == NO_NEIGHBOR {
                    if obtuse(y, x) && y.atan2(x) > FRAC_PI_2 + tol {
                        obtuse_boundary += 1;
                    }
                } else if (t as u32) < u {
                    let Some(k2) = self.neighbors[u as usize]
                        .iter()
                        .position(|&x| x == t as u32)
                    else {
                        continue;
                    };
                    if (obtuse(y, x) || obtuse(corners[u as usize].0, corners[u as usize].1[k2]))
                        && y.atan2(x) + angle(u as usize, k2) > PI + tol
                    {
                        non_delaunay += 1;
                    }
                }
            }
        }
        let min_angle = smallest.map_or(f64::INFINITY, |(_, t, k)| angle(t, k));
        let max_angle = largest.map_or(0.0, |(_, t, k)| angle(t, k));
        let loops = self.boundary_loops();
        let mut leaving = vec![0u32; self.vertices.len()];
        for e in &self.boundary_edges {
            leaving[e.vertices[0] as usize] += 1;
        }
        let pinch_vertices = leaving.iter().map(|&w| w.saturating_sub(1) as usize).sum();
        QualityReport {
            vertices: self.vertices.len(),
            triangles: self.triangles.len(),
            min_angle_deg: if min_angle.is_finite() {
                min_angle.to_degrees()
            } else {
                0.0
            },
            max_angle_deg: max_angle.max(0.0).to_degrees(),
            area,
            max_triangle_area,
            holes: loops.saturating_sub(self.component_count as usize),
            components: self.component_count as usize,
            pinch_vertices,
            non_delaunay_edges: non_delaunay,
            obtuse_boundary_edges: obtuse_boundary,
        }
    }

    /// The arctangent's arguments of triangle `t`'s corners, (|u × v|, [u · v per corner]),
    /// u and v the two edges at a corner: twice the area is the same at every corner.
    fn corner_arguments(&self, t: usize) -> (f64, [f64; 3]) {
        let p = self.triangles[t].map(|v| self.vertices[v as usize]);
        let e = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
        let cross = (e[0].x * e[1].y - e[0].y * e[1].x).abs();
        // Corner k lies between edge k (out of it) and edge k + 2 (into it).
        (cross, [0, 1, 2].map(|k| -e[k].dot(&e[(k + 2) % 3])))
    }

    /// The smallest interior angle in degrees, exactly as [`Mesh::quality`] reports it
    /// (`min_angle_deg`), in one pass on every core with nothing allocated: what a report
    /// that needs no more of the quality report asks for.
    pub fn min_angle_deg(&self) -> f64 {
        // The first corner (by triangle, then corner) of the smallest pseudo angle, as
        // `quality`'s loop finds it; NaN angles skipped.
        let corner = |t: usize| -> Option<(f64, usize, f64, f64)> {
            let (y, dots) = self.corner_arguments(t);
            let mut best: Option<(f64, usize, f64, f64)> = None;
            for x in dots {
                let key = pseudo_angle(y, x);
                if !key.is_nan() && best.is_none_or(|(m, ..)| key < m) {
                    best = Some((key, t, y, x));
                }
            }
            best
        };
        let first =
            |a: Option<(f64, usize, f64, f64)>, b: Option<(f64, usize, f64, f64)>| match (a, b) {
                (Some(a), Some(b)) => Some(if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
                    b
                } else {
                    a
                }),
                (a, None) => a,
                (None, b) => b,
            };
        let smallest = (0..self.triangles.len())
            .into_par_iter()
            .map(corner)
            .reduce(|| None, first);
        match smallest.map(|(_, _, y, x)| y.atan2(x)) {
            Some(a) if a.is_finite() => a.to_degrees(),
            _ => 0.0,
        }
    }

    /// The number of closed boundary loops (a vertex where two loops touch is walked around
    /// through its triangle fan, so touching loops count separately).
    pub fn boundary_loops(&self) -> usize {
        let mut seen = vec![false; self.boundary_edges.len()];
        let mut loops = 0;
        for start in 0..self.boundary_edges.len() {
            if seen[start] {
                continue;
            }
            loops += 1;
            let mut e = start;
            while !seen[e] {
                seen[e] = true;
                e = self.next_boundary_edge(e);
            }
        }
        loops
    }

    /// The boundary edge that follows boundary edge `e` (starting at its end vertex), found by
    /// turning around that vertex through the triangles of free space.
    fn next_boundary_edge(&self, e: usize) -> usize {
        let be = &self.boundary_edges[e];
        let b = be.vertices[1];
        let mut t = be.triangle as usize;
        // Edge b -> c of t is opposite the local vertex that precedes b.
        let mut j = (be.local_edge as usize + 1) % 3;
        for _ in 0..=self.triangles.len() {
            let n = self.neighbors[t][j];
            if n == NO_NEIGHBOR {
                return self.edge_boundary[t][j] as usize;
            }
            t = n as usize;
            let pb = self.triangles[t].iter().position(|&v| v == b).unwrap_or(0);
            j = (pb + 2) % 3;
        }
        e
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }
    /// The counter-clockwise triangles, as vertex indices.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// `neighbors()[t][k]`: the triangle across the edge opposite local vertex `k`, or [`NO_NEIGHBOR`].
    pub fn neighbors(&self) -> &[[u32; 3]] {
        &self.neighbors
    }
    /// All boundary edges with their tags.
    pub fn boundary_edges(&self) -> &[BoundaryEdge] {
        &self.boundary_edges
    }
    /// The boundary edge on local edge `k` of triangle `t`, if that edge is on the boundary.
    pub fn boundary_edge_of(&self, t: u32, k: usize) -> Option<&BoundaryEdge> {
        let i = self.edge_boundary[t as usize][k];
        (i != NO_NEIGHBOR).then(|| &self.boundary_edges[i as usize])
    }
    /// The boundary tag of each vertex (goal wins over obstacle, obstacle over wall), `None` inside.
    pub fn vertex_tags(&self) -> &[Option<BoundaryTag>] {
        &self.vertex_tags
    }
    /// The connected component of each triangle.
    pub fn triangle_components(&self) -> &[u32] {
        &self.triangle_component
    }
    /// The number of connected components of free space.
    pub fn component_count(&self) -> u32 {
        self.component_count
    }
    /// The three corner points of triangle `t`.
    pub fn triangle_points(&self, t: u32) -> [Point; 3] {
        self.triangles[t as usize].map(|v| self.vertices[v as usize])
    }
    /// The area of triangle `t`.
    pub fn triangle_area(&self, t: u32) -> f64 {
        let [a, b, c] = self.triangle_points(t);
        0.5 * twice_signed_area(a, b, c)
    }
}

fn tag_priority(a: BoundaryTag, b: BoundaryTag) -> BoundaryTag {
    fn rank(t: BoundaryTag) -> u8 {
        match t {
            BoundaryTag::Goal(_) => 0,
            BoundaryTag::Obstacle(_) => 1,
            BoundaryTag::Wall => 2,
        }
    }
    if rank(b) < rank(a) { b } else { a }
}

/// Each triangle's edge-connected component, numbered in order of their smallest triangles,
/// and the count.
fn components(neighbors: &[[u32; 3]]) -> (Vec<u32>, u32) {
    // Union–find over the triangles in order, each set's root its smallest triangle (the
    // larger root is linked below the smaller; paths halved as they are walked): the
    // triangles are read in order, not in a search's jumps across the mesh.
    let mut root: Vec<u32> = (0..neighbors.len() as u32).collect();
    let find = |root: &mut [u32], mut t: u32| {
        while root[t as usize] != t {
            let up = root[root[t as usize] as usize];
            root[t as usize] = up;
            t = up;
        }
        t
    };
    for (t, nbs) in neighbors.iter().enumerate() {
        for &n in nbs {
            if n != NO_NEIGHBOR && (n as usize) < t {
                let (a, b) = (find(&mut root, t as u32), find(&mut root, n));
                if a != b {
                    root[a.max(b) as usize] = a.min(b);
                }
            }
        }
    }
    // Numbered in order of their smallest triangles (a root precedes its set's members).
    let mut comp = vec![0; neighbors.len()];
    let mut count = 0;
    for t in 0..neighbors.len() {
        let r = find(&mut root, t as u32) as usize;
        if r == t {
            comp[t] = count;
            count += 1;
        } else {
            comp[t] = comp[r];
        }
    }
    (comp, count)
}

/// A number that orders the angles of [0, π] as they are ordered, from the arctangent's
/// arguments (y = |u × v| ≥ 0, x = u · v) without an arctangent: y / (|x| + y) on [0, π/2],
/// 2 − y / (|x| + y) beyond (0 at 0, 1 at π/2, 2 at π; `atan2(y, x)` · 2/π where |x| + y is
/// zero).
fn pseudo_angle(y: f64, x: f64) -> f64 {
    let s = x.abs() + y;
    if s == 0.0 || s.is_nan() {
        return y.atan2(x) * std::f64::consts::FRAC_2_PI;
    }
    let p = y / s;
    if x >= 0.0 { p } else { 2.0 - p }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The union–find numbering equals a depth-first search's from each smallest unvisited
    /// triangle, on random symmetric adjacencies of up to three neighbours (many components,
    /// chains, loops).
    #[test]
    fn components_are_numbered_by_their_smallest_triangle() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |m: usize| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % m as u64) as usize
        };
        for n in [1usize, 2, 7, 50, 400] {
            for _ in 0..20 {
                let mut nbs = vec![[NO_NEIGHBOR; 3]; n];
                for _ in 0..next(2 * n + 1) {
                    let (a, b) = (next(n), next(n));
                    let (ka, kb) = (next(3), next(3));
                    if a != b && nbs[a][ka] == NO_NEIGHBOR && nbs[b][kb] == NO_NEIGHBOR {
                        nbs[a][ka] = b as u32;
                        nbs[b][kb] = a as u32;
                    }
                }
                let mut reference = vec![NO_NEIGHBOR; n];
                let mut count = 0;
                for seed in 0..n {
                    if reference[seed] != NO_NEIGHBOR {
                        continue;
                    }
                    let mut stack = vec![seed];
                    reference[seed] = count;
                    while let Some(t) = stack.pop() {
                        for &u in &nbs[t] {
                            if u != NO_NEIGHBOR && reference[u as usize] == NO_NEIGHBOR {
                                reference[u as usize] = count;
                                stack.push(u as usize);
                            }
                        }
                    }
                    count += 1;
                }
                assert_eq!(components(&nbs), (reference, count), "{n} triangles");
            }
        }
    }

    fn unit_square() -> Mesh {
        let v = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let t = vec![[0, 1, 2], [0, 2, 3]];
        let b = [
            (0, 1, BoundaryTag::Wall),
            (1, 2, BoundaryTag::Wall),
            (2, 3, BoundaryTag::Goal(0)),
            (3, 0, BoundaryTag::Wall),
        ];
        Mesh::from_parts(v, t, &b).expect("valid mesh")
    }

    /// An n × n grid of unit cells, every vertex moved by up to `jitter` along each axis
    /// (xorshift from `seed`), each cell cut along a random diagonal: obtuse corners and
    /// non-Delaunay edges (no corner opposite the boundary is obtuse: the test adds one).
    fn jittered_grid(n: usize, jitter: f64, mut seed: u64) -> Mesh {
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 1_000_001) as f64 / 1_000_000.0
        };
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut v = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (dx, dy) = (jitter * (2.0 * next() - 1.0), jitter * (2.0 * next() - 1.0));
                v.push(Point::new(i as f64 + dx, j as f64 + dy));
            }
        }
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let c = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                if next() < 0.5 {
                    t.extend([[c[0], c[1], c[2]], [c[0], c[2], c[3]]]);
                } else {
                    t.extend([[c[0], c[1], c[3]], [c[1], c[2], c[3]]]);
                }
            }
        }
        let mut b = Vec::new();
        for k in 0..n {
            b.push((id(k, 0), id(k + 1, 0), BoundaryTag::Wall));
            b.push((id(n, k), id(n, k + 1), BoundaryTag::Wall));
            b.push((id(n - k, n), id(n - k - 1, n), BoundaryTag::Goal(0)));
            b.push((id(0, n - k), id(0, n - k - 1), BoundaryTag::Wall));
        }
        Mesh::from_parts(v, t, &b).expect("a jitter under a quarter cell keeps every triangle")
    }

    /// The quality report's angle figures as every corner's arctangent gives them.
    fn angles_by_arctangent(m: &Mesh) -> (f64, f64, usize, usize) {
        let tol = 1e-9;
        let angles: Vec<[f64; 3]> = (0..m.triangles().len() as u32)
            .map(|t| m.triangle_angles(t))
            .collect();
        let (mut lo, mut hi, mut non_delaunay, mut obtuse) = (f64::INFINITY, 0.0f64, 0, 0);
        for (t, ang) in angles.iter().enumerate() {
            for (k, &a) in ang.iter().enumerate() {
                lo = lo.min(a);
                hi = hi.max(a);
                let u = m.neighbors()[t][k];
                if u == NO_NEIGHBOR {
                    obtuse += usize::from(a > std::f64::consts::FRAC_PI_2 + tol);
                } else if (t as u32) < u {
                    let k2 = m.neighbors()[u as usize]
                        .iter()
                        .position(|&x| x == t as u32)
                        .expect("neighbours are mutual");
                    non_delaunay +=
                        usize::from(a + angles[u as usize][k2] > std::f64::consts::PI + tol);
                }
            }
        }
        (lo.to_degrees(), hi.to_degrees(), non_delaunay, obtuse)
    }

    #[test]
    fn quality_agrees_with_every_corners_arctangent() {
        for (jitter, seed) in [(0.0, 1), (0.1, 2), (0.2, 3), (0.24, 4), (0.24, 5)] {
            let m = jittered_grid(9, jitter, seed);
            let q = m.quality();
            let (lo, hi, non_delaunay, obtuse) = angles_by_arctangent(&m);
            assert!((q.min_angle_deg - lo).abs() <= 1e-12, "{jitter}: {lo}");
            assert!((q.max_angle_deg - hi).abs() <= 1e-12, "{jitter}: {hi}");
            assert_eq!(q.non_delaunay_edges, non_delaunay, "jitter {jitter}");
            assert_eq!(q.obtuse_boundary_edges, obtuse, "jitter {jitter}");
            if jitter >= 0.2 {
                assert!(non_delaunay > 0, "the check sees non-Delaunay edges");
            }
        }
        // A flat triangle: its corner opposite the boundary edge (0, 1) is obtuse.
        let flat = Mesh::from_parts(
            vec![
                Point::new(0.0, 0.0),
                Point::new(2.0, 0.0),
                Point::new(1.0, 0.2),
            ],
            vec![[0, 1, 2]],
            &[
                (0, 1, BoundaryTag::Wall),
                (1, 2, BoundaryTag::Wall),
                (2, 0, BoundaryTag::Goal(0)),
            ],
        )
        .expect("a counter-clockwise triangle");
        let q = flat.quality();
        assert_eq!(q.obtuse_boundary_edges, 1);
        assert_eq!(angles_by_arctangent(&flat).3, 1);
        assert!((q.max_angle_deg - angles_by_arctangent(&flat).1).abs() <= 1e-12);
    }

    #[test]
    fn pseudo_angles_order_corners_as_their_angles() {
        let mut seed = 7u64;
        let mut corners: Vec<(f64, f64)> = vec![(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (0.0, 0.0)];
        for _ in 0..2000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let a = (seed % 1_000_000) as f64 / 1_000_000.0 * std::f64::consts::PI;
            let r = 1.0 + (seed % 97) as f64;
            corners.push((r * a.sin().abs(), r * a.cos()));
        }
        for &(y1, x1) in &corners {
            for &(y2, x2) in corners.iter().step_by(7) {
                let (a1, a2) = (y1.atan2(x1), y2.atan2(x2));
                if (a1 - a2).abs() > 1e-12 {
                    assert_eq!(
                        pseudo_angle(y1, x1) < pseudo_angle(y2, x2),
                        a1 < a2,
                        "({y1}, {x1}) against ({y2}, {x2})"
                    );
                }
            }
        }
    }

    #[test]
    fn adjacency_and_boundary() {
        let m = unit_square();
        assert_eq!(m.neighbors()[0][1], 1); // edge (2,0) of triangle 0 is shared
        assert_eq!(m.neighbors()[1][2], 0);
        assert_eq!(m.boundary_edges().len(), 4);
        let e = m
            .boundary_edge_of(1, 0)
            .expect("edge 2-3 is on the boundary");
        assert_eq!(e.tag, BoundaryTag::Goal(0));
        assert_eq!(e.vertices, [2, 3]);
        assert_eq!(m.vertex_tags()[2], Some(BoundaryTag::Goal(0)));
        assert_eq!(m.vertex_tags()[0], Some(BoundaryTag::Wall));
        assert_eq!(m.component_count(), 1);
    }

    #[test]
    fn rejects_clockwise_and_untagged() {
        let v = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
        ];
        assert!(Mesh::from_parts(v.clone(), vec![[0, 2, 1]], &[]).is_err());
        assert!(Mesh::from_parts(v, vec![[0, 1, 2]], &[(0, 1, BoundaryTag::Wall)]).is_err());
    }

    #[test]
    fn an_edge_used_twice_in_one_direction_is_refused() {
        let p = Point::new;
        // Two triangles on the same side of edge 0 -> 1 (overlapping).
        let v = vec![p(0.0, 0.0), p(1.0, 0.0), p(0.5, 1.0), p(0.4, 0.5)];
        let e = Mesh::from_parts(v.clone(), vec![[0, 1, 2], [0, 1, 3]], &[]).unwrap_err();
        assert!(e.to_string().contains("edge (0, 1) is used twice"), "{e}");
        // The same around a vertex with a star larger than 16 triangles: a fan of 20
        // triangles around vertex 0, plus one repeating the fan's first edge.
        let mut v = vec![p(0.0, 0.0)];
        v.extend((0..=20).map(|i| {
            let t = 0.1 + 0.07 * i as f64;
            p(t.cos(), t.sin())
        }));
        let mut tris: Vec<[u32; 3]> = (1..=20).map(|i| [0, i, i + 1]).collect();
        v.push(p(0.9, 0.3));
        tris.push([0, 1, 22]);
        let e = Mesh::from_parts(v, tris, &[]).unwrap_err();
        assert!(e.to_string().contains("is used twice"), "{e}");
    }
}
