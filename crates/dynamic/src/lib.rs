//! Dynamic replanning (Garrido et al. 2010, §6): a local map around the robot, rebuilt and
//! solved at every step from the known map and what the laser sees.
//!
//! The pieces, in the order of the paper's Figure 10 loop:
//! - [`LaserScan`] / [`scan_obstacles`]: a scan (points in the robot frame plus the robot's pose)
//!   becomes obstacles: points explained by the known map are dropped, the rest are clustered by
//!   distance, and each cluster becomes its convex hull grown by a margin (the hull of
//!   octagons circumscribing discs around the points, so the growth is conservative).
//! - [`DynamicPlanner`]: the known map's global potential (built once), obstacles that can be
//!   added, moved and removed, and [`DynamicPlanner::replan`], which meshes a square window
//!   around the robot with the known and sensed obstacles in it, puts the goal on the global
//!   path where it leaves the window (or uses the real goal when it lies inside), solves and
//!   traces the local potential.
//! - [`World`] and [`run`]: a simulated world with moving and unmapped obstacles, a simulated
//!   laser ([`World::scan`]) and the loop itself — sense, solve, trace, move a step sized by
//!   the distance to the nearest moving obstacle, repeat — with the distance to the true
//!   obstacles checked at every step.
//!
//! The local map is a fixed background lattice of right triangles with the obstacles cut in
//! by blocking vertices ([`LocalMapMode::Lattice`]): a replan builds, factors and solves only
//! its own unknowns, numbered by an elimination order kept from earlier windows — about 0.3 ms
//! for the paper's 3200-triangle map. Where the lattice's safety margin
//! (up to `h/√2` beyond the robot's radius) traps the robot or seals its way, the window is
//! remeshed exactly instead ([`LocalMapMode::Remesh`] always does). What else stays valid
//! between replans is reused: the known map's domain, global potential and blocked lattice
//! vertices, the global path (traced again only when the robot has left it) and the local
//! waypoint (kept while it stays valid).
//!
//! ```
//! use harmonic_dynamic::{DynamicPlanner, LocalMapOptions};
//! use harmonic_planner::Scene;
//! let scene = Scene::from_json(r#"{
//!     "workspace": [[0, 0], [8, 0], [8, 3], [0, 3]],
//!     "goal": {"circle": {"center": [7.5, 1.5], "radius": 0.15}},
//!     "mesh": {"max_area": 0.02}
//! }"#)?;
//! let opts = LocalMapOptions { size: 2.0, max_area: 0.01, ..LocalMapOptions::default() };
//! let mut planner = DynamicPlanner::new(&scene, opts)?;
//! // An obstacle seen on the way: the local path goes around it.
//! planner.set_obstacle(7, vec![[1.4, 1.2], [1.7, 1.2], [1.7, 1.8], [1.4, 1.8]]);
//! let plan = planner.replan([0.5, 1.5])?;
//! assert!(plan.path.status.reached_goal());
//! assert!(plan.local_goal[0] > 1.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::collections::BTreeMap;
use std::time::Instant;

use geo::{Area, BooleanOps, ConvexHull, Coord, LineString, MultiPoint, Polygon};
use harmonic_mesh::{Point, geom};
use serde::Serialize;

use harmonic_planner::scene::{Circle, Goals, MeshSpec, Region, Scene};
use harmonic_planner::{PlanError, PlannedPath, Planner};
use harmonic_trajectory::{TraceStatus, path_metrics};
use lattice::{Lattice, LatticeGoal, LatticeMiss};

mod lattice;

/// Why a local plan could not be made.
#[derive(Debug, thiserror::Error)]
pub enum DynamicError {
    /// Building the global or the local planner failed.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The robot is outside the known map's workspace.
    #[error("robot at ({x}, {y}) is outside the workspace")]
    OutsideWorkspace {
        /// Robot position.
        x: f64,
        /// Robot position.
        y: f64,
    },
    /// The global potential gives no path from the robot's position (it is in an obstacle of
    /// the known map or cut off from the goal).
    #[error("no global path from ({x}, {y}): {status}")]
    NoGlobalPath {
        /// Robot position.
        x: f64,
        /// Robot position.
        y: f64,
        /// The global tracer's status.
        status: TraceStatus,
    },
    /// Every candidate local goal on the global path is blocked by a sensed obstacle.
    #[error("no free local goal on the global path from ({x}, {y})")]
    NoLocalGoal {
        /// Robot position.
        x: f64,
        /// Robot position.
        y: f64,
    },
    /// An option is out of range.
    #[error("invalid option {name} = {value}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
}

/// The local map: a square window around the robot.
#[derive(Clone, Copy, Debug)]
pub struct LocalMapOptions {
    /// Side of the window (default 4 m, the paper's 40 × 40 cells of 10 cm).
    pub size: f64,
    /// Largest triangle area (default 0.005, about 3200 triangles on an empty 4 m window).
    pub max_area: f64,
    /// Smallest angle the mesher aims for, degrees (default 25).
    pub min_angle_deg: f64,
    /// Radius of the local goal put on the global path (default 0.1).
    pub goal_radius: f64,
    /// The global path is traced again when the robot is farther than this from it
    /// (default 0.1).
    pub global_path_tolerance: f64,
    /// How the window is meshed (default [`LocalMapMode::Lattice`]).
    pub mode: LocalMapMode,
}

/// How the local map is meshed at each replan.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LocalMapMode {
    /// A fixed background lattice of right triangles (cells of side `√(2 max_area)`, so
    /// `max_area` is every triangle's area) with the obstacles cut in by blocking vertices,
    /// and a fill-reducing elimination order kept from one replan to the next. About ten
    /// times faster than remeshing (`cargo bench --bench replan`), at the price of a
    /// margin of up to `h/√2` around obstacles; where that margin traps the robot, seals its
    /// way or leaves no lattice vertex in the goal, the replan remeshes instead.
    #[default]
    Lattice,
    /// A constrained Delaunay mesh of the window, obstacles exact, built at every replan.
    Remesh,
}

impl Default for LocalMapOptions {
    fn default() -> Self {
        LocalMapOptions {
            size: 4.0,
            max_area: 0.005,
            min_angle_deg: 25.0,
            goal_radius: 0.1,
            global_path_tolerance: 0.1,
            mode: LocalMapMode::Lattice,
        }
    }
}

/// Largest lattice window side, in cells.
const MAX_LATTICE_CELLS: usize = 1000;

