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

    /// The nearest segment to `p`: its distance and payload.
    pub(crate) fn nearest(&self, p: Point) -> Option<(f64, u32)> {
        self.tree.nearest_neighbor(&[p.x, p.y]).map(|s| {
            (
                point_segment_dist2(p, pt(s.geom().from), pt(s.geom().to)).sqrt(),
                s.data,
            )
        })
    }

    /// Distance from `p` to the nearest segment (infinity if there is none).
    pub(crate) fn distance(&self, p: Point) -> f64 {
        self.tree
            .nearest_neighbor(&[p.x, p.y])
            .map_or(f64::INFINITY, |s| {
                point_segment_dist2(p, pt(s.geom().from), pt(s.geom().to)).sqrt()
            })
    }

    /// Distance from the segment `ab` to the nearest segment (0 if they meet).
    pub(crate) fn segment_distance(&self, a: Point, b: Point) -> f64 {
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
