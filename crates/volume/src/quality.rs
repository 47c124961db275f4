//! Mesh quality: dihedral angles, volumes, and the sign of the P1 stiffness edge weights
//! (the cotangent weights whose negativity breaks the discrete maximum principle).

use serde::Serialize;

use harmonic_types::{EDGES, TetEdges, TetMesh, Vector3 as Vector};

/// A summary of a mesh's shape quality.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct QualityReport {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of tetrahedra.
    pub tetrahedra: usize,
    /// Number of boundary faces.
    pub boundary_faces: usize,
    /// Smallest dihedral angle, degrees.
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle, degrees.
    pub max_dihedral_deg: f64,
    /// Smallest tetrahedron volume.
    pub min_volume: f64,
    /// Largest tetrahedron volume.
    pub max_volume: f64,
    /// Number of distinct mesh edges.
    pub edges: usize,
    /// Edges whose summed stiffness weight `−K_ij = −Σ_T V_T ∇λ_i·∇λ_j` is negative beyond
    /// round-off (`1e-12` of the largest weight at either end): each is a positive
    /// off-diagonal entry of the stiffness matrix if both ends are unknowns.
    pub negative_weight_edges: usize,
    /// Tetrahedra with an obtuse dihedral angle (> 90° + 1e-9).
    pub obtuse_tetrahedra: usize,
}

/// Dihedral angle (radians) of tetrahedron `t` at each of its [`EDGES`], and the stiffness
/// weight `−V ∇λ_i·∇λ_j` of each edge.
pub fn tet_angles_and_weights(mesh: &TetMesh, t: u32) -> ([f64; 6], [f64; 6]) {
    let (g, vol) = mesh.barycentric_gradients(t);
    let mut angles = [0.0; 6];
    for (e, &[i, j]) in EDGES.iter().enumerate() {
        // The dihedral angle at edge (i, j) is between faces k and l (the other two; the
        // four indices sum to 6); the gradients of λ_k and λ_l are inward normals of those
        // faces.
        let k = (0..4).find(|&m| m != i && m != j).unwrap_or(0);
        let l = 6 - i - j - k;
        let (a, b) = (g[k], g[l]);
        let c = (-a.dot(&b) / (a.norm() * b.norm())).clamp(-1.0, 1.0);
        angles[e] = c.acos();
    }
    (angles, weights_of(&g, vol))
}

/// The stiffness weights `−V ∇λ_i·∇λ_j` of a tetrahedron's [`EDGES`], its volume `vol` and
/// its barycentric coordinates' gradients `g`.
fn weights_of(g: &[Vector; 4], vol: f64) -> [f64; 6] {
    EDGES.map(|[i, j]| -vol * g[i].dot(&g[j]))
}

/// Measures `mesh`.
pub fn quality(mesh: &TetMesh) -> QualityReport {
    let mut report = QualityReport {
        vertices: mesh.vertices().len(),
        tetrahedra: mesh.tetrahedra().len(),
        boundary_faces: mesh.boundary_faces().len(),
        min_dihedral_deg: f64::INFINITY,
        max_dihedral_deg: 0.0,
        min_volume: f64::INFINITY,
        max_volume: 0.0,
        edges: 0,
        negative_weight_edges: 0,
        obtuse_tetrahedra: 0,
    };
    // Per tetrahedron (on every core, one gradient computation each): its angles and volume
    // folded into the extremes, its edges' stiffness weights kept for the edge pass.
    use rayon::prelude::*;
    const CHUNK: usize = 1024;
    let mut terms = vec![[0.0f64; 6]; mesh.tetrahedra().len()];
    let part = terms
        .par_chunks_mut(CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut part = Part::EMPTY;
            for (k, out) in chunk.iter_mut().enumerate() {
                let t = (c * CHUNK + k) as u32;
                let (g, vol) = mesh.barycentric_gradients(t);
                *out = weights_of(&g, vol);
                part = part.join(Part::of(mesh, t, &g));
            }
            part
        })
        .reduce(|| Part::EMPTY, Part::join);
    report.min_dihedral_deg = part.min_deg;
    report.max_dihedral_deg = part.max_deg;
    report.min_volume = part.min_vol;
    report.max_volume = part.max_vol;
    report.obtuse_tetrahedra = part.obtuse;
    let (edges, negative) = edge_weight_signs(mesh, &terms);
    report.edges = edges;
    report.negative_weight_edges = negative;
    report
}

