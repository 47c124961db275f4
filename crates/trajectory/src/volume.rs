//! Following a 3D field: the P1 field of a potential on a [`TetMesh`] and its exact
//! tetrahedron-to-tetrahedron tracer. (The smooth tracer, [`crate::trace_smooth`], is the
//! plane's, in three dimensions.)
//!
//! **Exact.** Inside a tetrahedron the gradient is constant, so steepest descent is a straight
//! segment to an exit face. The tracer keeps the point together with its *carrier*: the
//! smallest mesh simplex (tetrahedron, face, edge or vertex) holding it in its relative
//! interior. From there it moves into whichever incident cell descends steepest and can be
//! entered: a tetrahedron whose −∇ points into it, else a face (sliding along it: the flow
//! of both neighbours pushes into the face, or it is a wall and the flow points out), else an
//! edge toward its lower end. The value is linear on every cell, so each move goes straight to
//! the cell's boundary, and the path never leaves the mesh. Reaching a goal face ends the path;
//! a point from which nothing descends (a flat spot, a discrete saddle or minimum) is escaped
//! by a jump to a lower point in free space nearby (reached along a straight segment inside
//! the mesh), as in the 2D tracer; failing that the path is `stalled`.
//!

use std::sync::Arc;

use harmonic_types::{
    BoundaryTag, FACES, NO_NEIGHBOR, Point3 as Point, TetMesh, Vector3 as Vector,
};

use crate::{Fallback, Field, Locate, Path, Segment, TraceError, TraceStatus};

/// How points outside the mesh are classified (e.g. from the scene's exact solids).
pub type OutsideClassifier<'a> = &'a (dyn Fn(&Point) -> Locate<u32> + Sync);

/// A P1 field on a tetrahedral mesh: nodal values (decreasing toward the goal), borrowed mesh.
pub struct P1VolumeField<'a> {
    mesh: &'a TetMesh,
    parts: Arc<VolumeFieldParts>,
    outside: Option<OutsideClassifier<'a>>,
}

/// What a [`P1VolumeField`] computes once from its mesh and values (recovered gradients,
/// components): O(mesh) work that a planner keeps and shares between
/// queries ([`P1VolumeField::parts`], [`P1VolumeField::from_parts`]).
#[derive(Debug)]
pub struct VolumeFieldParts {
    values: Vec<f64>,
    nodal: Vec<Vector>,
    /// Per tetrahedron: its component; per component: whether it has a goal face.
    component: Vec<u32>,
    component_goal: Vec<bool>,
}

/// What a [`P1VolumeField`] needs of its mesh alone, before any values: the face-connected
/// components with whether each has a goal face, and the mesh's vertex → tetrahedra table
/// ([`TetMesh::tets_around`], kept by the mesh) built if the mesh had none. On a large mesh
/// it is worth computing while the values are still being solved for
/// ([`P1VolumeField::ascending_with`]).
#[derive(Debug)]
pub struct VolumeFieldTopology {
    component: Vec<u32>,
    component_goal: Vec<bool>,
}

impl VolumeFieldTopology {
    /// The topology of `mesh`.
    pub fn of(mesh: &TetMesh) -> Self {
        let tets = mesh.tetrahedra();
        // Built here, beside the solve, where the mesh came without it.
        mesh.tets_around();
        // Components and their goals.
        let mut component = vec![u32::MAX; tets.len()];
        let mut component_goal = Vec::new();
        let mut stack = Vec::new();
        for seed in 0..tets.len() {
            if component[seed] != u32::MAX {
                continue;
            }
            let c = component_goal.len() as u32;
            let mut goal = false;
            component[seed] = c;
            stack.push(seed as u32);
            while let Some(t) = stack.pop() {
                for k in 0..4 {
                    match mesh.neighbors()[t as usize][k] {
                        NO_NEIGHBOR => {
                            goal |= matches!(
                                mesh.boundary_face(t, k).map(|f| f.tag),
                                Some(BoundaryTag::Goal(_))
                            );
                        }
                        n if component[n as usize] == u32::MAX => {
                            component[n as usize] = c;
                            stack.push(n);
                        }
                        _ => {}
                    }
                }
            }
            component_goal.push(goal);
        }
        VolumeFieldTopology {
            component,
            component_goal,
        }
    }
}

