//! Volume scenes (`"dimension": 3`): the same pipeline as the plane's — mesh (isosurface
//! stuffing), assemble P1 on tetrahedra, solve for ψ, trace — with reports in the JSON
//! contract's shape.
//!
//! ```
//! use harmonic_planner::volume::{VolumePlanner, parse_volume_scene};
//! let scene = parse_volume_scene(r#"{
//!     "dimension": 3,
//!     "workspace": {"box": {"min": [0, 0, 0], "max": [4, 2, 2]}},
//!     "obstacles": [{"box": {"min": [1.5, -1, -1], "max": [2.5, 1.2, 3]}}],
//!     "goal": {"sphere": {"center": [3.5, 1, 1], "radius": 0.3}},
//!     "mesh": {"max_volume": 0.004}
//! }"#)?;
//! let planner = VolumePlanner::new(&scene)?;
//! let path = planner.plan([0.5, 1.0, 1.0]);
//! assert!(path.status.reached_goal());
//! // Around the wall, through the gap beside it (y > 1.2).
//! assert!(path.points.iter().any(|p| p[1] > 1.2));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;
use std::time::Instant;

use harmonic_fem::volume::{
    VolumeAssembler, VolumePotential, VolumeSolveMethod, VolumeSolveReport,
    solve_assembled_for_planning,
};
use harmonic_trajectory::volume::{
    ExactVolumeOptions, P1VolumeField, VolumeFieldParts, VolumeFieldTopology, trace_exact_volume,
};
use harmonic_trajectory::{Locate, Path, SmoothOptions, TraceStatus, Tracer, trace_smooth};
use harmonic_volume::io::PointData;
use harmonic_volume::{
    GoalRegion, MeshOptions, MeshReport, Point, PointClass, TetMesh, VolumeDomain, quality,
};
use rayon::prelude::*;
use serde::Serialize;

use crate::PlanError;
use crate::planner::{PlannedPath, PotentialSummary, Report, Timings, finite_or_zero, tag_name};
use crate::scene::SceneError;

pub use crate::scene::VolumeScene;
pub use harmonic_volume::VolumeError;

/// Parses a volume scene from JSON; errors name the field, line and column as for plane
/// scenes. (A file of either kind: [`crate::AnyScene::from_file`].)
pub fn parse_volume_scene(text: &str) -> Result<VolumeScene, SceneError> {
    crate::scene::parse_json(text)
}

/// A harmonic-potential planner for one volume scene: built once, queried many times.
pub struct VolumePlanner {
    domain: VolumeDomain,
    mesh: Arc<TetMesh>,
    report: MeshReport,
    potential: VolumePotential,
    /// The traced field's precomputed parts (vertex → tetrahedra, recovered gradients,
    /// components), built once so a query is only a trace.
    field: Arc<VolumeFieldParts>,
    clamped_edges: usize,
    positive_offdiagonals: usize,
    /// What produced ψ (`potential.solved_by`).
    solved_by: &'static str,
    timings: Timings,
    scale: f64,
}

/// The mesh part of a volume report.
#[derive(Clone, Debug, Serialize)]
pub struct VolumeMeshSummary {
    /// Mesh vertices.
    pub vertices: usize,
    /// Tetrahedra.
    pub tetrahedra: usize,
    /// Boundary faces.
    pub boundary_faces: usize,
    /// Smallest dihedral angle, degrees.
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle, degrees.
    pub max_dihedral_deg: f64,
    /// Edges whose P1 stiffness weight is negative (a positive off-diagonal).
    pub negative_weight_edges: usize,
    /// Of those, the ones clamped to zero because the Galerkin solution had an interior
    /// extremum (0 when the plain Galerkin field was kept).
    pub clamped_edges: usize,
    /// Lattice spacing of the stuffing.
    pub spacing: f64,
}

/// The report of `hplan plan` on a volume scene.
pub type VolumePlanReport = Report<PlannedPath<Point>, VolumeMeshSummary>;

impl std::fmt::Display for VolumeMeshSummary {
    /// `mesh: … vertices, … tetrahedra, dihedral angles …°–…°`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "mesh: {} vertices, {} tetrahedra, dihedral angles {:.1}°–{:.1}°",
            self.vertices, self.tetrahedra, self.min_dihedral_deg, self.max_dihedral_deg
        )
    }
}

