//! P1 assembly on tetrahedra straight into compressed sparse storage, with Dirichlet lifting,
//! Neumann load and lumped Robin mass. The pattern, the edge numbering and the position of
//! every edge's entries are computed once by [`VolumeAssembler::new`].

use std::collections::BTreeMap;
use std::sync::{Arc, OnceLock};

use harmonic_solver::{MMatrix, SymmetricCsc};
use harmonic_types::BoundaryTag;
use harmonic_types::{BoundaryFace, EDGES, NO_NEIGHBOR, Point3 as Point, TetEdges, TetMesh};

use super::FemError;
use crate::NotMMatrix;
use crate::bc::{BoundaryCondition, BoundaryConditions, ConditionKind};

const NONE: u32 = u32::MAX;

/// Spatially varying boundary data: `data(face, point)` at each vertex of every boundary face
/// replaces the constant value of the face's condition (the Dirichlet value, the Neumann flux
/// `g` or the Robin right-hand side `g`; Robin `a` and `b` stay constant). Over a face the
/// data is interpolated linearly and integrated exactly.
pub type VolumeBoundaryData<'a> = &'a dyn Fn(&BoundaryFace, &Point) -> f64;

/// How the stiffness of edges with a negative weight `−K_ij < 0` (a positive off-diagonal:
/// obtuse dihedral angles, which isosurface stuffing leaves near the boundary) is treated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NegativeWeights {
    /// Keep the Galerkin stiffness as it is: optimal convergence, but the maximum principle
    /// may fail.
    #[default]
    Keep,
    /// Add the graph-Laplacian diffusion `(1 + CLAMP_KEEP)·max(K_ij, 0)` on exactly those
    /// edges, so their weight becomes [`CLAMP_KEEP`] times its magnitude and the matrix an
    /// M-matrix: the discrete maximum principle then holds on any mesh (the "artificial
    /// diffusion" remedy of Burman & Ern, 2005). The change is confined to the offending
    /// edges, which lie in the boundary layer of a stuffed mesh, but it costs accuracy there
    /// (measured: the L2 rate on a stuffed cube-minus-ball falls from 2 to about 1.2 between
    /// h = 1/6 and 1/13.5).
    Clamp,
}

/// The fraction of a negative weight's magnitude that [`NegativeWeights::Clamp`] keeps, as
/// a positive weight. Clamped to exactly 0, a thin passage meshed by sliver tetrahedra,
/// whose every crossing edge has a negative weight, was cut off from the goal: ψ was 0
/// beyond it, the field flat and every start there stalled (a 2 × 0.3 bar through a 1.0
/// slot at the default spacing). A hundredth keeps every such edge a (resistive) path for
/// the flow and changes nothing else measurably.
pub const CLAMP_KEEP: f64 = 0.01;

/// Options of [`VolumeAssembler::new`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VolumeAssemblyOptions {
    /// Treatment of negative edge weights.
    pub negative_weights: NegativeWeights,
}

/// The reduced system `A x = b` for ψ at the free vertices.
#[derive(Clone, Debug)]
pub struct VolumeSystem {
    pub(super) matrix: SymmetricCsc,
    pub(super) rhs: Vec<f64>,
    pub(super) excess: Vec<f64>,
    pub(super) psi_fixed: Vec<f64>,
    pub(super) reference: f64,
    pub(super) not_m_matrix: Option<NotMMatrix>,
    pub(super) free: Arc<Vec<u32>>,
    pub(super) positive_offdiagonals: usize,
    pub(super) clamped: usize,
    /// Per vertex, the vertex it is identified with (a periodic mesh's folded system,
    /// `super::periodic`): `expand` copies ψ there.
    pub(super) images: Option<Arc<Vec<u32>>>,
}

