//! Queries: a start led onto the mesh (by a map's entry where it lies beside it), traced
//! down the field (`descend`: smooth, then exact where it stalls), ended on the goal and
//! measured; the car-like robot.

use super::*;

/// The smallest clearance of a path to be reported: measured along it, or known to be 0
/// (a path led in from outside the mesh, whose lead-in counts as clearance 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Clearance {
    Measure,
    Zero,
}

impl Planner {
    /// The potential as a smooth field (recovered gradients); its inputs were checked by
    /// [`Planner::with_options`].
    fn smooth_field(&self) -> SmoothP1Field<'_> {
        let field = smooth_field_of(&self.mesh, &self.potential, &self.nodal_gradients)
            .expect("one finite ψ and gradient per vertex, checked when the planner was built");
        match &self.vertex_goals {
            Some(goals) => field
                .with_goal_vertices(&goals.goal_of)
                .expect("one goal mark per vertex, made with the planner"),
            None => field,
        }
    }

    /// Plans a path from `start` to the goal by following the potential: the smooth tracer
    /// first; where it stalls or runs out of steps, the exact triangle-to-triangle tracer,
    /// along which φ strictly decreases.
    /// `start` is a [`Point`] or the scene format's `[x, y]`.
    pub fn plan(&self, start: impl Into<Point>) -> PlannedPath {
        self.entered(start.into(), |start, clearance| {
            let field = self.smooth_field();
            let (path, tracer) =
                descend(&field, start, None, &self.smooth, &ExactOptions::default());
            self.planned(start, path, tracer, clearance)
        })
    }

    /// The exact tracer's path from `start` (straight within each triangle, φ strictly
    /// decreasing along it).
    pub fn plan_exact(&self, start: impl Into<Point>) -> PlannedPath {
        self.entered(start.into(), |start, clearance| {
            let path = trace_exact(self.smooth_field().p1(), start, &ExactOptions::default());
            self.planned(start, path, Tracer::Exact, clearance)
        })
    }

    /// `plan(start)`, or, for a start outside the mesh that the planner's [`StartEntry`]
    /// leads in, that lead-in followed by `plan` from its last point. The lead-in keeps the
    /// robot radius but lies outside the meshed free space, so it counts as clearance 0
    /// (`plan` is told so, with [`Clearance::Zero`], and need not measure it).
    fn entered(&self, start: Point, plan: impl Fn(Point, Clearance) -> PlannedPath) -> PlannedPath {
        let Some(entry) = &self.entry else {
            return plan(start, Clearance::Measure);
        };
        if let Some([from, to]) = entry.direct(start) {
            return self.unplanned(start, TraceStatus::ReachedGoal(0), vec![from, to]);
        }
        if self.mesh.locate(start, None).is_some() {
            return plan(start, Clearance::Measure);
        }
        let lead = entry.lead_in(start, &|p| self.mesh.locate(p, None).is_some());
        let Some(lead) = lead.filter(|l| l.len() >= 2) else {
            return self.unplanned(start, entry.refusal(start), vec![start]);
        };
        let inside = lead[lead.len() - 1];
        if entry.goal_point(0) == Some(inside) {
            // The walk over clear cells reached the goal itself.
            return self.unplanned(start, TraceStatus::ReachedGoal(0), lead);
        }
        let mut path = plan(inside, Clearance::Zero);
        let lead_length: f64 = lead.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        path.start = [start.x, start.y];
        path.length += lead_length;
        let mut points: Vec<[f64; 2]> = lead[..lead.len() - 1].iter().map(|p| [p.x, p.y]).collect();
        points.append(&mut path.points);
        path.points = points;
        path
    }

    /// A path that needed no tracer: `points` straight, or a start with no path (`status`
    /// says why, `points` holds the start alone).
    fn unplanned(&self, start: Point, status: TraceStatus, points: Vec<Point>) -> PlannedPath {
        let min_clearance = match status {
            TraceStatus::ReachedGoal(_) => self.domain.polyline_clearance(&points),
            _ => 0.0,
        };
        PlannedPath {
            start: [start.x, start.y],
            status,
            goal: match status {
                TraceStatus::ReachedGoal(j) => Some(j),
                _ => None,
            },
            blocked_by: None,
            tracer: Tracer::Straight,
            // (+0, not the −0 an empty sum gives, for a start alone.)
            length: polyline_length(&points).max(0.0),
            min_clearance: finite_or_zero(min_clearance),
            min_gradient: 0.0,
            points: points.iter().map(|p| [p.x, p.y]).collect(),
        }
    }

    /// Plans from every start (points or `[x, y]` arrays), in parallel.
    pub fn plan_many<P: Copy + Into<Point> + Sync>(&self, starts: &[P]) -> Vec<PlannedPath> {
        crate::threads::install(self.pool.as_deref(), || {
            starts.par_iter().map(|&s| self.plan(s)).collect()
        })
    }

    fn planned(
        &self,
        start: Point,
        mut path: Path,
        tracer: Tracer,
        clearance: Clearance,
    ) -> PlannedPath {
        if let (TraceStatus::ReachedGoal(j), Some(goals)) = (path.status, &self.vertex_goals) {
            self.finish_at_vertex_goal(&mut path.points, j, goals);
        }
        let min_clearance = match clearance {
            Clearance::Measure => self.domain.polyline_clearance(&path.points),
            Clearance::Zero => 0.0,
        };
        // The last step, inside the goal's boundary, to the goal's point (its clearance is
        // the goal's own, not measured against the goal's boundary).
        if let (TraceStatus::ReachedGoal(j), Some(entry)) = (path.status, &self.entry)
            && let Some(end) = entry.goal_point(j)
            && path.points.last() != Some(&end)
        {
            path.points.push(end);
        }
        PlannedPath {
            start: [start.x, start.y],
            status: path.status,
            goal: path.goal,
            blocked_by: None,
            tracer,
            length: polyline_length(&path.points),
            min_clearance: finite_or_zero(min_clearance),
            min_gradient: finite_or_zero(path.min_gradient),
            points: path.points.iter().map(|p| [p.x, p.y]).collect(),
        }
    }

    /// A path that entered a triangle of vertex goal `j` goes on, straight within that
    /// triangle, to the goal's nearest held vertex there, and from it to the goal's point when
    /// that lies in a triangle of the vertex; each segment is checked clear of the exact
    /// geometry before it is added.
    fn finish_at_vertex_goal(&self, points: &mut Vec<Point>, j: u32, goals: &VertexGoals) {
        let Some(&last) = points.last() else {
            return;
        };
        let mesh = &self.mesh;
        let Some(t) = mesh.locate(last, None) else {
            return;
        };
        let around = std::iter::once(t).chain(
            mesh.neighbors()[t as usize]
                .into_iter()
                .filter(|&n| n != harmonic_mesh::NO_NEIGHBOR),
        );
        let nearest = around
            .flat_map(|u| mesh.triangles()[u as usize])
            .filter(|&v| goals.goal_of[v as usize] == j)
            .map(|v| (v, (mesh.vertices()[v as usize] - last).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((v, _)) = nearest else {
            return;
        };
        let at = mesh.vertices()[v as usize];
        if self.domain.segment_clearance(last, at) <= 0.0 {
            return;
        }
        if at != last {
            points.push(at);
        }
        if let Some(end) = goals.ends.get(j as usize).copied().flatten()
            && end != at
            && mesh
                .locate(end, None)
                .is_some_and(|u| mesh.triangles()[u as usize].contains(&v))
            && self.domain.segment_clearance(at, end) > 0.0
        {
            points.push(end);
        }
    }

    /// Drives a car-like robot from `pose` (rear-axle midpoint, heading) along the potential.
    pub fn car(&self, pose: [f64; 3], params: &CarParams) -> Result<CarRun, PlanError> {
        let field = self.smooth_field();
        let opts = params.options();
        let collides = |corners: &[Point; 4]| {
            (0..4).any(|k| {
                self.domain
                    .segment_clearance(corners[k], corners[(k + 1) % 4])
                    <= 0.0
            })
        };
        let collision = Collision {
            footprint: Footprint {
                rear: 0.2 * params.wheelbase * 1.25,
                front: 0.8 * params.wheelbase * 1.25,
                half_width: 0.3 * params.wheelbase,
            },
            collides: &collides,
        };
        let car: CarPath = drive(
            &field,
            pose,
            &opts,
            params.check_footprint.then_some(&collision),
        )?;
        let points: Vec<Point> = car.poses.iter().map(|q| Point::new(q[0], q[1])).collect();
        let min_clearance = self.domain.polyline_clearance(&points);
        Ok(CarRun {
            start: pose,
            status: car.status,
            goal: car.goal,
            length: car.length,
            min_clearance: finite_or_zero(min_clearance),
            min_gradient: finite_or_zero(car.min_gradient),
            max_curvature: car.max_curvature,
            poses: car.poses,
        })
    }
}
