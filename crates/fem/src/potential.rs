//! The solved potential: nodal values of ψ = c − φ on a mesh, point evaluation, gradients,
//! recovery, an error indicator and the discrete maximum principle check.

use std::sync::{Arc, OnceLock};

use harmonic_mesh::{Mesh, NO_NEIGHBOR, Point, Vector, orient2d};

use crate::FemError;

/// A P1 potential on a mesh, stored as ψ = c − φ at every vertex (see the crate docs).
///
/// The robot ascends ψ, i.e. descends φ: the direction of motion is
/// [`Evaluation::grad_psi`] = −∇φ.
#[derive(Clone, Debug)]
pub struct Potential {
    mesh: Arc<Mesh>,
    psi: Vec<f64>,
    reference: f64,
    nodal_gradients: OnceLock<Vec<Vector>>,
}

/// The potential at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evaluation {
    /// The triangle containing the point (pass it as the next `hint`).
    pub triangle: u32,
    /// ψ = c − φ, linearly interpolated.
    pub psi: f64,
    /// φ, linearly interpolated.
    pub phi: f64,
    /// ∇ψ = −∇φ on the triangle (constant per triangle).
    pub grad_psi: Vector,
}

impl Potential {
    /// A potential from ψ at every vertex of `mesh` and the reference value `c` (φ = c − ψ).
    pub fn new(mesh: Arc<Mesh>, psi: Vec<f64>, reference: f64) -> Result<Self, FemError> {
        if psi.len() != mesh.vertices().len() {
            return Err(FemError::LengthMismatch {
                what: "ψ values per mesh vertex",
                expected: mesh.vertices().len(),
                got: psi.len(),
            });
        }
        Ok(Potential {
            mesh,
            psi,
            reference,
            nodal_gradients: OnceLock::new(),
        })
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }
    /// ψ = c − φ at every vertex.
    pub fn psi(&self) -> &[f64] {
        &self.psi
    }
    /// The reference value `c`.
    pub fn reference(&self) -> f64 {
        self.reference
    }
    /// φ = c − ψ at every vertex (loses ψ's relative precision where φ ≈ c).
    pub fn phi_at_vertices(&self) -> Vec<f64> {
        self.psi.iter().map(|&s| self.reference - s).collect()
    }

    /// ∇ψ on triangle `t` (= −∇φ). Panics if `t` is out of range.
    pub fn triangle_gradient_psi(&self, t: u32) -> Vector {
        let tri = self.mesh.triangles()[t as usize];
        let [p0, p1, p2] = self.mesh.triangle_points(t);
        let [s0, s1, s2] = tri.map(|v| self.psi[v as usize]);
        // ∇λ_k = rot90(p_{k+2} − p_{k+1}) / 2A; sum ψ_k ∇λ_k.
        let rot = |d: Vector| Vector::new(-d.y, d.x);
        (rot(p2 - p1) * s0 + rot(p0 - p2) * s1 + rot(p1 - p0) * s2) / orient2d(p0, p1, p2)
    }

    /// ∇ψ on every triangle.
    pub fn triangle_gradients_psi(&self) -> Vec<Vector> {
        (0..self.mesh.triangles().len() as u32)
            .map(|t| self.triangle_gradient_psi(t))
            .collect()
    }

    /// Recovered nodal gradients of ψ: the area-weighted average of the gradients of the
    /// triangles around each vertex (zero at vertices used by no triangle). Computed once.
    pub fn nodal_gradients_psi(&self) -> &[Vector] {
        self.nodal_gradients.get_or_init(|| {
            let nv = self.mesh.vertices().len();
            let mut sum = vec![Vector::zeros(); nv];
            let mut area = vec![0.0; nv];
            for (t, tri) in self.mesh.triangles().iter().enumerate() {
                let a = self.mesh.triangle_area(t as u32);
                let g = self.triangle_gradient_psi(t as u32) * a;
                for &v in tri {
                    sum[v as usize] += g;
                    area[v as usize] += a;
                }
            }
            sum.iter()
                .zip(&area)
                .map(|(&s, &a)| if a > 0.0 { s / a } else { s })
                .collect()
        })
    }

