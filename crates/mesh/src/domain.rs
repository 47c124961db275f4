//! The free space of a scene: validated input shapes, merged obstacles, tagged boundary rings,
//! and exact clearance queries.

use std::collections::HashMap;

use geo::{
    Area, BooleanOps, Buffer, Coord, Intersects, LineString, MultiPolygon, Polygon,
    buffer::{BufferStyle, LineJoin},
    unary_union,
};
use serde::{Deserialize, Serialize};

use crate::frame::Frame;
use crate::geom::{SegmentIndex, point_segment_dist2, segments_intersect};
use crate::geom::{signed_area, twice_signed_area};
use crate::options::MeshOptions;
use crate::touch::{Rings, dedup_rings, multipolygon_of, rings_of, snap_near_touches};
use crate::{BoundaryTag, MeshError, Part, Point};

mod constraints;
mod isolated;
mod of_mesh;
mod of_rings;

pub(crate) use constraints::Constraints;

/// An obstacle shape, in workspace coordinates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// A simple polygon, either orientation, not closed (the last vertex is not repeated).
    Polygon(Vec<Point>),
    /// A disc, meshed as a regular polygon whose edges are at most the target edge length.
    Circle {
        /// Centre of the disc.
        center: Point,
        /// Radius, positive.
        radius: f64,
    },
}

/// A goal region, in workspace coordinates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GoalShape {
    /// A simple polygon, either orientation.
    Polygon(Vec<Point>),
    /// A disc.
    Circle {
        /// Centre of the disc.
        center: Point,
        /// Radius, positive.
        radius: f64,
    },
    /// A point; it becomes a small disc of radius twice the target edge length (at most half
    /// the distance to the nearest wall or obstacle).
    Point(Point),
}

/// The input of [`Domain::new`]: a workspace polygon, obstacles, goals and a robot radius.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DomainSpec {
    /// The outer boundary, a simple polygon (either orientation).
    pub workspace: Vec<Point>,
    /// Obstacles; they may overlap each other and cross the workspace boundary.
    pub obstacles: Vec<Shape>,
    /// Goal regions; they become holes of free space whose boundary is tagged `Goal(j)`.
    pub goals: Vec<GoalShape>,
    /// Radius of a disc robot: obstacles are inflated and the workspace shrunk by it (0: point robot).
    #[serde(default)]
    pub robot_radius: f64,
}

/// A closed boundary ring of free space with a tag per edge.
///
/// Edge `k` runs from `points[k]` to `points[(k + 1) % n]` and carries `tags[k]`. Outer rings
/// are counter-clockwise and holes clockwise, so free space is always on the left.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaggedRing {
    /// The ring's vertices, not repeated at the end.
    pub points: Vec<Point>,
    /// `tags[k]` is the tag of the edge from `points[k]` to the next point.
    pub tags: Vec<BoundaryTag>,
}

/// A merged region (obstacles after union, goals, or the workspace after shrinking).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// Counter-clockwise exterior ring.
    pub exterior: Vec<Point>,
    /// Clockwise holes.
    pub holes: Vec<Vec<Point>>,
    /// Input indices (obstacles or goals) that make up this region.
    pub sources: Vec<u32>,
}

/// The validated free space of a scene, ready to mesh.
#[derive(Clone, Debug)]
pub struct Domain {
    free: Vec<TaggedRing>,
    workspace: Vec<Region>,
    obstacles: Vec<Region>,
    goals: Vec<Region>,
    free_area: f64,
    scale: f64,
    bbox: (Point, Point),
    target_edge: f64,
    robot_radius: f64,
    /// Every free-space boundary edge (for the even-odd inside test and clearance), with its
    /// position among the edges of `free`, ring after ring. Built with the domain where
    /// validation needs it; for a mesh made elsewhere ([`Domain::of_mesh`]) at the first
    /// query or by [`Domain::prepare_queries`], beside the solve.
    boundary_index: std::sync::OnceLock<SegmentIndex>,
    /// Which free-space boundary edges (numbered as in `boundary_index`) are goal edges,
    /// which clearance leaves out: found at the first clearance query (meshing needs none).
    goal_edges: std::sync::OnceLock<Vec<bool>>,
    /// The map from the scene's coordinates to the unit coordinates every field above is in
    /// (see [`Frame`]).
    frame: Frame,
    /// `free` in the scene's coordinates (what [`Domain::free_rings`] returns).
    user_free: Vec<TaggedRing>,
    /// Interior segments and points the mesh must hold, in unit coordinates (see
    /// [`Domain::with_constraints`]).
    constraints: Constraints,
}

/// Drops the edges that two oriented rings of one polygon share in opposite directions and
/// chains the remaining edges into rings again.
///
/// Boolean operations can return an obstacle flush with the workspace boundary as a hole whose
/// edge coincides with an edge of the exterior ring (after snapping, exactly). Such a pair
/// bounds nothing — free space lies on neither side — and as triangulation constraints it makes
/// every face look like a hole. Cancelling the pair turns exterior and hole into one notched
/// exterior, which is what the region is.
fn cancel_shared_edges(rings: Vec<TaggedRing>) -> Vec<TaggedRing> {
    type Key = (u64, u64);
    let key = |p: Point| -> Key { (p.x.to_bits(), p.y.to_bits()) };
    let edges: Vec<(Point, Point, BoundaryTag)> = rings
        .iter()
        .flat_map(|r| {
            let n = r.points.len();
            (0..n).map(move |k| (r.points[k], r.points[(k + 1) % n], r.tags[k]))
        })
        .collect();
    let directed: std::collections::HashSet<(Key, Key)> =
        edges.iter().map(|&(a, b, _)| (key(a), key(b))).collect();
    let shared = |&(a, b, _): &(Point, Point, BoundaryTag)| directed.contains(&(key(b), key(a)));
    if !edges.iter().any(shared) {
        return rings;
    }
    let kept: Vec<(Point, Point, BoundaryTag)> =
        edges.iter().copied().filter(|e| !shared(e)).collect();
    let mut leaving: HashMap<Key, Vec<usize>> = HashMap::new();
    for (i, &(a, _, _)) in kept.iter().enumerate() {
        leaving.entry(key(a)).or_default().push(i);
    }
    let mut used = vec![false; kept.len()];
    let mut out = Vec::new();
    for first in 0..kept.len() {
        if used[first] {
            continue;
        }
        let (mut points, mut tags) = (Vec::new(), Vec::new());
        let mut e = first;
        loop {
            used[e] = true;
            points.push(kept[e].0);
            tags.push(kept[e].2);
            let end = key(kept[e].1);
            if end == key(kept[first].0) {
                break;
            }
            match leaving
                .get(&end)
                .and_then(|next| next.iter().copied().find(|&k| !used[k]))
            {
                Some(k) => e = k,
                None => break,
            }
        }
        if points.len() >= 3 && signed_area(&points) != 0.0 {
            out.push(TaggedRing { points, tags });
        }
    }
    out
}

