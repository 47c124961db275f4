//! The planner: build the mesh, the system and its factorisation once, then answer many
//! queries (point robots, car-like robots) from the same harmonic potential.

use std::sync::{Arc, OnceLock};
use std::time::Instant;

use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryConditions, MULTIGRID_REL_TOL, MultigridOptions,
    MultilevelSystem, Parallelism, Potential, SolveMethod, SolveReport, Solver,
    interior_local_extrema_except,
};
use harmonic_mesh::{
    BoundaryTag, Domain, DomainSpec, Mesh, MeshHierarchy, MeshOptions, MeshReport, Point,
    QualityReport,
};
use harmonic_trajectory::{
    CarOptions, CarPath, Collision, ExactOptions, Footprint, Path, SmoothOptions, SmoothP1Field,
    TraceStatus, Tracer, descend, drive, polyline_length, trace_exact,
};
use rayon::prelude::*;
use serde::Serialize;

use crate::scene::Scene;

/// Why a planner could not be built.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// [`PlannerOptions::threads`] could not be had.
    #[error("cannot plan on {threads} threads: {message}")]
    Threads {
        /// The threads asked for.
        threads: usize,
        /// Why not.
        message: String,
    },
    /// The scene's geometry is invalid or cannot be meshed.
    #[error(transparent)]
    Mesh(#[from] harmonic_mesh::MeshError),
    /// The boundary conditions make no solvable problem, or the solve failed.
    #[error(transparent)]
    Fem(#[from] harmonic_fem::FemError),
    /// A tracer or car option is out of range.
    #[error(transparent)]
    Trace(#[from] harmonic_trajectory::TraceError),
    /// A goal given to a [`crate::Workspace`] is not usable.
    #[error(transparent)]
    Goal(#[from] crate::workspace::GoalError),
    /// [`PlannerOptions::cancel`] asked to stop, at the start of `stage`.
    #[error("cancelled before {stage:?}")]
    Cancelled {
        /// The stage that was about to start.
        stage: Stage,
    },
    /// [`PlannerOptions::multigrid`] asked of a planner whose mesh is not a scene's own, or
    /// with the blended conditions.
    #[error(
        "multigrid (PlannerOptions::multigrid) needs a scene's own mesh and plain boundary conditions, not {what}"
    )]
    MultigridUnsupported {
        /// What the planner was built from instead.
        what: &'static str,
    },
}

/// A stage of [`Planner::with_options`], reported to [`PlannerOptions::on_stage`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Validating the scene and meshing its free space.
    Meshing,
    /// Assembling the finite element system.
    Assembling,
    /// Factoring and solving for the potential.
    Solving,
    /// The planner is built.
    Done,
}

/// Something told of each [`Stage`] as it starts (the command line draws a spinner with it).
pub type StageObserver = Arc<dyn Fn(Stage) + Send + Sync>;

/// Asked at the start of each [`Stage`] whether to stop building (true: stop).
pub type CancelCheck = Arc<dyn Fn() -> bool + Send + Sync>;

/// The conductivity k(x) > 0 of ∇·(k∇φ) = 0 at a point (taken at each triangle's centroid).
pub type Conductivity = Arc<dyn Fn(Point) -> f64 + Send + Sync>;

/// How to build a planner.
#[derive(Clone, Default)]
pub struct PlannerOptions {
    /// Called as each stage starts, and with [`Stage::Done`] at the end.
    pub on_stage: Option<StageObserver>,
    /// Threads for the Cholesky solve of the potential (by default rayon's pool from
    /// [`harmonic_solver::PARALLEL_MIN_UNKNOWNS`] unknowns). The same paths to rounding either
    /// way. The mesher's two halves (large meshes) run on two threads regardless.
    pub parallelism: Parallelism,
    /// How the potential's system is factored ([`SolveMethod::Auto`] by default: the
    /// accurate LDLᵀ up to [`harmonic_fem::AUTO_ACCURATE_MAX_UNKNOWNS`] unknowns, Cholesky
    /// above, redone accurately when ψ spans too many orders of magnitude).
    pub solve: SolveMethod,
    /// `Some(k)`: mesh at `4^k` times the scene's largest triangle area (its default when
    /// it sets none), refine that mesh uniformly `k` times ([`MeshHierarchy`]: the same
    /// smallest angle, triangles of at most the area asked) and solve by conjugate gradients
    /// with a multigrid V-cycle over those levels ([`MultilevelSystem`]) instead of a
    /// factorisation. Its work grows linearly with the mesh (a 1 M-triangle scene in about
    /// half the direct route's time), but ψ is right only to about 1e-10 of its largest
    /// value: for open scenes, not for mazes where ψ falls many orders of magnitude (the
    /// direct solve resolves those). Scene planners only ([`Planner::with_options`],
    /// [`Planner::with_constraints`]); others refuse it with
    /// [`PlanError::MultigridUnsupported`]. `None` (the default) or `Some(0)`: the direct solve.
    pub multigrid: Option<usize>,
    /// Asked at the start of every stage (meshing, assembling, solving); when it returns
    /// true the build stops there with [`PlanError::Cancelled`]. A stage already running
    /// finishes first.
    pub cancel: Option<CancelCheck>,
    /// `Some(k)`: the potential solves ∇·(k∇φ) = 0, k taken at each triangle's centroid
    /// ([`harmonic_fem::Assembler::with_conductivity`]): where k is small the flow, and the
    /// paths, go around (a map's graded costs, [`crate::map::MapOptions::cost_weight`]).
    /// Direct solves only: the multigrid route and the blend refuse it.
    pub conductivity: Option<Conductivity>,
    /// Threads for the whole build (meshing, assembly, the solve) and for tracing many
    /// starts ([`Planner::plan_many`], [`Planner::plan_report`]): `None` (the default) uses
    /// rayon's global pool, every core or `RAYON_NUM_THREADS`; `Some(n)` a pool of `n`
    /// threads the planner keeps. Paths are the same at any count.
    pub threads: Option<usize>,
}

