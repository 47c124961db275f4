//! Douglas–Peucker simplification of a closed ring.
//!
//! The ring is read as the polyline from its first vertex around and back to it, which is
//! what geo's `Simplify` does with a closed `LineString`, and the same vertices are kept
//! (the farthest vertex of a span is the last one at the largest distance; a span is cut when
//! that distance exceeds the tolerance). It works on squared distances and on indices, with
//! no allocation per span: on a traced map's rings it costs less than half of geo's (`hypot`
//! per vertex and a vector per level of recursion there; tb3_sandbox's first plan: 0.09 M
//! instructions against 0.19 M).

use super::point_segment_dist2;
use crate::Point;

/// The vertices of the closed `ring` that Douglas–Peucker keeps at tolerance `eps`, as
/// indices in ring order, vertex 0 first (it is always kept: the polyline starts and ends
/// there). Every vertex of `ring` lies within `eps` of the kept ring, edge for edge: a dropped
/// vertex is within `eps` of the kept edge that spans it. With `eps` not positive, or three
/// vertices or fewer, every vertex is kept.
///
/// ```
/// use harmonic_mesh::geom::simplify_ring;
/// // A square with a slight bump on its bottom edge.
/// let ring = [[0.0, 0.0], [1.0, 0.01], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
/// assert_eq!(simplify_ring(&ring, 0.1), vec![0, 2, 3, 4]);
/// assert_eq!(simplify_ring(&ring, 0.001), vec![0, 1, 2, 3, 4]);
/// ```
pub fn simplify_ring<P: Copy + Into<Point>>(ring: &[P], eps: f64) -> Vec<usize> {
    let n = ring.len();
    if eps.is_nan() || eps <= 0.0 || n <= 3 {
        return (0..n).collect();
    }
    // Vertex n is vertex 0 again: the polyline closes where it began.
    let at = |k: usize| -> Point { ring[k % n].into() };
    let eps2 = eps * eps;
    let mut keep = vec![false; n];
    keep[0] = true;
    let mut spans = vec![(0, n)];
    while let Some((a, b)) = spans.pop() {
        let (pa, pb) = (at(a), at(b));
        let mut far = (a, 0.0);
        for k in a + 1..b {
            let d = point_segment_dist2(at(k), pa, pb);
            if d >= far.1 {
                far = (k, d);
            }
        }
        if far.1 > eps2 {
            keep[far.0] = true;
            spans.push((far.0, b));
            spans.push((a, far.0));
        }
    }
    (0..n).filter(|&k| keep[k]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Coord, LineString, Simplify};
    use proptest::prelude::*;

    /// geo's Douglas–Peucker on the ring closed at its first vertex, less the closing vertex.
    fn geo_simplified(ring: &[[f64; 2]], eps: f64) -> Vec<[f64; 2]> {
        let mut coords: Vec<Coord<f64>> = ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
        coords.push(coords[0]);
        let mut out: Vec<[f64; 2]> = LineString::new(coords)
            .simplify(eps)
            .0
            .iter()
            .map(|c| [c.x, c.y])
            .collect();
        out.pop();
        out
    }

    proptest! {
        /// The same vertices as geo's `Simplify`, the well-kept implementation this one
        /// stands in for on the map's hot path.
        #[test]
        fn keeps_what_geo_keeps(
            ring in prop::collection::vec((-50.0..50.0f64, -50.0..50.0f64), 4..80),
            eps in 0.01..20.0f64,
        ) {
            let ring: Vec<[f64; 2]> = ring.into_iter().map(|(x, y)| [x, y]).collect();
            let ours: Vec<[f64; 2]> = simplify_ring(&ring, eps).into_iter().map(|k| ring[k]).collect();
            prop_assert_eq!(ours, geo_simplified(&ring, eps));
        }

        /// Every dropped vertex lies within `eps` of the kept edge that spans it.
        #[test]
        fn dropped_vertices_stay_within_the_tolerance(
            ring in prop::collection::vec((-50.0..50.0f64, -50.0..50.0f64), 4..80),
            eps in 0.01..20.0f64,
        ) {
            let ring: Vec<Point> = ring.into_iter().map(|(x, y)| Point::new(x, y)).collect();
            let kept = simplify_ring(&ring, eps);
            let n = ring.len();
            for (s, &a) in kept.iter().enumerate() {
                let b = kept.get(s + 1).copied().unwrap_or(n);
                for k in a + 1..b {
                    let d = point_segment_dist2(ring[k], ring[a], ring[b % n]).sqrt();
                    prop_assert!(d <= eps * (1.0 + 1e-12), "vertex {k}: {d} > {eps}");
                }
            }
        }
    }

    #[test]
    fn small_rings_and_no_tolerance_keep_every_vertex() {
        let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert_eq!(simplify_ring(&tri, 10.0), vec![0, 1, 2]);
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(simplify_ring(&square, 0.0), vec![0, 1, 2, 3]);
        assert_eq!(simplify_ring(&square, f64::NAN), vec![0, 1, 2, 3]);
        // A tolerance wider than the ring leaves its first vertex alone.
        assert_eq!(simplify_ring(&square, 5.0), vec![0]);
    }
}
