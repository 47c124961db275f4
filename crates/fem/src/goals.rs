//! Any goal from one factorisation: the walls' system factored once, a goal made of mesh
//! vertices added afterwards by a few solves against the kept factor.
//!
//! Hold the walls (Dirichlet and Robin parts as the conditions say) and leave every other
//! vertex free: that is the matrix `A` of a mesh with no goal, factored once. A goal is a set
//! `G` of its vertices held at ψ = ψ_g (the goal's level). By superposition the solution is
//!
//! ```text
//! ψ = ψ₀ + Σ_{j∈G} f_j · A⁻¹ e_j,      with   S f = ψ_g·1 − ψ₀|_G,   S = (A⁻¹)_GG,
//! ```
//!
//! where ψ₀ = A⁻¹ b₀ is what the walls alone drive (zero for the default conditions: walls at
//! the reference level, no flux) and `f_j = (A ψ)_j` is the flux the goal injects at vertex
//! `j`. The columns `A⁻¹ e_j` come from one blocked solve ([`AccurateLdlt::solve_block_in_place`]),
//! `S` is `k × k` and dense. `A⁻¹` of an M-matrix is entrywise non-negative and the goal's
//! fluxes are non-negative (ψ ≤ ψ_g everywhere), so with ψ₀ = 0 every ψ is a sum of
//! non-negative terms, each accurate entrywise through the accurate LDLᵀ: ψ keeps its
//! relative precision however small it gets, as a fresh solve with the goal held would.
//!
//! Vertices of the goal whose neighbours are all in the goal and that touch no wall carry no
//! flux (`f_j = 0` exactly): they are held without a column, so a goal region costs columns
//! only along its rim.
//!
//! Where the algebra does not allow it: with only Neumann walls (no Dirichlet part, no Robin
//! part with b/a > 0) the goal-free matrix is singular, and [`GoalSolver::new`] says so — such
//! a scene needs its goal in the mesh ([`crate::Solver`]). Robin walls and Neumann walls beside
//! a held part are fine; nonzero Neumann or Robin data make ψ₀ ≠ 0, whose terms may have
//! either sign, so those fields are accurate normwise rather than entrywise
//! ([`GoalReport::entrywise_accurate`]).

use std::collections::HashSet;
use std::sync::Arc;

use harmonic_solver::{AccurateLdlt, Cholesky, MMatrix, Ordering, SymbolicCholesky, SymmetricCsc};
use harmonic_types::Mesh;
use nalgebra::{DMatrix, DVector};

use crate::FemError;
use crate::assemble::{Assembler, LinearSystem};
use crate::bc::BoundaryConditions;
use crate::potential::Potential;
use crate::solve::SolveMethod;

/// At most this many columns are solved in one block (bounds the block's memory at
/// `n × 64` numbers); more goals are solved block after block.
pub const BLOCK_COLUMNS: usize = 64;

/// A goal may hold at most this many vertices that carry flux (its rim): the dense `k × k`
/// system grows as k³.
pub const MAX_GOAL_RIM: usize = 2048;

/// The factor kept for the goal-free system.
enum Factor {
    Accurate(AccurateLdlt),
    Cholesky(Cholesky),
}

impl Factor {
    fn solve_block(&self, x: &mut [f64], k: usize) -> Result<(), FemError> {
        match self {
            Factor::Accurate(f) => f.solve_block_in_place(x, k)?,
            Factor::Cholesky(f) => f.solve_block_in_place(x, k)?,
        }
        Ok(())
    }
}

