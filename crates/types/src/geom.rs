//! The workspace's one home of the geometric kernels of the plane: orientation (exact,
//! [`orient2d`], and in floating point, [`twice_signed_area`]), areas, barycentric
//! coordinates, distances and closest points between points, segments and polygons, the
//! even-odd inside test, polyline length; and of space: [`signed_volume`](crate::signed_volume).
//!
//! Rings are slices of vertices, closed implicitly (the last vertex joins the first), in
//! either orientation. Every function takes the project's [`Point`] or anything that turns
//! into one for free (`[f64; 2]`, as the scene format stores points), so callers holding
//! serde arrays need not copy their polygons.
//!
//! ```
//! use harmonic_types::geom::{polygon_contains, polygon_distance, segment_polygon_distance};
//! let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
//! assert!(polygon_contains(&square, [1.0, 1.0]));
//! assert_eq!(polygon_distance(&square, [1.0, 1.0]), 0.0);
//! assert_eq!(polygon_distance(&square, [3.0, 1.0]), 1.0);
//! assert_eq!(segment_polygon_distance([3.0, -1.0], [3.0, 3.0], &square), 1.0);
//! ```

use crate::Point;

/// Twice the signed area of the triangle `a, b, c` (positive when counter-clockwise), in
/// floating point: the element areas of assembly, the orientation checks of meshes. Its sign
/// may be wrong for nearly collinear points; [`orient2d`] decides them exactly.
pub fn twice_signed_area(a: Point, b: Point, c: Point) -> f64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// The orientation of `a, b, c`, exactly: positive when counter-clockwise, negative when
/// clockwise, zero only when exactly collinear (Shewchuk's adaptive predicate, through
/// `robust`). The magnitude approximates twice the triangle's area.
///
/// ```
/// use harmonic_types::{Point, geom::orient2d};
/// let (a, b) = (Point::new(0.1, 0.1), Point::new(0.3, 0.3));
/// assert_eq!(orient2d(a, b, Point::new(0.7, 0.7)), 0.0);
/// assert!(orient2d(a, b, Point::new(0.0, 1.0)) > 0.0);
/// ```
pub fn orient2d(a: Point, b: Point, c: Point) -> f64 {
    let coord = |p: Point| robust::Coord { x: p.x, y: p.y };
    robust::orient2d(coord(a), coord(b), coord(c))
}

/// The signed area of a ring (the shoelace formula): positive when counter-clockwise.
///
/// ```
/// use harmonic_types::geom::signed_area;
/// assert_eq!(signed_area(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]), 2.0);
/// assert_eq!(signed_area(&[[0.0, 0.0], [0.0, 1.0], [2.0, 1.0], [2.0, 0.0]]), -2.0);
/// ```
pub fn signed_area<P: Copy + Into<Point>>(ring: &[P]) -> f64 {
    0.5 * ring_edges(ring)
        .map(|(a, b)| a.x * b.y - b.x * a.y)
        .sum::<f64>()
}

/// The barycentric coordinates of `p` in the triangle `abc` (they sum to 1; all ≥ 0 inside).
///
/// ```
/// use harmonic_types::{Point, geom::barycentric};
/// let [a, b, c] = [Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0)];
/// assert_eq!(barycentric([a, b, c], Point::new(0.25, 0.5)), [0.25, 0.25, 0.5]);
/// ```
pub fn barycentric([a, b, c]: [Point; 3], p: Point) -> [f64; 3] {
    let det = twice_signed_area(a, b, c);
    let la = twice_signed_area(p, b, c) / det;
    let lb = twice_signed_area(p, c, a) / det;
    [la, lb, 1.0 - la - lb]
}

/// The edges of a ring, the closing edge last.
pub fn ring_edges<P: Copy + Into<Point>>(ring: &[P]) -> impl Iterator<Item = (Point, Point)> + '_ {
    let n = ring.len();
    (0..n).map(move |k| (ring[k].into(), ring[(k + 1) % n].into()))
}