/// The number of distinct edges of `mesh`, and of those whose summed stiffness weight is
/// negative beyond round-off (see [`QualityReport::negative_weight_edges`]), from each
/// tetrahedron's six terms (`terms`, as [`tet_angles_and_weights`] gives them).
///
/// The edges are numbered as the assembly numbers them ([`TetEdges`]: a counting sort by
/// the smaller vertex, not a sort of every term) and each one's terms summed in the order
/// of their tetrahedra, whatever the thread count. On me766's 5.58 M tetrahedra this report
/// took 2.7 s of a 12 s `hplan plan` when every term came with six arccosines and the
/// 33.5 M terms were sorted at once.
fn edge_weight_signs(mesh: &TetMesh, terms: &[[f64; 6]]) -> (usize, usize) {
    let tets = mesh.tetrahedra();
    let nv = mesh.vertices().len();
    let TetEdges { edges, of_tet } = mesh.edges();
    let mut sum = vec![0.0f64; edges.len()];
    // The largest term at each vertex: the round-off scale.
    let mut scale = vec![0.0f64; nv];
    for ((tet, w), te) in tets.iter().zip(terms).zip(of_tet) {
        for (e, &[i, j]) in EDGES.iter().enumerate() {
            sum[te[e] as usize] += w[e];
            for v in [tet[i], tet[j]] {
                scale[v as usize] = scale[v as usize].max(w[e].abs());
            }
        }
    }
    let negative = edges
        .iter()
        .zip(&sum)
        .filter(|&(&[a, b], &s)| s < -1e-12 * scale[a as usize].max(scale[b as usize]))
        .count();
    (edges.len(), negative)
}

/// The extremes of every tetrahedron's dihedral angles and volume, and its obtuse count.
#[derive(Clone, Copy)]
struct Part {
    min_deg: f64,
    max_deg: f64,
    min_vol: f64,
    max_vol: f64,
    obtuse: usize,
}

impl Part {
    const EMPTY: Part = Part {
        min_deg: f64::INFINITY,
        max_deg: 0.0,
        min_vol: f64::INFINITY,
        max_vol: 0.0,
        obtuse: 0,
    };

    fn join(self, q: Part) -> Part {
        Part {
            min_deg: self.min_deg.min(q.min_deg),
            max_deg: self.max_deg.max(q.max_deg),
            min_vol: self.min_vol.min(q.min_vol),
            max_vol: self.max_vol.max(q.max_vol),
            obtuse: self.obtuse + q.obtuse,
        }
    }

    /// Tetrahedron `t`, whose barycentric coordinates have the gradients `g`.
    fn of(mesh: &TetMesh, t: u32, g: &[Vector; 4]) -> Part {
        // The six angles' cosines, as `tet_angles_and_weights` computes them; the angle
        // decreases as its cosine grows, so the extremes are the arccosines of the extreme
        // cosines: two arccosines per tetrahedron instead of six, the same numbers.
        let norms = g.map(|v| v.norm());
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &[i, j] in &EDGES {
            let k = (0..4).find(|&m| m != i && m != j).unwrap_or(0);
            let l = 6 - i - j - k;
            let c = (-g[k].dot(&g[l]) / (norms[k] * norms[l])).clamp(-1.0, 1.0);
            lo = lo.min(c);
            hi = hi.max(c);
        }
        let vol = mesh.tet_volume(t);
        if hi < lo {
            // No finite cosine (a degenerate tetrahedron): no angle to report.
            return Part {
                min_vol: vol,
                max_vol: vol,
                ..Part::EMPTY
            };
        }
        let (min_deg, max_deg) = (hi.acos().to_degrees(), lo.acos().to_degrees());
        Part {
            min_deg,
            max_deg,
            min_vol: vol,
            max_vol: vol,
            obtuse: usize::from(max_deg > 90.0 + 1e-9),
        }
    }
}

/// [`quality`]'s angles and volumes only, on every core.
fn shapes(mesh: &TetMesh) -> Part {
    use rayon::prelude::*;
    (0..mesh.tetrahedra().len() as u32)
        .into_par_iter()
        .map(|t| Part::of(mesh, t, &mesh.barycentric_gradients(t).0))
        .reduce(|| Part::EMPTY, Part::join)
}

