//! The local map on a fixed background lattice: the window is a square of `n × n` cells of side
//! `h`, each split into two right triangles along the same diagonal (`2n²` triangles: 3200 for
//! the paper's 40 × 40 map), aligned with a world-fixed grid so that every window has the same
//! connectivity, whichever way the robot moves.
//!
//! Obstacles are cut in by blocking lattice vertices rather than by remeshing: a vertex is
//! blocked when it lies closer than `h/√2` to the known map's (robot-inflated) walls and
//! obstacles, or closer than `r + h/√2` to a sensed obstacle (`r` the robot's radius). The
//! local mesh keeps the triangles whose three vertices are free. Every point of such a
//! triangle lies within its circumradius `h/√2` of a free vertex, so the kept triangles — and
//! every path traced in them — keep clear of the obstacles. The price is a margin of up to
//! `h/√2` on top of the robot's radius; where it closes a passage the caller remeshes instead.
//!
//! On this lattice the P1 stiffness is the 5-point stencil (the diagonal edges face right
//! angles on both sides, so their cotangent weights vanish), and the Dirichlet problem of the
//! kept mesh has the kept mesh's interior vertices as unknowns, each coupled to its four
//! lattice neighbours; every other vertex is held at its boundary value. Each replan builds,
//! factors and solves only its own unknowns (in the benchmark window 690 of the 1681
//! vertices), with the M-matrix LDLᵀ of `harmonic-solver`, whose far-field ψ keeps its
//! relative accuracy. What is reused is the elimination order: a minimum-degree order
//! computed for an earlier window is kept by global lattice vertex and numbers the unknowns
//! while it still ranks most of them (it gives a fifth of the fill of the lattice's
//! nested-dissection order restricted to them); when the robot has moved on far enough, the
//! replan numbers them in that nested-dissection order and computes a fresh minimum-degree
//! order to keep.
//!
//! The two policies live in the crates that own them: the lattice's geometry and its
//! structured P1 system are [`harmonic_fem::StructuredGrid`], the kept order and its reuse
//! rule are [`harmonic_solver::KeptOrder`]. This module decides what is blocked, builds the
//! local mesh, and traces.

use std::collections::HashMap;
use std::sync::Arc;

use harmonic_fem::{Potential, StructuredGrid, VertexRole};
use harmonic_mesh::{BoundaryTag, Domain, Mesh, NO_NEIGHBOR, Point};
use harmonic_solver::{AccurateLdlt, KeptOrder, MMatrix, Ordering};
use harmonic_trajectory::{
    ExactOptions, Path, SmoothOptions, SmoothP1Field, TraceStatus, Tracer, descend,
};

use harmonic_mesh::geom::{polygon_contains, polygon_distance};

/// Side of the square tiles in which the known map's blocked lattice vertices are cached.
const TILE: i64 = 32;

/// Blocking distance from the known map's inflated boundary, in units of `h`: a little more
/// than the circumradius `1/√2` of the lattice's right triangles.
const CLEARANCE_FACTOR: f64 = std::f64::consts::FRAC_1_SQRT_2 * (1.0 + 1e-9);

/// Why the lattice could not serve a replan (the caller then remeshes the window).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LatticeMiss {
    /// The robot is not in a kept triangle: closer to an obstacle than the lattice's margin.
    RobotBlocked,
    /// No free lattice vertex lies in the goal region.
    NoGoalVertex,
    /// The trace from the robot did not reach the goal (the margin sealed the way, or the
    /// tracer stopped).
    NotReached,
    /// The lattice system could not be factored (it cannot happen for a well-formed window;
    /// kept as a reason rather than a panic).
    Solve,
}

impl LatticeMiss {
    /// The reason as a snake_case word.
    pub fn as_str(self) -> &'static str {
        match self {
            LatticeMiss::RobotBlocked => "robot_blocked",
            LatticeMiss::NoGoalVertex => "no_goal_vertex",
            LatticeMiss::NotReached => "not_reached",
            LatticeMiss::Solve => "solve",
        }
    }
}

/// A goal region as the lattice sees it.
pub(crate) enum LatticeGoal<'a> {
    /// A disc.
    Circle {
        /// Centre.
        center: [f64; 2],
        /// Radius.
        radius: f64,
    },
    /// A polygon.
    Polygon(&'a [[f64; 2]]),
    /// A point: the vertices of the lattice triangle holding it are the goal, and the path
    /// ends at the point itself.
    Point([f64; 2]),
}

