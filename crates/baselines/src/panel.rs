//! The panel method of Kim & Khosla (1992), *Real-time obstacle avoidance using harmonic
//! potential functions*: a uniform flow, a sink at the goal and constant-strength source
//! panels on the boundary of free space. The panel strengths `λ` solve `P λ = q` so that the
//! normal velocity at each panel's midpoint equals the desired `V_i` (their eqs. 29–35); the
//! velocity anywhere is the closed form of constant-strength source panels (eqs. 36–37, as in
//! Katz & Plotkin §10.2.1). The robot follows the velocity, which is the negative gradient of
//! a harmonic potential in the unbounded plane outside the obstacles.

use std::f64::consts::PI;
use std::time::Instant;

use geo::{BooleanOps, Coord, LineString, MultiPolygon, Polygon, unary_union};
use harmonic_mesh::{Point, Vector};
use harmonic_trajectory::{Field, Locate, TraceStatus};
use nalgebra::{DMatrix, DVector};

use crate::geometry::{check_point, check_polygon, check_positive};
use crate::{BaselineError, PlanResult};
use harmonic_mesh::geom::polygon_contains;

/// A straight source panel from `start` to `end`; its normal points to the right of
/// `start → end` (the outside of a counter-clockwise obstacle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// First end point.
    pub start: Point,
    /// Second end point.
    pub end: Point,
}

impl Panel {
    /// Unit tangent `start → end`.
    pub fn tangent(&self) -> Vector {
        (self.end - self.start).normalize()
    }

    /// Unit normal, to the right of the tangent.
    pub fn normal(&self) -> Vector {
        let t = self.tangent();
        Vector::new(t.y, -t.x)
    }

    /// The control point (midpoint).
    pub fn midpoint(&self) -> Point {
        nalgebra::center(&self.start, &self.end)
    }

    /// Velocity induced at `p` (not on the panel) by a unit-strength source distribution on
    /// the panel (per unit length `1/(2π)·r/|r|²`): in panel coordinates `(x, z)` with the
    /// panel on `0 ≤ x ≤ L`, `u = ln(r₁²/r₂²)/(4π)` and `w = (θ₂ − θ₁)/(2π)`. Across the
    /// panel the normal part jumps from −½ to +½.
    fn unit_velocity(&self, p: Point) -> Vector {
        let t = self.tangent();
        let n = Vector::new(t.y, -t.x);
        let len = (self.end - self.start).norm();
        let d = p - self.start;
        let (x, z) = (d.dot(&t), d.dot(&n));
        let r1 = x * x + z * z;
        let r2 = (x - len) * (x - len) + z * z;
        let u = (r1 / r2).ln() / (4.0 * PI);
        let w = (z.atan2(x - len) - z.atan2(x)) / (2.0 * PI);
        t * u + n * w
    }
}

impl Panel {
    /// Velocity potential at `p` of a unit-strength source distribution on the panel, whose
    /// gradient is [`Panel::unit_velocity`]: in panel coordinates
    /// `(x ln r₁² − (x − L) ln r₂² + 2z(θ₂ − θ₁)) / (4π)`.
    fn unit_potential(&self, p: Point) -> f64 {
        let t = self.tangent();
        let n = Vector::new(t.y, -t.x);
        let len = (self.end - self.start).norm();
        let d = p - self.start;
        let (x, z) = (d.dot(&t), d.dot(&n));
        let r1 = x * x + z * z;
        let r2 = (x - len) * (x - len) + z * z;
        // x ln x² → 0 at the end points.
        let term = |a: f64, r: f64| if r > 0.0 { a * r.ln() } else { 0.0 };
        (term(x, r1) - term(x - len, r2) + 2.0 * z * (z.atan2(x - len) - z.atan2(x))) / (4.0 * PI)
    }
}

/// The flow of [`PanelField::solve`]: a uniform stream, an optional point sink, and source
/// panels whose strengths give each panel's midpoint a prescribed normal velocity.
#[derive(Clone, Debug)]
pub struct PanelField {
    panels: Vec<Panel>,
    strengths: Vec<f64>,
    uniform: Vector,
    sink: Option<(Point, f64)>,
    /// The obstacles the panels cover, each with its range of panels (empty for a field
    /// built by [`PanelField::solve`]; [`PanelField::published`] fills it).
    pub(crate) bodies: Vec<crate::panel_published::Body>,
}

