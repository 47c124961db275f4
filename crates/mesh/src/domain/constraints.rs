//! Interior constraints of a domain: segments and points inside free space that the mesh
//! must contain (the interior segments and vertices of a Triangle `.poly` file), beside the
//! tagged boundary rings. They bound nothing: free space lies on both sides of a constraint
//! segment, and its mesh edges are interior edges with no tag.

use super::Domain;
use crate::{MeshError, Point, geom::twice_signed_area};

/// Constraint segments and points in a domain's unit coordinates.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Constraints {
    /// Segments, each with free space on both sides.
    pub(crate) segments: Vec<(Point, Point)>,
    /// Single points.
    pub(crate) points: Vec<Point>,
}

impl Constraints {
    /// Whether there are none.
    pub(crate) fn is_empty(&self) -> bool {
        self.segments.is_empty() && self.points.is_empty()
    }
}

/// Whether segments `ab` and `pq` cross at a point inside both (touching at an end or
/// running along each other is not crossing).
fn cross_properly(a: Point, b: Point, p: Point, q: Point) -> bool {
    let (d1, d2) = (twice_signed_area(a, b, p), twice_signed_area(a, b, q));
    let (d3, d4) = (twice_signed_area(p, q, a), twice_signed_area(p, q, b));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

impl Domain {
    /// The domain with interior constraints: `segments` the mesh must hold as edges (split
    /// where refinement needs to) and `points` it must hold as vertices. Each must lie in
    /// free space (a segment may end on the boundary but not cross it); those that meet a
    /// goal region are left out (the goal takes their place: a point goal's small disc may
    /// cover a file's interior vertices). Meshes of a domain with constraints are made in one
    /// piece (not in halves).
    ///
    /// ```
    /// use harmonic_mesh::{Domain, DomainSpec, MeshOptions, Point};
    /// let spec = DomainSpec {
    ///     workspace: vec![Point::new(0.0, 0.0), Point::new(4.0, 0.0), Point::new(4.0, 4.0), Point::new(0.0, 4.0)],
    ///     obstacles: vec![],
    ///     goals: vec![],
    ///     robot_radius: 0.0,
    /// };
    /// let opts = MeshOptions { max_area: Some(0.5), ..MeshOptions::default() };
    /// let slit = [Point::new(1.0, 2.0), Point::new(3.0, 2.0)];
    /// let domain = Domain::new(&spec, &opts)?.with_constraints(&[slit], &[Point::new(2.0, 1.0)])?;
    /// let (mesh, _) = domain.mesh(&opts)?;
    /// // The slit's ends and the point are mesh vertices, and the slit is covered by edges.
    /// for p in [slit[0], slit[1], Point::new(2.0, 1.0)] {
    ///     assert!(mesh.vertices().contains(&p));
    /// }
    /// let on_slit = |p: Point| p.y == 2.0 && (1.0..=3.0).contains(&p.x);
    /// let mut covered = 0.0;
    /// for t in mesh.triangles() {
    ///     for k in 0..3 {
    ///         let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
    ///         let (p, q) = (mesh.vertices()[a], mesh.vertices()[b]);
    ///         if a < b && on_slit(p) && on_slit(q) {
    ///             covered += (q - p).norm();
    ///         }
    ///     }
    /// }
    /// assert!((covered - 2.0).abs() < 1e-12, "{covered}");
    /// // A segment leaving free space is refused.
    /// let out = [Point::new(1.0, 1.0), Point::new(5.0, 1.0)];
    /// assert!(Domain::new(&spec, &opts)?.with_constraints(&[out], &[]).is_err());
    /// # Ok::<(), harmonic_mesh::MeshError>(())
    /// ```
    pub fn with_constraints(
        mut self,
        segments: &[[Point; 2]],
        points: &[Point],
    ) -> Result<Domain, MeshError> {
        let bad = |what, index, reason| MeshError::Constraint {
            what,
            index,
            reason,
        };
        let goals: Vec<Vec<Point>> = self.goals.iter().map(|g| g.exterior.clone()).collect();
        let meets_goal = |a: Point, b: Point| {
            goals
                .iter()
                .any(|g| crate::geom::segment_polygon_distance(a, b, g) == 0.0)
        };
        for (k, &[a, b]) in segments.iter().enumerate() {
            if ![a.x, a.y, b.x, b.y].iter().all(|v| v.is_finite()) {
                return Err(bad("segment", k, "has a non-finite coordinate"));
            }
            if meets_goal(a, b) {
                continue;
            }
            if a == b {
                return Err(bad("segment", k, "has zero length"));
            }
            let mid = Point::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
            if !(self.contains_free(a) && self.contains_free(b) && self.contains_free(mid)) {
                return Err(bad("segment", k, "does not lie in free space"));
            }
            let (ua, ub) = (self.frame.input_to_unit(a), self.frame.input_to_unit(b));
            let lo = Point::new(ua.x.min(ub.x), ua.y.min(ub.y));
            let hi = Point::new(ua.x.max(ub.x), ua.y.max(ub.y));
            if self
                .unit_boundary_index()
                .in_box(lo, hi)
                .any(|(p, q, _)| cross_properly(ua, ub, p, q))
            {
                return Err(bad("segment", k, "crosses the boundary of free space"));
            }
            self.constraints.segments.push((ua, ub));
        }
        for (k, &p) in points.iter().enumerate() {
            if !(p.x.is_finite() && p.y.is_finite()) {
                return Err(bad("point", k, "has a non-finite coordinate"));
            }
            if meets_goal(p, p) {
                continue;
            }
            if !self.contains_free(p) {
                return Err(bad("point", k, "does not lie in free space"));
            }
            self.constraints.points.push(self.frame.input_to_unit(p));
        }
        Ok(self)
    }

    /// The interior constraint segments, in the scene's coordinates.
    pub fn constraint_segments(&self) -> Vec<[Point; 2]> {
        self.constraints
            .segments
            .iter()
            .map(|&(a, b)| [self.frame.to_user(a), self.frame.to_user(b)])
            .collect()
    }

    /// The constraints in unit coordinates (what the mesher inserts).
    pub(crate) fn unit_constraints(&self) -> &Constraints {
        &self.constraints
    }
}
