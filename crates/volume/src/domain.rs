//! A volume scene: the workspace solid, obstacle solids (which may overlap each other and
//! cross the workspace boundary), goal regions and a ball robot's radius; free space as an
//! implicit function for the mesher, and the exact clearance of mesh faces.

use harmonic_mesh::BoundaryTag;

use crate::error::{SolidRole, VolumeError};
use crate::implicit::ImplicitDomain;
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
            let role = SolidRole::Goal(j);
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
    /// Per goal: carved after meshing (left out of the value, kept in the tag).
    carved: Vec<bool>,
    offsets: Vec<f64>,
    wall_offset: f64,
}

impl DomainImplicit<'_> {
    /// The value and the tag of the part attaining it.
    pub fn value_and_tag(&self, p: &Point) -> (f64, BoundaryTag) {
        self.value_and_tag_of(p, false)
    }

    /// As [`value_and_tag`](Self::value_and_tag), with the carved goals counted too when
    /// `carved` is set (how faces of a carved goal get its tag).
    fn value_and_tag_of(&self, p: &Point, carved: bool) -> (f64, BoundaryTag) {
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
            if self.carved[j] && !carved {
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

    /// Leaves goal `j` out of the value (when `carved[j]`): it is carved from the mesh after
    /// stuffing ([`VolumeDomain::mesh`]) rather than stuffed, but still names its faces.
    pub fn carving(mut self, carved: &[bool]) -> Self {
        for (slot, &c) in self.carved.iter_mut().zip(carved) {
            *slot = c;
        }
        self
    }
}

impl ImplicitDomain for DomainImplicit<'_> {
    fn value(&self, p: &Point) -> f64 {
        self.value_and_tag(p).0
    }
    fn tag(&self, p: &Point) -> BoundaryTag {
        self.value_and_tag_of(p, true).1
    }
    fn bounds(&self) -> (Point, Point) {
        let (lo, hi) = self.domain.workspace.bounds();
        let o = Vector::repeat(self.wall_offset.min(0.0));
        (lo + o, hi - o)
    }
}
