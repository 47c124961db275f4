//! The free configuration space as an [`ImplicitDomain`]: a function of the (scaled)
//! configuration that is negative where the robot, grown by the safety margin ε, touches
//! nothing, stays within its joint limits and is outside the goal region; meshed by the
//! periodic isosurface stuffing of `harmonic_volume`.
//!
//! **Coordinates.** The mesh lives in scaled coordinates `p = s ⊙ (q − o)` so that one unit of
//! every axis moves the robot about as much: a rigid robot's θ is scaled by its radius of
//! gyration about the body origin (x and y by 1), an arm's joint `i` by its reach beyond the
//! joint (the sum of the lengths of links `i…n`). A periodic axis's scale is then rounded so
//! that a whole number `N` of lattice cells spans the turn (`2π·s = N·h`), which is what lets
//! the lattice close on itself; the report gives the scales used. A periodic axis starts at
//! `o`, half a turn from the goal's angle, so the goal lies mid-period, away from the seam
//! where the slab's two ends are identified (and where the mesh is not refined).
//!
//! **Goals of any size** are left out of the stuffed function and carved from the mesh after
//! grading it down to them (`harmonic_volume::carve_goals`): a tolerance of 0.05 rad in a
//! lattice of 0.4 is resolved, not refused.
//!
//! **Which axes wrap.** θ always; an arm's joint when it has no limits (or limits spanning a
//! full turn). Limited joints are walls of the configuration box. A two-link arm's
//! configuration space is the plane (q1, q2); it is meshed as a thin slab of it (three lattice
//! cells thick, its flat faces under the natural condition `Obstacle(`[`EXTRUDE_PART`]`)`),
//! on which the harmonic potential does not depend on the third coordinate.
//!
//! **The value.** `ε − d(q)` with `d` the exact distance (parry2d, convex parts) from the
//! robot to the nearest obstacle or wall (negated when the robot is outside the workspace),
//! combined by `max` with the joint-limit terms, the slab faces and `−g(q)`, `g` the goal
//! region's own function (negative inside it). Its tag is the term that attains the max.

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

use harmonic_mesh::BoundaryTag;
use harmonic_volume::{
    CarveReport, EDGES, GoalHole, Grading, ImplicitDomain, PeriodicMesh, PeriodicStuffed, Point,
    SEAM_PART, StuffingOptions, carve_goals, longest_edge, periodic_lattice_tetrahedra,
    stuff_periodic,
};

use crate::error::CspaceError;
use crate::geometry::{Nearest, Pair, World, self_clearance};
use crate::robot::Robot;

/// The obstacle index of a two-link arm's slab faces (natural condition).
pub const EXTRUDE_PART: u32 = u32::MAX - 1;

/// The obstacle index of the faces around a free space's anti-goal (held at the walls'
/// value; see [`ConfigSpace::with_anti_goal`]).
pub const ANTIGOAL_PART: u32 = u32::MAX - 2;

/// The default tetrahedron budget of a configuration-space lattice.
pub const DEFAULT_MAX_TETRAHEDRA: u64 = 3_000_000;

/// [`ConfigSpace::with_refinement_near`] grades the lattice within this many spacings of
/// each configuration it is given...
pub const REFINE_NEAR_RADIUS: f64 = 1.0;

/// ... down to edges of this fraction of the spacing (the grading elsewhere stops at a
/// quarter).
pub const REFINE_NEAR_FLOOR: f64 = 0.125;

/// A goal in configuration space.
#[derive(Clone, Debug, PartialEq)]
pub enum ConfigGoal {
    /// A rigid robot's pose within `position` (distance) and `angle` (radians).
    Pose {
        /// `[x, y, θ]`.
        pose: [f64; 3],
        /// Position tolerance.
        position: f64,
        /// Heading tolerance, radians.
        angle: f64,
    },
    /// An arm's joints, each within `tolerance` radians.
    Joints {
        /// The joint angles.
        joints: Vec<f64>,
        /// Tolerance per joint, radians.
        tolerance: f64,
    },
    /// Any arm configuration whose tip is within `tolerance` of `point`.
    EndEffector {
        /// The point.
        point: [f64; 2],
        /// Distance tolerance.
        tolerance: f64,
    },
}

/// How one mesh axis behaves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Axis {
    /// A position coordinate: bounded by the workspace's box (the walls do the rest).
    Position {
        /// Lowest value.
        lo: f64,
        /// Highest value.
        hi: f64,
    },
    /// An angle that wraps around (θ, a free joint).
    Periodic,
    /// A limited joint: its limits are walls.
    Limited {
        /// Lowest angle.
        lo: f64,
        /// Highest angle.
        hi: f64,
    },
    /// The thickness of a two-link arm's slab.
    Extruded {
        /// Thickness in mesh units.
        thickness: f64,
    },
}