impl std::fmt::Debug for P1VolumeField<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("P1VolumeField")
            .field("vertices", &self.parts.values.len())
            .finish_non_exhaustive()
    }
}

impl<'a> P1VolumeField<'a> {
    /// A field whose value decreases toward the goal (φ).
    pub fn descending(mesh: &'a TetMesh, values: &[f64]) -> Result<Self, TraceError> {
        Self::build(mesh, values.to_vec())
    }

    /// A field from ψ, which increases toward the goal: the value followed is −ψ.
    pub fn ascending(mesh: &'a TetMesh, psi: &[f64]) -> Result<Self, TraceError> {
        Self::build(mesh, psi.iter().map(|v| -v).collect())
    }

    /// Classifies points outside the mesh with `f` (goal, obstacle or outside the workspace)
    /// instead of calling them all obstacles.
    pub fn with_outside(mut self, f: OutsideClassifier<'a>) -> Self {
        self.outside = Some(f);
        self
    }

    /// [`P1VolumeField::ascending`] with the mesh's [`VolumeFieldTopology`] computed
    /// beforehand (for instance beside the solve that gives ψ): only the gradients are left.
    pub fn ascending_with(
        mesh: &'a TetMesh,
        topology: VolumeFieldTopology,
        psi: &[f64],
    ) -> Result<Self, TraceError> {
        Self::build_with(mesh, psi.iter().map(|v| -v).collect(), topology, None)
    }

    /// [`P1VolumeField::ascending_with`] on a mesh made of copies of its first `period`
    /// tetrahedra — a periodic domain's covering, whose tetrahedron `t` is tetrahedron
    /// `t % period` moved by whole periods. A copy whose corners hold the same values as
    /// its original's takes the original's gradient (the same up to rounding: a translate),
    /// computed once; any other copy gets its own.
    pub fn ascending_with_copies(
        mesh: &'a TetMesh,
        topology: VolumeFieldTopology,
        psi: &[f64],
        period: usize,
    ) -> Result<Self, TraceError> {
        let nt = mesh.tetrahedra().len();
        if period == 0 || !nt.is_multiple_of(period) {
            return Err(TraceError::LengthMismatch {
                what: "tetrahedra of one copy (a divisor of the mesh's)",
                expected: period,
                got: nt,
            });
        }
        Self::build_with(
            mesh,
            psi.iter().map(|v| -v).collect(),
            topology,
            Some(period),
        )
    }

    fn build(mesh: &'a TetMesh, values: Vec<f64>) -> Result<Self, TraceError> {
        Self::check_values(mesh, &values)?;
        Self::build_checked(mesh, values, VolumeFieldTopology::of(mesh), None)
    }