impl VolumeSystem {
    /// Edges whose negative Galerkin weight was clamped ([`NegativeWeights::Clamp`]):
    /// how far the mesh is from giving an M-matrix by itself.
    pub fn clamped_edges(&self) -> usize {
        self.clamped
    }
    /// The reduced matrix (stiffness + lumped Robin mass), full symmetric pattern.
    pub fn matrix(&self) -> &SymmetricCsc {
        &self.matrix
    }
    /// The right-hand side (loads and lifting).
    pub fn rhs(&self) -> &[f64] {
        &self.rhs
    }
    /// Row excesses as sums of non-negative terms (weights of edges to prescribed vertices
    /// and lumped Robin mass): the accurate solve's primary data.
    pub fn excess(&self) -> &[f64] {
        &self.excess
    }
    /// The reference value `c` of ψ = c − φ.
    pub fn reference(&self) -> f64 {
        self.reference
    }
    /// The mesh vertex of each unknown.
    pub fn free_vertices(&self) -> &[u32] {
        &self.free
    }
    /// `None` if the matrix is an M-matrix given by non-negative data, else why not.
    pub fn not_m_matrix(&self) -> Option<NotMMatrix> {
        self.not_m_matrix
    }
    /// Positive off-diagonal pairs of the reduced matrix beyond round-off (each symmetric
    /// pair once) plus edges to prescribed vertices with negative weight: zero means the
    /// matrix is an M-matrix and the discrete maximum principle holds.
    pub fn positive_offdiagonals(&self) -> usize {
        self.positive_offdiagonals
    }
    /// The matrix as an [`MMatrix`] (off-diagonal magnitudes and excesses), if it is one.
    pub fn m_matrix(&self) -> Result<MMatrix, FemError> {
        if let Some(reason) = &self.not_m_matrix {
            return Err(FemError::NotMMatrix(*reason));
        }
        let a = &self.matrix;
        let n = a.n();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(a.nnz());
        let mut values = Vec::with_capacity(a.nnz());
        col_ptr.push(0);
        for j in 0..n {
            let (rows, vals) = a.column(j);
            for (&i, &v) in rows.iter().zip(vals) {
                if i != j {
                    row_idx.push(i);
                    values.push((-v).max(0.0));
                }
            }
            col_ptr.push(row_idx.len());
        }
        let w = SymmetricCsc::try_from_symmetric_pattern(n, col_ptr, row_idx, values)?;
        Ok(MMatrix::try_new(w, self.excess.clone())?)
    }
    /// ψ at every vertex from the reduced solution.
    pub fn expand(&self, x: &[f64]) -> Result<Vec<f64>, FemError> {
        if x.len() != self.free.len() {
            return Err(FemError::LengthMismatch {
                what: "solution of the reduced system",
                expected: self.free.len(),
                got: x.len(),
            });
        }
        let mut psi = self.psi_fixed.clone();
        for (&v, &xi) in self.free.iter().zip(x) {
            psi[v as usize] = xi;
        }
        if let Some(images) = &self.images {
            for (v, &r) in images.iter().enumerate() {
                psi[v] = psi[r as usize];
            }
        }
        Ok(psi)
    }
}

/// The pattern and Dirichlet map of a tetrahedral mesh for conditions of given kinds.
#[derive(Debug)]
pub struct VolumeAssembler {
    mesh: Arc<TetMesh>,
    /// A periodic slab's identification (see [`VolumeAssembler::with_identified`]).
    images: Option<Arc<Vec<u32>>>,
    options: VolumeAssemblyOptions,
    kinds: BTreeMap<BoundaryTag, ConditionKind>,
    unknown_of: Vec<u32>,
    free: Arc<Vec<u32>>,
    /// Per edge (the mesh's [`TetMesh::edges`]): positions of `(a, b)` and `(b, a)` when both
    /// ends are unknowns.
    edge_pos: Vec<[u32; 2]>,
    diag_pos: Vec<u32>,
    template: SymmetricCsc,
    /// Per component of free space (tetrahedron adjacency): a vertex, and whether a vertex is
    /// prescribed.
    components: Vec<(u32, bool)>,
    /// Per tetrahedron: its component.
    tet_component: Vec<u32>,
    /// The Galerkin edge weights, computed on first assembly.
    weights: OnceLock<Vec<f64>>,
}

