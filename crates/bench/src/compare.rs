//! Comparing planners (issue #9): the FEM harmonic planner against the seed papers' baselines
//! on the same scene, the same starts and the same exact geometry.
//!
//! - [`VisibilityGraph`]: the shortest collision-free path from a start to the goal region,
//!   through the reflex corners of free space (the domain's inflated polygons for a disc
//!   robot), by Dijkstra from the goal. Every planner's path length is divided by it.
//! - [`Arena`]: builds the planners of a scene once ([`PlannerKind`]: FEM with Dirichlet or
//!   Robin walls, Connolly's grid harmonic with SOR, the 8-connected wavefront, Khatib's
//!   attractive/repulsive potential, Kim & Khosla's panels, and the sphere-world navigation
//!   function where the scene is a sphere world), runs them from many starts and measures
//!   every path against the domain: reached or not, trapped (stalled) or not, clearance,
//!   length, time.
//! - [`Row`] and [`markdown_table`]: one aggregate per scene and planner.
//!
//! ```
//! use harmonic_planner::Scene;
//! use harmonic_bench::compare::{Arena, CompareOptions, PlannerKind};
//! let scene = Scene::from_json(r#"{
//!     "workspace": [[0, 0], [4, 0], [4, 4], [0, 4]],
//!     "obstacles": [{"polygon": [[1.5, 1], [2.5, 1], [2.5, 3], [1.5, 3]]}],
//!     "goal": {"circle": {"center": [3.5, 2], "radius": 0.2}},
//!     "mesh": {"max_area": 0.01}
//! }"#)?;
//! let options = CompareOptions { planners: vec![PlannerKind::FemDirichlet], ..Default::default() };
//! let arena = Arena::new(&scene, &options)?;
//! let comparison = arena.run(&[[0.5, 2.0]]);
//! let row = &comparison.rows()[0];
//! assert_eq!(row.success_rate, 1.0);
//! // The harmonic path is longer than the shortest one, which hugs the block's corners.
//! assert!(row.mean_length_ratio.unwrap() > 1.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::cmp::Ordering as CmpOrdering;
use std::collections::BinaryHeap;
use std::fmt::Write as _;
use std::time::Instant;

use harmonic_baselines::{
    BaselineError, Connectivity, Disc, GridHarmonic, NavigationFunction, NavigationOptions,
    PanelOptions, PanelPlanner, PanelVariant, PlanResult, PotentialField, PotentialFieldOptions,
    Raster, SorOptions, Wavefront,
};
use harmonic_mesh::geom::{closest_point_on_segment, polygon_contains, ring_distance};
use harmonic_mesh::{BoundaryTag, Domain, Point, geom::twice_signed_area};
use harmonic_trajectory::{SmoothOptions, TraceStatus, path_metrics, trace_smooth};
use rayon::prelude::*;
use serde::Serialize;

use harmonic_planner::fem::BoundaryCondition;
use harmonic_planner::render::Picture;
use harmonic_planner::scene::Scene;
use harmonic_planner::{PlanError, Planner};

/// Why a comparison could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// The scene cannot be meshed or solved by the FEM planner.
    #[error("scene {scene}: {source}")]
    Plan {
        /// The scene's `name` (`scene` if it has none).
        scene: String,
        /// The planner's error.
        #[source]
        source: PlanError,
    },
    /// The scene's geometry is invalid.
    #[error("scene {scene}: {source}")]
    Mesh {
        /// The scene's `name` (`scene` if it has none).
        scene: String,
        /// The mesher's error.
        #[source]
        source: harmonic_mesh::MeshError,
    },
    /// A baseline planner rejected the scene or its options.
    #[error("scene {scene}, planner {planner}: {source}")]
    Baseline {
        /// The scene's `name` (`scene` if it has none).
        scene: String,
        /// The planner, as [`PlannerKind::name`] names it.
        planner: &'static str,
        /// The baseline's error.
        #[source]
        source: BaselineError,
    },
    /// The scene has no goal region after meshing (nothing to plan toward).
    #[error("scene {scene}: no goal region")]
    NoGoal {
        /// The scene's `name` (`scene` if it has none).
        scene: String,
    },
}

// ---------------------------------------------------------------------------------------------
// Shortest paths
// ---------------------------------------------------------------------------------------------

/// A shortest collision-free path to the goal region.
#[derive(Clone, Debug, PartialEq)]
pub struct ShortestPath {
    /// Its length.
    pub length: f64,
    /// The polyline: the start, the corners it wraps, and the goal point it ends on.
    pub points: Vec<Point>,
}