    fn check_values(mesh: &TetMesh, values: &[f64]) -> Result<(), TraceError> {
        let nv = mesh.vertices().len();
        if values.len() != nv {
            return Err(TraceError::LengthMismatch {
                what: "nodal values",
                expected: nv,
                got: values.len(),
            });
        }
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(TraceError::NotFinite {
                what: "nodal values",
                index,
            });
        }
        Ok(())
    }

    fn build_with(
        mesh: &'a TetMesh,
        values: Vec<f64>,
        topology: VolumeFieldTopology,
        copies_of: Option<usize>,
    ) -> Result<Self, TraceError> {
        Self::check_values(mesh, &values)?;
        let nt = mesh.tetrahedra().len();
        if topology.component.len() != nt {
            return Err(TraceError::LengthMismatch {
                what: "field topology's tetrahedra",
                expected: nt,
                got: topology.component.len(),
            });
        }
        Self::build_checked(mesh, values, topology, copies_of)
    }

    /// The field from checked values and a topology of `mesh` (whose tetrahedra repeat the
    /// first `copies_of` ones, if given: [`P1VolumeField::ascending_with_copies`]).
    fn build_checked(
        mesh: &'a TetMesh,
        values: Vec<f64>,
        topology: VolumeFieldTopology,
        copies_of: Option<usize>,
    ) -> Result<Self, TraceError> {
        let nv = mesh.vertices().len();
        let tets = mesh.tetrahedra();
        let VolumeFieldTopology {
            component,
            component_goal,
        } = topology;
        let vt = mesh.tets_around();
        // Recovered nodal gradients (volume-weighted), for the smooth tracer.
        // Each tetrahedron's gradient on every core, summed into the vertices in order (the
        // same sums on any number of threads).
        let own = |t: u32| {
            let (g, vol) = mesh.barycentric_gradients(t);
            let tet = tets[t as usize];
            let grad: Vector = (0..4).map(|k| g[k] * values[tet[k] as usize]).sum();
            (grad * vol, vol)
        };
        // Each tetrahedron's (gradient × volume, volume) once: all of them, or those of the
        // first copy, which later copies look up (where their corners hold the same values)
        // instead of keeping their own.
        let period = copies_of.unwrap_or(tets.len()).max(1);
        let first: Vec<(Vector, f64)> = {
            use rayon::prelude::*;
            (0..period.min(tets.len()) as u32)
                .into_par_iter()
                .map(own)
                .collect()
        };
        let corner_values = |t: usize| tets[t].map(|v| values[v as usize].to_bits());
        let of_tet = |t: usize| {
            let o = t % period;
            if t == o || corner_values(t) == corner_values(o) {
                first[o]
            } else {
                own(t as u32)
            }
        };
        // Per vertex, its tetrahedra's sums in the order the vertex → tetrahedra table lists
        // them (the tetrahedra's own order), on every core.
        let nodal: Vec<Vector> = {
            use rayon::prelude::*;
            (0..nv)
                .into_par_iter()
                .map(|v| {
                    let around = vt.of(v);
                    let (mut n, mut w) = (Vector::zeros(), 0.0);
                    for &t in around {
                        let (gv, vol) = of_tet(t as usize);
                        n += gv;
                        w += vol;
                    }
                    if w > 0.0 { n / w } else { n }
                })
                .collect()
        };
        Ok(P1VolumeField {
            mesh,
            parts: Arc::new(VolumeFieldParts {
                values,
                nodal,
                component,
                component_goal,
            }),
            outside: None,
        })
    }

    /// The precomputed parts, to build further fields on the same mesh and values without
    /// redoing them ([`P1VolumeField::from_parts`]).
    pub fn parts(&self) -> &Arc<VolumeFieldParts> {
        &self.parts
    }

    /// A field from parts computed earlier on `mesh` (cheap: no pass over the mesh).
    pub fn from_parts(mesh: &'a TetMesh, parts: Arc<VolumeFieldParts>) -> Result<Self, TraceError> {
        let (nv, nt) = (mesh.vertices().len(), mesh.tetrahedra().len());
        if parts.values.len() != nv || parts.component.len() != nt {
            return Err(TraceError::LengthMismatch {
                what: "field parts",
                expected: nv,
                got: parts.values.len(),
            });
        }
        Ok(P1VolumeField {
            mesh,
            parts,
            outside: None,
        })
    }

    /// The mesh.
    pub fn mesh(&self) -> &TetMesh {
        self.mesh
    }

    /// The value's gradient on tetrahedron `t`.
    pub fn tet_gradient(&self, t: u32) -> Vector {
        let (g, _) = self.mesh.barycentric_gradients(t);
        let tet = self.mesh.tetrahedra()[t as usize];
        (0..4)
            .map(|k| g[k] * self.parts.values[tet[k] as usize])
            .sum()
    }

    fn vertex_tets(&self, v: u32) -> &[u32] {
        self.mesh.tets_around().of(v as usize)
    }

    /// The tetrahedra containing every vertex of `sigma`.
    fn star(&self, sigma: &[u32]) -> Vec<u32> {
        let first = sigma
            .iter()
            .min_by_key(|&&v| self.vertex_tets(v).len())
            .copied()
            .unwrap_or(0);
        self.vertex_tets(first)
            .iter()
            .copied()
            .filter(|&t| {
                let tet = self.mesh.tetrahedra()[t as usize];
                sigma.iter().all(|v| tet.contains(v))
            })
            .collect()
    }

    fn interpolate(&self, t: u32, p: &Point) -> f64 {
        let l = self.mesh.barycentric(t, p);
        let tet = self.mesh.tetrahedra()[t as usize];
        (0..4)
            .map(|k| l[k] * self.parts.values[tet[k] as usize])
            .sum()
    }

    /// Walks the straight segment `a → b` from tetrahedron `t` (holding `a`) through the
    /// mesh: where it ends, or the goal face it crosses first, or `Blocked` at a wall or
    /// obstacle face.
    pub fn walk_segment(&self, t: u32, a: &Point, b: &Point) -> Segment<u32> {
        let mut t = t;
        let mut s = 0.0f64;
        let mut previous: Option<u32> = None;
        let limit = 64 + 8 * (self.mesh.tetrahedra().len() as f64).cbrt() as usize;
        for _ in 0..limit {
            let la = self.mesh.barycentric(t, a);
            let lb = self.mesh.barycentric(t, b);
            // Exit parameter: the first face whose coordinate reaches zero after s.
            let mut exit = (f64::INFINITY, usize::MAX);
            for k in 0..4 {
                let d = lb[k] - la[k];
                if d < 0.0 {
                    let sk = -la[k] / d;
                    let back = previous.is_some_and(|q| self.mesh.neighbors()[t as usize][k] == q);
                    if sk < exit.0 && sk >= s - 1e-12 && !back {
                        exit = (sk, k);
                    }
                }
            }
            if exit.0 >= 1.0 {
                return Segment::Inside(t);
            }
            let k = exit.1;
            s = exit.0.max(s);
            match self.mesh.neighbors()[t as usize][k] {
                NO_NEIGHBOR => {
                    return match self.mesh.boundary_face(t, k).map(|f| f.tag) {
                        Some(BoundaryTag::Goal(j)) => Segment::Goal(j),
                        _ => Segment::Blocked,
                    };
                }
                n => {
                    previous = Some(t);
                    t = n;
                }
            }
        }
        Segment::Blocked
    }

    fn goal_reachable(&self, t: u32) -> bool {
        self.parts.component_goal[self.parts.component[t as usize] as usize]
    }
}

