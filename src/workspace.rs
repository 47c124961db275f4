//! A map or scene kept in memory with its walls factored once: any goal, later, by a few
//! solves.
//!
//! [`Workspace::new`] meshes a scene's free space without its goals, assembles the walls'
//! conditions and factors that system once ([`harmonic_fem::GoalSolver`]). A goal is then a
//! set of mesh vertices held at the goal's value: [`Workspace::planner`] gives a
//! [`Planner`] for it — the same queries, tracers, reports and pictures as a planner built
//! with the goal in its mesh — at the cost of a blocked triangular solve instead of a new
//! mesh and a new factorisation. Several goals at once come two ways:
//! [`Workspace::planners`] (independent goals, their columns solved together) and
//! [`Workspace::planner_for_any`] (one field whose goal is the set: a robot goes to whichever
//! the potential leads it to).
//!
//! ```
//! use harmonic_planner::{Goal, Point, Scene, Workspace};
//! let scene = Scene::from_json(r#"{
//!     "workspace": [[0, 0], [4, 0], [4, 4], [0, 4]],
//!     "obstacles": [{"polygon": [[1.5, 1], [2.5, 1], [2.5, 3], [1.5, 3]]}],
//!     "goal": {"point": [3.5, 2]},
//!     "mesh": {"max_area": 0.01}
//! }"#)?;
//! let workspace = Workspace::new(&scene)?;
//! for at in [Point::new(3.5, 2.0), Point::new(0.5, 3.5), Point::new(2.0, 0.5)] {
//!     let planner = workspace.planner(&Goal::point(at))?;
//!     let path = planner.plan([0.5, 0.5]);
//!     assert!(path.status.reached_goal());
//!     assert_eq!(*path.points.last().unwrap(), [at.x, at.y]); // ends on the goal point
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;
use std::time::Instant;

use harmonic_fem::{Assembler, AssemblyOptions, GoalReport, GoalSolver, SolveMethod};
use harmonic_mesh::{Domain, DomainSpec, Mesh, NO_NEIGHBOR, Point};
use harmonic_trajectory::NOT_A_GOAL;
use serde::Serialize;

use crate::planner::{
    Entry, MeshSummary, Meshed, PathSummary, PlanError, PlannedPath, Planner, PlannerOptions,
    PotentialSummary, Solved, Stage, VertexGoals,
};
use crate::scene::Scene;

/// A goal for a [`Workspace`]: mesh vertices to hold at the goal's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Goal {
    /// A point of free space: the free vertices of the triangle holding it, and every free
    /// vertex within `radius` of it. A path ends exactly on the point.
    Point {
        /// The goal point.
        at: Point,
        /// Also hold the vertices this close to `at` (0: only the triangle's).
        radius: f64,
    },
    /// A region given as its mesh vertices (a path ends on one of them).
    Vertices(Vec<u32>),
}

impl Goal {
    /// The point goal at `at` (the triangle holding it).
    pub fn point(at: impl Into<Point>) -> Goal {
        Goal::Point {
            at: at.into(),
            radius: 0.0,
        }
    }
}

/// Why a [`Goal`] cannot be used on a workspace.
#[derive(Debug, thiserror::Error)]
pub enum GoalError {
    /// A goal point that is not a finite point, or a negative or non-finite radius.
    #[error("goal {goal}: ({x}, {y}) with radius {radius} is not a finite point with a radius ≥ 0")]
    NotFinite {
        /// The goal's index in the request.
        goal: usize,
        /// The point.
        x: f64,
        /// The point.
        y: f64,
        /// The radius.
        radius: f64,
    },
    /// A goal point outside the mesh of free space (in an obstacle, within the robot's radius
    /// of one, beyond the walls, or in a part of the map that was not traced).
    #[error(
        "goal {goal}: ({x}, {y}) is not in the free space of this workspace (in an obstacle, within the robot's radius of one, or outside the walls)"
    )]
    OutsideFreeSpace {
        /// The goal's index in the request.
        goal: usize,
        /// The point.
        x: f64,
        /// The point.
        y: f64,
    },
    /// Every vertex near the goal point lies on a wall held at its own value.
    #[error(
        "goal {goal}: every mesh vertex near ({x}, {y}) lies on a wall, so nothing can be held at the goal's value there; move the goal away from the wall or refine the mesh"
    )]
    OnTheWall {
        /// The goal's index in the request.
        goal: usize,
        /// The point.
        x: f64,
        /// The point.
        y: f64,
    },
    /// A vertex index beyond the mesh.
    #[error("goal {goal}: vertex {vertex} is not a vertex of the mesh ({count} vertices)")]
    NoSuchVertex {
        /// The goal's index in the request.
        goal: usize,
        /// The vertex.
        vertex: u32,
        /// The mesh's vertex count.
        count: usize,
    },
    /// No goal was given.
    #[error("no goal given")]
    NoGoal,
}