impl PanelField {
    /// Solves for the panel strengths: `Σ_j λ_j (v_j(c_i) · n_i) = V_i − (U + v_sink(c_i)) · n_i`
    /// at each midpoint `c_i`, where `v_j` is panel `j`'s unit-strength velocity (its own
    /// normal part at its midpoint is ½). `sink` is `(point, Q)`, adding `−Q/(2π)·r/|r|²`.
    ///
    /// Errors if the numbers of panels and velocities differ, a panel has zero length or a
    /// non-finite end, or the system is singular (overlapping panels).
    ///
    /// ```
    /// use harmonic_baselines::{Panel, PanelField};
    /// use harmonic_mesh::{Point, Vector};
    /// // An impermeable panel across a uniform stream: the flow stops just in front of it.
    /// let panel = Panel { start: Point::new(0.0, 0.5), end: Point::new(0.0, -0.5) };
    /// let field = PanelField::solve(vec![panel], &[0.0], Vector::new(1.0, 0.0), None).unwrap();
    /// assert!((field.strengths()[0] - 2.0).abs() < 1e-12);
    /// assert!(field.velocity(Point::new(-1e-9, 0.0)).x.abs() < 1e-6);
    /// ```
    pub fn solve(
        panels: Vec<Panel>,
        normal_velocities: &[f64],
        uniform: Vector,
        sink: Option<(Point, f64)>,
    ) -> Result<Self, BaselineError> {
        if panels.len() != normal_velocities.len() {
            return Err(BaselineError::InvalidParameter {
                name: "normal_velocities",
                value: normal_velocities.len() as f64,
                reason: "needs one desired normal velocity per panel",
            });
        }
        for (i, p) in panels.iter().enumerate() {
            check_point(|| format!("panel {i}"), p.start)?;
            check_point(|| format!("panel {i}"), p.end)?;
            if p.start == p.end {
                return Err(BaselineError::ZeroLengthPanel { panel: i });
            }
        }
        let mut field = PanelField {
            strengths: vec![0.0; panels.len()],
            panels,
            uniform,
            sink,
            bodies: Vec::new(),
        };
        let m = field.panels.len();
        let mut a = DMatrix::zeros(m, m);
        let mut rhs = DVector::zeros(m);
        for (i, pi) in field.panels.iter().enumerate() {
            let (c, n) = (pi.midpoint(), pi.normal());
            for (j, pj) in field.panels.iter().enumerate() {
                // A panel's own normal velocity at its midpoint, on its normal's side, is ½
                // (computed, z could round to either side of the cut).
                a[(i, j)] = if i == j {
                    0.5
                } else {
                    pj.unit_velocity(c).dot(&n)
                };
            }
            rhs[i] = normal_velocities[i] - field.background(c).dot(&n);
        }
        let lu = a.lu();
        let lambda = lu
            .solve(&rhs)
            .ok_or(BaselineError::SingularPanels { panels: m })?;
        if lambda.iter().any(|v| !v.is_finite()) {
            return Err(BaselineError::SingularPanels { panels: m });
        }
        field.strengths = lambda.iter().copied().collect();
        Ok(field)
    }

    /// The uniform stream plus the sink at `p`.
    fn background(&self, p: Point) -> Vector {
        let mut v = self.uniform;
        if let Some((g, q)) = self.sink {
            let r = p - g;
            v -= r * (q / (2.0 * PI * r.norm_squared()));
        }
        v
    }

    /// The uniform stream's velocity `U (cos α, sin α)`.
    pub fn uniform(&self) -> Vector {
        self.uniform
    }

    /// The goal sink `(point, Q)`, if any.
    pub fn sink(&self) -> Option<(Point, f64)> {
        self.sink
    }

    /// The panels.
    pub fn panels(&self) -> &[Panel] {
        &self.panels
    }

    /// The source strength per unit length of each panel.
    pub fn strengths(&self) -> &[f64] {
        &self.strengths
    }

    /// The velocity potential `Φ` at `p` (velocity = ∇Φ): uniform stream `U·p`, sink
    /// `−Q ln|p − g| / (2π)`, panels `Σ λ_j Φ_j(p)`.
    pub fn potential(&self, p: Point) -> f64 {
        let mut phi = self.uniform.dot(&p.coords);
        if let Some((g, q)) = self.sink {
            phi -= q / (2.0 * PI) * (p - g).norm().ln();
        }
        self.panels
            .iter()
            .zip(&self.strengths)
            .fold(phi, |acc, (panel, &s)| acc + panel.unit_potential(p) * s)
    }

