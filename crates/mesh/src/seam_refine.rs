//! Refinement around vertices put on the seam of a half (see [`crate::halves`]), done
//! locally instead of by another pass of spade's refinement over the whole half.
//!
//! When two halves exchange their cut vertices, each half takes a few points on its seam
//! (each splits a seam edge) and must be refined again around them. spade's refinement
//! always starts from every face of the triangulation, so each such round cost as much as
//! a pass over the whole half (0.07 s at 60 k vertices) for a handful of new points. Here
//! the same Ruppert steps run from the faces around the new points only:
//!
//! - a face breaking the area or angle bound gets its circumcentre, unless that would
//!   encroach a constraint edge (lie in its diametral circle, found as spade does, by
//!   walking the edges the insertion would flip);
//! - an encroached seam edge is split at its midpoint (exactly on the cut, whose value is
//!   exact: see [`crate::halves::Cut::exact`]), and the faces around the new vertex are
//!   checked again.
//!
//! Anything else — a bad face at a vertex of the boundary rings, an encroached boundary
//! edge, a circumcentre outside free space, too many steps — is left to spade's full pass:
//! [`refine_at_seam`] then answers `false` and the caller runs it. Every vertex added here
//! is one spade could have added, so the mesh keeps all of refinement's bounds either way.

use spade::handles::{FixedDirectedEdgeHandle, FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{AngleLimit, ConstrainedDelaunayTriangulation, Point2, PositionInTriangulation};
use spade::{Triangulation, handles::DirectedEdgeHandle};

use crate::halves::Seam;

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;
type Edge<'a> = DirectedEdgeHandle<'a, Point2<f64>, (), spade::CdtEdge<()>, ()>;

/// The most vertices one local refinement adds before leaving the rest to spade.
const MAX_STEPS: usize = 2000;

/// The bounds a face must meet (those of spade's refinement).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bounds {
    pub max_area: f64,
    /// Circumradius over shortest edge, at most (`1 / (2 sin θ)` for the angle bound θ).
    pub max_ratio: f64,
}

impl Bounds {
    pub fn new(max_area: f64, min_angle_deg: f64) -> Bounds {
        Bounds {
            max_area,
            max_ratio: AngleLimit::from_deg(min_angle_deg).radius_to_shortest_edge_limit(),
        }
    }
}

/// What a step found.
enum Step {
    /// The face meets the bounds.
    Good,
    /// Insert this point.
    Insert(Point2<f64>),
    /// Split this seam edge at its midpoint.
    SplitSeam(FixedDirectedEdgeHandle),
    /// Outside what is done here: leave it to spade.
    GiveUp,
}

/// Refines the free faces around `new` (vertices just inserted on `seam`) of a half whose
/// faces outside free space are `excluded` (grown as faces are added: every new face is
/// free, and insertion keeps the indices of the faces it changes), while the half has fewer
/// than `vertex_cap` vertices. `true` if every face around every vertex added meets
/// `bounds` and no seam edge is encroached; `false` if it stopped at something it leaves to
/// spade.
pub(crate) fn refine_at_seam(
    cdt: &mut Cdt,
    excluded: &mut Vec<bool>,
    new: &[FixedVertexHandle],
    seam: &Seam,
    bounds: Bounds,
    vertex_cap: usize,
) -> bool {
    let mut faces: Vec<FixedFaceHandle<InnerTag>> = Vec::new();
    let mut vertices: Vec<FixedVertexHandle> = new.to_vec();
    let mut steps = 0;
    loop {
        excluded.resize(cdt.num_all_faces(), false);
        // The faces (and seam edges) around the vertices added last.
        for v in vertices.drain(..) {
            for e in cdt.vertex(v).out_edges() {
                if let Some(f) = e.face().as_inner() {
                    faces.push(f.fix());
                }
            }
        }
        let Some(f) = faces.pop() else {
            return true;
        };
        if excluded[f.index()] {
            continue;
        }
        let step = examine(cdt, f, seam, bounds);
        let added = match step {
            Step::Good => continue,
            Step::GiveUp => return false,
            Step::Insert(p) => match cdt.insert(p) {
                Ok(v) => v,
                Err(_) => return false,
            },
            Step::SplitSeam(e) => {
                let [a, b] = cdt.directed_edge(e).positions();
                let m = Point2::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
                if !seam.holds(m) {
                    return false;
                }
                match cdt.insert(m) {
                    Ok(v) => v,
                    Err(_) => return false,
                }
            }
        };
        steps += 1;
        if steps > MAX_STEPS || cdt.num_vertices() >= vertex_cap {
            return false;
        }
        // The face may still be bad (a seam split made room for its circumcentre).
        faces.push(f);
        vertices.push(added);
    }
}

