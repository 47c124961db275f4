//! Boundary conditions per boundary part and their validation.

use std::collections::BTreeMap;

use harmonic_types::BoundaryTag;

use crate::FemError;

/// The condition imposed on one boundary part, with `n` the outward normal of free space
/// (pointing into the wall, obstacle or goal).
///
/// In a scene file: `{"dirichlet": v}`, `{"neumann": g}` or `{"robin": {"a": a, "b": b, "g": g}}`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum BoundaryCondition {
    /// φ = value.
    Dirichlet(f64),
    /// ∂φ/∂n = g.
    Neumann(f64),
    /// a·∂φ/∂n + b·φ = g. With `a = 0` this is the Dirichlet condition φ = g/b; with `b = 0`
    /// it is the Neumann condition ∂φ/∂n = g/a.
    Robin {
        /// Coefficient of the normal derivative.
        a: f64,
        /// Coefficient of the value.
        b: f64,
        /// Right-hand side.
        g: f64,
    },
}

/// Whether a boundary part fixes the values of its vertices (Dirichlet, or Robin with `a = 0`)
/// or enters the weak form (Neumann, Robin).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ConditionKind {
    /// Values are prescribed: the part's vertices are not unknowns.
    Essential,
    /// Flux or Robin data: the part's vertices stay unknowns.
    Natural,
}

impl BoundaryCondition {
    /// Whether the condition prescribes values (`Essential`) or fluxes (`Natural`).
    pub fn kind(&self) -> ConditionKind {
        match *self {
            BoundaryCondition::Dirichlet(_) => ConditionKind::Essential,
            BoundaryCondition::Robin { a: 0.0, .. } => ConditionKind::Essential,
            _ => ConditionKind::Natural,
        }
    }

