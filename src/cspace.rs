//! Robots that are not discs, planned in their configuration space: a rigid polygon in
//! (x, y, θ) and a planar arm of two or three links in its joint angles. The scene's
//! `"robot"` has a `"polygon"` or an `"arm"` (`AnyScene::Config`); the free configuration
//! space is meshed by `harmonic_cspace` (periodic isosurface stuffing from exact parry2d
//! distances), solved with the volume FEM on the slab of one period with its ends identified
//! (`harmonic_fem::volume::solve_periodic_for_planning`), and traced by the volume tracers on
//! a covering of three periods, so that angles come out continuous.
//!
//! ```
//! use harmonic_planner::cspace::{ConfigPlanner, parse_config_scene};
//! let scene = parse_config_scene(r#"{
//!     "workspace": [[0, 0], [6, 0], [6, 4], [0, 4]],
//!     "obstacles": [{"polygon": [[2.8, 0], [3.2, 0], [3.2, 1.5], [2.8, 1.5]]},
//!                   {"polygon": [[2.8, 2.5], [3.2, 2.5], [3.2, 4], [2.8, 4]]}],
//!     "robot": {"polygon": [[-0.7, -0.1], [0.7, -0.1], [0.7, 0.1], [-0.7, 0.1]]},
//!     "goal": {"pose": [5.0, 2.0, 0.0], "tolerance": {"position": 0.3, "angle": 0.4}},
//!     "starts": [[1.0, 2.0, 1.5708]],
//!     "mesh": {"spacing": 0.2, "margin": 0.03}
//! }"#)?;
//! let planner = ConfigPlanner::new(&scene)?;
//! let path = planner.plan(&[1.0, 2.0, 1.5708]);
//! assert!(path.status.reached_goal());
//! // The bar turns to pass the door (1 wide, the bar 1.4 long).
//! let poses = path.poses.as_ref().unwrap();
//! let door = poses.iter().find(|p| (p[0] - 3.0).abs() < 0.05).unwrap();
//! assert!(door[2].cos().abs() > 0.7);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;
use std::time::Instant;

use harmonic_cspace::check::{check_path, exact_clearance};
use harmonic_cspace::svg::{MotionSvgOptions, motion_svg};
use harmonic_cspace::{
    ConfigClass, ConfigGoal, ConfigSpace, CspaceMeshReport, DEFAULT_MAX_TETRAHEDRA, EXTRUDE_PART,
    Robot,
};
use harmonic_fem::volume::{
    VolumePotential, assemble_periodic_for_planning, solve_folded_for_planning,
};
use harmonic_trajectory::volume::{
    ExactVolumeOptions, P1VolumeField, VolumeFieldParts, VolumeFieldTopology, trace_exact_volume,
};
use harmonic_trajectory::{Locate, Path, SmoothOptions, TraceStatus, Tracer, trace_smooth};
use harmonic_volume::{BoundaryTag, PeriodicMesh, Point, TetMesh, dihedral_range};
use rayon::prelude::*;
use serde::Serialize;

use crate::PlanError;
use crate::planner::{PathSummary, Report, Timings, finite_or_zero};
pub use crate::scene::config::{
    ArmSpec, ConfigGoalSpec, ConfigMeshSpec, ConfigRobotSpec, ConfigScene, ToleranceSpec,
    parse_config_scene,
};

