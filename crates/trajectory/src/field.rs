//! The [`Field`] trait that tracers and the car stepper follow, and the P1 (finite element)
//! fields [`P1Field`] and [`SmoothP1Field`], which borrow the mesh and the nodal values
//! without copying them. Their [`Field`] implementations are in `exact.rs`, beside the exact
//! tracer's move that they fall back on; this module needs nothing from the tracers.

use harmonic_types::{BoundaryTag, Mesh, NO_NEIGHBOR, Point, Vector};

use crate::TraceError;

/// Where a point lies with respect to a field's free space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Locate<C> {
    /// Inside free space, in this cell (on its boundary counts as inside).
    Inside(C),
    /// Inside goal region `j` (reaching it ends a path).
    Goal(u32),
    /// Inside an obstacle (or any other region of the workspace that is not free space).
    InObstacle,
    /// Outside the workspace.
    OutsideWorkspace,
}

/// Where a straight segment of motion ends (see [`Field::segment`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Segment<C> {
    /// The whole segment stays in free space; its end lies in this cell.
    Inside(C),
    /// The segment enters goal region `j` before leaving free space in any other way.
    Goal(u32),
    /// The segment crosses a wall or an obstacle boundary.
    Blocked,
}

/// The outcome of [`Field::fallback_step`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fallback<C, P = Point> {
    /// Moved downhill to this point, in this cell.
    Moved(P, C),
    /// Reached goal region `j`.
    Goal(u32),
    /// No guaranteed move is available here.
    Stuck,
}

/// A potential field over free space that a robot follows downhill, in the plane
/// (`Point = Point`) or in a volume or configuration space (`Point = Point3`).
///
/// `value` DECREASES toward the goal; the robot moves along `-gradient`. The FEM potential,
/// the baselines' grid fields and analytic fields all implement it, so the same smooth tracer
/// and car stepper follow every planner's field; the volume's P1 field implements it too,
/// for the volume's smooth tracer.
///
/// An analytic field needs only `locate`, `value` and `gradient`:
///
/// ```
/// use harmonic_mesh::{Point, Vector};
/// use harmonic_trajectory::{Field, Locate, SmoothOptions, TraceStatus, trace_smooth};
///
/// /// The distance to the origin in the square [-5, 5]²; the goal is the unit disc.
/// struct Cone;
/// impl Field for Cone {
///     type Point = Point;
///     type Vector = Vector;
///     type Cell = ();
///     fn locate(&self, p: Point, _hint: Option<()>) -> Locate<()> {
///         if p.x.abs() > 5.0 || p.y.abs() > 5.0 {
///             Locate::OutsideWorkspace
///         } else if p.coords.norm() <= 1.0 {
///             Locate::Goal(0)
///         } else {
///             Locate::Inside(())
///         }
///     }
///     fn value(&self, _: (), p: Point) -> f64 {
///         p.coords.norm()
///     }
///     fn gradient(&self, _: (), p: Point) -> Vector {
///         p.coords / p.coords.norm()
///     }
/// }
///
/// let path = trace_smooth(&Cone, Point::new(4.0, 3.0), &SmoothOptions::for_scale(10.0))?;
/// assert_eq!(path.status, TraceStatus::ReachedGoal(0));
/// assert!((path.length - 4.0).abs() < 1e-6);
/// # Ok::<(), harmonic_trajectory::TraceError>(())
/// ```
pub trait Field {
    /// The points the field is defined at: [`Point`] or `Point3`.
    type Point: Copy;
    /// Its gradients: [`Vector`] or `Vector3`.
    type Vector: Copy;
    /// A handle on the piece of the field holding a point (a triangle, a grid cell, ...).
    type Cell: Copy + PartialEq + std::fmt::Debug;

    /// Finds the cell holding `p`, starting the search from `hint` when given (the cell of a
    /// nearby point: the previous position of a path).
    fn locate(&self, p: Self::Point, hint: Option<Self::Cell>) -> Locate<Self::Cell>;