impl LocalMapOptions {
    /// The lattice window's side in cells: an even number (so the robot's nearest lattice
    /// vertex is the centre), of triangles no larger than `max_area`.
    fn lattice_cells(&self) -> usize {
        let half = (self.size / (2.0 * self.max_area).sqrt() * 0.5).ceil();
        // Saturates for absurd ratios; `validate` refuses those.
        (half.min(usize::MAX as f64 / 4.0) as usize).max(4) * 2
    }

    fn validate(&self) -> Result<(), DynamicError> {
        let positive = |name: &'static str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(DynamicError::InvalidOption {
                    name,
                    value,
                    reason: "must be a positive finite number",
                })
            }
        };
        positive("size", self.size)?;
        positive("max_area", self.max_area)?;
        positive("goal_radius", self.goal_radius)?;
        positive("global_path_tolerance", self.global_path_tolerance)?;
        if !(self.min_angle_deg > 0.0 && self.min_angle_deg <= 33.0) {
            return Err(DynamicError::InvalidOption {
                name: "min_angle_deg",
                value: self.min_angle_deg,
                reason: "must be in (0, 33]",
            });
        }
        if self.mode == LocalMapMode::Lattice && self.lattice_cells() > MAX_LATTICE_CELLS {
            return Err(DynamicError::InvalidOption {
                name: "max_area",
                value: self.max_area,
                reason: "the lattice window would have more than 1000 × 1000 cells",
            });
        }
        if self.goal_radius * 8.0 > self.size {
            return Err(DynamicError::InvalidOption {
                name: "goal_radius",
                value: self.goal_radius,
                reason: "must be at most an eighth of the window size",
            });
        }
        Ok(())
    }
}

/// Wall-clock time of the stages of one replan, in milliseconds.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct ReplanTimings {
    /// Building the local scene: clipping, the global path and the local goal.
    pub prepare: f64,
    /// Domain and constrained Delaunay mesh of the window.
    pub mesh: f64,
    /// Assembly of the P1 system.
    pub assemble: f64,
    /// Ordering, factorisation and solve.
    pub solve: f64,
    /// Tracing the local path.
    pub trace: f64,
    /// Everything.
    pub total: f64,
}

/// The result of one replan.
pub struct LocalPlan {
    /// The path in the local potential from the robot towards the local goal.
    pub path: PlannedPath,
    /// Centre of the local goal (the real goal's first vertex or centre when it is inside
    /// the window).
    pub local_goal: [f64; 2],
    /// Whether the local goal is the scene's own goal.
    pub goal_in_window: bool,
    /// How the window was meshed.
    pub method: LocalMapMode,
    /// Why the lattice could not serve a remeshed replan in [`LocalMapMode::Lattice`]:
    /// `robot_blocked` (the robot is within the lattice's margin of an obstacle),
    /// `no_goal_vertex` (no free lattice vertex in the goal), `not_reached` (the margin seals
    /// the way) or `solve`.
    pub remesh_reason: Option<&'static str>,
    /// The local scene that was meshed (remeshed windows only).
    pub scene: Option<Scene>,
    /// Triangles of the local mesh.
    pub triangles: usize,
    /// The local potential and its mesh, to look at (`None` when the robot started in the
    /// goal).
    pub potential: Option<harmonic_fem::Potential>,
    /// Time per stage.
    pub timings: ReplanTimings,
}

/// A planner for a changing world: the known map's global potential, obstacles that come and
/// go, and a local potential on a window around the robot, recomputed at every replan.
pub struct DynamicPlanner {
    scene: Scene,
    global: Planner,
    workspace: Polygon<f64>,
    options: LocalMapOptions,
    obstacles: BTreeMap<u32, Vec<[f64; 2]>>,
    global_path: Vec<[f64; 2]>,
    /// The last local goal on the global path, kept while it stays valid.
    waypoint: Option<[f64; 2]>,
    lattice: Option<Lattice>,
}

/// The goal of a window.
enum LocalGoal {
    /// The scene's own goal; `centre` is its first vertex or centre.
    Real { centre: [f64; 2] },
    /// A waypoint: a disc of [`LocalMapOptions::goal_radius`] around it.
    Waypoint([f64; 2]),
}

/// Largest number of lattice vertices over the known map whose blocking is computed when the
/// planner is built, about a second (beyond it, tiles are computed as the robot reaches them).
const LATTICE_WARM_VERTICES: usize = 1_000_000;

fn geo_polygon(points: &[[f64; 2]]) -> Polygon<f64> {
    Polygon::new(
        LineString::from(points.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()),
        vec![],
    )
}

fn region_polygon(region: &Region, segments: usize) -> Option<Vec<[f64; 2]>> {
    match (&region.polygon, &region.circle, &region.point) {
        (Some(p), _, _) => Some(p.clone()),
        (None, Some(c), _) => Some(circle_points(c.center, c.radius, segments)),
        _ => None,
    }
}

fn circle_points(center: [f64; 2], radius: f64, segments: usize) -> Vec<[f64; 2]> {
    (0..segments)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / segments as f64;
            [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
        })
        .collect()
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The point of segment `ab` closest to `p`, as the scene format's array.
fn projection(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let q = geom::closest_point_on_segment(p, a, b);
    [q.x, q.y]
}

/// A laser scan: hit points in the robot frame (x forward, y left) and the robot's pose
/// `[x, y, θ]` in the world when it was taken.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LaserScan {
    /// Robot pose `[x, y, heading]`.
    pub pose: [f64; 3],
    /// Hit points in the robot frame.
    pub points: Vec<[f64; 2]>,
}

impl LaserScan {
    /// The hit points in world coordinates.
    pub fn world_points(&self) -> Vec<[f64; 2]> {
        let [x, y, th] = self.pose;
        let (s, c) = th.sin_cos();
        self.points
            .iter()
            .map(|p| [x + c * p[0] - s * p[1], y + s * p[0] + c * p[1]])
            .collect()
    }
}

/// How scan points become obstacles.
#[derive(Clone, Copy, Debug)]
pub struct ScanOptions {
    /// Points closer than this are in the same cluster (default 0.3).
    pub cluster_gap: f64,
    /// Growth of each cluster's hull (default 0.1); less where the robot is closer than twice
    /// this, so the robot never ends up inside what it sensed.
    pub inflate: f64,
    /// Points within this distance of the known map's walls and obstacles are explained by
    /// the map and dropped (default 0.05).
    pub map_tolerance: f64,
}