/// The target edge length of an equilateral triangle of area `max_area`.
pub(crate) fn edge_for_area(max_area: f64) -> f64 {
    (4.0 * max_area / 3f64.sqrt()).sqrt()
}

pub(crate) fn bbox_of(points: &[Point]) -> (Point, Point) {
    let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in points {
        lo.x = lo.x.min(p.x);
        lo.y = lo.y.min(p.y);
        hi.x = hi.x.max(p.x);
        hi.y = hi.y.max(p.y);
    }
    (lo, hi)
}

/// Validates a user polygon and returns it counter-clockwise without duplicate or collinear
/// vertices.
fn clean_ring(part: Part, input: &[Point]) -> Result<Vec<Point>, MeshError> {
    for (vertex, p) in input.iter().enumerate() {
        if !p.x.is_finite() || !p.y.is_finite() {
            return Err(MeshError::NonFinite { part, vertex });
        }
    }
    // (point, index of the input vertex it came from)
    let mut ring: Vec<(Point, usize)> = Vec::with_capacity(input.len());
    for (i, &p) in input.iter().enumerate() {
        if ring.last().is_none_or(|&(q, _)| q != p) {
            ring.push((p, i));
        }
    }
    while ring.len() > 1 && ring[0].0 == ring[ring.len() - 1].0 {
        ring.pop();
    }
    let distinct = ring.len();
    // Drop collinear vertices (including spikes) until none is left.
    loop {
        let n = ring.len();
        if n < 3 {
            break;
        }
        let mut removed = false;
        let mut i = 0;
        while i < ring.len() && ring.len() >= 3 {
            let n = ring.len();
            let a = ring[(i + n - 1) % n].0;
            let b = ring[i].0;
            let c = ring[(i + 1) % n].0;
            let o = twice_signed_area(a, b, c);
            if o.abs() <= 1e-13 * (b - a).norm() * (c - b).norm() {
                ring.remove(i);
                removed = true;
            } else {
                i += 1;
            }
        }
        if !removed {
            break;
        }
    }
    if ring.len() < 3 && distinct >= 3 {
        return Err(MeshError::ZeroArea { part });
    }
    if ring.len() < 3 {
        return Err(MeshError::TooFewVertices {
            part,
            count: ring.len(),
        });
    }
    let n = ring.len();
    // Candidate pairs from an R-tree of the edges' boxes: O(n log n) for a simple polygon,
    // where comparing every pair took seconds at 50 000 vertices.
    let boxes: Vec<rstar::primitives::GeomWithData<rstar::primitives::Rectangle<[f64; 2]>, usize>> =
        (0..n)
            .map(|i| {
                let (lo, hi) = bbox_of(&[ring[i].0, ring[(i + 1) % n].0]);
                rstar::primitives::GeomWithData::new(
                    rstar::primitives::Rectangle::from_corners([lo.x, lo.y], [hi.x, hi.y]),
                    i,
                )
            })
            .collect();
    let tree = rstar::RTree::bulk_load(boxes.clone());
    let mut first: Option<(usize, usize)> = None;
    for b in &boxes {
        let i = b.data;
        for other in tree.locate_in_envelope_intersecting(&rstar::RTreeObject::envelope(b.geom())) {
            let j = other.data;
            if j <= i || j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            if segments_intersect(
                ring[i].0,
                ring[(i + 1) % n].0,
                ring[j].0,
                ring[(j + 1) % n].0,
            ) && first.is_none_or(|f| (i, j) < f)
            {
                first = Some((i, j));
            }
        }
    }
    if let Some((i, j)) = first {
        return Err(MeshError::SelfIntersection {
            part,
            edges: (ring[i].1, ring[j].1),
        });
    }
    let mut points: Vec<Point> = ring.into_iter().map(|(p, _)| p).collect();
    let area = signed_area(&points);
    let (lo, hi) = bbox_of(&points);
    if area.abs() <= 1e-14 * (hi - lo).norm_squared() {
        return Err(MeshError::ZeroArea { part });
    }
    if area < 0.0 {
        points.reverse();
    }
    Ok(points)
}

/// A regular polygon inscribed in the circle, counter-clockwise, vertex `k` at angle
/// `2πk/n`, with `n` chosen so that each chord is at most `h` (at least 12, at most 4096
/// vertices). The chord error (sagitta) is then at most `h²/(8r)`.
pub(crate) fn circle_polygon(
    part: Part,
    center: Point,
    radius: f64,
    h: f64,
) -> Result<Vec<Point>, MeshError> {
    check_circle(part, center, radius)?;
    Ok(regular_polygon(center, radius, sides(radius, h, 12)))
}

/// A finite centre and a positive, finite radius, or the error naming `part`.
fn check_circle(part: Part, center: Point, radius: f64) -> Result<(), MeshError> {
    if !center.x.is_finite() || !center.y.is_finite() {
        return Err(MeshError::NonFinite { part, vertex: 0 });
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err(MeshError::InvalidRadius { part, radius });
    }
    Ok(())
}

/// Sides of chords at most `h` on a circle of `radius`, from `fewest` to 4096.
fn sides(radius: f64, h: f64, fewest: usize) -> usize {
    ((std::f64::consts::TAU * radius / h).ceil() as usize).clamp(fewest, 4096)
}

/// `n` points evenly spaced on the circle of `radius` around `center`, counter-clockwise from
/// angle 0.
fn regular_polygon(center: Point, radius: f64, n: usize) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            Point::new(center.x + radius * t.cos(), center.y + radius * t.sin())
        })
        .collect()
}

/// The disc around a point goal: a regular polygon with sides of about the target edge `h`
/// (at least 6), its `k`-th of `n` vertices pulled in to `1 − k / (4n)` of `radius`. The
/// goal's shape is the mesher's choice. On a regular polygon every four vertices are
/// cocircular: each Delaunay in-circle test among them is a tie its exact arithmetic
/// resolves slowly (about 14 000 instructions, dozens per mesh); on this slow spiral none
/// are, and the disc still reaches `radius`. A disc near a wall is much smaller than `h`, and
/// refinement grades the mesh down to its sides: 6 of them rather than a circle's 12 take a
/// twentieth off a small map's mesh (tb3_sandbox 493 → 463 triangles).
pub(crate) fn point_goal_polygon(
    part: Part,
    center: Point,
    radius: f64,
    h: f64,
) -> Result<Vec<Point>, MeshError> {
    check_circle(part, center, radius)?;
    let mut ring = regular_polygon(center, radius, sides(radius, h, 6));
    let n = ring.len() as f64;
    for (k, p) in ring.iter_mut().enumerate() {
        let s = 1.0 - k as f64 / (4.0 * n);
        *p = Point::new(
            center.x + s * (p.x - center.x),
            center.y + s * (p.y - center.y),
        );
    }
    Ok(ring)
}

