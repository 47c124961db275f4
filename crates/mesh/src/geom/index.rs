//! A segment R-tree for clearance and tagging queries.

use rstar::{AABB, PointDistance, RTree, RTreeObject};

use super::{even_odd, point_segment_dist2, segment_segment_distance};
use crate::Point;

/// A segment with its payload and its bounding box, computed once: the bulk load compares
/// boxes O(n log n) times, and rstar's own `Line` recomputes its box at every comparison
/// (that was a fifth of the preparation of a forest of 3000 circles).
#[derive(Clone, Debug)]
struct Seg {
    from: [f64; 2],
    to: [f64; 2],
    data: u32,
    envelope: AABB<[f64; 2]>,
}

impl RTreeObject for Seg {
    type Envelope = AABB<[f64; 2]>;

    fn envelope(&self) -> Self::Envelope {
        self.envelope
    }
}

impl PointDistance for Seg {
    fn distance_2(&self, p: &[f64; 2]) -> f64 {
        point_segment_dist2(pt(*p), pt(self.from), pt(self.to))
    }
}

/// An R-tree of segments, each carrying a `u32` payload.
#[derive(Clone, Debug, Default)]
pub(crate) struct SegmentIndex {
    tree: RTree<Seg>,
}

fn finite(p: Point) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

fn pt(p: [f64; 2]) -> Point {
    Point::new(p[0], p[1])
}

impl SegmentIndex {
    pub(crate) fn new(segments: impl IntoIterator<Item = (Point, Point, u32)>) -> Self {
        let items: Vec<Seg> = segments
            .into_iter()
            .map(|(a, b, data)| Seg {
                from: [a.x, a.y],
                to: [b.x, b.y],
                data,
                envelope: AABB::from_corners([a.x, a.y], [b.x, b.y]),
            })
            .collect();
        SegmentIndex {
            tree: RTree::bulk_load(items),
        }
    }

    /// Segments whose bounding box meets the box `[lo, hi]`, as `(a, b, payload)`.
    pub(crate) fn in_box(&self, lo: Point, hi: Point) -> impl Iterator<Item = (Point, Point, u32)> {
        self.tree
            .locate_in_envelope_intersecting(&AABB::from_corners([lo.x, lo.y], [hi.x, hi.y]))
            .map(|s| (pt(s.from), pt(s.to), s.data))
    }

    /// The nearest segment to `p`: its distance and payload (`None` for a non-finite `p`,
    /// which the R-tree cannot order).
    pub(crate) fn nearest(&self, p: Point) -> Option<(f64, u32)> {
        if !finite(p) {
            return None;
        }
        self.tree
            .nearest_neighbor(&[p.x, p.y])
            .map(|s| (point_segment_dist2(p, pt(s.from), pt(s.to)).sqrt(), s.data))
    }

    /// [`nearest`](Self::nearest), first looking only at the segments whose boxes come within
    /// `r` of `p`: when `p` lies on (or within `r` of) a segment, as the midpoint of a mesh
    /// boundary edge does, a box query answers without the nearest-neighbour search's heap.
    /// The same answer as `nearest` either way.
    pub(crate) fn nearest_near(&self, p: Point, r: f64) -> Option<(f64, u32)> {
        if !finite(p) {
            return None;
        }
        let near = self
            .tree
            .locate_in_envelope_intersecting(&AABB::from_corners(
                [p.x - r, p.y - r],
                [p.x + r, p.y + r],
            ))
            .map(|s| (point_segment_dist2(p, pt(s.from), pt(s.to)), s.data))
            .min_by(|x, y| x.0.total_cmp(&y.0));
        match near {
            Some((d2, data)) if d2 <= r * r => Some((d2.sqrt(), data)),
            _ => self.nearest(p),
        }
    }

    /// Distance from `p` to the nearest segment (infinity if there is none, NaN for a
    /// non-finite `p`).
    pub(crate) fn distance(&self, p: Point) -> f64 {
        self.distance_where(p, |_| true)
    }