impl Default for ScanOptions {
    fn default() -> Self {
        ScanOptions {
            cluster_gap: 0.3,
            inflate: 0.1,
            map_tolerance: 0.05,
        }
    }
}

/// Splits points into clusters: two points closer than `gap` are in the same cluster
/// (single linkage, on a grid of cells of side `gap`).
///
/// ```
/// use harmonic_dynamic::cluster_points;
/// let pts = [[0.0, 0.0], [0.1, 0.0], [2.0, 2.0], [0.2, 0.05]];
/// let clusters = cluster_points(&pts, 0.15);
/// assert_eq!(clusters.len(), 2);
/// assert_eq!(clusters[0].len(), 3);
/// ```
pub fn cluster_points(points: &[[f64; 2]], gap: f64) -> Vec<Vec<[f64; 2]>> {
    let points: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    if points.is_empty() || !(gap.is_finite() && gap > 0.0) {
        return points.into_iter().map(|p| vec![p]).collect();
    }
    let cell = |p: [f64; 2]| ((p[0] / gap).floor() as i64, (p[1] / gap).floor() as i64);
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    for (i, &p) in points.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i);
    }
    // Union-find over neighbouring cells.
    let mut parent: Vec<usize> = (0..points.len()).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for (i, &p) in points.iter().enumerate() {
        let (cx, cy) = cell(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(others) = grid.get(&(cx + dx, cy + dy)) {
                    for &j in others {
                        if j > i && dist(p, points[j]) < gap {
                            let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                            parent[ri.max(rj)] = ri.min(rj);
                        }
                    }
                }
            }
        }
    }
    let mut clusters: BTreeMap<usize, Vec<[f64; 2]>> = BTreeMap::new();
    for (i, &p) in points.iter().enumerate() {
        let r = find(&mut parent, i);
        clusters.entry(r).or_default().push(p);
    }
    clusters.into_values().collect()
}