/// The smallest and the largest dihedral angle of `mesh`, in degrees: [`quality`]'s angles
/// without its edge pass (which sorts six entries per tetrahedron).
pub fn dihedral_range(mesh: &TetMesh) -> [f64; 2] {
    let part = shapes(mesh);
    [part.min_deg, part.max_deg]
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_types::{BoundaryTag, Point3 as Point};

    /// An n³ grid of unit cubes, each cut into Freudenthal's six tetrahedra, every vertex
    /// moved by up to `jitter` along each axis (seeded).
    fn jittered_cubes(n: usize, jitter: f64, seed: u64) -> TetMesh {
        let mut rng = harmonic_fixtures::Rng(seed);
        let mut next = || 2.0 * rng.next_f64() - 1.0;
        let id = |i: usize, j: usize, k: usize| ((k * (n + 1) + j) * (n + 1) + i) as u32;
        let mut vertices = Vec::new();
        for k in 0..=n {
            for j in 0..=n {
                for i in 0..=n {
                    let d = [next(), next(), next()].map(|x| jitter * x);
                    vertices.push(Point::new(
                        i as f64 + d[0],
                        j as f64 + d[1],
                        k as f64 + d[2],
                    ));
                }
            }
        }
        let mut tets = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    for order in [
                        [0, 1, 2],
                        [0, 2, 1],
                        [1, 0, 2],
                        [1, 2, 0],
                        [2, 0, 1],
                        [2, 1, 0],
                    ] {
                        let mut at = [i, j, k];
                        let mut tet = [id(i, j, k), 0, 0, 0];
                        for (s, &axis) in order.iter().enumerate() {
                            at[axis] += 1;
                            tet[s + 1] = id(at[0], at[1], at[2]);
                        }
                        let p = tet.map(|v| vertices[v as usize]);
                        if (p[1] - p[0]).cross(&(p[2] - p[0])).dot(&(p[3] - p[0])) < 0.0 {
                            tet.swap(2, 3);
                        }
                        tets.push(tet);
                    }
                }
            }
        }
        TetMesh::new(vertices, tets, &|_| BoundaryTag::Wall).expect("a jittered lattice")
    }

    /// The edge counts as every tetrahedron term sorted by edge gives them.
    fn by_sorting_every_term(mesh: &TetMesh) -> (usize, usize) {
        let mut entries: Vec<(u64, f64)> = Vec::new();
        for (t, tet) in mesh.tetrahedra().iter().enumerate() {
            let (_, w) = tet_angles_and_weights(mesh, t as u32);
            for (e, &[i, j]) in EDGES.iter().enumerate() {
                let (a, b) = (tet[i].min(tet[j]) as u64, tet[i].max(tet[j]) as u64);
                entries.push((a << 32 | b, w[e]));
            }
        }
        entries.sort_by_key(|e| e.0);
        let mut scale = vec![0.0f64; mesh.vertices().len()];
        for &(k, w) in &entries {
            for v in [k >> 32, k & 0xffff_ffff] {
                scale[v as usize] = scale[v as usize].max(w.abs());
            }
        }
        let (mut edges, mut negative, mut i) = (0, 0, 0);
        while i < entries.len() {
            let k = entries[i].0;
            let mut sum = 0.0;
            while i < entries.len() && entries[i].0 == k {
                sum += entries[i].1;
                i += 1;
            }
            let tol = 1e-12 * scale[(k >> 32) as usize].max(scale[(k & 0xffff_ffff) as usize]);
            edges += 1;
            negative += usize::from(sum < -tol);
        }
        (edges, negative)
    }

    #[test]
    fn negative_weight_edges_agree_with_a_sort_of_every_term() {
        for (jitter, seed) in [(0.0, 1), (0.1, 2), (0.2, 3), (0.25, 4)] {
            let mesh = jittered_cubes(5, jitter, seed);
            let q = quality(&mesh);
            let (edges, negative) = by_sorting_every_term(&mesh);
            assert_eq!(
                (q.edges, q.negative_weight_edges),
                (edges, negative),
                "jitter {jitter}"
            );
            if jitter >= 0.2 {
                assert!(negative > 0, "jitter {jitter}: some weights are negative");
            }
        }
    }
}