    /// The potential at `p`, which lies in `cell` (a cell returned by [`Field::locate`] or
    /// [`Field::segment`] for this field; other handles may panic).
    fn value(&self, cell: Self::Cell, p: Self::Point) -> f64;

    /// The gradient of the potential at `p`, which lies in `cell`.
    fn gradient(&self, cell: Self::Cell, p: Self::Point) -> Self::Vector;

    /// Follows the straight segment `from → to` (`from` lies in `cell`) and says whether it
    /// stays in free space, enters a goal, or crosses a wall or an obstacle.
    ///
    /// The default only locates `to`, which is exact for convex free space and a good
    /// approximation for short segments; fields that know their boundaries override it.
    fn segment(&self, cell: Self::Cell, from: Self::Point, to: Self::Point) -> Segment<Self::Cell> {
        let _ = from;
        match self.locate(to, Some(cell)) {
            Locate::Inside(c) => Segment::Inside(c),
            Locate::Goal(j) => Segment::Goal(j),
            Locate::InObstacle | Locate::OutsideWorkspace => Segment::Blocked,
        }
    }

    /// One guaranteed downhill move from `p` (in `cell`) that stays in free space, for when
    /// an integrator cannot make progress (its steps keep leaving free space, or the
    /// direction flips at a stagnation point). P1 fields make one move of the exact tracer.
    /// The default has none.
    fn fallback_step(&self, cell: Self::Cell, p: Self::Point) -> Fallback<Self::Cell, Self::Point> {
        let _ = (cell, p);
        Fallback::Stuck
    }

    /// Whether any goal can be reached from `cell` without leaving free space. A path from a
    /// cell that cannot reach a goal ends as `Unreachable` at once. The default says yes.
    fn goal_reachable(&self, cell: Self::Cell) -> bool {
        let _ = cell;
        true
    }
}

/// `|v|` without underflow or overflow: ψ's gradients go far below 1e-154 (where the squared
/// norm underflows to zero) in the far rooms of large scenes.
#[inline]
pub(crate) fn magnitude(v: Vector) -> f64 {
    let n2 = v.norm_squared();
    if (1e-280..1e280).contains(&n2) {
        n2.sqrt()
    } else {
        v.x.hypot(v.y)
    }
}

/// Sign of the orientation of `a, b, c` (exact): positive when counter-clockwise.
pub(crate) use harmonic_types::geom::orient2d as orient;

/// A piecewise-linear (P1) potential on a triangle mesh: one value per vertex, linear inside
/// each triangle, so the gradient is constant per triangle.
///
/// `value(p) = sign · Σ λᵢ(p) values[i]`. Use [`P1Field::descending`] for a potential that
/// already decreases toward the goal (φ) and [`P1Field::ascending`] for one that increases
/// toward it (ψ = φ_wall − φ): multiplying by −1 is exact, so ψ keeps its relative precision.
///
/// A ψ past the double range (a Dirichlet corridor of many widths) is given as mantissas and
/// binary exponents, ψᵢ = mᵢ·2^eᵢ ([`P1Field::ascending_extended`]). Such a field's value is
/// −ln ψ (decreasing toward the goal like −ψ, so every "lower" test of the tracers keeps its
/// meaning), and its gradient in a triangle is −∇ψ / max ψ over the triangle's vertices,
/// computed from the mantissas rescaled by the triangle's largest exponent: the direction of
/// −∇ψ at the magnitude of |∇ ln ψ|, comparable from triangle to triangle however small ψ is.
#[derive(Clone, Copy, Debug)]
pub struct P1Field<'a> {
    mesh: &'a Mesh,
    values: &'a [f64],
    sign: f64,
    /// Per vertex: the goal it belongs to, or [`NOT_A_GOAL`]; `None` when the goals are the
    /// mesh's goal-tagged boundary edges.
    goal_vertices: Option<&'a [u32]>,
    /// Binary exponents of `values` for an extended-range ψ (`sign` is then −1).
    exponents: Option<&'a [i32]>,
}

