//! The window planner: the known map's global potential, obstacles that come and go, and at
//! every replan a local potential on a square window around the robot — on the fixed lattice
//! with the obstacles cut in, or remeshed — with the goal where the global path leaves the
//! window.

use std::collections::BTreeMap;
use std::time::Instant;

use geo::{Area, BooleanOps, LineString, MultiPolygon, Polygon};
use harmonic_mesh::{Point, geom};
use serde::Serialize;

use harmonic_planner::scene::{Circle, Goals, MeshSpec, Region, Scene};
use harmonic_planner::{PlannedPath, Planner};
use harmonic_trajectory::path_metrics;

use crate::lattice::{Lattice, LatticeGoal, LatticeMiss};
use crate::{DynamicError, circle_points, dist, region_polygon};

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

    /// `InvalidOption` for the first option out of range.
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

/// A polygon's ring, as the scene format gives it.
type Ring = Vec<[f64; 2]>;

/// The obstacles of a window (see [`DynamicPlanner::window_obstacles`]).
struct WindowObstacles {
    /// The known map's obstacles strictly inside the window, as they are.
    obstacles: Vec<Region>,
    /// The extra obstacles strictly inside the window.
    extra: Vec<Vec<[f64; 2]>>,
    /// Every obstacle crossing the window's edge or the workspace's.
    cut: Vec<Polygon<f64>>,
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

/// A ring as a `geo` polygon without holes.
fn geo_polygon(points: &[[f64; 2]]) -> Polygon<f64> {
    Polygon::new(
        LineString::from(points.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()),
        vec![],
    )
}

/// The point of segment `ab` closest to `p`, as the scene format's array.
fn projection(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let q = geom::closest_point_on_segment(p, a, b);
    [q.x, q.y]
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
    /// `scan_obstacles` of the latest scan.
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
        let half = 0.5 * self.options.size;
        let (lo, hi) = (
            [robot[0] - half, robot[1] - half],
            [robot[0] + half, robot[1] + half],
        );
        let window = geo_polygon(&[lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]]);
        let clipped = window.intersection(&self.workspace);
        let WindowObstacles {
            mut obstacles,
            mut extra,
            cut,
        } = self.window_obstacles(lo, hi, &clipped);
        let (ws, holes) = self.free_workspace(robot, lo, hi, clipped, cut)?;
        // Holes of the cut workspace (none unless cut obstacles enclose free space) stay
        // obstacles.
        extra.extend(holes);
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

    /// The known and extra obstacles that reach into the window `[lo, hi]` (whose free part
    /// is `clipped`), sorted into those strictly inside it, which the mesher gets, and those
    /// crossing the window's edge or the workspace's, which are cut out of the local workspace.
    fn window_obstacles(
        &self,
        lo: [f64; 2],
        hi: [f64; 2],
        clipped: &MultiPolygon<f64>,
    ) -> WindowObstacles {
        let tiny = 1e-6 * self.options.size * self.options.size;
        let reaches_in = |ring: &[[f64; 2]]| {
            ring.len() >= 3 && geo_polygon(ring).intersection(clipped).unsigned_area() > tiny
        };
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
        WindowObstacles {
            obstacles,
            extra,
            cut,
        }
    }

    /// The piece of the window's free part `clipped` less the `cut` obstacles that holds
    /// `robot`: its outer ring, snapped back to the window's and the workspace's coordinates,
    /// and its holes.
    fn free_workspace(
        &self,
        robot: [f64; 2],
        lo: [f64; 2],
        hi: [f64; 2],
        clipped: MultiPolygon<f64>,
        cut: Vec<Polygon<f64>>,
    ) -> Result<(Ring, Vec<Ring>), DynamicError> {
        let free = if cut.is_empty() {
            clipped
        } else {
            clipped.difference(&MultiPolygon(cut))
        };
        let piece = free
            .0
            .iter()
            .find(|p| {
                let ring: Vec<[f64; 2]> = p.exterior().coords().map(|c| [c.x, c.y]).collect();
                geom::polygon_contains(&ring, robot)
            })
            .ok_or(DynamicError::OutsideWorkspace {
                x: robot[0],
                y: robot[1],
            })?;
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
        let eps = 1e-7 * self.options.size;
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
        Ok((ws, piece.interiors().iter().map(ring_of).collect()))
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

    /// The scene of a window: its workspace ring, obstacles and goal, with the known map's
    /// boundary conditions and robot and the local mesh options.
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
                simplify: None,
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

    /// One replan: on the lattice when there is one, remeshed where it misses (with the
    /// reason) or when there is none.
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

    /// The lattice replan; `Ok(Err(miss))` when the lattice cannot serve this one.
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
            blocked_by: None,
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
