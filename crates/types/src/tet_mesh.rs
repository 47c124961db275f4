//! The tetrahedral mesh: vertices, positively oriented tetrahedra, face adjacency and tagged
//! boundary faces.

use std::sync::OnceLock;

use crate::error::{Element, MeshDataError};
use crate::tet_locate::Locator;
use crate::{BoundaryTag, NO_NEIGHBOR, Point3 as Point, Vector3 as Vector};

/// The six edges of a tetrahedron as local vertex pairs.
pub const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// The faces of a tetrahedron `[v0, v1, v2, v3]`: face `k` is opposite vertex `k`, its local
/// vertices ordered so that its normal (right-hand rule) points out of the tetrahedron.
pub const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// Signed volume of the tetrahedron `abcd`: positive when `d` lies on the side of the
/// triangle `abc` its right-hand normal points to (1/6 for `0, e₁, e₂, e₃`).
pub fn signed_volume(a: &Point, b: &Point, c: &Point, d: &Point) -> f64 {
    (b - a).dot(&(c - a).cross(&(d - a))) / 6.0
}

/// Checks a mesh's parts: finite vertices, tetrahedra that refer to them and are positively
/// oriented.
pub fn check_tetrahedra(vertices: &[Point], tets: &[[u32; 4]]) -> Result<(), MeshDataError> {
    let nv = vertices.len();
    if let Some(i) = vertices
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(MeshDataError::NonFiniteVertex { vertex: i });
    }
    for (t, tet) in tets.iter().enumerate() {
        if let Some(&v) = tet.iter().find(|&&v| v as usize >= nv) {
            return Err(MeshDataError::VertexOutOfRange {
                element: Element::Tetrahedron,
                index: t,
                vertex: v,
                vertices: nv,
            });
        }
        let [a, b, c, d] = tet.map(|v| vertices[v as usize]);
        if signed_volume(&a, &b, &c, &d) <= 0.0 {
            return Err(MeshDataError::NotPositive {
                element: Element::Tetrahedron,
                index: t,
                vertices: *tet,
            });
        }
    }
    Ok(())
}

/// The face adjacency of `tets` (vertex indices checked): per tetrahedron, the tetrahedron
/// across face `k`, or [`NO_NEIGHBOR`]. A face belongs to its smallest vertex, and both
/// tetrahedra that share it hold that vertex: so the tetrahedra are grouped by vertex
/// ([`Grouped::tets_around`](crate::Grouped::tets_around), four `u32` per tetrahedron), and each
/// vertex pairs the faces it owns among its few tens of tetrahedra by sorting their other two
/// vertices — the vertices on every core, each face found by exactly one of them, so the
/// result does not depend on the thread count. Measured on me766's 5.58 M tetrahedra (2
/// cores): 0.36–0.48 s (grouping 0.09–0.17 s, pairing 0.27–0.30 s), against 0.78–0.85 s
/// when every face's 16-byte key was placed, one thread, in an array bucketed by its smallest
/// vertex (22.3 M keys, 357 MB). A face shared by more than two tetrahedra is an error (the
/// one with the smallest vertex triple).
pub fn face_neighbors(tets: &[[u32; 4]]) -> Result<Vec<[u32; 4]>, MeshDataError> {
    let nv = tets
        .iter()
        .flatten()
        .copied()
        .max()
        .map_or(0, |m| m as usize + 1);
    face_neighbors_around(tets, &crate::Grouped::tets_around(nv, tets))
}