/// How a volume or configuration-space solve names itself in `potential.solved_by`.
pub(crate) fn volume_solved_by(report: &VolumeSolveReport, clamped: bool) -> &'static str {
    use VolumeSolveMethod::{Accurate, Auto, Cholesky, Multigrid, Pcg};
    match (report.method, clamped) {
        (Accurate, false) => "accurate",
        (Accurate, true) => "accurate (clamped M-matrix)",
        (Cholesky, false) => "cholesky",
        (Cholesky, true) => "cholesky (clamped M-matrix)",
        (Pcg | Auto, false) => "pcg",
        (Pcg | Auto, true) => "pcg (clamped M-matrix)",
        (Multigrid, false) => "multigrid",
        (Multigrid, true) => "multigrid (clamped M-matrix)",
    }
}

/// The potential's figures on a tetrahedral mesh (a volume, a configuration space's slab).
pub(crate) fn volume_potential_summary(
    potential: &VolumePotential,
    solved_by: &'static str,
    positive_offdiagonals: usize,
) -> PotentialSummary {
    let phi = potential.phi_at_vertices();
    PotentialSummary {
        min: phi.iter().copied().fold(f64::INFINITY, f64::min),
        max: phi.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        interior_local_minima: potential.interior_local_minima(),
        interior_local_extrema: Some(potential.interior_local_extrema()),
        min_psi: PotentialSummary::smallest_positive(potential.psi()),
        min_log10_psi: None,
        positive_offdiagonals: Some(positive_offdiagonals),
        solved_by,
    }
}

impl VolumeExport {
    /// `mesh` and `potential` as outside tools read them.
    pub(crate) fn of(mesh: &TetMesh, potential: &VolumePotential) -> VolumeExport {
        VolumeExport {
            vertices: mesh.vertices().iter().map(|p| [p.x, p.y, p.z]).collect(),
            tetrahedra: mesh.tetrahedra().to_vec(),
            values: potential.phi_at_vertices(),
            psi: potential.psi().to_vec(),
            boundary_faces: mesh
                .boundary_faces()
                .iter()
                .map(|f| {
                    let [i, j, k] = f.vertices;
                    (i, j, k, tag_name(f.tag))
                })
                .collect(),
        }
    }
}

/// The mesh and the potential for outside tools (`hplan export --potential` on a volume or,
/// in scaled coordinates, a configuration space's slab).
#[derive(Clone, Debug, Serialize)]
pub struct VolumeExport {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Positively oriented tetrahedra.
    pub tetrahedra: Vec<[u32; 4]>,
    /// φ per vertex (underflows to the wall value where ψ is below the float's resolution).
    pub values: Vec<f64>,
    /// ψ = φ_wall − φ per vertex, accurate however small.
    pub psi: Vec<f64>,
    /// Boundary faces `[i, j, k, tag]`, normals out of free space.
    pub boundary_faces: Vec<(u32, u32, u32, String)>,
}

