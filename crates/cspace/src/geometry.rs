//! The plane the robot moves in: the workspace polygon, obstacle polygons and discs, cut into
//! convex parts for parry2d's exact convex–convex distances (GJK), with bounding boxes so
//! that far parts cost one box test. Parry triangulates a polygon (ear clipping) and merges
//! the triangles into convex pieces (Hertel–Mehlhorn); nothing here is hand-written beyond
//! the orientation and validity checks.

use parry2d_f64::bounding_volume::Aabb;
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query;
use parry2d_f64::shape::{Ball, ConvexPolygon, Cuboid, HalfSpace, Segment, Shape, TriMesh};
use parry2d_f64::transformation::hertel_mehlhorn;

use crate::error::CspaceError;

/// A convex piece of a robot or an obstacle.
#[derive(Clone, Debug)]
pub enum Part {
    /// A convex polygon.
    Polygon(ConvexPolygon),
    /// A disc.
    Ball(Ball),
    /// A segment (a link of zero width).
    Segment(Segment),
    /// A rectangle centred on its pose (a link of some width).
    Cuboid(Cuboid),
}

impl Part {
    /// The parry shape.
    pub fn shape(&self) -> &dyn Shape {
        match self {
            Part::Polygon(p) => p,
            Part::Ball(b) => b,
            Part::Segment(s) => s,
            Part::Cuboid(c) => c,
        }
    }
}

/// Checks a simple polygon (≥ 3 finite vertices, non-zero area, no two edges crossing) and
/// returns it counter-clockwise. `what` names it in errors (a JSON path).
pub fn checked_ring(ring: &[[f64; 2]], what: &str) -> Result<Vec<[f64; 2]>, CspaceError> {
    let bad = |message: String| CspaceError::Invalid {
        path: what.to_string(),
        message,
    };
    if ring.len() < 3 {
        return Err(bad(format!(
            "a polygon needs at least 3 vertices, got {}",
            ring.len()
        )));
    }
    if let Some(i) = ring.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(bad(format!("vertex {i} is not finite")));
    }
    let a2 = 2.0 * harmonic_mesh::geom::signed_area(ring);
    if a2.abs() <= 1e-12 * bbox_size(ring).powi(2) {
        return Err(bad("the polygon has no area".into()));
    }
    let n = ring.len();
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            let (c, d) = (ring[j], ring[(j + 1) % n]);
            let pt = |p: [f64; 2]| harmonic_mesh::Point::new(p[0], p[1]);
            if harmonic_mesh::geom::segments_intersect(pt(a), pt(b), pt(c), pt(d)) {
                return Err(bad(format!(
                    "edges {i} and {j} cross: not a simple polygon"
                )));
            }
        }
    }
    let mut out = ring.to_vec();
    if a2 < 0.0 {
        out.reverse();
    }
    Ok(out)
}