/// Where a configuration lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConfigClass {
    /// Free (the margin kept), outside the goal.
    Free,
    /// In the goal region.
    Goal,
    /// The robot (grown by the margin) touches an obstacle or a wall, or leaves the
    /// workspace.
    Collision,
    /// Beyond a joint limit.
    OutsideLimits,
}

/// A configuration space ready to mesh.
#[derive(Clone, Debug)]
pub struct ConfigSpace {
    robot: Robot,
    world: World,
    goal: ConfigGoal,
    margin: f64,
    spacing: f64,
    axes: [Axis; 3],
    scale: [f64; 3],
    /// Per periodic axis, the angle at mesh coordinate 0.
    origin: [f64; 3],
    cells: [Option<usize>; 3],
    /// A ball (mesh coordinates: centre, radius) left out of the mesh as if it collided
    /// ([`ConfigSpace::with_anti_goal`]).
    anti_goal: Option<(Point, f64)>,
    /// Configurations (mesh coordinates) around which the lattice is graded finer
    /// ([`ConfigSpace::with_refinement_near`]).
    refine_near: Vec<Point>,
}

/// What meshing the configuration space did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CspaceMeshReport {
    /// Lattice spacing (mesh units).
    pub spacing: f64,
    /// Scale of each coordinate (mesh units per configuration unit).
    pub scale: [f64; 3],
    /// Lattice cells per period along periodic axes.
    pub cells: [Option<usize>; 3],
    /// Lattice tetrahedra examined.
    pub lattice_tetrahedra: u64,
    /// Slab end faces identified across the period.
    pub seam_faces: usize,
    /// Lattice edges bisected before stuffing where the lattice's vertices missed a sliver of
    /// collision ([`ImplicitDomain::grading`]); 0 on the uniform lattice.
    pub graded: usize,
    /// Edges bisected to grade the mesh down to the goal region.
    pub refined: usize,
    /// Tetrahedra carved out of the goal region.
    pub goal_tetrahedra: usize,
    /// Wall-clock seconds.
    pub seconds: f64,
}

fn wrap_pi(a: f64) -> f64 {
    (a + PI).rem_euclid(TAU) - PI
}

