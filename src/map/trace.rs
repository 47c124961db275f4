//! The robot's free configuration space on a map as polygons: the clear cells around the
//! goal traced by marching squares and simplified without giving up the clearance.
//!
//! The guarantee is carried by the grid, not by polygon offsets. With a simplification
//! tolerance of `ε` cells the cells are cleared for a radius of `r + ε + ¼ + 10⁻⁶` cells
//! ([`bits::clear_cells`], exact square-to-square distances); the contour of the goal's
//! component stays within a quarter cell of those cells' squares (it cuts a corner of an
//! outside cell where three inside cells meet it), its vertices are moved off their lattice
//! by less than 10⁻⁶ cells ([`JITTER`]), and Douglas–Peucker moves it by at most `ε`. So
//! every point of the simplified polygons, and of the region they bound, keeps the
//! radius `r` from every blocked cell. Simplification never changes the topology: a ring whose
//! simplified form would cross another ring or itself, change its orientation, or end up on
//! the wrong side of another ring is kept as traced (traced rings are simple and disjoint).

use geo::{Coord, LineString, Simplify};
use harmonic_mesh::Point;
use harmonic_mesh::geom::{ring_edges, segments_intersect};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree, RTreeObject};

use super::bits::{self, BitGrid};

/// How far the traced contour may cut into a cell outside the component, in cells.
pub(super) const CONTOUR_CUT: f64 = 0.25;

/// How far [`jitter`] may move a traced vertex, in cells.
pub(super) const JITTER: f64 = 1e-6;

/// Moves every vertex of `rings` by a fixed pseudo-random offset (a hash of its position) of
/// less than [`JITTER`] cells. Traced vertices lie on a lattice of half and quarter cells,
/// where four of them are often cocircular, and each such tie sends the Delaunay
/// triangulation's in-circle test down its exact adaptive path (about 14 000 instructions;
/// on a 384² map a twentieth of the first plan in all). Off the lattice they are in general
/// position. The margin counts the move, so the clearance guarantee is unchanged, and the
/// rings stay simple and disjoint: their vertices and edges are a fraction of a cell apart.
fn jitter(rings: &mut [Vec<[f64; 2]>]) {
    for p in rings.iter_mut().flatten() {
        // splitmix64 of both coordinates' bits.
        let mut z = p[0]
            .to_bits()
            .wrapping_mul(0x9e37_79b9_7f4a_7c15)
            .wrapping_add(p[1].to_bits())
            .wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        // Two 26-bit fractions in [-1/2, 1/2): at most JITTER / √2 in all.
        let unit = |bits: u64| (bits & ((1 << 26) - 1)) as f64 / (1u64 << 26) as f64 - 0.5;
        p[0] += JITTER * unit(z);
        p[1] += JITTER * unit(z >> 32);
    }
}

/// The traced free space of the goal's component, in grid coordinates (cell `(i, j)` is
/// `[i, i + 1] × [j, j + 1]`).
pub(super) struct Traced {
    /// The outer ring, counter-clockwise.
    pub(super) outer: Vec<[f64; 2]>,
    /// The holes, clockwise.
    pub(super) holes: Vec<Vec<[f64; 2]>>,
}

/// Traces the 4-connected component of `clear` holding cell `(i, j)` (which must be set) and
/// simplifies its rings to `eps` cells, keeping their topology and keeping `goal` (grid
/// coordinates, in cell `(i, j)`) inside, at least [`GOAL_ROOM`] cells from every ring: rings
/// whose simplification would take that room are kept as traced. `None` when even the traced
/// rings leave the goal less room (it lies in a corner of its cell at the component's edge).
pub(super) fn trace(
    clear: &BitGrid,
    i: usize,
    j: usize,
    eps: f64,
    goal: [f64; 2],
) -> Option<Traced> {
    let component = bits::component(clear, i, j);
    let mut traced = bits::contours(&component);
    jitter(&mut traced);
    let rings = simplified(traced, eps, goal)?;
    let mut outer: Option<Vec<[f64; 2]>> = None;
    let mut holes = Vec::new();
    for ring in rings {
        if ring_area(&ring) > 0.0 {
            // A 4-connected component has one outer ring.
            outer = Some(ring);
        } else {
            holes.push(ring);
        }
    }
    Some(Traced {
        outer: outer.unwrap_or_default(),
        holes,
    })
}

/// How far inside the traced rings the goal must stay, in cells.
pub(super) const GOAL_ROOM: f64 = 0.05;

