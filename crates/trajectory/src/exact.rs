//! The exact tracer: steepest descent of a P1 field, triangle by triangle.
//!
//! Inside a triangle the gradient is constant, so the descent is a straight segment to the
//! exit edge. On an edge whose far side flows back (or a wall or obstacle edge), the path
//! slides along the edge to its lower end. At a vertex it continues into the incident
//! triangle (or along the incident edge) of steepest descent. A stagnation point (a flat
//! triangle, a level edge, a vertex with no lower neighbour) is escaped by a small
//! perturbation to a lower point in free space, as in Connolly's and Garrido's planners;
//! when none is found the path ends `Stalled`.
//!
//! This module also makes [`P1Field`] and [`SmoothP1Field`] [`Field`]s: their fallback step is
//! one move of this tracer, so their implementations sit here and `field.rs` needs nothing
//! from the tracers.

use harmonic_types::{BoundaryTag, NO_NEIGHBOR, Point, Vector};

use crate::field::{P1Field, SmoothP1Field, goal_crossing, magnitude, orient};
use crate::{Fallback, Field, Locate, Path, Segment, TraceStatus};

/// Options of the exact tracer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactOptions {
    /// Largest number of moves (triangle crossings, slides, vertex moves) before giving up
    /// with [`TraceStatus::MaxSteps`].
    pub max_steps: usize,
    /// Largest number of perturbations used to escape stagnation points.
    pub max_perturbations: usize,
}

impl Default for ExactOptions {
    fn default() -> Self {
        ExactOptions {
            max_steps: 10_000_000,
            max_perturbations: 32,
        }
    }
}

/// Relative distance along an edge under which an exit point is snapped to the vertex.
const SNAP: f64 = 1e-12;

/// Where the tracer is.
#[derive(Clone, Copy, Debug)]
enum At {
    /// At `p` in the closed triangle `t`, about to descend through `t` with gradient `g`.
    Face { t: u32, p: Point, g: Vector },
    /// On edge `k` of triangle `t`, at `a + mu (b - a)`; `g` is the gradient in `t`, `n` the
    /// triangle across the edge (or `NO_NEIGHBOR`) and `gn` the gradient there.
    Edge {
        t: u32,
        k: usize,
        mu: f64,
        g: Vector,
        n: u32,
        gn: Vector,
    },
    /// At vertex `v`, with `t` one of its triangles.
    Vertex { v: u32, t: u32 },
}

/// Traces the steepest descent of `field` from `start` to a goal.
///
/// The path never crosses a wall or obstacle edge, and the field's value decreases along it
/// (strictly inside triangles; perturbations jump only to lower points).
///
/// ```
/// use harmonic_mesh::{BoundaryTag, Mesh, Point};
/// use harmonic_trajectory::{ExactOptions, P1Field, TraceStatus, trace_exact};
/// // A unit square split in two; the goal is the top edge and ψ = y increases toward it.
/// let mesh = Mesh::from_parts(
///     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)],
///     vec![[0, 1, 2], [0, 2, 3]],
///     &[(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Wall),
///       (2, 3, BoundaryTag::Goal(0)), (3, 0, BoundaryTag::Wall)],
/// )?;
/// let psi = [0.0, 0.0, 1.0, 1.0];
/// let field = P1Field::ascending(&mesh, &psi)?;
/// let path = trace_exact(&field, Point::new(0.7, 0.2), &ExactOptions::default());
/// assert_eq!(path.status, TraceStatus::ReachedGoal(0));
/// assert!((path.length - 0.8).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn trace_exact(field: &P1Field<'_>, start: Point, opts: &ExactOptions) -> Path {
    trace_exact_with_hint(field, start, None, opts)
}

/// [`trace_exact`] with a triangle that probably holds `start`: the start is located by
/// walking from it, so no point-location structure is built. A wrong hint costs a longer
/// walk, never a wrong answer.
pub fn trace_exact_with_hint(
    field: &P1Field<'_>,
    start: Point,
    hint: Option<u32>,
    opts: &ExactOptions,
) -> Path {
    let t0 = match field.locate(start, hint) {
        Locate::Inside(t) => t,
        Locate::Goal(j) => {
            return Path::new(vec![start], TraceStatus::ReachedGoal(j), f64::INFINITY, 0);
        }
        Locate::InObstacle => {
            return Path::new(vec![start], TraceStatus::StartInObstacle, f64::INFINITY, 0);
        }
        Locate::OutsideWorkspace => {
            return Path::new(vec![start], TraceStatus::OutsideWorkspace, f64::INFINITY, 0);
        }
    };
    let mut tracer = Tracer {
        field,
        points: vec![start],
        min_gradient: f64::INFINITY,
        crossed: 0,
        last_face: t0,
        star: Vec::new(),
    };
    let status = tracer.run(classify(field, t0, start), opts);
    // Whether the start's component holds a goal is only asked when no goal was reached
    // (it scans the boundary): a start sealed off from every goal stalls at once on the flat
    // field there, or runs down to a minimum, and then reports `Unreachable`.
    if !status.reached_goal() && !field.goal_reachable(t0) {
        return Path::new(vec![start], TraceStatus::Unreachable, f64::INFINITY, 0);
    }
    Path::new(tracer.points, status, tracer.min_gradient, tracer.crossed)
}

