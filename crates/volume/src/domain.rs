//! A volume scene: the workspace solid, obstacle solids (which may overlap each other and
//! cross the workspace boundary), goal regions and a ball robot's radius; free space as an
//! implicit function for the mesher, and the exact clearance of mesh faces.

use harmonic_types::BoundaryTag;

use crate::error::{Part, VolumeError};
use crate::implicit::{Grading, ImplicitDomain};
use crate::solid::{BoxSolid, Point, Solid, SphereSolid, Vector};

/// A goal region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GoalRegion {
    /// A ball.
    Sphere(SphereSolid),
    /// An axis-aligned box.
    Box(BoxSolid),
    /// A point: a small ball whose radius is chosen from the mesh spacing.
    Point(Point),
}

/// Where a point lies with respect to a scene's exact solids (see [`VolumeDomain::classify`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointClass {
    /// In free space: inside the workspace shrunk by the robot radius, outside every goal and
    /// every obstacle inflated by it.
    Free,
    /// Inside goal region `j`.
    Goal(u32),
    /// Inside obstacle `i` inflated by the robot radius.
    Obstacle(u32),
    /// Outside the workspace shrunk by the robot radius.
    OutsideWorkspace,
}

/// Free space of a volume scene: the workspace shrunk by the robot radius, minus the
/// obstacles inflated by it, minus the goal regions (whose boundary is the goal).
#[derive(Clone, Debug)]
pub struct VolumeDomain {
    workspace: Solid,
    obstacles: Vec<Solid>,
    goals: Vec<GoalRegion>,
    robot_radius: f64,
}

impl VolumeDomain {
    /// A validated domain. Solids are validated when they are built; here the goals are
    /// checked (at least one, finite, positive sizes), and the robot radius (finite, ≥ 0,
    /// leaving some workspace).
    pub fn new(
        workspace: Solid,
        obstacles: Vec<Solid>,
        goals: Vec<GoalRegion>,
        robot_radius: f64,
    ) -> Result<Self, VolumeError> {
        if !robot_radius.is_finite() || robot_radius < 0.0 {
            return Err(VolumeError::BadRobotRadius {
                radius: robot_radius,
            });
        }
        if goals.is_empty() {
            return Err(VolumeError::NoGoal);
        }
        for (j, g) in goals.iter().enumerate() {
            let role = Part::Goal(j);
            match g {
                GoalRegion::Sphere(s) => {
                    Solid::new_sphere(role, s.center, s.radius)?;
                }
                GoalRegion::Box(b) => {
                    Solid::new_box(role, b.min, b.max)?;
                }
                GoalRegion::Point(p) => {
                    if !p.iter().all(|c| c.is_finite()) {
                        return Err(VolumeError::NonFinite {
                            solid: role,
                            what: "the goal point".into(),
                        });
                    }
                }
            }
        }
        let (lo, hi) = workspace.bounds();
        if (hi - lo).min() <= 2.0 * robot_radius {
            return Err(VolumeError::EmptyWorkspace {
                radius: robot_radius,
            });
        }
        Ok(VolumeDomain {
            workspace,
            obstacles,
            goals,
            robot_radius,
        })
    }

    /// The workspace solid.
    pub fn workspace(&self) -> &Solid {
        &self.workspace
    }
    /// The obstacle solids, in input order.
    pub fn obstacles(&self) -> &[Solid] {
        &self.obstacles
    }
    /// The goal regions, in input order.
    pub fn goals(&self) -> &[GoalRegion] {
        &self.goals
    }
    /// The robot radius.
    pub fn robot_radius(&self) -> f64 {
        self.robot_radius
    }

    /// Classifies `p` against the exact solids (point goals as balls of `point_goal_radius`):
    /// outside the shrunk workspace first, then goals, then inflated obstacles.
    pub fn classify(&self, p: &Point, point_goal_radius: f64) -> PointClass {
        let r = self.robot_radius;
        if self.workspace.signed_distance(p) > -r {
            return PointClass::OutsideWorkspace;
        }
        for (j, g) in self.goal_solids(point_goal_radius).iter().enumerate() {
            if g.signed_distance(p) <= 0.0 {
                return PointClass::Goal(j as u32);
            }
        }
        for (i, o) in self.obstacles.iter().enumerate() {
            if o.signed_distance(p) < r {
                return PointClass::Obstacle(i as u32);
            }
        }
        PointClass::Free
    }