/// The value of an extended-range field where ψ is zero (on a wall held at the reference):
/// above −ln ψ of every non-zero ψ (|log₂ ψ| < 2³¹), and finite, so differences stay finite.
const EXTENDED_ZERO_VALUE: f64 = 1e12;

/// `x · 2^k` (zero on underflow, infinity on overflow), for rescaling mantissas.
#[inline]
pub(crate) fn ldexp(x: f64, k: i64) -> f64 {
    let pow2 = |k: i64| f64::from_bits(((k + 1023) as u64) << 52);
    if x == 0.0 || k == 0 {
        x
    } else if k > 1023 {
        x * f64::INFINITY
    } else if k >= -1022 {
        x * pow2(k)
    } else if k >= -1022 - 60 {
        x * pow2(-1022) * pow2(k + 1022)
    } else {
        x * 0.0
    }
}

/// Marks a vertex that belongs to no goal in [`P1Field::with_goal_vertices`].
pub const NOT_A_GOAL: u32 = u32::MAX;

impl<'a> P1Field<'a> {
    /// A field whose nodal `values` decrease toward the goal (the robot descends them).
    ///
    /// Errors if there is not exactly one value per mesh vertex or a value is not finite.
    ///
    /// ```
    /// use harmonic_mesh::{BoundaryTag, Mesh, Point};
    /// use harmonic_trajectory::{Field, Locate, P1Field};
    /// let mesh = Mesh::from_parts(
    ///     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0)],
    ///     vec![[0, 1, 2]],
    ///     &[(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Goal(0)), (2, 0, BoundaryTag::Wall)],
    /// )?;
    /// let values = [1.0, 0.0, 0.0];
    /// let field = P1Field::descending(&mesh, &values)?;
    /// let p = Point::new(0.25, 0.25);
    /// let Locate::Inside(t) = field.locate(p, None) else { panic!("inside") };
    /// assert!((field.value(t, p) - 0.5).abs() < 1e-15);
    /// assert_eq!(field.gradient(t, p), harmonic_mesh::Vector::new(-1.0, -1.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn descending(mesh: &'a Mesh, values: &'a [f64]) -> Result<Self, TraceError> {
        Self::new(mesh, values, 1.0)
    }

    /// A field whose nodal `values` increase toward the goal (ψ); the robot ascends them and
    /// the field's `value` is `−values`.
    ///
    /// Errors if there is not exactly one value per mesh vertex or a value is not finite.
    pub fn ascending(mesh: &'a Mesh, values: &'a [f64]) -> Result<Self, TraceError> {
        Self::new(mesh, values, -1.0)
    }

    /// An increasing-toward-the-goal ψ past the double range: ψᵢ = `mantissas[i]` ·
    /// 2^`exponents[i]` (any finite mantissas; ψ ≥ 0 for a potential). See the type's docs
    /// for the value and gradient of such a field.
    ///
    /// Errors if a slice does not have one entry per vertex or a mantissa is not finite.
    ///
    /// ```
    /// use harmonic_mesh::{BoundaryTag, Mesh, Point};
    /// use harmonic_trajectory::{ExactOptions, P1Field, TraceStatus, trace_exact};
    /// let mesh = Mesh::from_parts(
    ///     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)],
    ///     vec![[0, 1, 2], [0, 2, 3]],
    ///     &[(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Wall),
    ///       (2, 3, BoundaryTag::Goal(0)), (3, 0, BoundaryTag::Wall)],
    /// )?;
    /// // ψ = 2^-4000 at the bottom, 2^-3999 at the top: far below any f64.
    /// let (m, e) = ([1.0; 4], [-4000, -4000, -3999, -3999]);
    /// let field = P1Field::ascending_extended(&mesh, &m, &e)?;
    /// let path = trace_exact(&field, Point::new(0.7, 0.2), &ExactOptions::default());
    /// assert_eq!(path.status, TraceStatus::ReachedGoal(0));
    /// assert!((path.length - 0.8).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn ascending_extended(
        mesh: &'a Mesh,
        mantissas: &'a [f64],
        exponents: &'a [i32],
    ) -> Result<Self, TraceError> {
        check_len("exponents", mesh.vertices().len(), exponents.len())?;
        let mut field = Self::new(mesh, mantissas, -1.0)?;
        field.exponents = Some(exponents);
        Ok(field)
    }

    fn new(mesh: &'a Mesh, values: &'a [f64], sign: f64) -> Result<Self, TraceError> {
        check_len("values", mesh.vertices().len(), values.len())?;
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(TraceError::NotFinite {
                what: "values",
                index: i,
            });
        }
        Ok(P1Field {
            mesh,
            values,
            sign,
            goal_vertices: None,
            exponents: None,
        })
    }

    /// The same field with its goals given as mesh vertices instead of goal-tagged boundary
    /// edges: `goal_of[v]` is the goal vertex `v` belongs to, or [`NOT_A_GOAL`]. A path reaches
    /// goal `j` when it enters a triangle with a vertex of goal `j` (inside that triangle the
    /// straight segment to the vertex stays in free space). For fields whose goals are held
    /// vertices of a mesh with no goal boundary, as a goal chosen after the mesh gives.
    ///
    /// Errors if there is not one entry per mesh vertex.
    pub fn with_goal_vertices(self, goal_of: &'a [u32]) -> Result<Self, TraceError> {
        check_len("goal vertices", self.mesh.vertices().len(), goal_of.len())?;
        Ok(P1Field {
            goal_vertices: Some(goal_of),
            ..self
        })
    }

    /// The goal a vertex of triangle `t` belongs to, when the goals are vertices (the first
    /// such vertex's goal); `None` otherwise.
    #[inline]
    pub fn goal_of_triangle(&self, t: u32) -> Option<u32> {
        let marks = self.goal_vertices?;
        self.mesh.triangles()[t as usize]
            .iter()
            .map(|&v| marks[v as usize])
            .find(|&g| g != NOT_A_GOAL)
    }

    /// Per vertex, the goal it belongs to, when the goals are vertices.
    pub fn goal_vertices(&self) -> Option<&'a [u32]> {
        self.goal_vertices
    }

    /// Whether ψ is given with exponents ([`P1Field::ascending_extended`]).
    pub fn is_extended(&self) -> bool {
        self.exponents.is_some()
    }

    /// The largest exponent among the non-zero ψ of triangle `tri` (0 if all are zero).
    #[inline]
    fn largest_exponent(&self, exponents: &[i32], tri: [u32; 3]) -> i32 {
        tri.iter()
            .filter(|&&v| self.values[v as usize] != 0.0)
            .map(|&v| exponents[v as usize])
            .max()
            .unwrap_or(0)
    }

    /// ψ at the vertices of `tri` rescaled by 2^−`scale`.
    #[inline]
    fn rescaled(&self, exponents: &[i32], tri: [u32; 3], scale: i32) -> [f64; 3] {
        tri.map(|v| {
            ldexp(
                self.values[v as usize],
                exponents[v as usize] as i64 - scale as i64,
            )
        })
    }

    /// −ln ψ for ψ = `m` · 2^`e` (the extended field's value).
    #[inline]
    fn extended_value(m: f64, e: i32) -> f64 {
        if m > 0.0 {
            -(m.ln() + e as f64 * std::f64::consts::LN_2)
        } else {
            EXTENDED_ZERO_VALUE
        }
    }

    /// The mesh the field lives on.
    pub fn mesh(&self) -> &'a Mesh {
        self.mesh
    }

    /// The field's value at vertex `v` (sign applied).
    #[inline]
    pub fn vertex_value(&self, v: u32) -> f64 {
        match self.exponents {
            None => self.sign * self.values[v as usize],
            Some(e) => Self::extended_value(self.values[v as usize], e[v as usize]),
        }
    }

    /// The (constant) gradient of the field in triangle `t` (sign applied).
    #[inline]
    pub fn triangle_gradient(&self, t: u32) -> Vector {
        let tri = self.mesh.triangles()[t as usize];
        let v = self.mesh.vertices();
        let [a, b, c] = tri.map(|i| v[i as usize]);
        let ([fa, fb, fc], sign) = match self.exponents {
            None => (tri.map(|i| self.values[i as usize]), self.sign),
            Some(e) => {
                let f = self.rescaled(e, tri, self.largest_exponent(e, tri));
                let top = f[0].max(f[1]).max(f[2]);
                if top.is_nan() || top <= 0.0 {
                    return Vector::zeros();
                }
                (f, -1.0 / top)
            }
        };
        let twice_area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        let gx = fa * (b.y - c.y) + fb * (c.y - a.y) + fc * (a.y - b.y);
        let gy = fa * (c.x - b.x) + fb * (a.x - c.x) + fc * (b.x - a.x);
        Vector::new(gx, gy) * (sign / twice_area)
    }

    /// ψ interpolated at `p` in triangle `cell` as (mantissa, exponent): the mantissas
    /// rescaled by the triangle's largest exponent (linear extrapolation outside `cell`).
    /// For a field without exponents the exponent is 0 and the value is ±`values` interpolated.
    #[inline]
    pub(crate) fn scaled_psi_at(&self, cell: u32, p: Point) -> (f64, i32) {
        let tri = self.mesh.triangles()[cell as usize];
        let l = self.barycentric(cell, p);
        let (f, scale) = match self.exponents {
            None => (tri.map(|i| self.values[i as usize]), 0),
            Some(e) => {
                let scale = self.largest_exponent(e, tri);
                (self.rescaled(e, tri, scale), scale)
            }
        };
        (l[0] * f[0] + l[1] * f[1] + l[2] * f[2], scale)
    }

    /// Barycentric coordinates of `p` in triangle `t` (they sum to one; negative outside).
    #[inline]
    pub(crate) fn barycentric(&self, t: u32, p: Point) -> [f64; 3] {
        harmonic_types::geom::barycentric(self.mesh.triangle_points(t), p)
    }

    /// Whether triangle `t` holds `p` (closed triangle, exact predicates).
    #[inline]
    pub(crate) fn contains(&self, t: u32, p: Point) -> bool {
        let [a, b, c] = self.mesh.triangle_points(t);
        orient(a, b, p) >= 0.0 && orient(b, c, p) >= 0.0 && orient(c, a, p) >= 0.0
    }

    /// Visibility walk from `start` toward `p`; `None` if the walk would leave the mesh or
    /// runs too long (non-Delaunay meshes can make visibility walks cycle).
    fn walk(&self, p: Point, start: u32) -> Option<u32> {
        let mesh = self.mesh;
        let tris = mesh.triangles();
        let verts = mesh.vertices();
        let mut t = start;
        let cap = tris.len() + 3;
        for step in 0..cap {
            let tri = tris[t as usize];
            let mut moved = false;
            for r in 0..3 {
                let k = (step + r) % 3;
                let a = verts[tri[(k + 1) % 3] as usize];
                let b = verts[tri[(k + 2) % 3] as usize];
                if orient(a, b, p) < 0.0 {
                    let n = mesh.neighbors()[t as usize][k];
                    if n == NO_NEIGHBOR {
                        return None;
                    }
                    t = n;
                    moved = true;
                    break;
                }
            }
            if !moved {
                return Some(t);
            }
        }
        None
    }

    /// Classifies a point that no triangle holds: the first boundary edge met by the ray
    /// going right from `p` separates it from free space, and its tag says what lies there.
    fn classify_outside(&self, p: Point) -> Locate<u32> {
        let verts = self.mesh.vertices();
        let mut best = f64::INFINITY;
        let mut tag = None;
        for e in self.mesh.boundary_edges() {
            let a = verts[e.vertices[0] as usize];
            let b = verts[e.vertices[1] as usize];
            if (a.y > p.y) == (b.y > p.y) {
                continue;
            }
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x >= p.x && x < best {
                best = x;
                tag = Some(e.tag);
            }
        }
        match tag {
            Some(BoundaryTag::Goal(j)) => Locate::Goal(j),
            Some(BoundaryTag::Obstacle(_)) => Locate::InObstacle,
            Some(BoundaryTag::Wall) | None => Locate::OutsideWorkspace,
        }
    }

    /// Straight walk along `from → to` starting in `t` (which holds `from`).
    fn segment_walk(&self, mut t: u32, from: Point, to: Point) -> Segment<u32> {
        let mesh = self.mesh;
        let tris = mesh.triangles();
        let verts = mesh.vertices();
        let mut nudged = false;
        for _ in 0..tris.len() + 3 {
            if self.contains(t, to) {
                return Segment::Inside(t);
            }
            let tri = tris[t as usize];
            // Vertices on the line count as lying to its right: a consistent symbolic
            // perturbation, so consecutive triangles agree on the crossed edges.
            let left = tri.map(|v| orient(from, to, verts[v as usize]) > 0.0);
            let exit = (0..3).find(|&k| !left[(k + 1) % 3] && left[(k + 2) % 3]);
            let Some(k) = exit else {
                // The perturbed line (shifted a hair to the left) misses this triangle:
                // `from` sits on a vertex or an edge of it. Restart from the triangle
                // holding a point a hair ahead of `from` and to the left of the line.
                if nudged {
                    return Segment::Blocked;
                }
                nudged = true;
                let d = (to - from) * 1e-9;
                let probe = from + d + Vector::new(-d.y, d.x);
                match self.walk(probe, t) {
                    Some(u) => {
                        if let Some(j) = self.goal_of_triangle(u) {
                            return Segment::Goal(j);
                        }
                        t = u;
                        continue;
                    }
                    None => return Segment::Blocked,
                }
            };
            let n = mesh.neighbors()[t as usize][k];
            if n == NO_NEIGHBOR {
                return match mesh.boundary_edge_of(t, k).map(|e| e.tag) {
                    Some(BoundaryTag::Goal(j)) => Segment::Goal(j),
                    _ => Segment::Blocked,
                };
            }
            if let Some(j) = self.goal_of_triangle(n) {
                return Segment::Goal(j);
            }
            t = n;
        }
        Segment::Blocked
    }

    /// Whether some goal edge lies in the same connected component as triangle `t`.
    pub(crate) fn component_has_goal(&self, t: u32) -> bool {
        let comps = self.mesh.triangle_components();
        let c = comps[t as usize];
        if let Some(marks) = self.goal_vertices {
            return self
                .mesh
                .triangles()
                .iter()
                .zip(comps)
                .any(|(tri, &ct)| ct == c && tri.iter().any(|&v| marks[v as usize] != NOT_A_GOAL));
        }
        self.mesh
            .boundary_edges()
            .iter()
            .any(|e| matches!(e.tag, BoundaryTag::Goal(_)) && comps[e.triangle as usize] == c)
    }
}

fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), TraceError> {
    if expected == got {
        Ok(())
    } else {
        Err(TraceError::LengthMismatch {
            what,
            expected,
            got,
        })
    }
}

impl P1Field<'_> {
    /// The triangle holding `p` ([`Field::locate`]): a walk from `hint` when given, else
    /// (or when the walk meets the boundary) the mesh's own point location, else what lies
    /// outside.
    pub(crate) fn locate_point(&self, p: Point, hint: Option<u32>) -> Locate<u32> {
        let n = self.mesh.triangles().len();
        if n == 0 || !p.x.is_finite() || !p.y.is_finite() {
            return Locate::OutsideWorkspace;
        }
        let inside = |t: u32| match self.goal_of_triangle(t) {
            Some(j) => Locate::Goal(j),
            None => Locate::Inside(t),
        };
        if let Some(t) = hint
            .filter(|&t| (t as usize) < n)
            .and_then(|h| self.walk(p, h))
        {
            return inside(t);
        }
        // No hint, or the walk met the boundary (non-convex free space): the mesh's own
        // bucket-grid location.
        if let Some(t) = self.mesh.locate(p, None) {
            return inside(t);
        }
        self.classify_outside(p)
    }

    /// The field's value at `p` in triangle `cell` ([`Field::value`]; sign applied).
    #[inline]
    pub(crate) fn value_at(&self, cell: u32, p: Point) -> f64 {
        if self.exponents.is_some() {
            let (m, e) = self.scaled_psi_at(cell, p);
            return Self::extended_value(m, e);
        }
        let tri = self.mesh.triangles()[cell as usize];
        let l = self.barycentric(cell, p);
        self.sign
            * (l[0] * self.values[tri[0] as usize]
                + l[1] * self.values[tri[1] as usize]
                + l[2] * self.values[tri[2] as usize])
    }

    /// Where the segment `from → to` from triangle `cell` ends ([`Field::segment`]):
    /// blocked for a triangle that is not the mesh's or a non-finite end.
    pub(crate) fn segment_from(&self, cell: u32, from: Point, to: Point) -> Segment<u32> {
        if (cell as usize) >= self.mesh.triangles().len() || !to.x.is_finite() || !to.y.is_finite()
        {
            return Segment::Blocked;
        }
        self.segment_walk(cell, from, to)
    }
}