/// One move of the exact tracer from `p` in triangle `t`: what the smooth tracer falls back
/// on when its steps keep being rejected (against a wall, at a stagnation point).
fn exact_move(field: &P1Field<'_>, t: u32, p: Point) -> Fallback<u32> {
    let mut tracer = Tracer {
        field,
        points: vec![p],
        min_gradient: f64::INFINITY,
        crossed: 0,
        last_face: t,
        star: Vec::new(),
    };
    let mut at = classify(field, t, p);
    let mut perturbations = 0;
    // A move that does not change the point (entering a triangle from an edge) is followed
    // by the next one; a handful always suffices.
    for _ in 0..16 {
        match tracer.advance(at, &mut perturbations, 2) {
            Ok(a) => at = a,
            Err(TraceStatus::ReachedGoal(j)) => return Fallback::Goal(j),
            Err(_) => return Fallback::Stuck,
        }
        if tracer.points.len() > 1 {
            let cell = match at {
                At::Face { t, .. } | At::Edge { t, .. } | At::Vertex { t, .. } => t,
            };
            let q = *tracer.points.last().unwrap_or(&p);
            return Fallback::Moved(q, cell);
        }
    }
    Fallback::Stuck
}

/// A P1 field is followed triangle by triangle; where an integrator cannot make progress it
/// falls back on one move of the exact tracer.
impl Field for P1Field<'_> {
    type Point = Point;
    type Vector = Vector;
    type Cell = u32;

    fn locate(&self, p: Point, hint: Option<u32>) -> Locate<u32> {
        self.locate_point(p, hint)
    }

    #[inline]
    fn value(&self, cell: u32, p: Point) -> f64 {
        self.value_at(cell, p)
    }

    #[inline]
    fn gradient(&self, cell: u32, _p: Point) -> Vector {
        self.triangle_gradient(cell)
    }

    fn segment(&self, cell: u32, from: Point, to: Point) -> Segment<u32> {
        self.segment_from(cell, from, to)
    }

    fn goal_reachable(&self, cell: u32) -> bool {
        self.component_has_goal(cell)
    }

    fn fallback_step(&self, cell: u32, p: Point) -> Fallback<u32> {
        if (cell as usize) >= self.mesh().triangles().len() {
            return Fallback::Stuck;
        }
        exact_move(self, cell, p)
    }
}

/// A smooth P1 field is its [`P1Field`] (location, values, segments, the exact fallback)
/// with the recovered, continuous gradient.
impl Field for SmoothP1Field<'_> {
    type Point = Point;
    type Vector = Vector;
    type Cell = u32;

    fn locate(&self, p: Point, hint: Option<u32>) -> Locate<u32> {
        self.p1().locate(p, hint)
    }

    fn value(&self, cell: u32, p: Point) -> f64 {
        self.p1().value(cell, p)
    }

    fn gradient(&self, cell: u32, p: Point) -> Vector {
        self.gradient_at(cell, p)
    }

    fn segment(&self, cell: u32, from: Point, to: Point) -> Segment<u32> {
        self.p1().segment(cell, from, to)
    }

    fn goal_reachable(&self, cell: u32) -> bool {
        self.p1().goal_reachable(cell)
    }

    fn fallback_step(&self, cell: u32, p: Point) -> Fallback<u32> {
        self.p1().fallback_step(cell, p)
    }
}

/// The gradient in triangle `n`, or zero across a boundary edge (`NO_NEIGHBOR`).
#[inline]
fn neighbour_gradient(field: &P1Field<'_>, n: u32) -> Vector {
    if n == NO_NEIGHBOR {
        Vector::zeros()
    } else {
        field.triangle_gradient(n)
    }
}

