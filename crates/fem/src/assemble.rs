//! P1 assembly straight into compressed sparse storage, with Dirichlet lifting.
//!
//! The pattern (the mesh's edges among free vertices, plus the diagonal) and the position of
//! every element entry in it are computed once by [`Assembler::new`]; [`Assembler::assemble`]
//! then only scatters values, so replanning with new boundary values costs one pass over the
//! triangles and the boundary edges.

use std::collections::BTreeMap;
use std::sync::Arc;

use harmonic_solver::{MMatrix, Ordering, SymmetricCsc};
use harmonic_types::{
    BoundaryEdge, BoundaryTag, Mesh, NO_NEIGHBOR, Point, geom::twice_signed_area,
};

use crate::FemError;
use crate::bc::{BoundaryCondition, BoundaryConditions, ConditionKind};

/// Marks "no unknown" / "no position" in the index tables.
const NONE: u32 = u32::MAX;

/// Spatially varying boundary data: `data(edge, point)`, called at both ends of every boundary
/// edge, replaces the constant value of the condition on `edge.tag` — the Dirichlet value,
/// the Neumann flux `g` or the Robin right-hand side `g` (Robin `a` and `b` stay constant).
/// Along an edge the data is interpolated linearly and integrated exactly. The edge is given
/// so flux data can use its outward normal (at a corner the two edges may differ).
pub type BoundaryData<'a> = &'a dyn Fn(&BoundaryEdge, Point) -> f64;

/// How the Robin boundary mass `(b/a)∫ψv` is integrated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RobinMass {
    /// Row-sum lumped onto the diagonal (`|e|/2` per end). Keeps the reduced matrix an
    /// M-matrix (nonpositive off-diagonals), hence the discrete maximum principle.
    #[default]
    Lumped,
    /// The consistent edge mass (`|e|/3` diagonal, `|e|/6` off-diagonal): positive
    /// off-diagonal entries, so the M-matrix property can be lost.
    Consistent,
}

/// Options for [`Assembler::new`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AssemblyOptions {
    /// Robin boundary mass integration.
    pub robin_mass: RobinMass,
}

/// Which vertices are unknowns, shared by an assembler and its systems.
#[derive(Debug)]
struct DofMap {
    /// Per vertex: its unknown index, or `NONE` if its value is prescribed (a Dirichlet vertex,
    /// or a vertex used by no triangle).
    unknown_of: Vec<u32>,
    /// Per unknown: its vertex (increasing, so unknowns follow the mesh's vertex order).
    free_vertices: Vec<u32>,
}

/// The reduced linear system `A x = b` for ψ at the free vertices, with what is needed to map
/// the solution back to every vertex.
#[derive(Clone, Debug)]
pub struct LinearSystem {
    matrix: SymmetricCsc,
    rhs: Vec<f64>,
    /// ψ at every vertex whose value is prescribed (0 at free vertices).
    psi_fixed: Vec<f64>,
    reference: f64,
    /// Row excesses `a_ii − Σ_j |a_ij|` computed as sums of non-negative terms (Dirichlet
    /// edge weights and lumped Robin mass), for the entrywise-accurate solve.
    excess: Vec<f64>,
    /// Why the matrix is not an M-matrix given by non-negative data, if it is not.
    not_m_matrix: Option<NotMMatrix>,
    dofs: Arc<DofMap>,
}

/// Why a reduced system cannot be handed to the entrywise-accurate solver
/// ([`crate::SolveMethod::Accurate`]) as an M-matrix with non-negative primary data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NotMMatrix {
    /// The cotangent weight of the mesh edge between `vertices` is negative beyond round-off
    /// (`weight`, i.e. the off-diagonal entry is positive): the edge is not locally Delaunay,
    /// or it is a boundary edge facing an obtuse angle.
    NegativeEdgeWeight {
        /// The edge's mesh vertices.
        vertices: [u32; 2],
        /// Its midpoint.
        midpoint: crate::At,
        /// The weight `(cot α + cot β)/2` (negative).
        weight: f64,
    },
    /// The consistent Robin mass ([`RobinMass::Consistent`]) adds positive off-diagonal
    /// entries; assemble with [`RobinMass::Lumped`].
    ConsistentRobinMass,
}

impl std::fmt::Display for NotMMatrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NotMMatrix::NegativeEdgeWeight {
                vertices,
                midpoint,
                weight,
            } => write!(
                f,
                "the edge between vertices {} and {} (midpoint {midpoint}) has stiffness weight {weight:e} < 0: the mesh is not Delaunay there",
                vertices[0], vertices[1]
            ),
            NotMMatrix::ConsistentRobinMass => write!(
                f,
                "the consistent Robin mass has positive off-diagonal entries; use the lumped mass"
            ),
        }
    }
}

impl LinearSystem {
    /// The reduced stiffness (+ Robin mass) matrix: symmetric positive definite, full pattern.
    pub fn matrix(&self) -> &SymmetricCsc {
        &self.matrix
    }
    /// The right-hand side (loads and Dirichlet lifting `−A_ID ψ_D`).
    pub fn rhs(&self) -> &[f64] {
        &self.rhs
    }
    /// The row excesses `s_i = a_ii − Σ_{j≠i} |a_ij|` of the matrix, each computed directly as
    /// a sum of non-negative terms — the weights of the edges from unknown `i` to prescribed
    /// vertices plus its lumped Robin mass — never as a difference. With
    /// [`off_diagonal_magnitudes`](Self::off_diagonal_magnitudes) they are the primary data of
    /// the entrywise-accurate solve.
    pub fn excess(&self) -> &[f64] {
        &self.excess
    }
    /// `None` if the matrix is a diagonally dominant M-matrix given by non-negative data (so
    /// [`crate::SolveMethod::Accurate`] applies), else the first reason it is not.
    pub fn not_m_matrix(&self) -> Option<NotMMatrix> {
        self.not_m_matrix
    }
    /// The matrix as an [`MMatrix`]: off-diagonal magnitudes `w_ij = −a_ij` (those within
    /// round-off of zero on the wrong side clamped to 0) and the row [`excess`](Self::excess).
    /// Fails with [`FemError::NotMMatrix`] when [`not_m_matrix`](Self::not_m_matrix) is set.
    pub fn m_matrix(&self) -> Result<MMatrix, FemError> {
        if let Some(reason) = self.not_m_matrix {
            return Err(FemError::NotMMatrix(reason));
        }
        Ok(MMatrix::try_new(
            self.off_diagonal_magnitudes(),
            self.excess.clone(),
        )?)
    }
    /// The off-diagonal magnitudes `max(−a_ij, 0)` with the matrix's pattern minus its
    /// diagonal (exactly symmetric, as the matrix is).
    pub fn off_diagonal_magnitudes(&self) -> SymmetricCsc {
        let a = &self.matrix;
        let n = a.n();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(a.nnz().saturating_sub(n));
        let mut values = Vec::with_capacity(a.nnz().saturating_sub(n));
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
        SymmetricCsc::try_from_symmetric_pattern(n, col_ptr, row_idx, values)
            .expect("dropping the diagonal of a valid symmetric pattern keeps it valid")
    }
    /// The reference value `c` of the transform ψ = c − φ.
    pub fn reference(&self) -> f64 {
        self.reference
    }
    /// The number of unknowns.
    pub fn unknown_count(&self) -> usize {
        self.dofs.free_vertices.len()
    }
    /// The mesh vertex of each unknown, in increasing order.
    pub fn free_vertices(&self) -> &[u32] {
        &self.dofs.free_vertices
    }
    /// The unknown index of each mesh vertex, `None` for prescribed vertices.
    pub fn unknown_of(&self, vertex: u32) -> Option<u32> {
        self.dofs
            .unknown_of
            .get(vertex as usize)
            .copied()
            .filter(|&u| u != NONE)
    }
    /// ψ at every mesh vertex from the solution `x` of the reduced system (prescribed values
    /// at Dirichlet vertices, 0 at vertices used by no triangle).
    pub fn expand(&self, x: &[f64]) -> Result<Vec<f64>, FemError> {
        if x.len() != self.unknown_count() {
            return Err(FemError::LengthMismatch {
                what: "solution of the reduced system",
                expected: self.unknown_count(),
                got: x.len(),
            });
        }
        let mut psi = self.psi_fixed.clone();
        for (&v, &xi) in self.dofs.free_vertices.iter().zip(x) {
            psi[v as usize] = xi;
        }
        Ok(psi)
    }
}