fn to_geo(points: &[Point]) -> Polygon<f64> {
    Polygon::new(
        LineString::from(
            points
                .iter()
                .map(|p| Coord { x: p.x, y: p.y })
                .collect::<Vec<_>>(),
        ),
        vec![],
    )
}

fn from_ls(ls: &LineString<f64>) -> Vec<Point> {
    let mut v: Vec<Point> = ls.0.iter().map(|c| Point::new(c.x, c.y)).collect();
    if v.len() > 1 && v[0] == v[v.len() - 1] {
        v.pop();
    }
    v
}

fn regions_of(mp: &MultiPolygon<f64>, parts: &[MultiPolygon<f64>]) -> Vec<Region> {
    use geo::BoundingRect;
    use rstar::primitives::{GeomWithData, Rectangle};
    // The parts' bounding boxes in an R-tree: which parts make up a region is then a box
    // query and a few exact tests, not a test of every part against every region (a forest
    // of 3000 circles spent most of its preparation recomputing bounding boxes there).
    let boxes: Vec<GeomWithData<Rectangle<[f64; 2]>, usize>> = parts
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            p.bounding_rect().map(|r| {
                GeomWithData::new(
                    Rectangle::from_corners([r.min().x, r.min().y], [r.max().x, r.max().y]),
                    i,
                )
            })
        })
        .collect();
    let tree = rstar::RTree::bulk_load(boxes);
    mp.0.iter()
        .map(|poly| {
            let mut exterior = from_ls(poly.exterior());
            if signed_area(&exterior) < 0.0 {
                exterior.reverse();
            }
            let holes = poly
                .interiors()
                .iter()
                .map(|r| {
                    let mut h = from_ls(r);
                    if signed_area(&h) > 0.0 {
                        h.reverse();
                    }
                    h
                })
                .collect();
            let mut sources: Vec<u32> = match poly.bounding_rect() {
                Some(r) => tree
                    .locate_in_envelope_intersecting(&rstar::AABB::from_corners(
                        [r.min().x, r.min().y],
                        [r.max().x, r.max().y],
                    ))
                    .map(|b| b.data)
                    .filter(|&i| parts[i].intersects(poly))
                    .map(|i| i as u32)
                    .collect(),
                None => Vec::new(),
            };
            sources.sort_unstable();
            Region {
                exterior,
                holes,
                sources,
            }
        })
        .collect()
}

/// Snaps boolean-operation output (which i_overlay rounds to its integer grid): back onto an
/// input vertex or an exact intersection of input segments when within `tol`, otherwise to a
/// power-of-two grid of about `1e-9 × scale`.
struct Snapper {
    tol: f64,
    grid: f64,
    cells: HashMap<(i64, i64), Vec<Point>>,
}

impl Snapper {
    fn new(scale: f64, inputs: impl Iterator<Item = Point>) -> Self {
        let tol = 1e-7 * scale;
        let grid = 2f64.powi((1e-9 * scale).log2().round() as i32);
        let mut cells: HashMap<(i64, i64), Vec<Point>> = HashMap::new();
        for p in inputs {
            cells
                .entry(((p.x / tol).floor() as i64, (p.y / tol).floor() as i64))
                .or_default()
                .push(p);
        }
        Snapper { tol, grid, cells }
    }

    /// Snaps `p`: to an input vertex within `tol`; else to the intersection of two input
    /// segments passing within `tol` (a vertex created by the boolean operation, recomputed
    /// in full precision); else to the grid.
    fn snap(
        &self,
        p: Point,
        sources: &[(Point, Point, BoundaryTag)],
        index: &SegmentIndex,
    ) -> Point {
        if let Some(q) = self.snap_vertex(p) {
            return q;
        }
        let t = self.tol;
        let near: Vec<(Point, Point)> = index
            .in_box(Point::new(p.x - t, p.y - t), Point::new(p.x + t, p.y + t))
            .map(|(_, _, k)| (sources[k as usize].0, sources[k as usize].1))
            .filter(|&(a, b)| point_segment_dist2(p, a, b) <= t * t)
            .collect();
        let mut best: Option<(f64, Point)> = None;
        for i in 0..near.len() {
            for j in i + 1..near.len() {
                if let Some(q) = line_intersection(near[i], near[j]) {
                    let d = (q - p).norm();
                    if d <= t && best.is_none_or(|(bd, _)| d < bd) {
                        best = Some((d, q));
                    }
                }
            }
        }
        match best {
            Some((_, q)) => q,
            None => Point::new(
                (p.x / self.grid).round() * self.grid,
                (p.y / self.grid).round() * self.grid,
            ),
        }
    }

    fn snap_vertex(&self, p: Point) -> Option<Point> {
        let cx = (p.x / self.tol).floor() as i64;
        let cy = (p.y / self.tol).floor() as i64;
        let mut best: Option<(f64, Point)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(list) = self.cells.get(&(cx + dx, cy + dy)) {
                    for &q in list {
                        let d = (q - p).norm();
                        if d <= self.tol && best.is_none_or(|(bd, _)| d < bd) {
                            best = Some((d, q));
                        }
                    }
                }
            }
        }
        best.map(|(_, q)| q)
    }
}

/// The intersection point of the lines through two segments, if they are not parallel.
fn line_intersection((a, b): (Point, Point), (c, d): (Point, Point)) -> Option<Point> {
    let r = b - a;
    let s = d - c;
    let den = r.x * s.y - r.y * s.x;
    if den.abs() <= 1e-12 * r.norm() * s.norm() {
        return None;
    }
    let t = ((c.x - a.x) * s.y - (c.y - a.y) * s.x) / den;
    Some(a + r * t)
}

fn tag_rank(tag: BoundaryTag) -> (u8, u32) {
    match tag {
        BoundaryTag::Goal(j) => (0, j),
        BoundaryTag::Obstacle(i) => (1, i),
        BoundaryTag::Wall => (2, 0),
    }
}

/// One multipolygon per input obstacle or goal, in input order.
type PerInput = Vec<MultiPolygon<f64>>;

/// An input boundary segment `(from, to)` and the tag of free-space edges on it.
type Source = (Point, Point, BoundaryTag);

/// The validated workspace polygon and the sizes every later stage of [`Domain::new`] uses.
struct Workspace {
    /// The workspace ring, cleaned and counter-clockwise.
    ring: Vec<Point>,
    /// The same ring as a geo polygon.
    geo: Polygon<f64>,
    /// Its bounding box `(min, max)`.
    bbox: (Point, Point),
    /// The diagonal of the bounding box.
    scale: f64,
    /// The target edge length (of `max_area`, or of the workspace area / 20000).
    h: f64,
    /// The robot radius (finite, non-negative).
    rr: f64,
    /// The angle step (radians) of the round joins when offsetting by the robot radius.
    join_angle: f64,
    /// [`MeshOptions::simplify`]: the tolerance obstacle polygons are simplified to.
    simplify: Option<f64>,
}