/// Each ring simplified by Douglas–Peucker to `eps`, except the rings whose simplified forms
/// would change the topology (see the module documentation) or come within [`GOAL_ROOM`] of
/// `goal` or put it outside, which stay as they are; `None` if the traced rings themselves do.
fn simplified(rings: Vec<Vec<[f64; 2]>>, eps: f64, goal: [f64; 2]) -> Option<Vec<Vec<[f64; 2]>>> {
    let mut out: Vec<Vec<[f64; 2]>> = rings
        .iter()
        .map(|r| {
            let s = simplify(r, eps);
            // The same orientation and no collapse, or the ring as traced.
            let (a, b) = (ring_area(r), ring_area(&s));
            if s.len() >= 3 && a * b > 0.0 && b.abs() >= 0.25 * a.abs() {
                s
            } else {
                r.clone()
            }
        })
        .collect();
    let mut exact: Vec<bool> = out.iter().zip(&rings).map(|(o, r)| o == r).collect();
    loop {
        let mut bad = conflicts(&out);
        if !room_for(&out, goal) {
            // The rings that come near the goal: within the tolerance and the room of it.
            let reach = eps + 1.0;
            bad.extend((0..out.len()).filter(|&k| near(&out[k], goal, reach)));
        }
        let mut changed = false;
        for k in bad {
            if !exact[k] {
                out[k] = rings[k].clone();
                exact[k] = true;
                changed = true;
            }
        }
        if !changed {
            return room_for(&out, goal).then_some(out);
        }
    }
}

/// Whether `p` lies inside the region `rings` bound (even-odd) and at least [`GOAL_ROOM`] from
/// every ring.
fn room_for(rings: &[Vec<[f64; 2]>], p: [f64; 2]) -> bool {
    let edges = || rings.iter().flat_map(|r| ring_edges(r));
    let inside = harmonic_mesh::geom::even_odd(edges(), Point::new(p[0], p[1]));
    inside
        && edges().all(|(a, b)| {
            harmonic_mesh::geom::point_segment_distance(Point::new(p[0], p[1]), a, b) >= GOAL_ROOM
        })
}

/// Whether the bounding box of `ring` comes within `reach` of `p`.
fn near(ring: &[[f64; 2]], p: [f64; 2], reach: f64) -> bool {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in ring {
        for d in 0..2 {
            lo[d] = lo[d].min(q[d]);
            hi[d] = hi[d].max(q[d]);
        }
    }
    (0..2).all(|d| p[d] >= lo[d] - reach && p[d] <= hi[d] + reach)
}

/// Douglas–Peucker on a closed ring (geo's `Simplify` on the ring closed at its first vertex).
fn simplify(ring: &[[f64; 2]], eps: f64) -> Vec<[f64; 2]> {
    if eps <= 0.0 || ring.len() <= 3 {
        return ring.to_vec();
    }
    let mut coords: Vec<Coord<f64>> = ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
    coords.push(coords[0]);
    let simplified = LineString::new(coords).simplify(eps);
    let mut out: Vec<[f64; 2]> = simplified.0.iter().map(|c| [c.x, c.y]).collect();
    out.pop();
    out
}

type Segment = GeomWithData<Rectangle<[f64; 2]>, (u32, u32)>;