/// Whether the ray from `p` towards +x crosses an odd number of `edges` (the even-odd rule):
/// for the edges of a closed ring, whether `p` lies inside it. Each edge counts on the
/// half-open interval of its y extent, so a vertex on the ray is crossed once.
pub fn even_odd(edges: impl IntoIterator<Item = (Point, Point)>, p: Point) -> bool {
    let mut inside = false;
    for (a, b) in edges {
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x > p.x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Whether `p` lies inside the polygon `ring` (even-odd rule; either orientation).
pub fn polygon_contains<P: Copy + Into<Point>>(ring: &[P], p: impl Into<Point>) -> bool {
    even_odd(ring_edges(ring), p.into())
}

/// The point of the closed segment `ab` closest to `p`.
pub fn closest_point_on_segment(
    p: impl Into<Point>,
    a: impl Into<Point>,
    b: impl Into<Point>,
) -> Point {
    let (p, a, b) = (p.into(), a.into(), b.into());
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a + ab * t
}

/// Squared distance from `p` to the closed segment `ab`.
pub fn point_segment_dist2(p: Point, a: Point, b: Point) -> f64 {
    (closest_point_on_segment(p, a, b) - p).norm_squared()
}

/// Distance from `p` to the closed segment `ab`.
pub fn point_segment_distance(
    p: impl Into<Point>,
    a: impl Into<Point>,
    b: impl Into<Point>,
) -> f64 {
    point_segment_dist2(p.into(), a.into(), b.into()).sqrt()
}

/// Whether the closed segments `ab` and `cd` share a point (touching counts).
pub fn segments_intersect(a: Point, b: Point, c: Point, d: Point) -> bool {
    let o1 = twice_signed_area(a, b, c);
    let o2 = twice_signed_area(a, b, d);
    let o3 = twice_signed_area(c, d, a);
    let o4 = twice_signed_area(c, d, b);
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return true;
    }
    let on = |p: Point, q: Point, r: Point, o: f64| {
        o == 0.0
            && r.x >= p.x.min(q.x)
            && r.x <= p.x.max(q.x)
            && r.y >= p.y.min(q.y)
            && r.y <= p.y.max(q.y)
    };
    on(a, b, c, o1) || on(a, b, d, o2) || on(c, d, a, o3) || on(c, d, b, o4)
}

/// Distance between the closed segments `ab` and `cd` (0 if they meet).
pub fn segment_segment_distance(a: Point, b: Point, c: Point, d: Point) -> f64 {
    if segments_intersect(a, b, c, d) {
        return 0.0;
    }
    point_segment_dist2(a, c, d)
        .min(point_segment_dist2(b, c, d))
        .min(point_segment_dist2(c, a, b))
        .min(point_segment_dist2(d, a, b))
        .sqrt()
}

/// The closest pair of points of the closed segments `ab` and `cd`: a point of `ab`, a point
/// of `cd`, and their distance (where they meet, a common point and 0).
///
/// ```
/// use harmonic_types::{Point, geom::closest_points_segment_segment};
/// let (p, q, d) = closest_points_segment_segment(
///     Point::new(0.0, 0.0), Point::new(2.0, 0.0), Point::new(1.0, 1.0), Point::new(3.0, 3.0));
/// assert_eq!((p, q, d), (Point::new(1.0, 0.0), Point::new(1.0, 1.0), 1.0));
/// ```
pub fn closest_points_segment_segment(
    a: Point,
    b: Point,
    c: Point,
    d: Point,
) -> (Point, Point, f64) {
    if segments_intersect(a, b, c, d) {
        // Proper crossing: solve a + s(b − a) = c + t(d − c); collinear overlap (or a touch
        // at an end point): an end point that lies on the other segment.
        let (r, e) = (b - a, d - c);
        let den = r.perp(&e);
        if den != 0.0 {
            let s = ((c - a).perp(&e) / den).clamp(0.0, 1.0);
            let p = a + r * s;
            return (p, p, 0.0);
        }
        for (p, x, y) in [(a, c, d), (b, c, d), (c, a, b), (d, a, b)] {
            if point_segment_dist2(p, x, y) == 0.0 {
                return (p, p, 0.0);
            }
        }
    }
    let candidates = [
        (a, closest_point_on_segment(a, c, d)),
        (b, closest_point_on_segment(b, c, d)),
        (closest_point_on_segment(c, a, b), c),
        (closest_point_on_segment(d, a, b), d),
    ];
    let (p, q) = candidates
        .into_iter()
        .min_by(|x, y| {
            (x.1 - x.0)
                .norm_squared()
                .total_cmp(&(y.1 - y.0).norm_squared())
        })
        .unwrap_or((a, c));
    (p, q, (q - p).norm())
}

/// The point of the boundary of `ring` closest to `p`, and its distance (`None` for an
/// empty ring).
pub fn closest_point_on_ring<P: Copy + Into<Point>>(
    ring: &[P],
    p: impl Into<Point>,
) -> Option<(Point, f64)> {
    let p = p.into();
    ring_edges(ring)
        .map(|(a, b)| {
            let c = closest_point_on_segment(p, a, b);
            (c, (c - p).norm())
        })
        .min_by(|x, y| x.1.total_cmp(&y.1))
}

/// Distance from `p` to the boundary of `ring` (infinity for an empty ring).
pub fn ring_distance<P: Copy + Into<Point>>(ring: &[P], p: impl Into<Point>) -> f64 {
    closest_point_on_ring(ring, p).map_or(f64::INFINITY, |(_, d)| d)
}

/// Distance from `p` to the polygon `ring` as a solid: 0 inside, the distance to its
/// boundary outside.
pub fn polygon_distance<P: Copy + Into<Point>>(ring: &[P], p: impl Into<Point>) -> f64 {
    let p = p.into();
    if polygon_contains(ring, p) {
        0.0
    } else {
        ring_distance(ring, p)
    }
}

/// Distance between the segment `ab` and the polygon `ring` as a solid: 0 if the segment
/// meets its boundary or starts inside it (infinity for an empty ring).
pub fn segment_polygon_distance<P: Copy + Into<Point>>(
    a: impl Into<Point>,
    b: impl Into<Point>,
    ring: &[P],
) -> f64 {
    closest_points_segment_polygon(a, b, ring).map_or(f64::INFINITY, |(_, _, d)| d)
}

/// The closest pair of points of the segment `ab` and the polygon `ring` as a solid: a point
/// of the segment, a point of the polygon's boundary, their distance — or, when the segment
/// starts inside the polygon, `a` twice and 0. `None` for an empty ring.
pub fn closest_points_segment_polygon<P: Copy + Into<Point>>(
    a: impl Into<Point>,
    b: impl Into<Point>,
    ring: &[P],
) -> Option<(Point, Point, f64)> {
    let (a, b) = (a.into(), b.into());
    if ring.is_empty() {
        return None;
    }
    if polygon_contains(ring, a) {
        return Some((a, a, 0.0));
    }
    ring_edges(ring)
        .map(|(c, d)| closest_points_segment_segment(a, b, c, d))
        .min_by(|x, y| x.2.total_cmp(&y.2))
}

/// Total length of the polyline through `points`.
pub fn polyline_length<P: Copy + Into<Point>>(points: &[P]) -> f64 {
    points
        .windows(2)
        .map(|w| (w[1].into() - w[0].into()).norm())
        .sum()
}