fn bbox_size(ring: &[[f64; 2]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in ring {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (hi[0] - lo[0]).max(hi[1] - lo[1])
}

/// Convex parts of a counter-clockwise simple polygon.
pub fn convex_parts(ring: &[[f64; 2]], what: &str) -> Result<Vec<Part>, CspaceError> {
    let pts: Vec<Vector> = ring.iter().map(|p| Vector::new(p[0], p[1])).collect();
    let fail = || CspaceError::Invalid {
        path: what.to_string(),
        message: "the polygon could not be cut into convex parts".into(),
    };
    let mesh = TriMesh::from_polygon(pts.clone()).ok_or_else(fail)?;
    let pieces = hertel_mehlhorn(&pts, mesh.indices());
    let parts: Vec<Part> = pieces
        .into_iter()
        .filter_map(|p| ConvexPolygon::from_convex_polyline(p).map(Part::Polygon))
        .collect();
    if parts.is_empty() {
        return Err(fail());
    }
    Ok(parts)
}

/// An obstacle: its exact outline and its convex parts.
#[derive(Clone, Debug)]
pub struct Obstacle {
    /// The outline (counter-clockwise), or `None` for a disc.
    pub ring: Option<Vec<[f64; 2]>>,
    /// A disc's centre and radius.
    pub disc: Option<([f64; 2], f64)>,
    /// Convex parts (in world coordinates) with their boxes.
    pub parts: Vec<(Part, Aabb)>,
}

/// The workspace and its obstacles.
#[derive(Clone, Debug)]
pub struct World {
    /// The workspace outline, counter-clockwise.
    pub workspace: Vec<[f64; 2]>,
    /// Its edges with their boxes.
    walls: Vec<(Wall, Aabb)>,
    /// The obstacles.
    pub obstacles: Vec<Obstacle>,
}

/// A workspace edge as the distance queries see it. An edge whose line has the whole
/// workspace on one side is the solid half-plane beyond it: for a robot part inside the
/// workspace its distance to that half-plane is its distance to the edge whenever the edge
/// is the nearest boundary (the line's points off the edge lie outside the workspace, so no
/// nearer to an inside point than the boundary is), and parry measures it with one support
/// point where a segment takes a GJK run. Every edge of a convex workspace is such a line;
/// the others (at a reflex corner) stay segments.
#[derive(Clone, Debug)]
enum Wall {
    /// The solid half-plane beyond the edge, placed at the edge's first end.
    Line(HalfSpace, Pose),
    /// The edge itself.
    Segment(Segment),
}

impl Wall {
    /// The edge from `a` to `b` of the counter-clockwise `workspace`.
    fn new(a: [f64; 2], b: [f64; 2], workspace: &[[f64; 2]]) -> Wall {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        // The inward normal (left of a → b); the solid lies on its negative side.
        let inward = Vector::new(-dy / len, dx / len);
        let tol = 1e-12 * bbox_size(workspace);
        let supporting = workspace
            .iter()
            .all(|p| inward.dot(Vector::new(p[0] - a[0], p[1] - a[1])) >= -tol);
        if supporting && len > 0.0 {
            Wall::Line(HalfSpace::new(inward), Pose::translation(a[0], a[1]))
        } else {
            Wall::Segment(Segment::new(
                Vector::new(a[0], a[1]),
                Vector::new(b[0], b[1]),
            ))
        }
    }

    fn shape(&self) -> (&dyn Shape, Pose) {
        match self {
            Wall::Line(h, pose) => (h, *pose),
            Wall::Segment(s) => (s, Pose::IDENTITY),
        }
    }
}

/// What a robot's nearest thing is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Nearest {
    /// A workspace edge (or the robot is outside the workspace).
    Wall,
    /// Obstacle `i`.
    Obstacle(u32),
    /// An arm's own links `i` and `j` (not adjacent).
    Links(u32, u32),
}

/// Which two convex pieces are nearest each other: one of the robot's parts and one piece of
/// the world (a workspace edge, an obstacle's convex part), or two of an arm's links. Two
/// configurations in collision through different pairs are blocked by different things, so
/// free space may lie between them however close they are; the same pair says nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Pair {
    /// The robot's part (an arm's link), or the first of two links.
    pub robot: u32,
    /// The world's piece: workspace edges first, then every obstacle's convex parts in
    /// order; for two links, [`Pair::LINKS`] plus the second link.
    pub world: u32,
}

impl Pair {
    /// Added to [`Pair::world`] for the second of two links.
    pub const LINKS: u32 = 1 << 31;
}

impl World {
    /// A validated world: the workspace a simple polygon, obstacles polygons or discs
    /// (`obstacles[i]` named in errors).
    pub fn new(workspace: &[[f64; 2]], obstacles: &[ObstacleInput]) -> Result<World, CspaceError> {
        let workspace = checked_ring(workspace, "workspace")?;
        let walls = (0..workspace.len())
            .map(|i| {
                let (a, b) = (workspace[i], workspace[(i + 1) % workspace.len()]);
                let wall = Wall::new(a, b, &workspace);
                // The box is a lower bound of a part's distance: a line's is the plane.
                let bb = match &wall {
                    Wall::Line(..) => Aabb::new(
                        Vector::splat(f64::NEG_INFINITY),
                        Vector::splat(f64::INFINITY),
                    ),
                    Wall::Segment(s) => s.compute_aabb(&Pose::IDENTITY),
                };
                (wall, bb)
            })
            .collect();
        let mut out = Vec::new();
        for (i, o) in obstacles.iter().enumerate() {
            let what = format!("obstacles[{i}]");
            match o {
                ObstacleInput::Polygon(ring) => {
                    let ring = checked_ring(ring, &format!("{what}.polygon"))?;
                    let parts = convex_parts(&ring, &format!("{what}.polygon"))?
                        .into_iter()
                        .map(|p| {
                            let bb = p.shape().compute_aabb(&Pose::IDENTITY);
                            (p, bb)
                        })
                        .collect();
                    out.push(Obstacle {
                        ring: Some(ring),
                        disc: None,
                        parts,
                    });
                }
                ObstacleInput::Circle { center, radius } => {
                    if !(radius.is_finite()
                        && *radius > 0.0
                        && center.iter().all(|c| c.is_finite()))
                    {
                        return Err(CspaceError::Invalid {
                            path: format!("{what}.circle"),
                            message: "a circle needs a finite centre and a positive radius".into(),
                        });
                    }
                    let ball = Ball::new(*radius);
                    let pose = Pose::translation(center[0], center[1]);
                    let bb = ball.compute_aabb(&pose);
                    out.push(Obstacle {
                        ring: None,
                        disc: Some((*center, *radius)),
                        parts: vec![(Part::Ball(ball), bb)],
                    });
                }
            }
        }
        Ok(World {
            workspace,
            walls,
            obstacles: out,
        })
    }