/// Wall-clock time of a workspace's stages, in milliseconds.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct WorkspaceTimings {
    /// Validating the scene and meshing its free space.
    pub mesh: f64,
    /// Assembling the walls' system.
    pub assemble: f64,
    /// Ordering and factoring it (once for every goal).
    pub factor: f64,
}

/// A scene's free space meshed and its walls' system factored once; goals come later.
pub struct Workspace {
    meshed: Meshed,
    goals: GoalSolver,
    timings: WorkspaceTimings,
    /// A way into the mesh for starts outside it and the tracer's tolerance, given to every
    /// planner (a map's clear cells).
    entry: Option<Entry>,
}

impl std::fmt::Debug for Workspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Workspace")
            .field("triangles", &self.meshed.mesh.triangles().len())
            .field("goals", &self.goals)
            .finish_non_exhaustive()
    }
}

fn millis(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

impl Workspace {
    /// Meshes `scene`'s free space without its goals (they are ignored: goals come later,
    /// from [`Workspace::planner`]), assembles its walls and obstacles under the scene's
    /// conditions and factors the system once. The goals' condition must be Dirichlet (the
    /// default φ = 0); walls and obstacles may be Dirichlet, Robin or Neumann as long as some
    /// part holds the potential (see [`harmonic_fem::GoalSolver`]).
    pub fn new(scene: &Scene) -> Result<Workspace, PlanError> {
        Workspace::with_options(scene, &PlannerOptions::default())
    }

    /// [`Workspace::new`] with options (a stage observer).
    pub fn with_options(scene: &Scene, options: &PlannerOptions) -> Result<Workspace, PlanError> {
        options.stage(Stage::Meshing)?;
        let spec = DomainSpec {
            goals: Vec::new(),
            ..scene.domain_spec()
        };
        let meshed = Meshed::new(scene, &spec)?;
        Workspace::factored(meshed, &scene.boundary_conditions(), options, None)
    }

    /// A workspace on a mesh made elsewhere (Triangle, gmsh; see [`crate::inputs`]): every
    /// boundary edge is held at the walls' value φ = 1 (whatever its tag), goals come later
    /// as points or vertices.
    pub fn from_mesh(mesh: Mesh, options: &PlannerOptions) -> Result<Workspace, PlanError> {
        options.stage(Stage::Meshing)?;
        let meshed = Meshed::of_mesh(mesh)?;
        Workspace::factored(
            meshed,
            &harmonic_fem::BoundaryConditions::default(),
            options,
            None,
        )
    }

    /// Assembles the walls' system of `meshed` under `bcs` and factors it; a map's `entry`
    /// goes into every planner made from it.
    pub(crate) fn factored(
        meshed: Meshed,
        bcs: &harmonic_fem::BoundaryConditions,
        options: &PlannerOptions,
        entry: Option<Entry>,
    ) -> Result<Workspace, PlanError> {
        if options.multigrid.unwrap_or(0) > 0 {
            // New goals reuse one factorisation; a multigrid solve keeps none.
            return Err(PlanError::MultigridUnsupported {
                what: "a workspace of many goals",
            });
        }
        options.stage(Stage::Assembling)?;
        let t = Instant::now();
        let bcs = bcs.clone();
        let assembler = Assembler::new(Arc::clone(&meshed.mesh), &bcs, AssemblyOptions::default())?;
        let assemble_ms = millis(t);

        options.stage(Stage::Solving)?;
        let t = Instant::now();
        let goals = GoalSolver::new(&assembler, &bcs, SolveMethod::Auto)?;
        let factor_ms = millis(t);
        options.stage(Stage::Done)?;

        Ok(Workspace {
            timings: WorkspaceTimings {
                mesh: meshed.ms,
                assemble: assemble_ms,
                factor: factor_ms,
            },
            meshed,
            goals,
            entry,
        })
    }

    /// The mesh of free space (no goal in it).
    pub fn mesh(&self) -> &Mesh {
        &self.meshed.mesh
    }

    /// The validated free space.
    pub fn domain(&self) -> &Domain {
        &self.meshed.domain
    }

    /// Time spent meshing, assembling and factoring.
    pub fn timings(&self) -> WorkspaceTimings {
        self.timings
    }

    /// The kept factorisation: accurate (M-matrix LDLᵀ) or Cholesky.
    pub fn method(&self) -> SolveMethod {
        self.goals.method()
    }

    /// The mesh vertices `goal` holds (goal `index` of a request, for error messages).
    pub fn goal_vertices(&self, goal: &Goal, index: usize) -> Result<Vec<u32>, GoalError> {
        let mesh = &self.meshed.mesh;
        let system = self.goals.system();
        let free = |v: u32| system.unknown_of(v).is_some();
        match goal {
            Goal::Vertices(vs) => {
                if let Some(&v) = vs.iter().find(|&&v| v as usize >= mesh.vertices().len()) {
                    return Err(GoalError::NoSuchVertex {
                        goal: index,
                        vertex: v,
                        count: mesh.vertices().len(),
                    });
                }
                Ok(vs.clone())
            }
            &Goal::Point { at, radius } => {
                if !(at.x.is_finite() && at.y.is_finite() && radius.is_finite() && radius >= 0.0) {
                    return Err(GoalError::NotFinite {
                        goal: index,
                        x: at.x,
                        y: at.y,
                        radius,
                    });
                }
                let t = mesh.locate(at, None).ok_or(GoalError::OutsideFreeSpace {
                    goal: index,
                    x: at.x,
                    y: at.y,
                })?;
                let mut held: Vec<u32> = mesh.triangles()[t as usize]
                    .into_iter()
                    .filter(|&v| free(v))
                    .collect();
                if radius > 0.0 {
                    held.extend(self.vertices_within(t, at, radius).filter(|&v| free(v)));
                }
                if held.is_empty() {
                    // A triangle with all three vertices on walls (a narrow passage): its
                    // neighbours' free vertices instead.
                    held.extend(
                        mesh.neighbors()[t as usize]
                            .into_iter()
                            .filter(|&n| n != NO_NEIGHBOR)
                            .flat_map(|n| mesh.triangles()[n as usize])
                            .filter(|&v| free(v)),
                    );
                }
                held.sort_unstable();
                held.dedup();
                if held.is_empty() {
                    return Err(GoalError::OnTheWall {
                        goal: index,
                        x: at.x,
                        y: at.y,
                    });
                }
                Ok(held)
            }
        }
    }

    /// The vertices within `radius` of `at`, found by growing from triangle `t` across
    /// triangles that come within the radius.
    fn vertices_within(&self, t: u32, at: Point, radius: f64) -> impl Iterator<Item = u32> {
        let mesh = &self.meshed.mesh;
        let mut seen = std::collections::HashSet::from([t]);
        let mut stack = vec![t];
        let mut found = Vec::new();
        while let Some(u) = stack.pop() {
            for v in mesh.triangles()[u as usize] {
                if (mesh.vertices()[v as usize] - at).norm() <= radius {
                    found.push(v);
                }
            }
            for n in mesh.neighbors()[u as usize] {
                if n != NO_NEIGHBOR && triangle_near(mesh, n, at, radius) && seen.insert(n) {
                    stack.push(n);
                }
            }
        }
        found.into_iter()
    }

    /// A planner for `goal`: its field by a blocked solve against the kept factor.
    pub fn planner(&self, goal: &Goal) -> Result<Planner, PlanError> {
        Ok(self
            .planners(std::slice::from_ref(goal))?
            .pop()
            .expect("one planner per goal"))
    }

    /// One planner per goal, the goals independent, their columns solved together.
    pub fn planners(&self, goals: &[Goal]) -> Result<Vec<Planner>, PlanError> {
        let t = Instant::now();
        let held = goals
            .iter()
            .enumerate()
            .map(|(i, g)| self.goal_vertices(g, i))
            .collect::<Result<Vec<_>, _>>()?;
        let solutions = self.goals.solve(&held)?;
        let share = millis(t) / goals.len().max(1) as f64;
        solutions
            .into_iter()
            .zip(goals.iter().zip(&held))
            .map(|(solution, (goal, held))| {
                let marks = self.marks(&[(goal, held)], solution.report);
                self.goal_planner(solution.psi, marks, share, Instant::now())
            })
            .collect()
    }

    /// One planner whose goal is the whole set `goals` (goal `j` of its paths is `goals[j]`).
    pub fn planner_for_any(&self, goals: &[Goal]) -> Result<Planner, PlanError> {
        if goals.is_empty() {
            return Err(GoalError::NoGoal.into());
        }
        let t = Instant::now();
        let held = goals
            .iter()
            .enumerate()
            .map(|(i, g)| self.goal_vertices(g, i))
            .collect::<Result<Vec<_>, _>>()?;
        let all: Vec<u32> = held.iter().flatten().copied().collect();
        let solution = self.goals.solve(&[all])?.remove(0);
        let pairs: Vec<_> = goals.iter().zip(&held).collect();
        let marks = self.marks(&pairs, solution.report);
        self.goal_planner(solution.psi, marks, 0.0, t)
    }

    /// The planner for `goal` from a fresh factorisation of the system with the same vertices
    /// held (no kept factor used): what [`Workspace::planner`] must match, for checks.
    pub fn fresh_planner(&self, goal: &Goal) -> Result<Planner, PlanError> {
        let t = Instant::now();
        let held = self.goal_vertices(goal, 0)?;
        let psi = self.goals.solve_fresh(&held)?;
        let report = GoalReport {
            held: held.len(),
            columns: 0,
            method: self.goals.method(),
            entrywise_accurate: self.goals.method() == SolveMethod::Accurate,
        };
        let marks = self.marks(&[(goal, &held)], report);
        self.goal_planner(psi, marks, 0.0, t)
    }

    /// The per-vertex goal marks, end points and markers of some goals, with how their
    /// field was solved.
    fn marks(&self, goals: &[(&Goal, &Vec<u32>)], report: GoalReport) -> VertexGoals {
        let mut goal_of = vec![NOT_A_GOAL; self.meshed.mesh.vertices().len()];
        let mut ends = Vec::with_capacity(goals.len());
        let mut markers = Vec::with_capacity(goals.len());
        for (j, (goal, held)) in goals.iter().enumerate() {
            for &v in held.iter() {
                if goal_of[v as usize] == NOT_A_GOAL {
                    goal_of[v as usize] = j as u32;
                }
            }
            let end = match goal {
                Goal::Point { at, .. } => Some(*at),
                Goal::Vertices(_) => None,
            };
            ends.push(end);
            let centroid = held
                .iter()
                .map(|&v| self.meshed.mesh.vertices()[v as usize].coords)
                .sum::<harmonic_mesh::Vector>()
                / held.len().max(1) as f64;
            markers.push(end.unwrap_or(Point::from(centroid)));
        }
        VertexGoals {
            goal_of,
            ends,
            markers,
            report: Some(report),
        }
    }

    /// A planner on this workspace's mesh with ψ given. Its timings are only its goal's
    /// solve (`solve_ms_before`, then since `started`, the gradient recovery included):
    /// meshing, assembly and the factorisation are the workspace's.
    fn goal_planner(
        &self,
        psi: Vec<f64>,
        marks: VertexGoals,
        solve_ms_before: f64,
        started: Instant,
    ) -> Result<Planner, PlanError> {
        let potential = self.goals.potential_of(psi)?;
        let solved = Solved {
            by: "goal superposition",
            mesh_ms: 0.0,
            assemble_ms: 0.0,
            solve_ms_before,
            started,
        };
        Planner::assembled(
            &self.meshed,
            potential,
            solved,
            Some(marks),
            self.entry.as_ref(),
        )
    }
}

/// Whether triangle `t` comes within `radius` of `at` (its closest point, exactly).
fn triangle_near(mesh: &Mesh, t: u32, at: Point, radius: f64) -> bool {
    let [a, b, c] = mesh.triangle_points(t);
    if mesh.triangle_contains(t, at) {
        return true;
    }
    [(a, b), (b, c), (c, a)]
        .into_iter()
        .any(|(p, q)| harmonic_mesh::geom::point_segment_distance(at, p, q) <= radius)
}

/// What `hplan plan` prints for several goals on one workspace.
#[derive(Clone, Debug, Serialize)]
pub struct GoalsReport {
    /// The workspace's mesh.
    pub mesh: MeshSummary,
    /// The workspace's stages (once for every goal), in milliseconds.
    pub timings_ms: WorkspaceTimings,
    /// The kept factorisation: `accurate` or `cholesky`.
    pub method: &'static str,
    /// One entry per goal, in the order given.
    pub goals: Vec<GoalRun>,
}

/// One goal of a [`GoalsReport`].
#[derive(Clone, Debug, Serialize)]
pub struct GoalRun {
    /// The goal point `[x, y]`.
    pub goal: [f64; 2],
    /// Mesh vertices held at the goal's value.
    pub held_vertices: usize,
    /// Whether ψ is accurate entrywise (see [`harmonic_fem::GoalReport`]).
    pub entrywise_accurate: bool,
    /// This goal's own time: its share of the blocked solve with its gradient recovery
    /// (`solve`) and its paths (`trace`), in milliseconds.
    pub timings_ms: GoalTimings,
    /// The goal's field.
    pub potential: PotentialSummary,
    /// One entry per start, in the order given.
    pub paths: Vec<PlannedPath>,
}

/// A goal's own time, in milliseconds.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct GoalTimings {
    /// Its field: its share of the blocked solve and the gradient recovery.
    pub solve: f64,
    /// Its paths.
    pub trace: f64,
}