/// Whether `e` is a constraint edge on the seam (glued, not boundary).
fn on_seam(e: Edge<'_>, seam: &Seam) -> bool {
    let [p, q] = e.positions();
    e.is_constraint_edge() && seam.holds_edge(p, q)
}

/// Whether `p` lies strictly inside the diametral circle of `a`–`b`.
fn encroaches(a: Point2<f64>, b: Point2<f64>, p: Point2<f64>) -> bool {
    (a.x - p.x) * (b.x - p.x) + (a.y - p.y) * (b.y - p.y) < 0.0
}

/// The next step for face `f`: its seam edges first (encroached by the opposite vertex),
/// then its bounds.
fn examine(cdt: &Cdt, f: FixedFaceHandle<InnerTag>, seam: &Seam, bounds: Bounds) -> Step {
    let face = cdt.face(f);
    let edges = face.adjacent_edges();
    for e in edges {
        if e.is_constraint_edge() {
            let [p, q] = e.positions();
            let o = e.opposite_position().unwrap_or(p);
            if encroaches(p, q, o) {
                return if on_seam(e, seam) {
                    Step::SplitSeam(e.fix())
                } else {
                    Step::GiveUp
                };
            }
        }
    }
    let [a, b, c] = face.positions();
    let shortest2 = [a.distance_2(b), b.distance_2(c), c.distance_2(a)]
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let (centre, radius2) = face.circumcircle();
    let bad = face.area() > bounds.max_area || radius2 / shortest2 > bounds.max_ratio.powi(2);
    if !bad {
        return Step::Good;
    }
    // At a vertex of the boundary rings (a constraint edge off the seam) spade's handling
    // of small input angles applies: leave it to spade.
    let at_ring = face.vertices().iter().any(|v| {
        v.out_edges()
            .any(|e| e.is_constraint_edge() && !on_seam(e, seam))
    });
    if at_ring {
        return Step::GiveUp;
    }
    insertion_of(cdt, f, centre, seam)
}

/// Inserting the circumcentre `c` of face `f`, unless it lies outside free space or would
/// encroach a constraint edge: the edges its insertion would flip are walked from the face
/// under it (as spade's refinement does); a fixed edge met on the way that `c` encroaches
/// is split instead (a seam edge) or left to spade.
fn insertion_of(cdt: &Cdt, f: FixedFaceHandle<InnerTag>, c: Point2<f64>, seam: &Seam) -> Step {
    let hint = cdt.face(f).vertices()[0].fix();
    let mut todo: Vec<FixedDirectedEdgeHandle> = match cdt.locate_with_hint(c, hint) {
        PositionInTriangulation::OnFace(under) => {
            cdt.face(under).adjacent_edges().map(|e| e.fix()).to_vec()
        }
        PositionInTriangulation::OnEdge(e) => {
            let e = cdt.directed_edge(e);
            if e.is_constraint_edge() || e.is_outer_edge() || e.rev().is_outer_edge() {
                return Step::GiveUp;
            }
            vec![
                e.next().fix(),
                e.prev().fix(),
                e.rev().next().fix(),
                e.rev().prev().fix(),
            ]
        }
        _ => return Step::GiveUp,
    };
    while let Some(e) = todo.pop() {
        let e = cdt.directed_edge(e);
        let [from, to] = e.positions();
        let fixed = e.is_constraint_edge() || e.rev().is_outer_edge() || e.is_outer_edge();
        if fixed {
            if encroaches(from, to, c) {
                return if on_seam(e, seam) {
                    Step::SplitSeam(e.fix())
                } else {
                    Step::GiveUp
                };
            }
            continue;
        }
        let Some(opposite) = e.rev().opposite_position() else {
            continue;
        };
        if in_circle(opposite, to, from, c) {
            todo.push(e.rev().next().fix());
            todo.push(e.rev().prev().fix());
        }
    }
    Step::Insert(c)
}

/// Whether `p` lies strictly inside the circle through `a`, `b`, `c` (counter-clockwise).
fn in_circle(a: Point2<f64>, b: Point2<f64>, c: Point2<f64>, p: Point2<f64>) -> bool {
    let k = |q: Point2<f64>| robust::Coord { x: q.x, y: q.y };
    robust::incircle(k(a), k(b), k(c), k(p)) > 0.0
}
