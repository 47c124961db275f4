//! Boundary conditions of a volume scene description ([`harmonic_volume::VolumeSceneSpec`]).

use harmonic_volume::{ConditionSpec, VolumeSceneSpec};

use crate::bc::{BoundaryCondition, BoundaryConditions};

/// The condition a [`ConditionSpec`] describes.
pub fn condition(spec: ConditionSpec) -> BoundaryCondition {
    match spec {
        ConditionSpec::Dirichlet(v) => BoundaryCondition::Dirichlet(v),
        ConditionSpec::Neumann(g) => BoundaryCondition::Neumann(g),
        ConditionSpec::Robin { a, b, g } => BoundaryCondition::Robin { a, b, g },
    }
}

/// The scene's boundary conditions: `boundary.walls`, `boundary.obstacles` and
/// `boundary.goal` (defaults Dirichlet 1, 1, 0) with the per-obstacle and per-goal overrides.
///
/// ```
/// use harmonic_fem::BoundaryCondition;
/// use harmonic_fem::volume::scene_conditions;
/// use harmonic_volume::VolumeSceneSpec;
/// let spec: VolumeSceneSpec = serde_json::from_str(r#"{"dimension": 3,
///     "workspace": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}},
///     "obstacles": [{"sphere": {"center": [0.5, 0.5, 0.5], "radius": 0.2}, "boundary": {"neumann": 0.0}}],
///     "goal": {"point": [0.1, 0.1, 0.1]},
///     "boundary": {"walls": {"robin": {"a": 1.0, "b": 2.0, "g": 2.0}}}}"#)?;
/// let bcs = scene_conditions(&spec);
/// assert_eq!(bcs.walls, BoundaryCondition::Robin { a: 1.0, b: 2.0, g: 2.0 });
/// assert_eq!(bcs.obstacle_overrides[&0], BoundaryCondition::Neumann(0.0));
/// assert_eq!(bcs.goals, BoundaryCondition::Dirichlet(0.0));
/// # Ok::<(), serde_json::Error>(())
/// ```
pub fn scene_conditions(spec: &VolumeSceneSpec) -> BoundaryConditions {
    let mut bcs = BoundaryConditions::default();
    if let Some(c) = spec.boundary.walls {
        bcs.walls = condition(c);
    }
    if let Some(c) = spec.boundary.obstacles {
        bcs.obstacles = condition(c);
    }
    if let Some(c) = spec.boundary.goal {
        bcs.goals = condition(c);
    }
    for (i, o) in spec.obstacles.iter().enumerate() {
        if let Some(c) = o.boundary {
            bcs.obstacle_overrides.insert(i as u32, condition(c));
        }
    }
    for (j, g) in spec.goal.regions().iter().enumerate() {
        if let Some(c) = g.boundary {
            bcs.goal_overrides.insert(j as u32, condition(c));
        }
    }
    bcs
}