/// Counts the positive off-diagonal pairs of the reduced matrix (each symmetric pair once).
/// Zero means the matrix is an M-matrix (it is SPD and diagonally dominant by construction),
/// so the discrete maximum principle holds. An entry counts as positive above a round-off
/// tolerance of `1e-12·max(a_ii, a_jj)` (right angles give cotangents of exactly zero in
/// exact arithmetic).
pub fn offdiagonal_sign_violations(system: &LinearSystem) -> usize {
    let a = &system.matrix;
    let diag = a.diagonal();
    let (col_ptr, row_idx, values) = (a.col_ptr(), a.row_idx(), a.values());
    let mut count = 0;
    for j in 0..a.n() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            if i > j && values[p] > 1e-12 * diag[i].max(diag[j]) {
                count += 1;
            }
        }
    }
    count
}

/// Systems with fewer unknowns than this are factored in their own numbering
/// ([`Assembler::ordering`]). Measured on Nav2's maps (first plan, best of 7, in-process):
/// with 163 and 561 unknowns (tb3_sandbox, depot) the natural order was 1.5 % faster than
/// nested dissection, with 1 659 (warehouse) 6 % slower.
pub const NATURAL_ORDER_BELOW: usize = 1000;

/// Builds the sparsity pattern and Dirichlet map of a mesh once, then assembles systems for
/// boundary conditions of the same kinds (which parts are Dirichlet) as often as needed.
///
/// Unknowns are the vertices not on any Dirichlet part, numbered in mesh vertex order. A
/// vertex on a Dirichlet part is prescribed even if it also touches a Neumann or Robin part;
/// a vertex on two Dirichlet parts with different values takes the **lower φ** (the goal's,
/// for the usual conditions), so goals are never shrunk by a neighbouring wall. Vertices used
/// by no triangle are prescribed too (ψ = 0).
///
/// Replanning with new values reuses the pattern and the symbolic factorisation:
/// ```
/// use std::sync::Arc;
/// use harmonic_fem::{Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, Ordering, Solver};
/// use harmonic_mesh::{BoundaryTag, Mesh, Point};
///
/// let vertices = vec![
///     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0),
///     Point::new(0.0, 1.0), Point::new(0.5, 0.5),
/// ];
/// let triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
/// let boundary = [
///     (0, 1, BoundaryTag::Goal(0)), (1, 2, BoundaryTag::Wall),
///     (2, 3, BoundaryTag::Wall), (3, 0, BoundaryTag::Obstacle(0)),
/// ];
/// let mesh = Arc::new(Mesh::from_parts(vertices, triangles, &boundary)?);
/// let mut bcs = BoundaryConditions::uniform(BoundaryCondition::Robin { a: 1.0, b: 1.0, g: 1.0 });
/// let assembler = Assembler::new(mesh.clone(), &bcs, AssemblyOptions::default())?;
/// let mut system = assembler.assemble(&bcs)?;
/// let solver = Solver::new(&system, Ordering::Amd)?;
/// let first = solver.potential(mesh.clone(), &system)?;
///
/// // Stiffer walls: same kinds (Robin stays Robin), so only values are re-assembled.
/// bcs.walls = BoundaryCondition::Robin { a: 1.0, b: 10.0, g: 10.0 };
/// assembler.assemble_into(&bcs, None, &mut system)?;
/// let second = solver.potential(mesh, &system)?;
/// assert!(second.phi_at_vertices()[2] > first.phi_at_vertices()[2]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Assembler {
    mesh: Arc<Mesh>,
    options: AssemblyOptions,
    /// Per triangle: the conductivity k of ∇·(k∇φ) = 0 (`None`: 1 everywhere, Laplace).
    conductivity: Option<Arc<[f64]>>,
    /// Per triangle: the absorption σ ≥ 0 of −∇·(k∇φ) + σ(φ − c) = 0 (`None`: 0 everywhere).
    absorption: Option<Arc<[f64]>>,
    kinds: BTreeMap<BoundaryTag, ConditionKind>,
    dofs: Arc<DofMap>,
    /// A zero-valued matrix with the final pattern.
    template: SymmetricCsc,
    /// Per triangle and local edge `k` (joining local vertices `k+1`, `k+2`): positions of
    /// the entries (row `k+1`, col `k+2`) and (row `k+2`, col `k+1`), or `NONE`.
    tri_pos: Vec<[u32; 6]>,
    /// Per unknown: position of its diagonal entry.
    diag_pos: Vec<u32>,
    /// Per triangle and local edge `k`: the slot in `lift_edges` of the edge if exactly one
    /// end is an unknown, or `NONE`.
    lift_pos: Vec<[u32; 3]>,
    /// Edges from an unknown to a prescribed vertex: (unknown index, prescribed vertex).
    lift_edges: Vec<(u32, u32)>,
    /// Per component of free space: whether it has a prescribed vertex.
    component_fixed: Vec<bool>,
    /// Per component: one of its vertices (for error messages).
    component_vertex: Vec<u32>,
}