/// What one lattice replan produced.
pub(crate) struct LatticePlan {
    /// The traced path (its last point is in the goal region).
    pub path: Path,
    /// Which tracer made it.
    pub tracer: Tracer,
    /// Triangles of the local mesh (kept triangles, goal triangles included).
    pub triangles: usize,
    /// The local potential on the kept triangles less the goal's (`None` when the robot
    /// started in the goal).
    pub potential: Option<Potential>,
    /// Milliseconds spent cutting the obstacles in and building the local mesh.
    pub mesh_ms: f64,
    /// Milliseconds spent on the lattice system's values.
    pub assemble_ms: f64,
    /// Milliseconds spent refactoring and solving.
    pub solve_ms: f64,
    /// Milliseconds spent tracing.
    pub trace_ms: f64,
}

/// The fixed lattice: geometry, the nested-dissection order of its vertices, the kept
/// minimum-degree order and the cache of the known map's blocked vertices.
pub(crate) struct Lattice {
    h: f64,
    cells: usize,
    /// The window's `cells × cells` grid: its triangles and its structured P1 system.
    grid: StructuredGrid,
    /// The robot's radius (sensed obstacles are grown by it).
    robot_radius: f64,
    /// The known map's goal regions as polygons: holes of its free space, but free for the
    /// lattice.
    goal_rings: Vec<Vec<[f64; 2]>>,
    /// A nested-dissection order of all `(cells + 1)²` lattice vertices (of the 5-point
    /// stencil's graph), computed once: each replan numbers its unknowns in this order.
    order: Vec<usize>,
    /// The minimum-degree elimination order of an earlier window's unknowns by global
    /// lattice vertex, reused while it covers most of the current ones.
    elimination: Option<KeptOrder<(i64, i64)>>,
    known: HashMap<(i64, i64), Vec<bool>>,
}