    /// The triangle containing `p` (`hint`: a triangle near `p`, e.g. the previous one).
    pub fn locate(&self, p: Point, hint: Option<u32>) -> Result<u32, FemError> {
        self.mesh
            .locate(p, hint)
            .ok_or(FemError::OutsideMesh { x: p.x, y: p.y })
    }

    /// Barycentric coordinates of `p` in triangle `t` (negative outside it).
    fn barycentric(&self, t: u32, p: Point) -> [f64; 3] {
        let [a, b, c] = self.mesh.triangle_points(t);
        let area = orient2d(a, b, c);
        [
            orient2d(p, b, c) / area,
            orient2d(a, p, c) / area,
            orient2d(a, b, p) / area,
        ]
    }

    /// ψ interpolated on triangle `t` at `p` (linear extrapolation if `p` is outside `t`).
    pub fn psi_in_triangle(&self, t: u32, p: Point) -> f64 {
        let l = self.barycentric(t, p);
        let tri = self.mesh.triangles()[t as usize];
        (0..3).map(|k| l[k] * self.psi[tri[k] as usize]).sum()
    }

    /// Value and gradient at `p`.
    pub fn evaluate(&self, p: Point, hint: Option<u32>) -> Result<Evaluation, FemError> {
        let t = self.locate(p, hint)?;
        let psi = self.psi_in_triangle(t, p);
        Ok(Evaluation {
            triangle: t,
            psi,
            phi: self.reference - psi,
            grad_psi: self.triangle_gradient_psi(t),
        })
    }

    /// ψ at `p`.
    pub fn psi_at(&self, p: Point, hint: Option<u32>) -> Result<f64, FemError> {
        Ok(self.evaluate(p, hint)?.psi)
    }

    /// φ at `p`.
    pub fn phi_at(&self, p: Point, hint: Option<u32>) -> Result<f64, FemError> {
        Ok(self.evaluate(p, hint)?.phi)
    }

    /// The recovered (continuous, piecewise linear) gradient of ψ at `p`: the nodal gradients
    /// of [`nodal_gradients_psi`](Self::nodal_gradients_psi) interpolated linearly.
    pub fn recovered_gradient_psi_at(
        &self,
        p: Point,
        hint: Option<u32>,
    ) -> Result<Vector, FemError> {
        let t = self.locate(p, hint)?;
        let l = self.barycentric(t, p);
        let g = self.nodal_gradients_psi();
        let tri = self.mesh.triangles()[t as usize];
        Ok((0..3).map(|k| g[tri[k] as usize] * l[k]).sum())
    }

    /// A per-triangle error indicator: η_T = (½ Σ_e |e|² [∂ψ/∂n]_e²)^½ over the interior
    /// edges `e` of `T`, with `[∂ψ/∂n]` the jump of the normal gradient across `e` (the edge
    /// part of the standard residual estimator; the element residual vanishes for P1).
    pub fn error_indicator(&self) -> Vec<f64> {
        let grads = self.triangle_gradients_psi();
        let mesh = &*self.mesh;
        mesh.triangles()
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let mut sum = 0.0;
                for k in 0..3 {
                    let nb = mesh.neighbors()[t][k];
                    if nb == NO_NEIGHBOR {
                        continue;
                    }
                    let d = mesh.vertices()[tri[(k + 2) % 3] as usize]
                        - mesh.vertices()[tri[(k + 1) % 3] as usize];
                    // |e| n = (d.y, −d.x); the jump times |e| is (g_T − g_N)·(|e| n).
                    let jump_times_len =
                        (grads[t] - grads[nb as usize]).dot(&Vector::new(d.y, -d.x));
                    sum += 0.5 * jump_times_len * jump_times_len;
                }
                sum.sqrt()
            })
            .collect()
    }

    /// The number of interior vertices (on no boundary) whose φ is a strict local minimum or
    /// maximum among their edge neighbours. Zero for a harmonic potential on a Delaunay mesh
    /// (discrete maximum principle).
    pub fn interior_local_extrema(&self) -> usize {
        let e = interior_local_extrema(&self.mesh, &self.psi);
        e.minima + e.maxima
    }
}