/// The condition kind on each boundary tag of `mesh` under `bcs`, and per vertex whether
/// it lies on an essential (Dirichlet) part.
fn condition_kinds(
    mesh: &Mesh,
    bcs: &BoundaryConditions,
) -> (BTreeMap<BoundaryTag, ConditionKind>, Vec<bool>) {
    let mut kinds = BTreeMap::new();
    let mut fixed = vec![false; mesh.vertices().len()];
    for e in mesh.boundary_edges() {
        let kind = bcs.for_tag(e.tag).kind();
        kinds.insert(e.tag, kind);
        if kind == ConditionKind::Essential {
            for &v in &e.vertices {
                fixed[v as usize] = true;
            }
        }
    }
    (kinds, fixed)
}

impl DofMap {
    /// The unknowns of `mesh`: every vertex used by a triangle and not `fixed`, in vertex
    /// order.
    fn new(mesh: &Mesh, fixed: &[bool]) -> DofMap {
        let nv = mesh.vertices().len();
        let mut used = vec![false; nv];
        for tri in mesh.triangles() {
            for &v in tri {
                used[v as usize] = true;
            }
        }
        let mut unknown_of = vec![NONE; nv];
        let mut free_vertices = Vec::new();
        for v in 0..nv {
            if used[v] && !fixed[v] {
                unknown_of[v] = free_vertices.len() as u32;
                free_vertices.push(v as u32);
            }
        }
        DofMap {
            unknown_of,
            free_vertices,
        }
    }
}

/// The unknowns `(a, b)` (or `NONE`) at the ends of local edge `k` of `tri`, the edge
/// joining local vertices `k + 1` and `k + 2`.
fn edge_unknowns(unknown_of: &[u32], tri: &[u32; 3], k: usize) -> (u32, u32) {
    (
        unknown_of[tri[(k + 1) % 3] as usize],
        unknown_of[tri[(k + 2) % 3] as usize],
    )
}

/// Per component of free space: whether it holds a prescribed vertex, and one of its
/// vertices (for error messages).
struct Components {
    fixed: Vec<bool>,
    vertex: Vec<u32>,
}

/// The number of entries of each column of the pattern (the diagonal, and each mesh edge
/// between unknowns once), with the components' [`Components`] fused into the same pass.
fn column_counts(mesh: &Mesh, dofs: &DofMap) -> (Vec<usize>, Components) {
    let unknown_of = &dofs.unknown_of;
    let mut count = vec![1usize; dofs.free_vertices.len()];
    let components = mesh.component_count() as usize;
    let mut component_fixed = vec![false; components];
    let mut component_vertex = vec![NONE; components];
    let triangle_components = mesh.triangle_components();
    for (t, (tri, nbs)) in mesh.triangles().iter().zip(mesh.neighbors()).enumerate() {
        let c = triangle_components[t] as usize;
        component_vertex[c] = tri[0];
        if tri.iter().any(|&v| unknown_of[v as usize] == NONE) {
            component_fixed[c] = true;
        }
        for (k, &nb) in nbs.iter().enumerate() {
            let (a, b) = edge_unknowns(unknown_of, tri, k);
            if (nb == NO_NEIGHBOR || nb as usize > t) && a != NONE && b != NONE {
                count[a as usize] += 1;
                count[b as usize] += 1;
            }
        }
    }
    (
        count,
        Components {
            fixed: component_fixed,
            vertex: component_vertex,
        },
    )
}

/// The column pointers of columns with `count` entries; an error if the entries would not
/// fit the `u32` position tables.
fn column_pointers(count: &[usize]) -> Result<Vec<usize>, FemError> {
    let mut col_ptr = Vec::with_capacity(count.len() + 1);
    col_ptr.push(0usize);
    for c in count {
        col_ptr.push(col_ptr[col_ptr.len() - 1] + c);
    }
    let nnz = col_ptr[count.len()];
    if nnz >= NONE as usize {
        return Err(FemError::TooLarge { nnz });
    }
    Ok(col_ptr)
}

/// The unsorted column structure U of the pattern and where each triangle's entries and
/// lifting edges are in it.
struct UnsortedPattern {
    /// Per slot of U: its row (the diagonal first in each column, then each mesh edge
    /// between unknowns once, from the triangle with the smaller index).
    u_rows: Vec<u32>,
    /// As [`Assembler::tri_pos`], but slots in U.
    tri_pos: Vec<[u32; 6]>,
    /// As [`Assembler::lift_pos`].
    lift_pos: Vec<[u32; 3]>,
    /// As [`Assembler::lift_edges`].
    lift_edges: Vec<(u32, u32)>,
}

/// The local index in triangle `nb` of its edge shared with triangle `t`.
fn shared_edge(neighbors: &[[u32; 3]], nb: usize, t: usize) -> usize {
    (0..3)
        .find(|&m| neighbors[nb][m] as usize == t)
        .expect("adjacency is symmetric")
}

/// Pattern, without sorting or searching, step 1: the unsorted column structure U with
/// the diagonal first and each mesh edge between unknowns once (from the triangle with the
/// smaller index), recording each triangle's slots in U, and the lifting edges.
fn unsorted_pattern(mesh: &Mesh, unknown_of: &[u32], col_ptr: &[usize]) -> UnsortedPattern {
    let triangles = mesh.triangles();
    let neighbors = mesh.neighbors();
    let n = col_ptr.len() - 1;
    let nnz = col_ptr[n];
    let mut next: Vec<usize> = col_ptr[..n].to_vec();
    let mut u_rows = vec![0u32; nnz];
    for (j, slot) in next.iter_mut().enumerate() {
        u_rows[*slot] = j as u32;
        *slot += 1;
    }
    // tri_pos[t][2k]: slot of (row a, col b), [2k+1]: slot of (row b, col a), where
    // (a, b) are the unknowns of local edge k; in U, remapped to T by `sort_pattern`.
    let mut tri_pos = vec![[NONE; 6]; triangles.len()];
    // Fused into this pass: the lifting edges (one end unknown, one prescribed), each once,
    // so their weights are summed over both triangles before use: a single triangle's
    // share may be negative.
    let mut lift_pos = vec![[NONE; 3]; triangles.len()];
    let mut lift_edges = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = edge_unknowns(unknown_of, tri, k);
            if a == NONE || b == NONE {
                if (a == NONE) != (b == NONE) {
                    let nb = neighbors[t][k];
                    if nb == NO_NEIGHBOR || nb as usize > t {
                        lift_pos[t][k] = lift_edges.len() as u32;
                        let (u, v) = if a != NONE {
                            (a, tri[(k + 2) % 3])
                        } else {
                            (b, tri[(k + 1) % 3])
                        };
                        lift_edges.push((u, v));
                    } else {
                        let nb = nb as usize;
                        let kn = shared_edge(neighbors, nb, t);
                        lift_pos[t][k] = lift_pos[nb][kn];
                    }
                }
                continue;
            }
            let nb = neighbors[t][k];
            if nb == NO_NEIGHBOR || nb as usize > t {
                let s_ab = next[b as usize];
                u_rows[s_ab] = a;
                next[b as usize] += 1;
                let s_ba = next[a as usize];
                u_rows[s_ba] = b;
                next[a as usize] += 1;
                tri_pos[t][2 * k] = s_ab as u32;
                tri_pos[t][2 * k + 1] = s_ba as u32;
            } else {
                let nb = nb as usize;
                let kn = shared_edge(neighbors, nb, t);
                let [s0, s1] = [tri_pos[nb][2 * kn], tri_pos[nb][2 * kn + 1]];
                // Same orientation in both triangles only if the mesh is inconsistent;
                // compare vertices rather than assume.
                let same = triangles[nb][(kn + 1) % 3] == tri[(k + 1) % 3];
                let (ab, ba) = if same { (s0, s1) } else { (s1, s0) };
                tri_pos[t][2 * k] = ab;
                tri_pos[t][2 * k + 1] = ba;
            }
        }
    }
    UnsortedPattern {
        u_rows,
        tri_pos,
        lift_pos,
        lift_edges,
    }
}