/// The rings taking part in a crossing (two edges that meet and are not neighbours on one
/// ring) or in a wrong nesting (a hole outside the outer ring or inside another hole, found by
/// the parity of a ray from one of its vertices).
fn conflicts(rings: &[Vec<[f64; 2]>]) -> Vec<usize> {
    let edge = |r: usize, e: usize| {
        let ring = &rings[r];
        (ring[e], ring[(e + 1) % ring.len()])
    };
    let segments: Vec<Segment> = rings
        .iter()
        .enumerate()
        .flat_map(|(r, ring)| {
            (0..ring.len()).map(move |e| {
                let (a, b) = (ring[e], ring[(e + 1) % ring.len()]);
                GeomWithData::new(
                    Rectangle::from_corners(
                        [a[0].min(b[0]), a[1].min(b[1])],
                        [a[0].max(b[0]), a[1].max(b[1])],
                    ),
                    (r as u32, e as u32),
                )
            })
        })
        .collect();
    let tree = RTree::bulk_load(segments.clone());
    let point = |p: [f64; 2]| Point::new(p[0], p[1]);
    let mut bad = vec![false; rings.len()];
    for s in &segments {
        let (r, e) = (s.data.0 as usize, s.data.1 as usize);
        let (a, b) = edge(r, e);
        for o in tree.locate_in_envelope_intersecting(&s.envelope()) {
            let (r2, e2) = (o.data.0 as usize, o.data.1 as usize);
            if (r2, e2) <= (r, e) {
                continue;
            }
            let n = rings[r].len();
            if r2 == r && (e2 == (e + 1) % n || e == (e2 + 1) % n) {
                continue;
            }
            let (c, d) = edge(r2, e2);
            if segments_intersect(point(a), point(b), point(c), point(d)) {
                bad[r] = true;
                bad[r2] = true;
            }
        }
    }
    // Nesting: a ray from a vertex of each hole to the right crosses the other rings an odd
    // number of times (once, the outer ring) when the hole is where it belongs.
    let x_max = segments
        .iter()
        .map(|s| s.envelope().upper()[0])
        .fold(f64::NEG_INFINITY, f64::max);
    for (r, ring) in rings.iter().enumerate() {
        if ring_area(ring) > 0.0 {
            continue;
        }
        let p = ring[0];
        let ray = AABB::from_corners([p[0], p[1]], [x_max + 1.0, p[1]]);
        let mut crossed = Vec::new();
        for o in tree.locate_in_envelope_intersecting(&ray) {
            let (r2, e2) = (o.data.0 as usize, o.data.1 as usize);
            if r2 == r {
                continue;
            }
            let (a, b) = edge(r2, e2);
            if (a[1] > p[1]) != (b[1] > p[1])
                && a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]) > p[0]
            {
                crossed.push(r2);
            }
        }
        if crossed.len() % 2 == 0 {
            bad[r] = true;
            for r2 in crossed {
                bad[r2] = true;
            }
        }
    }
    (0..rings.len()).filter(|&r| bad[r]).collect()
}

/// The signed area of a ring (positive counter-clockwise).
pub(super) fn ring_area(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|k| {
            let (p, q) = (ring[k], ring[(k + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simplification_keeps_rings_that_would_cross_as_traced() {
        // The outer ring's bottom bumps up to (20, 1.5); the hole's bottom bows over the
        // bump. At 1.2 cells the hole's bow would straighten through the bump.
        let outer = vec![
            [0.0, 0.0],
            [20.0, 1.5],
            [40.0, 0.0],
            [40.0, 10.0],
            [0.0, 10.0],
        ];
        let hole = vec![
            [5.0, 1.0],
            [5.0, 3.0],
            [35.0, 3.0],
            [35.0, 1.0],
            [20.0, 2.0],
        ];
        let rings = vec![outer.clone(), hole.clone()];
        assert!(conflicts(&rings).is_empty());
        assert_eq!(
            conflicts(&[outer.clone(), simplify(&hole, 1.2)]),
            vec![0, 1],
            "the simplified hole crosses the bump"
        );
        let out = simplified(rings, 1.2, [30.0, 8.0]).expect("room for the goal");
        assert_eq!(out, vec![outer, hole]);
        assert!(conflicts(&out).is_empty());
    }

    #[test]
    fn a_goal_near_the_boundary_keeps_its_rings_as_traced() {
        // A square with a one-cell tab out at the goal: simplified at 2 cells the tab would
        // go and take the goal (in it) outside.
        let outer = vec![
            [0.0, 0.0],
            [20.0, 0.0],
            [20.0, 20.0],
            [10.5, 20.0],
            [10.5, 21.0],
            [9.5, 21.0],
            [9.5, 20.0],
            [0.0, 20.0],
        ];
        assert_eq!(simplify(&outer, 2.0).len(), 4);
        let goal = [10.0, 20.5];
        let out = simplified(vec![outer.clone()], 2.0, goal).expect("room");
        assert_eq!(out[0], outer);
        // A goal outside the traced ring has no room at all.
        assert!(simplified(vec![outer], 2.0, [10.0, 21.2]).is_none());
    }

    #[test]
    fn a_hole_jumped_by_another_ring_is_found() {
        let outer = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        let big = vec![[2.0, 2.0], [2.0, 8.0], [8.0, 8.0], [8.0, 2.0]];
        let inside_big = vec![[4.0, 4.0], [4.0, 5.0], [5.0, 5.0], [5.0, 4.0]];
        // The nested hole and every ring its ray crosses (the culprit is among them).
        let bad = conflicts(&[outer.clone(), big, inside_big]);
        assert_eq!(bad, vec![0, 1, 2]);
        let outside = vec![[14.0, 4.0], [14.0, 5.0], [15.0, 5.0], [15.0, 4.0]];
        assert_eq!(conflicts(&[outer, outside]), vec![1]);
    }
}