    /// The workspace's bounding box `([xmin, ymin], [xmax, ymax])`.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &self.workspace {
            for a in 0..2 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        (lo, hi)
    }

    /// The size of the scene (the workspace box's larger side).
    pub fn size(&self) -> f64 {
        let (lo, hi) = self.bounds();
        (hi[0] - lo[0]).max(hi[1] - lo[1])
    }

    /// Whether `p` lies inside the workspace polygon.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        harmonic_mesh::geom::polygon_contains(&self.workspace, p)
    }

    /// The distance from a placed robot (convex parts with their poses, and one point of
    /// it) to the nearest wall or obstacle, and which that is. Inside an obstacle or
    /// touching one: 0. Outside the workspace the distance is returned negated (so that
    /// `margin − d` stays continuous and positive there).
    pub fn clearance(&self, robot: &[(Pose, &Part)], point: [f64; 2]) -> (f64, Nearest) {
        let (d, nearest, _) = self.nearest_pair(robot, point);
        (d, nearest)
    }

    /// [`World::clearance`], and the [`Pair`] it was measured between (in collision: the
    /// first pair found touching).
    pub fn nearest_pair(&self, robot: &[(Pose, &Part)], point: [f64; 2]) -> (f64, Nearest, Pair) {
        let placed: Vec<(Pose, &dyn Shape, Aabb)> = robot
            .iter()
            .map(|(pose, part)| (*pose, part.shape(), part.shape().compute_aabb(pose)))
            .collect();
        let mut best = f64::INFINITY;
        let mut nearest = (Nearest::Wall, Pair::default());
        // Whether two boxes are at least `d` apart (a part in the one at least that far
        // from a piece in the other), compared squared.
        let apart = |a: &Aabb, b: &Aabb, d: f64| {
            let dx = (b.mins.x - a.maxs.x).max(a.mins.x - b.maxs.x).max(0.0);
            let dy = (b.mins.y - a.maxs.y).max(a.mins.y - b.maxs.y).max(0.0);
            dx * dx + dy * dy >= d * d
        };
        let mut piece = 0u32;
        let mut measure =
            |shape: &dyn Shape, pose: &Pose, bb: &Aabb, what: Nearest, best: &mut f64| {
                for (r, (rp, rs, rb)) in placed.iter().enumerate() {
                    if apart(rb, bb, *best) {
                        continue;
                    }
                    let d = query::distance(rp, *rs, pose, shape)
                        .map(|d| d.distance)
                        .unwrap_or(0.0);
                    if d < *best {
                        *best = d;
                        let pair = Pair {
                            robot: r as u32,
                            world: piece,
                        };
                        nearest = (what, pair);
                    }
                }
                piece += 1;
            };
        for (wall, bb) in &self.walls {
            let (shape, pose) = wall.shape();
            measure(shape, &pose, bb, Nearest::Wall, &mut best);
        }
        for (i, o) in self.obstacles.iter().enumerate() {
            for (p, bb) in &o.parts {
                let pose = match o.disc {
                    Some((c, _)) => Pose::translation(c[0], c[1]),
                    None => Pose::IDENTITY,
                };
                measure(p.shape(), &pose, bb, Nearest::Obstacle(i as u32), &mut best);
            }
        }
        let best = best.max(0.0);
        if !self.contains(point) {
            return (-best, Nearest::Wall, nearest.1);
        }
        (best, nearest.0, nearest.1)
    }
}

/// An obstacle as the scene gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum ObstacleInput {
    /// A polygon, either orientation.
    Polygon(Vec<[f64; 2]>),
    /// A disc.
    Circle {
        /// Centre.
        center: [f64; 2],
        /// Radius.
        radius: f64,
    },
}

/// The smallest distance between two parts of `placed` that are not neighbours in the list
/// (an arm's links i and j with j ≥ i + 2; adjacent links share a joint), and which two;
/// `None` for fewer than three parts.
pub fn self_clearance(placed: &[(Pose, &Part)]) -> Option<(f64, Nearest)> {
    let mut best: Option<(f64, Nearest)> = None;
    for i in 0..placed.len() {
        for j in i + 2..placed.len() {
            let (pi, a) = placed[i];
            let (pj, b) = placed[j];
            let d = query::distance(&pi, a.shape(), &pj, b.shape())
                .map(|d| d.distance)
                .unwrap_or(0.0);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, Nearest::Links(i as u32, j as u32)));
            }
        }
    }
    best
}