/// Pattern, step 2: the transpose T of U, which is the same symmetric pattern with rows
/// increasing in every column; remaps `pattern.tri_pos` from U slots to T positions and
/// returns T's row indices and the position of each diagonal entry.
fn sort_pattern(col_ptr: &[usize], pattern: &mut UnsortedPattern) -> (Vec<usize>, Vec<u32>) {
    let n = col_ptr.len() - 1;
    let nnz = col_ptr[n];
    let u_rows = std::mem::take(&mut pattern.u_rows);
    let mut next: Vec<usize> = col_ptr[..n].to_vec();
    let mut row_idx = vec![0usize; nnz];
    // to_t[s]: for the U entry (row i, col j) in slot s, the T position of (row j, col i).
    let mut to_t = vec![0u32; nnz];
    for j in 0..n {
        for s in col_ptr[j]..col_ptr[j + 1] {
            let i = u_rows[s] as usize;
            row_idx[next[i]] = j;
            to_t[s] = next[i] as u32;
            next[i] += 1;
        }
    }
    drop(u_rows);
    for pos in &mut pattern.tri_pos {
        for k in 0..3 {
            if pos[2 * k] != NONE {
                let (ab, ba) = (pos[2 * k], pos[2 * k + 1]);
                pos[2 * k] = to_t[ba as usize];
                pos[2 * k + 1] = to_t[ab as usize];
            }
        }
    }
    let diag_pos: Vec<u32> = (0..n).map(|j| to_t[col_ptr[j]]).collect();
    (row_idx, diag_pos)
}

/// The boundary values of one assembly: each condition's constant, or the spatially
/// varying `data` when given (see [`BoundaryData`]).
struct BoundaryValues<'a> {
    vertices: &'a [Point],
    data: Option<BoundaryData<'a>>,
}

impl BoundaryValues<'_> {
    /// The value of `bc` (the Dirichlet value, or the Neumann or Robin `g`) at vertex `v` of
    /// boundary edge `e`; an error if `data` gives a number that is not finite.
    fn at(&self, bc: BoundaryCondition, e: &BoundaryEdge, v: u32) -> Result<f64, FemError> {
        let constant = match bc {
            BoundaryCondition::Dirichlet(v) => v,
            BoundaryCondition::Neumann(g) | BoundaryCondition::Robin { g, .. } => g,
        };
        match self.data {
            None => Ok(constant),
            Some(f) => {
                let p = self.vertices[v as usize];
                let value = f(e, p);
                if value.is_finite() {
                    Ok(value)
                } else {
                    Err(FemError::NonFiniteData {
                        part: e.tag.to_string(),
                        at: p.into(),
                        value,
                    })
                }
            }
        }
    }
}

/// What drives the flow of one assembly: the φ levels that the boundary prescribes
/// (Dirichlet values and Robin `g/b`), whether some Neumann or Robin flux is nonzero, and
/// per component of free space whether a Robin part anchors its level.
struct Drive {
    levels: Vec<f64>,
    flux: bool,
    anchored_by_robin: Vec<bool>,
}

impl Drive {
    /// The reference value c of ψ = c − φ: the highest prescribed level (0 if none); an
    /// error if nothing drives a flow (no flux and every level the same).
    fn reference(&self) -> Result<f64, FemError> {
        let levels = &self.levels;
        let reference = levels.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let reference = if reference.is_finite() {
            reference
        } else {
            0.0
        };
        let tol = 1e-12 * reference.abs().max(1.0);
        if !self.flux && levels.iter().all(|&l| (l - reference).abs() <= tol) {
            return Err(FemError::ConstantPotential { value: reference });
        }
        Ok(reference)
    }
}

impl Assembler {
    /// Computes the sparsity pattern and the Dirichlet map for `mesh` and the kinds of `bcs`
    /// (only which parts are Dirichlet matters here; values are taken by
    /// [`assemble`](Self::assemble)). Validates `bcs`.
    pub fn new(
        mesh: Arc<Mesh>,
        bcs: &BoundaryConditions,
        options: AssemblyOptions,
    ) -> Result<Self, FemError> {
        bcs.validate()?;
        let (kinds, fixed) = condition_kinds(&mesh, bcs);
        let dofs = DofMap::new(&mesh, &fixed);
        let (count, components) = column_counts(&mesh, &dofs);
        let col_ptr = column_pointers(&count)?;
        let mut pattern = unsorted_pattern(&mesh, &dofs.unknown_of, &col_ptr);
        let (row_idx, diag_pos) = sort_pattern(&col_ptr, &mut pattern);
        let n = dofs.free_vertices.len();
        let nnz = col_ptr[n];
        // Built from undirected mesh edges: symmetric by construction.
        let template =
            SymmetricCsc::try_from_symmetric_pattern(n, col_ptr, row_idx, vec![0.0; nnz])?;
        Ok(Assembler {
            mesh,
            options,
            conductivity: None,
            absorption: None,
            kinds,
            dofs: Arc::new(dofs),
            template,
            tri_pos: pattern.tri_pos,
            diag_pos,
            lift_pos: pattern.lift_pos,
            lift_edges: pattern.lift_edges,
            component_fixed: components.fixed,
            component_vertex: components.vertex,
        })
    }

    /// Solves ∇·(k∇φ) = 0 instead of Laplace's equation, with `k` constant on each triangle
    /// (`conductivity[t]`, positive and finite): the P1 stiffness of triangle t is scaled by
    /// k_t. Where k is small the field's flow, and a path following it, goes around: how a
    /// map's graded costs shape the field. Each triangle's cotangent weights keep their sign,
    /// so on a mesh without obtuse angles (a quadtree's right triangles) the matrix stays an
    /// M-matrix and the maximum principle holds; elsewhere an edge whose two triangles
    /// disagree can turn negative, and the system says so ([`LinearSystem::not_m_matrix`]).
    pub fn with_conductivity(mut self, conductivity: Vec<f64>) -> Result<Self, FemError> {
        self.check_per_triangle(
            &conductivity,
            |k| k > 0.0,
            |triangle, value| FemError::BadConductivity { triangle, value },
        )?;
        self.conductivity = Some(conductivity.into());
        Ok(self)
    }

