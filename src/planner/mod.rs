//! The planner: build the mesh, the system and its factorisation once, then answer many
//! queries (point robots, car-like robots) from the same harmonic potential.

use std::sync::Arc;
use std::time::Instant;

use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryConditions, MULTIGRID_REL_TOL, MultilevelSolve,
    MultilevelSystem, Parallelism, Potential, SolveMethod, SolveReport, Solver,
    interior_local_extrema_except,
};
use harmonic_mesh::{
    BoundaryTag, Domain, DomainSpec, Mesh, MeshHierarchy, MeshOptions, MeshReport, Point,
};
use harmonic_trajectory::{
    CarOptions, CarPath, Collision, ExactOptions, Footprint, Path, PathPoint, SmoothOptions,
    SmoothP1Field, TraceStatus, Tracer, descend, drive, polyline_length, trace_exact,
};
use rayon::prelude::*;
use serde::Serialize;

use crate::scene::Scene;

mod meshed;
mod options;
mod query;
mod report;

pub use crate::error::PlanError;
pub(crate) use meshed::*;
pub use options::*;
pub use report::*;

/// A harmonic-potential planner for one scene.
///
/// ```
/// use harmonic_planner::{Planner, Scene};
/// let scene = Scene::from_json(r#"{
///     "workspace": [[0, 0], [4, 0], [4, 4], [0, 4]],
///     "obstacles": [{"polygon": [[1.5, 1], [2.5, 1], [2.5, 3], [1.5, 3]]}],
///     "goal": {"circle": {"center": [3.5, 2], "radius": 0.2}},
///     "mesh": {"max_area": 0.01}
/// }"#)?;
/// let planner = Planner::new(&scene)?;
/// let path = planner.plan([0.5, 2.0]);
/// assert!(path.status.reached_goal());
/// assert!(path.min_clearance > 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Planner {
    pub(crate) domain: Arc<Domain>,
    pub(crate) mesh: Arc<Mesh>,
    pub(crate) mesh_report: MeshReport,
    pub(crate) potential: Potential,
    pub(crate) nodal_gradients: Vec<harmonic_mesh::Vector>,
    pub(crate) timings: Timings,
    pub(crate) scale: f64,
    /// Goals held as mesh vertices (a planner from a [`crate::Workspace`]); `None` when the
    /// goals are regions of the mesh's boundary.
    pub(crate) vertex_goals: Option<Arc<VertexGoals>>,
    /// A way into the mesh for starts outside it, if the planner's source has one.
    pub(crate) entry: Option<Arc<dyn StartEntry>>,
    /// The smooth tracer's options: [`SmoothOptions::for_scale`] of the scene's size, with
    /// the tolerance the planner's source may set (a map's `Entry`).
    pub(crate) smooth: SmoothOptions,
    /// What produced ψ (`potential.solved_by` in the report).
    pub(crate) solved_by: &'static str,
    /// The pool of [`PlannerOptions::threads`], for tracing many starts (`None`: the global
    /// pool).
    pub(crate) pool: Option<Arc<rayon::ThreadPool>>,
}

/// A way into a planner's mesh from a start outside it where the robot is nonetheless safe
/// (on a map: clear cells beside the meshed blocks, see [`crate::map`]).
///
/// It also knows the goal as its source gave it: a path that reaches the goal's boundary
/// goes on to the goal's point ([`StartEntry::goal_point`]), a start that already shares the
/// goal's safe neighbourhood goes there straight ([`StartEntry::direct`]), and a start that
/// can be neither planned nor led in is told why ([`StartEntry::refusal`]).
pub trait StartEntry: Send + Sync {
    /// A polyline from `start` to a point inside the mesh (`in_mesh` tells which points
    /// are), or to goal 0's point ([`StartEntry::goal_point`]: the path is then whole),
    /// along which the robot keeps its radius from every obstacle, or `None` when there is
    /// none.
    fn lead_in(&self, start: Point, in_mesh: &dyn Fn(Point) -> bool) -> Option<Vec<Point>>;