/// The convex hull of discs of radius `margin` around `points`, as a counter-clockwise polygon
/// (each disc is replaced by the octagon circumscribing it, so the result contains every disc).
pub fn inflated_hull(points: &[[f64; 2]], margin: f64) -> Vec<[f64; 2]> {
    let r = margin / (std::f64::consts::PI / 8.0).cos();
    let mut octagons = Vec::with_capacity(points.len() * 8);
    for p in points {
        for k in 0..8 {
            let a = std::f64::consts::TAU * (k as f64 + 0.5) / 8.0;
            octagons.push(Coord {
                x: p[0] + r * a.cos(),
                y: p[1] + r * a.sin(),
            });
        }
    }
    let hull = MultiPoint::from(octagons).convex_hull();
    let ring = hull.exterior();
    let mut out: Vec<[f64; 2]> = ring.coords().map(|c| [c.x, c.y]).collect();
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

/// Turns a scan into obstacles in world coordinates: points within
/// [`ScanOptions::map_tolerance`] of the known map (`known_distance`, the distance to its walls
/// and obstacles) are dropped, the others clustered and each cluster replaced by its inflated
/// convex hull. The growth of a cluster is capped at half its distance to the robot.
pub fn scan_obstacles(
    scan: &LaserScan,
    known_distance: impl Fn([f64; 2]) -> f64,
    opts: &ScanOptions,
) -> Vec<Vec<[f64; 2]>> {
    let robot = [scan.pose[0], scan.pose[1]];
    let unexplained: Vec<[f64; 2]> = scan
        .world_points()
        .into_iter()
        .filter(|&p| known_distance(p) > opts.map_tolerance)
        .collect();
    cluster_points(&unexplained, opts.cluster_gap)
        .into_iter()
        .filter_map(|cluster| {
            let bare = inflated_hull(&cluster, 0.0);
            let gap = if bare.len() >= 3 {
                geom::polygon_distance(&bare, robot)
            } else {
                cluster
                    .iter()
                    .map(|&p| dist(p, robot))
                    .fold(f64::INFINITY, f64::min)
            };
            let margin = opts.inflate.min(0.5 * gap);
            (margin > 0.0).then(|| inflated_hull(&cluster, margin))
        })
        .collect()
}

impl DynamicPlanner {
    /// Builds the global potential of the known map (`scene`, its obstacles being the static
    /// map) and an empty set of extra obstacles.
    pub fn new(scene: &Scene, options: LocalMapOptions) -> Result<DynamicPlanner, DynamicError> {
        options.validate()?;
        let global = Planner::new(scene)?;
        let lattice = (options.mode == LocalMapMode::Lattice).then(|| {
            let cells = options.lattice_cells();
            let h = options.size / cells as f64;
            let goal_rings = scene
                .goals()
                .iter()
                .filter_map(|g| region_polygon(g, 32))
                .collect();
            let mut lattice = Lattice::new(h, cells, scene.robot.radius, goal_rings);
            let (lo, hi) = global.domain().bounding_box();
            lattice.warm(global.domain(), lo, hi, LATTICE_WARM_VERTICES);
            lattice
        });
        Ok(DynamicPlanner {
            scene: scene.clone(),
            global,
            workspace: geo_polygon(&scene.workspace),
            options,
            obstacles: BTreeMap::new(),
            global_path: Vec::new(),
            waypoint: None,
            lattice,
        })
    }

    /// The planner of the known map.
    pub fn global(&self) -> &Planner {
        &self.global
    }

    /// The known map.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The local map options.
    pub fn options(&self) -> &LocalMapOptions {
        &self.options
    }

    /// Adds obstacle `id`, or moves it (replaces its polygon) if it exists.
    pub fn set_obstacle(&mut self, id: u32, polygon: Vec<[f64; 2]>) {
        self.obstacles.insert(id, polygon);
    }

    /// Removes obstacle `id`; returns whether it existed.
    pub fn remove_obstacle(&mut self, id: u32) -> bool {
        self.obstacles.remove(&id).is_some()
    }

    /// Replaces every extra obstacle by `polygons` (numbered from 0), e.g. with
    /// [`scan_obstacles`] of the latest scan.
    pub fn set_obstacles(&mut self, polygons: Vec<Vec<[f64; 2]>>) {
        self.obstacles = polygons
            .into_iter()
            .enumerate()
            .map(|(i, p)| (i as u32, p))
            .collect();
    }

    /// The extra (sensed or added) obstacles.
    pub fn obstacles(&self) -> impl Iterator<Item = (u32, &[[f64; 2]])> {
        self.obstacles.iter().map(|(&i, p)| (i, p.as_slice()))
    }

    /// Distance from `p` to the known map's walls and obstacles.
    pub fn known_distance(&self, p: [f64; 2]) -> f64 {
        self.global
            .domain()
            .distance_to_obstacles(Point::new(p[0], p[1]))
    }

    /// `OutsideWorkspace` unless `robot` is a finite point of the known map's workspace.
    fn check_in_workspace(&self, robot: [f64; 2]) -> Result<(), DynamicError> {
        if robot[0].is_finite()
            && robot[1].is_finite()
            && geom::polygon_contains(&self.scene.workspace, robot)
        {
            Ok(())
        } else {
            Err(DynamicError::OutsideWorkspace {
                x: robot[0],
                y: robot[1],
            })
        }
    }

    /// The global path from `robot`, reused while the robot stays within
    /// [`LocalMapOptions::global_path_tolerance`] of it (the part already travelled dropped).
    fn global_path_from(&mut self, robot: [f64; 2]) -> Result<&[[f64; 2]], DynamicError> {
        let nearest = self
            .global_path
            .windows(2)
            .enumerate()
            .map(|(i, w)| (i, geom::point_segment_distance(robot, w[0], w[1])))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match nearest {
            Some((i, d)) if d <= self.options.global_path_tolerance => {
                // Keep the path from the robot's projection on its nearest segment on; the
                // projection is not the robot's position, so a robot moving away from the
                // path drifts out of tolerance and the path is traced again.
                let (a, b) = (self.global_path[i], self.global_path[i + 1]);
                self.global_path[i] = projection(robot, a, b);
                self.global_path.drain(..i);
            }
            _ => {
                let path = self.global.plan(robot);
                if !path.status.reached_goal() {
                    return Err(DynamicError::NoGlobalPath {
                        x: robot[0],
                        y: robot[1],
                        status: path.status,
                    });
                }
                self.global_path = path.points;
            }
        }
        Ok(&self.global_path)
    }

    /// The scene of the window around `robot`: the workspace clipped to the window, the known
    /// and extra obstacles that reach into it, and the goal (the real one if it lies inside,
    /// else a small disc where the global path leaves the window). Returns the scene, the
    /// local goal's centre and whether it is the real goal.
    pub fn local_scene(
        &mut self,
        robot: [f64; 2],
    ) -> Result<(Scene, [f64; 2], bool), DynamicError> {
        self.check_in_workspace(robot)?;
        let outside = || DynamicError::OutsideWorkspace {
            x: robot[0],
            y: robot[1],
        };
        let half = 0.5 * self.options.size;
        let (lo, hi) = (
            [robot[0] - half, robot[1] - half],
            [robot[0] + half, robot[1] + half],
        );
        let window = geo_polygon(&[lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]]);
        let clipped = window.intersection(&self.workspace);
        let tiny = 1e-6 * self.options.size * self.options.size;
        let reaches_in = |ring: &[[f64; 2]]| {
            ring.len() >= 3 && geo_polygon(ring).intersection(&clipped).unsigned_area() > tiny
        };
        // Obstacles that cross the window's edge (or the workspace's) are cut out of the
        // local workspace here, so the mesher only gets obstacles strictly inside it.
        let eps = 1e-7 * self.options.size;
        let strictly_inside = |ring: &[[f64; 2]]| {
            ring.iter().all(|p| {
                p[0] > lo[0] + eps
                    && p[0] < hi[0] - eps
                    && p[1] > lo[1] + eps
                    && p[1] < hi[1] - eps
                    && geom::polygon_contains(&self.scene.workspace, *p)
            }) && self
                .scene
                .workspace
                .iter()
                .all(|w| !geom::polygon_contains(ring, *w))
        };
        let mut obstacles: Vec<Region> = Vec::new();
        let mut cut: Vec<Polygon<f64>> = Vec::new();
        for o in &self.scene.obstacles {
            // Circles as polygons circumscribing them, so what is cut out covers the circle.
            let ring = match (&o.polygon, &o.circle) {
                (Some(p), _) => p.clone(),
                (None, Some(c)) => {
                    let n = 64;
                    let grow = 1.0 / (std::f64::consts::PI / n as f64).cos();
                    circle_points(c.center, c.radius * grow, n)
                }
                _ => continue,
            };
            if !reaches_in(&ring) {
                continue;
            }
            if strictly_inside(&ring) {
                obstacles.push(o.clone());
            } else {
                cut.push(geo_polygon(&ring));
            }
        }
        let mut extra: Vec<Vec<[f64; 2]>> = Vec::new();
        for ring in self.obstacles.values() {
            if !reaches_in(ring) {
                continue;
            }
            if strictly_inside(ring) {
                extra.push(ring.clone());
            } else {
                cut.push(geo_polygon(ring));
            }
        }
        let free = if cut.is_empty() {
            clipped
        } else {
            clipped.difference(&geo::MultiPolygon(cut))
        };
        let piece = free
            .0
            .iter()
            .find(|p| {
                let ring: Vec<[f64; 2]> = p.exterior().coords().map(|c| [c.x, c.y]).collect();
                geom::polygon_contains(&ring, robot)
            })
            .ok_or_else(outside)?;
        let ring_of = |ls: &LineString<f64>| {
            let mut ring: Vec<[f64; 2]> = ls.coords().map(|c| [c.x, c.y]).collect();
            if ring.len() > 1 && ring.first() == ring.last() {
                ring.pop();
            }
            ring
        };
        let mut ws = ring_of(piece.exterior());
        // The clipper moves vertices by rounding (4.0 becomes 4.000000002): snap coordinates
        // back to the window's and the workspace's own, or an obstacle flush with a wall
        // leaves a sliver of free space a few nanometres wide.
        let snap_to: Vec<[f64; 2]> = self
            .scene
            .workspace
            .iter()
            .copied()
            .chain([lo, hi])
            .collect();
        for v in &mut ws {
            for k in 0..2 {
                if let Some(w) = snap_to.iter().find(|w| (w[k] - v[k]).abs() < eps) {
                    v[k] = w[k];
                }
            }
        }
        // Holes of the cut workspace (none unless cut obstacles enclose free space) stay
        // obstacles.
        for hole in piece.interiors() {
            extra.push(ring_of(hole));
        }
        obstacles.extend(extra.iter().map(|ring| Region {
            polygon: Some(ring.clone()),
            ..Region::default()
        }));

        let extra_rings: Vec<&[[f64; 2]]> = extra.iter().map(Vec::as_slice).collect();
        let goal = match self.choose_goal(robot, lo, hi, &extra_rings)? {
            LocalGoal::Real { centre } => {
                let scene = self.window_scene(ws, obstacles, self.scene.goal.clone());
                return Ok((scene, centre, true));
            }
            LocalGoal::Waypoint(c) => c,
        };
        let disc = Goals(vec![Region {
            circle: Some(Circle {
                center: goal,
                radius: self.options.goal_radius,
            }),
            ..Region::default()
        }]);
        let scene = self.window_scene(ws, obstacles, disc);
        Ok((scene, goal, false))
    }

    /// The goal of the window `[lo, hi]` around `robot`: the real one if every goal region
    /// lies inside the window (with room to spare) and clear of the `sensed` obstacles, else
    /// a point on the global path where it leaves the window (the last one clear of known
    /// and sensed obstacles), else the free point of the window's inner border with the
    /// lowest global potential.
    fn choose_goal(
        &mut self,
        robot: [f64; 2],
        lo: [f64; 2],
        hi: [f64; 2],
        sensed: &[&[[f64; 2]]],
    ) -> Result<LocalGoal, DynamicError> {
        let r = self.options.goal_radius;
        let margin = 2.0 * r;
        let inner = |p: [f64; 2]| inside_square(p, lo, hi, margin);
        let goal_rings: Vec<Option<Vec<[f64; 2]>>> = self
            .scene
            .goals()
            .iter()
            .map(|g| region_polygon(g, 16).or(g.point.map(|p| vec![p])))
            .collect();
        let goal_inside = goal_rings.iter().all(|g| {
            g.as_ref()
                .is_some_and(|ring| ring.iter().all(|&p| inner(p)))
        });
        let clear_of_sensed = |p: [f64; 2], need: f64| clear_of(sensed, p, need);
        if goal_inside
            && goal_rings
                .iter()
                .flatten()
                .all(|ring| ring.iter().all(|&p| clear_of_sensed(p, 0.0)))
        {
            let centre = goal_rings
                .iter()
                .flatten()
                .next()
                .and_then(|ring| ring.first().copied())
                .unwrap_or(robot);
            self.waypoint = None;
            return Ok(LocalGoal::Real { centre });
        }
        let known_clear = r * 1.5;
        // Keep the last waypoint while it is ahead, in the window and clear: a new one each
        // replan can flip between points before and behind an obstacle being discovered
        // (its sensed outline changes as the robot moves), and the robot then dithers.
        // It only has to stay in the window with its disc and a margin (the window moves
        // with the robot, so a waypoint near the border would otherwise come and go).
        let in_window = |p: [f64; 2]| inside_square(p, lo, hi, 1.5 * r);
        // `known_distance` is unsigned: a point deep inside a known obstacle is far from its
        // boundary too, so free space is checked as well.
        let still_valid = |p: [f64; 2]| {
            in_window(p)
                && dist(p, robot) > 2.0 * r
                && self.global.domain().contains_free(Point::new(p[0], p[1]))
                && self.known_distance(p) > known_clear
                && clear_of_sensed(p, 2.0 * r)
        };
        if let Some(w) = self.waypoint {
            if still_valid(w) {
                return Ok(LocalGoal::Waypoint(w));
            }
            // Where an obstacle grew onto it, the nearest valid point nearby: the robot keeps
            // the side of the obstacle it chose instead of flipping.
            let moved = (1..=4)
                .flat_map(|k| {
                    (0..16).map(move |a| {
                        let angle = std::f64::consts::TAU * a as f64 / 16.0;
                        let d = k as f64 * r;
                        [w[0] + d * angle.cos(), w[1] + d * angle.sin()]
                    })
                })
                .find(|&p| still_valid(p));
            if dist(w, robot) > 2.0 * r
                && let Some(p) = moved
            {
                self.waypoint = Some(p);
                return Ok(LocalGoal::Waypoint(p));
            }
        }
        let goal = self.choose_waypoint(robot, lo, hi, sensed)?;
        self.waypoint = Some(goal);
        Ok(LocalGoal::Waypoint(goal))
    }

    /// A new waypoint for [`Self::choose_goal`].
    fn choose_waypoint(
        &mut self,
        robot: [f64; 2],
        lo: [f64; 2],
        hi: [f64; 2],
        sensed: &[&[[f64; 2]]],
    ) -> Result<[f64; 2], DynamicError> {
        let r = self.options.goal_radius;
        let margin = 2.0 * r;
        let known_clear = r * 1.5;
        let inner = |p: [f64; 2]| inside_square(p, lo, hi, margin);
        let clear_of_sensed = |p: [f64; 2], need: f64| clear_of(sensed, p, need);
        // The last point of the global path in the window, if the path gets there clear of
        // the sensed obstacles. A path through a sensed obstacle is not used: a point before
        // the obstacle leads into its face, and a point behind its sensed outline may lie in
        // its unseen part; the border goal below leads around it instead.
        let candidate = |this: &Self, path: &[[f64; 2]]| {
            let leave = path.iter().position(|&p| !inner(p)).unwrap_or(path.len());
            if !path[..leave].iter().all(|&p| clear_of_sensed(p, r)) {
                return None;
            }
            path[..leave].iter().rev().copied().find(|&p| {
                dist(p, robot) > 2.0 * r
                    && this.known_distance(p) > known_clear
                    && clear_of_sensed(p, 2.0 * r)
            })
        };
        let path = self.global_path_from(robot)?.to_vec();
        if let Some(c) = candidate(self, &path) {
            return Ok(c);
        }
        // The kept global path may be stale: trace it again from the robot once.
        self.global_path.clear();
        let path = self.global_path_from(robot)?.to_vec();
        if let Some(c) = candidate(self, &path) {
            return Ok(c);
        }
        // The global path is blocked inside the window: the free point of the window's
        // inner border where the global potential is lowest.
        self.border_goal(lo, hi, margin, |p| {
            dist(p, robot) > 2.0 * r
                && self.known_distance(p) > known_clear
                && clear_of_sensed(p, 2.0 * r)
        })
        .ok_or(DynamicError::NoLocalGoal {
            x: robot[0],
            y: robot[1],
        })
    }

    /// The point of the square `[lo + margin, hi - margin]`'s boundary, in free space and
    /// accepted by `free`, with the largest global ψ (the lowest global potential).
    fn border_goal(
        &self,
        lo: [f64; 2],
        hi: [f64; 2],
        margin: f64,
        free: impl Fn([f64; 2]) -> bool,
    ) -> Option<[f64; 2]> {
        let (a, b) = (
            [lo[0] + margin, lo[1] + margin],
            [hi[0] - margin, hi[1] - margin],
        );
        let corners = [a, [b[0], a[1]], b, [a[0], b[1]]];
        let per_side = ((b[0] - a[0]) / self.options.goal_radius).ceil().max(1.0) as usize;
        let potential = self.global.potential();
        let mut hint = None;
        let mut best: Option<([f64; 2], f64)> = None;
        for k in 0..4 {
            let (p, q) = (corners[k], corners[(k + 1) % 4]);
            for i in 0..per_side {
                let s = i as f64 / per_side as f64;
                let c = [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])];
                let pt = Point::new(c[0], c[1]);
                if !self.global.domain().contains_free(pt) || !free(c) {
                    continue;
                }
                let Ok(t) = potential.locate(pt, hint) else {
                    continue;
                };
                hint = Some(t);
                let psi = potential.psi_in_triangle(t, pt);
                if best.is_none_or(|(_, v)| psi > v) {
                    best = Some((c, psi));
                }
            }
        }
        best.map(|(c, _)| c)
    }

    fn window_scene(&self, workspace: Vec<[f64; 2]>, obstacles: Vec<Region>, goal: Goals) -> Scene {
        Scene {
            name: Some("local window".into()),
            workspace,
            obstacles,
            goal,
            starts: Vec::new(),
            boundary: self.scene.boundary,
            mesh: MeshSpec {
                max_area: Some(self.options.max_area),
                min_angle_deg: Some(self.options.min_angle_deg),
                grading: None,
            },
            robot: self.scene.robot,
        }
    }

    /// Replans from `robot`: the window's goal, then its mesh — the lattice with the obstacles
    /// cut in ([`LocalMapMode::Lattice`]) or, when the lattice cannot serve or remeshing was
    /// asked for, a constrained Delaunay mesh of the window's scene — and its potential, and
    /// the path traced in it.
    pub fn replan(&mut self, robot: [f64; 2]) -> Result<LocalPlan, DynamicError> {
        let plan = self.replan_once(robot);
        // A waypoint that led nowhere is not kept.
        if !plan.as_ref().is_ok_and(|p| p.path.status.reached_goal()) {
            self.waypoint = None;
        }
        plan
    }

    fn replan_once(&mut self, robot: [f64; 2]) -> Result<LocalPlan, DynamicError> {
        let Some(mut lattice) = self.lattice.take() else {
            return self.replan_remeshed(robot);
        };
        let result = self.replan_on_lattice(&mut lattice, robot);
        self.lattice = Some(lattice);
        match result? {
            Ok(plan) => Ok(plan),
            Err(miss) => {
                let mut plan = self.replan_remeshed(robot)?;
                plan.remesh_reason = Some(miss.as_str());
                Ok(plan)
            }
        }
    }

    /// The lattice replan; `Ok(None)` when the lattice cannot serve this one.
    fn replan_on_lattice(
        &mut self,
        lattice: &mut Lattice,
        robot: [f64; 2],
    ) -> Result<Result<LocalPlan, LatticeMiss>, DynamicError> {
        let t0 = Instant::now();
        self.check_in_workspace(robot)?;
        let (lo, hi) = lattice.window(robot);
        let obstacles = std::mem::take(&mut self.obstacles);
        let sensed: Vec<&[[f64; 2]]> = obstacles.values().map(Vec::as_slice).collect();
        let chosen = self.choose_goal(robot, lo, hi, &sensed);
        let (goals, local_goal, goal_in_window) = match chosen {
            Ok(LocalGoal::Real { centre }) => (
                self.scene
                    .goals()
                    .iter()
                    .filter_map(|g| match (&g.polygon, &g.circle, g.point) {
                        (Some(p), _, _) => Some(LatticeGoal::Polygon(p)),
                        (None, Some(c), _) => Some(LatticeGoal::Circle {
                            center: c.center,
                            radius: c.radius,
                        }),
                        (None, None, Some(p)) => Some(LatticeGoal::Point(p)),
                        _ => None,
                    })
                    .collect::<Vec<_>>(),
                centre,
                true,
            ),
            // Every point lies within h/√2 of a lattice vertex: a disc that large holds one.
            Ok(LocalGoal::Waypoint(c)) => (
                vec![LatticeGoal::Circle {
                    center: c,
                    radius: self.options.goal_radius.max(lattice.cover_radius()),
                }],
                c,
                false,
            ),
            Err(e) => {
                self.obstacles = obstacles;
                return Err(e);
            }
        };
        let prepare = t0.elapsed().as_secs_f64() * 1e3;
        let planned = lattice.plan(self.global.domain(), robot, &sensed, &goals);
        let plan = match planned {
            Ok(plan) => plan,
            Err(miss) => {
                drop(goals);
                self.obstacles = obstacles;
                return Ok(Err(miss));
            }
        };
        let r = self.scene.robot.radius;
        let domain = self.global.domain();
        let metrics = path_metrics(&plan.path.points, |a, b| {
            let (a2, b2) = ([a.x, a.y], [b.x, b.y]);
            sensed
                .iter()
                .map(|ring| geom::segment_polygon_distance(a2, b2, ring) - r)
                .fold(domain.segment_clearance(a, b), f64::min)
        });
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        let path = PlannedPath {
            start: robot,
            status: plan.path.status,
            goal: plan.path.goal,
            tracer: plan.tracer,
            length: metrics.length,
            min_clearance: finite(metrics.min_clearance),
            min_gradient: finite(plan.path.min_gradient),
            points: plan.path.points.iter().map(|p| [p.x, p.y]).collect(),
        };
        drop(goals);
        self.obstacles = obstacles;
        Ok(Ok(LocalPlan {
            path,
            local_goal,
            goal_in_window,
            method: LocalMapMode::Lattice,
            remesh_reason: None,
            scene: None,
            triangles: plan.triangles,
            potential: plan.potential,
            timings: ReplanTimings {
                prepare,
                mesh: plan.mesh_ms,
                assemble: plan.assemble_ms,
                solve: plan.solve_ms,
                trace: plan.trace_ms,
                total: t0.elapsed().as_secs_f64() * 1e3,
            },
        }))
    }

    /// The remeshed replan: builds the local scene, meshes, assembles, solves and traces it.
    fn replan_remeshed(&mut self, robot: [f64; 2]) -> Result<LocalPlan, DynamicError> {
        let t0 = Instant::now();
        let (scene, local_goal, goal_in_window) = self.local_scene(robot)?;
        let prepare = t0.elapsed().as_secs_f64() * 1e3;
        let planner = Planner::new(&scene)?;
        let t = Instant::now();
        let path = planner.plan(robot);
        let trace = t.elapsed().as_secs_f64() * 1e3;
        let stage = planner.timings();
        Ok(LocalPlan {
            path,
            local_goal,
            goal_in_window,
            method: LocalMapMode::Remesh,
            remesh_reason: None,
            triangles: planner.mesh().triangles().len(),
            potential: Some(planner.potential().clone()),
            scene: Some(scene),
            timings: ReplanTimings {
                prepare,
                mesh: stage.mesh,
                assemble: stage.assemble,
                solve: stage.solve,
                trace,
                total: t0.elapsed().as_secs_f64() * 1e3,
            },
        })
    }
}