    /// Distance from `p` to the nearest segment whose payload `keep` accepts (infinity if
    /// there is none, NaN for a non-finite `p`): the segments in order of distance until one
    /// is kept.
    pub(crate) fn distance_where(&self, p: Point, keep: impl Fn(u32) -> bool) -> f64 {
        if !finite(p) {
            return f64::NAN;
        }
        self.tree
            .nearest_neighbor_iter(&[p.x, p.y])
            .find(|s| keep(s.data))
            .map_or(f64::INFINITY, |s| {
                point_segment_dist2(p, pt(s.from), pt(s.to)).sqrt()
            })
    }

    /// Distance from the polyline `points` (a segment: two points) to the nearest segment whose
    /// payload `keep` accepts: the smallest over its segments, 0 where one meets a kept
    /// segment (of its one point, for a single point; infinity for none; NaN if a point is not
    /// finite). Each vertex's nearest segment is found once, and a segment whose ends are
    /// farther, less half its length, than the smallest distance found so far is not searched:
    /// on a traced path of many short steps that is most of them.
    pub(crate) fn polyline_distance_where(
        &self,
        points: &[Point],
        keep: impl Fn(u32) -> bool + Copy,
    ) -> f64 {
        if !points.iter().all(|&p| finite(p)) {
            return f64::NAN;
        }
        let Some(&first) = points.first() else {
            return f64::INFINITY;
        };
        let mut d_prev = self.distance_where(first, keep);
        let mut best = d_prev;
        for w in points.windows(2) {
            let (a, b) = (w[0], w[1]);
            let d_b = self.distance_where(b, keep);
            let near = d_prev.min(d_b);
            best = best.min(near);
            d_prev = d_b;
            // Every point of ab is within half its length of an end.
            if best == 0.0 || !near.is_finite() || near - 0.5 * (b - a).norm() >= best {
                continue;
            }
            let lo = Point::new(a.x.min(b.x) - best, a.y.min(b.y) - best);
            let hi = Point::new(a.x.max(b.x) + best, a.y.max(b.y) + best);
            for (c, d, _) in self.in_box(lo, hi).filter(|&(_, _, k)| keep(k)) {
                best = best.min(segment_segment_distance(a, b, c, d));
                if best == 0.0 {
                    break;
                }
            }
        }
        best
    }

    /// Parity of the number of segments crossed by the ray from `p` towards +x (even-odd rule).
    pub(crate) fn ray_parity(&self, p: Point, x_max: f64) -> bool {
        let lo = Point::new(p.x, p.y);
        let hi = Point::new(x_max.max(p.x) + 1.0, p.y);
        even_odd(self.in_box(lo, hi).map(|(a, b, _)| (a, b)), p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The R-tree panics when asked to order a NaN distance; queries answer NaN instead.
    #[test]
    fn non_finite_points_get_nan_not_a_panic() {
        let index = SegmentIndex::new([(Point::new(0.0, 0.0), Point::new(1.0, 0.0), 0)]);
        let nan = Point::new(f64::NAN, 0.5);
        assert!(index.distance(nan).is_nan());
        assert!(index.nearest(nan).is_none());
        assert!(
            index
                .polyline_distance_where(&[nan, Point::new(0.5, 0.5)], |_| true)
                .is_nan()
        );
        assert_eq!(index.distance(Point::new(0.5, 2.0)), 2.0);
        assert!(index.nearest_near(nan, 1e-9).is_none());
    }

    #[test]
    fn nearest_near_agrees_with_nearest_on_and_off_the_segments() {
        let index = SegmentIndex::new([
            (Point::new(0.0, 0.0), Point::new(1.0, 0.0), 0),
            (Point::new(1.0, 0.0), Point::new(1.0, 1.0), 1),
            (Point::new(3.0, 0.0), Point::new(3.0, 2.0), 2),
        ]);
        for p in [
            Point::new(0.5, 0.0),
            Point::new(1.0, 0.5),
            Point::new(0.5, 1e-12),
            Point::new(2.2, 0.5),
            Point::new(2.9, 3.0),
        ] {
            assert_eq!(index.nearest_near(p, 1e-9), index.nearest(p), "at {p:?}");
        }
        assert_eq!(
            index.nearest_near(Point::new(2.2, 0.5), 1e-9).map(|n| n.1),
            Some(2)
        );
    }
}
