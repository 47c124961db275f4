//! Large meshes in two halves: free space is cut along an axis-parallel line, each half is
//! triangulated and refined on its own thread, and the halves are glued along the cut.
//!
//! The cut is a line `x = c` or `y = c` near the median of free area. Delaunay refinement
//! splits a cut segment at a weighted mean `w₀·a + w₁·b` of its ends; when `c` is `0` or
//! `±2^k` the products are exact and their sum rounds back to `c`, so every vertex refinement
//! puts on such a cut stays exactly on it, each half can take the other half's cut vertices
//! verbatim (an insertion exactly on a constraint edge splits it), and refinement runs again
//! until both halves have the same ones. On any other line the pre-split seam is glued only if
//! refinement left it alone (on the reference scene at 1 M triangles it does). The cut may pass
//! through ring vertices and run along ring segments (such a segment stays boundary, on the
//! side of free space); only its stretches through free space are glued. It must meet the
//! rings at 60° or more. Without a usable cut, or when the halves do not settle, the caller
//! meshes in one piece.

use spade::Point2;

use crate::geom::SegmentIndex;
use crate::{Domain, Point, TaggedRing};

/// The cut line: points whose coordinate `axis` (0 = x, 1 = y) is `at`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cut {
    pub axis: usize,
    pub at: f64,
    /// `at` is 0 or ±2^k: every point refinement puts on the cut is exactly on it, so the
    /// halves can exchange such points. On any other cut the halves are only glued if
    /// refinement left the cut's pre-split points alone.
    pub exact: bool,
}

impl Cut {
    /// The coordinate across the cut.
    pub fn across(&self, p: Point2<f64>) -> f64 {
        if self.axis == 0 { p.x } else { p.y }
    }

    /// The coordinate along the cut.
    pub fn along(&self, p: Point2<f64>) -> f64 {
        if self.axis == 0 { p.y } else { p.x }
    }

    /// The point of the cut at `t` along it.
    pub fn point(&self, t: f64) -> Point2<f64> {
        if self.axis == 0 {
            Point2::new(self.at, t)
        } else {
            Point2::new(t, self.at)
        }
    }

    /// Whether `p` lies exactly on the cut line.
    pub fn holds(&self, p: Point2<f64>) -> bool {
        self.across(p) == self.at
    }

    /// Area of `ring` (signed: counter-clockwise positive) on the low side of the cut
    /// (half-plane clipping keeps the shoelace sum exact for any simple ring).
    fn low_area(&self, ring: &[Point]) -> f64 {
        let pt = |p: &Point| Point2::new(p.x, p.y);
        let mut clipped: Vec<Point2<f64>> = Vec::with_capacity(ring.len() + 2);
        for k in 0..ring.len() {
            let (a, b) = (pt(&ring[k]), pt(&ring[(k + 1) % ring.len()]));
            let (da, db) = (self.across(a) - self.at, self.across(b) - self.at);
            if da <= 0.0 {
                clipped.push(a);
            }
            if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
                clipped.push(self.crossing(a, b));
            }
        }
        let n = clipped.len();
        (0..n)
            .map(|k| {
                let (a, b) = (clipped[k], clipped[(k + 1) % n]);
                a.x * b.y - a.y * b.x
            })
            .sum::<f64>()
            * 0.5
    }

    /// Whether every ring segment that crosses or touches the cut (and does not run along
    /// it) meets it at 60° or more: where the halves are refined alone, the cut is a boundary,
    /// and a shallower angle there would be a small input angle that refinement cannot remove.
    fn meets_rings_steeply(&self, rings: &[TaggedRing]) -> bool {
        let min_sin = 60f64.to_radians().sin();
        rings.iter().all(|ring| {
            let n = ring.points.len();
            (0..n).all(|k| {
                let (a, b) = (ring.points[k], ring.points[(k + 1) % n]);
                let (a, b) = (Point2::new(a.x, a.y), Point2::new(b.x, b.y));
                let (da, db) = (self.across(a) - self.at, self.across(b) - self.at);
                let meets = (da <= 0.0 && db >= 0.0) || (da >= 0.0 && db <= 0.0);
                let along = da == 0.0 && db == 0.0;
                let length = (b.x - a.x).hypot(b.y - a.y);
                !meets || along || (db - da).abs() >= min_sin * length
            })
        })
    }

    /// Where segment `a`–`b` (with ends strictly on either side) crosses the cut.
    fn crossing(&self, a: Point2<f64>, b: Point2<f64>) -> Point2<f64> {
        let s = (self.at - self.across(a)) / (self.across(b) - self.across(a));
        self.point(self.along(a) + s * (self.along(b) - self.along(a)))
    }
}