impl PlannerOptions {
    /// Tells the observer, if any, that `stage` starts, after asking [`PlannerOptions::cancel`]
    /// whether to stop.
    pub(crate) fn stage(&self, stage: Stage) -> Result<(), PlanError> {
        if stage != Stage::Done && self.cancel.as_ref().is_some_and(|c| c()) {
            return Err(PlanError::Cancelled { stage });
        }
        if let Some(observe) = &self.on_stage {
            observe(stage);
        }
        Ok(())
    }
}

/// A scene's free space meshed: what [`Planner`] and [`crate::Workspace`] both start from.
pub(crate) struct Meshed {
    pub(crate) domain: Arc<Domain>,
    pub(crate) mesh: Arc<Mesh>,
    pub(crate) report: MeshReport,
    /// The mesh's quality report, made when first asked for (a first plan needs none).
    pub(crate) quality: Arc<OnceLock<QualityReport>>,
    /// The larger side of the domain's bounding box.
    pub(crate) scale: f64,
    /// Validating and meshing, in milliseconds.
    pub(crate) ms: f64,
    /// The levels `mesh` is the finest of, when it was refined uniformly for a multigrid
    /// solve ([`PlannerOptions::multigrid`]).
    pub(crate) hierarchy: Option<MeshHierarchy>,
}

impl Meshed {
    /// Validates and meshes `spec` with the scene's mesh options.
    pub(crate) fn new(scene: &Scene, spec: &DomainSpec) -> Result<Meshed, PlanError> {
        Meshed::constrained(scene, spec, &[], &[], 0)
    }

    /// [`Meshed::new`] with interior constraint segments and points the mesh must hold
    /// (see [`Domain::with_constraints`]), meshed at `4^refinements` times the scene's
    /// largest area and refined uniformly `refinements` times.
    pub(crate) fn constrained(
        scene: &Scene,
        spec: &DomainSpec,
        segments: &[[Point; 2]],
        points: &[Point],
        refinements: usize,
    ) -> Result<Meshed, PlanError> {
        let t = Instant::now();
        let mut mesh_options = scene.mesh_options();
        let mut domain = Domain::new(spec, &mesh_options)?;
        if !segments.is_empty() || !points.is_empty() {
            domain = domain.with_constraints(segments, points)?;
        }
        if refinements == 0 {
            return Meshed::of_domain(domain, &mesh_options, t);
        }
        // Past 8 refinements any mesh is over the hierarchy's triangle budget anyway.
        let factor = 4f64.powi(refinements.min(16) as i32);
        mesh_options.max_area = mesh_options.max_area.map(|a| a * factor);
        let mut meshed = Meshed::of_domain(domain, &mesh_options, t)?;
        let coarse = Arc::try_unwrap(meshed.mesh).unwrap_or_else(|shared| (*shared).clone());
        let hierarchy = harmonic_mesh::uniform_hierarchy(coarse, refinements)?;
        meshed.mesh = Arc::clone(hierarchy.finest());
        meshed.quality = Arc::new(OnceLock::new());
        meshed.hierarchy = Some(hierarchy);
        meshed.ms = millis(t);
        Ok(meshed)
    }

    /// Meshes a validated domain; `t` is when its validation began (counted as meshing).
    pub(crate) fn of_domain(
        domain: Domain,
        mesh_options: &MeshOptions,
        t: Instant,
    ) -> Result<Meshed, PlanError> {
        let (mesh, report) = domain.mesh(mesh_options)?;
        let ms = millis(t);
        let (lo, hi) = domain.bounding_box();
        Ok(Meshed {
            domain: Arc::new(domain),
            mesh: Arc::new(mesh),
            report,
            quality: Arc::new(OnceLock::new()),
            scale: (hi.x - lo.x).max(hi.y - lo.y),
            ms,
            hierarchy: None,
        })
    }

    /// A mesh made elsewhere, as it is: its domain from its boundary loops
    /// ([`Domain::of_mesh`]).
    pub(crate) fn of_mesh(mesh: Mesh) -> Result<Meshed, PlanError> {
        let t = Instant::now();
        let domain = Domain::of_mesh(&mesh)?;
        // The largest area and smallest angle in one pass (each triangle's smallest angle is
        // the one opposite its shortest side); the full quality report (Delaunay checks,
        // boundary loops) is made when a report asks for it.
        let (mut max_area, mut min_angle) = (0.0f64, std::f64::consts::PI);
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|v| mesh.vertices()[v as usize]);
            let sides = [(b, c, a), (c, a, b), (a, b, c)];
            let (p, q, apex) = sides
                .into_iter()
                .min_by(|x, y| {
                    (x.1 - x.0)
                        .norm_squared()
                        .total_cmp(&(y.1 - y.0).norm_squared())
                })
                .expect("three sides");
            let (u, v) = (p - apex, q - apex);
            let cross = u.x * v.y - u.y * v.x;
            max_area = max_area.max(0.5 * cross.abs());
            min_angle = min_angle.min(cross.abs().atan2(u.dot(&v)));
        }
        let report = MeshReport {
            refinement_complete: true,
            seam: None,
            input_vertices: mesh.vertices().len(),
            added_vertices: 0,
            max_area,
            min_angle_deg: min_angle.to_degrees(),
            estimated_triangles: mesh.triangles().len(),
            bridges_split: 0,
            bridges_remaining: 0,
            seam_refinements: Default::default(),
        };
        let (lo, hi) = domain.bounding_box();
        Ok(Meshed {
            domain: Arc::new(domain),
            mesh: Arc::new(mesh),
            report,
            quality: Arc::new(OnceLock::new()),
            scale: (hi.x - lo.x).max(hi.y - lo.y),
            ms: millis(t),
            hierarchy: None,
        })
    }
}