    /// Checks that the numbers are finite, that `a` and `b` are not both zero and that
    /// `b/a ≥ 0` (a negative Robin coefficient makes the problem indefinite). `part` names the
    /// boundary part in the error.
    pub fn validate(&self, part: &str) -> Result<(), FemError> {
        let bad = |what: &str, value: f64| FemError::NonFinite {
            part: part.to_string(),
            what: what.to_string(),
            value,
        };
        match *self {
            BoundaryCondition::Dirichlet(v) if !v.is_finite() => Err(bad("Dirichlet value", v)),
            BoundaryCondition::Neumann(g) if !g.is_finite() => Err(bad("Neumann flux g", g)),
            BoundaryCondition::Robin { a, b, g } => {
                for (what, value) in [("Robin a", a), ("Robin b", b), ("Robin g", g)] {
                    if !value.is_finite() {
                        return Err(bad(what, value));
                    }
                }
                if a == 0.0 && b == 0.0 {
                    return Err(FemError::RobinBothZero {
                        part: part.to_string(),
                    });
                }
                if a != 0.0 && b / a < 0.0 {
                    return Err(FemError::NegativeRobin {
                        part: part.to_string(),
                        ratio: b / a,
                    });
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

/// Boundary conditions for every part of a mesh's boundary: the outer walls, the obstacles
/// (a default and per-obstacle overrides by input index) and the goals (likewise).
///
/// Defaults: walls and obstacles `Dirichlet(1)`, goals `Dirichlet(0)`.
///
/// ```
/// use harmonic_fem::{BoundaryCondition, BoundaryConditions};
/// use harmonic_mesh::BoundaryTag;
///
/// let mut bcs = BoundaryConditions::default();
/// bcs.obstacle_overrides.insert(2, BoundaryCondition::Neumann(0.0));
/// assert_eq!(bcs.for_tag(BoundaryTag::Obstacle(2)), BoundaryCondition::Neumann(0.0));
/// assert_eq!(bcs.for_tag(BoundaryTag::Obstacle(0)), BoundaryCondition::Dirichlet(1.0));
/// assert_eq!(bcs.for_tag(BoundaryTag::Goal(0)), BoundaryCondition::Dirichlet(0.0));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryConditions {
    /// The outer boundary of the workspace.
    pub walls: BoundaryCondition,
    /// Every obstacle without an override.
    pub obstacles: BoundaryCondition,
    /// Per-obstacle conditions, keyed by the obstacle's input index.
    pub obstacle_overrides: BTreeMap<u32, BoundaryCondition>,
    /// Every goal without an override.
    pub goals: BoundaryCondition,
    /// Per-goal conditions, keyed by the goal's input index.
    pub goal_overrides: BTreeMap<u32, BoundaryCondition>,
}

impl Default for BoundaryConditions {
    fn default() -> Self {
        BoundaryConditions {
            walls: BoundaryCondition::Dirichlet(1.0),
            obstacles: BoundaryCondition::Dirichlet(1.0),
            obstacle_overrides: BTreeMap::new(),
            goals: BoundaryCondition::Dirichlet(0.0),
            goal_overrides: BTreeMap::new(),
        }
    }
}

impl BoundaryConditions {
    /// The same condition on the walls and on every obstacle (overrides are cleared), the goals
    /// held at `Dirichlet(0)`: e.g. `uniform(BoundaryCondition::Robin { a: 1.0, b: 1.0, g: 1.0 })`.
    pub fn uniform(walls_and_obstacles: BoundaryCondition) -> Self {
        BoundaryConditions {
            walls: walls_and_obstacles,
            obstacles: walls_and_obstacles,
            ..BoundaryConditions::default()
        }
    }

    /// The condition on the boundary part `tag`.
    pub fn for_tag(&self, tag: BoundaryTag) -> BoundaryCondition {
        match tag {
            BoundaryTag::Wall => self.walls,
            BoundaryTag::Obstacle(i) => *self.obstacle_overrides.get(&i).unwrap_or(&self.obstacles),
            BoundaryTag::Goal(j) => *self.goal_overrides.get(&j).unwrap_or(&self.goals),
        }
    }

    /// Validates every condition (see [`BoundaryCondition::validate`]), naming the part.
    pub fn validate(&self) -> Result<(), FemError> {
        self.walls.validate("walls")?;
        self.obstacles.validate("obstacles (default)")?;
        for (i, bc) in &self.obstacle_overrides {
            bc.validate(&format!("obstacle {i}"))?;
        }
        self.goals.validate("goals (default)")?;
        for (j, bc) in &self.goal_overrides {
            bc.validate(&format!("goal {j}"))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds() {
        assert_eq!(
            BoundaryCondition::Dirichlet(1.0).kind(),
            ConditionKind::Essential
        );
        assert_eq!(
            BoundaryCondition::Robin {
                a: 0.0,
                b: 2.0,
                g: 1.0
            }
            .kind(),
            ConditionKind::Essential
        );
        assert_eq!(
            BoundaryCondition::Robin {
                a: 1.0,
                b: 0.0,
                g: 1.0
            }
            .kind(),
            ConditionKind::Natural
        );
        assert_eq!(
            BoundaryCondition::Neumann(0.0).kind(),
            ConditionKind::Natural
        );
    }

    #[test]
    fn validation_names_the_part() {
        let mut bcs = BoundaryConditions::default();
        bcs.obstacle_overrides.insert(
            3,
            BoundaryCondition::Robin {
                a: 0.0,
                b: 0.0,
                g: 1.0,
            },
        );
        let e = bcs.validate().unwrap_err();
        assert!(matches!(e, FemError::RobinBothZero { ref part } if part == "obstacle 3"));
        bcs.obstacle_overrides.clear();
        bcs.walls = BoundaryCondition::Dirichlet(f64::NAN);
        let e = bcs.validate().unwrap_err();
        assert!(e.to_string().contains("walls"), "{e}");
        bcs.walls = BoundaryCondition::Robin {
            a: 1.0,
            b: -1.0,
            g: 0.0,
        };
        assert!(matches!(
            bcs.validate(),
            Err(FemError::NegativeRobin { .. })
        ));
        assert!(BoundaryConditions::default().validate().is_ok());
    }
}