/// The goal-free system of a mesh, factored once, answering any goal made of its vertices.
///
/// ```
/// use std::sync::Arc;
/// use harmonic_fem::{Assembler, AssemblyOptions, BoundaryConditions, GoalSolver, SolveMethod};
/// use harmonic_mesh::{BoundaryTag, Mesh, Point};
///
/// // A 4 × 4 grid of unit squares, walls all round, no goal in the mesh.
/// let n = 5u32;
/// let vertices = (0..n * n).map(|k| Point::new((k % n) as f64, (k / n) as f64)).collect();
/// let mut triangles = Vec::new();
/// for j in 0..n - 1 {
///     for i in 0..n - 1 {
///         let v = j * n + i;
///         triangles.extend([[v, v + 1, v + n + 1], [v, v + n + 1, v + n]]);
///     }
/// }
/// let mut boundary = Vec::new();
/// for i in 0..n - 1 {
///     boundary.push((i, i + 1, BoundaryTag::Wall));
///     boundary.push((i * n + n - 1, (i + 1) * n + n - 1, BoundaryTag::Wall));
///     boundary.push((n * (n - 1) + i + 1, n * (n - 1) + i, BoundaryTag::Wall));
///     boundary.push(((i + 1) * n, i * n, BoundaryTag::Wall));
/// }
/// let mesh = Arc::new(Mesh::from_parts(vertices, triangles, &boundary)?);
/// let bcs = BoundaryConditions::default();
/// let assembler = Assembler::new(mesh.clone(), &bcs, AssemblyOptions::default())?;
/// let goals = GoalSolver::new(&assembler, &bcs, SolveMethod::Auto)?;
/// // The centre vertex as the goal: held at ψ = 1, the walls at 0.
/// let solution = goals.solve(&[vec![12]])?.remove(0);
/// assert_eq!(solution.psi[12], 1.0);
/// assert!(solution.flux[0] > 0.0);
/// // Its four axis neighbours are alike by symmetry.
/// let p = &solution.psi;
/// assert!((p[7] - p[11]).abs() < 1e-14 && (p[7] - p[13]).abs() < 1e-14 && (p[7] - p[17]).abs() < 1e-14);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct GoalSolver {
    mesh: Arc<Mesh>,
    system: LinearSystem,
    factor: Factor,
    /// ψ₀ = A⁻¹ b₀ at every unknown, `None` when b₀ = 0.
    base: Option<Vec<f64>>,
    /// ψ of the goal's level, c − φ_goal.
    goal_psi: f64,
}

impl std::fmt::Debug for GoalSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GoalSolver")
            .field("unknowns", &self.system.unknown_count())
            .field("method", &self.method())
            .field("goal_psi", &self.goal_psi)
            .finish_non_exhaustive()
    }
}

/// The field of one goal, from [`GoalSolver::solve`].
#[derive(Clone, Debug)]
pub struct GoalSolution {
    /// ψ at every mesh vertex (the goal's vertices exactly at the goal's level).
    pub psi: Vec<f64>,
    /// The goal's held vertices with a column (its rim), in the order of [`Self::flux`].
    pub rim: Vec<u32>,
    /// The flux `f_j = (Aψ)_j` the goal injects at each rim vertex (non-negative in exact
    /// arithmetic when the walls alone drive nothing).
    pub flux: Vec<f64>,
    /// How the field was computed.
    pub report: GoalReport,
}

/// What [`GoalSolver::solve`] did for one goal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoalReport {
    /// Vertices held at the goal's level.
    pub held: usize,
    /// Of these, the rim: those with a column of `A⁻¹` (the rest carry no flux).
    pub columns: usize,
    /// The factorisation the columns came from: `Accurate` or `Cholesky`.
    pub method: SolveMethod,
    /// Whether every ψ is a sum of non-negative accurate terms (accurate LDLᵀ, no flux from
    /// the walls, every goal flux ≥ 0): then ψ is accurate entrywise, to its smallest values.
    pub entrywise_accurate: bool,
}