impl Workspace {
    /// Checks the robot radius and the workspace polygon of `spec`, and derives the sizes.
    fn new(spec: &DomainSpec, opts: &MeshOptions) -> Result<Workspace, MeshError> {
        let rr = spec.robot_radius;
        if !(rr.is_finite() && rr >= 0.0) {
            return Err(MeshError::InvalidRobotRadius(rr));
        }
        let ws = clean_ring(Part::Workspace, &spec.workspace)?;
        let ws_area = signed_area(&ws);
        let (ws_lo, ws_hi) = bbox_of(&ws);
        let scale = (ws_hi - ws_lo).norm();
        let h = edge_for_area(opts.max_area.unwrap_or(ws_area / 20000.0));
        let ws_geo = to_geo(&ws);
        let join_angle = (h / rr.max(1e-300)).clamp(0.05, 0.3);
        Ok(Workspace {
            ring: ws,
            geo: ws_geo,
            bbox: (ws_lo, ws_hi),
            scale,
            h,
            rr,
            join_angle,
            simplify: opts.simplify,
        })
    }
}

/// Obstacles: validated, discretised and inflated by the robot radius, one multipolygon per
/// input; with a robot radius also the obstacles before inflation (for error messages).
fn inflated_obstacles(
    spec: &DomainSpec,
    ws: &Workspace,
) -> Result<(PerInput, PerInput), MeshError> {
    let (rr, h, join_angle) = (ws.rr, ws.h, ws.join_angle);
    let mut obstacle_geo: Vec<MultiPolygon<f64>> = Vec::with_capacity(spec.obstacles.len());
    // The obstacles before inflation (only kept with a robot radius, for error messages).
    let mut raw_obstacles: Vec<MultiPolygon<f64>> = Vec::new();
    for (i, shape) in spec.obstacles.iter().enumerate() {
        let part = Part::Obstacle(i);
        let mp = match shape {
            Shape::Polygon(pts) => {
                let ring = clean_ring(part, pts)?;
                if let Some(tol) = ws.simplify {
                    if rr > 0.0 {
                        raw_obstacles.push(MultiPolygon(vec![to_geo(&ring)]));
                    }
                    simplified(&ring, tol, rr, join_angle)
                } else if rr > 0.0 {
                    raw_obstacles.push(MultiPolygon(vec![to_geo(&ring)]));
                    to_geo(&ring).buffer_with_style(
                        BufferStyle::new(rr).line_join(LineJoin::Round(join_angle)),
                    )
                } else {
                    MultiPolygon(vec![to_geo(&ring)])
                }
            }
            Shape::Circle { center, radius } => {
                if !(radius.is_finite() && *radius > 0.0) {
                    return Err(MeshError::InvalidRadius {
                        part,
                        radius: *radius,
                    });
                }
                if rr > 0.0 {
                    raw_obstacles.push(MultiPolygon(vec![to_geo(&circle_polygon(
                        part, *center, *radius, h,
                    )?)]));
                }
                MultiPolygon(vec![to_geo(&circle_polygon(
                    part,
                    *center,
                    radius + rr,
                    h,
                )?)])
            }
        };
        if mp.intersection(&ws.geo).unsigned_area() <= 0.0 {
            return Err(MeshError::OutsideWorkspace { part });
        }
        obstacle_geo.push(mp);
    }
    Ok((obstacle_geo, raw_obstacles))
}

/// A conservative simplification of the obstacle `ring`, inflated by `rr`: Ramer–Douglas–
/// Peucker to `tol / 2` ([`crate::geom::simplify_ring`]) keeps every point of the original within `tol / 2`
/// of the simplified boundary, so growing the simplified polygon by `tol / 2` (mitred joins,
/// which contain round ones) contains the original; the robot radius is added to the same
/// offset. The boundary moves out by at most about `tol`.
fn simplified(ring: &[Point], tol: f64, rr: f64, join_angle: f64) -> MultiPolygon<f64> {
    let poly = to_geo(ring);
    let kept: Vec<Point> = crate::geom::simplify_ring(ring, 0.5 * tol)
        .into_iter()
        .map(|k| ring[k])
        .collect();
    // A ring that would collapse stays as it is.
    let coarse = if kept.len() >= 3 {
        to_geo(&kept)
    } else {
        poly.clone()
    };
    let grow = 0.5 * tol + rr;
    let join = if rr > 0.0 {
        LineJoin::Round(join_angle)
    } else {
        LineJoin::Miter(4.0)
    };
    let out = coarse.buffer_with_style(BufferStyle::new(grow).line_join(join));
    if out.unsigned_area() > 0.0 {
        out
    } else {
        MultiPolygon(vec![poly])
    }
}

/// Goals: validated and discretised, one multipolygon per input; a point goal becomes a
/// disc that stays clear of the walls and the (inflated) obstacles.
fn goal_shapes(
    spec: &DomainSpec,
    ws: &Workspace,
    obstacle_geo: &[MultiPolygon<f64>],
) -> Result<Vec<MultiPolygon<f64>>, MeshError> {
    let (h, ring) = (ws.h, &ws.ring);
    let clearance = Clearance::new(
        spec.goals
            .iter()
            .filter(|g| matches!(g, GoalShape::Point(_)))
            .count(),
        obstacle_geo
            .iter()
            .flat_map(rings_of)
            .flatten()
            .flat_map(|pts| {
                let n = pts.len();
                (0..n).map(move |k| (pts[k], pts[(k + 1) % n]))
            })
            .chain((0..ring.len()).map(|k| (ring[k], ring[(k + 1) % ring.len()]))),
    );
    let mut goal_geo: Vec<MultiPolygon<f64>> = Vec::with_capacity(spec.goals.len());
    for (j, goal) in spec.goals.iter().enumerate() {
        let part = Part::Goal(j);
        let ring = match goal {
            GoalShape::Polygon(pts) => clean_ring(part, pts)?,
            GoalShape::Circle { center, radius } => circle_polygon(part, *center, *radius, h)?,
            GoalShape::Point(p) => {
                // Twice the target edge length, but at most half the way to the nearest
                // wall or obstacle so the disc stays in free space.
                let d = clearance.distance(*p);
                let r = if d > 0.0 {
                    (2.0 * h).min(0.5 * d)
                } else {
                    2.0 * h
                };
                point_goal_polygon(part, *p, r, h)?
            }
        };
        let poly = to_geo(&ring);
        if poly.intersection(&ws.geo).unsigned_area() <= 0.0 {
            return Err(MeshError::OutsideWorkspace { part });
        }
        goal_geo.push(MultiPolygon(vec![poly]));
    }
    Ok(goal_geo)
}