impl Field for P1VolumeField<'_> {
    type Point = Point;
    type Vector = Vector;
    type Cell = u32;
    fn locate(&self, p: Point, hint: Option<u32>) -> Locate<u32> {
        let p = &p;
        match self.mesh.locate(p, hint) {
            Some(t) => Locate::Inside(t),
            None => match self.outside {
                Some(f) => match f(p) {
                    // The classifier says free, but the mesh (kept off the obstacles by its
                    // safety margin) does not reach it: not plannable here.
                    Locate::Inside(_) => Locate::InObstacle,
                    other => other,
                },
                None => {
                    let (lo, hi) = self.mesh.bounds();
                    if (0..3).any(|a| p[a] < lo[a] || p[a] > hi[a]) {
                        Locate::OutsideWorkspace
                    } else {
                        Locate::InObstacle
                    }
                }
            },
        }
    }
    fn value(&self, cell: u32, p: Point) -> f64 {
        self.interpolate(cell, &p)
    }
    /// The recovered (smooth) gradient, interpolated.
    fn gradient(&self, cell: u32, p: Point) -> Vector {
        let l = self.mesh.barycentric(cell, &p);
        let tet = self.mesh.tetrahedra()[cell as usize];
        (0..4)
            .map(|k| self.parts.nodal[tet[k] as usize] * l[k])
            .sum()
    }
    fn segment(&self, cell: u32, from: Point, to: Point) -> Segment<u32> {
        self.walk_segment(cell, &from, &to)
    }
    fn fallback_step(&self, cell: u32, p: Point) -> Fallback<u32, Point> {
        let mut tracer = Exact::new(self, ExactVolumeOptions::default());
        let mut at = tracer.carrier(cell, p);
        let v0 = self.interpolate(cell, &p);
        for _ in 0..16 {
            match tracer.advance(&at) {
                Ok(next) => {
                    at = next;
                    if self.interpolate(at.tet, &at.p) < v0 - 1e-15 * v0.abs().max(1.0) {
                        return Fallback::Moved(at.p, at.tet);
                    }
                }
                Err(TraceStatus::ReachedGoal(j)) => return Fallback::Goal(j),
                Err(_) => return Fallback::Stuck,
            }
        }
        Fallback::Stuck
    }
}

/// Options of [`trace_exact_volume`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactVolumeOptions {
    /// Largest number of moves.
    pub max_steps: usize,
    /// Largest number of perturbations escaping stagnation points.
    pub max_perturbations: usize,
}

impl Default for ExactVolumeOptions {
    fn default() -> Self {
        ExactVolumeOptions {
            max_steps: 1_000_000,
            max_perturbations: 32,
        }
    }
}