/// The state of a point `p` lying in the closed triangle `t`: on a vertex, on an edge, or inside.
fn classify(field: &P1Field<'_>, t: u32, p: Point) -> At {
    let mesh = field.mesh();
    let tri = mesh.triangles()[t as usize];
    let pts = mesh.triangle_points(t);
    let on = [0, 1, 2].map(|k| orient(pts[(k + 1) % 3], pts[(k + 2) % 3], p) == 0.0);
    match on {
        [false, true, true] => At::Vertex { v: tri[0], t },
        [true, false, true] => At::Vertex { v: tri[1], t },
        [true, true, false] => At::Vertex { v: tri[2], t },
        _ => match on.iter().position(|&z| z) {
            Some(k) => {
                let a = pts[(k + 1) % 3];
                let e = pts[(k + 2) % 3] - a;
                let mu = ((p - a).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
                At::Edge {
                    t,
                    k,
                    mu,
                    g: field.triangle_gradient(t),
                    n: field.mesh().neighbors()[t as usize][k],
                    gn: neighbour_gradient(field, field.mesh().neighbors()[t as usize][k]),
                }
            }
            None => At::Face {
                t,
                p,
                g: field.triangle_gradient(t),
            },
        },
    }
}

struct Tracer<'f, 'a> {
    field: &'f P1Field<'a>,
    points: Vec<Point>,
    min_gradient: f64,
    crossed: usize,
    last_face: u32,
    /// Scratch buffer for the triangles around a vertex.
    star: Vec<u32>,
}

/// What one move produced.
enum Next {
    Go(At),
    Done(TraceStatus),
    Stuck(Point, u32),
}

impl Tracer<'_, '_> {
    fn push(&mut self, p: Point) {
        if self.points.last() != Some(&p) {
            self.points.push(p);
        }
    }

    fn run(&mut self, mut at: At, opts: &ExactOptions) -> TraceStatus {
        let mut perturbations = 0;
        for _ in 0..opts.max_steps {
            at = match self.advance(at, &mut perturbations, opts.max_perturbations) {
                Ok(a) => a,
                Err(s) => return s,
            };
        }
        TraceStatus::MaxSteps
    }

    /// One move of the tracer (escaping a stagnation point by a perturbation if needed).
    fn advance(
        &mut self,
        at: At,
        perturbations: &mut usize,
        max_perturbations: usize,
    ) -> Result<At, TraceStatus> {
        let next = match at {
            At::Face { t, p, g } => self.face(t, p, g),
            At::Edge { t, k, mu, g, n, gn } => self.edge(t, k, mu, g, n, gn),
            At::Vertex { v, t } => self.vertex(v, t),
        };
        match next {
            Next::Go(a) => Ok(a),
            Next::Done(s) => Err(s),
            Next::Stuck(p, t) => {
                if *perturbations >= max_perturbations {
                    return Err(TraceStatus::Stalled { at: p });
                }
                *perturbations += 1;
                match self.perturb(p, t) {
                    Some(Next::Go(a)) => Ok(a),
                    Some(Next::Done(s)) => Err(s),
                    _ => Err(TraceStatus::Stalled { at: p }),
                }
            }
        }
    }

    /// Descends through triangle `t` from `p` along `-g` to the exit edge or vertex.
    fn face(&mut self, t: u32, p: Point, g: Vector) -> Next {
        if let Some(j) = self.field.goal_of_triangle(t) {
            return Next::Done(TraceStatus::ReachedGoal(j));
        }
        let gn = magnitude(g);
        if !(gn > 0.0 && gn.is_finite()) {
            return Next::Stuck(p, t);
        }
        if t != self.last_face {
            self.crossed += 1;
            self.last_face = t;
        }
        self.min_gradient = self.min_gradient.min(gn);
        let mesh = self.field.mesh();
        let tri = mesh.triangles()[t as usize];
        // Read early: the load overlaps the ray cast below.
        let nbs = mesh.neighbors()[t as usize];
        let pts = mesh.triangle_points(t);
        let d = -g;
        let mut h = [0.0; 3];
        let mut rate = [0.0; 3];
        let mut best = None;
        let mut best_s = f64::INFINITY;
        for k in 0..3 {
            let a = pts[(k + 1) % 3];
            let b = pts[(k + 2) % 3];
            let e = b - a;
            h[k] = ((e.x) * (p.y - a.y) - (e.y) * (p.x - a.x)).max(0.0);
            rate[k] = d.x * e.y - d.y * e.x;
            if rate[k] > 0.0 {
                let s = h[k] / rate[k];
                if s < best_s {
                    best_s = s;
                    best = Some(k);
                }
            }
        }
        let Some(k) = best else {
            return Next::Stuck(p, t);
        };
        // The next triangle's gradient, fetched as early as possible (memory latency).
        let n = nbs[k];
        let gn = neighbour_gradient(self.field, n);
        // Twice-areas of the exit point against the edges at the exit edge's ends.
        let ia = (k + 1) % 3;
        let ib = (k + 2) % 3;
        let wa = (h[ia] - best_s * rate[ia]).max(0.0);
        let wb = (h[ib] - best_s * rate[ib]).max(0.0);
        let mu = if wa + wb > 0.0 { wb / (wa + wb) } else { 0.5 };
        if mu <= SNAP {
            self.push(pts[ia]);
            return Next::Go(At::Vertex { v: tri[ia], t });
        }
        if mu >= 1.0 - SNAP {
            self.push(pts[ib]);
            return Next::Go(At::Vertex { v: tri[ib], t });
        }
        self.push(pts[ia] + (pts[ib] - pts[ia]) * mu);
        Next::Go(At::Edge { t, k, mu, g, n, gn })
    }

    /// At a point of edge `k` of `t`: cross, descend into `t`, slide, or stop at a goal.
    fn edge(&mut self, t: u32, k: usize, mu: f64, gt: Vector, n: u32, gn: Vector) -> Next {
        let field = self.field;
        let mesh = field.mesh();
        let tri = mesh.triangles()[t as usize];
        let (va, vb) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
        let a = mesh.vertices()[va as usize];
        let b = mesh.vertices()[vb as usize];
        let e = b - a;
        let p = a + e * mu;
        // Outward normal of `t` on this edge (not normalised).
        let nu = Vector::new(e.y, -e.x);
        let into_t = (-gt).dot(&nu) < 0.0;
        let choice = if n == NO_NEIGHBOR {
            if let Some(BoundaryTag::Goal(j)) = mesh.boundary_edge_of(t, k).map(|e| e.tag) {
                return Next::Done(TraceStatus::ReachedGoal(j));
            }
            into_t.then_some((t, gt))
        } else {
            let into_n = (-gn).dot(&nu) > 0.0;
            match (into_t, into_n) {
                (true, true) if magnitude(gt) >= magnitude(gn) => Some((t, gt)),
                (true, false) => Some((t, gt)),
                (_, true) => Some((n, gn)),
                (false, false) => None,
            }
        };
        if let Some((u, g)) = choice {
            return Next::Go(At::Face { t: u, p, g });
        }
        // Both sides flow onto the edge (or a wall): slide to its lower end.
        let (fa, fb) = (field.vertex_value(va), field.vertex_value(vb));
        let slope = (fa - fb).abs() / e.norm();
        if fb < fa {
            self.min_gradient = self.min_gradient.min(slope);
            self.push(b);
            Next::Go(At::Vertex { v: vb, t })
        } else if fa < fb {
            self.min_gradient = self.min_gradient.min(slope);
            self.push(a);
            Next::Go(At::Vertex { v: va, t })
        } else {
            // A level edge: free to move along it, and worth it if it leads to a goal.
            let tags = mesh.vertex_tags();
            for (v, q) in [(va, a), (vb, b)] {
                if let Some(BoundaryTag::Goal(_)) = tags[v as usize] {
                    self.push(q);
                    return Next::Go(At::Vertex { v, t });
                }
            }
            Next::Stuck(p, t)
        }
    }

    /// Collects the triangles around vertex `v` (one of them is `t`) into `self.star`.
    fn collect_star(&mut self, v: u32, t: u32) {
        let mesh = self.field.mesh();
        let tris = mesh.triangles();
        let nbs = mesh.neighbors();
        let local = |u: u32| -> usize {
            let tri = tris[u as usize];
            if tri[0] == v {
                0
            } else if tri[1] == v {
                1
            } else {
                2
            }
        };
        self.star.clear();
        self.star.push(t);
        // Counter-clockwise: across the edge opposite local vertex i+1.
        let mut u = t;
        let mut closed = false;
        loop {
            let n = nbs[u as usize][(local(u) + 1) % 3];
            if n == NO_NEIGHBOR {
                break;
            }
            if n == t || self.star.len() > tris.len() {
                closed = true;
                break;
            }
            self.star.push(n);
            u = n;
        }
        if !closed {
            // Clockwise from `t` until the boundary on the other side.
            let mut u = t;
            loop {
                let n = nbs[u as usize][(local(u) + 2) % 3];
                if n == NO_NEIGHBOR || n == t || self.star.len() > tris.len() {
                    break;
                }
                self.star.push(n);
                u = n;
            }
        }
    }

    /// At vertex `v`: continue into the steepest descending triangle or edge around it.
    fn vertex(&mut self, v: u32, t: u32) -> Next {
        let field = self.field;
        let mesh = field.mesh();
        if let Some(BoundaryTag::Goal(j)) = mesh.vertex_tags()[v as usize] {
            return Next::Done(TraceStatus::ReachedGoal(j));
        }
        if let Some(j) = field
            .goal_vertices()
            .map(|g| g[v as usize])
            .filter(|&j| j != crate::field::NOT_A_GOAL)
        {
            return Next::Done(TraceStatus::ReachedGoal(j));
        }
        self.collect_star(v, t);
        let verts = mesh.vertices();
        let pv = verts[v as usize];
        let fv = field.vertex_value(v);
        // (rate, triangle, Some(edge end) for an edge move)
        let mut best: Option<(f64, u32, Option<u32>, Vector)> = None;
        for &u in &self.star {
            let tri = mesh.triangles()[u as usize];
            let i = tri.iter().position(|&x| x == v).unwrap_or(0);
            let w1 = tri[(i + 1) % 3];
            let w2 = tri[(i + 2) % 3];
            let e1 = verts[w1 as usize] - pv;
            let e2 = verts[w2 as usize] - pv;
            let g = field.triangle_gradient(u);
            let d = -g;
            let rate = magnitude(d);
            let inside = e1.perp(&d) >= 0.0 && d.perp(&e2) >= 0.0;
            if inside && rate > 0.0 && rate.is_finite() && best.is_none_or(|b| rate > b.0) {
                best = Some((rate, u, None, g));
            }
            for (w, e) in [(w1, e1), (w2, e2)] {
                let r = (fv - field.vertex_value(w)) / e.norm();
                // Strictly steeper than any triangle so far: triangles win ties.
                if r > 0.0 && r.is_finite() && best.is_none_or(|b| r > b.0) {
                    best = Some((r, u, Some(w), g));
                }
            }
        }
        match best {
            None => Next::Stuck(pv, t),
            Some((_, u, None, g)) => Next::Go(At::Face { t: u, p: pv, g }),
            Some((r, u, Some(w), _)) => {
                self.min_gradient = self.min_gradient.min(r);
                if u != self.last_face {
                    self.crossed += 1;
                    self.last_face = u;
                }
                self.push(verts[w as usize]);
                Next::Go(At::Vertex { v: w, t: u })
            }
        }
    }

    /// Escapes a stagnation point `p` (in triangle `t`) by jumping to the lowest of a ring
    /// of nearby points that is lower than `p` and reachable in a straight line.
    fn perturb(&mut self, p: Point, t: u32) -> Option<Next> {
        let field = self.field;
        let f0 = field.value(t, p);
        // Radii from a twentieth of the triangle's longest edge to two of them, so a flat
        // triangle (three vertices on one Dirichlet boundary, as in a corner) is left too.
        let [a, b, c] = field.mesh().triangle_points(t);
        let r0 = 0.05 * (b - a).norm().max((c - b).norm()).max((a - c).norm());
        let mut best: Option<(f64, Point, u32)> = None;
        for scale in [1.0, 5.0, 20.0, 40.0] {
            for i in 0..16 {
                let ang = (i as f64 + 0.5) * std::f64::consts::TAU / 16.0;
                let q = p + Vector::new(ang.cos(), ang.sin()) * (r0 * scale);
                match field.segment(t, p, q) {
                    Segment::Goal(j) => {
                        // Stop on the goal's boundary, if that is lower.
                        let c = goal_crossing(field, t, p, q);
                        if let Segment::Inside(u) = field.segment(t, p, c)
                            && field.value(u, c) < f0
                        {
                            self.push(c);
                            return Some(Next::Done(TraceStatus::ReachedGoal(j)));
                        }
                    }
                    Segment::Inside(u) => {
                        let f = field.value(u, q);
                        if f < f0 && best.is_none_or(|b| f < b.0) {
                            best = Some((f, q, u));
                        }
                    }
                    Segment::Blocked => {}
                }
            }
            if best.is_some() {
                break;
            }
        }
        let (_, q, u) = best?;
        self.push(q);
        Some(Next::Go(classify(field, u, q)))
    }
}