    /// The goal regions as solids, point goals becoming balls of `point_goal_radius`.
    pub fn goal_solids(&self, point_goal_radius: f64) -> Vec<Solid> {
        self.goals
            .iter()
            .map(|g| match *g {
                GoalRegion::Sphere(s) => Solid::Sphere(s),
                GoalRegion::Box(b) => Solid::Box(b),
                GoalRegion::Point(p) => Solid::Sphere(SphereSolid {
                    center: p,
                    radius: point_goal_radius,
                }),
            })
            .collect()
    }

    /// Free space as an implicit function: point goals become balls of `point_goal_radius`,
    /// obstacles are inflated by the robot radius plus their entry of `obstacle_margins`
    /// (0 where missing) and the workspace shrunk by the radius plus `wall_margin`.
    pub fn implicit(
        &self,
        point_goal_radius: f64,
        obstacle_margins: &[f64],
        wall_margin: f64,
    ) -> DomainImplicit<'_> {
        DomainImplicit {
            domain: self,
            goals: self.goal_solids(point_goal_radius),
            carved: vec![false; self.goals.len()],
            offsets: (0..self.obstacles.len())
                .map(|i| self.robot_radius + obstacle_margins.get(i).copied().unwrap_or(0.0))
                .collect(),
            wall_offset: self.robot_radius + wall_margin,
        }
    }

    /// An estimate of the free volume (workspace minus inflated obstacles and goals) by
    /// sampling a 48³ grid of cell centres over the workspace bounds.
    pub fn free_volume_estimate(&self) -> f64 {
        let f = self.implicit(0.0, &[], 0.0);
        let (lo, hi) = self.workspace.bounds();
        let n = 48usize;
        let d = (hi - lo) / n as f64;
        let mut inside = 0usize;
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let p = lo
                        + Vector::new(
                            (i as f64 + 0.5) * d.x,
                            (j as f64 + 0.5) * d.y,
                            (k as f64 + 0.5) * d.z,
                        );
                    if f.value(&p) < 0.0 {
                        inside += 1;
                    }
                }
            }
        }
        (hi - lo).product() * inside as f64 / (n * n * n) as f64
    }

    /// How far the triangle `tri` (a boundary face of a mesh of this domain) falls short of
    /// the robot's clearance: `r − distance` to each obstacle (raising `obstacles[i]` to it)
    /// and to the workspace boundary (raising `wall`). Exact: parry3d distances to the
    /// obstacles; for a box workspace the distance to its boundary is concave inside it, so
    /// its minimum over the triangle is at a corner. Positive means the face comes closer to
    /// an obstacle or a wall than the robot radius allows (or crosses it). Obstacles farther
    /// than `r` from the triangle's bounding box are skipped (they leave their entry alone).
    pub fn raise_clearance_deficits(&self, tri: [Point; 3], obstacles: &mut [f64], wall: &mut f64) {
        let r = self.robot_radius;
        let (tlo, thi) = (
            tri[0].inf(&tri[1]).inf(&tri[2]),
            tri[0].sup(&tri[1]).sup(&tri[2]),
        );
        for (obstacle, slot) in self.obstacles.iter().zip(obstacles.iter_mut()) {
            let (lo, hi) = obstacle.bounds();
            let gap = (lo - thi).sup(&(tlo - hi)).max();
            if gap > r {
                continue;
            }
            let d = obstacle.distance_to_triangle(tri);
            let mut short = r - d;
            if d == 0.0 {
                // Touching or crossing: how deep do the corners and the centroid go?
                let c = Point::from((tri[0].coords + tri[1].coords + tri[2].coords) / 3.0);
                let depth = tri
                    .iter()
                    .chain(std::iter::once(&c))
                    .map(|p| -obstacle.signed_distance(p))
                    .fold(0.0f64, f64::max);
                short = r + depth;
            }
            *slot = slot.max(short);
        }
        let clearance = match &self.workspace {
            Solid::Box(_) | Solid::Sphere(_) => tri
                .iter()
                .map(|p| -self.workspace.signed_distance(p))
                .fold(f64::INFINITY, f64::min),
            Solid::Surface(_) => {
                let inside = tri.iter().all(|p| self.workspace.signed_distance(p) < 0.0);
                if inside {
                    self.workspace.distance_to_triangle(tri)
                } else {
                    tri.iter()
                        .map(|p| -self.workspace.signed_distance(p))
                        .fold(f64::INFINITY, f64::min)
                }
            }
        };
        *wall = wall.max(r - clearance);
    }
}