impl VolumeAssembler {
    /// Computes the pattern for `mesh` and the kinds of `bcs` (validated), with the default
    /// options ([`NegativeWeights::Keep`]).
    pub fn new(mesh: Arc<TetMesh>, bcs: &BoundaryConditions) -> Result<Self, FemError> {
        Self::with_options(mesh, bcs, VolumeAssemblyOptions::default())
    }

    /// [`new`](Self::new) with options.
    pub fn with_options(
        mesh: Arc<TetMesh>,
        bcs: &BoundaryConditions,
        options: VolumeAssemblyOptions,
    ) -> Result<Self, FemError> {
        Self::build(mesh, bcs, options, None)
    }

    /// [`with_options`](Self::with_options) for a periodic slab whose vertex `v` is one with
    /// `images[v]` (`super::periodic`): a vertex is prescribed when any vertex it is
    /// identified with lies on a prescribed face, with the lowest value among them, so the
    /// folded system keeps identified vertices alike.
    pub fn with_identified(
        mesh: Arc<TetMesh>,
        bcs: &BoundaryConditions,
        options: VolumeAssemblyOptions,
        images: Arc<Vec<u32>>,
    ) -> Result<Self, FemError> {
        if images.len() != mesh.vertices().len()
            || images.iter().any(|&r| r as usize >= images.len())
        {
            return Err(FemError::LengthMismatch {
                what: "periodic images",
                expected: mesh.vertices().len(),
                got: images.len(),
            });
        }
        Self::build(mesh, bcs, options, Some(images))
    }