/// The visibility graph of a domain's free space: its reflex corners (free space bends
/// around them), which of them see each other, and how far each is from the goal region.
///
/// A shortest path in a polygonal domain is a polyline whose inner vertices are reflex
/// corners of free space (where the boundary turns right with free space on its left), and
/// whose last leg ends at the closest point of a goal edge. Corners are moved 1e-7 × the
/// scene's size into free space along their bisector, so a leg that runs along a wall or
/// grazes a corner has a positive clearance; a leg is visible when
/// [`Domain::segment_clearance`] is positive and its midpoint is free. Lengths are exact to
/// about 1e-7 × the scene's size per corner.
///
/// ```
/// use harmonic_bench::compare::VisibilityGraph;
/// use harmonic_planner::mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Point, Shape};
/// let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
///     vec![Point::new(x0, y0), Point::new(x1, y0), Point::new(x1, y1), Point::new(x0, y1)]
/// };
/// let spec = DomainSpec {
///     workspace: rect(0.0, 0.0, 10.0, 10.0),
///     obstacles: vec![Shape::Polygon(rect(4.0, 4.0, 6.0, 6.0))],
///     goals: vec![GoalShape::Polygon(rect(8.0, 4.5, 9.0, 5.5))],
///     robot_radius: 0.0,
/// };
/// let domain = Domain::new(&spec, &MeshOptions::default())?;
/// let graph = VisibilityGraph::new(&domain);
/// // From (2, 5) the block is in the way: over its corner (4, 6) and (6, 6), then down to
/// // the goal's corner (8, 5.5).
/// let path = graph.shortest_path(Point::new(2.0, 5.0)).expect("a path exists");
/// let by_hand = 5f64.sqrt() + 2.0 + 2.0f64.hypot(0.5);
/// assert!((path.length - by_hand).abs() < 1e-5);
/// # Ok::<(), harmonic_planner::mesh::MeshError>(())
/// ```
pub struct VisibilityGraph<'d> {
    domain: &'d Domain,
    /// Reflex corners, moved into free space.
    nodes: Vec<Point>,
    /// Goal edges (free space on their left).
    goal_edges: Vec<(Point, Point)>,
    /// Length of the shortest path from each node to the goal region (infinite if none).
    to_goal: Vec<f64>,
    /// The next node on that path, or `None` when the path goes straight to the goal.
    next: Vec<Option<usize>>,
    /// The goal point the path of each node ends on.
    goal_point: Vec<Point>,
}