    /// One finite value per triangle, each passing `ok`; else the count's error or `bad`'s.
    fn check_per_triangle(
        &self,
        values: &[f64],
        ok: impl Fn(f64) -> bool,
        bad: impl Fn(usize, f64) -> FemError,
    ) -> Result<(), FemError> {
        let expected = self.mesh.triangles().len();
        if values.len() != expected {
            return Err(FemError::ConductivityCount {
                expected,
                got: values.len(),
            });
        }
        match values.iter().position(|&v| !(v.is_finite() && ok(v))) {
            Some(t) => Err(bad(t, values[t])),
            None => Ok(()),
        }
    }

    /// Adds an absorption σ_t ≥ 0, constant on each triangle (`absorption[t]`, finite):
    /// solves −∇·(k∇φ) + σ(φ − c) = 0, where c is the reference level of ψ = c − φ (the
    /// highest prescribed level: the walls' on a map). In ψ the term is σψ: where σ > 0 the
    /// potential is drawn toward the walls' level, so ψ decays there (like e^(−√σ·d) over a
    /// distance d in a uniform region) and a path, which climbs ψ, keeps away, as it keeps
    /// away from walls: how a map's graded costs repel paths without insulating the walls
    /// behind them (which a small conductivity alone does). The term is lumped: each vertex
    /// of triangle t gets σ_t |t| / 3 on its diagonal and nothing off it, so the matrix stays
    /// an M-matrix (its rows only grow more dominant) and ψ keeps the maximum principle: with
    /// −∇·(k∇ψ) = −σψ ≤ 0, ψ has no interior local maximum.
    pub fn with_absorption(mut self, absorption: Vec<f64>) -> Result<Self, FemError> {
        self.check_per_triangle(
            &absorption,
            |s| s >= 0.0,
            |triangle, value| FemError::BadAbsorption { triangle, value },
        )?;
        self.absorption = absorption
            .iter()
            .any(|&s| s > 0.0)
            .then(|| absorption.into());
        Ok(self)
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }

    /// The number of unknowns.
    pub fn unknown_count(&self) -> usize {
        self.dofs.free_vertices.len()
    }

    /// The coordinates of the unknowns' vertices, e.g. for a nested-dissection ordering.
    pub fn unknown_coordinates(&self) -> Vec<[f64; 2]> {
        let v = self.mesh.vertices();
        self.dofs
            .free_vertices
            .iter()
            .map(|&i| [v[i as usize].x, v[i as usize].y])
            .collect()
    }

    /// Geometric nested dissection of the unknowns (from their coordinates): on the reference
    /// scene it beats AMD in symbolic + numeric factorisation time from about 30k triangles
    /// up (1M triangles: 1.1 s against 2.2 s). [`Assembler::ordering`] takes it for all but
    /// small systems.
    pub fn nested_dissection(&self) -> Ordering {
        Ordering::NestedDissection {
            coords: self.unknown_coordinates(),
        }
    }

    /// The ordering this system factors fastest with: below [`NATURAL_ORDER_BELOW`] unknowns
    /// their own numbering (a mesh numbers its vertices along a Hilbert curve from
    /// `harmonic_mesh::HILBERT_FROM` vertices, so that order is already local), where dissecting costs more than the fill it saves; from there
    /// [`Assembler::nested_dissection`].
    pub fn ordering(&self) -> Ordering {
        if self.unknown_count() < NATURAL_ORDER_BELOW {
            Ordering::Natural
        } else {
            self.nested_dissection()
        }
    }

    /// A zero system with this assembler's pattern, to fill with
    /// [`assemble_into`](Self::assemble_into).
    pub fn empty_system(&self) -> LinearSystem {
        LinearSystem {
            // The pattern is shared with the template, not copied.
            matrix: SymmetricCsc::zeros_like(&self.template),
            rhs: vec![0.0; self.unknown_count()],
            psi_fixed: vec![0.0; self.mesh.vertices().len()],
            reference: 0.0,
            excess: vec![0.0; self.unknown_count()],
            not_m_matrix: None,
            dofs: Arc::clone(&self.dofs),
        }
    }

    /// Assembles the reduced system for constant boundary conditions `bcs`.
    pub fn assemble(&self, bcs: &BoundaryConditions) -> Result<LinearSystem, FemError> {
        let mut system = self.empty_system();
        self.assemble_into(bcs, None, &mut system)?;
        Ok(system)
    }

    /// Assembles the reduced system for `bcs` with spatially varying values from `data`
    /// (see [`BoundaryData`]).
    pub fn assemble_with(
        &self,
        bcs: &BoundaryConditions,
        data: BoundaryData<'_>,
    ) -> Result<LinearSystem, FemError> {
        let mut system = self.empty_system();
        self.assemble_into(bcs, Some(data), &mut system)?;
        Ok(system)
    }

    /// Re-assembles values into an existing system of this assembler (no allocation of the
    /// pattern). `data`, if given, overrides the constant values (see [`BoundaryData`]).
    /// On error the system's contents are unspecified: assemble again before solving it.
    pub fn assemble_into(
        &self,
        bcs: &BoundaryConditions,
        data: Option<BoundaryData<'_>>,
        system: &mut LinearSystem,
    ) -> Result<(), FemError> {
        self.assemble_levels(bcs, data, None, system)
    }

    /// Assembles the system of a mesh that has no goal yet, for goals chosen later as sets of
    /// its vertices held at φ = `goal_value` ([`crate::GoalSolver`]): the goal's level joins
    /// the walls' in choosing the reference `c` of ψ = c − φ, so ψ is what a mesh with that
    /// goal would give. The goal's vertices are unknowns here.
    pub fn assemble_for_goals(
        &self,
        bcs: &BoundaryConditions,
        goal_value: f64,
    ) -> Result<LinearSystem, FemError> {
        if !goal_value.is_finite() {
            return Err(FemError::NonFinite {
                part: "goal".into(),
                what: "Dirichlet value".into(),
                value: goal_value,
            });
        }
        let mut system = self.empty_system();
        self.assemble_levels(bcs, None, Some(goal_value), &mut system)?;
        Ok(system)
    }