impl ConfigSpace {
    /// A configuration space for `robot` in `world` with `goal`, safety margin `margin` and
    /// lattice spacing `spacing` (mesh units); checks the goal against the robot (errors
    /// name `goal…`).
    pub fn new(
        robot: Robot,
        world: World,
        goal: ConfigGoal,
        margin: f64,
        spacing: f64,
    ) -> Result<ConfigSpace, CspaceError> {
        let bad = |path: &str, message: String| CspaceError::Invalid {
            path: path.into(),
            message,
        };
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(bad("mesh.margin", format!("must be ≥ 0, got {margin}")));
        }
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(bad(
                "mesh.spacing",
                format!("must be positive, got {spacing}"),
            ));
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        match (&robot, &goal) {
            (
                Robot::Rigid(_),
                ConfigGoal::Pose {
                    pose,
                    position,
                    angle,
                },
            ) => {
                if !pose.iter().all(|c| c.is_finite()) {
                    return Err(bad("goal.pose", "must be finite".into()));
                }
                if !positive(*position) || !positive(*angle) {
                    return Err(bad(
                        "goal.tolerance",
                        "position and angle must be positive".into(),
                    ));
                }
            }
            (Robot::Arm(arm), ConfigGoal::Joints { joints, tolerance }) => {
                if joints.len() != arm.links.len() || !joints.iter().all(|c| c.is_finite()) {
                    return Err(bad(
                        "goal.joints",
                        format!("needs {} finite angles", arm.links.len()),
                    ));
                }
                if !positive(*tolerance) {
                    return Err(bad("goal.tolerance", "must be positive".into()));
                }
            }
            (Robot::Arm(_), ConfigGoal::EndEffector { point, tolerance }) => {
                if !point.iter().all(|c| c.is_finite()) {
                    return Err(bad("goal.end_effector", "must be finite".into()));
                }
                if !positive(*tolerance) {
                    return Err(bad("goal.tolerance", "must be positive".into()));
                }
            }
            (Robot::Rigid(_), _) => {
                return Err(bad("goal", "a polygon robot's goal is a \"pose\"".into()));
            }
            (Robot::Arm(_), _) => {
                return Err(bad(
                    "goal",
                    "an arm's goal is \"joints\" or \"end_effector\"".into(),
                ));
            }
        }
        let (lo, hi) = world.bounds();
        let mut axes = [Axis::Periodic; 3];
        let mut scale = [1.0; 3];
        match &robot {
            Robot::Rigid(r) => {
                axes[0] = Axis::Position {
                    lo: lo[0],
                    hi: hi[0],
                };
                axes[1] = Axis::Position {
                    lo: lo[1],
                    hi: hi[1],
                };
                scale[2] = r.radius_of_gyration;
            }
            Robot::Arm(arm) => {
                for (i, l) in arm.limits.iter().enumerate() {
                    axes[i] = match l {
                        Some([lo, hi]) => Axis::Limited { lo: *lo, hi: *hi },
                        None => Axis::Periodic,
                    };
                    scale[i] = arm.reach_from(i);
                }
                if arm.links.len() == 2 {
                    axes[2] = Axis::Extruded {
                        thickness: 3.0 * spacing,
                    };
                }
            }
        }
        let mut cells = [None; 3];
        for a in 0..3 {
            if axes[a] == Axis::Periodic {
                let n = ((TAU * scale[a] / spacing).round() as usize).max(3);
                cells[a] = Some(n);
                scale[a] = n as f64 * spacing / TAU;
            }
        }
        Ok(ConfigSpace {
            robot,
            world,
            goal,
            margin,
            spacing,
            axes,
            scale,
            origin: [0.0; 3],
            cells,
            anti_goal: None,
            refine_near: Vec::new(),
        }
        .centred_on_thin_goal())
    }

    /// Whether the goal region is thinner than half the spacing: too thin for the lattice to
    /// give it faces, so it is carved rather than stuffed.
    fn goal_is_thin(&self) -> bool {
        4.0 * self.goal_geometry().1 < self.spacing
    }

    /// A goal thinner than half the spacing is carved after refining down to it, and refinement
    /// stays off the slab's seam: so every periodic axis then starts half a turn from the
    /// goal's angle, putting the goal mid-period. (A thicker goal is stuffed and leaves the
    /// axes as they are.)
    fn centred_on_thin_goal(mut self) -> Self {
        if !self.goal_is_thin() {
            return self;
        }
        for a in 0..3 {
            if self.axes[a] == Axis::Periodic {
                let centre = match &self.goal {
                    ConfigGoal::Pose { pose, .. } => Some(pose[a]),
                    ConfigGoal::Joints { joints, .. } => joints.get(a).copied(),
                    ConfigGoal::EndEffector { .. } => None,
                };
                if let Some(c) = centre {
                    self.origin[a] = c - PI;
                }
            }
        }
        self
    }

    /// The robot.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }
    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }
    /// The goal.
    pub fn goal(&self) -> &ConfigGoal {
        &self.goal
    }
    /// The safety margin ε.
    pub fn margin(&self) -> f64 {
        self.margin
    }
    /// The axes.
    pub fn axes(&self) -> [Axis; 3] {
        self.axes
    }
    /// Mesh units per configuration unit, per axis.
    pub fn scale(&self) -> [f64; 3] {
        self.scale
    }
    /// Per periodic axis, the angle at mesh coordinate 0 (half a turn from the goal's, so
    /// the goal lies mid-period); 0 on the other axes.
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }
    /// The robot's degrees of freedom.
    pub fn dof(&self) -> usize {
        self.robot.dof()
    }

    /// The configuration of a mesh point (the slab coordinate of a two-link arm dropped).
    pub fn config(&self, p: &Point) -> Vec<f64> {
        self.config_array(p)[..self.dof()].to_vec()
    }

    /// [`ConfigSpace::config`] without allocating: the first `dof()` entries (the rest 0).
    fn config_array(&self, p: &Point) -> [f64; 3] {
        let dof = self.dof();
        [0, 1, 2].map(|a| {
            if a < dof {
                p[a] / self.scale[a] + self.origin[a]
            } else {
                0.0
            }
        })
    }

    /// The mesh point of `q` with its periodic coordinates brought into the first period,
    /// and what was taken off them (so `q = config(p) + shift`).
    pub fn to_mesh(&self, q: &[f64]) -> (Point, Vec<f64>) {
        let mut p = Point::origin();
        let mut shift = vec![0.0; self.dof()];
        for a in 0..3 {
            match self.axes[a] {
                Axis::Extruded { thickness } => p[a] = 0.5 * thickness,
                Axis::Periodic => {
                    let r = (q[a] - self.origin[a]).rem_euclid(TAU);
                    shift[a] = q[a] - self.origin[a] - r;
                    p[a] = r * self.scale[a];
                }
                _ => p[a] = q[a] * self.scale[a],
            }
        }
        (p, shift)
    }

    /// The goal's own function at `q`: negative inside the goal region.
    pub fn goal_value(&self, q: &[f64]) -> f64 {
        match &self.goal {
            ConfigGoal::Pose {
                pose,
                position,
                angle,
            } => {
                let d = (q[0] - pose[0]).hypot(q[1] - pose[1]) - position;
                let t = (wrap_pi(q[2] - pose[2]).abs() - angle) * self.scale[2];
                d.max(t)
            }
            ConfigGoal::Joints { joints, tolerance } => (0..joints.len())
                .map(|a| {
                    let d = q[a] - joints[a];
                    let d = if self.axes[a] == Axis::Periodic {
                        wrap_pi(d)
                    } else {
                        d
                    };
                    (d.abs() - tolerance) * self.scale[a]
                })
                .fold(f64::NEG_INFINITY, f64::max),
            ConfigGoal::EndEffector { point, tolerance } => match &self.robot {
                Robot::Arm(arm) => {
                    let t = arm.tip(q);
                    (t[0] - point[0]).hypot(t[1] - point[1]) - tolerance
                }
                Robot::Rigid(_) => f64::INFINITY,
            },
        }
    }

    /// The robot's distance to the nearest obstacle or wall at `q` (negated outside the
    /// workspace), or between two of an arm's links that are not neighbours, and which that
    /// is.
    pub fn clearance(&self, q: &[f64]) -> (f64, Nearest) {
        let (d, nearest, _) = self.nearest_pair(q);
        (d, nearest)
    }

    /// [`ConfigSpace::clearance`] and the pair of pieces it was measured between.
    fn nearest_pair(&self, q: &[f64]) -> (f64, Nearest, Pair) {
        match &self.robot {
            Robot::Rigid(r) => {
                let placed = r.placed(q);
                let outline = r.outline(&q[..3]);
                self.world.nearest_pair(&placed, outline[0])
            }
            Robot::Arm(arm) => {
                let parts = arm.placed_parts(q);
                let placed: Vec<_> = parts.iter().map(|(pose, p)| (*pose, p)).collect();
                let world = self.world.nearest_pair(&placed, arm.base);
                // Links that are not neighbours must not touch each other either.
                match self_clearance(&placed) {
                    Some((d, own @ Nearest::Links(i, j))) if d < world.0 => {
                        let pair = Pair {
                            robot: i,
                            world: Pair::LINKS + j,
                        };
                        (d, own, pair)
                    }
                    _ => world,
                }
            }
        }
    }

    /// The terms of the value and the boundary part of the largest; the goal's term only
    /// `with_goal` (the goal is carved from the mesh, not stuffed, but names its faces).
    fn terms(&self, p: &Point, with_goal: bool) -> Term {
        let q = &self.config_array(p)[..self.dof()];
        let (d, nearest, pair) = self.nearest_pair(q);
        let mut best = Term {
            value: self.margin - d,
            tag: match nearest {
                Nearest::Wall | Nearest::Links(..) => BoundaryTag::Wall,
                Nearest::Obstacle(i) => BoundaryTag::Obstacle(i),
            },
            pair,
        };
        // The terms that are not the robot's clearance: pairs of their own.
        let mut raise = |value: f64, tag: BoundaryTag, which: u32| {
            if value > best.value {
                let pair = Pair {
                    robot: u32::MAX,
                    world: which,
                };
                best = Term { value, tag, pair };
            }
        };
        for a in 0..3 {
            let side = 4 * a as u32;
            match self.axes[a] {
                Axis::Limited { lo, hi } => {
                    raise((lo - q[a]) * self.scale[a], BoundaryTag::Wall, side);
                    raise((q[a] - hi) * self.scale[a], BoundaryTag::Wall, side + 1);
                }
                Axis::Extruded { thickness } => {
                    let tag = BoundaryTag::Obstacle(EXTRUDE_PART);
                    raise(-p[a], tag, side + 2);
                    raise(p[a] - thickness, tag, side + 3);
                }
                _ => {}
            }
        }
        if with_goal {
            raise(-self.goal_value(q), BoundaryTag::Goal(0), 12);
        }
        if let Some((d, r)) = self.anti_goal_offset(p) {
            let n = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            raise(r - n, BoundaryTag::Obstacle(ANTIGOAL_PART), 13);
        }
        best
    }

    /// This space with a ball of `radius` around `centre` (mesh coordinates, taken modulo the
    /// periods) left out of the mesh, its faces tagged [`ANTIGOAL_PART`]: for a space that
    /// nothing but its goal bounds (every joint wraps and the robot touches nothing anywhere),
    /// where a potential held only at the goal would be constant. Held at the walls' value,
    /// the ball's faces make φ rise from the goal to them with no interior extremum, so every
    /// start but those inside the ball flows to the goal. [`ConfigSpace::classify`] does not
    /// see the ball: it is no collision.
    pub fn with_anti_goal(mut self, centre: Point, radius: f64) -> Self {
        self.anti_goal = Some((centre, radius));
        self
    }

    /// The space with its lattice graded down to [`REFINE_NEAR_FLOOR`] of the spacing within
    /// [`REFINE_NEAR_RADIUS`] spacings of each configuration of `near`: where a path's motion
    /// met an obstacle's image that the mesh cut across (the planner's second build).
    pub fn with_refinement_near(mut self, near: &[Vec<f64>]) -> Self {
        let dof = self.dof();
        let points: Vec<Point> = near
            .iter()
            .filter(|q| q.len() == dof && q.iter().all(|x| x.is_finite()))
            .map(|q| self.to_mesh(q).0)
            .collect();
        self.refine_near.extend(points);
        self
    }

    /// Whether the mesh point `p` lies within [`REFINE_NEAR_RADIUS`] spacings of a point of
    /// [`ConfigSpace::with_refinement_near`].
    fn near_refinement(&self, p: &Point) -> bool {
        let r = REFINE_NEAR_RADIUS * self.spacing;
        self.refine_near.iter().any(|c| {
            let d = self.periodic_offset(c, p);
            d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= r * r
        })
    }

    /// The offset from `c` to `p` (mesh points), the shortest way round along periodic axes.
    fn periodic_offset(&self, c: &Point, p: &Point) -> [f64; 3] {
        [0, 1, 2].map(|a| {
            let x = p[a] - c[a];
            match self.axes[a] {
                Axis::Periodic => {
                    let period = TAU * self.scale[a];
                    (x + 0.5 * period).rem_euclid(period) - 0.5 * period
                }
                _ => x,
            }
        })
    }

    /// The offset from the anti-goal's centre to the mesh point `p`, the shortest way round
    /// along periodic axes, and the ball's radius.
    fn anti_goal_offset(&self, p: &Point) -> Option<([f64; 3], f64)> {
        let (c, r) = self.anti_goal?;
        Some((self.periodic_offset(&c, p), r))
    }

    /// For a configuration inside the anti-goal's ball ([`ConfigSpace::with_anti_goal`]):
    /// the configuration straight away from the ball's centre at 1.25 radii, where the mesh
    /// begins (a space with an anti-goal touches nothing anywhere, so the straight move is
    /// free). `None` outside the ball or without one.
    pub fn out_of_anti_goal(&self, q: &[f64]) -> Option<Vec<f64>> {
        let dof = self.dof();
        if self.anti_goal.is_none() || q.len() != dof || !q.iter().all(|x| x.is_finite()) {
            return None;
        }
        let (d, r) = self.anti_goal_offset(&self.to_mesh(q).0)?;
        let n = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > r {
            return None;
        }
        let dir = if n > 1e-12 * r {
            d.map(|x| x / n)
        } else {
            [1.0, 0.0, 0.0]
        };
        let step = 1.25 * r - n;
        Some(
            (0..dof)
                .map(|a| q[a] + dir[a] * step / self.scale[a])
                .collect(),
        )
    }

    /// Where `q` lies.
    pub fn classify(&self, q: &[f64]) -> ConfigClass {
        for (axis, qa) in self.axes.iter().zip(q) {
            if let Axis::Limited { lo, hi } = *axis
                && !(lo..=hi).contains(qa)
            {
                return ConfigClass::OutsideLimits;
            }
        }
        if self.clearance(q).0 <= self.margin {
            return ConfigClass::Collision;
        }
        if self.goal_value(q) <= 0.0 {
            ConfigClass::Goal
        } else {
            ConfigClass::Free
        }
    }

    /// What the robot at `q` is nearest to, in words (`"obstacle 2"`, `"the workspace
    /// boundary"`, `"itself (links 0 and 2)"`): what a configuration in collision collides
    /// with.
    pub fn nearest_name(&self, q: &[f64]) -> String {
        nearest_name(self.clearance(q).1)
    }

    /// The lattice tetrahedra meshing would examine.
    pub fn estimated_tetrahedra(&self) -> u64 {
        periodic_lattice_tetrahedra(self.bounds(), self.spacing, self.cells)
    }

    /// Meshes the free configuration space (refusing, before any work, a lattice of more than
    /// `max_tetrahedra`): the slab of one period and a covering of three along each periodic
    /// axis.
    pub fn mesh(
        &self,
        max_tetrahedra: u64,
    ) -> Result<(PeriodicMesh, CspaceMeshReport), CspaceError> {
        let start = std::time::Instant::now();
        let estimated = self.estimated_tetrahedra();
        if estimated > max_tetrahedra {
            return Err(CspaceError::TooLarge {
                estimated,
                budget: max_tetrahedra,
                spacing: self.spacing,
            });
        }
        let options = StuffingOptions {
            spacing: self.spacing,
            max_tetrahedra,
        };
        // A goal at least half a spacing thick is stuffed with the rest (smooth goal faces, no
        // refinement); a thinner one, or one the stuffing gave no face, is carved.
        if !self.goal_is_thin() {
            let stuffed = stuff_periodic(&WithGoal(self), &options, self.cells)?;
            if !stuffed.stuffed.tetrahedra.is_empty() {
                let mut mesh = PeriodicMesh::new(&stuffed, 1, &|p| self.tag(p))?;
                self.goal_faces_by_corners(&mut mesh);
                if mesh
                    .slab
                    .boundary_faces()
                    .iter()
                    .any(|f| f.tag == BoundaryTag::Goal(0))
                {
                    let report = self.report(estimated, &mesh, stuffed.stuffed.graded, None, start);
                    return Ok((mesh, report));
                }
            }
        }
        let mut stuffed = stuff_periodic(self, &options, self.cells)?;
        if stuffed.stuffed.tetrahedra.is_empty() {
            return Err(CspaceError::NoFreeSpace {
                spacing: self.spacing,
            });
        }
        let carved = self.carve_goal(&mut stuffed, max_tetrahedra);
        if carved.carved.first().is_none_or(|&n| n == 0) {
            return Err(self.goal_unmeshed(carved.refine.budget_reached, max_tetrahedra));
        }
        let mut mesh = PeriodicMesh::new(&stuffed, 1, &|p| self.tag(p))?;
        self.goal_faces_by_corners(&mut mesh);
        let graded = stuffed.stuffed.graded;
        let report = self.report(estimated, &mesh, graded, Some(&carved), start);
        Ok((mesh, report))
    }
}