/// A Dijkstra heap entry (smallest distance first).
#[derive(PartialEq)]
struct Entry(f64, usize);
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<CmpOrdering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> CmpOrdering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl<'d> VisibilityGraph<'d> {
    /// Builds the graph: the corners, their mutual visibility (in parallel) and, by Dijkstra
    /// from the goal, each corner's distance to it.
    pub fn new(domain: &'d Domain) -> Self {
        let eps = 1e-7 * domain.scale();
        let mut nodes = Vec::new();
        let mut goal_edges = Vec::new();
        for ring in domain.free_rings() {
            let n = ring.points.len();
            let is_goal = |k: usize| matches!(ring.tags[k % n], BoundaryTag::Goal(_));
            for k in 0..n {
                let (prev, v, next) = (
                    ring.points[(k + n - 1) % n],
                    ring.points[k],
                    ring.points[(k + 1) % n],
                );
                if is_goal(k) {
                    goal_edges.push((v, next));
                }
                // Edge k - 1 ends at v, edge k starts there; a corner on a goal edge is a goal
                // point, not a corner to go around.
                if is_goal(k + n - 1) || is_goal(k) || twice_signed_area(prev, v, next) >= 0.0 {
                    continue;
                }
                let left = |d: harmonic_mesh::Vector| {
                    let d = d.normalize();
                    harmonic_mesh::Vector::new(-d.y, d.x)
                };
                let bisector = left(v - prev) + left(next - v);
                if bisector.norm() == 0.0 {
                    continue;
                }
                let p = v + bisector.normalize() * eps;
                if domain.contains_free(p) && domain.distance_to_obstacles(p) > 0.0 {
                    nodes.push(p);
                }
            }
        }
        let visible: Vec<Vec<(usize, f64)>> = (0..nodes.len())
            .into_par_iter()
            .map(|i| {
                (0..nodes.len())
                    .filter(|&j| j != i && Self::sees(domain, nodes[i], nodes[j]))
                    .map(|j| (j, (nodes[i] - nodes[j]).norm()))
                    .collect()
            })
            .collect();
        let legs: Vec<(f64, Point)> = nodes
            .par_iter()
            .map(|&p| Self::goal_leg(domain, &goal_edges, p))
            .collect();
        let mut to_goal: Vec<f64> = legs.iter().map(|l| l.0).collect();
        let mut goal_point: Vec<Point> = legs.iter().map(|l| l.1).collect();
        let mut next = vec![None; nodes.len()];
        let mut done = vec![false; nodes.len()];
        let mut heap: BinaryHeap<Entry> = to_goal
            .iter()
            .enumerate()
            .filter(|(_, d)| d.is_finite())
            .map(|(i, &d)| Entry(d, i))
            .collect();
        while let Some(Entry(d, u)) = heap.pop() {
            if done[u] {
                continue;
            }
            done[u] = true;
            for &(v, w) in &visible[u] {
                if !done[v] && d + w < to_goal[v] {
                    to_goal[v] = d + w;
                    next[v] = Some(u);
                    goal_point[v] = goal_point[u];
                    heap.push(Entry(d + w, v));
                }
            }
        }
        VisibilityGraph {
            domain,
            nodes,
            goal_edges,
            to_goal,
            next,
            goal_point,
        }
    }

    /// Whether the segment `ab` lies in free space.
    fn sees(domain: &Domain, a: Point, b: Point) -> bool {
        domain.segment_clearance(a, b) > 0.0 && domain.contains_free(a + (b - a) * 0.5)
    }

    /// The shortest straight leg from `p` to a goal edge: to the closest point of each goal
    /// edge that `p` sees. Infinite length if it sees none.
    fn goal_leg(domain: &Domain, goal_edges: &[(Point, Point)], p: Point) -> (f64, Point) {
        goal_edges
            .iter()
            .map(|&(a, b)| closest_point_on_segment(p, a, b))
            .filter(|&q| Self::sees(domain, p, q))
            .map(|q| ((q - p).norm(), q))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .unwrap_or((f64::INFINITY, p))
    }

    /// The corners of free space the graph goes around (moved slightly into free space).
    pub fn corners(&self) -> &[Point] {
        &self.nodes
    }

    /// The shortest collision-free path from `start` to the goal region, or `None` if `start`
    /// is not in free space or no path exists (it lies in a component without a goal).
    pub fn shortest_path(&self, start: Point) -> Option<ShortestPath> {
        if !self.domain.contains_free(start) {
            return None;
        }
        let (direct, q) = Self::goal_leg(self.domain, &self.goal_edges, start);
        let via = (0..self.nodes.len())
            .into_par_iter()
            .filter(|&i| self.to_goal[i].is_finite())
            .map(|i| ((self.nodes[i] - start).norm() + self.to_goal[i], i))
            .filter(|&(d, i)| d < direct && Self::sees(self.domain, start, self.nodes[i]))
            .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        match via {
            Some((length, first)) => {
                let mut points = vec![start];
                let mut at = Some(first);
                while let Some(i) = at {
                    points.push(self.nodes[i]);
                    at = self.next[i];
                }
                points.push(self.goal_point[first]);
                Some(ShortestPath { length, points })
            }
            None if direct.is_finite() => Some(ShortestPath {
                length: direct,
                points: vec![start, q],
            }),
            None => None,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The planners
// ---------------------------------------------------------------------------------------------

/// The planners the harness can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PlannerKind {
    /// The FEM harmonic planner with φ = 1 on walls and obstacles.
    FemDirichlet,
    /// The FEM harmonic planner with Robin walls and obstacles, ∂φ/∂n + φ = 1.
    FemRobin,
    /// Connolly's grid harmonic (red–black SOR until every cell's residual is below 1e-6 of
    /// its value, [`SorOptions::default`]) followed by the shared smooth tracer.
    GridSor,
    /// The 8-connected wavefront on the same grid.
    Wavefront,
    /// Khatib's attractive/repulsive potential, descended with a fixed step.
    AttractiveRepulsive,
    /// Our bounded panel method (wall panels close the workspace; `PanelVariant::Bounded`).
    Panel,
    /// Kim & Khosla's panel method as published: unbounded, no wall panels, λ_g = 30 s, V_i
    /// = 0.5 (`PanelVariant::Published` without the per-query remedy, whose stagnation
    /// search costs seconds a query on the cluttered scenes).
    PanelPublished,
    /// Rimon & Koditschek's navigation function (sphere worlds only).
    NavigationFunction,
}

impl PlannerKind {
    /// Every planner, in the order of the tables.
    pub const ALL: [PlannerKind; 8] = [
        PlannerKind::FemDirichlet,
        PlannerKind::FemRobin,
        PlannerKind::GridSor,
        PlannerKind::Wavefront,
        PlannerKind::AttractiveRepulsive,
        PlannerKind::Panel,
        PlannerKind::PanelPublished,
        PlannerKind::NavigationFunction,
    ];

    /// The name in tables and legends.
    pub fn name(self) -> &'static str {
        match self {
            PlannerKind::FemDirichlet => "FEM harmonic, Dirichlet",
            PlannerKind::FemRobin => "FEM harmonic, Robin",
            PlannerKind::GridSor => "grid harmonic (SOR)",
            PlannerKind::Wavefront => "wavefront (8-conn.)",
            PlannerKind::AttractiveRepulsive => "attractive/repulsive",
            PlannerKind::Panel => "panel method (bounded)",
            PlannerKind::PanelPublished => "panel method (published)",
            PlannerKind::NavigationFunction => "navigation function",
        }
    }

    fn colour(self) -> &'static str {
        match self {
            PlannerKind::FemDirichlet => "#d62728",
            PlannerKind::FemRobin => "#ff7f0e",
            PlannerKind::GridSor => "#1f77b4",
            PlannerKind::Wavefront => "#17becf",
            PlannerKind::AttractiveRepulsive => "#9467bd",
            PlannerKind::Panel => "#8c564b",
            PlannerKind::PanelPublished => "#bcbd22",
            PlannerKind::NavigationFunction => "#e377c2",
        }
    }
}

/// How to set up a comparison.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// The planners to run (those that do not apply to a scene are left out with a note).
    pub planners: Vec<PlannerKind>,
    /// Cells per side of the grid planners' raster.
    pub grid_n: usize,
    /// Starts per side of the grid of starts over the workspace's bounding box.
    pub starts_per_side: usize,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            planners: PlannerKind::ALL.to_vec(),
            grid_n: 256,
            starts_per_side: 5,
        }
    }
}