    fn assemble_levels(
        &self,
        bcs: &BoundaryConditions,
        data: Option<BoundaryData<'_>>,
        goal_level: Option<f64>,
        system: &mut LinearSystem,
    ) -> Result<(), FemError> {
        self.check_compatible(bcs, system)?;
        let values = BoundaryValues {
            vertices: self.mesh.vertices(),
            data,
        };
        let mut drive = self.prescribed_phi(bcs, &values, &mut system.psi_fixed)?;
        drive.levels.extend(goal_level);
        self.check_anchored(&drive.anchored_by_robin)?;
        let reference = drive.reference()?;
        self.psi_of_prescribed(reference, &mut system.psi_fixed);
        system.reference = reference;
        let lift_weight = self.scatter_stiffness(system);
        let not_m_matrix = self.lift(&lift_weight, system);
        self.boundary_terms(bcs, &values, system)?;
        system.not_m_matrix = not_m_matrix;
        Ok(())
    }

    /// Checks that `system` is one of this assembler's and that `bcs` is valid and has the
    /// same condition kind on every boundary part as the conditions the pattern was made for.
    fn check_compatible(
        &self,
        bcs: &BoundaryConditions,
        system: &LinearSystem,
    ) -> Result<(), FemError> {
        if !Arc::ptr_eq(&system.dofs, &self.dofs) {
            return Err(FemError::ForeignSystem);
        }
        bcs.validate()?;
        for (&tag, &was) in &self.kinds {
            let now = bcs.for_tag(tag).kind();
            if now != was {
                return Err(FemError::KindChanged {
                    part: tag.to_string(),
                    was,
                    now,
                });
            }
        }
        Ok(())
    }

    /// Prescribed φ (lowest wins) into `psi_fixed` (∞ at prescribed vertices that no
    /// Dirichlet part touches, 0 at unknowns), and what drives the flow.
    fn prescribed_phi(
        &self,
        bcs: &BoundaryConditions,
        values: &BoundaryValues<'_>,
        psi_fixed: &mut [f64],
    ) -> Result<Drive, FemError> {
        let mesh = &*self.mesh;
        psi_fixed.fill(f64::INFINITY);
        for (v, &u) in self.dofs.unknown_of.iter().enumerate() {
            if u != NONE {
                psi_fixed[v] = 0.0;
            }
        }
        let mut levels: Vec<f64> = Vec::new();
        let mut flux = false;
        let mut anchored_by_robin = vec![false; self.component_fixed.len()];
        for e in mesh.boundary_edges() {
            let bc = bcs.for_tag(e.tag);
            let [i, j] = e.vertices;
            let (gi, gj) = (values.at(bc, e, i)?, values.at(bc, e, j)?);
            match bc {
                BoundaryCondition::Dirichlet(_) => {
                    for (v, phi) in [(i, gi), (j, gj)] {
                        let slot = &mut psi_fixed[v as usize];
                        *slot = slot.min(phi);
                    }
                    levels.extend([gi, gj]);
                }
                BoundaryCondition::Robin { a: 0.0, b, .. } => {
                    for (v, phi) in [(i, gi / b), (j, gj / b)] {
                        let slot = &mut psi_fixed[v as usize];
                        *slot = slot.min(phi);
                    }
                    levels.extend([gi / b, gj / b]);
                }
                BoundaryCondition::Robin { b, .. } if b != 0.0 => {
                    levels.extend([gi / b, gj / b]);
                    anchored_by_robin[mesh.triangle_components()[e.triangle as usize] as usize] =
                        true;
                }
                BoundaryCondition::Neumann(_) | BoundaryCondition::Robin { .. } => {
                    flux |= gi != 0.0 || gj != 0.0;
                }
            }
        }
        Ok(Drive {
            levels,
            flux,
            anchored_by_robin,
        })
    }

    /// An error for the first component of free space with neither a prescribed vertex nor
    /// a Robin part (`anchored_by_robin`, per component) to fix the potential's level.
    fn check_anchored(&self, anchored_by_robin: &[bool]) -> Result<(), FemError> {
        let vertices = self.mesh.vertices();
        for (c, (&fixed, &robin)) in self
            .component_fixed
            .iter()
            .zip(anchored_by_robin)
            .enumerate()
        {
            if !fixed && !robin {
                let p = vertices[self.component_vertex[c] as usize];
                return Err(FemError::OnlyNeumann {
                    component: c as u32,
                    at: p.into(),
                });
            }
        }
        Ok(())
    }

    /// Turns the prescribed φ in `psi_fixed` into ψ = c − φ for the reference value `c`
    /// (0 at a prescribed vertex no Dirichlet part touches: it is unused).
    fn psi_of_prescribed(&self, reference: f64, psi_fixed: &mut [f64]) {
        for (v, slot) in psi_fixed.iter_mut().enumerate() {
            if self.dofs.unknown_of[v] == NONE {
                // Prescribed vertex: c − φ, or 0 if no Dirichlet part touches it (unused).
                *slot = if slot.is_finite() {
                    reference - *slot
                } else {
                    0.0
                };
            }
        }
    }

    /// Clears the matrix values, right-hand side and row excesses of `system` and scatters
    /// the stiffness into the matrix: K_pq = −k_t (cot θ_k)/2 for the edge opposite local
    /// vertex k of triangle t (k_t its conductivity, 1 by default), and the lumped
    /// absorption σ_t |t| / 3 on each of its vertices' diagonals. Returns the summed weight
    /// of each lifting edge.
    fn scatter_stiffness(&self, system: &mut LinearSystem) -> Vec<f64> {
        let vertices = self.mesh.vertices();
        let unknown_of = &self.dofs.unknown_of;
        let values = system.matrix.values_mut();
        values.fill(0.0);
        system.rhs.fill(0.0);
        let diag_pos = &self.diag_pos;
        system.excess.fill(0.0);
        let mut lift_weight = vec![0.0; self.lift_edges.len()];
        for (t, ((tri, pos), lift)) in self
            .mesh
            .triangles()
            .iter()
            .zip(&self.tri_pos)
            .zip(&self.lift_pos)
            .enumerate()
        {
            let [p0, p1, p2] = tri.map(|v| vertices[v as usize]);
            let k = self.conductivity.as_ref().map_or(1.0, |c| c[t]);
            let twice_area = twice_signed_area(p0, p1, p2);
            let half_inv = 0.5 * k / twice_area;
            if let Some(sigma) = &self.absorption {
                // Lumped: a third of σ_t |t| on each vertex's diagonal, counted in its row's
                // excess (the row sum the accurate elimination keeps exactly).
                let lumped = sigma[t] * twice_area / 6.0;
                for &v in tri {
                    let u = unknown_of[v as usize];
                    if u != NONE {
                        values[diag_pos[u as usize] as usize] += lumped;
                        system.excess[u as usize] += lumped;
                    }
                }
            }
            let w = [
                (p1 - p0).dot(&(p2 - p0)) * half_inv,
                (p2 - p1).dot(&(p0 - p1)) * half_inv,
                (p0 - p2).dot(&(p1 - p2)) * half_inv,
            ];
            for k in 0..3 {
                let (a, b) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
                let (ua, ub) = (unknown_of[a], unknown_of[b]);
                let wk = w[k];
                if ua != NONE {
                    values[diag_pos[ua as usize] as usize] += wk;
                    if ub != NONE {
                        values[pos[2 * k] as usize] -= wk;
                        values[pos[2 * k + 1] as usize] -= wk;
                    }
                }
                if ub != NONE {
                    values[diag_pos[ub as usize] as usize] += wk;
                }
                if lift[k] != NONE {
                    lift_weight[lift[k] as usize] += wk;
                }
            }
        }
        lift_weight
    }