impl std::fmt::Debug for PlannerOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PlannerOptions")
            .field("on_stage", &self.on_stage.as_ref().map(|_| "observer"))
            .field("parallelism", &self.parallelism)
            .field("solve", &self.solve)
            .field("multigrid", &self.multigrid)
            .field("cancel", &self.cancel.as_ref().map(|_| "check"))
            .field("conductivity", &self.conductivity.as_ref().map(|_| "k(x)"))
            .field("threads", &self.threads)
            .finish()
    }
}

/// Wall-clock time of each stage, in milliseconds.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Timings {
    /// Validating the scene and meshing its free space.
    pub mesh: f64,
    /// Assembling the finite element system (sparsity pattern and values).
    pub assemble: f64,
    /// Ordering, factoring and solving for the potential, and recovering its nodal gradients.
    pub solve: f64,
    /// Answering a report's queries (every start, in parallel); 0 in [`Planner::timings`].
    pub trace: f64,
}

impl std::fmt::Display for Timings {
    /// `time: mesh … ms, assemble … ms, solve … ms, trace … ms`, the summaries' line.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "time: mesh {:.1} ms, assemble {:.1} ms, solve {:.1} ms, trace {:.1} ms",
            self.mesh, self.assemble, self.solve, self.trace
        )
    }
}

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
    pub(crate) quality: Arc<OnceLock<QualityReport>>,
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
    /// are) along which the robot keeps its radius from every obstacle, or `None` when there
    /// is none.
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

/// One planned path, as the `hplan plan --json` contract prints it.
#[derive(Clone, Debug, Serialize)]
pub struct PlannedPath {
    /// The query point `[x, y]`, as given.
    pub start: [f64; 2],
    /// How the path ended, serialised as `reached_goal`, `unreachable`, `stalled`,
    /// `start_in_obstacle`, `outside_workspace` or `max_steps`.
    pub status: TraceStatus,
    /// The goal reached, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goal: Option<u32>,
    /// Which tracer made the path: `smooth` (the default) or `exact` (the fallback).
    pub tracer: Tracer,
    /// Length of the polyline `points`, in scene units.
    pub length: f64,
    /// Smallest distance from the path to a wall or an obstacle (exact geometry).
    pub min_clearance: f64,
    /// Smallest |∇φ| met along the path (0 if none was met).
    pub min_gradient: f64,
    /// The path's vertices `[x, y]` from the start; on reaching the goal the last lies on its
    /// boundary.
    pub points: Vec<[f64; 2]>,
}

impl PlannedPath {
    /// The path as poses `[x, y, θ]`: each point with the heading of the path there (see
    /// [`poses_along`]); `start_heading` for the first pose if given, and on reaching the
    /// goal `goal_heading` for the last (a pose goal).
    pub fn poses(&self, start_heading: Option<f64>, goal_heading: Option<f64>) -> Vec<[f64; 3]> {
        let goal_heading = goal_heading.filter(|_| self.status.reached_goal());
        poses_along(&self.points, start_heading, goal_heading)
    }
}

/// Poses `[x, y, θ]` along a polyline: each point carries the heading of the segment that
/// leaves it (radians from +x; a zero-length segment takes the next one's), the last point
/// that of the segment arriving at it; `first` and `last`, where given, replace the headings
/// of the first and the last pose (a start's and a pose goal's heading). A single point
/// takes `first`, else `last`, else 0.
///
/// ```
/// use harmonic_planner::poses_along;
/// let poses = poses_along(&[[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]], None, Some(3.0));
/// assert_eq!(poses[0], [0.0, 0.0, 0.0]);
/// assert_eq!(poses[1], [1.0, 0.0, std::f64::consts::FRAC_PI_2]);
/// assert_eq!(poses[2], [1.0, 2.0, 3.0]);
/// ```
pub fn poses_along(points: &[[f64; 2]], first: Option<f64>, last: Option<f64>) -> Vec<[f64; 3]> {
    let n = points.len();
    // The heading of the first non-zero segment from point i on, else of the last one before.
    let mut ahead: Vec<Option<f64>> = vec![None; n];
    for i in (0..n.saturating_sub(1)).rev() {
        let (a, b) = (points[i], points[i + 1]);
        ahead[i] = if a == b {
            ahead[i + 1]
        } else {
            Some((b[1] - a[1]).atan2(b[0] - a[0]))
        };
    }
    let mut behind = None;
    let mut poses: Vec<[f64; 3]> = Vec::with_capacity(n);
    for (i, p) in points.iter().enumerate() {
        let theta = ahead[i].or(behind).or(first).or(last).unwrap_or(0.0);
        if ahead[i].is_some() {
            behind = ahead[i];
        }
        poses.push([p[0], p[1], theta]);
    }
    if let (Some(pose), Some(t)) = (poses.last_mut(), last) {
        pose[2] = t;
    }
    if let (Some(pose), Some(t)) = (poses.first_mut(), first)
        && (n > 1 || last.is_none())
    {
        pose[2] = t;
    }
    poses
}

/// One car run, as `hplan car --json` prints it.
#[derive(Clone, Debug, Serialize)]
pub struct CarRun {
    /// The start pose `[x, y, θ]`: rear-axle midpoint and heading in radians from +x.
    pub start: [f64; 3],
    /// How the run ended (as for [`PlannedPath::status`], or `collision`).
    pub status: TraceStatus,
    /// The goal reached, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goal: Option<u32>,
    /// Distance driven by the rear-axle midpoint (sum of the steps' arc lengths).
    pub length: f64,
    /// Smallest distance from the rear-axle midpoint's polyline to a wall or an obstacle.
    pub min_clearance: f64,
    /// Smallest |∇φ| met at the front axle (0 if none was met).
    pub min_gradient: f64,
    /// Largest |curvature| commanded, `tan δ / L`, in 1 / scene units.
    pub max_curvature: f64,
    /// The poses `[x, y, θ]` from the start pose, one per step.
    pub poses: Vec<[f64; 3]>,
}