    /// The point a path that reached goal `j` ends on, when the goal is a point that its
    /// boundary surrounds convexly (a map's goal cell): the last straight step from the
    /// boundary to it keeps the robot safe.
    fn goal_point(&self, _j: u32) -> Option<Point> {
        None
    }

    /// For a start that lies where a straight segment to the goal keeps the robot safe (in
    /// the goal's own cell), that segment.
    fn direct(&self, _start: Point) -> Option<[Point; 2]> {
        None
    }

    /// Why a start outside the mesh that [`StartEntry::lead_in`] cannot lead in has no path.
    fn refusal(&self, _start: Point) -> TraceStatus {
        TraceStatus::OutsideWorkspace
    }
}

impl std::fmt::Debug for Planner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Planner")
            .field("vertices", &self.mesh.vertices().len())
            .field("triangles", &self.mesh.triangles().len())
            .field(
                "vertex_goals",
                &self.vertex_goals.as_ref().map(|g| g.ends.len()),
            )
            .field("timings", &self.timings)
            .finish_non_exhaustive()
    }
}

/// Goals held as mesh vertices: which goal each vertex belongs to and where each ends.
#[derive(Clone, Debug)]
pub(crate) struct VertexGoals {
    /// Per vertex: its goal, or [`harmonic_trajectory::NOT_A_GOAL`].
    pub(crate) goal_of: Vec<u32>,
    /// Per goal: the point a path ends on (a point goal's point), if any.
    pub(crate) ends: Vec<Option<Point>>,
    /// Per goal: where to draw it.
    pub(crate) markers: Vec<Point>,
    /// How the field was solved.
    pub(crate) report: Option<harmonic_fem::GoalReport>,
}

/// How a solve report names the method in `potential.solved_by`; `after_multigrid` for a
/// direct solve of the finest level after the multigrid ψ failed its check
/// ([`MultilevelSystem::checked_potential`]).
fn solved_by(report: &SolveReport, after_multigrid: bool) -> &'static str {
    use SolveMethod::Cholesky;
    match (
        report.method,
        report.extended,
        report.flat_but_sound,
        after_multigrid,
    ) {
        (Cholesky, _, true, false) => "cholesky (flat, checked: no interior extremum)",
        (Cholesky, _, false, false) => "cholesky",
        (_, true, _, false) => "accurate (extended exponent)",
        (_, false, _, false) => "accurate",
        (Cholesky, _, true, true) => "cholesky (flat, checked; the multigrid ψ failed its check)",
        (Cholesky, _, false, true) => "cholesky (the multigrid ψ failed its check)",
        (_, true, _, true) => "accurate (extended exponent; the multigrid ψ failed its check)",
        (_, false, _, true) => "accurate (the multigrid ψ failed its check)",
    }
}

/// The ME766 blend `k·φ_D + (1 − k)·φ_N` on `mesh`, `φ_N` scaled to a largest value of 1.
fn blended_potential(
    mesh: &Arc<Mesh>,
    k: f64,
    dirichlet: &BoundaryConditions,
    neumann: &BoundaryConditions,
    parallelism: Parallelism,
) -> Result<Potential, PlanError> {
    let solve = |bcs: &BoundaryConditions| -> Result<Potential, PlanError> {
        let assembler = Assembler::new(Arc::clone(mesh), bcs, AssemblyOptions::default())?;
        let system = assembler.assemble(bcs)?;
        let solver = Solver::with_parallelism(
            &system,
            assembler.ordering(),
            SolveMethod::Auto,
            parallelism,
        )?;
        Ok(solver.potential(Arc::clone(mesh), &system)?)
    };
    let d = solve(dirichlet)?;
    let n = solve(neumann)?;
    // φ = c − ψ; the largest φ is c − min ψ.
    let min_psi = n.psi().iter().copied().fold(f64::INFINITY, f64::min);
    let top = n.reference() - min_psi;
    let scale = if top > 0.0 && top.is_finite() {
        1.0 / top
    } else {
        1.0
    };
    let scaled = Potential::new(
        Arc::clone(mesh),
        n.psi().iter().map(|v| v * scale).collect(),
        n.reference() * scale,
    )?;
    Ok(harmonic_fem::blend(k, &d, &scaled)?)
}