    /// Lifting, per edge with both triangles' shares summed (`lift_weight`): rhs_u += w ψ_v,
    /// and the excess of row u gains w. A weight below zero beyond round-off means the edge
    /// is not Delaunay; within round-off (right angles) it is clamped to 0. Returns why the
    /// matrix is not an M-matrix, if it is not (consistent Robin mass, a negative lifting
    /// weight, or a positive off-diagonal entry).
    fn lift(&self, lift_weight: &[f64], system: &mut LinearSystem) -> Option<NotMMatrix> {
        let vertices = self.mesh.vertices();
        let values = system.matrix.values_mut();
        let diag_pos = &self.diag_pos;
        let mut not_m_matrix = (self.options.robin_mass == RobinMass::Consistent)
            .then_some(NotMMatrix::ConsistentRobinMass);
        for (&(u, v), &w) in self.lift_edges.iter().zip(lift_weight) {
            let diag = values[diag_pos[u as usize] as usize];
            if w < -1e-12 * diag && not_m_matrix.is_none() {
                let (p, q) = (
                    vertices[self.dofs.free_vertices[u as usize] as usize],
                    vertices[v as usize],
                );
                not_m_matrix = Some(NotMMatrix::NegativeEdgeWeight {
                    vertices: [self.dofs.free_vertices[u as usize], v],
                    midpoint: nalgebra::center(&p, &q).into(),
                    weight: w,
                });
            }
            let w = w.max(0.0);
            system.rhs[u as usize] += w * system.psi_fixed[v as usize];
            system.excess[u as usize] += w;
        }
        if not_m_matrix.is_none() {
            not_m_matrix = self.positive_off_diagonal(values);
        }
        not_m_matrix
    }

    /// Neumann and Robin edges: ∫ f v with f linear along the edge is |e|(2f_i + f_j)/6 on
    /// the right-hand side, and the Robin mass (lumped or consistent) in the matrix.
    fn boundary_terms(
        &self,
        bcs: &BoundaryConditions,
        values: &BoundaryValues<'_>,
        system: &mut LinearSystem,
    ) -> Result<(), FemError> {
        let vertices = self.mesh.vertices();
        let unknown_of = &self.dofs.unknown_of;
        let reference = system.reference;
        let psi_fixed = &system.psi_fixed;
        let rhs = &mut system.rhs;
        let excess = &mut system.excess;
        let matrix = system.matrix.values_mut();
        let diag_pos = &self.diag_pos;
        for e in self.mesh.boundary_edges() {
            let bc = bcs.for_tag(e.tag);
            let [i, j] = e.vertices;
            let (ui, uj) = (unknown_of[i as usize], unknown_of[j as usize]);
            if ui == NONE && uj == NONE {
                continue;
            }
            let length = (vertices[j as usize] - vertices[i as usize]).norm();
            let (gi, gj) = (values.at(bc, e, i)?, values.at(bc, e, j)?);
            // ψ flux data f (∂ψ/∂n = f − βψ) and Robin coefficient β = b/a.
            let (fi, fj, beta) = match bc {
                BoundaryCondition::Dirichlet(_) => continue,
                BoundaryCondition::Robin { a: 0.0, .. } => continue,
                BoundaryCondition::Neumann(_) => (-gi, -gj, 0.0),
                BoundaryCondition::Robin { a, b, .. } => {
                    ((b * reference - gi) / a, (b * reference - gj) / a, b / a)
                }
            };
            if ui != NONE {
                rhs[ui as usize] += length * (2.0 * fi + fj) / 6.0;
            }
            if uj != NONE {
                rhs[uj as usize] += length * (fi + 2.0 * fj) / 6.0;
            }
            if beta == 0.0 {
                continue;
            }
            match self.options.robin_mass {
                RobinMass::Lumped => {
                    for u in [ui, uj] {
                        if u != NONE {
                            matrix[diag_pos[u as usize] as usize] += beta * length / 2.0;
                            excess[u as usize] += beta * length / 2.0;
                        }
                    }
                }
                RobinMass::Consistent => {
                    let off = beta * length / 6.0;
                    for (u, other, other_u) in [(ui, j, uj), (uj, i, ui)] {
                        if u == NONE {
                            continue;
                        }
                        matrix[diag_pos[u as usize] as usize] += beta * length / 3.0;
                        if other_u == NONE {
                            rhs[u as usize] -= off * psi_fixed[other as usize];
                        }
                    }
                    if ui != NONE && uj != NONE {
                        let k = e.local_edge as usize;
                        let pos = self.tri_pos[e.triangle as usize];
                        matrix[pos[2 * k] as usize] += off;
                        matrix[pos[2 * k + 1] as usize] += off;
                    }
                }
            }
        }
        Ok(())
    }