/// [`face_neighbors`] with the tetrahedra around each vertex given: `around` must be
/// [`Grouped::tets_around`](crate::Grouped::tets_around) of these `tets` (as
/// [`TetMesh::tets_around`] keeps it).
pub fn face_neighbors_around(
    tets: &[[u32; 4]],
    around: &crate::Grouped<u32>,
) -> Result<Vec<[u32; 4]>, MeshDataError> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicU32, Ordering};
    let nv = around.start.len() - 1;
    let neighbors: Vec<[AtomicU32; 4]> = (0..tets.len())
        .into_par_iter()
        .map(|_| std::array::from_fn(|_| AtomicU32::new(NO_NEIGHBOR)))
        .collect();
    // The faces vertex `a` owns: (other two vertices ascending, tetrahedron, local face).
    let pair = |a: usize, faces: &mut Vec<u128>| -> Option<MeshDataError> {
        faces.clear();
        let a32 = a as u32;
        for &t in around.of(a) {
            let tet = &tets[t as usize];
            for (k, f) in FACES.iter().enumerate() {
                let [x, y, z] = f.map(|l| tet[l]);
                let (lo, hi) = if x == a32 {
                    (y.min(z), y.max(z))
                } else if y == a32 {
                    (x.min(z), x.max(z))
                } else if z == a32 {
                    (x.min(y), x.max(y))
                } else {
                    continue;
                };
                if lo > a32 {
                    faces.push(
                        (lo as u128) << 64 | (hi as u128) << 32 | (t << 2 | k as u32) as u128,
                    );
                }
            }
        }
        faces.sort_unstable();
        let side = |x: u128| ((x as u32 >> 2) as usize, (x as u32 & 3) as usize);
        let mut i = 0;
        while i < faces.len() {
            let mut j = i + 1;
            while j < faces.len() && faces[j] >> 32 == faces[i] >> 32 {
                j += 1;
            }
            match j - i {
                1 => {}
                2 => {
                    let ((t0, k0), (t1, k1)) = (side(faces[i]), side(faces[i + 1]));
                    neighbors[t0][k0].store(t1 as u32, Ordering::Relaxed);
                    neighbors[t1][k1].store(t0 as u32, Ordering::Relaxed);
                }
                n => {
                    let k = faces[i] >> 32;
                    return Some(MeshDataError::FaceSharedTooOften {
                        face: [a32, (k >> 32) as u32, k as u32],
                        count: n,
                    });
                }
            }
            i = j;
        }
        None
    };
    let runs = crate::grouped::vertex_runs(nv);
    if let Some(e) = runs.par_iter().find_map_first(|&(v0, v1)| {
        let mut faces = Vec::new();
        (v0..v1).find_map(|a| pair(a, &mut faces))
    }) {
        return Err(e);
    }
    Ok(neighbors
        .into_par_iter()
        .map(|n| n.map(AtomicU32::into_inner))
        .collect())
}

/// `cell`'s value, computed by `f` where it has none yet. Not `OnceLock::get_or_init`: `f`
/// runs on every core (rayon), and while the thread computing it waits for its own parallel
/// tasks, rayon may hand it another task that asks for the same cell (the volume planner
/// asks for a mesh's tables from both sides of a `join`; tracing many starts at once asks
/// for the point locator from each): inside `get_or_init` that re-entrant initialisation
/// deadlocks. Here two asks at once both compute, the same value, and the first one done is
/// kept.
fn computed_once<T>(cell: &OnceLock<T>, f: impl FnOnce() -> T) -> &T {
    if let Some(v) = cell.get() {
        return v;
    }
    let v = f();
    cell.get_or_init(|| v)
}

/// One boundary face of the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryFace {
    /// The face's vertices, ordered so that the normal points out of free space (into the
    /// wall, obstacle or goal).
    pub vertices: [u32; 3],
    /// The tetrahedron it bounds.
    pub tet: u32,
    /// The local face index `k` in `tet` (the face opposite local vertex `k`).
    pub local_face: u8,
    /// Which part of the boundary it lies on.
    pub tag: BoundaryTag,
}

/// A tetrahedral mesh of free space.
#[derive(Debug)]
pub struct TetMesh {
    vertices: Vec<Point>,
    tets: Vec<[u32; 4]>,
    neighbors: Vec<[u32; 4]>,
    boundary: Vec<BoundaryFace>,
    /// Per tetrahedron face: index into `boundary`, or `NO_NEIGHBOR`.
    face_boundary: Vec<[u32; 4]>,
    on_boundary: Vec<bool>,
    locator: OnceLock<Locator>,
    around: OnceLock<crate::Grouped<u32>>,
    edges: OnceLock<crate::TetEdges>,
}