/// One planned motion, as `hplan plan --json` prints it.
#[derive(Clone, Debug, Serialize)]
pub struct ConfigPlannedPath {
    /// The start configuration.
    pub start: Vec<f64>,
    /// How the path ended (`reached_goal`, `unreachable`, `stalled`, `start_in_obstacle`,
    /// `outside_workspace`, `max_steps`).
    pub status: TraceStatus<Point>,
    /// For a start in collision: with what (`"obstacle 2"`, `"the workspace boundary"`,
    /// `"itself (links 0 and 2)"`), the margin counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blocked_by: Option<String>,
    /// Which tracer made it.
    pub tracer: Tracer,
    /// Length in configuration space, in its scaled metric (θ times the radius of gyration,
    /// joint i times its reach), the unit of the scene.
    pub length: f64,
    /// Smallest exact clearance of the robot at the path's entries (polygons, not the mesh).
    pub min_clearance: f64,
    /// Smallest |∇φ| met.
    pub min_gradient: f64,
    /// A rigid robot's poses `[x, y, θ]` (θ continuous, not wrapped).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub poses: Option<Vec<[f64; 3]>>,
    /// An arm's joints `[q1, …]` (continuous).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joints: Option<Vec<Vec<f64>>>,
}

impl ConfigPlannedPath {
    /// The path's configurations.
    pub fn configurations(&self) -> Vec<Vec<f64>> {
        match (&self.poses, &self.joints) {
            (Some(p), _) => p.iter().map(|q| q.to_vec()).collect(),
            (None, Some(j)) => j.clone(),
            _ => Vec::new(),
        }
    }
}

/// The mesh part of a configuration-space report.
#[derive(Clone, Debug, Serialize)]
pub struct ConfigMeshSummary {
    /// Slab vertices (one period).
    pub vertices: usize,
    /// Slab tetrahedra.
    pub tetrahedra: usize,
    /// Unknowns of the folded (periodic) system.
    pub unknowns: usize,
    /// Covering tetrahedra (three periods along each periodic axis).
    pub covering_tetrahedra: usize,
    /// Smallest dihedral angle (slab), degrees.
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle (slab), degrees.
    pub max_dihedral_deg: f64,
    /// Lattice spacing.
    pub spacing: f64,
    /// Scale of each coordinate.
    pub scale: [f64; 3],
    /// Lattice cells per turn along periodic axes.
    pub cells: [Option<usize>; 3],
    /// Slab end faces identified.
    pub seam_faces: usize,
    /// Lattice edges bisected where its vertices missed a sliver of collision.
    pub graded: usize,
    /// Safety margin ε.
    pub margin: f64,
    /// Edges clamped by the planning solve.
    pub clamped_edges: usize,
    /// Configurations the mesh was graded finer around, where a motion from a start met an
    /// obstacle's image that the mesh before cut across (0: one build sufficed).
    pub refined_near: usize,
}

/// The report of `hplan plan` on a configuration-space scene (`configuration`: `"pose"` or
/// `"joints"`).
pub type ConfigPlanReport = Report<ConfigPlannedPath, ConfigMeshSummary>;

impl std::fmt::Display for ConfigMeshSummary {
    /// `configuration space: … vertices, … tetrahedra per period (… unknowns), spacing …`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "configuration space: {} vertices, {} tetrahedra per period ({} unknowns), spacing {}, margin {}",
            self.vertices, self.tetrahedra, self.unknowns, self.spacing, self.margin
        )
    }
}

impl PathSummary for ConfigPlannedPath {
    /// `[start]: status (collides with …), length …, clearance …, end […]`.
    fn line(&self) -> String {
        let end = self.configurations().last().cloned().unwrap_or_default();
        let blocked = self
            .blocked_by
            .as_ref()
            .map(|b| format!(" (collides with {b})"))
            .unwrap_or_default();
        format!(
            "{:?}: {}{blocked}, length {:.3}, clearance {:.3}, end {:?}",
            self.start,
            self.status.as_str(),
            self.length + 0.0, // no "-0.000"
            self.min_clearance,
            end.iter()
                .map(|v| (v * 1e3).round() / 1e3)
                .collect::<Vec<_>>()
        )
    }
}