    /// The first off-diagonal entry of the stiffness part that is positive beyond round-off
    /// (`1e-12·max(a_ii, a_jj)`), as a [`NotMMatrix`].
    fn positive_off_diagonal(&self, values: &[f64]) -> Option<NotMMatrix> {
        let a = &self.template;
        let vertices = self.mesh.vertices();
        let free = &self.dofs.free_vertices;
        let diag = |j: usize| values[self.diag_pos[j] as usize];
        (0..a.n()).find_map(|j| {
            (a.col_ptr()[j]..a.col_ptr()[j + 1]).find_map(|p| {
                let i = a.row_idx()[p];
                // `values[p] > 0` first: on a Delaunay mesh almost no entry passes it, so the
                // diagonals (scattered reads) are looked up almost never.
                (i > j && values[p] > 0.0 && values[p] > 1e-12 * diag(i).max(diag(j))).then(|| {
                    let (vi, vj) = (free[i], free[j]);
                    NotMMatrix::NegativeEdgeWeight {
                        vertices: [vi, vj],
                        midpoint: nalgebra::center(&vertices[vi as usize], &vertices[vj as usize])
                            .into(),
                        weight: -values[p],
                    }
                })
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3×3-vertex grid on [0, 2]² cut into 8 triangles (diagonals alternating), bottom side
    /// the goal, the rest walls.
    fn small_mesh() -> Arc<Mesh> {
        let vertices = (0..9)
            .map(|v| Point::new((v % 3) as f64, (v / 3) as f64 * 0.8))
            .collect();
        let triangles = vec![
            [0, 1, 4],
            [0, 4, 3],
            [1, 2, 4],
            [2, 5, 4],
            [3, 4, 6],
            [4, 7, 6],
            [4, 5, 8],
            [4, 8, 7],
        ];
        let boundary = [
            (0, 1, BoundaryTag::Goal(0)),
            (1, 2, BoundaryTag::Goal(0)),
            (2, 5, BoundaryTag::Wall),
            (5, 8, BoundaryTag::Wall),
            (8, 7, BoundaryTag::Wall),
            (7, 6, BoundaryTag::Wall),
            (6, 3, BoundaryTag::Wall),
            (3, 0, BoundaryTag::Wall),
        ];
        Arc::new(Mesh::from_parts(vertices, triangles, &boundary).expect("valid mesh"))
    }

    /// Dense reference assembly of the full stiffness matrix (all vertices).
    fn dense_stiffness(mesh: &Mesh) -> Vec<Vec<f64>> {
        let nv = mesh.vertices().len();
        let mut k = vec![vec![0.0; nv]; nv];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let p = mesh.triangle_points(t as u32);
            let area = mesh.triangle_area(t as u32);
            // ∇λ_i = rot90(p_{i+2} − p_{i+1}) / 2A.
            let g: Vec<_> = (0..3)
                .map(|i| {
                    let d = p[(i + 2) % 3] - p[(i + 1) % 3];
                    nalgebra::Vector2::new(-d.y, d.x) / (2.0 * area)
                })
                .collect();
            for i in 0..3 {
                for j in 0..3 {
                    k[tri[i] as usize][tri[j] as usize] += area * g[i].dot(&g[j]);
                }
            }
        }
        k
    }

    fn entry(a: &SymmetricCsc, i: usize, j: usize) -> f64 {
        let (rows, vals) = a.column(j);
        rows.iter().position(|&r| r == i).map_or(0.0, |p| vals[p])
    }

    #[test]
    fn matches_dense_assembly_with_lifting() {
        let mesh = small_mesh();
        let bcs = BoundaryConditions {
            walls: BoundaryCondition::Neumann(0.5),
            ..BoundaryConditions::default()
        };
        let assembler =
            Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("pattern");
        let system = assembler.assemble(&bcs).expect("assembly");
        // Goal vertices 0, 1, 2 are prescribed; 6 unknowns in vertex order.
        assert_eq!(system.free_vertices(), &[3, 4, 5, 6, 7, 8]);
        let k = dense_stiffness(&mesh);
        let free = system.free_vertices();
        let a = system.matrix();
        for (ui, &vi) in free.iter().enumerate() {
            for (uj, &vj) in free.iter().enumerate() {
                let want = k[vi as usize][vj as usize];
                assert!((entry(a, ui, uj) - want).abs() < 1e-14, "({vi}, {vj})");
            }
        }
        // Reference c = 0 (goal 0, no other level): ψ_D = 0 − 0, so the right-hand side is the
        // Neumann load only: ∂ψ/∂n = −0.5 on the walls, ∫ −0.5 v over each vertex's wall edges.
        assert_eq!(system.reference(), 0.0);
        let wall_len = |v: usize| -> f64 {
            mesh.boundary_edges()
                .iter()
                .filter(|e| e.tag == BoundaryTag::Wall && e.vertices.contains(&(v as u32)))
                .map(|e| {
                    (mesh.vertices()[e.vertices[1] as usize]
                        - mesh.vertices()[e.vertices[0] as usize])
                        .norm()
                })
                .sum()
        };
        for (ui, &vi) in free.iter().enumerate() {
            let want = -0.5 * wall_len(vi as usize) / 2.0;
            assert!(
                (system.rhs()[ui] - want).abs() < 1e-14,
                "rhs at vertex {vi}"
            );
        }
    }

    #[test]
    fn excess_is_the_row_sum_and_consistent_mass_is_not_an_m_matrix() {
        let mesh = small_mesh();
        let bcs = BoundaryConditions {
            walls: BoundaryCondition::Robin {
                a: 1.0,
                b: 3.0,
                g: 3.0,
            },
            ..BoundaryConditions::default()
        };
        let system = Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default())
            .expect("pattern")
            .assemble(&bcs)
            .expect("assembly");
        assert_eq!(system.not_m_matrix(), None);
        let a = system.matrix();
        let m = system.m_matrix().expect("M-matrix");
        for j in 0..a.n() {
            let (rows, vals) = a.column(j);
            let row_sum: f64 = vals.iter().sum();
            assert!(
                row_sum > 0.0,
                "every row here touches the goal or a Robin wall"
            );
            assert!(
                (system.excess()[j] - row_sum).abs() < 1e-14 * a.diagonal()[j],
                "row {j}: excess {} vs row sum {row_sum}",
                system.excess()[j]
            );
            let (mrows, mvals) = m.offdiag().column(j);
            let off: Vec<(usize, f64)> = rows
                .iter()
                .zip(vals)
                .filter(|(i, _)| **i != j)
                .map(|(&i, &v)| (i, -v))
                .collect();
            let got: Vec<(usize, f64)> = mrows.iter().copied().zip(mvals.iter().copied()).collect();
            assert_eq!(got, off);
        }
        let consistent = Assembler::new(
            Arc::clone(&mesh),
            &bcs,
            AssemblyOptions {
                robin_mass: RobinMass::Consistent,
            },
        )
        .expect("pattern")
        .assemble(&bcs)
        .expect("assembly");
        assert_eq!(
            consistent.not_m_matrix(),
            Some(NotMMatrix::ConsistentRobinMass)
        );
        assert!(matches!(
            consistent.m_matrix(),
            Err(FemError::NotMMatrix(NotMMatrix::ConsistentRobinMass))
        ));
    }

    #[test]
    fn lifting_moves_dirichlet_columns_to_the_right_hand_side() {
        let mesh = small_mesh();
        let bcs = BoundaryConditions::default(); // walls 1, goal 0: c = 1
        let system = Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default())
            .expect("pattern")
            .assemble(&bcs)
            .expect("assembly");
        // Only the centre vertex 4 is free; ψ_D = 1 on the goal, 0 on the walls.
        assert_eq!(system.free_vertices(), &[4]);
        let k = dense_stiffness(&mesh);
        let want: f64 = [0usize, 1, 2].iter().map(|&d| -k[4][d] * 1.0).sum();
        assert!((system.rhs()[0] - want).abs() < 1e-14);
        assert!((system.matrix().values()[0] - k[4][4]).abs() < 1e-14);
        let psi = system.expand(&[0.25]).expect("expand");
        assert_eq!(psi, vec![1.0, 1.0, 1.0, 0.0, 0.25, 0.0, 0.0, 0.0, 0.0]);
    }
}