/// Mesh figures of a report.
#[derive(Clone, Debug, Serialize)]
pub struct MeshSummary {
    /// Number of mesh vertices.
    pub vertices: usize,
    /// Number of triangles.
    pub triangles: usize,
    /// Smallest angle of any triangle, in degrees.
    pub min_angle_deg: f64,
    /// False if refinement stopped at its cap before meeting the area and angle bounds.
    pub refinement_complete: bool,
}

/// Potential figures of a report.
#[derive(Clone, Debug, Serialize)]
pub struct PotentialSummary {
    /// Smallest φ at a vertex (the goal's value for the default conditions).
    pub min: f64,
    /// Largest φ at a vertex (the walls' value for the default conditions).
    pub max: f64,
    /// Interior vertices that are strict local minima of φ (0 for a harmonic potential on a
    /// Delaunay mesh).
    pub interior_local_minima: usize,
    /// The smallest positive ψ = φ_wall − φ at a vertex: how flat the field gets (the
    /// smallest positive float: past the double range see `min_log10_psi`).
    pub min_psi: f64,
    /// log₁₀ of the smallest non-zero ψ, given only when ψ goes past the double range (the
    /// potential is kept with exponents, a corridor of hundreds of widths).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_log10_psi: Option<f64>,
    /// What produced ψ: `cholesky`, `cholesky (flat, checked: no interior extremum)`,
    /// `accurate`, `accurate (extended exponent)`, `multigrid`, `blend` or `goal
    /// superposition` (a workspace's goals).
    pub solved_by: &'static str,
}

/// What `hplan plan --json` and `hplan car --json` print: the mesh, the stage timings, the
/// potential's figures and one entry per path.
#[derive(Clone, Debug, Serialize)]
pub struct Report<P> {
    /// The mesh's figures.
    pub mesh: MeshSummary,
    /// Wall-clock time of each stage, in milliseconds (`trace`: all the report's queries).
    pub timings_ms: Timings,
    /// The potential's figures.
    pub potential: PotentialSummary,
    /// One entry per start, in the order given.
    pub paths: Vec<P>,
}

/// The report of `hplan plan`.
pub type PlanReport = Report<PlannedPath>;
/// The report of `hplan car`.
pub type CarReport = Report<CarRun>;

/// What a summary line says of a path or a car run.
pub trait PathSummary {
    /// Start, status, length, clearance, smallest |∇φ|.
    fn line(&self) -> (Vec<f64>, &'static str, f64, f64, f64);
}

impl PathSummary for PlannedPath {
    fn line(&self) -> (Vec<f64>, &'static str, f64, f64, f64) {
        (
            self.start.to_vec(),
            self.status.as_str(),
            self.length,
            self.min_clearance,
            self.min_gradient,
        )
    }
}

impl PathSummary for CarRun {
    fn line(&self) -> (Vec<f64>, &'static str, f64, f64, f64) {
        (
            self.start.to_vec(),
            self.status.as_str(),
            self.length,
            self.min_clearance,
            self.min_gradient,
        )
    }
}

/// The mesh and the potential for outside tools (`hplan export --potential`).
#[derive(Clone, Debug, Serialize)]
pub struct Export {
    /// Vertex positions `[x, y]`.
    pub vertices: Vec<[f64; 2]>,
    /// Triangles as three vertex indices, counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// φ at every vertex.
    pub values: Vec<f64>,
    /// ψ = φ_wall − φ at every vertex, accurate where φ rounds to φ_wall (0 where ψ is below
    /// the double range).
    pub psi: Vec<f64>,
    /// log₁₀ ψ at every vertex, exact however small ψ is; `null` where ψ = 0 (a vertex held
    /// at the walls' value).
    pub log10_psi: Vec<Option<f64>>,
    /// `[i, j, tag]` with tag `wall`, `obstacle:I` or `goal:J`; free space lies left of i → j.
    pub boundary_edges: Vec<(u32, u32, String)>,
}

/// A car-like robot: rear-wheel drive, front-wheel steering.
#[derive(Clone, Copy, Debug)]
pub struct CarParams {
    /// Distance between the axles.
    pub wheelbase: f64,
    /// Steering limit of the front wheels, radians.
    pub max_steer: f64,
    /// Arc length per step.
    pub step: f64,
    /// Check a rectangular footprint (1.25 L × 0.6 L) against the obstacles every step.
    pub check_footprint: bool,
}

impl CarParams {
    /// Defaults sized from the scene: a wheelbase of 2 % of the scene's size, 35° steering,
    /// steps of a tenth of the wheelbase.
    pub fn for_scene(planner: &Planner) -> CarParams {
        let wheelbase = 0.02 * planner.scale;
        CarParams {
            wheelbase,
            max_steer: 35f64.to_radians(),
            step: 0.1 * wheelbase,
            check_footprint: false,
        }
    }

    fn options(&self) -> CarOptions {
        CarOptions::new(self.wheelbase, self.max_steer, self.step)
    }