impl ConfigSpace {
    /// The goal's function in mesh units and its Lipschitz constant there, and the size of
    /// tetrahedra that fit in the goal region.
    fn goal_geometry(&self) -> (f64, f64) {
        let dof = self.dof();
        match &self.goal {
            ConfigGoal::Pose {
                position, angle, ..
            } => (1.0, 0.5 * position.min(angle * self.scale[2])),
            ConfigGoal::Joints { tolerance, .. } => {
                let s = self.scale[..dof]
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                (1.0, 0.5 * tolerance * s)
            }
            // A joint's scale is its reach, so the tip moves at most one unit per mesh unit
            // along each axis.
            ConfigGoal::EndEffector { tolerance, .. } => {
                let l = (dof as f64).sqrt();
                (l, 0.5 * tolerance / l)
            }
        }
    }

    /// Grades the stuffed slab down to the goal region and carves it out (see
    /// `harmonic_volume::carve_goals`); seam vertices stay as they are, so the two ends of
    /// the slab stay copies of each other.
    fn carve_goal(&self, stuffed: &mut PeriodicStuffed, max_tetrahedra: u64) -> CarveReport {
        let (lipschitz, size) = self.goal_geometry();
        let mut members = vec![0u32; stuffed.orbit.len()];
        for &o in &stuffed.orbit {
            members[o as usize] += 1;
        }
        let orbit = &stuffed.orbit;
        let frozen = |v: u32| {
            orbit
                .get(v as usize)
                .is_some_and(|&o| members[o as usize] > 1)
        };
        let value = |p: &Point| self.goal_value(&self.config_array(p)[..self.dof()]);
        let holes = [GoalHole {
            value: &value,
            lipschitz,
            size,
        }];
        let s = &mut stuffed.stuffed;
        let before = s.vertices.len();
        let budget = usize::try_from(max_tetrahedra).unwrap_or(usize::MAX);
        let report = carve_goals(&mut s.vertices, &mut s.tetrahedra, &holes, &frozen, budget);
        let classes = stuffed.orbit.iter().copied().max().map_or(0, |m| m + 1);
        let (orbit, wrap): (Vec<u32>, Vec<[i32; 3]>) = report
            .kept
            .iter()
            .map(|&v| {
                let v = v as usize;
                if v < before {
                    (stuffed.orbit[v], stuffed.wrap[v])
                } else {
                    // A new vertex is off the seam: a class of its own.
                    (classes + (v - before) as u32, [0; 3])
                }
            })
            .unzip();
        stuffed.orbit = orbit;
        stuffed.wrap = wrap;
        report
    }