impl TetMesh {
    /// A mesh from its vertices and tetrahedra; boundary faces (faces of one tetrahedron only)
    /// are tagged by `tag(centroid of the face)`. Checks indices, finiteness, that every
    /// tetrahedron has positive volume and that no face is shared by more than two.
    pub fn new(
        vertices: Vec<Point>,
        tets: Vec<[u32; 4]>,
        tag: &dyn Fn(&Point) -> BoundaryTag,
    ) -> Result<Self, MeshDataError> {
        let nv = vertices.len();
        // Faces are numbered 4·t + k in 32 bits.
        if nv >= NO_NEIGHBOR as usize || tets.len() >= 1 << 30 {
            return Err(MeshDataError::TooLarge {
                element: Element::Tetrahedron,
                vertices: nv,
                elements: tets.len(),
            });
        }
        check_tetrahedra(&vertices, &tets)?;
        let around = crate::Grouped::tets_around(nv, &tets);
        let neighbors = face_neighbors_around(&tets, &around)?;
        let mesh = Self::with_neighbors(vertices, tets, neighbors, &mut |_, _, c| tag(c));
        // Kept: the assembly numbers the edges and the tracer walks around vertices with it.
        let _ = mesh.around.set(around);
        Ok(mesh)
    }

    /// A mesh from parts already checked and their face adjacency (as [`face_neighbors`]
    /// finds it); every face without a neighbour is a boundary face, tagged by
    /// `tag(tetrahedron, local face, centroid of the face)`.
    pub fn with_neighbors(
        vertices: Vec<Point>,
        tets: Vec<[u32; 4]>,
        neighbors: Vec<[u32; 4]>,
        tag: &mut dyn FnMut(u32, usize, &Point) -> BoundaryTag,
    ) -> Self {
        let mut face_boundary = vec![[NO_NEIGHBOR; 4]; tets.len()];
        let mut boundary = Vec::new();
        let mut on_boundary = vec![false; vertices.len()];
        for (t, across) in neighbors.iter().enumerate() {
            for (k, &n) in across.iter().enumerate() {
                if n != NO_NEIGHBOR {
                    continue;
                }
                let f = FACES[k].map(|l| tets[t][l]);
                let c = Point::from(
                    (vertices[f[0] as usize].coords
                        + vertices[f[1] as usize].coords
                        + vertices[f[2] as usize].coords)
                        / 3.0,
                );
                face_boundary[t][k] = boundary.len() as u32;
                for &v in &f {
                    on_boundary[v as usize] = true;
                }
                boundary.push(BoundaryFace {
                    vertices: f,
                    tet: t as u32,
                    local_face: k as u8,
                    tag: tag(t as u32, k, &c),
                });
            }
        }
        TetMesh {
            vertices,
            tets,
            neighbors,
            boundary,
            face_boundary,
            on_boundary,
            locator: OnceLock::new(),
            around: OnceLock::new(),
            edges: OnceLock::new(),
        }
    }

    /// Sets the tag of boundary face `i` (an index into [`boundary_faces`](Self::boundary_faces)).
    pub fn set_tag(&mut self, i: usize, tag: BoundaryTag) {
        self.boundary[i].tag = tag;
    }

    /// Gives each boundary face the tag `retag` returns for it (its corners and its current
    /// tag): how a goal's faces are kept to those wholly inside it, which the centroid alone
    /// cannot tell.
    pub fn retag(&mut self, retag: &dyn Fn(&[Point; 3], BoundaryTag) -> BoundaryTag) {
        for f in &mut self.boundary {
            let corners = f.vertices.map(|v| self.vertices[v as usize]);
            f.tag = retag(&corners, f.tag);
        }
    }

    /// The tetrahedra around each vertex, ascending
    /// ([`Grouped::tets_around`](crate::Grouped::tets_around); kept from [`TetMesh::new`],
    /// else built on first use).
    pub fn tets_around(&self) -> &crate::Grouped<u32> {
        computed_once(&self.around, || {
            crate::Grouped::tets_around(self.vertices.len(), &self.tets)
        })
    }