/// The point and its carrier simplex (sorted vertices), with one tetrahedron holding it.
#[derive(Clone, Debug)]
struct At {
    p: Point,
    sigma: Vec<u32>,
    tet: u32,
}

/// A cell to move in: its vertices and the direction.
struct Move {
    cell: Vec<u32>,
    tet: u32,
    dir: Vector,
    rate: f64,
}

struct Exact<'f, 'a> {
    field: &'f P1VolumeField<'a>,
    opts: ExactVolumeOptions,
    perturbations: usize,
    min_gradient: f64,
}

/// Barycentric coordinates of `p` in the simplex `pts` (1 to 4 points), after projecting
/// `p` onto its affine hull.
fn simplex_coords(pts: &[Point], p: &Point) -> Vec<f64> {
    match pts.len() {
        1 => vec![1.0],
        2 => {
            let e = pts[1] - pts[0];
            let s = (p - pts[0]).dot(&e) / e.norm_squared();
            vec![1.0 - s, s]
        }
        3 => {
            let (e1, e2, d) = (pts[1] - pts[0], pts[2] - pts[0], p - pts[0]);
            let m = nalgebra::Matrix2::new(e1.dot(&e1), e1.dot(&e2), e1.dot(&e2), e2.dot(&e2));
            let r = nalgebra::Vector2::new(e1.dot(&d), e2.dot(&d));
            let c = m
                .try_inverse()
                .map_or(nalgebra::Vector2::zeros(), |inv| inv * r);
            vec![1.0 - c.x - c.y, c.x, c.y]
        }
        _ => {
            let vol = harmonic_types::signed_volume(&pts[0], &pts[1], &pts[2], &pts[3]);
            (0..4)
                .map(|k| {
                    let mut q = [pts[0], pts[1], pts[2], pts[3]];
                    q[k] = *p;
                    harmonic_types::signed_volume(&q[0], &q[1], &q[2], &q[3]) / vol
                })
                .collect()
        }
    }
}

impl<'f, 'a> Exact<'f, 'a> {
    fn new(field: &'f P1VolumeField<'a>, opts: ExactVolumeOptions) -> Self {
        Exact {
            field,
            opts,
            perturbations: 0,
            min_gradient: f64::INFINITY,
        }
    }

    fn mesh(&self) -> &TetMesh {
        self.field.mesh
    }

    /// The carrier of `p` in tetrahedron `t`: its vertices with a coordinate above 1e-10,
    /// and `p` snapped onto that simplex.
    fn carrier(&self, t: u32, p: Point) -> At {
        let tet = self.mesh().tetrahedra()[t as usize];
        let l = self.mesh().barycentric(t, &p);
        self.snap(t, &tet, &l)
    }

    fn snap(&self, t: u32, cell: &[u32], l: &[f64]) -> At {
        let keep: Vec<usize> = (0..cell.len()).filter(|&k| l[k] > 1e-10).collect();
        let keep = if keep.is_empty() {
            // Round-off pushed every coordinate down: the largest one's vertex.
            vec![
                (0..cell.len())
                    .max_by(|&a, &b| l[a].total_cmp(&l[b]))
                    .unwrap_or(0),
            ]
        } else {
            keep
        };
        let sum: f64 = keep.iter().map(|&k| l[k].max(0.0)).sum();
        let v = self.mesh().vertices();
        let p = if sum > 0.0 {
            Point::from(
                keep.iter()
                    .map(|&k| v[cell[k] as usize].coords * (l[k].max(0.0) / sum))
                    .sum::<Vector>(),
            )
        } else {
            v[cell[keep[0]] as usize]
        };
        let mut sigma: Vec<u32> = keep.iter().map(|&k| cell[k]).collect();
        sigma.sort_unstable();
        At { p, sigma, tet: t }
    }

    /// Whether the carrier lies on a goal face.
    fn on_goal(&self, at: &At, star: &[u32]) -> Option<u32> {
        if at.sigma.len() == 4 {
            return None;
        }
        for &t in star {
            let tet = self.mesh().tetrahedra()[t as usize];
            for (k, f) in FACES.iter().enumerate() {
                if at.sigma.contains(&tet[k]) {
                    continue;
                }
                let _ = f;
                if let Some(bf) = self.mesh().boundary_face(t, k)
                    && let BoundaryTag::Goal(j) = bf.tag
                {
                    return Some(j);
                }
            }
        }
        None
    }