/// Point goals with fewer than this many siblings measure their clearance by a scan of every
/// wall and obstacle edge: cheaper than building an R-tree of them (O(n log n)) for a few
/// queries.
const SCANNED_POINT_GOALS: usize = 8;

/// Distances from point goals to the walls and obstacles: a scan of the edges for a few
/// goals, an R-tree for many, nothing without point goals.
enum Clearance {
    Scan(Vec<(Point, Point)>),
    Index(SegmentIndex),
}

impl Clearance {
    /// The clearance of `queries` point goals against `edges`.
    fn new(queries: usize, edges: impl Iterator<Item = (Point, Point)>) -> Clearance {
        if queries == 0 {
            Clearance::Scan(Vec::new())
        } else if queries < SCANNED_POINT_GOALS {
            Clearance::Scan(edges.collect())
        } else {
            Clearance::Index(SegmentIndex::new(edges.map(|(a, b)| (a, b, 0))))
        }
    }

    /// Distance from `p` to the nearest edge (infinity without edges, NaN for a non-finite
    /// `p`).
    fn distance(&self, p: Point) -> f64 {
        match self {
            Clearance::Index(index) => index.distance(p),
            Clearance::Scan(_) if !(p.x.is_finite() && p.y.is_finite()) => f64::NAN,
            Clearance::Scan(edges) => edges
                .iter()
                .map(|&(a, b)| point_segment_dist2(p, a, b))
                .fold(f64::INFINITY, f64::min)
                .sqrt(),
        }
    }
}

/// The workspace, shrunk by the robot radius; an error if nothing is left.
fn shrunk_workspace(ws: &Workspace) -> Result<MultiPolygon<f64>, MeshError> {
    let rr = ws.rr;
    let ws_mp = if rr > 0.0 {
        ws.geo
            .buffer_with_style(BufferStyle::new(-rr).line_join(LineJoin::Round(ws.join_angle)))
    } else {
        MultiPolygon(vec![ws.geo.clone()])
    };
    if ws_mp.unsigned_area() <= 0.0 {
        return Err(MeshError::NoFreeSpace { robot_radius: rr });
    }
    Ok(ws_mp)
}

/// Makes near touches between inputs exact (see `touch`): a vertex a rounding error off
/// another input's edge would leave a sliver no mesh can resolve. Returns the rings of every
/// input (the workspace's first, then the obstacles', then the goals') and the workspace,
/// obstacles and goals made from them.
fn snap_touches(
    ws_mp: MultiPolygon<f64>,
    obstacle_geo: PerInput,
    goal_geo: PerInput,
    scale: f64,
) -> (Vec<Rings>, MultiPolygon<f64>, PerInput, PerInput) {
    let mut groups: Vec<Rings> = std::iter::once(rings_of(&ws_mp))
        .chain(obstacle_geo.iter().map(rings_of))
        .chain(goal_geo.iter().map(rings_of))
        .collect();
    if snap_near_touches(&mut groups, 1e-9 * scale) {
        groups.iter_mut().for_each(dedup_rings);
        let n_obs = obstacle_geo.len();
        let mut mps = groups.iter().map(multipolygon_of);
        let ws_mp = mps.next().expect("the workspace group comes first");
        let obstacle_geo: Vec<MultiPolygon<f64>> = mps.by_ref().take(n_obs).collect();
        let goal_geo = mps.collect();
        (groups, ws_mp, obstacle_geo, goal_geo)
    } else {
        (groups, ws_mp, obstacle_geo, goal_geo)
    }
}

/// Every input boundary segment of `groups` (the workspace, the obstacles numbered
/// `obstacles`, the goals) with the tag it gives (obstacles, goals, then walls), and
/// the points free-space vertices may snap to (the workspace ring `ws`, then the vertices of
/// every segment).
fn boundary_sources(
    ws: &[Point],
    groups: &[Rings],
    obstacles: &[usize],
    spec: &DomainSpec,
) -> (Vec<Source>, Vec<Point>) {
    let mut sources: Vec<Source> = Vec::new();
    let mut snap_inputs: Vec<Point> = ws.to_vec();
    // Obstacles (those in `groups`, by input index), goals, then walls (groups hold the
    // walls first).
    let tags = obstacles
        .iter()
        .map(|&i| BoundaryTag::Obstacle(i as u32))
        .chain((0..spec.goals.len()).map(|j| BoundaryTag::Goal(j as u32)))
        .chain(std::iter::once(BoundaryTag::Wall));
    for (group, tag) in groups[1..].iter().chain(&groups[..1]).zip(tags) {
        for pts in group.iter().flatten() {
            snap_inputs.extend_from_slice(pts);
            let n = pts.len();
            for k in 0..n {
                sources.push((pts[k], pts[(k + 1) % n], tag));
            }
        }
    }
    (sources, snap_inputs)
}

/// Free space as polygons, with the unions of obstacles and of goals it was cut from.
struct FreeSpace {
    free: MultiPolygon<f64>,
    obstacles: MultiPolygon<f64>,
    goals: MultiPolygon<f64>,
}

/// The shrunk workspace less the obstacles `cut` (the others, of total area `isolated_area`,
/// are isolated holes: see `isolated`) and the goals; an error if nothing is left or a goal
/// touches no free space (saying whether an obstacle of `obstacle_geo`, all of them, covers
/// it).
fn free_space(
    ws: &Workspace,
    ws_mp: &MultiPolygon<f64>,
    cut: &[MultiPolygon<f64>],
    isolated_area: f64,
    obstacle_geo: &[MultiPolygon<f64>],
    goal_geo: &[MultiPolygon<f64>],
    raw_obstacles: &[MultiPolygon<f64>],
) -> Result<FreeSpace, MeshError> {
    let rr = ws.rr;
    let obstacle_union = unary_union(cut.iter());
    let goal_union = unary_union(goal_geo.iter());
    let free0 = if cut.is_empty() {
        ws_mp.clone()
    } else {
        ws_mp.difference(&obstacle_union)
    };
    if free0.unsigned_area() - isolated_area <= 0.0 {
        return Err(MeshError::NoFreeSpace { robot_radius: rr });
    }
    for (j, g) in goal_geo.iter().enumerate() {
        if g.intersection(&free0).unsigned_area() <= 0.0 {
            let raw = if rr > 0.0 {
                raw_obstacles
            } else {
                obstacle_geo
            };
            let uncovered = g.intersection(&ws.geo).difference(&unary_union(raw.iter()));
            if uncovered.unsigned_area() <= 0.0 {
                let obstacle = raw.iter().position(|o| o.intersects(g)).unwrap_or(0);
                return Err(MeshError::GoalInObstacle { goal: j, obstacle });
            }
            return Err(MeshError::GoalNotInFreeSpace {
                goal: j,
                robot_radius: rr,
            });
        }
    }
    let free_mp = if goal_geo.is_empty() {
        free0
    } else {
        free0.difference(&goal_union)
    };
    if free_mp.unsigned_area() - isolated_area <= 0.0 {
        return Err(MeshError::NoFreeSpace { robot_radius: rr });
    }
    Ok(FreeSpace {
        free: free_mp,
        obstacles: obstacle_union,
        goals: goal_union,
    })
}