/// A harmonic planner in a robot's configuration space: built once, queried many times.
pub struct ConfigPlanner {
    space: ConfigSpace,
    slab: Arc<TetMesh>,
    covering: Arc<TetMesh>,
    potential: VolumePotential,
    field: Arc<VolumeFieldParts>,
    report: CspaceMeshReport,
    unknowns: usize,
    clamped_edges: usize,
    /// What produced ψ (`potential.solved_by`).
    solved_by: &'static str,
    timings: Timings,
    scale: f64,
    size: f64,
    /// Configurations the mesh was graded finer around ([`ConfigPlanner::new`]).
    refined_near: usize,
}

/// At most this many second builds of [`ConfigPlanner::new`], each graded finer around the
/// configurations where the build before let a motion into an obstacle's image.
pub const THIN_IMAGE_REBUILDS: usize = 2;

fn millis(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// The part the faces around a free space's anti-goal get: held at the walls' value (see
/// `free_everywhere`).
pub use harmonic_cspace::ANTIGOAL_PART;

/// A configuration space bounded by nothing but its goal (an arm whose joints all wrap and
/// that touches nothing anywhere): every configuration is free and a potential held only at
/// the goal is constant. The point of the torus farthest from the goal is then held at the
/// walls' value: a two-link arm's slab faces within 1.5 spacings of it are retagged here; for
/// three wrapping joints (no slab faces there) the point returned is the centre of a ball of
/// that radius to leave out of the mesh ([`ConfigSpace::with_anti_goal`]), meshed again.
/// φ then rises from the goal to there with no interior extremum, and every start but those
/// very points flows to the goal.
fn free_everywhere(
    space: &ConfigSpace,
    mesh: &mut PeriodicMesh,
    spacing: f64,
) -> Result<Option<Point>, PlanError> {
    let bounded = mesh.slab.boundary_faces().iter().any(|f| {
        !matches!(f.tag, BoundaryTag::Goal(_))
            && f.tag != BoundaryTag::Obstacle(harmonic_volume::SEAM_PART)
            && f.tag != BoundaryTag::Obstacle(EXTRUDE_PART)
    });
    if bounded {
        return Ok(None);
    }
    let centroid = |f: &harmonic_volume::BoundaryFace| {
        let v = mesh.slab.vertices();
        f.vertices
            .iter()
            .map(|&i| v[i as usize].coords)
            .sum::<harmonic_volume::Vector>()
            / 3.0
    };
    let goals: Vec<_> = mesh
        .slab
        .boundary_faces()
        .iter()
        .filter(|f| matches!(f.tag, BoundaryTag::Goal(_)))
        .map(centroid)
        .collect();
    let extruded = space
        .axes()
        .iter()
        .any(|a| matches!(a, harmonic_cspace::Axis::Extruded { .. }));
    if goals.is_empty() {
        return Err(PlanError::NothingToAvoid);
    }
    let goal = goals.iter().sum::<harmonic_volume::Vector>() / goals.len() as f64;
    let period = mesh.period;
    let anti = [0, 1, 2].map(|a| period[a].map(|l| (goal[a] + 0.5 * l).rem_euclid(l)));
    let radius = ANTIGOAL_SPACINGS * spacing;
    if !extruded {
        return Ok(Some(Point::new(
            anti[0].unwrap_or(goal[0]),
            anti[1].unwrap_or(goal[1]),
            anti[2].unwrap_or(goal[2]),
        )));
    }
    let near = move |c: &[Point; 3]| {
        let m = (c[0].coords + c[1].coords + c[2].coords) / 3.0;
        let d2: f64 = (0..3)
            .filter_map(|a| {
                let (l, x) = (period[a]?, anti[a]?);
                let d = (m[a] - x).rem_euclid(l);
                Some(d.min(l - d).powi(2))
            })
            .sum();
        d2 <= radius * radius
    };
    mesh.retag(&|c, tag| {
        if tag == BoundaryTag::Obstacle(EXTRUDE_PART) && near(c) {
            BoundaryTag::Obstacle(ANTIGOAL_PART)
        } else {
            tag
        }
    });
    Ok(None)
}

/// Radius of the anti-goal ball (or of the slab faces held around it), in lattice spacings.
const ANTIGOAL_SPACINGS: f64 = 1.5;

impl ConfigPlanner {
    /// Builds the planner: validates the scene, meshes its configuration space, solves.
    ///
    /// Where a path from one of the scene's starts reaches the goal but its motion meets an
    /// obstacle — the mesh's faces cut across the obstacle's configuration-space image by
    /// more than the safety margin (a sliver thinner than the lattice, or an edge of the
    /// image sharper than it resolves: an arm's tip at full reach grazing a small circle) —
    /// the space is meshed and solved again, graded finer around every such
    /// configuration ([`ConfigSpace::with_refinement_near`]), at most
    /// [`THIN_IMAGE_REBUILDS`] times; a build that fails keeps the one before.
    pub fn new(scene: &ConfigScene) -> Result<ConfigPlanner, PlanError> {
        let mut planner = Self::build(scene, scene.build()?)?;
        for _ in 0..THIN_IMAGE_REBUILDS {
            let t = Instant::now();
            let thin: Vec<Vec<f64>> = scene
                .starts
                .par_iter()
                .filter_map(|s| planner.plan_checked(s).1)
                .collect();
            if thin.is_empty() {
                break;
            }
            let checked_ms = millis(t);
            let space = planner.space.clone().with_refinement_near(&thin);
            let Ok(mut finer) = Self::build(scene, space) else {
                break;
            };
            finer.timings.mesh += planner.timings.mesh + checked_ms;
            finer.timings.solve += planner.timings.solve;
            finer.refined_near = planner.refined_near + thin.len();
            planner = finer;
        }
        Ok(planner)
    }

    /// Meshes `space` (the scene's, or one graded finer) and solves.
    fn build(scene: &ConfigScene, space: ConfigSpace) -> Result<ConfigPlanner, PlanError> {
        let t = Instant::now();
        let budget = scene.mesh.max_tetrahedra.unwrap_or(DEFAULT_MAX_TETRAHEDRA);
        let (mut mesh, mut report) = space.mesh(budget)?;
        let space = match free_everywhere(&space, &mut mesh, report.spacing)? {
            None => space,
            Some(anti) => {
                let space = space.with_anti_goal(anti, ANTIGOAL_SPACINGS * report.spacing);
                (mesh, report) = space.mesh(budget)?;
                space
            }
        };
        let PeriodicMesh {
            slab,
            images,
            covering,
            slab_vertex,
            ..
        } = mesh;
        let slab = Arc::new(slab);
        let covering = Arc::new(covering);
        let mesh_ms = millis(t);

        let t = Instant::now();
        let bcs = scene.boundary_conditions();
        // Beside the assembly, the covering's point-location grid (what a first query would
        // build); beside the solve, whose IC(0) sweeps keep one core, what the field needs of
        // the covering alone (vertex → tetrahedra, components).
        let (system, ()) = rayon::join(
            || assemble_periodic_for_planning(&slab, &images, &bcs),
            || covering.prepare_locate(),
        );
        let system = system?;
        let (solved, topology) = rayon::join(
            || solve_folded_for_planning(&slab, &system),
            || VolumeFieldTopology::of(&covering),
        );
        drop(system);
        let (potential, solved) = solved?;
        let psi: Vec<f64> = slab_vertex
            .iter()
            .map(|&v| potential.psi()[v as usize])
            .collect();
        // The covering's tetrahedra are copies of the slab's, one copy after another.
        let field = P1VolumeField::ascending_with_copies(
            &covering,
            topology,
            &psi,
            slab.tetrahedra().len(),
        )?;
        let field = Arc::clone(field.parts());
        let solve_ms = millis(t);
        let (lo, hi) = covering.bounds();
        let size = space.world().size();
        Ok(ConfigPlanner {
            space,
            slab,
            covering,
            potential,
            field,
            report,
            unknowns: solved.unknowns,
            clamped_edges: solved.clamped_edges,
            solved_by: crate::volume::volume_solved_by(&solved.solve, solved.clamped_edges > 0),
            timings: Timings {
                mesh: mesh_ms,
                assemble: 0.0,
                solve: solve_ms,
                trace: 0.0,
            },
            scale: (hi - lo).max(),
            size,
            refined_near: 0,
        })
    }

    /// What a configuration is: `"pose"` (`[x, y, θ]` of a polygon robot) or `"joints"` (an
    /// arm's joint angles).
    pub fn configuration(&self) -> &'static str {
        match self.space.robot() {
            Robot::Rigid(_) => "pose",
            Robot::Arm(_) => "joints",
        }
    }

    /// The configuration space.
    pub fn space(&self) -> &ConfigSpace {
        &self.space
    }
    /// The slab mesh (one period).
    pub fn slab(&self) -> &TetMesh {
        &self.slab
    }
    /// The covering mesh the tracer follows.
    pub fn covering(&self) -> &TetMesh {
        &self.covering
    }
    /// The potential on the slab.
    pub fn potential(&self) -> &VolumePotential {
        &self.potential
    }
    /// What produced ψ, as the report's `potential.solved_by` says it.
    pub fn solved_by(&self) -> &'static str {
        self.solved_by
    }

    /// Milliseconds spent building (assembly counted in `solve`).
    pub fn timings(&self) -> Timings {
        self.timings
    }
    /// The meshing report.
    pub fn mesh_report(&self) -> &CspaceMeshReport {
        &self.report
    }

    /// Plans from the configuration `start` (`[x, y, θ]` or the joint angles). A start that
    /// touches an obstacle or a wall without overlapping it (closer than the safety margin,
    /// as a robot parked against a wall is) is first led straight away from it, up the
    /// exact clearance, until the margin is kept; a start that overlaps one is
    /// `start_in_obstacle`.
    pub fn plan(&self, start: &[f64]) -> ConfigPlannedPath {
        self.plan_checked(start).0
    }

    /// [`ConfigPlanner::plan`], and the configuration where the path reached the goal but
    /// its motion met an obstacle (an image the mesh cut across).
    fn plan_checked(&self, start: &[f64]) -> (ConfigPlannedPath, Option<Vec<f64>>) {
        let Some(lead) = self.lead_out(start) else {
            return self.trace_from(start);
        };
        let Some(from) = lead.last() else {
            return self.trace_from(start);
        };
        let (mut out, thin) = self.trace_from(from);
        let scale = self.space.scale();
        let mut length = 0.0;
        let mut clearance = f64::INFINITY;
        for w in lead.windows(2) {
            length += (0..w[0].len())
                .map(|a| ((w[1][a] - w[0][a]) * scale[a]).powi(2))
                .sum::<f64>()
                .sqrt();
        }
        for q in &lead {
            clearance = clearance.min(exact_clearance(self.space.robot(), self.space.world(), q));
        }
        out.start = start.to_vec();
        out.length += length;
        out.min_clearance = out.min_clearance.min(clearance.max(0.0));
        let before = &lead[..lead.len() - 1];
        if let Some(poses) = out.poses.as_mut() {
            let mut all: Vec<[f64; 3]> = before.iter().map(|q| [q[0], q[1], q[2]]).collect();
            all.append(poses);
            *poses = all;
        }
        if let Some(joints) = out.joints.as_mut() {
            let mut all = before.to_vec();
            all.append(joints);
            *joints = all;
        }
        (out, thin)
    }

    /// The way out of the anti-goal's ball ([`ConfigSpace::out_of_anti_goal`]), or out of
    /// the safety margin from a start that touches but does not overlap an obstacle or wall:
    /// steps of a quarter margin up the exact clearance's gradient (central
    /// differences in mesh units) until the clearance exceeds 1.5 margins; `None` when the
    /// start keeps the margin, overlaps something, breaks a joint limit, or no way out is
    /// found in 64 steps.
    fn lead_out(&self, start: &[f64]) -> Option<Vec<Vec<f64>>> {
        let dof = self.space.dof();
        if start.len() != dof || !start.iter().all(|c| c.is_finite()) {
            return None;
        }
        if let Some(out) = self.space.out_of_anti_goal(start) {
            return Some(vec![start.to_vec(), out]);
        }
        if self.space.classify(start) != ConfigClass::Collision {
            return None;
        }
        let clear = |q: &[f64]| exact_clearance(self.space.robot(), self.space.world(), q);
        if clear(start) < 0.0 {
            return None;
        }
        let margin = self.space.margin().max(1e-9);
        let scale = self.space.scale();
        let delta = 1e-4 * self.report.spacing;
        let mut q = start.to_vec();
        let mut lead = vec![q.clone()];
        for _ in 0..64 {
            let grad: Vec<f64> = (0..dof)
                .map(|a| {
                    let h = delta / scale[a];
                    let (mut up, mut down) = (q.clone(), q.clone());
                    up[a] += h;
                    down[a] -= h;
                    (clear(&up) - clear(&down)) / (2.0 * delta)
                })
                .collect();
            let norm = grad.iter().map(|g| g * g).sum::<f64>().sqrt();
            if !(norm > 0.0 && norm.is_finite()) {
                return None;
            }
            let step = 0.25 * margin;
            let next: Vec<f64> = (0..dof)
                .map(|a| q[a] + step * grad[a] / norm / scale[a])
                .collect();
            // The motion itself must not overlap anything.
            if (1..=8).any(|k| {
                let t = k as f64 / 8.0;
                let m: Vec<f64> = (0..dof).map(|a| q[a] + t * (next[a] - q[a])).collect();
                clear(&m) < 0.0
            }) {
                return None;
            }
            q = next;
            lead.push(q.clone());
            if clear(&q) > 1.5 * margin && self.space.classify(&q) == ConfigClass::Free {
                return Some(lead);
            }
        }
        None
    }

    /// Traces from `start` as it is; also returns where a path that reached the goal met an
    /// obstacle.
    fn trace_from(&self, start: &[f64]) -> (ConfigPlannedPath, Option<Vec<f64>>) {
        let dof = self.space.dof();
        if start.len() != dof || !start.iter().all(|c| c.is_finite()) {
            return (self.planned(start, None, Tracer::Exact), None);
        }
        let (p, shift) = self.space.to_mesh(start);
        let classify = |q: &Point| match self.space.classify(&self.space.config(q)) {
            ConfigClass::Free => Locate::Inside(0),
            ConfigClass::Goal => Locate::Goal(0),
            ConfigClass::Collision => Locate::InObstacle,
            ConfigClass::OutsideLimits => Locate::OutsideWorkspace,
        };
        let Ok(field) = P1VolumeField::from_parts(&self.covering, Arc::clone(&self.field)) else {
            return (self.planned(start, None, Tracer::Exact), None);
        };
        let field = field.with_outside(&classify);
        let to_configs = |path: &Path<Point>| -> Vec<Vec<f64>> {
            path.points
                .iter()
                .map(|q| {
                    let c = self.space.config(q);
                    c.iter().zip(&shift).map(|(a, s)| a + s).collect()
                })
                .collect()
        };
        // The smooth tracer first; the exact one where it stalls or where its motion meets an
        // obstacle between entries (a C-obstacle thinner than the mesh can lie under a chord).
        let smooth = trace_smooth(&field, p, &SmoothOptions::for_scale(self.scale))
            .ok()
            .filter(|path| {
                !matches!(
                    path.status,
                    TraceStatus::Stalled { .. } | TraceStatus::MaxSteps
                )
            })
            .map(|path| {
                let configs = to_configs(&path);
                (path, configs)
            })
            .filter(|(_, configs)| self.first_collision(configs).is_none());
        // The smooth path kept above has no collision; only the exact one is still checked.
        let (path, configs, tracer, collision) = match smooth {
            Some((path, configs)) => (path, configs, Tracer::Smooth, None),
            None => {
                let path = trace_exact_volume(&field, p, &ExactVolumeOptions::default());
                let configs = to_configs(&path);
                let collision = self.first_collision(&configs);
                (path, configs, Tracer::Exact, collision)
            }
        };
        let mut out = self.planned(start, Some((path, configs)), tracer);
        if let Some(first) = out.poses.as_mut().and_then(|p| p.first_mut()) {
            first.copy_from_slice(&start[..3]);
        }
        if let Some(first) = out.joints.as_mut().and_then(|p| p.first_mut()) {
            first.copy_from_slice(start);
        }
        // A descent that stops short of the goal's faces but inside its tolerance has
        // arrived: the tolerance is what was asked; the faces are only where the field ends.
        if matches!(
            out.status,
            TraceStatus::Stalled { .. } | TraceStatus::MaxSteps
        ) && out
            .configurations()
            .last()
            .is_some_and(|q| self.space.classify(q) == ConfigClass::Goal)
        {
            out.status = TraceStatus::ReachedGoal(0);
        }
        // A path that reached the goal but touches an obstacle on the way is not reached.
        let thin = collision.filter(|_| out.status.reached_goal());
        if let Some(q) = &thin {
            out.status = TraceStatus::Collision { at: None };
            out.blocked_by = Some(format!(
                "{} at {q:.4?}, where the mesh cuts across its image in configuration space (a \
                 sliver thinner, or an edge sharper, than the mesh resolves); a smaller \
                 mesh.spacing resolves it",
                self.space.nearest_name(q)
            ));
            out.min_clearance = 0.0;
        }
        (out, thin)
    }

    /// The first configuration along the path's motions where the robot touches an obstacle,
    /// the workspace boundary or itself (exact clearance 0; the safety margin not counted):
    /// samples at most 1e-3 × the scene size of robot motion apart, except where the
    /// clearance at a sample certifies the motion up to a farther one.
    fn first_collision(&self, configs: &[Vec<f64>]) -> Option<Vec<f64>> {
        let robot = self.space.robot();
        let step = 1e-3 * self.size;
        if let [only] = configs {
            return (self.space.clearance(only).0 <= 0.0).then(|| only.clone());
        }
        for w in configs.windows(2) {
            // Conservative advancement: no robot point moves more than `bound · Δt` between
            // t and t + Δt, so a clearance c (to the world, or between two links, which both
            // move) certifies Δt = c / (2 bound) free; elsewhere the samples are `step` of
            // motion apart, as a plain sampling at that spacing would be.
            let bound = robot.sweep_bound(&w[0], &w[1]);
            let at = |t: f64| -> Vec<f64> {
                w[0].iter()
                    .zip(&w[1])
                    .map(|(a, b)| a + t * (b - a))
                    .collect()
            };
            let mut t = 0.0f64;
            for _ in 0..=(1 << 20) {
                let q = at(t);
                let clearance = self.space.clearance(&q).0;
                if clearance <= 0.0 {
                    return Some(q);
                }
                if t >= 1.0 || bound <= 0.0 {
                    break;
                }
                t = (t + (0.5 * clearance).max(step) / bound).min(1.0);
            }
        }
        None
    }

    fn planned(
        &self,
        start: &[f64],
        path: Option<(Path<Point>, Vec<Vec<f64>>)>,
        tracer: Tracer,
    ) -> ConfigPlannedPath {
        let (status, min_gradient, configs, length) = match path {
            Some((p, c)) => (p.status, p.min_gradient, c, p.length),
            None => (TraceStatus::OutsideWorkspace, 0.0, Vec::new(), 0.0),
        };
        let clearance = configs
            .iter()
            .map(|q| exact_clearance(self.space.robot(), self.space.world(), q))
            .fold(f64::INFINITY, f64::min);
        let (poses, joints) = match self.space.robot() {
            Robot::Rigid(_) => (
                Some(configs.iter().map(|q| [q[0], q[1], q[2]]).collect()),
                None,
            ),
            Robot::Arm(_) => (None, Some(configs)),
        };
        let blocked_by = (matches!(status, TraceStatus::StartInObstacle)
            && start.len() == self.space.dof())
        .then(|| self.space.nearest_name(start));
        ConfigPlannedPath {
            start: start.to_vec(),
            status,
            blocked_by,
            tracer,
            length,
            min_clearance: finite_or_zero(clearance),
            min_gradient: finite_or_zero(min_gradient),
            poses,
            joints,
        }
    }

    /// Plans from every start, in parallel.
    pub fn plan_many(&self, starts: &[Vec<f64>]) -> Vec<ConfigPlannedPath> {
        starts.par_iter().map(|s| self.plan(s)).collect()
    }

    /// Checks every motion of `path` against the exact polygons at samples no robot point
    /// moves more than `1e-3 ×` the scene size between; the smallest clearance met.
    pub fn check(&self, path: &ConfigPlannedPath) -> f64 {
        check_path(
            self.space.robot(),
            self.space.world(),
            &path.configurations(),
            1e-3 * self.size,
        )
        .min_clearance
    }

    /// Plans from `starts` and reports as `hplan plan --json` prints.
    pub fn plan_report(&self, starts: &[Vec<f64>]) -> ConfigPlanReport {
        let t = Instant::now();
        let paths = self.plan_many(starts);
        let mut timings = self.timings;
        timings.trace = millis(t);
        let [min_dihedral_deg, max_dihedral_deg] = dihedral_range(&self.slab);
        ConfigPlanReport {
            configuration: Some(self.configuration()),
            mesh: ConfigMeshSummary {
                vertices: self.slab.vertices().len(),
                tetrahedra: self.slab.tetrahedra().len(),
                unknowns: self.unknowns,
                covering_tetrahedra: self.covering.tetrahedra().len(),
                min_dihedral_deg,
                max_dihedral_deg,
                spacing: self.report.spacing,
                scale: self.report.scale,
                cells: self.report.cells,
                seam_faces: self.report.seam_faces,
                graded: self.report.graded,
                margin: self.space.margin(),
                clamped_edges: self.clamped_edges,
                refined_near: self.refined_near,
            },
            timings_ms: timings,
            potential: crate::volume::volume_potential_summary(
                &self.potential,
                self.solved_by,
                self.clamped_edges,
            ),
            paths,
        }
    }

    /// The slab of one period (in the space's scaled coordinates) and its potential, for
    /// outside tools.
    pub fn export(&self) -> crate::volume::VolumeExport {
        crate::volume::VolumeExport::of(&self.slab, &self.potential)
    }

    /// The slab of one period (in the space's scaled coordinates) with φ, ψ and ∇φ as a VTK
    /// unstructured grid, for ParaView.
    pub fn vtu(&self) -> Result<String, harmonic_volume::VolumeError> {
        crate::volume::potential_vtu(self.slab(), &self.potential)
    }

    /// The scene with the robot drawn along each path.
    pub fn svg(&self, paths: &[Vec<Vec<f64>>], title: Option<String>) -> String {
        let marker = match self.space.goal() {
            ConfigGoal::Pose { pose, .. } => Some([pose[0], pose[1]]),
            ConfigGoal::EndEffector { point, .. } => Some(*point),
            ConfigGoal::Joints { joints, .. } => match self.space.robot() {
                Robot::Arm(a) => Some(a.tip(joints)),
                Robot::Rigid(_) => None,
            },
        };
        motion_svg(
            self.space.robot(),
            self.space.world(),
            paths,
            marker,
            &MotionSvgOptions {
                title,
                ..MotionSvgOptions::default()
            },
        )
    }
}