/// From this many estimated triangles a scene planner takes the multigrid route by default
/// ([`PlannerOptions::multigrid`] `None`): meshed coarser, refined uniformly
/// [`AUTO_MULTIGRID_REFINEMENTS`] times, solved by multigrid-preconditioned conjugate
/// gradients and checked, else solved directly on the same mesh. On the reference scene it
/// plans 2.3–2.7× faster than the direct route from 100 k to 1 M triangles.
pub const AUTO_MULTIGRID_FROM: usize = 100_000;

/// The uniform refinements of the automatic multigrid route (levels below the finest).
pub const AUTO_MULTIGRID_REFINEMENTS: usize = 2;

/// A coefficient field (a conductivity, an absorption) at each triangle's centroid.
fn at_centroids(mesh: &Mesh, f: &(dyn Fn(Point) -> f64 + Send + Sync)) -> Vec<f64> {
    let v = mesh.vertices();
    mesh.triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| v[i as usize]);
            f(Point::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0))
        })
        .collect()
}

/// Refuses [`PlannerOptions::multigrid`] on a mesh with no coarser levels (a map, a validated
/// domain, a mesh made elsewhere).
fn no_multigrid_without_levels(options: &PlannerOptions) -> Result<(), PlanError> {
    match options.multigrid.unwrap_or(0) {
        0 => Ok(()),
        _ => Err(PlanError::MultigridUnsupported {
            what: "a map, a validated domain or a mesh made elsewhere",
        }),
    }
}