    /// The flow velocity at `p` (off the panels).
    pub fn velocity(&self, p: Point) -> Vector {
        self.panels
            .iter()
            .zip(&self.strengths)
            .fold(self.background(p), |v, (panel, &s)| {
                v + panel.unit_velocity(p) * s
            })
    }
}

/// Settings of [`PanelPlanner`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelOptions {
    /// Speed `U` of the uniform stream, which flows from the start toward the goal.
    pub uniform_speed: f64,
    /// Strength `Q` of the goal sink (flux it swallows) when the walls carry no panels. With
    /// wall panels the workspace is closed and the sink must swallow exactly the flux the
    /// panels emit, `Σ V·L`, so this is ignored.
    pub sink_strength: f64,
    /// Desired outward normal velocity `V` at every panel midpoint (0: impermeable; larger
    /// values push the flow, and the robot, further off the obstacles).
    pub normal_velocity: f64,
    /// Also put panels on the workspace boundary (normals pointing inward).
    pub include_walls: bool,
    /// Edges longer than this are split into equal panels (the normal velocity is only
    /// enforced at panel midpoints, so long panels let the flow leak near corners).
    pub max_panel_length: f64,
    /// Length of each step along the flow direction.
    pub step: f64,
    /// The goal counts as reached within this distance.
    pub goal_tolerance: f64,
    /// Give up after this many steps.
    pub max_steps: usize,
    /// Stalled when the flow speed falls below this (a stagnation point).
    pub stall_speed: f64,
    /// Which panel method: ours with the workspace closed by wall panels, or Kim & Khosla's
    /// unbounded one with its checks.
    pub variant: PanelVariant,
}

/// Which panel method a [`PanelPlanner`] runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PanelVariant {
    /// Panels on the boundary of free space (walls too when `include_walls`), the sink
    /// swallowing what the panels emit: a flow that stays in the workspace.
    Bounded,
    /// Kim & Khosla as published (§§3–4, [`PanelField::published_with_remedy`]): the
    /// unbounded plane, no wall panels, one body per connected obstacle (the outer rings of
    /// the union of the obstacles), a goal sink of strength `sink_strength` (their `λ_g`),
    /// and, with a `remedy`, per query the stagnation-point search and the remedy that raises
    /// `V_i` of an obstacle with more than one (each round searches every obstacle's box, so
    /// it costs far more than the solve). `include_walls` is ignored.
    Published {
        /// The search's samples per side of each obstacle's box.
        search_samples: usize,
        /// The remedy's increase of `V_i` per round and its rounds; `None`: solve with the
        /// given `V_i` and search nothing.
        remedy: Option<crate::Remedy>,
    },
}

impl PanelVariant {
    /// The published variant with the default search and remedy.
    pub fn published() -> Self {
        PanelVariant::Published {
            search_samples: crate::StagnationSearch::default().samples,
            remedy: Some(crate::Remedy::default()),
        }
    }

    /// `"bounded"` or `"published"`.
    pub fn name(&self) -> &'static str {
        match self {
            PanelVariant::Bounded => "bounded",
            PanelVariant::Published { .. } => "published",
        }
    }
}

impl Default for PanelOptions {
    fn default() -> Self {
        PanelOptions {
            uniform_speed: 1.0,
            sink_strength: 10.0,
            normal_velocity: 0.5,
            include_walls: true,
            max_panel_length: 0.25,
            step: 0.02,
            goal_tolerance: 0.05,
            max_steps: 100_000,
            stall_speed: 1e-9,
            variant: PanelVariant::Bounded,
        }
    }
}

/// Kim & Khosla's planner: panels on the boundary of free space (the workspace minus the
/// union of the obstacles; without walls, the boundary of the union of the obstacles), a
/// sink at the goal and a uniform stream from the start toward the goal; the point robot
/// follows the flow. The strengths depend on the stream's direction, so they are solved per
/// query.
///
/// Panelling the union rather than each polygon matters where shapes touch: an obstacle
/// flush with a wall, or two obstacles sharing an edge, would otherwise put two panels on the
/// same segment with opposite normals, and two such panels induce the same velocity
/// everywhere off the segment, so the system for their strengths is singular.
#[derive(Clone, Debug)]
pub struct PanelPlanner {
    workspace: Vec<Point>,
    obstacles: Vec<Vec<Point>>,
    goal: Point,
    options: PanelOptions,
    /// The panels, normals pointing into free space (the bounded variant).
    panels: Vec<Panel>,
    /// The outer rings of the union of the obstacles (the published variant's bodies).
    bodies: Vec<Vec<Point>>,
}