    /// Why the goal kept no tetrahedron: the goal configuration collides or lies outside the
    /// joint limits, or refinement stopped at the budget.
    fn goal_unmeshed(&self, budget_reached: bool, budget: u64) -> CspaceError {
        let centre = match &self.goal {
            ConfigGoal::Pose { pose, .. } => Some(pose.to_vec()),
            ConfigGoal::Joints { joints, .. } => Some(joints.clone()),
            ConfigGoal::EndEffector { .. } => None,
        };
        if let Some(q) = centre {
            match self.classify(&q) {
                ConfigClass::Collision => {
                    let (d, nearest) = self.clearance(&q);
                    return CspaceError::GoalInCollision {
                        with: nearest_name(nearest),
                        clearance: d,
                        margin: self.margin,
                    };
                }
                ConfigClass::OutsideLimits => return CspaceError::GoalOutsideLimits,
                _ => {}
            }
        }
        if budget_reached {
            CspaceError::GoalNotResolved { budget }
        } else {
            CspaceError::GoalUnreachableRegion
        }
    }
}

/// "obstacle i" or "the workspace boundary".
fn nearest_name(n: Nearest) -> String {
    match n {
        Nearest::Wall => "the workspace boundary".into(),
        Nearest::Obstacle(i) => format!("obstacle {i}"),
        Nearest::Links(i, j) => format!("itself (links {i} and {j})"),
    }
}