impl GoalSolver {
    /// Assembles the goal-free system of `assembler`'s mesh (which must have no goal edges
    /// held by a Dirichlet condition: goals come later, as vertices) with the goal level
    /// `bcs.goals` (Dirichlet), and factors it once: by the accurate LDLᵀ when the system is
    /// an M-matrix (for [`SolveMethod::Auto`] and [`SolveMethod::Accurate`]), else by
    /// Cholesky. Fails when the walls hold nothing (only Neumann walls), when `bcs.goals` is
    /// not a Dirichlet condition, or for [`SolveMethod::Accurate`] on a non-M-matrix.
    pub fn new(
        assembler: &Assembler,
        bcs: &BoundaryConditions,
        method: SolveMethod,
    ) -> Result<Self, FemError> {
        let crate::BoundaryCondition::Dirichlet(goal_value) = bcs.goals else {
            return Err(FemError::GoalNotDirichlet);
        };
        let mesh = Arc::clone(assembler.mesh());
        if mesh
            .boundary_edges()
            .iter()
            .any(|e| matches!(e.tag, harmonic_types::BoundaryTag::Goal(_)))
        {
            return Err(FemError::GoalInMesh);
        }
        let system = assembler
            .assemble_for_goals(bcs, goal_value)
            .map_err(|e| match e {
                FemError::OnlyNeumann { at, .. } => FemError::WallsHoldNothing { at },
                other => other,
            })?;
        let accurate = match method {
            SolveMethod::Cholesky => false,
            SolveMethod::Accurate => match system.not_m_matrix() {
                Some(reason) => return Err(FemError::NotMMatrix(reason)),
                None => true,
            },
            SolveMethod::Auto => system.not_m_matrix().is_none(),
        };
        let ordering = assembler.ordering();
        let factor = if accurate {
            Factor::Accurate(AccurateLdlt::factor(&system.m_matrix()?, ordering)?)
        } else {
            Factor::Cholesky(
                SymbolicCholesky::analyze(system.matrix(), ordering)?.factor(system.matrix())?,
            )
        };
        let base = if system.rhs().iter().any(|&b| b != 0.0) {
            let mut x = system.rhs().to_vec();
            factor.solve_block(&mut x, 1)?;
            Some(x)
        } else {
            None
        };
        let goal_psi = system.reference() - goal_value;
        Ok(GoalSolver {
            mesh,
            system,
            factor,
            base,
            goal_psi,
        })
    }

    /// The factorisation kept: [`SolveMethod::Accurate`] or [`SolveMethod::Cholesky`].
    pub fn method(&self) -> SolveMethod {
        match self.factor {
            Factor::Accurate(_) => SolveMethod::Accurate,
            Factor::Cholesky(_) => SolveMethod::Cholesky,
        }
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }

    /// The goal-free system (goal vertices are unknowns in it).
    pub fn system(&self) -> &LinearSystem {
        &self.system
    }

    /// ψ at a goal's vertices: the reference minus the goal's φ.
    pub fn goal_psi(&self) -> f64 {
        self.goal_psi
    }

    /// The fields of several independent goals, each a set of mesh vertices held at the
    /// goal's level, their columns solved together block by block. Fails if a goal is empty,
    /// names a vertex that is not an unknown (on a Dirichlet wall, or in no triangle), or has
    /// a rim of more than [`MAX_GOAL_RIM`] vertices.
    pub fn solve(&self, goals: &[Vec<u32>]) -> Result<Vec<GoalSolution>, FemError> {
        let parts = goals
            .iter()
            .enumerate()
            .map(|(g, vertices)| self.split(g, vertices))
            .collect::<Result<Vec<_>, _>>()?;
        let mut solutions = Vec::with_capacity(goals.len());
        // Goals whose rims fill a block, solved together (a rim larger than a block alone).
        let mut start = 0;
        while start < parts.len() {
            let mut end = start + 1;
            let mut width = parts[start].rim.len();
            while end < parts.len() && width + parts[end].rim.len() <= BLOCK_COLUMNS {
                width += parts[end].rim.len();
                end += 1;
            }
            let block = self.columns(parts[start..end].iter().flat_map(|p| &p.rim), width)?;
            let mut offset = 0;
            for part in &parts[start..end] {
                solutions.push(self.combine(part, &block, width, offset)?);
                offset += part.rim.len();
            }
            start = end;
        }
        Ok(solutions)
    }