fn to_geo(points: &[Point]) -> Polygon<f64> {
    let ring: Vec<Coord<f64>> = points.iter().map(|p| Coord { x: p.x, y: p.y }).collect();
    Polygon::new(LineString::from(ring), vec![])
}

/// A geo ring as points: the closing point dropped, and vertices within `eps` of the
/// previous kept one merged (the booleans can leave such slivers where shapes touch).
fn from_geo(ring: &LineString<f64>, eps: f64) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::with_capacity(ring.0.len());
    for c in &ring.0 {
        let p = Point::new(c.x, c.y);
        if out.last().is_none_or(|q| (p - q).norm() > eps) {
            out.push(p);
        }
    }
    while out.len() > 1 && (out[0] - out[out.len() - 1]).norm() <= eps {
        out.pop();
    }
    out
}

/// The panels on the boundary of free space, normals pointing into it: with walls, the
/// boundary of `workspace − ∪ obstacles`; without, the boundary of `∪ obstacles`. Each edge
/// is split into panels at most `max_len` long. Segments where shapes touch are inside the
/// union, so they carry no panel.
fn boundary_panels(
    workspace: &[Point],
    obstacles: &[Vec<Point>],
    include_walls: bool,
    max_len: f64,
) -> Vec<Panel> {
    let (lo, hi) = workspace
        .iter()
        .chain(obstacles.iter().flatten())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.x.min(p.y)), hi.max(p.x.max(p.y)))
        });
    let eps = 1e-12 * (hi - lo).max(1.0);
    let shapes: Vec<Polygon<f64>> = obstacles.iter().map(|o| to_geo(o)).collect();
    let union = unary_union(shapes.iter());
    // The region whose boundary is panelled, and whether free space is inside it.
    let (region, free_inside): (MultiPolygon<f64>, bool) = if include_walls {
        (
            MultiPolygon::new(vec![to_geo(workspace)]).difference(&union),
            true,
        )
    } else {
        (union, false)
    };
    let mut panels = Vec::new();
    for polygon in &region {
        // Exterior rings bound the region from outside, holes from inside.
        edge_panels(
            &from_geo(polygon.exterior(), eps),
            !free_inside,
            max_len,
            &mut panels,
        );
        for hole in polygon.interiors() {
            edge_panels(&from_geo(hole, eps), free_inside, max_len, &mut panels);
        }
    }
    panels
}

/// The outer rings of the union of the obstacles (clipped to the workspace), vertices
/// merged as in [`boundary_panels`].
fn union_rings(workspace: &[Point], obstacles: &[Vec<Point>]) -> Vec<Vec<Point>> {
    let (lo, hi) = workspace
        .iter()
        .chain(obstacles.iter().flatten())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.x.min(p.y)), hi.max(p.x.max(p.y)))
        });
    let eps = 1e-12 * (hi - lo).max(1.0);
    let shapes: Vec<Polygon<f64>> = obstacles.iter().map(|o| to_geo(o)).collect();
    unary_union(shapes.iter())
        .iter()
        .map(|p| from_geo(p.exterior(), eps))
        .filter(|r| r.len() >= 3)
        .collect()
}

/// Panels on the edges of `poly`, at most `max_len` long, with normals pointing out of it
/// (`outward`) or into it.
pub(crate) fn edge_panels(poly: &[Point], outward: bool, max_len: f64, panels: &mut Vec<Panel>) {
    let ccw = harmonic_mesh::geom::signed_area(poly) > 0.0;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        if a == b {
            continue;
        }
        let pieces = ((b - a).norm() / max_len).ceil().max(1.0) as usize;
        for m in 0..pieces {
            let p = a + (b - a) * (m as f64 / pieces as f64);
            let q = a + (b - a) * ((m + 1) as f64 / pieces as f64);
            // The right-hand normal of a counter-clockwise edge points out of the polygon.
            panels.push(if ccw == outward {
                Panel { start: p, end: q }
            } else {
                Panel { start: q, end: p }
            });
        }
    }
}

