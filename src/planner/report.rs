//! What a planner answers with: paths and reports as the JSON contract prints them, their
//! text summaries, the export, VTU and SVG.

use super::*;

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

/// One planned path, as the `hplan plan --json` contract prints it: in the plane
/// (`PlannedPath`) or through a volume (`PlannedPath<Point3>`).
#[derive(Clone, Debug, Serialize)]
#[serde(bound = "")]
pub struct PlannedPath<P: PathPoint = Point> {
    /// The query point (`[x, y]`, `[x, y, z]`), as given.
    pub start: P::Array,
    /// How the path ended, serialised as `reached_goal`, `unreachable`, `stalled`,
    /// `start_in_obstacle`, `outside_workspace`, `max_steps` or `collision`.
    pub status: TraceStatus<P>,
    /// The goal reached, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goal: Option<u32>,
    /// For a start in an obstacle or outside the workspace, where the planner says which
    /// (`"obstacle 2"`, `"the workspace"`; volumes), with the robot's radius counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blocked_by: Option<String>,
    /// Which tracer made the path: `smooth` (the default) or `exact` (the fallback).
    pub tracer: Tracer,
    /// Length of the polyline `points`, in scene units.
    pub length: f64,
    /// Smallest distance from the path to a wall or an obstacle (exact geometry; in a volume,
    /// from the path's vertices, the robot's radius not subtracted).
    pub min_clearance: f64,
    /// Smallest |∇φ| met along the path (0 if none was met).
    pub min_gradient: f64,
    /// The path's vertices from the start; on reaching the goal the last lies on its
    /// boundary (or on a point goal).
    pub points: Vec<P::Array>,
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

/// Potential figures of a report: the same figures for the plane, volumes and configuration
/// spaces (`interior_local_extrema` and `positive_offdiagonals` where the mesh is stuffed).
#[derive(Clone, Debug, Serialize)]
pub struct PotentialSummary {
    /// Smallest φ at a vertex (the goal's value for the default conditions).
    pub min: f64,
    /// Largest φ at a vertex (the walls' value for the default conditions).
    pub max: f64,
    /// Interior vertices that are strict local minima of φ (0 for a harmonic potential on a
    /// Delaunay mesh; a path would stop there).
    pub interior_local_minima: usize,
    /// Volumes and configuration spaces: interior vertices where φ is a strict local minimum
    /// or maximum.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interior_local_extrema: Option<usize>,
    /// The smallest positive ψ = φ_wall − φ at a vertex: how flat the field gets (the
    /// smallest positive float: past the double range see `min_log10_psi`).
    pub min_psi: f64,
    /// log₁₀ of the smallest non-zero ψ, given only when ψ goes past the double range (the
    /// potential is kept with exponents, a corridor of hundreds of widths).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_log10_psi: Option<f64>,
    /// Volumes and configuration spaces: positive off-diagonals of the assembled (unclamped)
    /// matrix, the obtuse dihedral angles' mark.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positive_offdiagonals: Option<usize>,
    /// What produced ψ. The plane: `cholesky`, `cholesky (flat, checked: no interior
    /// extremum)`, `accurate`, `accurate (extended exponent)`, `multigrid`, `blend` or `goal
    /// superposition` (a workspace's goals); volumes and configuration spaces: `accurate`,
    /// `cholesky` or `pcg`, followed by ` (clamped M-matrix)` where the obtuse tetrahedra's
    /// weights were clamped.
    pub solved_by: &'static str,
}

impl PotentialSummary {
    /// The smallest positive entry of `psi` (0 if none).
    pub(crate) fn smallest_positive(psi: &[f64]) -> f64 {
        finite_or_zero(
            psi.iter()
                .copied()
                .filter(|&v| v > 0.0)
                .fold(f64::INFINITY, f64::min),
        )
    }
}

impl std::fmt::Display for PotentialSummary {
    /// `potential: φ in [min, max], smallest ψ …, interior local minima …` (and extrema).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "potential: φ in [{:.6}, {:.6}], smallest ψ = φ_wall − φ {:.2e}, interior local minima {}",
            self.min, self.max, self.min_psi, self.interior_local_minima
        )?;
        if let Some(e) = self.interior_local_extrema {
            write!(f, ", interior local extrema {e}")?;
        }
        Ok(())
    }
}

/// What `hplan plan --json` and `hplan car --json` print, for the plane, a volume or a
/// configuration space: the mesh (`M`: [`MeshSummary`], [`crate::volume::VolumeMeshSummary`],
/// [`crate::cspace::ConfigMeshSummary`]), the stage timings, the potential's figures and one
/// entry per path (`P`).
#[derive(Clone, Debug, Serialize)]
pub struct Report<P, M = MeshSummary> {
    /// Configuration spaces only: `"pose"` (a rigid robot) or `"joints"` (an arm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub configuration: Option<&'static str>,
    /// The mesh's figures.
    pub mesh: M,
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

/// The line a text summary gives a path, a car run or a motion.
pub trait PathSummary {
    /// Start, status (and what blocks it), length, clearance, and the figure that matters.
    fn line(&self) -> String;
}

/// `(x, y): status, length …, clearance …, smallest |∇φ| …`, the common line.
fn path_line(
    start: &[f64],
    status: &str,
    blocked_by: Option<&str>,
    (length, clearance, gradient): (f64, f64, f64),
) -> String {
    let start: Vec<String> = start.iter().map(|v| format!("{v}")).collect();
    let blocked = blocked_by
        .map(|b| format!(" ({b}, robot radius counted)"))
        .unwrap_or_default();
    format!(
        "({}): {status}{blocked}, length {length:.3}, clearance {clearance:.3}, smallest |∇φ| {gradient:.2e}",
        start.join(", "),
        length = length + 0.0, // no "-0.000"
    )
}

impl<P: PathPoint> PathSummary for PlannedPath<P> {
    fn line(&self) -> String {
        path_line(
            self.start.as_ref(),
            self.status.as_str(),
            self.blocked_by.as_deref(),
            (self.length, self.min_clearance, self.min_gradient),
        )
    }
}

impl PathSummary for CarRun {
    fn line(&self) -> String {
        path_line(
            &self.start,
            self.status.as_str(),
            None,
            (self.length, self.min_clearance, self.min_gradient),
        )
    }
}

impl std::fmt::Display for MeshSummary {
    /// `mesh: … vertices, … triangles, min angle …°`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "mesh: {} vertices, {} triangles, min angle {:.1}°",
            self.vertices, self.triangles, self.min_angle_deg
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

impl Planner {
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
                vertices: self.mesh.vertices().len(),
                triangles: self.mesh.triangles().len(),
                min_angle_deg: self.mesh.min_angle_deg(),
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
                interior_local_extrema: None,
                min_psi: finite_or_zero(min_psi),
                min_log10_psi: min_log10_psi.filter(|v| v.is_finite()),
                positive_offdiagonals: None,
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
            configuration: None,
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
            configuration: None,
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

impl<P: PathSummary, M: std::fmt::Display> Report<P, M> {
    /// A human-readable summary: the mesh, the timings, the potential, one line per path.
    pub fn summary(&self) -> String {
        use std::fmt::Write as _;
        let mut s = format!("{}\n{}\n{}\n", self.mesh, self.timings_ms, self.potential);
        for path in &self.paths {
            let _ = writeln!(s, "{}", path.line());
        }
        s
    }
}
