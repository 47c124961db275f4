//! Mesh quality: dihedral angles, volumes, and the sign of the P1 stiffness edge weights
//! (the cotangent weights whose negativity breaks the discrete maximum principle).

use serde::Serialize;

use harmonic_types::{EDGES, TetMesh};

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
    let mut weights = [0.0; 6];
    for (e, &[i, j]) in EDGES.iter().enumerate() {
        weights[e] = -vol * g[i].dot(&g[j]);
        // The dihedral angle at edge (i, j) is between faces k and l (the other two; the
        // four indices sum to 6); the gradients of λ_k and λ_l are inward normals of those
        // faces.
        let k = (0..4).find(|&m| m != i && m != j).unwrap_or(0);
        let l = 6 - i - j - k;
        let (a, b) = (g[k], g[l]);
        let c = (-a.dot(&b) / (a.norm() * b.norm())).clamp(-1.0, 1.0);
        angles[e] = c.acos();
    }
    (angles, weights)
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
    // Per tetrahedron (on every core): its angles and volume folded into the extremes, then
    // its edges with their stiffness weights.
    use rayon::prelude::*;
    let part = shapes(mesh);
    report.min_dihedral_deg = part.min_deg;
    report.max_dihedral_deg = part.max_deg;
    report.min_volume = part.min_vol;
    report.max_volume = part.max_vol;
    report.obtuse_tetrahedra = part.obtuse;
    let mut edges: Vec<(u64, f64)> = vec![(0, 0.0); 6 * mesh.tetrahedra().len()];
    edges
        .par_chunks_mut(6)
        .zip(mesh.tetrahedra().par_iter())
        .enumerate()
        .for_each(|(t, (out, tet))| {
            let (_, weights) = tet_angles_and_weights(mesh, t as u32);
            for (e, slot) in out.iter_mut().enumerate() {
                let [i, j] = EDGES[e];
                let (a, b) = (tet[i].min(tet[j]) as u64, tet[i].max(tet[j]) as u64);
                *slot = (a << 32 | b, weights[e]);
            }
        });
    // In place, and in one order at any thread count: by edge, then by the weight's bits.
    edges.par_sort_unstable_by_key(|e| (e.0, e.1.to_bits()));
    // Largest |weight| at each vertex, for the round-off tolerance.
    let mut scale = vec![0.0f64; mesh.vertices().len()];
    for &(k, w) in &edges {
        for v in [k >> 32, k & 0xffff_ffff] {
            scale[v as usize] = scale[v as usize].max(w.abs());
        }
    }
    let mut i = 0;
    while i < edges.len() {
        let mut j = i;
        let mut sum = 0.0;
        while j < edges.len() && edges[j].0 == edges[i].0 {
            sum += edges[j].1;
            j += 1;
        }
        let k = edges[i].0;
        let tol = 1e-12 * scale[(k >> 32) as usize].max(scale[(k & 0xffff_ffff) as usize]);
        report.edges += 1;
        if sum < -tol {
            report.negative_weight_edges += 1;
        }
        i = j;
    }
    report
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

/// The first half of [`quality`]: angles and volumes only, on every core.
fn shapes(mesh: &TetMesh) -> Part {
    use rayon::prelude::*;
    let empty = Part {
        min_deg: f64::INFINITY,
        max_deg: 0.0,
        min_vol: f64::INFINITY,
        max_vol: 0.0,
        obtuse: 0,
    };
    let join = |p: Part, q: Part| Part {
        min_deg: p.min_deg.min(q.min_deg),
        max_deg: p.max_deg.max(q.max_deg),
        min_vol: p.min_vol.min(q.min_vol),
        max_vol: p.max_vol.max(q.max_vol),
        obtuse: p.obtuse + q.obtuse,
    };
    (0..mesh.tetrahedra().len() as u32)
        .into_par_iter()
        .map(|t| {
            // The six angles' cosines, as `tet_angles_and_weights` computes them; the angle
            // decreases as its cosine grows, so the extremes are the arccosines of the
            // extreme cosines: two arccosines per tetrahedron instead of six, the same
            // numbers.
            let (g, _) = mesh.barycentric_gradients(t);
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
                    ..empty
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
        })
        .reduce(|| empty, join)
}

/// The smallest and the largest dihedral angle of `mesh`, in degrees: [`quality`]'s angles
/// without its edge pass (which sorts six entries per tetrahedron).
pub fn dihedral_range(mesh: &TetMesh) -> [f64; 2] {
    let part = shapes(mesh);
    [part.min_deg, part.max_deg]
}