/// [`VolumeDomain`] as an [`ImplicitDomain`]: the maximum of the workspace's signed distance
/// (plus the offset) and the negated signed distances of the obstacles (minus the offset) and
/// goals. The tag of a point is the part whose term is largest there.
#[derive(Debug)]
pub struct DomainImplicit<'a> {
    domain: &'a VolumeDomain,
    goals: Vec<Solid>,
    /// Per goal: carved after meshing (left out of the value and the tag).
    carved: Vec<bool>,
    offsets: Vec<f64>,
    wall_offset: f64,
}

impl DomainImplicit<'_> {
    /// The value and the tag of the part attaining it.
    pub fn value_and_tag(&self, p: &Point) -> (f64, BoundaryTag) {
        let mut best = self.domain.workspace.signed_distance(p) + self.wall_offset;
        let mut tag = BoundaryTag::Wall;
        for (i, (o, &offset)) in self.domain.obstacles.iter().zip(&self.offsets).enumerate() {
            // Skip by the bounding box: its distance bounds the signed distance from below.
            let (lo, hi) = o.bounds();
            let gap = (lo - p).sup(&(p - hi)).sup(&Vector::zeros()).norm();
            if gap > 0.0 && offset - gap <= best {
                continue;
            }
            let v = offset - o.signed_distance(p);
            if v > best {
                best = v;
                tag = BoundaryTag::Obstacle(i as u32);
            }
        }
        for (j, g) in self.goals.iter().enumerate() {
            if self.carved[j] {
                continue;
            }
            let v = -g.signed_distance(p);
            if v > best {
                best = v;
                tag = BoundaryTag::Goal(j as u32);
            }
        }
        (best, tag)
    }

    /// The point-goal balls and the other goals as solids.
    pub fn goal_solids(&self) -> &[Solid] {
        &self.goals
    }

    /// Leaves goal `j` out of the value and the tag (when `carved[j]`): it is carved from the
    /// mesh after stuffing ([`VolumeDomain::mesh`]) rather than stuffed.
    pub fn carving(mut self, carved: &[bool]) -> Self {
        for (slot, &c) in self.carved.iter_mut().zip(carved) {
            *slot = c;
        }
        self
    }
}

/// A boundary part of a volume domain, for grading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Surface {
    Wall,
    Obstacle(usize),
}

/// How far below the lattice spacing grading may go.
const GRADING_LEVELS: f64 = 16.0;

impl DomainImplicit<'_> {
    /// The distance from `p` to part `part` grown by its offset, positive on the free side.
    fn part_distance(&self, part: Surface, p: &Point) -> f64 {
        match part {
            Surface::Wall => -self.domain.workspace.signed_distance(p) - self.wall_offset,
            Surface::Obstacle(i) => self.domain.obstacles[i].signed_distance(p) - self.offsets[i],
        }
    }

    /// The part's distance gradient by central differences.
    fn part_gradient(&self, part: Surface, p: &Point, step: f64) -> Vector {
        let mut g = Vector::zeros();
        for a in 0..3 {
            let mut e = Vector::zeros();
            e[a] = step;
            g[a] = (self.part_distance(part, &(p + e)) - self.part_distance(part, &(p - e)))
                / (2.0 * step);
        }
        g
    }

    /// The box a part (grown by its offset) lies in; the workspace's is its own box.
    fn part_bounds(&self, part: Surface) -> (Point, Point) {
        match part {
            Surface::Wall => self.domain.workspace.bounds(),
            Surface::Obstacle(i) => {
                let (lo, hi) = self.domain.obstacles[i].bounds();
                let o = Vector::repeat(self.offsets[i]);
                (lo - o, hi + o)
            }
        }
    }

    /// The thickness below which obstacle `i` (grown by its offset) may slip between the
    /// vertices of a lattice of spacing h, as a multiple of h: a box thinner than h/2 may
    /// hold no lattice plane, a ball narrower than twice the lattice's covering radius
    /// (√5/4 h) may hold no vertex; a surface is judged by its bounding box, like a box.
    /// Returns (thickness, the thickness it must reach in spacings).
    fn thickness(&self, i: usize) -> (f64, f64) {
        let grown = 2.0 * self.offsets[i];
        match &self.domain.obstacles[i] {
            Solid::Sphere(b) => (2.0 * b.radius + grown, 2.0 * 5f64.sqrt() / 4.0),
            other => {
                let (lo, hi) = other.bounds();
                ((hi - lo).min() + grown, 0.5)
            }
        }
    }
}