fn millis(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// What a planner built on a map's clear cells is given up front, with its mesh: how starts
/// beside the mesh enter it, the tracer's tolerance for the map's resolution, and the
/// meshing time spent before it was asked (checking, tracing or snapping the cells).
#[derive(Clone)]
pub(crate) struct Entry {
    pub(crate) start: Arc<dyn StartEntry>,
    pub(crate) trace_tolerance: f64,
    pub(crate) mesh_ms: f64,
}

/// The blended conditions of a scene: the weight and the Dirichlet and Neumann conditions.
pub(crate) type Blend = (f64, BoundaryConditions, BoundaryConditions);

/// How a planner's potential was had, for its report: by what, and the time of each stage
/// (`started`: when its solve began; `solve_ms_before`: solve time spent before that, a
/// workspace goal's share of a blocked solve).
pub(crate) struct Solved {
    pub(crate) by: &'static str,
    pub(crate) mesh_ms: f64,
    pub(crate) assemble_ms: f64,
    pub(crate) solve_ms_before: f64,
    pub(crate) started: Instant,
}

impl Planner {
    /// Builds the planner: validates and meshes the scene, assembles and solves for the
    /// potential.
    pub fn new(scene: &Scene) -> Result<Planner, PlanError> {
        Planner::with_options(scene, &PlannerOptions::default())
    }

    /// [`Planner::new`] with options (a stage observer).
    pub fn with_options(scene: &Scene, options: &PlannerOptions) -> Result<Planner, PlanError> {
        Planner::with_constraints(scene, &[], &[], options)
    }

    /// [`Planner::with_options`] on a scene whose mesh must also hold interior constraint
    /// segments and points (a Triangle `.poly` file's inner segments and vertices, see
    /// [`crate::inputs`]).
    pub fn with_constraints(
        scene: &Scene,
        segments: &[[Point; 2]],
        points: &[Point],
        options: &PlannerOptions,
    ) -> Result<Planner, PlanError> {
        Planner::built(options, None, |options| {
            // The multigrid route by default only where it may run: the automatic solve,
            // Laplace's equation, one set of conditions.
            let refinements = match options.multigrid {
                Some(k) => Some(k),
                None if options.solve == SolveMethod::Auto
                    && options.conductivity.is_none()
                    && options.absorption.is_none()
                    && scene.blend_conditions().is_none() =>
                {
                    None
                }
                None => Some(0),
            };
            let meshed =
                Meshed::constrained(scene, &scene.domain_spec(), segments, points, refinements)?;
            Ok((
                meshed,
                scene.boundary_conditions(),
                scene.blend_conditions(),
            ))
        })
    }

    /// A planner on a validated free space ([`Domain::of_rings`], say: a map's configuration
    /// space traced as rings), meshed with `mesh_options` and solved with the default
    /// conditions (walls and obstacles φ = 1, goals φ = 0).
    pub fn from_domain(
        domain: Domain,
        mesh_options: &MeshOptions,
        options: &PlannerOptions,
    ) -> Result<Planner, PlanError> {
        Planner::entered_domain(domain, mesh_options, options, None)
    }

    /// [`Planner::from_domain`] with a map's [`Entry`].
    pub(crate) fn entered_domain(
        domain: Domain,
        mesh_options: &MeshOptions,
        options: &PlannerOptions,
        entry: Option<Entry>,
    ) -> Result<Planner, PlanError> {
        Planner::built(options, entry, |_| {
            let meshed = Meshed::of_domain(domain, mesh_options, Instant::now())?;
            Ok((meshed, BoundaryConditions::default(), None))
        })
    }

    /// A planner on a mesh made elsewhere (Triangle, gmsh; see [`crate::inputs`]), solved as
    /// it is: goal-tagged boundary edges ([`BoundaryTag::Goal`]) held at φ = 0, every other
    /// boundary edge at φ = 1 (the default conditions). The mesh must have goal edges.
    pub fn from_mesh(mesh: Mesh, options: &PlannerOptions) -> Result<Planner, PlanError> {
        Planner::entered_mesh(mesh, options, None)
    }

    /// [`Planner::from_mesh`] with a map's [`Entry`].
    ///
    /// The mesh's domain (its boundary loops, their index for the clearance queries) is
    /// built beside the assembly and the solve, which need only the mesh.
    pub(crate) fn entered_mesh(
        mesh: Mesh,
        options: &PlannerOptions,
        entry: Option<Entry>,
    ) -> Result<Planner, PlanError> {
        crate::threads::build_in(
            options,
            |e| e,
            |options| {
                options.stage(Stage::Meshing)?;
                no_multigrid_without_levels(options)?;
                let mesh = Arc::new(mesh);
                let bcs = BoundaryConditions::default();
                options.stage(Stage::Assembling)?;
                let (meshed, solved) = rayon::join(
                    || -> Result<Meshed, PlanError> {
                        let meshed = Meshed::of_shared_mesh(Arc::clone(&mesh))?;
                        meshed.domain.prepare_queries();
                        Ok(meshed)
                    },
                    || Planner::directly_solved(&mesh, &bcs, options),
                );
                let (meshed, (potential, assemble_ms, started, by)) = (meshed?, solved?);
                let solved = Solved {
                    by,
                    // The domain was built beside the other stages: the mesh was ready
                    // when the entry's meshing ended.
                    mesh_ms: entry.as_ref().map_or(meshed.ms, |e| e.mesh_ms),
                    assemble_ms,
                    solve_ms_before: 0.0,
                    started,
                };
                let planner = Planner::assembled(&meshed, potential, solved, None, entry.as_ref())?;
                options.stage(Stage::Done)?;
                Ok(planner)
            },
        )
    }

    /// The frame of every constructor above: in the pool of [`PlannerOptions::threads`]
    /// (which the planner keeps), the meshing stage announced, `mesh` makes the mesh and
    /// says its conditions (and the blend, if any); then [`Planner::solved`].
    fn built(
        options: &PlannerOptions,
        entry: Option<Entry>,
        mesh: impl FnOnce(
            &PlannerOptions,
        ) -> Result<(Meshed, BoundaryConditions, Option<Blend>), PlanError>
        + Send,
    ) -> Result<Planner, PlanError> {
        crate::threads::build_in(
            options,
            |e| e,
            |options| {
                options.stage(Stage::Meshing)?;
                let (meshed, bcs, blend) = mesh(options)?;
                Planner::solved(meshed, &bcs, blend, options, entry)
            },
        )
    }

    /// Assembles and solves on `meshed` under `bcs` (or the blend), the stages after
    /// meshing that every way of building a planner shares; a map's `entry` is part of the
    /// planner from the start.
    fn solved(
        meshed: Meshed,
        bcs: &BoundaryConditions,
        blend: Option<Blend>,
        options: &PlannerOptions,
        entry: Option<Entry>,
    ) -> Result<Planner, PlanError> {
        let stage = |s: Stage| options.stage(s);
        let mesh = Arc::clone(&meshed.mesh);
        if meshed.hierarchy.is_none() {
            no_multigrid_without_levels(options)?;
        }
        if (options.conductivity.is_some() || options.absorption.is_some())
            && (meshed.hierarchy.is_some() || blend.is_some())
        {
            return Err(PlanError::MultigridUnsupported {
                what: "a conductivity or absorption (graded costs)",
            });
        }
        stage(Stage::Assembling)?;
        let t = Instant::now();
        let (potential, assemble_ms, t, solved_by) = if let Some(hierarchy) = &meshed.hierarchy {
            if blend.is_some() {
                return Err(PlanError::MultigridUnsupported {
                    what: "the blended conditions",
                });
            }
            let levels = MultilevelSystem::assemble(hierarchy, bcs)?;
            let assemble_ms = millis(t);
            stage(Stage::Solving)?;
            let t = Instant::now();
            let (potential, how) =
                levels.checked_potential(MULTIGRID_REL_TOL, options.parallelism)?;
            let by = match how {
                MultilevelSolve::Multigrid(_) => "multigrid (checked: no interior extremum)",
                MultilevelSolve::Direct { report, .. } => solved_by(&report, true),
            };
            (potential, assemble_ms, t, by)
        } else if let Some((k, d, n)) = blend {
            stage(Stage::Solving)?;
            let p = blended_potential(&mesh, k, &d, &n, options.parallelism)?;
            (p, 0.0, t, "blend")
        } else {
            // The domain's point and clearance queries (a map mesh's boundary R-tree) are
            // built beside the assembly and solve: tracing needs them, the solve does not.
            let (solved, ()) = rayon::join(
                || Planner::directly_solved(&mesh, bcs, options),
                || meshed.domain.prepare_queries(),
            );
            solved?
        };
        let solved = Solved {
            by: solved_by,
            mesh_ms: meshed.ms + entry.as_ref().map_or(0.0, |e| e.mesh_ms),
            assemble_ms,
            solve_ms_before: 0.0,
            started: t,
        };
        let planner = Planner::assembled(&meshed, potential, solved, None, entry.as_ref())?;
        stage(Stage::Done)?;
        Ok(planner)
    }

    /// Assembles on `mesh` under `bcs` (with the options' conductivity and absorption) and
    /// solves by a direct method: the potential, the assembly's time, when the solve began
    /// and what solved it.
    fn directly_solved(
        mesh: &Arc<Mesh>,
        bcs: &BoundaryConditions,
        options: &PlannerOptions,
    ) -> Result<(Potential, f64, Instant, &'static str), PlanError> {
        let t = Instant::now();
        let mut assembler = Assembler::new(Arc::clone(mesh), bcs, AssemblyOptions::default())?;
        if let Some(k) = &options.conductivity {
            assembler = assembler.with_conductivity(at_centroids(mesh, &**k))?;
        }
        if let Some(sigma) = &options.absorption {
            assembler = assembler.with_absorption(at_centroids(mesh, &**sigma))?;
        }
        let system = assembler.assemble(bcs)?;
        let assemble_ms = millis(t);

        options.stage(Stage::Solving)?;
        let t = Instant::now();
        // Geometric nested dissection (about half AMD's factorisation time at 1M
        // triangles), the natural order for small systems.
        let solver = Solver::with_parallelism(
            &system,
            assembler.ordering(),
            options.solve,
            options.parallelism,
        )?;
        let (potential, report) = solver.potential_with_report(Arc::clone(mesh), &system)?;
        Ok((potential, assemble_ms, t, solved_by(&report, false)))
    }

    /// The one constructor every way of building a planner ends in (a scene, a domain, a
    /// mesh made elsewhere, a map, a workspace's goals), given everything up front: recovers
    /// ∇ψ at the vertices and checks the smooth field once, so queries need not.
    pub(crate) fn assembled(
        meshed: &Meshed,
        potential: Potential,
        solved: Solved,
        vertex_goals: Option<VertexGoals>,
        entry: Option<&Entry>,
    ) -> Result<Planner, PlanError> {
        let mesh = Arc::clone(&meshed.mesh);
        let nodal_gradients = potential.nodal_gradients_psi().to_vec();
        smooth_field_of(&mesh, &potential, &nodal_gradients)?;
        let smooth = SmoothOptions::for_scale(meshed.scale);
        Ok(Planner {
            domain: Arc::clone(&meshed.domain),
            mesh,
            mesh_report: meshed.report.clone(),
            potential,
            nodal_gradients,
            timings: Timings {
                mesh: solved.mesh_ms,
                assemble: solved.assemble_ms,
                solve: solved.solve_ms_before + millis(solved.started),
                trace: 0.0,
            },
            scale: meshed.scale,
            vertex_goals: vertex_goals.map(Arc::new),
            smooth: SmoothOptions {
                tolerance: entry.map_or(smooth.tolerance, |e| e.trace_tolerance),
                ..smooth
            },
            entry: entry.map(|e| Arc::clone(&e.start)),
            solved_by: solved.by,
            pool: None,
        })
    }

    /// The validated free space (merged obstacles, tagged rings, clearance queries).
    pub fn domain(&self) -> &Domain {
        &self.domain
    }
    /// The mesh of free space.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The harmonic potential (ψ = φ_wall − φ at every vertex).
    pub fn potential(&self) -> &Potential {
        &self.potential
    }
    /// What produced ψ, as the report's `potential.solved_by` says it.
    pub fn solved_by(&self) -> &'static str {
        self.solved_by
    }

    /// Time spent meshing, assembling and solving. For a planner from a
    /// [`crate::Workspace`] only `solve` is its own (the goal's solve and gradient recovery);
    /// the workspace's stages are [`crate::Workspace::timings`].
    pub fn timings(&self) -> Timings {
        self.timings
    }

    /// For a planner from a [`crate::Workspace`]: how its goal's field was solved.
    pub fn goal_report(&self) -> Option<harmonic_fem::GoalReport> {
        self.vertex_goals.as_ref().and_then(|g| g.report)
    }
}

fn smooth_field_of<'a>(
    mesh: &'a Mesh,
    potential: &'a Potential,
    nodal_gradients: &'a [harmonic_mesh::Vector],
) -> Result<SmoothP1Field<'a>, harmonic_trajectory::TraceError> {
    match (
        potential.psi_extended(),
        potential.nodal_gradients_extended(),
    ) {
        (Some((m, e)), Some((g, ge))) => SmoothP1Field::ascending_extended(mesh, m, e, g, ge),
        _ => SmoothP1Field::ascending(mesh, potential.psi(), nodal_gradients),
    }
}

pub(crate) fn tag_name(tag: BoundaryTag) -> String {
    match tag {
        BoundaryTag::Wall => "wall".into(),
        BoundaryTag::Obstacle(i) => format!("obstacle:{i}"),
        BoundaryTag::Goal(j) => format!("goal:{j}"),
    }
}

pub(crate) fn finite_or_zero(v: f64) -> f64 {
    if v.is_finite() { v } else { 0.0 }
}
