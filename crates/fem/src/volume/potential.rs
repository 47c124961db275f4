//! The solved potential on a tetrahedral mesh: ψ = c − φ at the vertices, point values,
//! constant per-tetrahedron gradients, recovered nodal gradients and the maximum principle
//! check.

use std::sync::{Arc, OnceLock};

use harmonic_types::{Point3 as Point, TetMesh, Vector3 as Vector};

use super::FemError;

/// A P1 potential on a tetrahedral mesh, stored as ψ = c − φ.
#[derive(Clone, Debug)]
pub struct VolumePotential {
    mesh: Arc<TetMesh>,
    psi: Vec<f64>,
    reference: f64,
    nodal_gradients: OnceLock<Vec<Vector>>,
    /// Interior strict local minima of φ and extrema of either kind, counted once.
    extrema: OnceLock<(usize, usize)>,
}

/// The potential at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeEvaluation {
    /// The tetrahedron holding the point (pass it as the next hint).
    pub tet: u32,
    /// ψ, interpolated.
    pub psi: f64,
    /// φ = c − ψ.
    pub phi: f64,
    /// ∇ψ = −∇φ on the tetrahedron.
    pub grad_psi: Vector,
}

impl VolumePotential {
    /// A potential from ψ at every vertex and the reference `c`.
    pub fn new(mesh: Arc<TetMesh>, psi: Vec<f64>, reference: f64) -> Result<Self, FemError> {
        if psi.len() != mesh.vertices().len() {
            return Err(FemError::LengthMismatch {
                what: "ψ values per mesh vertex",
                expected: mesh.vertices().len(),
                got: psi.len(),
            });
        }
        Ok(VolumePotential {
            mesh,
            psi,
            reference,
            nodal_gradients: OnceLock::new(),
            extrema: OnceLock::new(),
        })
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<TetMesh> {
        &self.mesh
    }
    /// ψ at every vertex.
    pub fn psi(&self) -> &[f64] {
        &self.psi
    }
    /// The reference value `c`.
    pub fn reference(&self) -> f64 {
        self.reference
    }
    /// φ = c − ψ at every vertex.
    pub fn phi_at_vertices(&self) -> Vec<f64> {
        self.psi.iter().map(|&s| self.reference - s).collect()
    }

    /// ∇ψ on tetrahedron `t`.
    pub fn tet_gradient_psi(&self, t: u32) -> Vector {
        let (g, _) = self.mesh.barycentric_gradients(t);
        let tet = self.mesh.tetrahedra()[t as usize];
        (0..4).map(|k| g[k] * self.psi[tet[k] as usize]).sum()
    }

    /// ψ, φ and ∇ψ at `p`, locating it from `hint`.
    pub fn evaluate(&self, p: &Point, hint: Option<u32>) -> Result<VolumeEvaluation, FemError> {
        let t = self
            .mesh
            .locate(p, hint)
            .ok_or(FemError::OutsideMesh { at: (*p).into() })?;
        let l = self.mesh.barycentric(t, p);
        let tet = self.mesh.tetrahedra()[t as usize];
        let psi: f64 = (0..4).map(|k| l[k] * self.psi[tet[k] as usize]).sum();
        Ok(VolumeEvaluation {
            tet: t,
            psi,
            phi: self.reference - psi,
            grad_psi: self.tet_gradient_psi(t),
        })
    }

    /// Recovered nodal gradients of ψ: the volume-weighted mean of the gradients of the
    /// tetrahedra around each vertex (computed once).
    pub fn recovered_gradients(&self) -> &[Vector] {
        self.nodal_gradients.get_or_init(|| {
            let nv = self.mesh.vertices().len();
            let mut sum = vec![Vector::zeros(); nv];
            let mut weight = vec![0.0; nv];
            for (t, tet) in self.mesh.tetrahedra().iter().enumerate() {
                let g = self.tet_gradient_psi(t as u32);
                let v = self.mesh.tet_volume(t as u32);
                for &i in tet {
                    sum[i as usize] += g * v;
                    weight[i as usize] += v;
                }
            }
            sum.iter()
                .zip(&weight)
                .map(|(s, &w)| if w > 0.0 { s / w } else { Vector::zeros() })
                .collect()
        })
    }

    /// The number of vertices off the boundary whose ψ is strictly above or strictly below
    /// every neighbour's: zero when the discrete maximum principle holds.
    pub fn interior_local_extrema(&self) -> usize {
        self.counted_extrema().1
    }

    /// The number of vertices off the boundary whose ψ is strictly above every
    /// neighbour's — strict local minima of φ, where a path descending φ would stop short of
    /// the goal (the contract's `interior_local_minima`).
    pub fn interior_local_minima(&self) -> usize {
        self.counted_extrema().0
    }

    /// Off-boundary vertices whose ψ is strictly above every neighbour's, and those strictly
    /// above or below, in one pass over the edges (made at the first call: the planning
    /// solve's check and the report share it).
    fn counted_extrema(&self) -> (usize, usize) {
        *self.extrema.get_or_init(|| {
            let nv = self.mesh.vertices().len();
            let mut lo = vec![f64::INFINITY; nv];
            let mut hi = vec![f64::NEG_INFINITY; nv];
            for tet in self.mesh.tetrahedra() {
                for &[i, j] in &harmonic_types::EDGES {
                    let (a, b) = (tet[i] as usize, tet[j] as usize);
                    lo[a] = lo[a].min(self.psi[b]);
                    hi[a] = hi[a].max(self.psi[b]);
                    lo[b] = lo[b].min(self.psi[a]);
                    hi[b] = hi[b].max(self.psi[a]);
                }
            }
            let (mut minima, mut extrema) = (0, 0);
            for v in 0..nv {
                if self.mesh.is_boundary_vertex(v as u32) || lo[v] > hi[v] {
                    continue;
                }
                let psi = self.psi[v];
                minima += usize::from(psi > hi[v]);
                extrema += usize::from(psi > hi[v] || psi < lo[v]);
            }
            (minima, extrema)
        })
    }
}