impl ConfigSpace {
    /// A face is the goal's exactly when its three corners are in the goal region (to
    /// rounding): carving leaves such faces, stuffing puts its goal faces' corners on the
    /// goal's surface, and a wall, limit or slab face that reaches out of the goal takes the
    /// tag of the part it lies on, so a path that stops on a goal face stops inside the
    /// tolerance.
    fn goal_faces_by_corners(&self, mesh: &mut PeriodicMesh) {
        let tol = 1e-9 * self.spacing;
        let fix = |c: &[Point; 3], tag: BoundaryTag| {
            // The slab's ends are identified, not boundary: they keep their tag.
            if tag == BoundaryTag::Obstacle(SEAM_PART) {
                return tag;
            }
            if c.iter()
                .all(|p| self.goal_value(&self.config_array(p)[..self.dof()]) <= tol)
            {
                return BoundaryTag::Goal(0);
            }
            if tag != BoundaryTag::Goal(0) {
                return tag;
            }
            let centroid = Point::from((c[0].coords + c[1].coords + c[2].coords) / 3.0);
            self.terms(&centroid, false).tag
        };
        mesh.retag(&fix);
    }

    /// The meshing report.
    fn report(
        &self,
        estimated: u64,
        mesh: &PeriodicMesh,
        graded: usize,
        carved: Option<&CarveReport>,
        start: std::time::Instant,
    ) -> CspaceMeshReport {
        CspaceMeshReport {
            spacing: self.spacing,
            scale: self.scale,
            cells: self.cells,
            lattice_tetrahedra: estimated,
            seam_faces: mesh.seam_faces,
            graded,
            refined: carved.map_or(0, |c| c.refine.bisections),
            goal_tetrahedra: carved.and_then(|c| c.carved.first().copied()).unwrap_or(0),
            seconds: start.elapsed().as_secs_f64(),
        }
    }
}