enum Engine {
    Fem(Box<Planner>),
    Grid(Box<GridHarmonic>),
    Wave(Box<Wavefront>),
    Apf(PotentialField),
    Panel(PanelPlanner),
    Nav(NavigationFunction, NavigationOptions),
}

/// A planner built for a scene.
pub struct Contestant {
    kind: PlannerKind,
    build_ms: f64,
    engine: Engine,
}

impl Contestant {
    /// Which planner this is.
    pub fn kind(&self) -> PlannerKind {
        self.kind
    }
    /// Time to build it (mesh, assembly and factorisation; raster and relaxation; ...), ms.
    pub fn build_ms(&self) -> f64 {
        self.build_ms
    }
}

/// One query of one planner, measured against the exact domain. A path that reached the
/// goal but stopped short of the exact goal region (the grid planners stop in the first goal
/// cell) ends with a straight step to the closest goal point, included in its length and
/// clearance.
#[derive(Clone, Debug, Serialize)]
pub struct Run {
    /// The query point `[x, y]`.
    pub start: [f64; 2],
    /// The planner's own status (`reached_goal`, `stalled`, `collision`, ...), or `error`
    /// when the query failed (see `error`).
    pub status: &'static str,
    /// Reached the goal without touching a wall or an obstacle (exact geometry).
    pub success: bool,
    /// Trapped in a local minimum or a stagnation point.
    pub stalled: bool,
    /// Length of `points`, in scene units.
    pub length: f64,
    /// Smallest distance from the path to a wall or an obstacle; 0 if it touches or crosses one.
    pub min_clearance: f64,
    /// Wall-clock time of the query alone (not the measuring), in milliseconds.
    pub query_ms: f64,
    /// Why the query failed, if it did (a singular panel system, ...).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The path from the start, with the closing step to the goal region if one was added
    /// (just the start when the query failed); not serialised.
    #[serde(skip)]
    pub points: Vec<Point>,
}

/// A scene with every planner built, the exact domain and its visibility graph.
pub struct Arena {
    name: String,
    domain: Domain,
    contestants: Vec<Contestant>,
    notes: Vec<String>,
    scene_starts: Vec<[f64; 2]>,
    goal_rings: Vec<Vec<Point>>,
}

/// Every ring (exterior and holes) of a list of domain regions (`harmonic_mesh` does not
/// export its `Region` type by name, so its fields are reached through inference).
macro_rules! rings {
    ($regions:expr) => {
        $regions
            .iter()
            .flat_map(|r| std::iter::once(r.exterior.clone()).chain(r.holes.iter().cloned()))
            .collect::<Vec<Vec<Point>>>()
    };
}

fn millis(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Area centroid of a ring (vertex average for degenerate rings).
fn centroid(ring: &[Point]) -> Point {
    let n = ring.len();
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let (p, q) = (ring[k], ring[(k + 1) % n]);
        let c = p.x * q.y - q.x * p.y;
        a += c;
        cx += (p.x + q.x) * c;
        cy += (p.y + q.y) * c;
    }
    if a.abs() > 0.0 {
        Point::new(cx / (3.0 * a), cy / (3.0 * a))
    } else {
        let s = ring
            .iter()
            .fold(harmonic_mesh::Vector::zeros(), |s, p| s + p.coords);
        Point::from(s / n.max(1) as f64)
    }
}