    /// Checks the ranges of the parameters.
    pub fn validate(&self) -> Result<(), PlanError> {
        self.options().validate()?;
        Ok(())
    }
}

/// How a solve report names the method in `potential.solved_by`.
fn solved_by(report: &SolveReport) -> &'static str {
    match (report.method, report.extended, report.flat_but_sound) {
        (SolveMethod::Cholesky, _, true) => "cholesky (flat, checked: no interior extremum)",
        (SolveMethod::Cholesky, _, false) => "cholesky",
        (_, true, _) => "accurate (extended exponent)",
        _ => "accurate",
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

fn millis(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// The smallest clearance of a path to be reported: measured along it, or known to be 0
/// (a path led in from outside the mesh, whose lead-in counts as clearance 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Clearance {
    Measure,
    Zero,
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

impl Planner {
    /// Builds the planner: validates and meshes the scene, assembles and solves for the
    /// potential.
    pub fn new(scene: &Scene) -> Result<Planner, PlanError> {
        Planner::with_options(scene, &PlannerOptions::default())
    }

    /// [`Planner::new`] with options (a stage observer).
    pub fn with_options(scene: &Scene, options: &PlannerOptions) -> Result<Planner, PlanError> {
        crate::threads::build_in(
            options,
            |e| e,
            |options| {
                options.stage(Stage::Meshing)?;
                let refinements = options.multigrid.unwrap_or(0);
                let meshed =
                    Meshed::constrained(scene, &scene.domain_spec(), &[], &[], refinements)?;
                Planner::solved(
                    meshed,
                    &scene.boundary_conditions(),
                    scene.blend_conditions(),
                    options,
                    None,
                )
            },
        )
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
        crate::threads::build_in(
            options,
            |e| e,
            |options| {
                options.stage(Stage::Meshing)?;
                let refinements = options.multigrid.unwrap_or(0);
                let meshed = Meshed::constrained(
                    scene,
                    &scene.domain_spec(),
                    segments,
                    points,
                    refinements,
                )?;
                Planner::solved(
                    meshed,
                    &scene.boundary_conditions(),
                    scene.blend_conditions(),
                    options,
                    None,
                )
            },
        )
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
        crate::threads::build_in(
            options,
            |e| e,
            |options| {
                options.stage(Stage::Meshing)?;
                let meshed = Meshed::of_domain(domain, mesh_options, Instant::now())?;
                let bcs = BoundaryConditions::default();
                Planner::solved(meshed, &bcs, None, options, entry)
            },
        )
    }

    /// A planner on a mesh made elsewhere (Triangle, gmsh; see [`crate::inputs`]), solved as
    /// it is: goal-tagged boundary edges ([`BoundaryTag::Goal`]) held at φ = 0, every other
    /// boundary edge at φ = 1 (the default conditions). The mesh must have goal edges.
    pub fn from_mesh(mesh: Mesh, options: &PlannerOptions) -> Result<Planner, PlanError> {
        Planner::entered_mesh(mesh, options, None)
    }

    /// [`Planner::from_mesh`] with a map's [`Entry`].
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
                let meshed = Meshed::of_mesh(mesh)?;
                let bcs = BoundaryConditions::default();
                Planner::solved(meshed, &bcs, None, options, entry)
            },
        )
    }