/// A P1 potential whose gradient is the recovered nodal gradient interpolated linearly
/// (barycentrically) inside each triangle: continuous, so integrated paths are smooth.
/// Values, location and free-space checks are those of the underlying [`P1Field`].
#[derive(Clone, Copy, Debug)]
pub struct SmoothP1Field<'a> {
    p1: P1Field<'a>,
    gradients: &'a [Vector],
    /// Binary exponents of `gradients` for an extended-range ψ.
    gradient_exponents: Option<&'a [i32]>,
}

impl<'a> SmoothP1Field<'a> {
    /// A smooth field from values decreasing toward the goal and their recovered nodal
    /// gradients (one per vertex, gradients of `values`).
    ///
    /// Errors if a slice does not have one entry per vertex or holds a non-finite number.
    pub fn descending(
        mesh: &'a Mesh,
        values: &'a [f64],
        gradients: &'a [Vector],
    ) -> Result<Self, TraceError> {
        Self::new(P1Field::descending(mesh, values)?, gradients)
    }

    /// A smooth field from values increasing toward the goal (ψ) and their recovered nodal
    /// gradients (gradients of ψ; the sign is applied here).
    ///
    /// Errors if a slice does not have one entry per vertex or holds a non-finite number.
    pub fn ascending(
        mesh: &'a Mesh,
        values: &'a [f64],
        gradients: &'a [Vector],
    ) -> Result<Self, TraceError> {
        Self::new(P1Field::ascending(mesh, values)?, gradients)
    }