impl DomainImplicit<'_> {
    /// Whether obstacle `b` (grown) reaches into part `a` (grown; the wall: beyond the
    /// shrunk workspace): such parts leave wedges around where they meet, not passages.
    /// Balls are tested exactly, boxes and surfaces by their boxes.
    fn overlap(&self, a: Surface, b: Surface) -> bool {
        let Surface::Obstacle(j) = b else {
            return false;
        };
        let grown_ball = |k: usize| match &self.domain.obstacles[k] {
            Solid::Sphere(s) => Some((s.center, s.radius + self.offsets[k])),
            _ => None,
        };
        match a {
            Surface::Wall => match grown_ball(j) {
                Some((c, r)) => self.part_distance(Surface::Wall, &c) < r,
                None => {
                    let (lo, hi) = self.part_bounds(b);
                    let (wlo, whi) = self.domain.workspace.bounds();
                    let w = self.wall_offset;
                    (0..3).any(|k| lo[k] < wlo[k] + w || hi[k] > whi[k] - w)
                }
            },
            Surface::Obstacle(i) => match (grown_ball(i), grown_ball(j)) {
                (Some((c, r)), _) => self.part_distance(b, &c) < r,
                (None, Some((c, r))) => self.part_distance(a, &c) < r,
                (None, None) => box_gap(self.part_bounds(a), self.part_bounds(b)) < 0.0,
            },
        }
    }
}

/// Whether `p` is within `margin` of the box `(lo, hi)`.
fn near_box(p: &Point, (lo, hi): (Point, Point), margin: f64) -> bool {
    (0..3).all(|a| p[a] >= lo[a] - margin && p[a] <= hi[a] + margin)
}

/// The gap between two boxes along the axis that separates them most (negative: overlap).
fn box_gap(a: (Point, Point), b: (Point, Point)) -> f64 {
    (0..3)
        .map(|k| (b.0[k] - a.1[k]).max(a.0[k] - b.1[k]))
        .fold(f64::NEG_INFINITY, f64::max)
}