/// Snaps, orients and tags the rings of `free_mp`: vertices onto the input points and
/// segments (`snap_inputs`, `sources`), outer rings counter-clockwise and holes clockwise,
/// every edge tagged with the input it lies on.
fn tagged_free_rings(
    free_mp: &MultiPolygon<f64>,
    sources: &[(Point, Point, BoundaryTag)],
    snap_inputs: Vec<Point>,
    scale: f64,
) -> Vec<TaggedRing> {
    let snapper = Snapper::new(scale, snap_inputs.into_iter());
    let source_index = SegmentIndex::new(
        sources
            .iter()
            .enumerate()
            .map(|(k, &(a, b, _))| (a, b, k as u32)),
    );
    let tol = 1e-7 * scale;
    let mut free = Vec::new();
    for poly in &free_mp.0 {
        let mut rings = Vec::new();
        for (r, ls) in std::iter::once(poly.exterior())
            .chain(poly.interiors())
            .enumerate()
        {
            let mut pts: Vec<Point> = from_ls(ls)
                .into_iter()
                .map(|p| snapper.snap(p, sources, &source_index))
                .collect();
            pts.dedup();
            while pts.len() > 1 && pts[0] == pts[pts.len() - 1] {
                pts.pop();
            }
            if pts.len() < 3 || signed_area(&pts) == 0.0 {
                continue;
            }
            let ccw = signed_area(&pts) > 0.0;
            if (r == 0) != ccw {
                pts.reverse();
            }
            rings.push(tag_ring(&pts, sources, &source_index, tol));
        }
        free.extend(cancel_shared_edges(rings));
    }
    free
}

/// The segment index of free space's boundary: every edge (for the inside test), its payload
/// the edge's position among all ring edges, ring after ring (what the mesher's boundary
/// tagging looks segments up by).
fn boundary_index(free: &[TaggedRing]) -> SegmentIndex {
    let mut next = 0u32;
    SegmentIndex::new(free.iter().flat_map(|r| {
        let n = r.points.len();
        let first = next;
        next += n as u32;
        (0..n).map(move |k| (r.points[k], r.points[(k + 1) % n], first + k as u32))
    }))
}

/// Per boundary edge, ring after ring (the numbering of [`boundary_index`]): whether it is a
/// goal edge.
fn goal_edges(free: &[TaggedRing]) -> Vec<bool> {
    free.iter()
        .flat_map(|r| r.tags.iter().map(|t| matches!(t, BoundaryTag::Goal(_))))
        .collect()
}

impl Domain {
    /// Validates the scene and builds its free space.
    ///
    /// Circles are discretised with edges no longer than the target edge length of `opts`
    /// (from `max_area`, or the default area workspace/20000). Overlapping obstacles are merged,
    /// obstacles crossing the workspace boundary are cut out of it, goals are removed from free
    /// space, and every boundary edge is tagged with the input it lies on.
    ///
    /// The work is done in unit coordinates (see [`Frame`]): any finite scale and offset of a
    /// scene gives the same free space, scaled; every accessor answers in the scene's
    /// coordinates.
    pub fn new(spec: &DomainSpec, opts: &MeshOptions) -> Result<Domain, MeshError> {
        opts.validate()?;
        let frame = Frame::of(&spec.workspace);
        let unit_spec = spec_to_unit(spec, &frame);
        let unit_opts = options_to_unit(opts, &frame);
        let mut domain =
            Domain::build(&unit_spec, &unit_opts).map_err(|e| error_to_user(e, spec, opts))?;
        let to_user = |r: &Region| Region {
            exterior: r.exterior.iter().map(|&p| frame.to_user(p)).collect(),
            holes: r
                .holes
                .iter()
                .map(|h| h.iter().map(|&p| frame.to_user(p)).collect())
                .collect(),
            sources: r.sources.clone(),
        };
        domain.user_free = domain
            .free
            .iter()
            .map(|r| TaggedRing {
                points: r.points.iter().map(|&p| frame.to_user(p)).collect(),
                tags: r.tags.clone(),
            })
            .collect();
        domain.workspace = domain.workspace.iter().map(to_user).collect();
        domain.obstacles = domain.obstacles.iter().map(to_user).collect();
        domain.goals = domain.goals.iter().map(to_user).collect();
        domain.frame = frame;
        Ok(domain)
    }

    /// [`Domain::new`] on a scene already in unit coordinates (the frame is the identity
    /// until `new` sets it).
    fn build(spec: &DomainSpec, opts: &MeshOptions) -> Result<Domain, MeshError> {
        let ws = Workspace::new(spec, opts)?;
        let (obstacle_geo, raw_obstacles) = inflated_obstacles(spec, &ws)?;
        let goal_geo = goal_shapes(spec, &ws, &obstacle_geo)?;
        let ws_mp = shrunk_workspace(&ws)?;
        // Obstacles that touch nothing are holes as they are; the booleans, the snapping and
        // the tagging only see the others.
        let isolated = isolated::Isolated::find(&ws_mp, &obstacle_geo, &goal_geo, ws.scale);
        let (cut_ids, cut_geo): (Vec<usize>, PerInput) = obstacle_geo
            .iter()
            .enumerate()
            .filter(|&(i, _)| !isolated.contains(i))
            .map(|(i, mp)| (i, mp.clone()))
            .unzip();
        let (groups, ws_mp, cut_geo, goal_geo) = snap_touches(ws_mp, cut_geo, goal_geo, ws.scale);
        let mut obstacle_geo = obstacle_geo;
        for (&i, mp) in cut_ids.iter().zip(&cut_geo) {
            obstacle_geo[i] = mp.clone();
        }
        let (sources, snap_inputs) = boundary_sources(&ws.ring, &groups, &cut_ids, spec);
        let space = free_space(
            &ws,
            &ws_mp,
            &cut_geo,
            isolated.area,
            &obstacle_geo,
            &goal_geo,
            &raw_obstacles,
        )?;
        let mut free = tagged_free_rings(&space.free, &sources, snap_inputs, ws.scale);
        free.extend(isolated.holes());
        let boundary_index = boundary_index(&free);
        let mut obstacle_regions = if cut_geo.is_empty() {
            Vec::new()
        } else {
            regions_of(&space.obstacles.intersection(&ws.geo), &obstacle_geo)
        };
        obstacle_regions.extend(isolated.regions());
        let goal_regions = if goal_geo.is_empty() {
            Vec::new()
        } else {
            regions_of(&space.goals, &goal_geo)
        };
        Ok(Domain {
            free_area: free.iter().map(|r| signed_area(&r.points)).sum(),
            free,
            workspace: regions_of(&ws_mp, &[]),
            obstacles: obstacle_regions,
            goals: goal_regions,
            scale: ws.scale,
            bbox: ws.bbox,
            target_edge: ws.h,
            robot_radius: ws.rr,
            boundary_index: std::sync::OnceLock::from(boundary_index),
            goal_edges: std::sync::OnceLock::new(),
            frame: Frame::identity(),
            user_free: Vec::new(),
            constraints: Constraints::default(),
        })
    }