    /// A smooth field from an extended-range ψ (mantissas and exponents, as
    /// [`P1Field::ascending_extended`]) and its recovered nodal gradients, also as mantissa
    /// vectors and exponents (∇ψᵢ = `gradients[i]` · 2^`gradient_exponents[i]`). Its gradient
    /// is the recovered ∇ψ divided by ψ at the point, −∇ ln ψ: the direction of the ordinary
    /// smooth field's, at a magnitude that stays in range.
    ///
    /// Errors if a slice does not have one entry per vertex or holds a non-finite number.
    pub fn ascending_extended(
        mesh: &'a Mesh,
        mantissas: &'a [f64],
        exponents: &'a [i32],
        gradients: &'a [Vector],
        gradient_exponents: &'a [i32],
    ) -> Result<Self, TraceError> {
        check_len(
            "gradient exponents",
            mesh.vertices().len(),
            gradient_exponents.len(),
        )?;
        let mut field = Self::new(
            P1Field::ascending_extended(mesh, mantissas, exponents)?,
            gradients,
        )?;
        field.gradient_exponents = Some(gradient_exponents);
        Ok(field)
    }

    fn new(p1: P1Field<'a>, gradients: &'a [Vector]) -> Result<Self, TraceError> {
        check_len("gradients", p1.mesh.vertices().len(), gradients.len())?;
        if let Some(i) = gradients
            .iter()
            .position(|g| !g.x.is_finite() || !g.y.is_finite())
        {
            return Err(TraceError::NotFinite {
                what: "gradients",
                index: i,
            });
        }
        Ok(SmoothP1Field {
            p1,
            gradients,
            gradient_exponents: None,
        })
    }