impl ImplicitDomain for DomainImplicit<'_> {
    /// Grades the lattice down to passages between two parts that face each other closer
    /// than the spacing (two obstacles, or an obstacle and a wall) and to obstacles thinner
    /// than it: a tetrahedron near both faces of a passage of width w (its centroid within
    /// its size of each, their normals opposed) is bisected until it is no longer than w/2,
    /// one near a part thin enough to slip between lattice vertices (see `thickness`) until
    /// it cannot, and never below 1/16 of the spacing. A part too thin even for that size
    /// is not refined for (it would slip between the finest vertices too; paths through it
    /// are `collision`s). Parts that overlap or share a face leave no passage and are not
    /// refined for. Only pairs whose boxes come that close are examined, so a scene without
    /// narrow passages or thin parts keeps the uniform lattice.
    fn grading(&self, spacing: f64) -> Option<Grading<'_>> {
        let n = self.domain.obstacles.len();
        let mut pairs: Vec<(Surface, Surface)> = Vec::new();
        for i in 0..n {
            let bi = self.part_bounds(Surface::Obstacle(i));
            for j in i + 1..n {
                let bj = self.part_bounds(Surface::Obstacle(j));
                let (a, b) = (Surface::Obstacle(i), Surface::Obstacle(j));
                if box_gap(bi, bj) < spacing && !self.overlap(a, b) {
                    pairs.push((a, b));
                }
            }
            // Near a wall of the workspace's box (from inside).
            let (wlo, whi) = self.domain.workspace.bounds();
            let w = self.wall_offset;
            let to_wall = (0..3)
                .map(|a| (bi.0[a] - wlo[a] - w).min(whi[a] - w - bi.1[a]))
                .fold(f64::INFINITY, f64::min);
            if to_wall < spacing && !self.overlap(Surface::Wall, Surface::Obstacle(i)) {
                pairs.push((Surface::Wall, Surface::Obstacle(i)));
            }
        }
        // A part too thin even for the finest size would slip between its vertices too:
        // refining over its whole surface would only cost time and memory (a 0.2 mm plate
        // across a 10 m box took minutes and gigabytes), so it is left to the exact check of
        // every path, which calls a motion through it a collision.
        let floor = spacing / GRADING_LEVELS;
        let thin: Vec<usize> = (0..n)
            .filter(|&i| {
                let (t, need) = self.thickness(i);
                t < need * spacing && t >= need * floor
            })
            .collect();
        if pairs.is_empty() && thin.is_empty() {
            return None;
        }
        // Where each pair's faces can both be within a spacing of a point, and where a thin
        // part's surface can be: a box test rejects every other tetrahedron cheaply.
        let grow =
            |(lo, hi): (Point, Point), m: f64| (lo - Vector::repeat(m), hi + Vector::repeat(m));
        let pairs: Vec<(Surface, Surface, (Point, Point))> = pairs
            .into_iter()
            .map(|(a, b)| {
                let (ba, bb) = (
                    grow(self.part_bounds(a), spacing),
                    grow(self.part_bounds(b), spacing),
                );
                let zone = match a {
                    Surface::Wall => bb,
                    Surface::Obstacle(_) => (ba.0.sup(&bb.0), ba.1.inf(&bb.1)),
                };
                (a, b, zone)
            })
            .collect();
        let thin: Vec<(usize, (Point, Point))> = thin
            .into_iter()
            .map(|i| (i, grow(self.part_bounds(Surface::Obstacle(i)), spacing)))
            .collect();
        let zones: Vec<(Point, Point)> = pairs
            .iter()
            .map(|p| p.2)
            .chain(thin.iter().map(|t| t.1))
            .collect();
        let want = move |p: &[Point; 4]| -> bool {
            let s = crate::refine::longest_edge(p);
            if s <= floor {
                return false;
            }
            let c = Point::from((p[0].coords + p[1].coords + p[2].coords + p[3].coords) / 4.0);
            for &(a, b, zone) in &pairs {
                if !near_box(&c, zone, 0.0) {
                    continue;
                }
                let (da, db) = (self.part_distance(a, &c), self.part_distance(b, &c));
                // A passage of positive width (parts that overlap or share a face leave none).
                let width = da + db;
                // Passages narrower than the finest size are left closed: no interior vertex
                // would fit in them anyway.
                // So are passages the lattice keeps open by itself (a spacing wide or more).
                if da.abs() >= s
                    || db.abs() >= s
                    || width < 2.0 * floor
                    || width >= spacing
                    || s <= 0.5 * width
                {
                    continue;
                }
                let step = 1e-3 * s;
                let (ga, gb) = (
                    self.part_gradient(a, &c, step),
                    self.part_gradient(b, &c, step),
                );
                if ga.dot(&gb) < -0.5 * ga.norm() * gb.norm() {
                    return true;
                }
            }
            thin.iter().any(|&(i, zone)| {
                near_box(&c, zone, 0.0)
                    && self.part_distance(Surface::Obstacle(i), &c).abs() < s
                    && {
                        let (t, need) = self.thickness(i);
                        s * need > t
                    }
            })
        };
        // Ties are broken towards the zones: the distance to the nearest one.
        let rank = move |c: &Point| {
            zones
                .iter()
                .map(|(lo, hi)| (lo - c).sup(&(c - hi)).sup(&Vector::zeros()).norm())
                .fold(f64::INFINITY, f64::min)
        };
        Some(Grading {
            want: Box::new(want),
            rank: Box::new(rank),
            known: None,
        })
    }

    fn value(&self, p: &Point) -> f64 {
        self.value_and_tag(p).0
    }
    /// The part whose term is largest; carved goals are left to [`VolumeDomain::mesh`], which
    /// gives a face to a carved goal when its three corners lie in it.
    fn tag(&self, p: &Point) -> BoundaryTag {
        self.value_and_tag(p).1
    }
    fn bounds(&self) -> (Point, Point) {
        let (lo, hi) = self.domain.workspace.bounds();
        let o = Vector::repeat(self.wall_offset.min(0.0));
        (lo + o, hi - o)
    }
}