fn millis(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

impl VolumePlanner {
    /// Builds the planner: validates and meshes the scene, assembles and solves for ψ.
    pub fn new(scene: &VolumeScene) -> Result<VolumePlanner, PlanError> {
        let t = Instant::now();
        let domain = scene.build()?;
        let max_volume = scene.max_volume(&domain)?;
        let (mesh, report) = domain.mesh(&MeshOptions::with_max_volume(max_volume))?;
        let mesh = Arc::new(mesh);
        let mesh_ms = millis(t);

        let t = Instant::now();
        let bcs = scene.conditions();
        let assembler = VolumeAssembler::new(Arc::clone(&mesh), &bcs)?;
        let system = assembler.assemble(&bcs)?;
        let positive_offdiagonals = system.positive_offdiagonals();
        let assemble_ms = millis(t);

        let t = Instant::now();
        // Stuffed meshes keep a few obtuse tetrahedra; where their positive off-diagonals let
        // the Galerkin field have an interior extremum (or ψ is too flat for Cholesky), the
        // planning solve redoes it on the M-matrix with those weights clamped.
        // The mesh's point-location grid (what a first query would build) and what the field
        // needs of the mesh alone beside the solve.
        let (solved, topology) = rayon::join(
            || solve_assembled_for_planning(&assembler, &bcs, &system),
            || {
                mesh.prepare_locate();
                VolumeFieldTopology::of(&mesh)
            },
        );
        let (potential, solve, clamped) = solved?;
        let solved_by = volume_solved_by(&solve, clamped.is_some());
        let clamped_edges = clamped.unwrap_or(0);
        let field =
            Arc::clone(P1VolumeField::ascending_with(&mesh, topology, potential.psi())?.parts());
        let solve_ms = millis(t);

        let (lo, hi) = mesh.bounds();
        let scale = (hi - lo).max();
        Ok(VolumePlanner {
            domain,
            mesh,
            report,
            potential,
            field,
            clamped_edges,
            positive_offdiagonals,
            solved_by,
            timings: Timings {
                mesh: mesh_ms,
                assemble: assemble_ms,
                solve: solve_ms,
                trace: 0.0,
            },
            scale,
        })
    }

    /// The tetrahedral mesh.
    pub fn mesh(&self) -> &TetMesh {
        &self.mesh
    }

    /// The validated free space.
    pub fn domain(&self) -> &VolumeDomain {
        &self.domain
    }

    /// The potential.
    pub fn potential(&self) -> &VolumePotential {
        &self.potential
    }

    /// What produced ψ, as the report's `potential.solved_by` says it.
    pub fn solved_by(&self) -> &'static str {
        self.solved_by
    }

    /// Milliseconds spent building.
    pub fn timings(&self) -> Timings {
        self.timings
    }

    /// Plans from `start`: the smooth tracer, or the exact tet-to-tet tracer where the smooth
    /// one stalls or runs out of steps. A free start that the mesh does not reach (it keeps
    /// a safety margin off curved and sharp obstacles) is first led straight to the nearest
    /// point of the mesh, where that segment keeps the robot's radius from every solid.
    pub fn plan(&self, start: [f64; 3]) -> PlannedPath<Point> {
        let p = Point::new(start[0], start[1], start[2]);
        if let Some(entry) = self.lead_in(&p) {
            let mut out = self.trace_from(entry);
            out.start = start;
            out.length += (entry - p).norm();
            out.points.insert(0, start);
            out.min_clearance = out.min_clearance.min(finite_or_zero(self.clearance(&p)));
            return out;
        }
        self.trace_from(p)
    }

    /// The point just inside the mesh a free start off the mesh is led to (see
    /// [`plan`](Self::plan)), or `None` when the start is on the mesh, not free, or the
    /// straight way in is not clear.
    fn lead_in(&self, p: &Point) -> Option<Point> {
        if self.mesh.locate(p, None).is_some() {
            return None;
        }
        let radius = self.domain.robot_radius();
        if self.domain.classify(p, self.report.point_goal_radius) != PointClass::Free {
            return None;
        }
        let (q, face) = harmonic_volume::nearest_boundary_point(&self.mesh, p)?;
        let tet = self.mesh.boundary_faces()[face].tet;
        let inner = Point::from(
            self.mesh
                .tet_points(tet)
                .iter()
                .map(|v| v.coords)
                .sum::<harmonic_volume::Vector>()
                / 4.0,
        );
        let entry = q + (inner - q) * 1e-6;
        self.mesh.locate(&entry, Some(tet))?;
        let samples = 64;
        let clear = (0..=samples).all(|k| {
            let x = p + (entry - p) * (k as f64 / samples as f64);
            self.clearance(&x) >= radius - 1e-12
        });
        clear.then_some(entry)
    }

    /// Traces from `start` as it is.
    fn trace_from(&self, p: Point) -> PlannedPath<Point> {
        let start = [p.x, p.y, p.z];
        let goal_radius = self.report.point_goal_radius;
        let classify = |q: &Point| match self.domain.classify(q, goal_radius) {
            PointClass::Free => Locate::Inside(0),
            PointClass::Goal(j) => Locate::Goal(j),
            PointClass::Obstacle(_) => Locate::InObstacle,
            PointClass::OutsideWorkspace => Locate::OutsideWorkspace,
        };
        let field = P1VolumeField::from_parts(&self.mesh, Arc::clone(&self.field))
            .expect("the parts were built on this mesh")
            .with_outside(&classify);
        let smooth = trace_smooth(&field, p, &SmoothOptions::for_scale(self.scale));
        let (path, tracer) = match smooth {
            Ok(path)
                if !matches!(
                    path.status,
                    TraceStatus::Stalled { .. } | TraceStatus::MaxSteps
                ) =>
            {
                (path, Tracer::Smooth)
            }
            _ => (
                trace_exact_volume(&field, p, &ExactVolumeOptions::default()),
                Tracer::Exact,
            ),
        };
        self.planned(start, path, tracer)
    }

    /// Plans from every start, in parallel.
    pub fn plan_many(&self, starts: &[[f64; 3]]) -> Vec<PlannedPath<Point>> {
        starts.par_iter().map(|&s| self.plan(s)).collect()
    }

    fn planned(
        &self,
        start: [f64; 3],
        mut path: Path<Point>,
        tracer: Tracer,
    ) -> PlannedPath<Point> {
        // A point goal is carved as a small free ball around it: the last straight step from
        // the ball's face ends exactly on the point.
        if let TraceStatus::ReachedGoal(j) = path.status
            && let Some(GoalRegion::Point(g)) = self.domain.goals().get(j as usize)
            && let Some(last) = path.points.last().copied()
            && last != *g
        {
            path.length += (g - last).norm();
            path.points.push(*g);
        }
        let clearance = path
            .points
            .iter()
            .map(|q| self.clearance(q))
            .fold(f64::INFINITY, f64::min);
        let blocked = matches!(
            path.status,
            TraceStatus::StartInObstacle | TraceStatus::OutsideWorkspace
        );
        let mut blocked_by = if blocked {
            match self
                .domain
                .classify(&Point::new(start[0], start[1], start[2]), 0.0)
            {
                PointClass::Obstacle(i) => Some(format!("obstacle {i}")),
                PointClass::OutsideWorkspace => Some("the workspace".to_string()),
                _ => None,
            }
        } else {
            None
        };
        // A path that reached the goal but whose robot touches a solid on the way (a chord of
        // the stuffed boundary across something thinner than the mesh) is not reached.
        let mut status = path.status;
        let mut clearance = clearance;
        if status.reached_goal()
            && let Some((q, what)) = self.first_contact(&path.points)
        {
            status = TraceStatus::Collision { at: None };
            clearance = 0.0;
            blocked_by = Some(format!(
                "{what} at ({:.4}, {:.4}, {:.4}), where it is thinner than the mesh; a smaller \
                 mesh.max_volume resolves it",
                q.x, q.y, q.z
            ));
        }
        PlannedPath {
            start,
            status,
            goal: path.goal,
            blocked_by,
            tracer,
            length: path.length,
            min_clearance: finite_or_zero(clearance),
            min_gradient: finite_or_zero(path.min_gradient),
            points: path.points.iter().map(|q| [q.x, q.y, q.z]).collect(),
        }
    }

    /// The first segment of the polyline `points` along which the robot comes closer than its
    /// radius (less 1e-6 of the scene) to an obstacle or leaves the workspace shrunk by it —
    /// exact segment-to-solid distances (parry), so no obstacle however thin is stepped over
    /// — as the point of the segment nearest to the offending solid's surface, and which
    /// solid that is.
    fn first_contact(&self, points: &[Point]) -> Option<(Point, String)> {
        let radius = self.domain.robot_radius();
        let tol = 1e-6 * self.scale;
        for w in points.windows(2) {
            let (a, b) = (w[0], w[1]);
            // A distance of 0 is a touch or a crossing: a crossing has points inside, found
            // by sampling the segment finely (only then).
            let inside = || self.closest_to_solids(&a, &b).1 < radius - tol;
            let hit = self
                .domain
                .obstacles()
                .iter()
                .enumerate()
                .find(|(_, o)| {
                    let d = o.distance_to_segment(&a, &b);
                    d < radius - tol || (d <= 0.0 && inside())
                })
                .map(|(i, _)| format!("obstacle {i}"))
                .or_else(|| {
                    // The workspace's boundary (large, not thin) by sampling the signed
                    // distance (1-Lipschitz): steps as long as the gap, at least 1e-3 of the
                    // scene.
                    let min_step = 1e-3 * self.scale;
                    let len = (b - a).norm();
                    let mut t = 0.0;
                    loop {
                        let q = a + (b - a) * (t / len.max(f64::MIN_POSITIVE)).min(1.0);
                        let gap = -self.domain.workspace().signed_distance(&q) - radius;
                        if gap < -tol {
                            return Some("the workspace boundary".to_string());
                        }
                        if t >= len {
                            return None;
                        }
                        t = (t + gap.max(min_step)).min(len);
                    }
                });
            if let Some(what) = hit {
                return Some((self.closest_to_solids(&a, &b).0, what));
            }
        }
        None
    }

    /// The point of the segment a–b with the smallest clearance, and that clearance, sampled
    /// at 1e-4 of the segment.
    fn closest_to_solids(&self, a: &Point, b: &Point) -> (Point, f64) {
        (0..=10_000)
            .map(|k| {
                let p = a + (b - a) * (k as f64 / 10_000.0);
                (p, self.clearance(&p))
            })
            .min_by(|p, q| p.1.total_cmp(&q.1))
            .unwrap_or((*a, f64::INFINITY))
    }

    /// Distance from `q` to the nearest wall or obstacle surface (exact solids).
    fn clearance(&self, q: &Point) -> f64 {
        let wall = -self.domain.workspace().signed_distance(q);
        self.domain
            .obstacles()
            .iter()
            .map(|o| o.signed_distance(q))
            .fold(wall, f64::min)
    }

    /// Plans from `starts` and reports as `hplan plan --json` prints.
    pub fn plan_report(&self, starts: &[[f64; 3]]) -> VolumePlanReport {
        let t = Instant::now();
        let paths = self.plan_many(starts);
        let mut timings = self.timings;
        timings.trace = millis(t);
        let q = quality(&self.mesh);
        VolumePlanReport {
            configuration: None,
            mesh: VolumeMeshSummary {
                vertices: q.vertices,
                tetrahedra: q.tetrahedra,
                boundary_faces: q.boundary_faces,
                min_dihedral_deg: q.min_dihedral_deg,
                max_dihedral_deg: q.max_dihedral_deg,
                negative_weight_edges: q.negative_weight_edges,
                clamped_edges: self.clamped_edges,
                spacing: self.report.spacing,
            },
            timings_ms: timings,
            potential: volume_potential_summary(
                &self.potential,
                self.solved_by,
                self.positive_offdiagonals,
            ),
            paths,
        }
    }

    /// The mesh and the potential for outside tools.
    pub fn export(&self) -> VolumeExport {
        VolumeExport::of(&self.mesh, &self.potential)
    }

    /// The mesh with φ, ψ and ∇φ (recovered) as a VTK unstructured grid, for ParaView.
    pub fn vtu(&self) -> Result<String, VolumeError> {
        potential_vtu(&self.mesh, &self.potential)
    }

    /// The three orthographic projections (xy, xz, yz) of the boundary and the paths.
    pub fn svg(&self, paths: &[Vec<[f64; 3]>]) -> String {
        let paths: Vec<Vec<Point>> = paths
            .iter()
            .map(|p| p.iter().map(|q| Point::new(q[0], q[1], q[2])).collect())
            .collect();
        harmonic_volume::io::projections_svg(&self.mesh, &paths)
    }
}

/// `mesh` with `potential`'s φ, ψ and ∇φ (recovered) as a VTK unstructured grid: a volume's,
/// or a configuration space's slab.
pub(crate) fn potential_vtu(
    mesh: &TetMesh,
    potential: &VolumePotential,
) -> Result<String, VolumeError> {
    let phi = potential.phi_at_vertices();
    let grad: Vec<[f64; 3]> = potential
        .recovered_gradients()
        .iter()
        .map(|g| [-g.x, -g.y, -g.z])
        .collect();
    harmonic_volume::io::vtu_string(
        mesh,
        &[
            PointData::Scalar("phi", &phi),
            PointData::Scalar("psi", potential.psi()),
            PointData::Vector("grad_phi", &grad),
        ],
    )
}