/// Counts of interior vertices where φ (= c − ψ) is a strict local extremum.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LocalExtrema {
    /// Vertices whose φ is below every edge neighbour's (ψ above): where a robot would stop.
    pub minima: usize,
    /// Vertices whose φ is above every edge neighbour's (ψ below).
    pub maxima: usize,
}

/// The strict local extrema of the nodal values `psi` over the interior vertices (on no
/// boundary) of `mesh`, each vertex compared with the vertices it shares an edge with. The
/// discrete maximum principle says both counts are zero for a harmonic potential on a mesh
/// whose stiffness is an M-matrix.
pub fn interior_local_extrema(mesh: &Mesh, psi: &[f64]) -> LocalExtrema {
    interior_local_extrema_except(mesh, psi, |_| false)
}

/// [`interior_local_extrema`] over the interior vertices that are not `excluded`: for a
/// field whose goal is held at interior vertices, which are its maxima of ψ by design.
pub fn interior_local_extrema_except(
    mesh: &Mesh,
    psi: &[f64],
    excluded: impl Fn(u32) -> bool,
) -> LocalExtrema {
    let nv = mesh.vertices().len().min(psi.len());
    // Per vertex: the smallest and largest ψ among its neighbours.
    let mut lo = vec![f64::INFINITY; nv];
    let mut hi = vec![f64::NEG_INFINITY; nv];
    for tri in mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
            if a >= nv || b >= nv {
                continue;
            }
            lo[a] = lo[a].min(psi[b]);
            hi[a] = hi[a].max(psi[b]);
            lo[b] = lo[b].min(psi[a]);
            hi[b] = hi[b].max(psi[a]);
        }
    }
    let tags = mesh.vertex_tags();
    let interior = (0..nv).filter(|&v| tags[v].is_none() && lo[v] <= hi[v] && !excluded(v as u32));
    interior.fold(LocalExtrema::default(), |mut e, v| {
        e.minima += usize::from(psi[v] > hi[v]);
        e.maxima += usize::from(psi[v] < lo[v]);
        e
    })
}

/// The blended field of the ME766 paper: φ = k·φ_a + (1−k)·φ_b, e.g. `a` from a Dirichlet
/// solve and `b` from one with Neumann walls and obstacles. `k` must lie in [0, 1] (a convex
/// combination keeps the maximum principle); both potentials must share the mesh.
///
/// ```
/// # use std::sync::Arc;
/// # use harmonic_fem::{Potential, blend};
/// # use harmonic_mesh::{BoundaryTag, Mesh, Point};
/// # let mesh = Arc::new(Mesh::from_parts(
/// #     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0)],
/// #     vec![[0, 1, 2]],
/// #     &[(0, 1, BoundaryTag::Goal(0)), (1, 2, BoundaryTag::Wall), (2, 0, BoundaryTag::Wall)],
/// # )?);
/// let a = Potential::new(mesh.clone(), vec![1.0, 0.0, 0.5], 1.0)?;
/// let b = Potential::new(mesh, vec![3.0, 1.0, 2.0], 2.0)?;
/// let c = blend(0.25, &a, &b)?;
/// let phi = c.phi_at_vertices();
/// assert!((phi[0] - (0.25 * 0.0 + 0.75 * -1.0)).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn blend(k: f64, a: &Potential, b: &Potential) -> Result<Potential, FemError> {
    if !(0.0..=1.0).contains(&k) {
        return Err(FemError::BadWeight { k });
    }
    let same_mesh = Arc::ptr_eq(&a.mesh, &b.mesh)
        || (a.mesh.vertices() == b.mesh.vertices() && a.mesh.triangles() == b.mesh.triangles());
    if !same_mesh {
        return Err(FemError::DifferentMeshes);
    }
    let psi = a
        .psi
        .iter()
        .zip(&b.psi)
        .map(|(&x, &y)| k * x + (1.0 - k) * y)
        .collect();
    Potential::new(
        Arc::clone(&a.mesh),
        psi,
        k * a.reference + (1.0 - k) * b.reference,
    )
}
