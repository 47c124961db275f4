//! Snapping of near-touching input rings before the polygon booleans.
//!
//! An input vertex a hair's breadth off another input's edge (an obstacle corner at
//! `y = 2e-16` next to the wall `y = 0`) is neither touching nor clearly apart: the booleans
//! keep the sliver between them, and Delaunay refinement then has to resolve a gap far below
//! the floating-point resolution of the scene (spade fails to locate its own Steiner points).
//! Moving such a vertex onto the edge, and giving the edge that vertex too, turns the near
//! touch into an exact one, which the booleans handle like any flush obstacle.

use geo::{Coord, LineString, MultiPolygon, Polygon};

use crate::Point;
use crate::geom::{SegmentIndex, point_segment_dist2};

/// The rings of a multipolygon: per polygon, the exterior ring then the holes, each not closed.
pub(crate) type Rings = Vec<Vec<Vec<Point>>>;

/// The rings of `mp`, without the closing vertex.
pub(crate) fn rings_of(mp: &MultiPolygon<f64>) -> Rings {
    mp.0.iter()
        .map(|poly| {
            std::iter::once(poly.exterior())
                .chain(poly.interiors())
                .map(|ls| {
                    let mut v: Vec<Point> = ls.0.iter().map(|c| Point::new(c.x, c.y)).collect();
                    if v.len() > 1 && v[0] == v[v.len() - 1] {
                        v.pop();
                    }
                    v
                })
                .collect()
        })
        .collect()
}

/// The multipolygon of `rings` (polygons whose exterior has fewer than 3 vertices are dropped,
/// and so are such holes).
pub(crate) fn multipolygon_of(rings: &Rings) -> MultiPolygon<f64> {
    let ls = |r: &Vec<Point>| {
        LineString::from(
            r.iter()
                .map(|p| Coord { x: p.x, y: p.y })
                .collect::<Vec<_>>(),
        )
    };
    MultiPolygon(
        rings
            .iter()
            .filter(|poly| poly.first().is_some_and(|e| e.len() >= 3))
            .map(|poly| {
                Polygon::new(
                    ls(&poly[0]),
                    poly[1..].iter().filter(|h| h.len() >= 3).map(ls).collect(),
                )
            })
            .collect(),
    )
}

/// The point of segment `ab` nearest to `p`, exactly on the segment when it is horizontal or
/// vertical.
fn project(p: Point, a: Point, b: Point) -> Point {
    if a.y == b.y {
        return Point::new(p.x.clamp(a.x.min(b.x), a.x.max(b.x)), a.y);
    }
    if a.x == b.x {
        return Point::new(a.x, p.y.clamp(a.y.min(b.y), a.y.max(b.y)));
    }
    crate::geom::closest_point_on_segment(p, a, b)
}