    /// The edges and each tetrahedron's edges among them
    /// ([`TetEdges::around`](crate::TetEdges::around)), built on first use and kept: the
    /// assembly and the quality report share them.
    pub fn edges(&self) -> &crate::TetEdges {
        computed_once(&self.edges, || {
            crate::TetEdges::around(&self.tets, self.tets_around())
        })
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }
    /// The tetrahedra, positively oriented.
    pub fn tetrahedra(&self) -> &[[u32; 4]] {
        &self.tets
    }
    /// Per tetrahedron, the tetrahedron across face `k` (opposite local vertex `k`), or
    /// [`NO_NEIGHBOR`].
    pub fn neighbors(&self) -> &[[u32; 4]] {
        &self.neighbors
    }
    /// The boundary faces.
    pub fn boundary_faces(&self) -> &[BoundaryFace] {
        &self.boundary
    }
    /// The boundary face on local face `k` of tetrahedron `t`, if that face is on the boundary.
    pub fn boundary_face(&self, t: u32, k: usize) -> Option<&BoundaryFace> {
        let i = self.face_boundary[t as usize][k];
        (i != NO_NEIGHBOR).then(|| &self.boundary[i as usize])
    }
    /// Whether vertex `v` lies on a boundary face.
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        self.on_boundary[v as usize]
    }
    /// The four corners of tetrahedron `t`.
    pub fn tet_points(&self, t: u32) -> [Point; 4] {
        self.tets[t as usize].map(|v| self.vertices[v as usize])
    }
    /// The volume of tetrahedron `t`.
    pub fn tet_volume(&self, t: u32) -> f64 {
        let [a, b, c, d] = self.tet_points(t);
        signed_volume(&a, &b, &c, &d)
    }
    /// The total volume.
    pub fn volume(&self) -> f64 {
        (0..self.tets.len() as u32)
            .map(|t| self.tet_volume(t))
            .sum()
    }

    /// The gradients of the four barycentric coordinates of tetrahedron `t` (constant on it)
    /// and its volume: `∇λ_k = −A_k / (3V)` with `A_k` the outward area vector of face `k`.
    pub fn barycentric_gradients(&self, t: u32) -> ([Vector; 4], f64) {
        let p = self.tet_points(t);
        let vol = signed_volume(&p[0], &p[1], &p[2], &p[3]);
        let g = FACES.map(|f| {
            let area = (p[f[1]] - p[f[0]]).cross(&(p[f[2]] - p[f[0]])) * 0.5;
            -area / (3.0 * vol)
        });
        (g, vol)
    }

    /// The barycentric coordinates of `p` in tetrahedron `t`.
    pub fn barycentric(&self, t: u32, p: &Point) -> [f64; 4] {
        let q = self.tet_points(t);
        let vol = signed_volume(&q[0], &q[1], &q[2], &q[3]);
        let mut l = [0.0; 4];
        for (k, lk) in l.iter_mut().enumerate() {
            let mut r = q;
            r[k] = *p;
            *lk = signed_volume(&r[0], &r[1], &r[2], &r[3]) / vol;
        }
        l
    }

    /// Builds the bucket grid [`TetMesh::locate`] falls back on, if it is not built yet: a
    /// planner does it while it builds (beside its solve), so that its first query does not.
    pub fn prepare_locate(&self) {
        if !self.tets.is_empty() {
            computed_once(&self.locator, || Locator::new(self));
        }
    }

    /// The tetrahedron holding `p` (on its boundary counts), walking from `hint` when given
    /// and falling back on a bucket grid; `None` if `p` is outside the mesh.
    pub fn locate(&self, p: &Point, hint: Option<u32>) -> Option<u32> {
        if !p.iter().all(|c| c.is_finite()) || self.tets.is_empty() {
            return None;
        }
        if let Some(t) = hint.filter(|&t| (t as usize) < self.tets.len())
            && let Some(t) = self.walk(p, t)
        {
            return Some(t);
        }
        computed_once(&self.locator, || Locator::new(self)).locate(self, p)
    }

    /// Walks from `start` toward `p` across faces; `None` if the walk leaves the mesh or
    /// takes too long.
    pub fn walk(&self, p: &Point, start: u32) -> Option<u32> {
        let mut t = start;
        let limit = 64 + 4 * (self.tets.len() as f64).cbrt() as usize;
        for _ in 0..limit {
            let l = self.barycentric(t, p);
            let (k, &m) = l.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1))?;
            if m >= -1e-12 {
                return Some(t);
            }
            let n = self.neighbors[t as usize][k];
            if n == NO_NEIGHBOR {
                return None;
            }
            t = n;
        }
        None
    }

    /// The axis-aligned bounding box of the vertices.
    pub fn bounds(&self) -> (Point, Point) {
        let mut lo = Point::from(Vector::repeat(f64::INFINITY));
        let mut hi = Point::from(Vector::repeat(f64::NEG_INFINITY));
        for p in &self.vertices {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube cut into 6 tetrahedra around the diagonal 0–6 (Kuhn).
    pub(crate) fn kuhn_cube() -> TetMesh {
        let v: Vec<Point> = (0..8)
            .map(|i| Point::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        let paths = [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]];
        let tets = paths
            .iter()
            .map(|&[a, b]| {
                let mut t = [0u32, a, b, 7];
                let p = t.map(|i| v[i as usize]);
                if signed_volume(&p[0], &p[1], &p[2], &p[3]) < 0.0 {
                    t.swap(1, 2);
                }
                t
            })
            .collect();
        TetMesh::new(v, tets, &|p: &Point| {
            if p.z < 1e-9 {
                BoundaryTag::Goal(0)
            } else {
                BoundaryTag::Wall
            }
        })
        .unwrap()
    }

    /// Bucketed face matching against every pair of tetrahedra compared face by face, on
    /// the Kuhn cube and on a strip of cubes with shuffled vertex numbers; a face shared by
    /// three tetrahedra is named by its vertices.
    #[test]
    fn face_neighbors_match_a_pairwise_search() {
        let faces_of = |t: &[u32; 4]| {
            FACES.map(|f| {
                let mut k = [t[f[0]], t[f[1]], t[f[2]]];
                k.sort_unstable();
                k
            })
        };
        let brute = |tets: &[[u32; 4]]| {
            let mut out = vec![[NO_NEIGHBOR; 4]; tets.len()];
            for (a, ta) in tets.iter().enumerate() {
                for (b, tb) in tets.iter().enumerate() {
                    for (k, fa) in faces_of(ta).iter().enumerate() {
                        if a != b && faces_of(tb).contains(fa) {
                            out[a][k] = b as u32;
                        }
                    }
                }
            }
            out
        };
        let cube = kuhn_cube().tetrahedra().to_vec();
        // Four cubes side by side along x, vertices renumbered by a permutation.
        let perm = |v: u32| (v * 7 + 3) % 40;
        let strip: Vec<[u32; 4]> = (0..4u32)
            .flat_map(|c| {
                cube.iter().map(move |t| {
                    t.map(|v| {
                        let (x, rest) = (v & 1, v >> 1);
                        perm((c + x) * 4 + rest)
                    })
                })
            })
            .collect();
        for tets in [cube.clone(), strip] {
            assert_eq!(face_neighbors(&tets).unwrap(), brute(&tets));
        }
        let mut three = cube;
        three.push([0, 1, 3, 7]);
        three.push([0, 1, 3, 6]);
        match face_neighbors(&three) {
            Err(MeshDataError::FaceSharedTooOften { face, count }) => {
                assert_eq!((face, count), ([0, 1, 3], 3));
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn cube_adjacency_and_location() {
        let m = kuhn_cube();
        assert_eq!(m.tetrahedra().len(), 6);
        assert_eq!(m.boundary_faces().len(), 12);
        assert_eq!(
            m.boundary_faces()
                .iter()
                .filter(|f| f.tag == BoundaryTag::Goal(0))
                .count(),
            2
        );
        assert!((m.volume() - 1.0).abs() < 1e-15);
        // Outward boundary normals.
        for f in m.boundary_faces() {
            let [a, b, c] = f.vertices.map(|v| m.vertices()[v as usize]);
            let n = (b - a).cross(&(c - a));
            let centroid = (a.coords + b.coords + c.coords) / 3.0;
            assert!(n.dot(&(centroid - Vector::repeat(0.5))) > 0.0);
        }
        let p = Point::new(0.2, 0.7, 0.4);
        let t = m.locate(&p, Some(0)).unwrap();
        assert!(m.barycentric(t, &p).iter().all(|&l| l >= -1e-12));
        assert_eq!(m.locate(&Point::new(1.5, 0.5, 0.5), None), None);
        // Gradients of the barycentric coordinates sum to zero and reproduce x.
        let (g, _) = m.barycentric_gradients(t);
        let sum: Vector = g.iter().sum();
        assert!(sum.norm() < 1e-14);
        let gx: Vector = (0..4)
            .map(|k| g[k] * m.vertices()[m.tetrahedra()[t as usize][k] as usize].x)
            .sum();
        assert!((gx - Vector::x()).norm() < 1e-14);
    }

    #[test]
    fn inverted_tetrahedra_are_refused() {
        let v = vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
            Point::new(0.0, 0.0, 1.0),
        ];
        let e = TetMesh::new(v, vec![[0, 2, 1, 3]], &|_: &Point| BoundaryTag::Wall).unwrap_err();
        assert!(e.to_string().contains("not positively oriented"), "{e}");
    }
}
