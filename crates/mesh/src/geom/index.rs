//! A segment R-tree for clearance and tagging queries.

use rstar::primitives::{GeomWithData, Line};
use rstar::{AABB, RTree};

use super::{even_odd, point_segment_dist2, segment_segment_distance};
use crate::Point;

type Seg = GeomWithData<Line<[f64; 2]>, u32>;

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
            .map(|(a, b, d)| GeomWithData::new(Line::new([a.x, a.y], [b.x, b.y]), d))
            .collect();
        SegmentIndex {
            tree: RTree::bulk_load(items),
        }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.tree.size() == 0
    }

    /// Segments whose bounding box meets the box `[lo, hi]`, as `(a, b, payload)`.
    pub(crate) fn in_box(&self, lo: Point, hi: Point) -> impl Iterator<Item = (Point, Point, u32)> {
        self.tree
            .locate_in_envelope_intersecting(&AABB::from_corners([lo.x, lo.y], [hi.x, hi.y]))
            .map(|s| (pt(s.geom().from), pt(s.geom().to), s.data))
    }

    /// The nearest segment to `p`: its distance and payload (`None` for a non-finite `p`,
    /// which the R-tree cannot order).
    pub(crate) fn nearest(&self, p: Point) -> Option<(f64, u32)> {
        if !finite(p) {
            return None;
        }
        self.tree.nearest_neighbor(&[p.x, p.y]).map(|s| {
            (
                point_segment_dist2(p, pt(s.geom().from), pt(s.geom().to)).sqrt(),
                s.data,
            )
        })
    }

    /// Distance from `p` to the nearest segment (infinity if there is none, NaN for a
    /// non-finite `p`).
    pub(crate) fn distance(&self, p: Point) -> f64 {
        if !finite(p) {
            return f64::NAN;
        }
        self.tree
            .nearest_neighbor(&[p.x, p.y])
            .map_or(f64::INFINITY, |s| {
                point_segment_dist2(p, pt(s.geom().from), pt(s.geom().to)).sqrt()
            })
    }

    /// Distance from the segment `ab` to the nearest segment (0 if they meet; NaN if an end
    /// is not finite).
    pub(crate) fn segment_distance(&self, a: Point, b: Point) -> f64 {
        if !(finite(a) && finite(b)) {
            return f64::NAN;
        }
        let mut best = self.distance(a).min(self.distance(b));
        if !best.is_finite() || best == 0.0 {
            return best;
        }
        let lo = Point::new(a.x.min(b.x) - best, a.y.min(b.y) - best);
        let hi = Point::new(a.x.max(b.x) + best, a.y.max(b.y) + best);
        for (c, d, _) in self.in_box(lo, hi) {
            best = best.min(segment_segment_distance(a, b, c, d));
            if best == 0.0 {
                break;
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
        assert!(index.segment_distance(nan, Point::new(0.5, 0.5)).is_nan());
        assert_eq!(index.distance(Point::new(0.5, 2.0)), 2.0);
    }
}