/// A ring's bounding box and signed area (the shoelace sum [`Cut::low_area`] takes over a
/// ring wholly on the low side).
struct RingExtent {
    lo: [f64; 2],
    hi: [f64; 2],
    area: f64,
}

impl RingExtent {
    fn of(ring: &[Point]) -> RingExtent {
        let (lo, hi) = crate::domain::bbox_of(ring);
        RingExtent {
            lo: [lo.x, lo.y],
            hi: [hi.x, hi.y],
            area: crate::geom::signed_area(ring),
        }
    }
}

/// How much more even an exact cut counts than a median cut: its halves settle by
/// exchanging seam vertices, while a median cut's glue only when refinement leaves the seam
/// alone (otherwise the mesh is made again in one piece, which costs more than a less even
/// split).
const EXACT_BONUS: f64 = 0.15;

/// Cuts to mesh `domain` in two halves, best first: axis-parallel lines at the values `0` and
/// `±2^k` (whose split points stay exact) and, on each axis, through the median of free area
/// (moved off the rings' vertices by at least `spacing / 4`), ranked by how evenly they split
/// free space, an exact cut counting as [`EXACT_BONUS`] more even. Each leaves between 30 % and
/// 70 % of free space on each side and meets the rings steeply.
pub(crate) fn choose_cuts(domain: &Domain, spacing: f64) -> Vec<Cut> {
    let rings = domain.unit_rings();
    let (lo, hi) = domain.unit_bbox();
    let total = domain.unit_free_area();
    // Each ring's extent: a ring wholly on one side of a cut is all or nothing of its
    // area (the clipping would give the very same sum), so only rings the cut crosses are
    // clipped — the median search evaluates 120 cuts.
    let extents: Vec<RingExtent> = rings.iter().map(|r| RingExtent::of(&r.points)).collect();
    let low_fraction = |cut: &Cut| {
        rings
            .iter()
            .zip(&extents)
            .map(|(r, e)| {
                if e.hi[cut.axis] <= cut.at {
                    e.area
                } else if e.lo[cut.axis] > cut.at {
                    0.0
                } else {
                    cut.low_area(&r.points)
                }
            })
            .sum::<f64>()
            / total
    };
    let mut ranked: Vec<(f64, Cut)> = Vec::new();
    let mut consider = |cut: Cut| {
        if !cut.meets_rings_steeply(rings) {
            return;
        }
        let imbalance = (low_fraction(&cut) - 0.5).abs();
        let score = imbalance - if cut.exact { EXACT_BONUS } else { 0.0 };
        if imbalance <= 0.2 {
            ranked.push((score, cut));
        }
    };
    for axis in 0..2 {
        let (l, h) = if axis == 0 {
            (lo.x, hi.x)
        } else {
            (lo.y, hi.y)
        };
        let span = h - l;
        if !(span > 0.0 && span.is_finite()) {
            continue;
        }
        let inside = |at: f64| at > l + 0.05 * span && at < h - 0.05 * span;
        let top = l.abs().max(h.abs()).log2().ceil() as i32;
        let powers = (top - 60..=top).flat_map(|k| [2f64.powi(k), -(2f64.powi(k))]);
        for at in powers.chain([0.0]).filter(|&at| inside(at)) {
            consider(Cut {
                axis,
                at,
                exact: true,
            });
        }
        // The median of free area along this axis (the low side's area grows with `at`).
        let (mut a, mut b) = (l, h);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            let cut = Cut {
                axis,
                at: m,
                exact: false,
            };
            if low_fraction(&cut) < 0.5 {
                a = m;
            } else {
                b = m;
            }
        }
        let median = 0.5 * (a + b);
        let clear = |at: f64| {
            rings.iter().flat_map(|r| &r.points).all(|p| {
                let c = if axis == 0 { p.x } else { p.y };
                (c - at).abs() >= 0.25 * spacing
            })
        };
        let nudged = (0..16)
            .map(|k| {
                let step = 0.5 * spacing * f64::from((k + 1) / 2);
                if k % 2 == 0 {
                    median + step
                } else {
                    median - step
                }
            })
            .find(|&at| inside(at) && clear(at));
        if let Some(at) = nudged {
            consider(Cut {
                axis,
                at,
                exact: false,
            });
        }
    }
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    ranked.into_iter().map(|(_, cut)| cut).collect()
}

/// Constraint input of one half: vertices and edges (indices into the vertices).
#[derive(Default)]
pub(crate) struct HalfInput {
    pub vertices: Vec<Point2<f64>>,
    pub edges: Vec<[usize; 2]>,
    ids: std::collections::HashMap<(u64, u64), usize>,
}

impl HalfInput {
    fn vertex(&mut self, p: Point2<f64>) -> usize {
        *self
            .ids
            .entry((p.x.to_bits(), p.y.to_bits()))
            .or_insert_with(|| {
                self.vertices.push(p);
                self.vertices.len() - 1
            })
    }