    /// The steepest feasible move from `at`.
    fn best_move(&self, at: &At, star: &[u32]) -> Option<Move> {
        let mesh = self.mesh();
        let v = mesh.vertices();
        let mut best: Option<Move> = None;
        let consider = |m: Move, best: &mut Option<Move>| {
            if m.rate > 0.0
                && best
                    .as_ref()
                    .is_none_or(|b| m.rate > b.rate * (1.0 + 1e-12))
            {
                *best = Some(m);
            }
        };
        for &t in star {
            let g = self.field.tet_gradient(t);
            let d = -g;
            let dn = d.norm();
            if dn == 0.0 || !dn.is_finite() {
                continue;
            }
            let tet = mesh.tetrahedra()[t as usize];
            let (gl, _) = mesh.barycentric_gradients(t);
            // Entering t: every coordinate that is zero at p must not decrease.
            let enters = (0..4)
                .all(|k| at.sigma.contains(&tet[k]) || gl[k].dot(&d) > 1e-9 * gl[k].norm() * dn);
            if enters {
                consider(
                    Move {
                        cell: tet.to_vec(),
                        tet: t,
                        dir: d / dn,
                        rate: dn,
                    },
                    &mut best,
                );
            }
            if at.sigma.len() == 4 {
                continue;
            }
            // Faces and edges of t containing the carrier.
            for k in 0..4 {
                let face: Vec<u32> = (0..4).filter(|&m| m != k).map(|m| tet[m]).collect();
                if !at.sigma.iter().all(|s| face.contains(s)) {
                    continue;
                }
                let pts: Vec<Point> = face.iter().map(|&i| v[i as usize]).collect();
                let n = (pts[1] - pts[0]).cross(&(pts[2] - pts[0])).normalize();
                let df = d - n * d.dot(&n);
                let r = df.norm();
                // Unit directions: the gradient may be far below the coordinates' precision.
                if r > 1e-14 * dn && self.moves_inside(&pts, &face, at, &(df / r)) {
                    consider(
                        Move {
                            cell: face.clone(),
                            tet: t,
                            dir: df / r,
                            rate: r,
                        },
                        &mut best,
                    );
                }
            }
            for &[i, j] in &harmonic_types::EDGES {
                let (a, b) = (tet[i], tet[j]);
                if !at.sigma.iter().all(|s| *s == a || *s == b) {
                    continue;
                }
                let (va, vb) = (
                    self.field.parts.values[a as usize],
                    self.field.parts.values[b as usize],
                );
                let (lo, hi) = if va < vb { (a, b) } else { (b, a) };
                if va == vb || at.sigma == [lo] {
                    continue;
                }
                let e = v[lo as usize] - v[hi as usize];
                let len = e.norm();
                consider(
                    Move {
                        cell: vec![hi, lo],
                        tet: t,
                        dir: e / len,
                        rate: (va - vb).abs() / len,
                    },
                    &mut best,
                );
            }
        }
        best
    }

    /// Whether moving from `at` along `d` stays in the triangle `pts` (coordinates that are
    /// zero at the point do not decrease).
    fn moves_inside(&self, pts: &[Point], face: &[u32], at: &At, d: &Vector) -> bool {
        let l0 = simplex_coords(pts, &at.p);
        let l1 = simplex_coords(pts, &(at.p + d));
        let scale = d.norm();
        (0..3).all(|m| {
            at.sigma.contains(&face[m]) || {
                let _ = l0[m];
                l1[m] - l0[m] > 1e-9 * scale / (pts[(m + 1) % 3] - pts[(m + 2) % 3]).norm()
            }
        })
    }