/// The sphere world of a scene: its workspace a regular polygon standing for a disc (all
/// vertices within 1 % of one distance from their centroid) and every obstacle a circle.
fn sphere_world(scene: &Scene) -> Option<(Disc, Vec<Disc>)> {
    if scene.robot.radius != 0.0 || scene.workspace.len() < 8 {
        return None;
    }
    let ws: Vec<Point> = scene
        .workspace
        .iter()
        .map(|p| Point::new(p[0], p[1]))
        .collect();
    let c = centroid(&ws);
    let radii: Vec<f64> = ws.iter().map(|p| (p - c).norm()).collect();
    let (lo, hi) = radii
        .iter()
        .fold((f64::INFINITY, 0f64), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    if hi - lo > 0.01 * hi {
        return None;
    }
    let obstacles = scene
        .obstacles
        .iter()
        .map(|o| {
            o.circle.map(|c| Disc {
                centre: Point::new(c.center[0], c.center[1]),
                radius: c.radius,
            })
        })
        .collect::<Option<Vec<_>>>()?;
    Some((
        Disc {
            centre: c,
            radius: lo,
        },
        obstacles,
    ))
}

/// What the attractive/repulsive, panel and navigation planners are given: the domain's
/// largest workspace ring and its obstacles as polygons, the first goal's centroid and
/// inradius, and a length scale (a tenth of the domain's size).
struct Shapes {
    goal: Point,
    goal_radius: f64,
    scale: f64,
    workspace: Vec<Point>,
    obstacles: Vec<Vec<Point>>,
}

impl Shapes {
    /// The shapes of `domain` (the scene `name`'s, for the error without a goal).
    fn of(domain: &Domain, name: &str) -> Result<Shapes, CompareError> {
        let goal_ring = domain
            .goal_polygons()
            .first()
            .map(|r| r.exterior.clone())
            .ok_or_else(|| CompareError::NoGoal {
                scene: name.to_string(),
            })?;
        let goal = centroid(&goal_ring);
        let goal_radius = ring_distance(&goal_ring, goal);
        let (lo, hi) = domain.bounding_box();
        let size = (hi.x - lo.x).max(hi.y - lo.y);
        let workspace = domain
            .workspace_rings()
            .iter()
            .max_by(|a, b| {
                let area = |r: &[Point]| harmonic_mesh::geom::signed_area(r);
                area(&a.exterior).total_cmp(&area(&b.exterior))
            })
            .map(|r| r.exterior.clone())
            .unwrap_or_default();
        let obstacles = domain
            .obstacle_polygons()
            .iter()
            .map(|r| r.exterior.clone())
            .collect();
        Ok(Shapes {
            goal,
            goal_radius,
            scale: size / 10.0,
            workspace,
            obstacles,
        })
    }
}

/// The scene with every wall and obstacle under the FEM planner `kind`'s condition
/// (Dirichlet 1, or Robin ∂φ/∂n + φ = 1) and the goal at Dirichlet 0, per-part overrides
/// dropped.
fn fem_variant(scene: &Scene, kind: PlannerKind) -> Scene {
    let mut variant = scene.clone();
    let c = if kind == PlannerKind::FemDirichlet {
        BoundaryCondition::Dirichlet(1.0)
    } else {
        BoundaryCondition::Robin {
            a: 1.0,
            b: 1.0,
            g: 1.0,
        }
    };
    variant.boundary.walls = Some(c);
    variant.boundary.obstacles = Some(c);
    variant.boundary.goal = Some(BoundaryCondition::Dirichlet(0.0));
    for o in &mut variant.obstacles {
        o.boundary = None;
    }
    for g in &mut variant.goal.0 {
        g.boundary = None;
    }
    variant
}

/// Builds the planners of one arena in turn: the grid planners share one raster (built by the
/// first of them and timed with it), planners that do not apply leave a note.
struct Builder<'a> {
    scene: &'a Scene,
    name: &'a str,
    domain: &'a Domain,
    shapes: &'a Shapes,
    options: &'a CompareOptions,
    /// The raster and the milliseconds it took, once built.
    raster: Option<(Raster, f64)>,
    notes: Vec<String>,
}

impl Builder<'_> {
    /// The planner `kind`, timed; `None` (with a note) where it does not apply.
    fn contestant(&mut self, kind: PlannerKind) -> Result<Option<Contestant>, CompareError> {
        let name = self.name;
        let baseline = |source| CompareError::Baseline {
            scene: name.to_string(),
            planner: kind.name(),
            source,
        };
        let Shapes {
            goal,
            goal_radius,
            scale: s,
            ..
        } = *self.shapes;
        let (workspace, obstacles) = (&self.shapes.workspace, &self.shapes.obstacles);
        let t = Instant::now();
        let engine = match kind {
            PlannerKind::FemDirichlet | PlannerKind::FemRobin => {
                let variant = fem_variant(self.scene, kind);
                let planner = Planner::new(&variant).map_err(|source| CompareError::Plan {
                    scene: name.to_string(),
                    source,
                })?;
                Engine::Fem(Box::new(planner))
            }
            PlannerKind::GridSor | PlannerKind::Wavefront => {
                let (r, raster_ms) = match &self.raster {
                    Some(r) => r.clone(),
                    None => {
                        let r = Raster::from_domain(self.domain, self.options.grid_n)
                            .map_err(baseline)?;
                        let made = (r, millis(t));
                        self.raster = Some(made.clone());
                        made
                    }
                };
                let t = Instant::now();
                let engine = if kind == PlannerKind::GridSor {
                    Engine::Grid(Box::new(
                        GridHarmonic::solve(r, &SorOptions::default()).map_err(baseline)?,
                    ))
                } else {
                    Engine::Wave(Box::new(Wavefront::new(r, Connectivity::Eight)))
                };
                return Ok(Some(Contestant {
                    kind,
                    build_ms: raster_ms + millis(t),
                    engine,
                }));
            }
            PlannerKind::AttractiveRepulsive => {
                let opts = PotentialFieldOptions {
                    d_star: 2.0 * s,
                    q_star: s,
                    eta: s.powi(4),
                    goal_tolerance: goal_radius,
                    ..PotentialFieldOptions::default()
                };
                Engine::Apf(
                    PotentialField::new(workspace, obstacles, goal, opts).map_err(baseline)?,
                )
            }
            PlannerKind::Panel => {
                let opts = PanelOptions {
                    max_panel_length: 0.25 * s,
                    step: 0.02 * s,
                    goal_tolerance: goal_radius,
                    ..PanelOptions::default()
                };
                Engine::Panel(
                    PanelPlanner::new(workspace, obstacles, goal, opts).map_err(baseline)?,
                )
            }
            PlannerKind::PanelPublished => {
                // Their setting (50) scaled to the scene: U = 1, V_i = 0.5, λ_g = 30 s (the
                // sink outweighs the stream at the same distance in every scene).
                let opts = PanelOptions {
                    sink_strength: 30.0 * s,
                    max_panel_length: 0.25 * s,
                    step: 0.02 * s,
                    goal_tolerance: goal_radius,
                    variant: PanelVariant::Published {
                        search_samples: 24,
                        remedy: None,
                    },
                    ..PanelOptions::default()
                };
                Engine::Panel(
                    PanelPlanner::new(workspace, obstacles, goal, opts).map_err(baseline)?,
                )
            }
            PlannerKind::NavigationFunction => match sphere_world(self.scene) {
                Some((world, discs)) => {
                    let nav = NavigationFunction::new(world, discs, goal, 6.0).map_err(baseline)?;
                    let opts = NavigationOptions {
                        step: 0.02 * s,
                        goal_tolerance: goal_radius,
                        ..NavigationOptions::default()
                    };
                    Engine::Nav(nav, opts)
                }
                None => {
                    self.notes.push(format!(
                        "{name}: navigation function not run: it needs a sphere world (a \
                         disc workspace with circular obstacles only)"
                    ));
                    return Ok(None);
                }
            },
        };
        Ok(Some(Contestant {
            kind,
            build_ms: millis(t),
            engine,
        }))
    }
}

