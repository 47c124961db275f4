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
//! Crossings and nesting are judged by the caller's check, which is the domain's own
//! ([`harmonic_mesh::Domain::of_rings`]): the rings are checked once, by the code that
//! would refuse them.

use harmonic_mesh::geom::{ring_edges, signed_area, simplify_ring};
use harmonic_mesh::{MeshError, Point};

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
/// `[i, i + 1] × [j, j + 1]`): one outer ring, counter-clockwise, and the holes, clockwise,
/// in no particular order.
pub(super) struct Traced {
    pub(super) rings: Vec<Vec<[f64; 2]>>,
}

impl Traced {
    /// The index of the outer ring (a 4-connected component has one), if any.
    pub(super) fn outer(&self) -> Option<usize> {
        self.rings.iter().position(|r| signed_area(r) > 0.0)
    }

    /// The indices of the holes, in order.
    pub(super) fn holes(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.rings.len()).filter(|&k| signed_area(&self.rings[k]) <= 0.0)
    }
}

/// Why a check refused a set of rings: the error, and the rings taking part in it (a
/// crossing, a wrong nesting), which simplification may give back as traced. With no ring
/// named the error stands.
pub(super) struct Refused {
    pub(super) rings: Vec<usize>,
    pub(super) error: MeshError,
}

/// Traces the 4-connected component of `clear` holding cell `(i, j)` (which must be set) and
/// simplifies its rings to `eps` cells, keeping their topology and keeping `goal` (in cell
/// `(i, j)`) inside, at least [`GOAL_ROOM`] cells from every ring: rings
/// whose simplification would take that room, or that `check` refuses, are kept as traced.
/// `check` sees every candidate set of rings (in the order of [`Traced::rings`]) and makes
/// what the caller builds of them; it is called until it accepts one. `Ok(None)` when even
/// the traced rings leave the goal less room (it lies in a corner of its cell at the
/// component's edge); an error when `check` refuses rings it cannot blame on
/// simplification. The rings and `goal` are in the cells of the whole map `clear` was cut
/// from: `clear`'s cell `(0, 0)` is the map's cell `offset` (`[0, 0]` for a whole map).
pub(super) fn trace<T>(
    clear: &BitGrid,
    (i, j): (usize, usize),
    offset: [f64; 2],
    eps: f64,
    goal: [f64; 2],
    check: impl FnMut(&Traced) -> Result<T, Refused>,
) -> Result<Option<(Traced, T)>, MeshError> {
    let component = bits::component(clear, i, j);
    let mut traced = bits::contours(&component);
    // In the whole map's cells (exactly: quarter cells plus whole ones), so that a planner
    // built on a part of a map traces, jitters and simplifies as one built on all of it.
    for p in traced.iter_mut().flatten() {
        p[0] += offset[0];
        p[1] += offset[1];
    }
    jitter(&mut traced);
    simplified(traced, eps, goal, check)
}

/// How far inside the traced rings the goal must stay, in cells.
pub(super) const GOAL_ROOM: f64 = 0.05;