    fn build(
        mesh: Arc<TetMesh>,
        bcs: &BoundaryConditions,
        options: VolumeAssemblyOptions,
        images: Option<Arc<Vec<u32>>>,
    ) -> Result<Self, FemError> {
        bcs.validate()?;
        let nv = mesh.vertices().len();
        let tets = mesh.tetrahedra();
        let mut kinds = BTreeMap::new();
        let mut fixed = vec![false; nv];
        for f in mesh.boundary_faces() {
            let kind = bcs.for_tag(f.tag).kind();
            kinds.insert(f.tag, kind);
            if kind == ConditionKind::Essential {
                for &v in &f.vertices {
                    fixed[v as usize] = true;
                }
            }
        }
        if let Some(images) = &images {
            for v in 0..nv {
                if fixed[v] {
                    fixed[images[v] as usize] = true;
                }
            }
            for v in 0..nv {
                fixed[v] = fixed[images[v] as usize];
            }
        }
        let mut used = vec![false; nv];
        for t in tets {
            for &v in t {
                used[v as usize] = true;
            }
        }
        let mut unknown_of = vec![NONE; nv];
        let mut free = Vec::new();
        for v in 0..nv {
            if used[v] && !fixed[v] {
                unknown_of[v] = free.len() as u32;
                free.push(v as u32);
            }
        }
        let n = free.len();

        // Unique edges and each tetrahedron's edge numbers.
        let edges = &mesh.edges().edges;

        // Pattern: diagonal plus edges between unknowns, rows sorted per column.
        let mut count = vec![1usize; n];
        for &[a, b] in edges {
            let (ua, ub) = (unknown_of[a as usize], unknown_of[b as usize]);
            if ua != NONE && ub != NONE {
                count[ua as usize] += 1;
                count[ub as usize] += 1;
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        for c in &count {
            col_ptr.push(col_ptr[col_ptr.len() - 1] + c);
        }
        let nnz = col_ptr[n];
        if nnz >= NONE as usize {
            return Err(FemError::TooLarge { nnz });
        }
        let mut next: Vec<usize> = col_ptr[..n].to_vec();
        let mut row_idx = vec![0usize; nnz];
        for (j, slot) in next.iter_mut().enumerate() {
            row_idx[*slot] = j;
            *slot += 1;
        }
        for &[a, b] in edges {
            let (ua, ub) = (unknown_of[a as usize], unknown_of[b as usize]);
            if ua != NONE && ub != NONE {
                row_idx[next[ub as usize]] = ua as usize;
                next[ub as usize] += 1;
                row_idx[next[ua as usize]] = ub as usize;
                next[ua as usize] += 1;
            }
        }
        for j in 0..n {
            row_idx[col_ptr[j]..col_ptr[j + 1]].sort_unstable();
        }
        let find = |row: usize, col: usize| -> u32 {
            let r = &row_idx[col_ptr[col]..col_ptr[col + 1]];
            (col_ptr[col] + r.binary_search(&row).unwrap_or(0)) as u32
        };
        let diag_pos: Vec<u32> = (0..n).map(|j| find(j, j)).collect();
        let edge_pos: Vec<[u32; 2]> = edges
            .iter()
            .map(|&[a, b]| {
                let (ua, ub) = (unknown_of[a as usize], unknown_of[b as usize]);
                if ua != NONE && ub != NONE {
                    [
                        find(ua as usize, ub as usize),
                        find(ub as usize, ua as usize),
                    ]
                } else {
                    [NONE, NONE]
                }
            })
            .collect();
        let template =
            SymmetricCsc::try_from_symmetric_pattern(n, col_ptr, row_idx, vec![0.0; nnz])?;

        // Components of free space by face adjacency, and whether each holds a prescribed
        // vertex.
        let mut tet_component = vec![NONE; tets.len()];
        let mut components = Vec::new();
        let mut stack = Vec::new();
        for seed in 0..tets.len() {
            if tet_component[seed] != NONE {
                continue;
            }
            let c = components.len() as u32;
            let mut has_fixed = false;
            tet_component[seed] = c;
            stack.push(seed as u32);
            while let Some(t) = stack.pop() {
                has_fixed |= tets[t as usize]
                    .iter()
                    .any(|&v| unknown_of[v as usize] == NONE);
                for &nb in &mesh.neighbors()[t as usize] {
                    if nb != NO_NEIGHBOR && tet_component[nb as usize] == NONE {
                        tet_component[nb as usize] = c;
                        stack.push(nb);
                    }
                }
            }
            components.push((tets[seed][0], has_fixed));
        }

        Ok(VolumeAssembler {
            mesh,
            images,
            options,
            kinds,
            unknown_of,
            free: Arc::new(free),
            edge_pos,
            diag_pos,
            template,
            components,
            tet_component,
            weights: OnceLock::new(),
        })
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<TetMesh> {
        &self.mesh
    }
    /// The number of unknowns.
    pub fn unknown_count(&self) -> usize {
        self.free.len()
    }
    /// The number of mesh edges.
    pub fn edge_count(&self) -> usize {
        self.mesh.edges().edges.len()
    }

    /// Assembles the reduced system for constant conditions `bcs`.
    pub fn assemble(&self, bcs: &BoundaryConditions) -> Result<VolumeSystem, FemError> {
        self.assemble_with(bcs, None)
    }

    /// Assembles with spatially varying values from `data` when given (see
    /// [`VolumeBoundaryData`]). The stages: check the condition kinds, collect the prescribed
    /// values (and the reference c), lift them to ψ, scatter the edge weights, add the Neumann
    /// and Robin face terms, then count what keeps the matrix from being an M-matrix.
    pub fn assemble_with(
        &self,
        bcs: &BoundaryConditions,
        data: Option<VolumeBoundaryData<'_>>,
    ) -> Result<VolumeSystem, FemError> {
        self.assemble_weighted(bcs, data, self.options.negative_weights)
    }

    /// [`assemble`](Self::assemble) with `negative_weights` in place of the options' (the
    /// planning solve's clamped redo reuses the pattern this way).
    pub fn assemble_weighted(
        &self,
        bcs: &BoundaryConditions,
        data: Option<VolumeBoundaryData<'_>>,
        negative_weights: NegativeWeights,
    ) -> Result<VolumeSystem, FemError> {
        bcs.validate()?;
        self.check_kinds(bcs)?;
        let values = FaceValues {
            vertices: self.mesh.vertices(),
            data,
        };
        let prescribed = self.prescribed(bcs, &values)?;
        let psi_fixed = self.psi_of_prescribed(&prescribed);
        let weight = self.edge_weights();
        let clamp = negative_weights == NegativeWeights::Clamp;
        let mut parts = self.scatter_stiffness(weight, &psi_fixed, clamp);
        self.boundary_terms(bcs, &values, prescribed.reference, &mut parts)?;
        let Scattered {
            mut matrix,
            rhs,
            excess,
            diag,
            negative,
            clamped,
        } = parts;
        {
            let values = matrix.values_mut();
            for (j, &d) in diag.iter().enumerate() {
                values[self.diag_pos[j] as usize] = d;
            }
        }
        let (positive, first) = self.negative_weights(weight, &negative, &diag);
        Ok(VolumeSystem {
            matrix,
            rhs,
            excess,
            psi_fixed,
            reference: prescribed.reference,
            not_m_matrix: first,
            free: Arc::clone(&self.free),
            positive_offdiagonals: positive,
            clamped,
            images: None,
        })
    }

    /// Conditions must be of the kinds the pattern was built for.
    fn check_kinds(&self, bcs: &BoundaryConditions) -> Result<(), FemError> {
        for (&tag, &was) in &self.kinds {
            if bcs.for_tag(tag).kind() != was {
                return Err(FemError::KindChanged {
                    part: tag.to_string(),
                    was,
                    now: bcs.for_tag(tag).kind(),
                });
            }
        }
        Ok(())
    }

    /// Prescribed φ per vertex (lowest wins), the reference c (the highest level), and the
    /// checks that every component is anchored and something drives the flow.
    fn prescribed(
        &self,
        bcs: &BoundaryConditions,
        values: &FaceValues<'_, '_>,
    ) -> Result<Prescribed, FemError> {
        let mesh = &*self.mesh;
        let vertices = mesh.vertices();
        let mut phi_fixed = vec![f64::INFINITY; vertices.len()];
        let mut levels: Vec<f64> = Vec::new();
        let mut flux = false;
        let mut anchored = vec![false; self.components.len()];
        for f in mesh.boundary_faces() {
            let bc = bcs.for_tag(f.tag);
            let mut gv = [0.0; 3];
            for (k, slot) in gv.iter_mut().enumerate() {
                *slot = values.at(bc, f, f.vertices[k])?;
            }
            match bc {
                BoundaryCondition::Dirichlet(_) => {
                    for k in 0..3 {
                        let slot = &mut phi_fixed[f.vertices[k] as usize];
                        *slot = slot.min(gv[k]);
                    }
                    levels.extend(gv);
                }
                BoundaryCondition::Robin { a: 0.0, b, .. } => {
                    for k in 0..3 {
                        let slot = &mut phi_fixed[f.vertices[k] as usize];
                        *slot = slot.min(gv[k] / b);
                    }
                    levels.extend(gv.map(|x| x / b));
                }
                BoundaryCondition::Robin { b, .. } if b != 0.0 => {
                    levels.extend(gv.map(|x| x / b));
                    anchored[self.tet_component[f.tet as usize] as usize] = true;
                }
                BoundaryCondition::Neumann(_) | BoundaryCondition::Robin { .. } => {
                    flux |= gv.iter().any(|&x| x != 0.0);
                }
            }
        }
        if let Some(images) = &self.images {
            for v in 0..phi_fixed.len() {
                let r = images[v] as usize;
                phi_fixed[r] = phi_fixed[r].min(phi_fixed[v]);
            }
            for v in 0..phi_fixed.len() {
                phi_fixed[v] = phi_fixed[images[v] as usize];
            }
        }
        for (c, (&(v, fixed), &robin)) in self.components.iter().zip(&anchored).enumerate() {
            if !fixed && !robin {
                let p = vertices[v as usize];
                return Err(FemError::OnlyNeumann {
                    component: c as u32,
                    at: p.into(),
                });
            }
        }
        let reference = levels.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let reference = if reference.is_finite() {
            reference
        } else {
            0.0
        };
        let tol = 1e-12 * reference.abs().max(1.0);
        if !flux && levels.iter().all(|&l| (l - reference).abs() <= tol) {
            return Err(FemError::ConstantPotential { value: reference });
        }
        Ok(Prescribed {
            phi_fixed,
            reference,
        })
    }

    /// ψ = c − φ at the prescribed vertices (0 at the unknowns).
    fn psi_of_prescribed(&self, prescribed: &Prescribed) -> Vec<f64> {
        (0..prescribed.phi_fixed.len())
            .map(|v| {
                if self.unknown_of[v] == NONE && prescribed.phi_fixed[v].is_finite() {
                    prescribed.reference - prescribed.phi_fixed[v]
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Edge weights w_ij = −Σ_T V ∇λ_i·∇λ_j.
    fn edge_weights(&self) -> &[f64] {
        self.weights.get_or_init(|| {
            use rayon::prelude::*;
            let mesh = &*self.mesh;
            // Each tetrahedron's six terms on every core, summed into the edges in order (the
            // same sums on any number of threads).
            let TetEdges { edges, of_tet } = mesh.edges();
            let local: Vec<[f64; 6]> = (0..of_tet.len() as u32)
                .into_par_iter()
                .map(|t| {
                    let (g, vol) = mesh.barycentric_gradients(t);
                    EDGES.map(|[i, j]| -vol * g[i].dot(&g[j]))
                })
                .collect();
            let mut weight = vec![0.0; edges.len()];
            for (te, w) in of_tet.iter().zip(&local) {
                for (&e, &we) in te.iter().zip(w) {
                    weight[e as usize] += we;
                }
            }
            weight
        })
    }

    /// The edge weights into the matrix (off-diagonals), the diagonal, and the lifting of
    /// prescribed neighbours into the right-hand side and the excesses; negative weights are
    /// clamped when `clamp` ([`CLAMP_KEEP`]).
    fn scatter_stiffness(&self, weight: &[f64], psi_fixed: &[f64], clamp: bool) -> Scattered {
        let unknown_of = &self.unknown_of;
        let n = self.free.len();
        let mut matrix = SymmetricCsc::zeros_like(&self.template);
        let mut rhs = vec![0.0; n];
        let mut excess = vec![0.0; n];
        let mut diag = vec![0.0; n];
        let mut negative: Vec<usize> = Vec::new();
        let mut clamped = 0;
        let round_off = 1e-12 * weight.iter().fold(0.0f64, |m, w| m.max(w.abs()));
        {
            let values = matrix.values_mut();
            for (e, (&[a, b], &w)) in self.mesh.edges().edges.iter().zip(weight).enumerate() {
                let (ua, ub) = (unknown_of[a as usize], unknown_of[b as usize]);
                let w = if clamp && w < 0.0 {
                    if (ua != NONE || ub != NONE) && w < -round_off {
                        clamped += 1;
                    }
                    -CLAMP_KEEP * w
                } else {
                    w
                };
                match (ua != NONE, ub != NONE) {
                    (true, true) => {
                        let [p, q] = self.edge_pos[e];
                        values[p as usize] = -w;
                        values[q as usize] = -w;
                        diag[ua as usize] += w;
                        diag[ub as usize] += w;
                        if w < 0.0 {
                            negative.push(e);
                        }
                    }
                    (true, false) | (false, true) => {
                        let (u, v) = if ua != NONE { (ua, b) } else { (ub, a) };
                        diag[u as usize] += w;
                        if w < 0.0 {
                            negative.push(e);
                        }
                        // A negative weight to a prescribed vertex within round-off is 0.
                        rhs[u as usize] += w * psi_fixed[v as usize];
                        excess[u as usize] += w.max(0.0);
                    }
                    (false, false) => {}
                }
            }
        }
        Scattered {
            matrix,
            rhs,
            excess,
            diag,
            negative,
            clamped,
        }
    }

    /// Neumann and Robin faces: ∫ f v_i with f linear is A (2f_i + f_j + f_k)/12; Robin's
    /// lumped mass b/a · A/3 on the diagonal (and in the excess).
    fn boundary_terms(
        &self,
        bcs: &BoundaryConditions,
        values: &FaceValues<'_, '_>,
        reference: f64,
        parts: &mut Scattered,
    ) -> Result<(), FemError> {
        let mesh = &*self.mesh;
        let vertices = mesh.vertices();
        for f in mesh.boundary_faces() {
            let bc = bcs.for_tag(f.tag);
            let u = f.vertices.map(|v| self.unknown_of[v as usize]);
            if u.iter().all(|&x| x == NONE) {
                continue;
            }
            let (beta, fdata) = match bc {
                BoundaryCondition::Dirichlet(_) | BoundaryCondition::Robin { a: 0.0, .. } => {
                    continue;
                }
                BoundaryCondition::Neumann(_) => {
                    let mut fd = [0.0; 3];
                    for (slot, &v) in fd.iter_mut().zip(&f.vertices) {
                        *slot = -values.at(bc, f, v)?;
                    }
                    (0.0, fd)
                }
                BoundaryCondition::Robin { a, b, .. } => {
                    let mut fd = [0.0; 3];
                    for (slot, &v) in fd.iter_mut().zip(&f.vertices) {
                        *slot = (b * reference - values.at(bc, f, v)?) / a;
                    }
                    (b / a, fd)
                }
            };
            let [p0, p1, p2] = f.vertices.map(|v| vertices[v as usize]);
            let area = (p1 - p0).cross(&(p2 - p0)).norm() / 2.0;
            let sum: f64 = fdata.iter().sum();
            for k in 0..3 {
                if u[k] == NONE {
                    continue;
                }
                let uk = u[k] as usize;
                parts.rhs[uk] += area * (fdata[k] + sum) / 12.0;
                if beta != 0.0 {
                    parts.diag[uk] += beta * area / 3.0;
                    parts.excess[uk] += beta * area / 3.0;
                }
            }
        }
        Ok(())
    }

    /// Negative weights beyond round-off (1e-12 of the diagonal at either end): how many, and
    /// the first named for the error message.
    fn negative_weights(
        &self,
        weight: &[f64],
        negative: &[usize],
        diag: &[f64],
    ) -> (usize, Option<NotMMatrix>) {
        let vertices = self.mesh.vertices();
        let unknown_of = &self.unknown_of;
        let mut positive = 0;
        let mut first: Option<NotMMatrix> = None;
        for &e in negative {
            let w = weight[e];
            let [a, b] = self.mesh.edges().edges[e];
            let scale = [a, b]
                .iter()
                .filter(|&&v| unknown_of[v as usize] != NONE)
                .map(|&v| diag[unknown_of[v as usize] as usize])
                .fold(0.0f64, f64::max);
            if w < -1e-12 * scale {
                positive += 1;
                if first.is_none() {
                    let (p, q) = (vertices[a as usize], vertices[b as usize]);
                    first = Some(NotMMatrix::NegativeEdgeWeight {
                        vertices: [a, b],
                        midpoint: nalgebra::center(&p, &q).into(),
                        weight: w,
                    });
                }
            }
        }
        (positive, first)
    }
}

/// The boundary values of a condition at a face's vertex: the condition's constant, or the
/// caller's data there (which must be finite).
struct FaceValues<'m, 'd> {
    vertices: &'m [Point],
    data: Option<VolumeBoundaryData<'d>>,
}

impl FaceValues<'_, '_> {
    fn at(&self, bc: BoundaryCondition, f: &BoundaryFace, v: u32) -> Result<f64, FemError> {
        let constant = match bc {
            BoundaryCondition::Dirichlet(v) => v,
            BoundaryCondition::Neumann(g) | BoundaryCondition::Robin { g, .. } => g,
        };
        match self.data {
            None => Ok(constant),
            Some(d) => {
                let p = self.vertices[v as usize];
                let value = d(f, &p);
                if value.is_finite() {
                    Ok(value)
                } else {
                    Err(FemError::NonFiniteData {
                        part: f.tag.to_string(),
                        at: p.into(),
                        value,
                    })
                }
            }
        }
    }
}

/// Prescribed φ per vertex (infinity where none) and the reference value c.
struct Prescribed {
    phi_fixed: Vec<f64>,
    reference: f64,
}

/// The stiffness scattered into the reduced system, before the diagonal is written.
struct Scattered {
    matrix: SymmetricCsc,
    rhs: Vec<f64>,
    excess: Vec<f64>,
    diag: Vec<f64>,
    negative: Vec<usize>,
    clamped: usize,
}