impl Arena {
    /// Builds the scene's domain and every requested planner, timing each build. The FEM
    /// planners use the scene's mesh options with their boundary conditions replaced; the
    /// grid planners share one raster of the domain; the attractive/repulsive and panel
    /// planners get the domain's (inflated, merged) polygons and the first goal's centroid,
    /// with their lengths and gains scaled to the scene's size and the goal counted as
    /// reached within the goal region's inradius.
    pub fn new(scene: &Scene, options: &CompareOptions) -> Result<Arena, CompareError> {
        let name = scene.name.clone().unwrap_or_else(|| "scene".into());
        let domain =
            Domain::new(&scene.domain_spec(), &scene.mesh_options()).map_err(|source| {
                CompareError::Mesh {
                    scene: name.clone(),
                    source,
                }
            })?;
        let shapes = Shapes::of(&domain, &name)?;
        let mut builder = Builder {
            scene,
            name: &name,
            domain: &domain,
            shapes: &shapes,
            options,
            raster: None,
            notes: Vec::new(),
        };
        let mut contestants = Vec::new();
        for &kind in &options.planners {
            if let Some(contestant) = builder.contestant(kind)? {
                contestants.push(contestant);
            }
        }
        let notes = builder.notes;
        Ok(Arena {
            name,
            contestants,
            notes,
            scene_starts: scene.starts.clone(),
            goal_rings: rings!(domain.goal_polygons()),
            domain,
        })
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The exact free space every path is measured against.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }
    /// The planners built.
    pub fn contestants(&self) -> &[Contestant] {
        &self.contestants
    }
    /// Why some requested planners were left out.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// A `k × k` grid of points over the workspace's bounding box (cell centres) that lie in
    /// free space at least 1 % of the scene's size from walls and obstacles, followed by the
    /// scene's own starts that lie in free space.
    pub fn starts(&self, k: usize) -> Vec<[f64; 2]> {
        let (lo, hi) = self.domain.bounding_box();
        let margin = 0.01 * (hi.x - lo.x).max(hi.y - lo.y);
        let mut starts = Vec::new();
        for j in 0..k {
            for i in 0..k {
                let p = Point::new(
                    lo.x + (hi.x - lo.x) * (i as f64 + 0.5) / k as f64,
                    lo.y + (hi.y - lo.y) * (j as f64 + 0.5) / k as f64,
                );
                if self.domain.contains_free(p) && self.domain.distance_to_obstacles(p) > margin {
                    starts.push([p.x, p.y]);
                }
            }
        }
        starts.extend(
            self.scene_starts
                .iter()
                .filter(|s| self.domain.contains_free(Point::new(s[0], s[1]))),
        );
        starts
    }

    /// Whether `q` lies in a goal region or within 1e-9 × the scene's size of its boundary
    /// (paths end there, off free space).
    fn in_goal(&self, q: Point) -> bool {
        self.goal_rings
            .iter()
            .filter(|r| polygon_contains(r, q))
            .count()
            % 2
            == 1
            || self
                .goal_rings
                .iter()
                .any(|r| ring_distance(r, q) <= 1e-9 * self.domain.scale())
    }

    /// Ends a path that stopped short of the exact goal region (the grid planners stop in
    /// the first goal cell, up to a cell's diagonal away) with a straight step to the closest
    /// goal point, so that every length is measured to the same region.
    fn complete_to_goal(&self, points: &mut Vec<Point>) {
        let Some(&last) = points.last() else {
            return;
        };
        if self.in_goal(last) {
            return;
        }
        let closest = self
            .goal_rings
            .iter()
            .flat_map(|r| {
                (0..r.len())
                    .map(move |k| closest_point_on_segment(last, r[k], r[(k + 1) % r.len()]))
            })
            .min_by(|a, b| (a - last).norm().total_cmp(&(b - last).norm()));
        if let Some(q) = closest {
            points.push(q);
        }
    }