/// Makes near touches between different groups of rings exact.
///
/// `groups` are in priority order (workspace, obstacles, goals). A vertex within `tol` of a
/// vertex of a group earlier in the list moves onto that vertex; otherwise, within `tol` of an
/// edge of an earlier group, it moves onto the edge (its nearest point). Then every vertex
/// lying within `tol` of another group's edge (not at its ends) is inserted into that edge, so
/// the two rings share the vertex exactly. Vertices move by at most `tol`; rings of one group
/// are not snapped to each other. Returns whether anything changed.
pub(crate) fn snap_near_touches(groups: &mut [Rings], tol: f64) -> bool {
    if !(tol > 0.0 && tol.is_finite()) || groups.len() < 2 {
        return false;
    }
    // Every ring as (group, polygon, ring); every edge as (ring id, edge index).
    let mut ring_ids: Vec<(usize, usize, usize)> = Vec::new();
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for (g, group) in groups.iter().enumerate() {
        for (p, poly) in group.iter().enumerate() {
            for (r, ring) in poly.iter().enumerate() {
                let id = ring_ids.len() as u32;
                ring_ids.push((g, p, r));
                edges.extend((0..ring.len() as u32).map(|k| (id, k)));
            }
        }
    }
    let edge_points = |groups: &[Rings], e: u32| -> (Point, Point) {
        let (id, k) = edges[e as usize];
        let (g, p, r) = ring_ids[id as usize];
        let pts = &groups[g][p][r];
        (pts[k as usize], pts[(k as usize + 1) % pts.len()])
    };
    let build_index = |groups: &[Rings]| {
        SegmentIndex::new((0..edges.len() as u32).map(|e| {
            let (a, b) = edge_points(groups, e);
            (a, b, e)
        }))
    };
    let tol2 = tol * tol;
    let mut changed = false;

    // Pass 1: move vertices onto vertices, then edges, of higher-priority groups. Earlier
    // groups are final by the time a group is processed; the index holds the original
    // positions, which differ from the current ones by at most `tol`, hence the wider box.
    let index = build_index(groups);
    let w = 2.0 * tol;
    for id in 0..ring_ids.len() as u32 {
        let (g, p, r) = ring_ids[id as usize];
        if g == 0 {
            continue;
        }
        for k in 0..groups[g][p][r].len() {
            let v = groups[g][p][r][k];
            let near: Vec<(Point, Point)> = index
                .in_box(Point::new(v.x - w, v.y - w), Point::new(v.x + w, v.y + w))
                .filter(|&(_, _, e)| ring_ids[edges[e as usize].0 as usize].0 < g)
                .map(|(_, _, e)| edge_points(groups, e))
                .collect();
            let nearest_vertex = near
                .iter()
                .flat_map(|&(a, b)| [a, b])
                .map(|q| ((q - v).norm_squared(), q))
                .filter(|&(d, _)| d <= tol2)
                .min_by(|x, y| x.0.total_cmp(&y.0));
            let target = match nearest_vertex {
                Some((_, q)) => Some(q),
                None => near
                    .iter()
                    .map(|&(a, b)| (point_segment_dist2(v, a, b), a, b))
                    .filter(|&(d, _, _)| d <= tol2)
                    .min_by(|x, y| x.0.total_cmp(&y.0))
                    .map(|(_, a, b)| project(v, a, b)),
            };
            if let Some(q) = target
                && q != v
            {
                groups[g][p][r][k] = q;
                changed = true;
            }
        }
    }

    // Pass 2: insert each vertex into the other groups' edges it lies on (within `tol`).
    // The index of pass 1 still holds every edge where it is unless a vertex moved.
    let index = if changed { build_index(groups) } else { index };
    let mut cuts: Vec<(u32, f64, Point)> = Vec::new();
    for id in 0..ring_ids.len() as u32 {
        let (g, p, r) = ring_ids[id as usize];
        for &v in &groups[g][p][r] {
            for (_, _, e) in index.in_box(
                Point::new(v.x - tol, v.y - tol),
                Point::new(v.x + tol, v.y + tol),
            ) {
                if ring_ids[edges[e as usize].0 as usize].0 == g {
                    continue;
                }
                let (a, b) = edge_points(groups, e);
                if v == a || v == b || point_segment_dist2(v, a, b) > tol2 {
                    continue;
                }
                let ab = b - a;
                let t = (v - a).dot(&ab) / ab.norm_squared();
                if t > 0.0 && t < 1.0 {
                    cuts.push((e, t, v));
                }
            }
        }
    }
    if cuts.is_empty() {
        return changed;
    }
    cuts.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    cuts.dedup_by(|x, y| x.0 == y.0 && x.2 == y.2);
    let mut by_ring: Vec<Vec<(u32, Point)>> = vec![Vec::new(); ring_ids.len()];
    for &(e, _, v) in &cuts {
        let (id, k) = edges[e as usize];
        by_ring[id as usize].push((k, v));
    }
    for (id, ring_cuts) in by_ring.iter().enumerate() {
        if ring_cuts.is_empty() {
            continue;
        }
        let (g, p, r) = ring_ids[id];
        let old = std::mem::take(&mut groups[g][p][r]);
        let mut new = Vec::with_capacity(old.len() + ring_cuts.len());
        let mut c = 0;
        for (k, &q) in old.iter().enumerate() {
            new.push(q);
            while c < ring_cuts.len() && ring_cuts[c].0 as usize == k {
                new.push(ring_cuts[c].1);
                c += 1;
            }
        }
        groups[g][p][r] = new;
    }
    true
}

/// Drops consecutive duplicate vertices (snapping can merge neighbours) from every ring.
pub(crate) fn dedup_rings(rings: &mut Rings) {
    for poly in rings {
        for ring in poly.iter_mut() {
            ring.dedup();
            while ring.len() > 1 && ring[0] == ring[ring.len() - 1] {
                ring.pop();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn a_vertex_just_off_a_horizontal_wall_lands_on_it_and_splits_it() {
        let mut groups = vec![
            vec![vec![vec![
                p(0.0, 0.0),
                p(20.0, 0.0),
                p(20.0, 10.0),
                p(0.0, 10.0),
            ]]],
            vec![vec![vec![p(8.0, 2.0), p(12.5, 2.1e-16), p(11.0, 7.0)]]],
        ];
        assert!(snap_near_touches(&mut groups, 1e-8));
        assert_eq!(groups[1][0][0][1], p(12.5, 0.0));
        assert_eq!(
            groups[0][0][0],
            vec![
                p(0.0, 0.0),
                p(12.5, 0.0),
                p(20.0, 0.0),
                p(20.0, 10.0),
                p(0.0, 10.0)
            ]
        );
    }

    #[test]
    fn a_wall_corner_just_inside_an_obstacle_edge_splits_the_edge() {
        // The workspace never moves: the obstacle edge gets the corner as a vertex.
        let mut groups = vec![
            vec![vec![vec![
                p(0.0, 0.0),
                p(10.0, 0.0),
                p(10.0, 10.0),
                p(0.0, 10.0),
            ]]],
            vec![vec![vec![p(9.0, 1.0), p(11.0, -1.0 + 1e-13), p(11.0, 3.0)]]],
        ];
        // (10, 0) is 7e-14 off the edge (9,1)-(11,-1+1e-13).
        assert!(snap_near_touches(&mut groups, 1e-8));
        assert_eq!(groups[1][0][0][1], p(10.0, 0.0));
        assert_eq!(groups[1][0][0].len(), 4);
    }

    #[test]
    fn rings_apart_by_more_than_the_tolerance_are_left_alone() {
        let mut groups = vec![
            vec![vec![vec![
                p(0.0, 0.0),
                p(20.0, 0.0),
                p(20.0, 10.0),
                p(0.0, 10.0),
            ]]],
            vec![vec![vec![p(8.0, 2.0), p(12.5, 1e-6), p(11.0, 7.0)]]],
        ];
        let before = groups.clone();
        assert!(!snap_near_touches(&mut groups, 1e-8));
        assert_eq!(groups, before);
    }
}