/// Whether `p` lies inside the square `[lo + margin, hi − margin]`.
fn inside_square(p: [f64; 2], lo: [f64; 2], hi: [f64; 2], margin: f64) -> bool {
    (0..2).all(|k| p[k] > lo[k] + margin && p[k] < hi[k] - margin)
}

/// Whether `p` is farther than `need` from every ring of `sensed`.
fn clear_of(sensed: &[&[[f64; 2]]], p: [f64; 2], need: f64) -> bool {
    sensed
        .iter()
        .all(|ring| geom::polygon_distance(ring, p) > need)
}

/// An obstacle of the simulated world that the known map does not have: static (zero
/// velocity) or moving.
#[derive(Clone, Debug, Serialize)]
pub struct WorldObstacle {
    /// The polygon at time 0.
    pub polygon: Vec<[f64; 2]>,
    /// Velocity, m/s.
    pub velocity: [f64; 2],
    /// 0: moves on forever; otherwise it turns back every `period / 2` seconds, returning to
    /// where it started every `period`.
    pub period: f64,
}

impl WorldObstacle {
    /// Whether the obstacle moves.
    pub fn moves(&self) -> bool {
        self.velocity != [0.0, 0.0]
    }

    /// The polygon at time `t`.
    pub fn at(&self, t: f64) -> Vec<[f64; 2]> {
        let s = if self.period > 0.0 {
            let h = 0.5 * self.period;
            h - (t.rem_euclid(self.period) - h).abs()
        } else {
            t
        };
        let (dx, dy) = (self.velocity[0] * s, self.velocity[1] * s);
        self.polygon
            .iter()
            .map(|p| [p[0] + dx, p[1] + dy])
            .collect()
    }
}