    /// The boundary rings of free space (outer rings counter-clockwise, holes clockwise), with
    /// a tag per edge. These are the constraint edges of the triangulation.
    pub fn free_rings(&self) -> &[TaggedRing] {
        &self.user_free
    }
    /// The workspace after shrinking by the robot radius (one region unless the shrink split it).
    pub fn workspace_rings(&self) -> &[Region] {
        &self.workspace
    }
    /// The obstacles after inflation by the robot radius, merging and clipping to the workspace.
    pub fn obstacle_polygons(&self) -> &[Region] {
        &self.obstacles
    }
    /// The goal regions after merging (point goals as their small discs).
    pub fn goal_polygons(&self) -> &[Region] {
        &self.goals
    }
    /// The exact area of free space (of the polygons that are meshed).
    pub fn free_area(&self) -> f64 {
        self.frame.area_to_user(self.free_area)
    }
    /// The diagonal of the workspace bounding box.
    pub fn scale(&self) -> f64 {
        self.frame.len_to_user(self.scale)
    }
    /// The workspace bounding box `(min, max)`.
    pub fn bounding_box(&self) -> (Point, Point) {
        (
            self.frame.to_user(self.bbox.0),
            self.frame.to_user(self.bbox.1),
        )
    }
    /// The target edge length used to discretise circles.
    pub fn target_edge_length(&self) -> f64 {
        self.frame.len_to_user(self.target_edge)
    }
    /// The robot radius the domain was built with.
    pub fn robot_radius(&self) -> f64 {
        self.frame.len_to_user(self.robot_radius)
    }
    /// The map from the scene's coordinates to the unit coordinates the domain is meshed in.
    pub fn frame(&self) -> Frame {
        self.frame
    }

    /// The free-space rings in unit coordinates (what the mesher triangulates).
    pub(crate) fn unit_rings(&self) -> &[TaggedRing] {
        &self.free
    }
    /// The unit rings' edges in an R-tree, each with its position among all ring edges
    /// (ring after ring, edge `k` of a ring from its point `k`).
    pub(crate) fn unit_boundary_index(&self) -> &SegmentIndex {
        self.boundary_index
            .get_or_init(|| boundary_index(&self.free))
    }
    /// Builds now what point and clearance queries need ([`Domain::contains_free`],
    /// [`Domain::polyline_clearance`], …) and is otherwise built at the first query: the
    /// boundary's R-tree and which of its edges are goal edges. A planner calls it beside its
    /// solve, so that the domain of a map's mesh is ready when tracing starts.
    pub fn prepare_queries(&self) {
        self.unit_boundary_index();
        self.goal_edges();
    }
    /// Whether each boundary edge is a goal edge (found at the first call).
    fn goal_edges(&self) -> &[bool] {
        self.goal_edges.get_or_init(|| goal_edges(&self.free))
    }
    /// The workspace bounding box in unit coordinates.
    pub(crate) fn unit_bbox(&self) -> (Point, Point) {
        self.bbox
    }
    /// The free area in unit coordinates.
    pub(crate) fn unit_free_area(&self) -> f64 {
        self.free_area
    }

    /// Whether `p` lies in free space (closed set: points within 1e-12 × scene size of the
    /// boundary count as free).
    pub fn contains_free(&self, p: Point) -> bool {
        if !p.x.is_finite() || !p.y.is_finite() {
            return false;
        }
        let p = self.frame.to_unit(p);
        if self.unit_boundary_index().distance(p) <= 1e-12 * self.scale {
            return true;
        }
        self.unit_boundary_index().ray_parity(p, self.bbox.1.x)
    }

    /// Exact distance from `p` to the nearest wall or obstacle boundary segment of free space
    /// (goal boundaries excluded), whether `p` is inside free space or not. For a disc robot
    /// the boundaries are those of the inflated obstacles. Infinity if there are none.
    pub fn distance_to_obstacles(&self, p: Point) -> f64 {
        let goal = self.goal_edges();
        self.frame.len_to_user(
            self.unit_boundary_index()
                .distance_where(self.frame.to_unit(p), |k| !goal[k as usize]),
        )
    }

    /// Minimum distance from the polyline `points` to walls and obstacles: the smallest
    /// [`Domain::segment_clearance`] of its segments (for one point, its
    /// [`Domain::distance_to_obstacles`]; infinity for none), found with a nearest-segment
    /// search per vertex rather than two per segment.
    pub fn polyline_clearance(&self, points: &[Point]) -> f64 {
        let unit: Vec<Point> = points.iter().map(|&p| self.frame.to_unit(p)).collect();
        self.unit_polyline_clearance(&unit)
    }

    /// Minimum distance from the segment `ab` to walls and obstacles (0 if it touches or
    /// crosses one). A segment fully inside an obstacle also has a positive value: check
    /// [`Domain::contains_free`] on an end point as well.
    pub fn segment_clearance(&self, a: Point, b: Point) -> f64 {
        self.unit_polyline_clearance(&[self.frame.to_unit(a), self.frame.to_unit(b)])
    }

    /// [`Domain::polyline_clearance`] of a polyline in unit coordinates.
    fn unit_polyline_clearance(&self, unit: &[Point]) -> f64 {
        let goal = self.goal_edges();
        if goal.iter().all(|&g| g) {
            return f64::INFINITY;
        }
        self.frame.len_to_user(
            self.unit_boundary_index()
                .polyline_distance_where(unit, |k| !goal[k as usize]),
        )
    }
}

/// Areas and lengths of mesh options in unit coordinates are kept below this, so that a
/// bound meaning "no bound" at a tiny scale does not overflow.
const UNIT_LIMIT: f64 = 1e200;