impl PanelPlanner {
    /// Builds the planner. Errors on polygons with fewer than three vertices, non-finite
    /// coordinates, or a non-positive step, tolerance or stall speed.
    ///
    /// ```
    /// use harmonic_baselines::{PanelOptions, PanelPlanner};
    /// use harmonic_mesh::Point;
    /// let ws = vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0), Point::new(10.0, 10.0), Point::new(0.0, 10.0)];
    /// let block = vec![Point::new(4.0, 4.0), Point::new(6.0, 4.0), Point::new(6.0, 6.0), Point::new(4.0, 6.0)];
    /// let planner = PanelPlanner::new(&ws, &[block], Point::new(9.0, 5.2), PanelOptions::default()).unwrap();
    /// let plan = planner.plan(Point::new(1.0, 5.0)).unwrap();
    /// assert!(plan.status.reached_goal());
    /// ```
    pub fn new(
        workspace: &[Point],
        obstacles: &[Vec<Point>],
        goal: Point,
        options: PanelOptions,
    ) -> Result<Self, BaselineError> {
        check_polygon(|| "workspace".to_string(), workspace)?;
        for (i, o) in obstacles.iter().enumerate() {
            check_polygon(|| format!("obstacle {i}"), o)?;
        }
        check_point(|| "goal".to_string(), goal)?;
        check_positive("step", options.step)?;
        check_positive("goal_tolerance", options.goal_tolerance)?;
        check_positive("stall_speed", options.stall_speed)?;
        check_positive("max_panel_length", options.max_panel_length)?;
        for (name, v) in [
            ("uniform_speed", options.uniform_speed),
            ("sink_strength", options.sink_strength),
            ("normal_velocity", options.normal_velocity),
        ] {
            if !v.is_finite() {
                return Err(BaselineError::NonFinite {
                    what: name.to_string(),
                    value: v,
                });
            }
        }
        let (panels, bodies) = match options.variant {
            PanelVariant::Bounded => (
                boundary_panels(
                    workspace,
                    obstacles,
                    options.include_walls,
                    options.max_panel_length,
                ),
                Vec::new(),
            ),
            PanelVariant::Published { search_samples, .. } => {
                if search_samples < 3 {
                    return Err(BaselineError::InvalidParameter {
                        name: "search_samples",
                        value: search_samples as f64,
                        reason: "the stagnation search needs at least 3 samples a side",
                    });
                }
                check_positive("sink_strength", options.sink_strength)?;
                (Vec::new(), union_rings(workspace, obstacles))
            }
        };
        Ok(PanelPlanner {
            workspace: workspace.to_vec(),
            obstacles: obstacles.to_vec(),
            goal,
            options,
            panels,
            bodies,
        })
    }

    /// The published variant's flow for a query from `start`, with the rounds of its remedy
    /// (`None` for the bounded variant and for the published one without a remedy).
    pub fn published(&self, start: Point) -> Result<Option<crate::Remedied>, BaselineError> {
        let PanelVariant::Published {
            search_samples,
            remedy,
        } = self.options.variant
        else {
            return Ok(None);
        };
        let o = &self.options;
        let setting = crate::PublishedSetting {
            uniform_speed: o.uniform_speed,
            goal_strength: o.sink_strength,
            normal_velocity: o.normal_velocity,
            max_panel_length: o.max_panel_length,
        };
        let search = crate::StagnationSearch {
            samples: search_samples,
            ..crate::StagnationSearch::default()
        };
        let Some(remedy) = remedy else {
            return Ok(None);
        };
        PanelField::published_with_remedy(
            &self.bodies,
            start,
            self.goal,
            &setting,
            &search,
            &remedy,
        )
        .map(Some)
    }

    /// The flow for a query from `start`: the stream runs from `start` toward the goal.
    pub fn field(&self, start: Point) -> Result<PanelField, BaselineError> {
        if let Some(remedied) = self.published(start)? {
            return Ok(remedied.field);
        }
        if let PanelVariant::Published { .. } = self.options.variant {
            let o = &self.options;
            let setting = crate::PublishedSetting {
                uniform_speed: o.uniform_speed,
                goal_strength: o.sink_strength,
                normal_velocity: o.normal_velocity,
                max_panel_length: o.max_panel_length,
            };
            return PanelField::published(&self.bodies, start, self.goal, &setting);
        }
        let panels = self.panels.clone();
        let sink = if self.options.include_walls {
            let perimeter: f64 = panels.iter().map(|p| (p.end - p.start).norm()).sum();
            perimeter * self.options.normal_velocity
        } else {
            self.options.sink_strength
        };
        let dir = self.goal - start;
        let uniform = if dir.norm() > 0.0 {
            dir.normalize() * self.options.uniform_speed
        } else {
            Vector::zeros()
        };
        let velocities = vec![self.options.normal_velocity; panels.len()];
        PanelField::solve(panels, &velocities, uniform, Some((self.goal, sink)))
    }