    /// The same field with its goals given as mesh vertices ([`P1Field::with_goal_vertices`]).
    pub fn with_goal_vertices(self, goal_of: &'a [u32]) -> Result<Self, TraceError> {
        Ok(SmoothP1Field {
            p1: self.p1.with_goal_vertices(goal_of)?,
            ..self
        })
    }

    /// The underlying piecewise-linear field (what the exact tracer follows).
    pub fn p1(&self) -> &P1Field<'a> {
        &self.p1
    }
}

impl SmoothP1Field<'_> {
    /// The recovered gradient at `p` in triangle `cell` ([`Field::gradient`]): the nodal
    /// gradients interpolated with the barycentric coordinates clamped to the triangle,
    /// sign applied.
    pub(crate) fn gradient_at(&self, cell: u32, p: Point) -> Vector {
        let tri = self.p1.mesh.triangles()[cell as usize];
        let l = self.p1.barycentric(cell, p).map(|x| x.clamp(0.0, 1.0));
        if let Some(ge) = self.gradient_exponents {
            return self.extended_gradient_at(ge, tri, l, cell, p);
        }
        let g = self.gradients[tri[0] as usize] * l[0]
            + self.gradients[tri[1] as usize] * l[1]
            + self.gradients[tri[2] as usize] * l[2];
        g * (self.p1.sign / (l[0] + l[1] + l[2]))
    }
}