/// `spec` in the unit coordinates of `frame`.
fn spec_to_unit(spec: &DomainSpec, frame: &Frame) -> DomainSpec {
    let pts = |v: &[Point]| {
        v.iter()
            .map(|&p| frame.input_to_unit(p))
            .collect::<Vec<_>>()
    };
    let len = |r: f64| frame.input_len_to_unit(r);
    DomainSpec {
        workspace: pts(&spec.workspace),
        obstacles: spec
            .obstacles
            .iter()
            .map(|o| match o {
                Shape::Polygon(v) => Shape::Polygon(pts(v)),
                Shape::Circle { center, radius } => Shape::Circle {
                    center: frame.input_to_unit(*center),
                    radius: len(*radius),
                },
            })
            .collect(),
        goals: spec
            .goals
            .iter()
            .map(|g| match g {
                GoalShape::Polygon(v) => GoalShape::Polygon(pts(v)),
                GoalShape::Circle { center, radius } => GoalShape::Circle {
                    center: frame.input_to_unit(*center),
                    radius: len(*radius),
                },
                GoalShape::Point(p) => GoalShape::Point(frame.input_to_unit(*p)),
            })
            .collect(),
        robot_radius: len(spec.robot_radius),
    }
}

/// `opts` in the unit coordinates of `frame` (areas and lengths; angles and counts as they are).
pub(crate) fn options_to_unit(opts: &MeshOptions, frame: &Frame) -> MeshOptions {
    let mut unit = opts.clone();
    unit.max_area = opts
        .max_area
        .map(|a| frame.input_area_to_unit(a).min(UNIT_LIMIT));
    if let Some(g) = unit.grading.as_mut() {
        g.radius = frame.input_len_to_unit(g.radius).min(UNIT_LIMIT);
    }
    unit.simplify = opts
        .simplify
        .map(|t| frame.input_len_to_unit(t).min(UNIT_LIMIT));
    unit
}

/// An error of the unit scene, with the user's numbers where it quotes one.
fn error_to_user(e: MeshError, spec: &DomainSpec, opts: &MeshOptions) -> MeshError {
    let radius_of = |part: Part| match part {
        Part::Obstacle(i) => match spec.obstacles.get(i) {
            Some(Shape::Circle { radius, .. }) => Some(*radius),
            _ => None,
        },
        Part::Goal(j) => match spec.goals.get(j) {
            Some(GoalShape::Circle { radius, .. }) => Some(*radius),
            _ => None,
        },
        Part::Workspace => None,
    };
    match e {
        MeshError::InvalidRadius { part, radius } => MeshError::InvalidRadius {
            part,
            radius: radius_of(part).unwrap_or(radius),
        },
        MeshError::NoFreeSpace { .. } => MeshError::NoFreeSpace {
            robot_radius: spec.robot_radius,
        },
        MeshError::GoalNotInFreeSpace { goal, .. } => MeshError::GoalNotInFreeSpace {
            goal,
            robot_radius: spec.robot_radius,
        },
        MeshError::InvalidRobotRadius(_) => MeshError::InvalidRobotRadius(spec.robot_radius),
        MeshError::InvalidOption {
            name,
            value,
            reason,
        } => MeshError::InvalidOption {
            name,
            value: match name {
                "max_area" => opts.max_area.unwrap_or(value),
                "grading.radius" => opts.grading.map_or(value, |g| g.radius),
                "simplify" => opts.simplify.unwrap_or(value),
                _ => value,
            },
            reason,
        },
        other => other,
    }
}

/// Splits each edge of `pts` at the input vertices lying on it and tags every piece with the
/// input segment it lies on (goal before obstacle before wall, lowest index first).
fn tag_ring(
    pts: &[Point],
    sources: &[(Point, Point, BoundaryTag)],
    index: &SegmentIndex,
    tol: f64,
) -> TaggedRing {
    let n = pts.len();
    let tol2 = tol * tol;
    let mut points = Vec::with_capacity(n);
    let mut tags = Vec::with_capacity(n);
    for k in 0..n {
        let p = pts[k];
        let q = pts[(k + 1) % n];
        let lo = Point::new(p.x.min(q.x) - tol, p.y.min(q.y) - tol);
        let hi = Point::new(p.x.max(q.x) + tol, p.y.max(q.y) + tol);
        let cands: Vec<usize> = index
            .in_box(lo, hi)
            .map(|(_, _, s)| s as usize)
            .filter(|&s| {
                let (a, b, _) = sources[s];
                // Collinear with pq and overlapping it.
                let on_a = point_segment_dist2(a, p, q) <= tol2;
                let on_b = point_segment_dist2(b, p, q) <= tol2;
                let p_on = point_segment_dist2(p, a, b) <= tol2;
                let q_on = point_segment_dist2(q, a, b) <= tol2;
                (on_a as u8 + on_b as u8 + p_on as u8 + q_on as u8) >= 2
            })
            .collect();
        let pq = q - p;
        let len2 = pq.norm_squared();
        let mut cuts: Vec<(f64, Point)> = Vec::new();
        for &s in &cands {
            let (a, b, _) = sources[s];
            for c in [a, b] {
                let t = (c - p).dot(&pq) / len2;
                if point_segment_dist2(c, p, q) <= tol2
                    && (c - p).norm_squared() > tol2
                    && (c - q).norm_squared() > tol2
                {
                    cuts.push((t, c));
                }
            }
        }
        cuts.sort_by(|x, y| x.0.total_cmp(&y.0));
        cuts.dedup_by(|x, y| (x.1 - y.1).norm_squared() <= tol2);
        let mut stops = vec![p];
        stops.extend(cuts.into_iter().map(|(_, c)| c));
        stops.push(q);
        for w in stops.windows(2) {
            let m = Point::new(0.5 * (w[0].x + w[1].x), 0.5 * (w[0].y + w[1].y));
            let mut best: Option<(BoundaryTag, f64)> = None;
            for &s in &cands {
                let (a, b, tag) = sources[s];
                if point_segment_dist2(m, a, b) <= tol2
                    && best.is_none_or(|(bt, _)| tag_rank(tag) < tag_rank(bt))
                {
                    best = Some((tag, 0.0));
                }
            }
            let tag = match best {
                Some((t, _)) => t,
                None => nearest_tag(m, sources, index),
            };
            points.push(w[0]);
            tags.push(tag);
        }
    }
    TaggedRing { points, tags }
}

/// The tag of the input segment nearest to `m` (fallback when nothing lies within tolerance).
fn nearest_tag(
    m: Point,
    sources: &[(Point, Point, BoundaryTag)],
    index: &SegmentIndex,
) -> BoundaryTag {
    let d = index.distance(m);
    let r = d * (1.0 + 1e-9) + f64::MIN_POSITIVE;
    index
        .in_box(Point::new(m.x - r, m.y - r), Point::new(m.x + r, m.y + r))
        .map(|(_, _, s)| sources[s as usize])
        .filter(|&(a, b, _)| point_segment_dist2(m, a, b).sqrt() <= r)
        .map(|(_, _, t)| t)
        .min_by_key(|&t| tag_rank(t))
        .unwrap_or(BoundaryTag::Wall)
}