    fn is_free(&self, p: Point) -> bool {
        polygon_contains(&self.workspace, p)
            && !self.obstacles.iter().any(|o| polygon_contains(o, p))
    }

    /// The flow for a query from `start` as a [`Field`] the shared tracer and car stepper can
    /// follow (its value is `−Φ`, decreasing along the flow toward the goal).
    pub fn flow(&self, start: Point) -> Result<PanelFlow<'_>, BaselineError> {
        Ok(PanelFlow {
            planner: self,
            field: self.field(start)?,
        })
    }

    /// Follows the flow from `start` in fixed-length steps along the velocity direction.
    /// Errors only if the panel system is singular.
    pub fn plan(&self, start: Point) -> Result<PlanResult, BaselineError> {
        if !self.is_free(start) {
            return Ok(self.follow(None, start));
        }
        let field = self.field(start)?;
        Ok(self.follow(Some(&field), start))
    }

    /// Follows `field` (any flow over this planner's scene, such as one round of the
    /// published variant's remedy) from `start` with the planner's steps and stops. The start
    /// is checked first: outside the workspace or in an obstacle the path is just the start.
    pub fn follow_field(&self, field: &PanelField, start: Point) -> PlanResult {
        self.follow(Some(field), start)
    }

    fn follow(&self, field: Option<&PanelField>, start: Point) -> PlanResult {
        let clock = Instant::now();
        let o = &self.options;
        let mut points = vec![start];
        let status = if !polygon_contains(&self.workspace, start) {
            TraceStatus::OutsideWorkspace
        } else if !self.is_free(start) {
            TraceStatus::StartInObstacle
        } else if let Some(field) = field {
            let mut q = start;
            let mut status = TraceStatus::MaxSteps;
            for _ in 0..o.max_steps {
                if (q - self.goal).norm() < o.goal_tolerance {
                    status = TraceStatus::ReachedGoal(0);
                    break;
                }
                let v = field.velocity(q);
                if v.norm() < o.stall_speed || !v.norm().is_finite() {
                    status = TraceStatus::Stalled { at: q };
                    break;
                }
                let h = o.step.min((q - self.goal).norm());
                let next = q + v.normalize() * h;
                if !self.is_free(next) {
                    status = TraceStatus::Collision {
                        at: Some([q.x, q.y, v.y.atan2(v.x)]),
                    };
                    break;
                }
                q = next;
                points.push(q);
            }
            status
        } else {
            TraceStatus::StartInObstacle
        };
        PlanResult::new(points, status, clock.elapsed())
    }
}

/// A panel flow over a planner's scene, as a [`Field`]: free space is the workspace minus the
/// obstacles, the goal the disc of radius `goal_tolerance` around the goal point, the value
/// `−Φ` and the gradient `−velocity`. Its only cell is `()`.
#[derive(Clone, Debug)]
pub struct PanelFlow<'a> {
    planner: &'a PanelPlanner,
    field: PanelField,
}

impl PanelFlow<'_> {
    /// The underlying flow.
    pub fn field(&self) -> &PanelField {
        &self.field
    }
}