impl Workspace {
    /// Solves every goal point (together, block by block) and plans each one's starts:
    /// what `hplan plan --goal X,Y --goal X,Y ...` prints. Also returns the planners (for
    /// pictures).
    pub fn report(
        &self,
        goals: &[(Point, Vec<[f64; 2]>)],
    ) -> Result<(GoalsReport, Vec<Planner>), PlanError> {
        let specs: Vec<Goal> = goals.iter().map(|(g, _)| Goal::point(*g)).collect();
        let planners = self.planners(&specs)?;
        let runs = planners
            .iter()
            .zip(goals)
            .map(|(planner, (goal, starts))| {
                let report = planner.plan_report(starts);
                let goal_report = planner.goal_report();
                GoalRun {
                    goal: [goal.x, goal.y],
                    held_vertices: goal_report.map_or(0, |r| r.held),
                    entrywise_accurate: goal_report.is_some_and(|r| r.entrywise_accurate),
                    timings_ms: GoalTimings {
                        solve: report.timings_ms.solve,
                        trace: report.timings_ms.trace,
                    },
                    potential: report.potential,
                    paths: report.paths,
                }
            })
            .collect();
        let mesh = match planners.first() {
            Some(p) => p.summaries().0,
            None => return Err(GoalError::NoGoal.into()),
        };
        let method = match self.method() {
            SolveMethod::Accurate => "accurate",
            _ => "cholesky",
        };
        Ok((
            GoalsReport {
                mesh,
                timings_ms: self.timings,
                method,
                goals: runs,
            },
            planners,
        ))
    }
}

impl GoalsReport {
    /// A human-readable summary: the workspace, then each goal and its paths.
    pub fn summary(&self) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let t = &self.timings_ms;
        let _ = writeln!(s, "{}", self.mesh);
        let _ = writeln!(
            s,
            "workspace: mesh {:.1} ms, assemble {:.1} ms, factor {:.1} ms ({}), once for {} goals",
            t.mesh,
            t.assemble,
            t.factor,
            self.method,
            self.goals.len()
        );
        for g in &self.goals {
            let _ = writeln!(
                s,
                "goal ({}, {}): {} vertices held, solve {:.1} ms, trace {:.1} ms, interior local minima {}",
                g.goal[0],
                g.goal[1],
                g.held_vertices,
                g.timings_ms.solve,
                g.timings_ms.trace,
                g.potential.interior_local_minima
            );
            for p in &g.paths {
                let _ = writeln!(s, "  {}", p.line());
            }
        }
        s
    }
}