    /// Assembles and solves on `meshed` under `bcs` (or the blend), the stages after
    /// meshing that every way of building a planner shares; a map's `entry` is part of the
    /// planner from the start.
    fn solved(
        meshed: Meshed,
        bcs: &BoundaryConditions,
        blend: Option<(f64, BoundaryConditions, BoundaryConditions)>,
        options: &PlannerOptions,
        entry: Option<Entry>,
    ) -> Result<Planner, PlanError> {
        let stage = |s: Stage| options.stage(s);
        let mesh = Arc::clone(&meshed.mesh);
        if options.multigrid.unwrap_or(0) > 0 && meshed.hierarchy.is_none() {
            return Err(PlanError::MultigridUnsupported {
                what: "a map, a validated domain or a mesh made elsewhere",
            });
        }
        if options.conductivity.is_some() && (meshed.hierarchy.is_some() || blend.is_some()) {
            return Err(PlanError::MultigridUnsupported {
                what: "a conductivity (graded costs)",
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
            let cycle = levels.multigrid(MultigridOptions::default())?;
            let (potential, _) = levels.solve(&cycle, MULTIGRID_REL_TOL)?;
            (potential, assemble_ms, t, "multigrid")
        } else if let Some((k, d, n)) = blend {
            stage(Stage::Solving)?;
            let p = blended_potential(&mesh, k, &d, &n, options.parallelism)?;
            (p, 0.0, t, "blend")
        } else {
            let mut assembler = Assembler::new(Arc::clone(&mesh), bcs, AssemblyOptions::default())?;
            if let Some(k) = &options.conductivity {
                let v = mesh.vertices();
                let at_centroids = mesh
                    .triangles()
                    .iter()
                    .map(|t| {
                        let [a, b, c] = t.map(|i| v[i as usize]);
                        k(Point::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0))
                    })
                    .collect();
                assembler = assembler.with_conductivity(at_centroids)?;
            }
            let system = assembler.assemble(bcs)?;
            let assemble_ms = millis(t);

            stage(Stage::Solving)?;
            let t = Instant::now();
            // Geometric nested dissection (about half AMD's factorisation time at 1M triangles),
            // the natural order for small systems.
            let solver = Solver::with_parallelism(
                &system,
                assembler.ordering(),
                options.solve,
                options.parallelism,
            )?;
            let (potential, report) = solver.potential_with_report(Arc::clone(&mesh), &system)?;
            (potential, assemble_ms, t, solved_by(&report))
        };
        let nodal_gradients = potential.nodal_gradients_psi().to_vec();
        // Checked once here, so queries need not.
        smooth_field_of(&mesh, &potential, &nodal_gradients)?;
        let solve_ms = millis(t);
        stage(Stage::Done)?;
        Ok(Planner {
            domain: meshed.domain,
            mesh,
            mesh_report: meshed.report,
            quality: meshed.quality,
            potential,
            nodal_gradients,
            timings: Timings {
                mesh: meshed.ms + entry.as_ref().map_or(0.0, |e| e.mesh_ms),
                assemble: assemble_ms,
                solve: solve_ms,
                trace: 0.0,
            },
            scale: meshed.scale,
            vertex_goals: None,
            smooth: SmoothOptions {
                tolerance: entry
                    .as_ref()
                    .map_or(SmoothOptions::for_scale(meshed.scale).tolerance, |e| {
                        e.trace_tolerance
                    }),
                ..SmoothOptions::for_scale(meshed.scale)
            },
            entry: entry.map(|e| e.start),
            solved_by,
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

    /// The mesh's quality report (angles, areas, Delaunay checks), made at the first call.
    pub(crate) fn quality(&self) -> &QualityReport {
        self.quality.get_or_init(|| self.mesh.quality())
    }
    /// The harmonic potential (ψ = φ_wall − φ at every vertex).
    pub fn potential(&self) -> &Potential {
        &self.potential
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

    /// The potential as a smooth field (recovered gradients); its inputs were checked by
    /// [`Planner::with_options`].
    fn smooth_field(&self) -> SmoothP1Field<'_> {
        let field = smooth_field_of(&self.mesh, &self.potential, &self.nodal_gradients)
            .expect("one finite ψ and gradient per vertex, checked when the planner was built");
        match &self.vertex_goals {
            Some(goals) => field
                .with_goal_vertices(&goals.goal_of)
                .expect("one goal mark per vertex, made with the planner"),
            None => field,
        }
    }

    /// Plans a path from `start` to the goal by following the potential: the smooth tracer
    /// first; where it stalls or runs out of steps, the exact triangle-to-triangle tracer,
    /// along which φ strictly decreases.
    /// `start` is a [`Point`] or the scene format's `[x, y]`.
    pub fn plan(&self, start: impl Into<Point>) -> PlannedPath {
        self.entered(start.into(), |start, clearance| {
            let field = self.smooth_field();
            let (path, tracer) =
                descend(&field, start, None, &self.smooth, &ExactOptions::default());
            self.planned(start, path, tracer, clearance)
        })
    }

    /// The exact tracer's path from `start` (straight within each triangle, φ strictly
    /// decreasing along it).
    pub fn plan_exact(&self, start: impl Into<Point>) -> PlannedPath {
        self.entered(start.into(), |start, clearance| {
            let path = trace_exact(self.smooth_field().p1(), start, &ExactOptions::default());
            self.planned(start, path, Tracer::Exact, clearance)
        })
    }

    /// `plan(start)`, or, for a start outside the mesh that the planner's [`StartEntry`]
    /// leads in, that lead-in followed by `plan` from its last point. The lead-in keeps the
    /// robot radius but lies outside the meshed free space, so it counts as clearance 0
    /// (`plan` is told so, with [`Clearance::Zero`], and need not measure it).
    fn entered(&self, start: Point, plan: impl Fn(Point, Clearance) -> PlannedPath) -> PlannedPath {
        let Some(entry) = &self.entry else {
            return plan(start, Clearance::Measure);
        };
        if let Some([from, to]) = entry.direct(start) {
            return self.unplanned(start, TraceStatus::ReachedGoal(0), vec![from, to]);
        }
        if self.mesh.locate(start, None).is_some() {
            return plan(start, Clearance::Measure);
        }
        let lead = entry.lead_in(start, &|p| self.mesh.locate(p, None).is_some());
        let Some(lead) = lead.filter(|l| l.len() >= 2) else {
            return self.unplanned(start, entry.refusal(start), vec![start]);
        };
        let inside = lead[lead.len() - 1];
        let mut path = plan(inside, Clearance::Zero);
        let lead_length: f64 = lead.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        path.start = [start.x, start.y];
        path.length += lead_length;
        let mut points: Vec<[f64; 2]> = lead[..lead.len() - 1].iter().map(|p| [p.x, p.y]).collect();
        points.append(&mut path.points);
        path.points = points;
        path
    }

    /// A path that needed no tracer: `points` straight, or a start with no path (`status`
    /// says why, `points` holds the start alone).
    fn unplanned(&self, start: Point, status: TraceStatus, points: Vec<Point>) -> PlannedPath {
        let min_clearance = match status {
            TraceStatus::ReachedGoal(_) => self.domain.polyline_clearance(&points),
            _ => 0.0,
        };
        PlannedPath {
            start: [start.x, start.y],
            status,
            goal: match status {
                TraceStatus::ReachedGoal(j) => Some(j),
                _ => None,
            },
            tracer: Tracer::Straight,
            // (+0, not the −0 an empty sum gives, for a start alone.)
            length: polyline_length(&points).max(0.0),
            min_clearance: finite_or_zero(min_clearance),
            min_gradient: 0.0,
            points: points.iter().map(|p| [p.x, p.y]).collect(),
        }
    }

    /// Plans from every start (points or `[x, y]` arrays), in parallel.
    pub fn plan_many<P: Copy + Into<Point> + Sync>(&self, starts: &[P]) -> Vec<PlannedPath> {
        crate::threads::install(self.pool.as_deref(), || {
            starts.par_iter().map(|&s| self.plan(s)).collect()
        })
    }

    fn planned(
        &self,
        start: Point,
        mut path: Path,
        tracer: Tracer,
        clearance: Clearance,
    ) -> PlannedPath {
        if let (TraceStatus::ReachedGoal(j), Some(goals)) = (path.status, &self.vertex_goals) {
            self.finish_at_vertex_goal(&mut path.points, j, goals);
        }
        let min_clearance = match clearance {
            Clearance::Measure => self.domain.polyline_clearance(&path.points),
            Clearance::Zero => 0.0,
        };
        // The last step, inside the goal's boundary, to the goal's point (its clearance is
        // the goal's own, not measured against the goal's boundary).
        if let (TraceStatus::ReachedGoal(j), Some(entry)) = (path.status, &self.entry)
            && let Some(end) = entry.goal_point(j)
            && path.points.last() != Some(&end)
        {
            path.points.push(end);
        }
        PlannedPath {
            start: [start.x, start.y],
            status: path.status,
            goal: path.goal,
            tracer,
            length: polyline_length(&path.points),
            min_clearance: finite_or_zero(min_clearance),
            min_gradient: finite_or_zero(path.min_gradient),
            points: path.points.iter().map(|p| [p.x, p.y]).collect(),
        }
    }

    /// A path that entered a triangle of vertex goal `j` goes on, straight within that
    /// triangle, to the goal's nearest held vertex there, and from it to the goal's point when
    /// that lies in a triangle of the vertex; each segment is checked clear of the exact
    /// geometry before it is added.
    fn finish_at_vertex_goal(&self, points: &mut Vec<Point>, j: u32, goals: &VertexGoals) {
        let Some(&last) = points.last() else {
            return;
        };
        let mesh = &self.mesh;
        let Some(t) = mesh.locate(last, None) else {
            return;
        };
        let around = std::iter::once(t).chain(
            mesh.neighbors()[t as usize]
                .into_iter()
                .filter(|&n| n != harmonic_mesh::NO_NEIGHBOR),
        );
        let nearest = around
            .flat_map(|u| mesh.triangles()[u as usize])
            .filter(|&v| goals.goal_of[v as usize] == j)
            .map(|v| (v, (mesh.vertices()[v as usize] - last).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((v, _)) = nearest else {
            return;
        };
        let at = mesh.vertices()[v as usize];
        if self.domain.segment_clearance(last, at) <= 0.0 {
            return;
        }
        if at != last {
            points.push(at);
        }
        if let Some(end) = goals.ends.get(j as usize).copied().flatten()
            && end != at
            && mesh
                .locate(end, None)
                .is_some_and(|u| mesh.triangles()[u as usize].contains(&v))
            && self.domain.segment_clearance(at, end) > 0.0
        {
            points.push(end);
        }
    }

    /// Drives a car-like robot from `pose` (rear-axle midpoint, heading) along the potential.
    pub fn car(&self, pose: [f64; 3], params: &CarParams) -> Result<CarRun, PlanError> {
        let field = self.smooth_field();
        let opts = params.options();
        let collides = |corners: &[Point; 4]| {
            (0..4).any(|k| {
                self.domain
                    .segment_clearance(corners[k], corners[(k + 1) % 4])
                    <= 0.0
            })
        };
        let collision = Collision {
            footprint: Footprint {
                rear: 0.2 * params.wheelbase * 1.25,
                front: 0.8 * params.wheelbase * 1.25,
                half_width: 0.3 * params.wheelbase,
            },
            collides: &collides,
        };
        let car: CarPath = drive(
            &field,
            pose,
            &opts,
            params.check_footprint.then_some(&collision),
        )?;
        let points: Vec<Point> = car.poses.iter().map(|q| Point::new(q[0], q[1])).collect();
        let min_clearance = self.domain.polyline_clearance(&points);
        Ok(CarRun {
            start: pose,
            status: car.status,
            goal: car.goal,
            length: car.length,
            min_clearance: finite_or_zero(min_clearance),
            min_gradient: finite_or_zero(car.min_gradient),
            max_curvature: car.max_curvature,
            poses: car.poses,
        })
    }

    pub(crate) fn summaries(&self) -> (MeshSummary, PotentialSummary) {
        let psi = self.potential.psi();
        // Past the double range: the smallest non-zero ψ by its logarithm.
        let min_log10_psi = self.potential.is_extended().then(|| {
            self.potential
                .log10_psi()
                .into_iter()
                .filter(|v| v.is_finite())
                .fold(f64::INFINITY, f64::min)
        });
        let c = self.potential.reference();
        let (mut lo, mut hi, mut min_psi) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        for &v in psi {
            lo = lo.min(c - v);
            hi = hi.max(c - v);
            if v > 0.0 {
                min_psi = min_psi.min(v);
            }
        }
        (
            MeshSummary {
                vertices: self.quality().vertices,
                triangles: self.quality().triangles,
                min_angle_deg: self.quality().min_angle_deg,
                refinement_complete: self.mesh_report.refinement_complete,
            },
            PotentialSummary {
                min: lo,
                max: hi,
                interior_local_minima: match &self.vertex_goals {
                    None => self.potential.local_extrema().minima,
                    Some(g) => {
                        interior_local_extrema_except(&self.mesh, psi, |v| {
                            g.goal_of[v as usize] != harmonic_trajectory::NOT_A_GOAL
                        })
                        .minima
                    }
                },
                min_psi: finite_or_zero(min_psi),
                min_log10_psi: min_log10_psi.filter(|v| v.is_finite()),
                solved_by: self.solved_by,
            },
        )
    }

    /// Plans from every start and reports as `hplan plan --json` does.
    pub fn plan_report<P: Copy + Into<Point> + Sync>(&self, starts: &[P]) -> PlanReport {
        let t = Instant::now();
        let paths = self.plan_many(starts);
        let mut timings_ms = self.timings;
        timings_ms.trace = millis(t);
        let (mesh, potential) = self.summaries();
        PlanReport {
            mesh,
            timings_ms,
            potential,
            paths,
        }
    }

    /// Drives the car from every pose, in parallel, and reports as `hplan car --json` does.
    /// Errors only if the car parameters are invalid; how each run ended is its status.
    pub fn car_report(
        &self,
        poses: &[[f64; 3]],
        params: &CarParams,
    ) -> Result<CarReport, PlanError> {
        let t = Instant::now();
        let paths = poses
            .par_iter()
            .map(|&q| self.car(q, params))
            .collect::<Result<Vec<_>, _>>()?;
        let mut timings_ms = self.timings;
        timings_ms.trace = millis(t);
        let (mesh, potential) = self.summaries();
        Ok(CarReport {
            mesh,
            timings_ms,
            potential,
            paths,
        })
    }

    /// The mesh and potential for outside tools.
    pub fn export(&self) -> Export {
        let c = self.potential.reference();
        Export {
            vertices: self.mesh.vertices().iter().map(|p| [p.x, p.y]).collect(),
            triangles: self.mesh.triangles().to_vec(),
            values: self.potential.psi().iter().map(|&v| c - v).collect(),
            psi: self.potential.psi().to_vec(),
            log10_psi: self
                .potential
                .log10_psi()
                .into_iter()
                .map(|v| v.is_finite().then_some(v))
                .collect(),
            boundary_edges: self
                .mesh
                .boundary_edges()
                .iter()
                .map(|e| (e.vertices[0], e.vertices[1], tag_name(e.tag)))
                .collect(),
        }
    }

    /// The mesh with φ, ψ, log₁₀ ψ and ∇φ as a VTK unstructured grid for ParaView.
    pub fn vtu(&self) -> String {
        let c = self.potential.reference();
        let phi: Vec<f64> = self.potential.psi().iter().map(|&v| c - v).collect();
        let grad_phi: Vec<_> = self.nodal_gradients.iter().map(|g| -g).collect();
        let log10_psi = crate::render::floored_log10(&self.potential.log10_psi());
        crate::render::to_vtu(
            &self.mesh,
            &phi,
            self.potential.psi(),
            &log10_psi,
            &grad_phi,
        )
    }

    /// An SVG of the scene, the potential's isolines and the given paths and car runs.
    pub fn svg(
        &self,
        paths: &[Vec<[f64; 2]>],
        car_poses: &[Vec<[f64; 3]>],
        opts: &SvgOptions,
    ) -> String {
        macro_rules! rings {
            ($regions:expr) => {
                $regions
                    .iter()
                    .flat_map(|r| {
                        std::iter::once(r.exterior.clone()).chain(r.holes.iter().cloned())
                    })
                    .collect()
            };
        }
        // Past the double range the isolines follow log ψ.
        let log10_psi = self
            .potential
            .is_extended()
            .then(|| self.potential.log10_psi());
        let picture = crate::render::Picture {
            workspace: rings!(self.domain.workspace_rings()),
            obstacles: rings!(self.domain.obstacle_polygons()),
            shaded: opts
                .shaded
                .iter()
                .map(|(ring, d)| (ring.iter().copied().map(Point::from).collect(), *d))
                .collect(),
            goals: match &self.vertex_goals {
                None => rings!(self.domain.goal_polygons()),
                Some(g) => g
                    .markers
                    .iter()
                    .map(|&c| marker(c, 0.01 * self.scale))
                    .collect(),
            },
            mesh: Some(&self.mesh),
            show_mesh: opts.show_mesh,
            psi: Some(self.potential.psi()),
            log10_psi: log10_psi.as_deref(),
            paths: paths
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let colour = crate::render::PATH_COLOURS[i % crate::render::PATH_COLOURS.len()];
                    (p.iter().copied().map(Point::from).collect(), colour)
                })
                .collect(),
            car_poses: car_poses.to_vec(),
            car_size: opts.car_size,
            title: opts.title.clone(),
        };
        picture.to_svg(opts.width_px)
    }
}

/// Options of [`Planner::svg`].
#[derive(Clone, Debug)]
pub struct SvgOptions {
    /// Draw the mesh edges.
    pub show_mesh: bool,
    /// Picture width in pixels.
    pub width_px: f64,
    /// Car footprint length and width.
    pub car_size: (f64, f64),
    /// A title in the corner.
    pub title: Option<String>,
    /// Regions shaded under the picture, each with its darkness in [0, 1] (a map's graded
    /// costs: [`crate::map::OccupancyMap::cost_shading`]).
    pub shaded: Vec<(Vec<[f64; 2]>, f64)>,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            show_mesh: false,
            width_px: 800.0,
            car_size: (0.25, 0.12),
            title: None,
            shaded: Vec::new(),
        }
    }
}

/// A small 16-gon around `c`: how a goal held at mesh vertices is drawn.
fn marker(c: Point, r: f64) -> Vec<Point> {
    (0..16)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 16.0;
            Point::new(c.x + r * a.cos(), c.y + r * a.sin())
        })
        .collect()
}