impl SmoothP1Field<'_> {
    /// [`gradient_at`](Self::gradient_at) of an extended-range field: the nodal gradients
    /// rescaled by their largest exponent and interpolated, divided by ψ at `p` (both on
    /// their own scales, the ratio rescaled once).
    fn extended_gradient_at(
        &self,
        ge: &[i32],
        tri: [u32; 3],
        l: [f64; 3],
        cell: u32,
        p: Point,
    ) -> Vector {
        let nonzero = |v: u32| {
            let g = self.gradients[v as usize];
            g.x != 0.0 || g.y != 0.0
        };
        let top = tri
            .iter()
            .filter(|&&v| nonzero(v))
            .map(|&v| ge[v as usize])
            .max()
            .unwrap_or(0);
        let mut g = Vector::zeros();
        for k in 0..3 {
            let v = tri[k] as usize;
            let w = ldexp(l[k], ge[v] as i64 - top as i64);
            g += self.gradients[v] * w;
        }
        let g = g / (l[0] + l[1] + l[2]);
        let (psi, scale) = self.p1.scaled_psi_at(cell, p);
        if psi > 0.0 {
            let r = ldexp(1.0 / psi, top as i64 - scale as i64);
            -g * r
        } else {
            -g
        }
    }
}

/// The last free point before the goal on the segment `a → b` (which enters it), found by
/// bisection to 2⁻⁴⁰ of the segment: the path ends on the goal's boundary, still in the mesh
/// (a goal is a hole in the plane's mesh and in a volume's). Any dimension.
pub(crate) fn goal_crossing<
    const D: usize,
    F: Field<Point = nalgebra::Point<f64, D>, Vector = nalgebra::SVector<f64, D>>,
>(
    field: &F,
    cell: F::Cell,
    a: nalgebra::Point<f64, D>,
    b: nalgebra::Point<f64, D>,
) -> nalgebra::Point<f64, D> {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        match field.segment(cell, a, a + (b - a) * mid) {
            Segment::Goal(_) => hi = mid,
            _ => lo = mid,
        }
    }
    a + (b - a) * lo
}