impl Field for PanelFlow<'_> {
    type Point = Point;
    type Vector = Vector;
    type Cell = ();

    fn locate(&self, p: Point, _hint: Option<()>) -> Locate<()> {
        let pl = self.planner;
        if !polygon_contains(&pl.workspace, p) {
            Locate::OutsideWorkspace
        } else if pl.obstacles.iter().any(|o| polygon_contains(o, p)) {
            Locate::InObstacle
        } else if (p - pl.goal).norm() < pl.options.goal_tolerance {
            Locate::Goal(0)
        } else {
            Locate::Inside(())
        }
    }

    fn value(&self, _cell: (), p: Point) -> f64 {
        -self.field.potential(p)
    }

    fn gradient(&self, _cell: (), p: Point) -> Vector {
        -self.field.velocity(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the flow on the x-axis in front of a single panel of length `len` on the y-axis
    /// (normal facing −x, into a unit stream in +x) comes to rest, found by bisection.
    fn stagnation(len: f64, vn: f64) -> f64 {
        let panel = Panel {
            start: Point::new(0.0, len / 2.0),
            end: Point::new(0.0, -len / 2.0),
        };
        let field = PanelField::solve(vec![panel], &[vn], Vector::new(1.0, 0.0), None).unwrap();
        // λ/2 − U = V at the midpoint.
        assert!((field.strengths()[0] - 2.0 * (1.0 + vn)).abs() < 1e-12);
        let u = |x: f64| field.velocity(Point::new(x, 0.0)).x;
        let (mut lo, mut hi) = (-100.0, -1e-12);
        assert!(u(lo) > 0.0);
        if u(hi) >= 0.0 {
            return hi;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if u(mid) > 0.0 { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    }

    #[test]
    fn single_panel_stagnation_points() {
        // On the axis u(x) = U + (λ/π) arctan(L/(2x)) and λ = 2(U + V), so the flow stops at
        // x* = −(L/2) cot(π / (2(1 + V/U))): 0⁻, −L/2, −(√3/2)L for V = 0, 1, 2. The quoted
        // values 0⁻, −1, −√3 are these for L = 2 (a half-length of 1).
        let sqrt3 = 3f64.sqrt();
        for (len, expected) in [(2.0, [0.0, -1.0, -sqrt3]), (1.0, [0.0, -0.5, -sqrt3 / 2.0])] {
            for (vn, x) in expected.iter().enumerate() {
                let got = stagnation(len, vn as f64);
                let closed = -(len / 2.0) / (PI / (2.0 * (1.0 + vn as f64))).tan();
                assert!((got - x).abs() < 1e-6, "L = {len}, V = {vn}: {got} vs {x}");
                assert!((closed - x).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn impermeable_panels_have_zero_normal_flow_at_every_midpoint() {
        // A square obstacle in a diagonal stream.
        let sq = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let mut panels = Vec::new();
        edge_panels(&sq, true, 2.0, &mut panels);
        let field = PanelField::solve(
            panels,
            &[0.0; 4],
            Vector::new(1.0, 0.5),
            Some((Point::new(5.0, 5.0), 2.0)),
        )
        .unwrap();
        for p in field.panels() {
            // Just outside the midpoint, the normal velocity tends to 0.
            let c = p.midpoint() + p.normal() * 1e-9;
            assert!(field.velocity(c).dot(&p.normal()).abs() < 1e-6);
        }
        // Outward normals of the counter-clockwise square.
        assert_eq!(field.panels()[0].normal(), Vector::new(0.0, -1.0));
    }

    #[test]
    fn plans_around_a_block_without_collision() {
        let ws = vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let block = vec![
            Point::new(4.0, 3.0),
            Point::new(6.0, 3.0),
            Point::new(6.0, 6.5),
            Point::new(4.0, 6.5),
        ];
        let planner =
            PanelPlanner::new(&ws, &[block], Point::new(9.0, 5.0), PanelOptions::default())
                .unwrap();
        for start in [
            Point::new(1.0, 5.0),
            Point::new(1.0, 8.0),
            Point::new(2.0, 1.0),
        ] {
            let plan = planner.plan(start).unwrap();
            assert!(
                plan.status.reached_goal(),
                "from {start}: {:?}",
                plan.status
            );
            assert!(plan.points.iter().all(|&p| planner.is_free(p)));
        }
        assert_eq!(
            planner.plan(Point::new(5.0, 5.0)).unwrap().status,
            TraceStatus::StartInObstacle
        );
    }

    #[test]
    fn the_shared_tracer_follows_the_panel_flow() {
        use harmonic_trajectory::{SmoothOptions, trace_smooth};
        let ws = vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let block = vec![
            Point::new(4.0, 3.0),
            Point::new(6.0, 3.0),
            Point::new(6.0, 6.5),
            Point::new(4.0, 6.5),
        ];
        let planner =
            PanelPlanner::new(&ws, &[block], Point::new(9.0, 5.0), PanelOptions::default())
                .unwrap();
        let start = Point::new(1.0, 5.0);
        let flow = planner.flow(start).unwrap();
        // ∇(−Φ) = −velocity, checked against finite differences of the potential.
        for p in [
            Point::new(2.0, 2.0),
            Point::new(7.0, 8.0),
            Point::new(3.5, 5.0),
        ] {
            let h = 1e-6;
            let fd = Vector::new(
                flow.value((), p + Vector::x() * h) - flow.value((), p - Vector::x() * h),
                flow.value((), p + Vector::y() * h) - flow.value((), p - Vector::y() * h),
            ) / (2.0 * h);
            let g = flow.gradient((), p);
            assert!(
                (g - fd).norm() < 1e-5 * (1.0 + g.norm()),
                "at {p}: {g} vs {fd}"
            );
        }
        let path = trace_smooth(&flow, start, &SmoothOptions::for_scale(10.0)).unwrap();
        assert_eq!(path.status, TraceStatus::ReachedGoal(0));
        assert!(path.points.iter().all(|&p| planner.is_free(p)));
    }

    #[test]
    fn obstacles_flush_with_a_wall_or_each_other_get_no_panel_where_they_touch() {
        // A 10 × 10 room with a shelf flush with its left wall and a second block sharing the
        // shelf's right edge.
        let ws = vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let shelf = vec![
            Point::new(0.0, 4.0),
            Point::new(3.0, 4.0),
            Point::new(3.0, 6.0),
            Point::new(0.0, 6.0),
        ];
        let block = vec![
            Point::new(3.0, 4.5),
            Point::new(4.0, 4.5),
            Point::new(4.0, 5.5),
            Point::new(3.0, 5.5),
        ];
        let obstacles = [shelf, block];
        let opts = PanelOptions::default();
        // Panelled polygon by polygon, the shared segments carry two coinciding panels with
        // opposite normals: the system is singular.
        let mut naive = Vec::new();
        for o in &obstacles {
            edge_panels(o, true, opts.max_panel_length, &mut naive);
        }
        edge_panels(&ws, false, opts.max_panel_length, &mut naive);
        let m = naive.len();
        assert_eq!(
            PanelField::solve(
                naive,
                &vec![0.5; m],
                Vector::x(),
                Some((Point::new(9.0, 5.0), 1.0))
            )
            .unwrap_err(),
            BaselineError::SingularPanels { panels: m }
        );
        let planner = PanelPlanner::new(&ws, &obstacles, Point::new(9.0, 5.0), opts).unwrap();
        // The boundary of free space: the room's 40 minus the wall between y = 4 and 6, the
        // shelf's top, bottom and the uncovered parts of its right edge, the block's three
        // free sides.
        let total: f64 = planner
            .panels
            .iter()
            .map(|p| (p.end - p.start).norm())
            .sum();
        assert!((total - (40.0 - 2.0 + 3.0 + 3.0 + 1.0 + 1.0 + 1.0 + 1.0)).abs() < 1e-9);
        for p in &planner.panels {
            // Every normal points into free space, and no panel lies on a touching segment.
            let c = p.midpoint();
            assert!(planner.is_free(c + p.normal() * 1e-6), "panel at {c}");
            assert!(!planner.is_free(c - p.normal() * 1e-6), "panel at {c}");
        }
        for start in [
            Point::new(1.0, 8.0),
            Point::new(1.0, 2.0),
            Point::new(5.0, 9.0),
        ] {
            let plan = planner.plan(start).unwrap();
            assert!(
                plan.status.reached_goal(),
                "from {start}: {:?}",
                plan.status
            );
            assert!(plan.points.iter().all(|&p| planner.is_free(p)));
        }
        // Without wall panels: the boundary of the union of the obstacles, 10 + 4 minus the
        // shared unit segment counted on both.
        let open = PanelOptions {
            include_walls: false,
            ..opts
        };
        let planner = PanelPlanner::new(&ws, &obstacles, Point::new(9.0, 5.0), open).unwrap();
        let total: f64 = planner
            .panels
            .iter()
            .map(|p| (p.end - p.start).norm())
            .sum();
        assert!((total - 12.0).abs() < 1e-9, "{total}");
        let in_obstacle = |q: Point| obstacles.iter().any(|o| polygon_contains(o, q));
        for p in &planner.panels {
            let c = p.midpoint();
            assert!(!in_obstacle(c + p.normal() * 1e-6), "panel at {c}");
            assert!(in_obstacle(c - p.normal() * 1e-6), "panel at {c}");
        }
        assert!(
            planner
                .plan(Point::new(1.0, 8.0))
                .unwrap()
                .status
                .reached_goal()
        );
    }

    #[test]
    fn rejects_degenerate_panels() {
        let p = Panel {
            start: Point::new(1.0, 1.0),
            end: Point::new(1.0, 1.0),
        };
        assert_eq!(
            PanelField::solve(vec![p], &[0.0], Vector::zeros(), None).unwrap_err(),
            BaselineError::ZeroLengthPanel { panel: 0 }
        );
        assert!(PanelField::solve(vec![], &[0.0], Vector::zeros(), None).is_err());
        let q = Panel {
            start: Point::new(0.0, 0.0),
            end: Point::new(1.0, 0.0),
        };
        assert_eq!(
            PanelField::solve(vec![q, q], &[0.0, 0.0], Vector::x(), None).unwrap_err(),
            BaselineError::SingularPanels { panels: 2 }
        );
    }
}