/// Each ring simplified by Douglas–Peucker to `eps`, except the rings whose simplified forms
/// collapse or turn over, come within [`GOAL_ROOM`] of `goal` or put it outside, or take part
/// in what `check` refuses, which stay as they are (see [`trace`]).
fn simplified<T>(
    rings: Vec<Vec<[f64; 2]>>,
    eps: f64,
    goal: [f64; 2],
    mut check: impl FnMut(&Traced) -> Result<T, Refused>,
) -> Result<Option<(Traced, T)>, MeshError> {
    let mut out: Vec<Vec<[f64; 2]>> = rings
        .iter()
        .map(|r| {
            let s = simplify(r, eps);
            // The same orientation and no collapse, or the ring as traced.
            let (a, b) = (signed_area(r), signed_area(&s));
            if s.len() >= 3 && a * b > 0.0 && b.abs() >= 0.25 * a.abs() {
                s
            } else {
                r.clone()
            }
        })
        .collect();
    let mut exact: Vec<bool> = out.iter().zip(&rings).map(|(o, r)| o == r).collect();
    loop {
        let (bad, refused) = if room_for(&out, goal) {
            let candidate = Traced { rings: out };
            match check(&candidate) {
                Ok(made) => return Ok(Some((candidate, made))),
                Err(refused) => {
                    out = candidate.rings;
                    (refused.rings.clone(), Some(refused.error))
                }
            }
        } else {
            // The rings that come near the goal: within the tolerance and the room of it.
            let reach = eps + 1.0;
            (
                (0..out.len())
                    .filter(|&k| near(&out[k], goal, reach))
                    .collect(),
                None,
            )
        };
        let mut changed = false;
        for k in bad {
            if k < out.len() && !exact[k] {
                out[k] = rings[k].clone();
                exact[k] = true;
                changed = true;
            }
        }
        if !changed {
            // Traced rings are simple and disjoint: a refusal of them is the caller's to
            // report; no room around the goal is `None`.
            return refused.map_or(Ok(None), Err);
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

/// Douglas–Peucker on a closed ring ([`harmonic_mesh::geom::simplify_ring`]).
fn simplify(ring: &[[f64; 2]], eps: f64) -> Vec<[f64; 2]> {
    simplify_ring(ring, eps)
        .into_iter()
        .map(|k| ring[k])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_mesh::{Domain, MeshOptions};

    /// The planner's check, on grid coordinates: the domain of the rings (no goal), or the
    /// rings its refusal blames, sorted.
    fn check(t: &Traced) -> Result<(), Refused> {
        let points = |k: usize| -> Vec<Point> {
            t.rings[k].iter().map(|p| Point::new(p[0], p[1])).collect()
        };
        let outer = points(t.outer().expect("an outer ring"));
        let holes: Vec<Vec<Point>> = t.holes().map(points).collect();
        Domain::of_rings(&outer, &holes, &[], &MeshOptions::default())
            .map(|_| ())
            .map_err(|e| {
                let mut refused = crate::map::traced::refused(t, e);
                refused.rings.sort_unstable();
                refused
            })
    }

    fn blamed(rings: Vec<Vec<[f64; 2]>>) -> Option<Vec<usize>> {
        check(&Traced { rings }).err().map(|r| r.rings)
    }

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
        assert_eq!(blamed(rings.clone()), None);
        assert_eq!(
            blamed(vec![outer.clone(), simplify(&hole, 1.2)]),
            Some(vec![0, 1]),
            "the simplified hole crosses the bump"
        );
        let mut checks = 0;
        let (out, ()) = simplified(rings, 1.2, [30.0, 8.0], |t| {
            checks += 1;
            check(t)
        })
        .expect("no refusal of the traced rings")
        .expect("room for the goal");
        assert_eq!(out.rings, vec![outer, hole]);
        assert_eq!(checks, 2, "refused once, then accepted as traced");
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
        let (out, ()) = simplified(vec![outer.clone()], 2.0, goal, check)
            .expect("no refusal")
            .expect("room");
        assert_eq!(out.rings[0], outer);
        // A goal outside the traced ring has no room at all.
        assert!(
            simplified(vec![outer], 2.0, [10.0, 21.2], check)
                .expect("no refusal")
                .is_none()
        );
    }

    #[test]
    fn wrong_nestings_blame_both_rings() {
        let outer = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        let big = vec![[2.0, 2.0], [2.0, 8.0], [8.0, 8.0], [8.0, 2.0]];
        let inside_big = vec![[4.0, 4.0], [4.0, 5.0], [5.0, 5.0], [5.0, 4.0]];
        // A hole in a hole: both holes.
        assert_eq!(
            blamed(vec![outer.clone(), big, inside_big]),
            Some(vec![1, 2])
        );
        // A hole outside the outer ring: the hole and the outer ring.
        let outside = vec![[14.0, 4.0], [14.0, 5.0], [15.0, 5.0], [15.0, 4.0]];
        assert_eq!(blamed(vec![outside, outer.clone()]), Some(vec![0, 1]));
    }

    #[test]
    fn a_refusal_of_the_traced_rings_is_an_error() {
        // Two holes that touch: traced rings never do, so nothing can be given back.
        let outer = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        let a = vec![[2.0, 2.0], [2.0, 4.0], [4.0, 4.0], [4.0, 2.0]];
        let b = vec![[4.0, 2.0], [4.0, 4.0], [6.0, 4.0], [6.0, 2.0]];
        let e = simplified(vec![outer, a, b], 0.0, [8.0, 8.0], check)
            .err()
            .expect("refused");
        assert!(e.to_string().contains("touch or cross"), "{e}");
    }
}
