//! The mesher's view of free space: an inside test (a continuous function negative in free
//! space), cut points on segments that cross the boundary, and the tag of the boundary part
//! met. Scenes of solids ([`crate::VolumeDomain`]) and configuration spaces known only through
//! collision queries implement the same trait, so the same lattice mesher serves both.

use harmonic_types::BoundaryTag;

use crate::solid::Point;

/// Free space given implicitly.
///
/// ```
/// use harmonic_types::BoundaryTag;
/// use harmonic_volume::{ImplicitDomain, Point};
///
/// /// The unit ball, known only through an inside test (no distances).
/// struct Ball;
/// impl ImplicitDomain for Ball {
///     fn value(&self, p: &Point) -> f64 {
///         if p.coords.norm() < 1.0 { -1.0 } else { 1.0 }
///     }
///     fn tag(&self, _p: &Point) -> BoundaryTag {
///         BoundaryTag::Wall
///     }
///     fn bounds(&self) -> (Point, Point) {
///         (Point::new(-1.0, -1.0, -1.0), Point::new(1.0, 1.0, 1.0))
///     }
/// }
/// let (a, b) = (Point::origin(), Point::new(2.0, 0.0, 0.0));
/// let c = Ball.cut(&a, Ball.value(&a), &b, Ball.value(&b));
/// assert!((c.x - 1.0).abs() < 1e-9);
/// ```
pub trait ImplicitDomain: Sync {
    /// A continuous function, negative in free space, positive outside it and zero on its
    /// boundary. A signed distance is best (cut points then converge fast); a ±1 inside
    /// test works too (cut points are found by bisection).
    fn value(&self, p: &Point) -> f64;

    /// Whether `p` lies in free space.
    fn inside(&self, p: &Point) -> bool {
        self.value(p) < 0.0
    }

    /// The point where the segment from `a` (inside) to `b` (outside) meets the boundary,
    /// given the [`value`](Self::value)s `fa` and `fb` there (the stuffing has them: they
    /// decided that the edge is cut). The default brackets the sign change by the Illinois
    /// variant of regula falsi (bisection when the values carry no slope information), to
    /// 1e-13 of the segment's length.
    fn cut(&self, a: &Point, fa: f64, b: &Point, fb: f64) -> Point {
        let (mut s0, mut s1) = (0.0f64, 1.0f64);
        let (mut f0, mut f1) = (fa, fb);
        if f0 >= 0.0 {
            return *a;
        }
        if f1 <= 0.0 {
            return *b;
        }
        let mut side = 0i8;
        for _ in 0..200 {
            if s1 - s0 <= 1e-13 {
                break;
            }
            let mut s = (s0 * f1 - s1 * f0) / (f1 - f0);
            if !(s > s0 && s < s1) {
                s = 0.5 * (s0 + s1);
            }
            let f = self.value(&(a + (b - a) * s));
            if f == 0.0 {
                return a + (b - a) * s;
            }
            if f < 0.0 {
                s0 = s;
                f0 = f;
                if side == -1 {
                    f1 *= 0.5;
                }
                side = -1;
            } else {
                s1 = s;
                f1 = f;
                if side == 1 {
                    f0 *= 0.5;
                }
                side = 1;
            }
        }
        a + (b - a) * (0.5 * (s0 + s1))
    }

    /// The boundary part nearest to `p` (a point on or near the boundary).
    fn tag(&self, p: &Point) -> BoundaryTag;

    /// A box `(min, max)` containing free space.
    fn bounds(&self) -> (Point, Point);

    /// Where a lattice of spacing `spacing` is too coarse for this domain (passages narrower
    /// than it, parts thinner than it), as a refinement criterion on the lattice's
    /// tetrahedra; `None` (the default) meshes on the uniform lattice.
    fn grading(&self, spacing: f64) -> Option<Grading<'_>> {
        let _ = spacing;
        None
    }
}

/// A test on a tetrahedron's corners.
pub type TetTest<'a> = dyn Fn(&[Point; 4]) -> bool + Sync + 'a;

/// Values of the domain already computed, by point (`None` where there is none).
pub type KnownValues<'a> = dyn Fn(&Point) -> Option<f64> + Sync + 'a;

/// A refinement criterion for the stuffing lattice (see [`ImplicitDomain::grading`]).
pub struct Grading<'a> {
    /// Whether a lattice tetrahedron (its corners) should be bisected (asked of the
    /// lattice's tetrahedra on every core).
    pub want: Box<TetTest<'a>>,
    /// A rank of points, smaller near what is refined for: among edges of equal length the
    /// one nearer is bisected first, which keeps the refinement local.
    pub rank: Box<dyn Fn(&Point) -> f64 + Sync + 'a>,
    /// The domain's values the criterion already computed, by point (`None` where it has
    /// none): stuffing the graded lattice reads them instead of asking
    /// [`ImplicitDomain::value`] again. `None` (no such store) asks for every value.
    pub known: Option<Box<KnownValues<'a>>>,
}