    /// Plans from `start` with contestant `c` and measures the path against the domain.
    pub fn plan(&self, c: &Contestant, start: [f64; 2]) -> Run {
        let p = Point::new(start[0], start[1]);
        let t = Instant::now();
        let failed = |e: String| (vec![p], "error", false, Some(e));
        let (points, status, stalled, error) = match &c.engine {
            Engine::Fem(planner) => {
                let path = planner.plan(start);
                let pts = path.points.iter().map(|q| Point::new(q[0], q[1])).collect();
                (
                    pts,
                    path.status.as_str(),
                    matches!(path.status, TraceStatus::Stalled { .. }),
                    None,
                )
            }
            Engine::Grid(field) => {
                let (lo, hi) = self.domain.bounding_box();
                let opts = SmoothOptions::for_scale((hi.x - lo.x).max(hi.y - lo.y));
                match trace_smooth(field.as_ref(), p, &opts) {
                    Ok(path) => result_parts(&PlanResult::from_path(path, t.elapsed())),
                    Err(e) => failed(e.to_string()),
                }
            }
            Engine::Wave(w) => result_parts(&w.plan(p)),
            Engine::Apf(f) => result_parts(&f.plan(p)),
            Engine::Panel(planner) => match planner.plan(p) {
                Ok(r) => result_parts(&r),
                Err(e) => failed(e.to_string()),
            },
            Engine::Nav(nav, opts) => match nav.plan(p, opts) {
                Ok(r) => result_parts(&r),
                Err(e) => failed(e.to_string()),
            },
        };
        let query_ms = millis(t);
        let mut points = points;
        if status == "reached_goal" {
            self.complete_to_goal(&mut points);
        }
        let metrics = path_metrics(&points, |a, b| self.domain.segment_clearance(a, b));
        let inside = points
            .iter()
            .all(|&q| self.domain.contains_free(q) || self.in_goal(q));
        let min_clearance = if inside && metrics.min_clearance.is_finite() {
            metrics.min_clearance
        } else {
            0.0
        };
        Run {
            start,
            status,
            success: status == "reached_goal" && min_clearance > 0.0,
            stalled,
            length: metrics.length,
            min_clearance,
            query_ms,
            error,
            points,
        }
    }

    /// Runs every planner from every start (in parallel over starts) and finds the shortest
    /// path from each start. Starts from which no collision-free path reaches the goal are
    /// left out.
    pub fn run(&self, starts: &[[f64; 2]]) -> Comparison {
        let graph = VisibilityGraph::new(&self.domain);
        let (starts, shortest): (Vec<[f64; 2]>, Vec<ShortestPath>) = starts
            .iter()
            .filter_map(|&s| {
                graph
                    .shortest_path(Point::new(s[0], s[1]))
                    .map(|path| (s, path))
            })
            .unzip();
        let results: Vec<PlannerRuns> = self
            .contestants
            .iter()
            .map(|c| PlannerRuns {
                kind: c.kind,
                build_ms: c.build_ms,
                runs: starts.par_iter().map(|&s| self.plan(c, s)).collect(),
            })
            .collect();
        let mut notes = self.notes.clone();
        for r in &results {
            let mut errors: Vec<&str> = r.runs.iter().filter_map(|x| x.error.as_deref()).collect();
            let count = errors.len();
            errors.sort_unstable();
            errors.dedup();
            if !errors.is_empty() {
                notes.push(format!(
                    "{}: {} failed from {count} of {} starts: {}",
                    self.name,
                    r.kind.name(),
                    r.runs.len(),
                    errors.join("; ")
                ));
            }
        }
        Comparison {
            scene: self.name.clone(),
            starts,
            shortest,
            results,
            notes,
            rings: [
                rings!(self.domain.workspace_rings()),
                rings!(self.domain.obstacle_polygons()),
                rings!(self.domain.goal_polygons()),
            ],
        }
    }
}

/// Points, status, whether stalled, and no error.
type Parts = (Vec<Point>, &'static str, bool, Option<String>);

fn result_parts(r: &PlanResult) -> Parts {
    (
        r.points.clone(),
        r.status.as_str(),
        matches!(r.status, TraceStatus::Stalled { .. }),
        None,
    )
}

// ---------------------------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------------------------

/// Every run of one planner on one scene.
#[derive(Clone, Debug)]
pub struct PlannerRuns {
    /// The planner.
    pub kind: PlannerKind,
    /// Time to build it for the scene, in milliseconds (as [`Contestant::build_ms`]).
    pub build_ms: f64,
    /// One per start, in the order of [`Comparison::starts`].
    pub runs: Vec<Run>,
}

/// The outcome of [`Arena::run`].
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The scene's `name` (`scene` if it has none).
    pub scene: String,
    /// The starts from which a collision-free path to the goal exists.
    pub starts: Vec<[f64; 2]>,
    /// The shortest path from each start.
    pub shortest: Vec<ShortestPath>,
    /// One entry per planner.
    pub results: Vec<PlannerRuns>,
    /// Planners left out or failing, and why.
    pub notes: Vec<String>,
    rings: [Vec<Vec<Point>>; 3],
}