/// Milliseconds since `t`.
fn millis(t: std::time::Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

impl Lattice {
    /// A lattice of `cells × cells` cells of side `h`, for a map whose goal regions are
    /// `goal_rings`.
    pub fn new(h: f64, cells: usize, robot_radius: f64, goal_rings: Vec<Vec<[f64; 2]>>) -> Lattice {
        let grid = StructuredGrid::new(cells, cells, h);
        let order = grid.nested_dissection();
        Lattice {
            h,
            cells,
            grid,
            robot_radius,
            goal_rings,
            order,
            elimination: None,
            known: HashMap::new(),
        }
    }

    /// A radius within which every point of the window has a lattice vertex.
    pub fn cover_radius(&self) -> f64 {
        CLEARANCE_FACTOR * self.h
    }

    /// Vertices per side.
    fn side(&self) -> usize {
        self.cells + 1
    }

    /// Global lattice index of the window's lower-left vertex for a robot at `robot`: the
    /// window's centre vertex is the lattice vertex nearest the robot.
    pub fn origin(&self, robot: [f64; 2]) -> (i64, i64) {
        let half = (self.cells / 2) as i64;
        (
            (robot[0] / self.h).round() as i64 - half,
            (robot[1] / self.h).round() as i64 - half,
        )
    }

    /// The window `[lo, hi]` of a robot at `robot`.
    pub fn window(&self, robot: [f64; 2]) -> ([f64; 2], [f64; 2]) {
        let (gi, gj) = self.origin(robot);
        let lo = [gi as f64 * self.h, gj as f64 * self.h];
        let span = self.cells as f64 * self.h;
        (lo, [lo[0] + span, lo[1] + span])
    }

    /// Tile `key` of the known map's blocked lattice vertices (row by row; computed on first
    /// use): a vertex is blocked when it is outside the map's free space and goal regions, or
    /// too close to its walls and obstacles.
    fn known_tile(&mut self, domain: &Domain, key: (i64, i64)) -> &[bool] {
        let h = self.h;
        let goal_rings = &self.goal_rings;
        self.known.entry(key).or_insert_with(|| {
            let mut tile = Vec::with_capacity((TILE * TILE) as usize);
            for b in 0..TILE {
                for a in 0..TILE {
                    let p =
                        Point::new((key.0 * TILE + a) as f64 * h, (key.1 * TILE + b) as f64 * h);
                    let in_goal = || goal_rings.iter().any(|g| polygon_contains(g, [p.x, p.y]));
                    tile.push(
                        domain.distance_to_obstacles(p) < CLEARANCE_FACTOR * h
                            || !(domain.contains_free(p) || in_goal()),
                    );
                }
            }
            tile
        })
    }

    /// Fills the known map's cache for every tile of the rectangle `[lo, hi]` (up to
    /// `max_vertices` lattice vertices), so replans do not pay for it.
    pub fn warm(&mut self, domain: &Domain, lo: Point, hi: Point, max_vertices: usize) {
        let (i0, j0) = (
            (lo.x / self.h).floor() as i64,
            (lo.y / self.h).floor() as i64,
        );
        let (i1, j1) = ((hi.x / self.h).ceil() as i64, (hi.y / self.h).ceil() as i64);
        let count = (i1 - i0 + 1).max(0) as usize * (j1 - j0 + 1).max(0) as usize;
        if count > max_vertices {
            return;
        }
        for tj in j0.div_euclid(TILE)..=j1.div_euclid(TILE) {
            for ti in i0.div_euclid(TILE)..=i1.div_euclid(TILE) {
                self.known_tile(domain, (ti, tj));
            }
        }
    }

    /// Plans on the lattice window around `robot` with the known map `domain`, the sensed
    /// obstacles `sensed` and `goals`; the reasons the lattice cannot serve are
    /// [`LatticeMiss`]es.
    pub fn plan(
        &mut self,
        domain: &Domain,
        robot: [f64; 2],
        sensed: &[&[[f64; 2]]],
        goals: &[LatticeGoal<'_>],
    ) -> Result<LatticePlan, LatticeMiss> {
        let t = std::time::Instant::now();
        let window = Window {
            origin: self.origin(robot),
            side: self.side(),
            h: self.h,
        };
        let blocked = self.blocked(domain, &window, sensed);
        let is_goal = self.goal_vertices(&window, &blocked, goals);
        if !is_goal.contains(&true) {
            return Err(LatticeMiss::NoGoalVertex);
        }
        let kind = self.classify(&blocked, &is_goal);
        let kept = kind.iter().filter(|&&k| k != Kind::Removed).count();
        let robot_tri = self
            .triangle_at(robot, &window)
            .filter(|&tri| kind[tri] != Kind::Removed)
            .ok_or(LatticeMiss::RobotBlocked)?;
        // The robot already in a goal triangle: the goal is one straight step away, inside
        // that kept triangle.
        if kind[robot_tri] == Kind::Goal {
            let mut points = vec![Point::new(robot[0], robot[1])];
            points.extend(self.goal_targets(robot_tri, robot, &is_goal, goals, &window));
            return Ok(LatticePlan {
                path: Path::new(points, TraceStatus::ReachedGoal(0), f64::INFINITY, 0),
                tracer: Tracer::Straight,
                triangles: kept,
                potential: None,
                mesh_ms: millis(t),
                assemble_ms: 0.0,
                solve_ms: 0.0,
                trace_ms: 0.0,
            });
        }
        let (mesh, index) = self.local_mesh(&window, &kind)?;
        let mesh_ms = millis(t);

        let t = std::time::Instant::now();
        let system = self.system(&mesh, &index, &window)?;
        let assemble_ms = millis(t);

        let t = std::time::Instant::now();
        let (psi, fresh) = system.solve()?;
        if let Some(order) = fresh {
            let keys = order.into_iter().map(|v| window.global(v));
            self.elimination = Some(KeptOrder::new(keys));
        }
        let potential =
            Potential::new(Arc::clone(&mesh), psi, 1.0).map_err(|_| LatticeMiss::Solve)?;
        let field =
            SmoothP1Field::ascending(&mesh, potential.psi(), potential.nodal_gradients_psi())
                .map_err(|_| LatticeMiss::Solve)?;
        let solve_ms = millis(t);

        // Trace as the planner does: smooth first, the exact tracer where it stalls.
        let t = std::time::Instant::now();
        let start = Point::new(robot[0], robot[1]);
        let span = self.cells as f64 * self.h;
        // The local mesh numbers its triangles in lattice order: the robot's is the count of
        // mesh triangles before it (a hint, so the tracer builds no point locator).
        let hint = kind[..robot_tri]
            .iter()
            .filter(|&&k| k == Kind::Mesh)
            .count() as u32;
        let (path, tracer) = descend(
            &field,
            start,
            Some(hint),
            &SmoothOptions::for_scale(span),
            &ExactOptions::default(),
        );
        if !matches!(path.status, TraceStatus::ReachedGoal(_)) {
            return Err(LatticeMiss::NotReached);
        }
        let path = self.step_into_goal(path, start, &is_goal, goals, &window, &kind);
        Ok(LatticePlan {
            path,
            tracer,
            triangles: kept,
            potential: Some(potential),
            mesh_ms,
            assemble_ms,
            solve_ms,
            trace_ms: millis(t),
        })
    }

    /// `path` (traced from `start` to the goal's hole) completed by the step from where it met
    /// the hole to a goal vertex (or the goal point), inside the goal triangle it entered.
    fn step_into_goal(
        &self,
        mut path: Path,
        start: Point,
        is_goal: &[bool],
        goals: &[LatticeGoal<'_>],
        window: &Window,
        kind: &[Kind],
    ) -> Path {
        if let Some(&end) = path.points.last() {
            let before = path
                .points
                .len()
                .checked_sub(2)
                .map_or(start, |k| path.points[k]);
            let step = 1e-6 * self.h * (end - before).try_normalize(0.0).unwrap_or_default();
            let inward = end + step;
            let entered = self
                .triangle_at([inward.x, inward.y], window)
                .filter(|&tri| kind[tri] == Kind::Goal)
                .or_else(|| self.goal_triangle_touching(end, window, kind));
            if let Some(tri) = entered {
                let mut points = std::mem::take(&mut path.points);
                points.extend(self.goal_targets(tri, [end.x, end.y], is_goal, goals, window));
                path = Path::new(points, path.status, path.min_gradient, path.cells_crossed);
            }
        }
        path
    }

    /// Blocked vertices of `window`: the known map's (cached), then those within the robot's
    /// radius plus the margin of a sensed obstacle.
    fn blocked(&mut self, domain: &Domain, window: &Window, sensed: &[&[[f64; 2]]]) -> Vec<bool> {
        let (gi0, gj0) = window.origin;
        let side = window.side;
        // The known map's part, copied tile by tile from the cache.
        let mut blocked = vec![false; side * side];
        let tiles = |lo: i64| lo.div_euclid(TILE)..=(lo + side as i64 - 1).div_euclid(TILE);
        for tj in tiles(gj0) {
            for ti in tiles(gi0) {
                let tile = self.known_tile(domain, (ti, tj));
                let (i_lo, i_hi) = (
                    (ti * TILE).max(gi0),
                    (ti * TILE + TILE).min(gi0 + side as i64),
                );
                let (j_lo, j_hi) = (
                    (tj * TILE).max(gj0),
                    (tj * TILE + TILE).min(gj0 + side as i64),
                );
                for gj in j_lo..j_hi {
                    let row = ((gj - tj * TILE) * TILE) as usize;
                    let dst = (gj - gj0) as usize * side;
                    for gi in i_lo..i_hi {
                        blocked[dst + (gi - gi0) as usize] = tile[row + (gi - ti * TILE) as usize];
                    }
                }
            }
        }
        let h = self.h;
        let grow = self.robot_radius + CLEARANCE_FACTOR * h;
        let cells = self.cells as f64;
        for ring in sensed {
            if ring.len() < 3 {
                continue;
            }
            let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for p in ring.iter() {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            // The range of lattice indices within `grow` of the ring's bounding box.
            let range = |lo: f64, hi: f64, origin: i64| {
                (
                    ((lo - grow) / h - origin as f64).ceil().max(0.0),
                    ((hi + grow) / h - origin as f64).floor().min(cells),
                )
            };
            let (i_lo, i_hi) = range(lo[0], hi[0], gi0);
            let (j_lo, j_hi) = range(lo[1], hi[1], gj0);
            // Also skips rings with non-finite coordinates (every comparison false).
            if !(i_lo <= i_hi && j_lo <= j_hi) {
                continue;
            }
            for j in j_lo as usize..=j_hi as usize {
                for i in i_lo as usize..=i_hi as usize {
                    let v = j * side + i;
                    if blocked[v] {
                        continue;
                    }
                    let p = window.at(v);
                    if polygon_contains(ring, p) || polygon_distance(ring, p) < grow {
                        blocked[v] = true;
                    }
                }
            }
        }
        blocked
    }

    /// The free vertices of `window` in a goal region (for a point goal: the vertices of the
    /// triangle holding it, if that triangle is free).
    fn goal_vertices(
        &self,
        window: &Window,
        blocked: &[bool],
        goals: &[LatticeGoal<'_>],
    ) -> Vec<bool> {
        let mut is_goal = vec![false; blocked.len()];
        for goal in goals {
            match goal {
                LatticeGoal::Circle { center, radius } => {
                    let r2 = radius * radius;
                    for (v, g) in is_goal.iter_mut().enumerate() {
                        let p = window.at(v);
                        let (dx, dy) = (p[0] - center[0], p[1] - center[1]);
                        *g |= dx * dx + dy * dy <= r2;
                    }
                }
                LatticeGoal::Polygon(ring) => {
                    for (v, g) in is_goal.iter_mut().enumerate() {
                        *g |= polygon_contains(ring, window.at(v));
                    }
                }
                LatticeGoal::Point(p) => {
                    if let Some(tri) = self.triangle_at(*p, window) {
                        let verts = self.grid.triangle_vertices(tri);
                        if verts.iter().all(|&v| !blocked[v]) {
                            for v in verts {
                                is_goal[v] = true;
                            }
                        }
                    }
                }
            }
        }
        for (g, &b) in is_goal.iter_mut().zip(blocked) {
            *g &= !b;
        }
        is_goal
    }

    /// What each lattice triangle is: removed (a blocked vertex), part of the goal's hole
    /// (kept, touching a goal vertex) or part of the local mesh.
    fn classify(&self, blocked: &[bool], is_goal: &[bool]) -> Vec<Kind> {
        (0..self.grid.triangle_count())
            .map(|tri| {
                let verts = self.grid.triangle_vertices(tri);
                if verts.iter().any(|&v| blocked[v]) {
                    Kind::Removed
                } else if verts.iter().any(|&v| is_goal[v]) {
                    Kind::Goal
                } else {
                    Kind::Mesh
                }
            })
            .collect()
    }

    /// The local mesh (the `Mesh` triangles, boundary edges tagged by what lies across them:
    /// goal hole, removed triangles, or the window's border) and the lattice-to-mesh vertex
    /// numbering (`u32::MAX` off the mesh).
    fn local_mesh(
        &self,
        window: &Window,
        kind: &[Kind],
    ) -> Result<(Arc<Mesh>, Vec<u32>), LatticeMiss> {
        let mut index = vec![u32::MAX; window.side * window.side];
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        let mut boundary = Vec::new();
        // Mesh number of each kept lattice triangle (the mesh keeps them in lattice order).
        let mut number = vec![NO_NEIGHBOR; kind.len()];
        for (tri, _) in kind.iter().enumerate().filter(|(_, k)| **k == Kind::Mesh) {
            number[tri] = triangles.len() as u32;
            let local = self.grid.triangle_vertices(tri).map(|v| {
                if index[v] == u32::MAX {
                    index[v] = vertices.len() as u32;
                    vertices.push(window.point(v));
                }
                index[v]
            });
            triangles.push(local);
        }
        let mut neighbors = Vec::with_capacity(triangles.len());
        for (tri, _) in kind.iter().enumerate().filter(|(_, k)| **k == Kind::Mesh) {
            let local = triangles[number[tri] as usize];
            let mut across = [NO_NEIGHBOR; 3];
            for (k, other) in self.grid.triangle_neighbors(tri).into_iter().enumerate() {
                let tag = match other.map(|u| kind[u]) {
                    Some(Kind::Mesh) => {
                        across[k] = other.map_or(NO_NEIGHBOR, |u| number[u]);
                        continue;
                    }
                    Some(Kind::Goal) => BoundaryTag::Goal(0),
                    Some(Kind::Removed) => BoundaryTag::Obstacle(0),
                    None => BoundaryTag::Wall,
                };
                boundary.push((local[(k + 1) % 3], local[(k + 2) % 3], tag));
            }
            neighbors.push(across);
        }
        // The lattice knows the adjacency: the mesh only checks it.
        let mesh = Mesh::from_parts_with_neighbors(vertices, triangles, neighbors, &boundary)
            .map_err(|_| LatticeMiss::Solve)?;
        Ok((Arc::new(mesh), index))
    }

    /// The local mesh's Dirichlet problem on the lattice. The unknowns are the kept mesh's
    /// interior vertices (5-point rows); every other vertex is held at its value (1 on the
    /// goal's boundary, else 0) and moves to the right-hand side, or is off the mesh.
    ///
    /// The unknowns are numbered in the kept minimum-degree order of an earlier window while it
    /// ranks at least 70 % of them ([`KeptOrder::order_for`]); otherwise in the lattice's
    /// nested-dissection order, and the solve computes a fresh minimum-degree order to keep.
    fn system(
        &self,
        mesh: &Mesh,
        index: &[u32],
        window: &Window,
    ) -> Result<LocalSystem, LatticeMiss> {
        let tags = mesh.vertex_tags();
        let roles: Vec<VertexRole> = index
            .iter()
            .map(|&m| match m {
                u32::MAX => VertexRole::Removed,
                m => match tags[m as usize] {
                    None => VertexRole::Unknown,
                    Some(BoundaryTag::Goal(_)) => VertexRole::Prescribed(1.0),
                    Some(_) => VertexRole::Prescribed(0.0),
                },
            })
            .collect();
        let unknown = |v: usize| roles[v] == VertexRole::Unknown;
        let kept = self.elimination.as_ref().and_then(|kept| {
            let vertices: Vec<usize> = (0..index.len()).filter(|&v| unknown(v)).collect();
            let keys: Vec<(i64, i64)> = vertices.iter().map(|&v| window.global(v)).collect();
            let neighbours = |k: usize| {
                let near = self.grid.vertex_neighbors(vertices[k]);
                near.map(|u| window.global(u))
            };
            let perm = kept.order_for(&keys, neighbours)?;
            Some(perm.into_iter().map(|k| vertices[k]).collect::<Vec<_>>())
        });
        let fresh_order = kept.is_none();
        let order =
            kept.unwrap_or_else(|| self.order.iter().copied().filter(|&v| unknown(v)).collect());
        let system = self
            .grid
            .system(&roles, Some(&order))
            .map_err(|_| LatticeMiss::Solve)?;
        let (matrix, rhs, lattice_vertex) = system.into_parts();
        let unknowns = lattice_vertex.iter().map(|&v| index[v]).collect();
        // ψ at the mesh's vertices: the held values now, the unknowns' after the solve.
        let mut psi = vec![0.0; mesh.vertices().len()];
        for (&k, role) in index.iter().zip(&roles) {
            if let VertexRole::Prescribed(value) = *role {
                psi[k as usize] = value;
            }
        }
        Ok(LocalSystem {
            matrix: (matrix.n() > 0).then_some(matrix),
            rhs,
            unknowns,
            lattice_vertex,
            fresh_order,
            psi,
        })
    }

    /// Where a path goes once it is in goal triangle `tri` (straight segments inside kept
    /// triangles): a point goal lying in this triangle; else the triangle's goal vertex
    /// nearest `from`, followed by a point goal whose triangle has that vertex.
    fn goal_targets(
        &self,
        tri: usize,
        from: [f64; 2],
        is_goal: &[bool],
        goals: &[LatticeGoal<'_>],
        window: &Window,
    ) -> Vec<Point> {
        let points = || {
            goals.iter().filter_map(|g| match g {
                LatticeGoal::Point(p) => Some(*p),
                _ => None,
            })
        };
        if let Some(p) = points().find(|&p| self.closed_triangle_holds(tri, window, p, 0.0)) {
            return vec![Point::new(p[0], p[1])];
        }
        let from = Point::new(from[0], from[1]);
        let distance = |v: usize| (window.point(v) - from).norm();
        let Some(v) = self
            .grid
            .triangle_vertices(tri)
            .into_iter()
            .filter(|&v| is_goal[v])
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
        else {
            return Vec::new();
        };
        let mut targets = vec![window.point(v)];
        let point_beyond = points().find(|&p| {
            self.triangle_at(p, window)
                .is_some_and(|t| self.grid.triangle_vertices(t).contains(&v))
        });
        if let Some(p) = point_beyond {
            targets.push(Point::new(p[0], p[1]));
        }
        targets
    }

    /// Whether the closed triangle `tri` holds `p`, with an orientation tolerance `tol`.
    fn closed_triangle_holds(&self, tri: usize, window: &Window, p: [f64; 2], tol: f64) -> bool {
        let [a, b, c] = self.grid.triangle_vertices(tri).map(|v| window.point(v));
        let p = Point::new(p[0], p[1]);
        [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, w)| harmonic_mesh::geom::twice_signed_area(u, w, p) >= -tol)
    }

    /// A goal triangle whose closure holds `p` (for a path ending exactly on a vertex).
    fn goal_triangle_touching(&self, p: Point, window: &Window, kind: &[Kind]) -> Option<usize> {
        let (gi0, gj0) = window.origin;
        let (ci, cj) = (
            (p.x / self.h - gi0 as f64).floor() as i64,
            (p.y / self.h - gj0 as f64).floor() as i64,
        );
        let cells = self.cells as i64;
        let tol = 1e-9 * self.h * self.h;
        (-1..=1)
            .flat_map(|dj| (-1..=1).map(move |di| (ci + di, cj + dj)))
            .filter(|&(i, j)| i >= 0 && j >= 0 && i < cells && j < cells)
            .flat_map(|(i, j)| {
                let lower = 2 * (j as usize * self.cells + i as usize);
                [lower, lower + 1]
            })
            .find(|&tri| {
                kind[tri] == Kind::Goal && self.closed_triangle_holds(tri, window, [p.x, p.y], tol)
            })
    }

    /// The lattice triangle of `window` holding `p`, if `p` is in the window.
    fn triangle_at(&self, p: [f64; 2], window: &Window) -> Option<usize> {
        let (gi0, gj0) = window.origin;
        let (x, y) = (p[0] / self.h - gi0 as f64, p[1] / self.h - gj0 as f64);
        self.grid.triangle_at(x, y)
    }
}

/// The Dirichlet problem of one local mesh on the lattice (see [`Lattice::system`]).
struct LocalSystem {
    /// The unknowns' M-matrix (`None` when the mesh has no interior vertex).
    matrix: Option<MMatrix>,
    /// Its right-hand side: the held neighbours' values.
    rhs: Vec<f64>,
    /// The mesh vertex of each unknown.
    unknowns: Vec<u32>,
    /// The window's lattice vertex of each unknown.
    lattice_vertex: Vec<usize>,
    /// Whether the unknowns still need a minimum-degree order (else they are numbered in a
    /// kept one).
    fresh_order: bool,
    /// ψ at the mesh's vertices, the unknowns' entries still to be solved for.
    psi: Vec<f64>,
}

impl LocalSystem {
    /// Factors with the M-matrix LDLᵀ of `harmonic-solver`, whose far-field ψ keeps its
    /// relative accuracy, and solves: ψ at the mesh's vertices, and the window's lattice
    /// vertices in the minimum-degree order computed here if the system needed one.
    fn solve(mut self) -> Result<(Vec<f64>, Option<Vec<usize>>), LatticeMiss> {
        let mut fresh = None;
        if let Some(matrix) = &self.matrix {
            let ordering = if self.fresh_order {
                Ordering::Amd
            } else {
                Ordering::Natural
            };
            let factor = AccurateLdlt::factor(matrix, ordering).map_err(|_| LatticeMiss::Solve)?;
            factor
                .solve_in_place(&mut self.rhs)
                .map_err(|_| LatticeMiss::Solve)?;
            if self.fresh_order {
                let perm = factor.permutation();
                fresh = Some(perm.iter().map(|&k| self.lattice_vertex[k]).collect());
            }
        }
        for (&k, &value) in self.unknowns.iter().zip(&self.rhs) {
            self.psi[k as usize] = value;
        }
        Ok((self.psi, fresh))
    }
}

/// One window of the lattice: where its lower-left vertex is on the world-fixed grid.
#[derive(Clone, Copy, Debug)]
struct Window {
    /// Global lattice index of the lower-left vertex.
    origin: (i64, i64),
    /// Vertices per side.
    side: usize,
    /// Cell side.
    h: f64,
}

impl Window {
    /// Global lattice index of window vertex `v`.
    fn global(&self, v: usize) -> (i64, i64) {
        (
            self.origin.0 + (v % self.side) as i64,
            self.origin.1 + (v / self.side) as i64,
        )
    }

    /// Position of window vertex `v` (numbered row by row from the lower left).
    fn at(&self, v: usize) -> [f64; 2] {
        [
            (self.origin.0 + (v % self.side) as i64) as f64 * self.h,
            (self.origin.1 + (v / self.side) as i64) as f64 * self.h,
        ]
    }

    /// [`Window::at`] as a point.
    fn point(&self, v: usize) -> Point {
        let [x, y] = self.at(v);
        Point::new(x, y)
    }
}

/// What a lattice triangle is in one replan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A vertex is blocked.
    Removed,
    /// Kept, touching a goal vertex: part of the goal's hole.
    Goal,
    /// Kept: part of the local mesh.
    Mesh,
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_fem::interior_local_extrema;
    use harmonic_fem::{BoundaryConditions, solve_potential};
    use harmonic_planner::Scene;

    /// A 6 × 4 room with a post; the lattice is the 10 cm one of the paper, 4 m wide around the
    /// robot, the goal at (3.8, 2) inside it.
    fn room() -> Domain {
        let scene = Scene::from_json(
            r#"{
                "workspace": [[0, 0], [6, 0], [6, 4], [0, 4]],
                "obstacles": [{"polygon": [[2.6, 2.6], [3.0, 2.6], [3.0, 4.0], [2.6, 4.0]]}],
                "goal": {"circle": {"center": [5.5, 2.0], "radius": 0.12}},
                "mesh": {"max_area": 0.02}
            }"#,
        )
        .expect("valid scene");
        Domain::new(&scene.domain_spec(), &scene.mesh_options()).expect("valid domain")
    }

    /// A sensed box in the window, between the robot's start and the goal.
    const BOX: [[f64; 2]; 4] = [[2.9, 1.5], [3.3, 1.5], [3.3, 2.3], [2.9, 2.3]];

    /// A lattice replan in [`room`] from `robot` with [`BOX`] sensed, the goal a disc at (3.8, 2).
    fn plan(lattice: &mut Lattice, robot: [f64; 2]) -> Result<LatticePlan, LatticeMiss> {
        let goal = [LatticeGoal::Circle {
            center: [3.8, 2.0],
            radius: 0.12,
        }];
        lattice.plan(&room(), robot, &[&BOX[..]], &goal)
    }

    #[test]
    fn the_lattice_potential_is_the_fem_solution_on_the_kept_mesh() {
        let mut lattice = Lattice::new(0.1, 40, 0.0, Vec::new());
        let plan = plan(&mut lattice, [2.0, 2.0]).expect("the lattice serves this window");
        assert_eq!(plan.path.status, TraceStatus::ReachedGoal(0));
        let potential = plan.potential.expect("a potential");
        let mesh = Arc::clone(potential.mesh());
        // The same Dirichlet problem assembled from the mesh by the FEM crate.
        let fem =
            solve_potential(Arc::clone(&mesh), &BoundaryConditions::default()).expect("FEM solve");
        let worst = potential
            .psi()
            .iter()
            .zip(fem.psi())
            .map(|(a, b)| (a - b).abs() / b.abs().max(1e-300))
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "relative difference {worst:e}");
        assert_eq!(interior_local_extrema(&mesh, potential.psi()).minima, 0);
        // Triangles cut out around the box and the post: fewer than the full 3200.
        assert!(
            plan.triangles < 3200 && plan.triangles > 2500,
            "{}",
            plan.triangles
        );
    }

    #[test]
    fn paths_keep_clear_of_known_and_sensed_obstacles() {
        let mut lattice = Lattice::new(0.1, 40, 0.0, Vec::new());
        let domain = room();
        for robot in [[2.0, 2.0], [2.4, 1.0], [2.3, 3.0], [2.2, 0.5]] {
            let plan = plan(&mut lattice, robot).expect("the lattice serves this window");
            assert_eq!(plan.path.status, TraceStatus::ReachedGoal(0), "{robot:?}");
            for w in plan.path.points.windows(2) {
                assert!(domain.segment_clearance(w[0], w[1]) > 0.0, "{robot:?}");
                // Whole segments, not just their ends, keep off the sensed box.
                let (a, b) = ([w[0].x, w[0].y], [w[1].x, w[1].y]);
                let d = harmonic_mesh::geom::segment_polygon_distance(a, b, &BOX);
                assert!(d > 0.0, "{robot:?}: {a:?}-{b:?}");
            }
            // The path ends in the goal disc.
            let end = plan.path.points.last().expect("points");
            assert!(
                (end - Point::new(3.8, 2.0)).norm() <= 0.12 + 1e-12,
                "{end:?}"
            );
        }
    }

    #[test]
    fn a_replan_does_not_depend_on_earlier_ones() {
        let mut reused = Lattice::new(0.1, 40, 0.0, Vec::new());
        plan(&mut reused, [1.9, 1.2]).expect("first replan");
        let again = plan(&mut reused, [2.0, 2.0]).expect("second replan");
        let fresh = plan(&mut Lattice::new(0.1, 40, 0.0, Vec::new()), [2.0, 2.0]).expect("fresh");
        // The second replan numbers its unknowns by the first one's elimination order, the
        // fresh one by its own: the same ψ and path up to rounding.
        let (a, b) = (again.potential.expect("ψ"), fresh.potential.expect("ψ"));
        for (x, y) in a.psi().iter().zip(b.psi()) {
            assert!((x - y).abs() <= 1e-12 * y.abs(), "{x} vs {y}");
        }
        assert_eq!(again.path.points.len(), fresh.path.points.len());
        for (p, q) in again.path.points.iter().zip(&fresh.path.points) {
            assert!((p - q).norm() < 1e-9, "{p} vs {q}");
        }
    }

    #[test]
    fn misses_are_reported_not_papered_over() {
        let mut lattice = Lattice::new(0.1, 40, 0.0, Vec::new());
        // Within the lattice's margin of the box.
        assert_eq!(
            plan(&mut lattice, [2.85, 2.0]).err(),
            Some(LatticeMiss::RobotBlocked)
        );
        // A goal inside the box has no free vertex.
        let goal = [LatticeGoal::Point([3.1, 1.9])];
        assert_eq!(
            lattice.plan(&room(), [2.0, 2.0], &[&BOX[..]], &goal).err(),
            Some(LatticeMiss::NoGoalVertex)
        );
    }

    #[test]
    fn point_goals_are_reached_exactly() {
        let mut lattice = Lattice::new(0.1, 40, 0.0, Vec::new());
        let goal = [LatticeGoal::Point([3.73, 2.47])];
        let plan = lattice
            .plan(&room(), [2.0, 2.0], &[&BOX[..]], &goal)
            .expect("the lattice serves this window");
        assert_eq!(plan.path.status, TraceStatus::ReachedGoal(0));
        assert_eq!(plan.path.points.last(), Some(&Point::new(3.73, 2.47)));
    }
}