    /// One move (or a perturbation).
    fn advance(&mut self, at: &At) -> Result<At, TraceStatus<Point>> {
        let star = self.field.star(&at.sigma);
        if let Some(j) = self.on_goal(at, &star) {
            return Err(TraceStatus::ReachedGoal(j));
        }
        let Some(m) = self.best_move(at, &star) else {
            return self.perturb(at);
        };
        self.min_gradient = self.min_gradient.min(m.rate);
        let v = self.mesh().vertices();
        let pts: Vec<Point> = m.cell.iter().map(|&i| v[i as usize]).collect();
        let l0 = simplex_coords(&pts, &at.p);
        let l1 = simplex_coords(&pts, &(at.p + m.dir));
        let mut s = f64::INFINITY;
        for k in 0..pts.len() {
            let r = l1[k] - l0[k];
            if r < 0.0 {
                s = s.min(l0[k].max(0.0) / -r);
            }
        }
        if !s.is_finite() {
            return self.perturb(at);
        }
        let q = at.p + m.dir * s;
        let l = simplex_coords(&pts, &q);
        // Re-express in the tetrahedron for the carrier (a face or edge move ends on the
        // boundary of that cell, inside the tetrahedron `m.tet`).
        let next = if pts.len() == 4 {
            self.snap(m.tet, &m.cell, &l)
        } else {
            let snapped = self.snap(m.tet, &m.cell, &l);
            At {
                tet: m.tet,
                ..snapped
            }
        };
        Ok(next)
    }

    /// Escapes a stagnation point: the lowest of a few points around `at` that lies lower and
    /// is reached by a straight segment inside the mesh.
    fn perturb(&mut self, at: &At) -> Result<At, TraceStatus<Point>> {
        if self.perturbations >= self.opts.max_perturbations {
            return Err(TraceStatus::Stalled { at: at.p });
        }
        self.perturbations += 1;
        let field = self.field;
        let v0 = field.interpolate(at.tet, &at.p);
        let scale = field.mesh.tet_volume(at.tet).abs().cbrt();
        let mut best: Option<(f64, Point, u32)> = None;
        let mut dirs = Vec::new();
        for x in -1..=1 {
            for y in -1..=1 {
                for z in -1..=1 {
                    if (x, y, z) != (0, 0, 0) {
                        dirs.push(Vector::new(x as f64, y as f64, z as f64).normalize());
                    }
                }
            }
        }
        for r in [0.05, 0.2, 0.5, 1.0, 2.0] {
            for d in &dirs {
                let q = at.p + d * (r * scale);
                match field.walk_segment(at.tet, &at.p, &q) {
                    Segment::Goal(j) => return Err(TraceStatus::ReachedGoal(j)),
                    Segment::Inside(c) => {
                        let vq = field.interpolate(c, &q);
                        if vq < v0 - 1e-13 * v0.abs().max(1e-300)
                            && best.is_none_or(|(b, _, _)| vq < b)
                        {
                            best = Some((vq, q, c));
                        }
                    }
                    Segment::Blocked => {}
                }
            }
            if let Some((_, q, c)) = best {
                return Ok(self.carrier(c, q));
            }
        }
        Err(TraceStatus::Stalled { at: at.p })
    }
}

/// Traces steepest descent of `field` from `start` through the mesh (see the module docs).
pub fn trace_exact_volume(
    field: &P1VolumeField<'_>,
    start: Point,
    opts: &ExactVolumeOptions,
) -> Path<Point> {
    let t0 = match field.locate(start, None) {
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
    if !field.goal_reachable(t0) {
        return Path::new(vec![start], TraceStatus::Unreachable, f64::INFINITY, 0);
    }
    let mut tracer = Exact::new(field, *opts);
    let mut at = tracer.carrier(t0, start);
    let mut points = vec![start];
    if (at.p - start).norm() > 0.0 {
        points.push(at.p);
    }
    let mut moves = 0;
    // Moves that do not lower the value (entering a cell from its boundary) are normal, but
    // many in a row mean the tracer is circling at a stagnation point.
    let mut flat = 0;
    let status = loop {
        if moves >= opts.max_steps {
            break TraceStatus::MaxSteps;
        }
        let before = field.interpolate(at.tet, &at.p);
        let step = if flat > 64 {
            flat = 0;
            tracer.perturb(&at)
        } else {
            tracer.advance(&at)
        };
        match step {
            Ok(next) => {
                moves += 1;
                if (next.p - at.p).norm() > 0.0 {
                    points.push(next.p);
                }
                let after = field.interpolate(next.tet, &next.p);
                if after < before - 1e-14 * before.abs().max(1e-300) {
                    flat = 0;
                } else {
                    flat += 1;
                }
                at = next;
            }
            Err(status) => break status,
        }
    };
    Path::new(points, status, tracer.min_gradient, moves)
}