/// One line of the comparison table.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// The scene's `name` (`scene` if it has none).
    pub scene: String,
    /// The planner, as [`PlannerKind::name`] names it.
    pub planner: &'static str,
    /// Number of starts.
    pub starts: usize,
    /// Fraction of starts from which the planner reached the goal without touching a wall or
    /// an obstacle.
    pub success_rate: f64,
    /// Starts from which it got trapped (local minimum or stagnation point).
    pub stalled: usize,
    /// Paths that touch or cross a wall or an obstacle (exact geometry), whether or not the
    /// planner noticed.
    pub collided: usize,
    /// Mean over the successful starts of path length / shortest path length (`null` if none).
    pub mean_length_ratio: Option<f64>,
    /// Smallest clearance over the successful paths (`null` if none).
    pub min_clearance: Option<f64>,
    /// Build time plus the mean time per query: the cost of one plan from scratch.
    pub millis: f64,
    /// Build time (mesh + assembly + factorisation, raster + relaxation, ...).
    pub build_ms: f64,
    /// Mean time per query.
    pub query_ms: f64,
}

impl Comparison {
    /// One row per planner.
    pub fn rows(&self) -> Vec<Row> {
        self.results
            .iter()
            .map(|r| {
                let n = r.runs.len();
                let ok: Vec<(usize, &Run)> = r
                    .runs
                    .iter()
                    .enumerate()
                    .filter(|(_, x)| x.success)
                    .collect();
                let ratio = (!ok.is_empty()).then(|| {
                    ok.iter()
                        .map(|(i, x)| x.length / self.shortest[*i].length)
                        .sum::<f64>()
                        / ok.len() as f64
                });
                let clearance = ok.iter().map(|(_, x)| x.min_clearance).reduce(f64::min);
                let query_ms = if n == 0 {
                    0.0
                } else {
                    r.runs.iter().map(|x| x.query_ms).sum::<f64>() / n as f64
                };
                Row {
                    scene: self.scene.clone(),
                    planner: r.kind.name(),
                    starts: n,
                    success_rate: if n == 0 {
                        0.0
                    } else {
                        ok.len() as f64 / n as f64
                    },
                    stalled: r.runs.iter().filter(|x| x.stalled).count(),
                    collided: r.runs.iter().filter(|x| x.min_clearance <= 0.0).count(),
                    mean_length_ratio: ratio,
                    min_clearance: clearance,
                    millis: r.build_ms + query_ms,
                    build_ms: r.build_ms,
                    query_ms,
                }
            })
            .collect()
    }

    /// An SVG of the scene with every planner's paths (one colour per planner, a legend) and
    /// the shortest paths in black.
    pub fn svg(&self, width_px: f64) -> String {
        let mut paths: Vec<(Vec<Point>, &'static str)> = self
            .shortest
            .iter()
            .map(|s| (s.points.clone(), "#000000"))
            .collect();
        for r in &self.results {
            paths.extend(r.runs.iter().map(|x| (x.points.clone(), r.kind.colour())));
        }
        let [workspace, obstacles, goals] = self.rings.clone();
        let picture = Picture {
            workspace,
            obstacles,
            goals,
            paths,
            title: Some(format!("{}: {} starts", self.scene, self.starts.len())),
            ..Default::default()
        };
        let svg = picture.to_svg(width_px);
        let mut legend = format!(
            r##"<rect x="4" y="26" width="200" height="{:.0}" fill="#ffffff" fill-opacity="0.85"/>"##,
            18.0 * (self.results.len() + 1) as f64 + 6.0
        );
        let entries = std::iter::once(("shortest path", "#000000")).chain(
            self.results
                .iter()
                .map(|r| (r.kind.name(), r.kind.colour())),
        );
        for (i, (name, colour)) in entries.enumerate() {
            let y = 38.0 + 18.0 * i as f64;
            let _ = writeln!(
                legend,
                r##"<rect x="8" y="{:.0}" width="14" height="4" fill="{colour}"/><text x="28" y="{:.0}" font-family="sans-serif" font-size="13" fill="#222">{name}</text>"##,
                y - 4.0,
                y + 1.0
            );
        }
        match svg.rfind("</svg>") {
            Some(end) => format!("{}{legend}{}", &svg[..end], &svg[end..]),
            None => svg,
        }
    }
}

/// The rows as a Markdown table.
pub fn markdown_table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| scene | planner | starts | success | stalled | collided | length / shortest | min clearance | build ms | query ms |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let opt = |v: Option<f64>, digits: usize| match v {
        Some(v) => format!("{v:.digits$}"),
        None => "–".into(),
    };
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.0} % | {} | {} | {} | {} | {:.1} | {:.2} |",
            r.scene,
            r.planner,
            r.starts,
            100.0 * r.success_rate,
            r.stalled,
            r.collided,
            opt(r.mean_length_ratio, 3),
            opt(r.min_clearance, 3),
            r.build_ms,
            r.query_ms
        );
    }
    s
}