/// The simulated world: the known map's walls and obstacles, plus obstacles it does not know.
pub struct World {
    known_segments: Vec<([f64; 2], [f64; 2])>,
    /// Obstacles not in the known map, seen only by the laser.
    pub obstacles: Vec<WorldObstacle>,
}

fn ring_segments(ring: &[[f64; 2]]) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
    (0..ring.len()).map(move |i| (ring[i], ring[(i + 1) % ring.len()]))
}

/// Where the ray `o + s·d` (s ≥ 0) first meets the segment `ab`, as `s`.
fn ray_hit(o: [f64; 2], d: [f64; 2], a: [f64; 2], b: [f64; 2]) -> Option<f64> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let den = d[0] * e[1] - d[1] * e[0];
    if den.abs() < 1e-300 {
        return None;
    }
    let w = [a[0] - o[0], a[1] - o[1]];
    let s = (w[0] * e[1] - w[1] * e[0]) / den;
    let u = (w[0] * d[1] - w[1] * d[0]) / den;
    (s >= 0.0 && (0.0..=1.0).contains(&u)).then_some(s)
}

impl World {
    /// A world made of the known map of `scene` and the unknown `obstacles`.
    pub fn new(scene: &Scene, obstacles: Vec<WorldObstacle>) -> World {
        let mut known_segments: Vec<_> = ring_segments(&scene.workspace).collect();
        for o in &scene.obstacles {
            if let Some(ring) = region_polygon(o, 64) {
                known_segments.extend(ring_segments(&ring));
            }
        }
        World {
            known_segments,
            obstacles,
        }
    }