    fn edge(&mut self, a: Point2<f64>, b: Point2<f64>) {
        let (i, j) = (self.vertex(a), self.vertex(b));
        if i != j {
            self.edges.push([i, j]);
        }
    }
}

/// A cut and its stretches through free space (intervals along it, sorted): where the two
/// halves are glued.
pub(crate) struct Seam {
    pub cut: Cut,
    stretches: Vec<(f64, f64)>,
    /// Points and pieces the stretches were pre-split into.
    pub points: usize,
    pub pieces: usize,
}

impl Seam {
    /// Whether `p` is on a stretch of the cut (ends included).
    pub fn holds(&self, p: Point2<f64>) -> bool {
        self.cut.holds(p) && self.on_stretch(self.cut.along(p))
    }

    /// Whether the segment `p`–`q` lies on a stretch (a glued edge, not boundary).
    pub fn holds_edge(&self, p: Point2<f64>, q: Point2<f64>) -> bool {
        let mid = 0.5 * (self.cut.along(p) + self.cut.along(q));
        self.holds(p) && self.holds(q) && self.on_stretch(mid)
    }

    fn on_stretch(&self, t: f64) -> bool {
        let k = self.stretches.partition_point(|&(_, t1)| t1 < t);
        self.stretches.get(k).is_some_and(|&(t0, _)| t0 <= t)
    }
}

/// The constraint inputs of the two halves (low side first) and the seam: the cut's
/// stretches through free space. Ring segments are split where they cross the cut; a segment along the cut
/// goes to the side of free space (on its left); the stretches (between consecutive points
/// where rings meet the cut, when free space lies between) are pre-split into pieces no
/// longer than `spacing` — the same points on both sides. `index` holds the rings'
/// segments, `x_max` bounds them on the right. `None` for inputs no cut can serve
/// (non-finite coordinates).
pub(crate) fn split_inputs(
    rings: &[TaggedRing],
    cut: Cut,
    spacing: f64,
    index: &SegmentIndex,
    x_max: f64,
) -> Option<([HalfInput; 2], Seam)> {
    let mut halves = [HalfInput::default(), HalfInput::default()];
    // Positions along the cut where rings meet it.
    let mut events: Vec<f64> = Vec::new();
    for ring in rings {
        let n = ring.points.len();
        for k in 0..n {
            let (a, b) = (ring.points[k], ring.points[(k + 1) % n]);
            let (a, b) = (Point2::new(a.x, a.y), Point2::new(b.x, b.y));
            let (da, db) = (cut.across(a) - cut.at, cut.across(b) - cut.at);
            if !(da.is_finite() && db.is_finite()) {
                return None;
            }
            for (d, p) in [(da, a), (db, b)] {
                if d == 0.0 {
                    events.push(cut.along(p));
                }
            }
            if da == 0.0 && db == 0.0 {
                // Along the cut: free space is on the segment's left.
                let up = cut.along(b) > cut.along(a);
                let side = usize::from(if cut.axis == 0 { !up } else { up });
                halves[side].edge(a, b);
            } else if da <= 0.0 && db <= 0.0 {
                halves[0].edge(a, b);
            } else if da >= 0.0 && db >= 0.0 {
                halves[1].edge(a, b);
            } else {
                let p = cut.crossing(a, b);
                events.push(cut.along(p));
                let side = |d: f64| usize::from(d > 0.0);
                halves[side(da)].edge(a, p);
                halves[side(db)].edge(p, b);
            }
        }
    }
    events.sort_by(f64::total_cmp);
    events.dedup();
    let mut stretches = Vec::new();
    for pair in events.windows(2) {
        let (t0, t1) = (pair[0], pair[1]);
        let m = cut.point(0.5 * (t0 + t1));
        let m = Point::new(m.x, m.y);
        if index.distance(m) > 0.0 && index.ray_parity(m, x_max) {
            stretches.push((t0, t1));
        }
    }
    let mut points = std::collections::HashSet::new();
    let mut total_pieces = 0;
    for &(t0, t1) in &stretches {
        let pieces = ((t1 - t0) / spacing).ceil().clamp(1.0, 1e6) as usize;
        total_pieces += pieces;
        let at = |i: usize| {
            if i == pieces {
                t1
            } else {
                t0 + (t1 - t0) * (i as f64 / pieces as f64)
            }
        };
        for i in 0..pieces {
            let (a, b) = (cut.point(at(i)), cut.point(at(i + 1)));
            points.extend([at(i).to_bits(), at(i + 1).to_bits()]);
            for half in &mut halves {
                half.edge(a, b);
            }
        }
    }
    Some((
        halves,
        Seam {
            cut,
            stretches,
            points: points.len(),
            pieces: total_pieces,
        },
    ))
}