/// The smooth field of a potential: on the extended ψ (mantissas and exponents) when the
/// potential keeps them, else on the floats.
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

impl<P: PathSummary> Report<P> {
    /// A human-readable summary.
    pub fn summary(&self) -> String {
        summary(
            &self.mesh,
            &self.timings_ms,
            &self.potential,
            self.paths.iter().map(P::line),
        )
    }
}

fn summary(
    mesh: &MeshSummary,
    t: &Timings,
    pot: &PotentialSummary,
    paths: impl Iterator<Item = (Vec<f64>, &'static str, f64, f64, f64)>,
) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "mesh: {} vertices, {} triangles, min angle {:.1}°",
        mesh.vertices, mesh.triangles, mesh.min_angle_deg
    );
    let _ = writeln!(s, "{t}");
    let _ = writeln!(
        s,
        "potential: φ in [{:.6}, {:.6}], smallest ψ = φ_wall − φ {:.2e}, interior local minima {}",
        pot.min, pot.max, pot.min_psi, pot.interior_local_minima
    );
    for (start, status, length, clearance, grad) in paths {
        let start: Vec<String> = start.iter().map(|v| format!("{v}")).collect();
        let _ = writeln!(
            s,
            "({}): {status}, length {length:.3}, clearance {clearance:.3}, smallest |∇φ| {grad:.2e}",
            start.join(", ")
        );
    }
    s
}