/// The largest term of the space's value at a point ([`ConfigSpace::terms`]): the value,
/// the boundary part it names, and the pair of pieces it was measured between.
#[derive(Clone, Copy, Debug)]
struct Term {
    value: f64,
    tag: BoundaryTag,
    pair: Pair,
}

/// Terms of the space at points, each computed once, shared by every core: tables keyed
/// by the point's bits, in shards so that cores seldom wait for each other.
struct ValueTable(Vec<std::sync::RwLock<HashMap<[u64; 3], Term, BuildBitsHasher>>>);

impl ValueTable {
    fn new() -> Self {
        ValueTable((0..64).map(|_| Default::default()).collect())
    }

    /// The shard of `k`: six middle bits of its hash. Not the top ones: the shard's map
    /// tags each entry with the hash's top seven bits (hashbrown's control byte), and the low
    /// ones pick its bucket, so a shard chosen by either would leave its map those bits
    /// constant (with the top six, a lookup's tag matched about half the entries of each
    /// group it scanned: on a seeded 3-link arm, the lookups took 4.8 % of a one-thread plan's
    /// samples, 3.0 % now, and half the key comparisons).
    fn shard(&self, k: &[u64; 3]) -> &std::sync::RwLock<HashMap<[u64; 3], Term, BuildBitsHasher>> {
        use std::hash::BuildHasher;
        &self.0[((BuildBitsHasher.hash_one(k) >> 32) & 63) as usize]
    }

    fn get(&self, p: &Point) -> Option<Term> {
        let k = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        self.shard(&k).read().ok()?.get(&k).copied()
    }

    fn insert(&self, p: &Point, v: Term) {
        let k = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        if let Ok(mut shard) = self.shard(&k).write() {
            shard.insert(k, v);
        }
    }
}

/// The hasher of the [`ValueTable`]: the coordinates' bits mixed by multiplication (its keys
/// are lattice points and midpoints, which need no protection from chosen collisions).
#[derive(Clone, Copy, Default)]
struct BuildBitsHasher;

#[derive(Default)]
struct BitsHasher(u64);

impl std::hash::Hasher for BitsHasher {
    fn write(&mut self, bytes: &[u8]) {
        // `[u64; 3]` hashes its entries as one byte slice: take them 8 bytes at a time.
        let mut words = bytes.chunks_exact(8);
        for w in &mut words {
            let mut word = [0u8; 8];
            word.copy_from_slice(w);
            self.write_u64(u64::from_le_bytes(word));
        }
        for &b in words.remainder() {
            self.write_u64(b as u64);
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(21) ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 29)
    }
}

impl std::hash::BuildHasher for BuildBitsHasher {
    type Hasher = BitsHasher;
    fn build_hasher(&self) -> BitsHasher {
        BitsHasher::default()
    }
}

/// The configuration space with its goal region stuffed too (for goals thick enough).
struct WithGoal<'a>(&'a ConfigSpace);

impl ImplicitDomain for WithGoal<'_> {
    fn value(&self, p: &Point) -> f64 {
        self.0.terms(p, true).value
    }
    /// The space's grading, without its stored values: they leave the goal out.
    fn grading(&self, spacing: f64) -> Option<Grading<'_>> {
        self.0
            .grading(spacing)
            .map(|g| Grading { known: None, ..g })
    }
    fn tag(&self, p: &Point) -> BoundaryTag {
        self.0.tag(p)
    }
    fn bounds(&self) -> (Point, Point) {
        self.0.bounds()
    }
}

