//! The planners' descent policy: the smooth tracer first, the exact tracer where the smooth
//! one stalls or runs out of steps.

use harmonic_types::Point;
use serde::Serialize;

use crate::{
    ExactOptions, Path, SmoothOptions, SmoothP1Field, TraceStatus, trace_exact_with_hint,
    trace_smooth_with_hint,
};

/// Which tracer made a path (serialised as `"smooth"`, `"exact"` or `"straight"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Tracer {
    /// The smooth Dormand–Prince tracer on recovered gradients.
    Smooth,
    /// The exact triangle-to-triangle tracer (φ strictly decreasing along it).
    Exact,
    /// No tracer: the start was already in a cell touching the goal, one straight step away.
    Straight,
}

impl Tracer {
    /// The contract's word for the tracer.
    pub fn as_str(self) -> &'static str {
        match self {
            Tracer::Smooth => "smooth",
            Tracer::Exact => "exact",
            Tracer::Straight => "straight",
        }
    }
}

impl std::fmt::Display for Tracer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Follows `field` downhill from `start`: the smooth tracer's path unless it stalled, ran
/// out of steps or refused its options, else the exact tracer's (which cannot stall in a
/// flat spot the smooth one misjudged). `hint` is a triangle that probably holds `start`.
///
/// ```
/// use harmonic_fem::solve_potential;
/// # use harmonic_fem::BoundaryConditions;
/// # use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Point};
/// use harmonic_trajectory::{ExactOptions, SmoothOptions, SmoothP1Field, Tracer, descend};
/// # let square = vec![Point::new(0.0, 0.0), Point::new(4.0, 0.0), Point::new(4.0, 4.0), Point::new(0.0, 4.0)];
/// # let spec = DomainSpec { workspace: square, obstacles: vec![],
/// #     goals: vec![GoalShape::Circle { center: Point::new(3.5, 3.5), radius: 0.2 }], robot_radius: 0.0 };
/// # let options = MeshOptions { max_area: Some(0.05), ..MeshOptions::default() };
/// # let (mesh, _) = Domain::new(&spec, &options)?.mesh(&options)?;
/// # let mesh = std::sync::Arc::new(mesh);
/// let potential = solve_potential(mesh.clone(), &BoundaryConditions::default())?;
/// let field = SmoothP1Field::ascending(&mesh, potential.psi(), potential.nodal_gradients_psi())?;
/// let opts = SmoothOptions::for_scale(4.0);
/// let (path, tracer) = descend(&field, Point::new(0.5, 0.5), None, &opts, &ExactOptions::default());
/// assert!(path.status.reached_goal());
/// assert_eq!(tracer, Tracer::Smooth);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn descend(
    field: &SmoothP1Field<'_>,
    start: Point,
    hint: Option<u32>,
    smooth: &SmoothOptions,
    exact: &ExactOptions,
) -> (Path, Tracer) {
    match trace_smooth_with_hint(field, start, hint, smooth) {
        Ok(path) if !exact_might_help(&path.status) => (path, Tracer::Smooth),
        _ => (
            trace_exact_with_hint(field.p1(), start, hint, exact),
            Tracer::Exact,
        ),
    }
}

/// Whether the exact tracer may do better than a smooth path that ended so.
fn exact_might_help(status: &TraceStatus) -> bool {
    matches!(status, TraceStatus::Stalled { .. } | TraceStatus::MaxSteps)
}