    /// A goal's unknowns, split into its rim (flux-carrying, with a column) and its inside.
    fn split(&self, goal: usize, vertices: &[u32]) -> Result<GoalPart, FemError> {
        if vertices.is_empty() {
            return Err(FemError::EmptyGoal { goal });
        }
        let mut held = Vec::with_capacity(vertices.len());
        let mut seen = HashSet::with_capacity(vertices.len());
        for &v in vertices {
            let u = self
                .system
                .unknown_of(v)
                .ok_or(FemError::GoalVertexNotFree { goal, vertex: v })?;
            if seen.insert(u) {
                held.push(u as usize);
            }
        }
        let excess = self.system.excess();
        let a = self.system.matrix();
        let (rim, inside): (Vec<usize>, Vec<usize>) = held.into_iter().partition(|&u| {
            excess[u] != 0.0 || a.column(u).0.iter().any(|i| !seen.contains(&(*i as u32)))
        });
        if rim.len() > MAX_GOAL_RIM {
            return Err(FemError::GoalTooLarge {
                goal,
                rim: rim.len(),
                max: MAX_GOAL_RIM,
            });
        }
        Ok(GoalPart { rim, inside })
    }

    /// The columns `A⁻¹ e_u` for the given unknowns, as an `n × width` row-major block.
    fn columns<'a>(
        &self,
        unknowns: impl Iterator<Item = &'a usize>,
        width: usize,
    ) -> Result<Vec<f64>, FemError> {
        let n = self.system.unknown_count();
        let mut block = vec![0.0; n * width];
        for (c, &u) in unknowns.enumerate() {
            block[u * width + c] = 1.0;
        }
        self.factor.solve_block(&mut block, width)?;
        Ok(block)
    }

    /// ψ for one goal from its columns `block[.., offset .. offset + k]`.
    fn combine(
        &self,
        part: &GoalPart,
        block: &[f64],
        width: usize,
        offset: usize,
    ) -> Result<GoalSolution, FemError> {
        let n = self.system.unknown_count();
        let k = part.rim.len();
        let column = |u: usize, j: usize| block[u * width + offset + j];
        // S = (A⁻¹)_GG (symmetric in exact arithmetic: average the two halves).
        let s = DMatrix::from_fn(k, k, |i, j| {
            0.5 * (column(part.rim[i], j) + column(part.rim[j], i))
        });
        let base = |u: usize| self.base.as_ref().map_or(0.0, |b| b[u]);
        let target = DVector::from_fn(k, |i, _| self.goal_psi - base(part.rim[i]));
        let flux = solve_dense(&s, &target).ok_or(FemError::GoalSingular)?;
        let mut x: Vec<f64> = (0..n)
            .map(|u| {
                let row = &block[u * width + offset..u * width + offset + k];
                base(u) + row.iter().zip(flux.iter()).map(|(c, f)| c * f).sum::<f64>()
            })
            .collect();
        for &u in part.rim.iter().chain(&part.inside) {
            x[u] = self.goal_psi;
        }
        let accurate = matches!(self.factor, Factor::Accurate(_))
            && self.base.is_none()
            && flux.iter().all(|&f| f >= 0.0);
        let free = self.system.free_vertices();
        Ok(GoalSolution {
            psi: self.system.expand(&x)?,
            rim: part.rim.iter().map(|&u| free[u]).collect(),
            flux: flux.iter().copied().collect(),
            report: GoalReport {
                held: part.rim.len() + part.inside.len(),
                columns: k,
                method: self.method(),
                entrywise_accurate: accurate,
            },
        })
    }

    /// A goal's ψ (from [`GoalSolver::solve`] or [`GoalSolver::solve_fresh`]) as a
    /// [`Potential`] on the mesh.
    pub fn potential_of(&self, psi: Vec<f64>) -> Result<Potential, FemError> {
        Potential::new(Arc::clone(&self.mesh), psi, self.system.reference())
    }

    /// The same goal solved from scratch, for checks: the goal's vertices eliminated from the
    /// goal-free system (as a mesh with the goal held would give), a new factorisation of the
    /// remaining unknowns (the accurate LDLᵀ with AMD, or Cholesky) and one solve. Costs a
    /// whole factorisation: this is what [`GoalSolver::solve`] saves.
    pub fn solve_fresh(&self, vertices: &[u32]) -> Result<Vec<f64>, FemError> {
        let part = self.split(0, vertices)?;
        let n = self.system.unknown_count();
        let mut held = vec![false; n];
        for &u in part.rim.iter().chain(&part.inside) {
            held[u] = true;
        }
        let mut index = vec![usize::MAX; n];
        let free: Vec<usize> = (0..n).filter(|&u| !held[u]).collect();
        for (i, &u) in free.iter().enumerate() {
            index[u] = i;
        }
        let a = self.system.matrix();
        let m = free.len();
        let (mut col_ptr, mut rows, mut vals) = (vec![0], Vec::new(), Vec::new());
        let mut excess: Vec<f64> = free.iter().map(|&u| self.system.excess()[u]).collect();
        let mut rhs: Vec<f64> = free.iter().map(|&u| self.system.rhs()[u]).collect();
        let accurate = matches!(self.factor, Factor::Accurate(_));
        for (j, &u) in free.iter().enumerate() {
            let (r, v) = a.column(u);
            for (&i, &aij) in r.iter().zip(v) {
                if held[i] {
                    // The goal's value lifted to the right-hand side; its weight joins the
                    // row's excess (a sum of non-negative terms, as the assembler makes it).
                    rhs[j] -= aij * self.goal_psi;
                    excess[j] += (-aij).max(0.0);
                } else if i == u {
                    if !accurate {
                        rows.push(j);
                        vals.push(aij);
                    }
                } else {
                    rows.push(index[i]);
                    vals.push(if accurate { (-aij).max(0.0) } else { aij });
                }
            }
            col_ptr.push(rows.len());
        }
        let matrix = SymmetricCsc::try_new(m, col_ptr, rows, vals)?;
        let x = if accurate {
            AccurateLdlt::factor(&MMatrix::try_new(matrix, excess)?, Ordering::Amd)?.solve(&rhs)?
        } else {
            SymbolicCholesky::analyze(&matrix, Ordering::Amd)?
                .factor(&matrix)?
                .solve(&rhs)?
        };
        let mut full = vec![self.goal_psi; n];
        for (i, &u) in free.iter().enumerate() {
            full[u] = x[i];
        }
        self.system.expand(&full)
    }
}

/// A goal's unknowns: its rim (with columns) and its inside (no flux).
struct GoalPart {
    rim: Vec<usize>,
    inside: Vec<usize>,
}

/// Solves the small SPD system `S f = t` by Cholesky (LU if round-off spoils definiteness)
/// with one step of iterative refinement.
fn solve_dense(s: &DMatrix<f64>, t: &DVector<f64>) -> Option<DVector<f64>> {
    enum Dense {
        Cholesky(nalgebra::Cholesky<f64, nalgebra::Dyn>),
        Lu(nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>),
    }
    let factor = match s.clone().cholesky() {
        Some(c) => Dense::Cholesky(c),
        None => Dense::Lu(s.clone().lu()),
    };
    let solve = |rhs: &DVector<f64>| match &factor {
        Dense::Cholesky(c) => Some(c.solve(rhs)),
        Dense::Lu(lu) => lu.solve(rhs),
    };
    let mut f = solve(t)?;
    let residual = t - s * &f;
    f += solve(&residual)?;
    f.iter().all(|v| v.is_finite()).then_some(f)
}