impl ImplicitDomain for ConfigSpace {
    fn value(&self, p: &Point) -> f64 {
        self.terms(p, false).value
    }
    /// Grades the lattice (periodic or not) where its vertices miss what lies between them:
    /// - a sliver of collision, down to a quarter of the spacing: a tetrahedron whose four
    ///   corners are free and whose centroid collides. Such slivers are where the
    ///   configuration-space image of an obstacle is thinner than the lattice: a small
    ///   obstacle, or the tip of an arm at full reach grazing one. The centroid is looked at
    ///   only where every corner is free by less than the robot moves from that corner to
    ///   the centroid ([`Robot::sweep_bound`]): elsewhere it is free for certain.
    /// - a narrow passage, down to half the spacing: a tetrahedron with an edge whose two
    ///   ends collide through different [`Pair`]s of pieces while its middle is free. A door
    ///   barely wider than the robot, or the heading range a long robot must keep through a
    ///   slot, is such a passage: free configurations between two different contacts,
    ///   thinner than the lattice (a 2 × 0.3 bar through a 0.4-thick wall: a 0.8 slot is
    ///   planned at the default spacing, where 1.2 was needed before). Ends that touch
    ///   through one pair are not probed: between them lies one piece's image, not a gap.
    fn grading(&self, spacing: f64) -> Option<Grading<'_>> {
        use std::sync::Arc;
        let floor = spacing / 4.0;
        let table = Arc::new(ValueTable::new());
        let stored = Arc::clone(&table);
        let term = move |p: &Point| -> Term {
            table.get(p).unwrap_or_else(|| {
                let t = self.terms(p, false);
                table.insert(p, t);
                t
            })
        };
        let term = Arc::new(term);
        let dof = self.dof();
        let want = {
            let term = Arc::clone(&term);
            move |p: &[Point; 4]| -> bool {
                let longest = longest_edge(p);
                let c = Point::from((p[0].coords + p[1].coords + p[2].coords + p[3].coords) / 4.0);
                // Around a configuration where a motion met an image the mesh cut across:
                // everything, below the usual floor.
                if longest > REFINE_NEAR_FLOOR * spacing && self.near_refinement(&c) {
                    return true;
                }
                if longest <= floor {
                    return false;
                }
                let t = [term(&p[0]), term(&p[1]), term(&p[2]), term(&p[3])];
                let free = t.iter().filter(|t| t.value < 0.0).count();
                if free < 4 {
                    // A gap between two contacts: an edge whose ends collide through
                    // different pairs, with its middle clearly free (by a twentieth of the
                    // edge: not the tip of the wedge where two images meet). Down to half
                    // the spacing: a quarter, as for slivers, doubled the mesh time of
                    // polygon robots among clutter, where such wedges line every junction
                    // of two obstacles' images, and found no passage more.
                    return longest > 2.0 * floor
                        && EDGES.iter().any(|&[a, b]| {
                            t[a].value >= 0.0
                                && t[b].value >= 0.0
                                && t[a].pair != t[b].pair
                                && term(&Point::from((p[a].coords + p[b].coords) / 2.0)).value
                                    < -0.05 * (p[a] - p[b]).norm()
                        });
                }
                // The centroid can collide only if every corner is free by less than the
                // robot moves from that corner to the centroid.
                let qc = self.config_array(&c);
                if (0..4).any(|k| {
                    -t[k].value
                        >= self
                            .robot
                            .sweep_bound(&self.config_array(&p[k])[..dof], &qc[..dof])
                }) {
                    return false;
                }
                self.terms(&c, false).value > 0.0
            }
        };
        let known = move |p: &Point| stored.get(p).map(|t| t.value);
        let rank = move |c: &Point| term(c).value.abs();
        Some(Grading {
            want: Box::new(want),
            rank: Box::new(rank),
            known: Some(Box::new(known)),
        })
    }
    /// The part whose term is largest, the goal's included (the goal's faces are then
    /// settled by their corners: `ConfigSpace::goal_faces_by_corners`).
    fn tag(&self, p: &Point) -> BoundaryTag {
        self.terms(p, true).tag
    }
    fn bounds(&self) -> (Point, Point) {
        let mut lo = Point::origin();
        let mut hi = Point::origin();
        for a in 0..3 {
            let (l, h) = match self.axes[a] {
                Axis::Position { lo, hi } => (lo, hi),
                Axis::Periodic => (0.0, TAU),
                Axis::Limited { lo, hi } => (lo, hi),
                Axis::Extruded { thickness } => (0.0, thickness / self.scale[a]),
            };
            lo[a] = l * self.scale[a];
            hi[a] = h * self.scale[a];
        }
        // The periodic extent exactly N·h, as the lattice needs.
        for a in 0..3 {
            if let Some(n) = self.cells[a] {
                lo[a] = 0.0;
                hi[a] = n as f64 * self.spacing;
            }
        }
        (lo, hi)
    }
}