    /// A laser scan from `pose` at time `t`: `beams` rays evenly spread over a full turn,
    /// each returning its first hit closer than `range` (in the robot frame).
    pub fn scan(&self, pose: [f64; 3], t: f64, beams: usize, range: f64) -> LaserScan {
        let moving: Vec<Vec<[f64; 2]>> = self.obstacles.iter().map(|o| o.at(t)).collect();
        let o = [pose[0], pose[1]];
        let mut points = Vec::with_capacity(beams);
        for k in 0..beams {
            let local = std::f64::consts::TAU * k as f64 / beams as f64;
            let (s, c) = (pose[2] + local).sin_cos();
            let d = [c, s];
            let hit = self
                .known_segments
                .iter()
                .copied()
                .chain(moving.iter().flat_map(|r| ring_segments(r)))
                .filter_map(|(a, b)| ray_hit(o, d, a, b))
                .fold(f64::INFINITY, f64::min);
            if hit < range {
                let (ls, lc) = local.sin_cos();
                points.push([hit * lc, hit * ls]);
            }
        }
        LaserScan { pose, points }
    }

    /// Distance from `p` to the unknown obstacles at time `t` (0 inside one); `moving_only`
    /// restricts it to the moving ones.
    pub fn distance(&self, p: [f64; 2], t: f64, moving_only: bool) -> f64 {
        self.obstacles
            .iter()
            .filter(|o| !moving_only || o.moves())
            .map(|o| geom::polygon_distance(&o.at(t), p))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The loop's settings.
#[derive(Clone, Copy, Debug)]
pub struct RunOptions {
    /// Laser rays per scan (default 180).
    pub beams: usize,
    /// Laser range (default 3 m).
    pub range: f64,
    /// Robot speed, m/s (default 1); obstacles must not be faster.
    pub speed: f64,
    /// Longest step (default 0.1 m).
    pub max_step: f64,
    /// Shortest step (default 0.002 m).
    pub min_step: f64,
    /// A step is this fraction of the distance to the nearest sensed obstacle (default 0.25).
    pub step_fraction: f64,
    /// Time the robot waits when it has no path, s (default 0.02).
    pub wait: f64,
    /// Steps before giving up (default 2000).
    pub max_steps: usize,
    /// Record the unknown obstacles every this many steps (default 10; 0: never).
    pub snapshot_every: usize,
    /// How scans become obstacles.
    pub scan: ScanOptions,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            beams: 180,
            range: 3.0,
            speed: 1.0,
            max_step: 0.1,
            min_step: 0.002,
            step_fraction: 0.25,
            wait: 0.02,
            max_steps: 2000,
            snapshot_every: 10,
            scan: ScanOptions::default(),
        }
    }
}

/// What happened in a run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Run {
    /// Whether the robot reached the goal.
    pub reached: bool,
    /// Successful replans.
    pub replans: usize,
    /// Of those, replans that remeshed the window (the lattice could not serve them, or
    /// [`LocalMapMode::Remesh`] was asked for).
    pub remeshed: usize,
    /// Replans that failed (the robot waited); the last error's message.
    pub failed_replans: usize,
    /// The last failure, if any.
    pub last_error: Option<String>,
    /// Robot positions, one per step.
    pub trail: Vec<[f64; 2]>,
    /// Simulated time at each trail point, s.
    pub times: Vec<f64>,
    /// Smallest distance from the robot to the true obstacles (known map, walls and unknown
    /// obstacles at their positions of the moment) over all steps and the segments between.
    pub min_distance_to_obstacles: f64,
    /// Wall-clock time of each replan, ms.
    pub replan_ms: Vec<f64>,
    /// Stage times summed over the run.
    pub stage_ms: ReplanTimings,
    /// `(time, unknown obstacles then)` every [`RunOptions::snapshot_every`] steps.
    pub snapshots: Vec<(f64, Vec<Vec<[f64; 2]>>)>,
    /// Local mesh sizes, smallest and largest.
    pub triangles: (usize, usize),
}

/// Walks `points` from the first one for an arc length `step`; returns where it stops.
fn advance(points: &[[f64; 2]], step: f64) -> [f64; 2] {
    let mut left = step;
    for w in points.windows(2) {
        let l = dist(w[0], w[1]);
        if l >= left && l > 0.0 {
            let s = left / l;
            return [
                w[0][0] + s * (w[1][0] - w[0][0]),
                w[0][1] + s * (w[1][1] - w[0][1]),
            ];
        }
        left -= l;
    }
    points.last().copied().unwrap_or([f64::NAN, f64::NAN])
}

/// The paper's Figure 10 loop: from `start`, scan, turn the scan into obstacles, replan,
/// move a step along the local path sized by the distance to the nearest sensed obstacle,
/// let the world's obstacles move for the step's duration, repeat until the goal is reached
/// or [`RunOptions::max_steps`] steps.
pub fn run(planner: &mut DynamicPlanner, world: &World, start: [f64; 2], opts: &RunOptions) -> Run {
    let mut out = Run {
        min_distance_to_obstacles: f64::INFINITY,
        triangles: (usize::MAX, 0),
        ..Run::default()
    };
    let true_distance = |planner: &DynamicPlanner, p: [f64; 2], t: f64| {
        planner.known_distance(p).min(world.distance(p, t, false))
    };
    let (mut pos, mut heading, mut t) = (start, 0.0f64, 0.0f64);
    out.trail.push(pos);
    out.times.push(t);
    out.min_distance_to_obstacles = true_distance(planner, pos, t);
    for step_no in 0..opts.max_steps {
        if opts.snapshot_every > 0 && step_no % opts.snapshot_every == 0 {
            out.snapshots
                .push((t, world.obstacles.iter().map(|o| o.at(t)).collect()));
        }
        let scan = world.scan([pos[0], pos[1], heading], t, opts.beams, opts.range);
        let sensed = scan_obstacles(&scan, |p| planner.known_distance(p), &opts.scan);
        let nearest = sensed
            .iter()
            .map(|ring| geom::polygon_distance(ring, pos))
            .fold(f64::INFINITY, f64::min);
        planner.set_obstacles(sensed);
        let plan = match planner.replan(pos) {
            Ok(plan) if plan.path.status.reached_goal() && plan.path.points.len() >= 2 => plan,
            other => {
                out.failed_replans += 1;
                out.last_error = Some(match other {
                    Ok(plan) => format!("local path {}", plan.path.status),
                    Err(e) => e.to_string(),
                });
                t += opts.wait;
                let d = true_distance(planner, pos, t);
                out.min_distance_to_obstacles = out.min_distance_to_obstacles.min(d);
                continue;
            }
        };
        out.replans += 1;
        out.remeshed += usize::from(plan.method == LocalMapMode::Remesh);
        out.replan_ms.push(plan.timings.total);
        for (sum, v) in [
            (&mut out.stage_ms.prepare, plan.timings.prepare),
            (&mut out.stage_ms.mesh, plan.timings.mesh),
            (&mut out.stage_ms.assemble, plan.timings.assemble),
            (&mut out.stage_ms.solve, plan.timings.solve),
            (&mut out.stage_ms.trace, plan.timings.trace),
            (&mut out.stage_ms.total, plan.timings.total),
        ] {
            *sum += v;
        }
        out.triangles.0 = out.triangles.0.min(plan.triangles);
        out.triangles.1 = out.triangles.1.max(plan.triangles);

        let step = (opts.step_fraction * nearest).clamp(opts.min_step, opts.max_step);
        let remaining = geom::polyline_length(&plan.path.points);
        let final_leg = plan.goal_in_window && remaining <= step;
        let next = if final_leg {
            plan.path.points[plan.path.points.len() - 1]
        } else {
            advance(&plan.path.points, step)
        };
        let moved = dist(pos, next);
        // The segment against the static map, then the end point against everything.
        let seg = planner
            .global()
            .domain()
            .segment_clearance(Point::new(pos[0], pos[1]), Point::new(next[0], next[1]));
        if moved > 0.0 {
            heading = (next[1] - pos[1]).atan2(next[0] - pos[0]);
        }
        t += moved / opts.speed;
        pos = next;
        let d = true_distance(planner, pos, t).min(seg);
        out.min_distance_to_obstacles = out.min_distance_to_obstacles.min(d);
        out.trail.push(pos);
        out.times.push(t);
        if final_leg {
            out.reached = true;
            break;
        }
    }
    if out.replans == 0 {
        out.triangles = (0, 0);
    }
    out
}

impl Run {
    /// The median and the 99th percentile of the replan times, ms (0 without replans).
    pub fn replan_percentiles(&self) -> (f64, f64) {
        let mut v = self.replan_ms.clone();
        if v.is_empty() {
            return (0.0, 0.0);
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
        (at(0.5), at(0.99))
    }
}
