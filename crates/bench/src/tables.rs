//! The papers' experiments, as functions the examples print and the tests check.
//!
//! - [`bc_table`]: Garrido et al. (2010), Table 1 — how the boundary condition on walls and
//!   obstacles changes the clearance of the paths.

use serde::Serialize;

use harmonic_planner::fem::BoundaryCondition;
use harmonic_planner::scene::Scene;
use harmonic_planner::{PlanError, Planner};

/// The kind of condition a row of the boundary-condition table puts on walls and obstacles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BcKind {
    /// ∂φ/∂n = [`NEUMANN_INFLOW`].
    Neumann,
    /// ∂φ/∂n = K(1 − φ).
    Robin,
    /// φ = 1.
    Dirichlet,
}

impl BcKind {
    /// The word the table and the JSON print.
    pub fn as_str(self) -> &'static str {
        match self {
            BcKind::Neumann => "neumann",
            BcKind::Robin => "robin",
            BcKind::Dirichlet => "dirichlet",
        }
    }
}

impl std::fmt::Display for BcKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One row of the boundary-condition table: the condition `(a, b, K)` on walls and obstacles
/// (∂φ/∂n = K(1 − φ) for Robin rows), the goal held at φ = 0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BcRow {
    /// Serialised as `"type": "neumann" | "robin" | "dirichlet"`.
    #[serde(rename = "type")]
    pub kind: BcKind,
    /// The paper's `a` column, as printed: 0 in the Dirichlet row, 1 in the others
    /// ([`BcRow::condition`] reads only `kind` and `k`).
    pub a: f64,
    /// The paper's `b` column, as printed (1 in every row).
    pub b: f64,
    /// The gain K of ∂φ/∂n = K(1 − φ) in Robin rows (0 in the Neumann and Dirichlet rows).
    pub k: f64,
}

/// The rows of Garrido et al. (2010), Table 1, in the paper's order.
pub const PAPER_ROWS: [BcRow; 8] = [
    BcRow {
        kind: BcKind::Neumann,
        a: 1.0,
        b: 1.0,
        k: 0.0,
    },
    BcRow {
        kind: BcKind::Robin,
        a: 1.0,
        b: 1.0,
        k: 1.0,
    },
    BcRow {
        kind: BcKind::Robin,
        a: 1.0,
        b: 1.0,
        k: 2.0,
    },
    BcRow {
        kind: BcKind::Robin,
        a: 1.0,
        b: 1.0,
        k: 3.0,
    },
    BcRow {
        kind: BcKind::Robin,
        a: 1.0,
        b: 1.0,
        k: 10.0,
    },
    BcRow {
        kind: BcKind::Dirichlet,
        a: 0.0,
        b: 1.0,
        k: 0.0,
    },
    BcRow {
        kind: BcKind::Robin,
        a: 1.0,
        b: 1.0,
        k: 100.0,
    },
    BcRow {
        kind: BcKind::Robin,
        a: 1.0,
        b: 1.0,
        k: 1000.0,
    },
];

/// The uniform inflow that drives the Neumann row: ∂φ/∂n = 1 on walls and obstacles (φ rises
/// toward them). Homogeneous Neumann walls with a Dirichlet goal give the constant potential
/// φ ≡ 0 and no path; the paper does not say how its Neumann row was driven.
pub const NEUMANN_INFLOW: f64 = 1.0;

impl BcRow {
    /// The condition on walls and obstacles this row stands for.
    pub fn condition(&self) -> BoundaryCondition {
        match self.kind {
            BcKind::Dirichlet => BoundaryCondition::Dirichlet(1.0),
            BcKind::Neumann => BoundaryCondition::Neumann(NEUMANN_INFLOW),
            BcKind::Robin => BoundaryCondition::Robin {
                a: 1.0,
                b: self.k,
                g: self.k,
            },
        }
    }
}

/// A measured row: for each start, the clearance relative to the Dirichlet row (`d`, %), and
/// what the paper lacks — the path length, the smallest |∇φ| along it, whether it arrived.
#[derive(Clone, Debug, Serialize)]
pub struct BcResult {
    /// The row measured (its fields inline in the JSON object).
    #[serde(flatten)]
    pub row: BcRow,
    /// d = d_i / d_D × 100 % for each start, d_i the smallest distance from the path to a wall
    /// or an obstacle.
    pub d: Vec<f64>,
    /// d_i itself, for each start.
    pub clearance: Vec<f64>,
    /// Whether the path from each start reached the goal.
    pub reached: Vec<bool>,
    /// Length of the path from each start, in scene units.
    pub length: Vec<f64>,
    /// Smallest |∇φ| along the path from each start (0 if none was met).
    pub min_gradient: Vec<f64>,
}

/// Runs the table on `scene` (its own boundary conditions are replaced row by row) from
/// `starts`, optionally with a coarser or finer mesh.
pub fn bc_table(
    scene: &Scene,
    starts: &[[f64; 2]],
    rows: &[BcRow],
) -> Result<Vec<BcResult>, PlanError> {
    let mut dirichlet = scene.clone();
    dirichlet.boundary.walls = Some(BoundaryCondition::Dirichlet(1.0));
    dirichlet.boundary.obstacles = Some(BoundaryCondition::Dirichlet(1.0));
    let reference: Vec<f64> = Planner::new(&dirichlet)?
        .plan_many(starts)
        .iter()
        .map(|p| p.min_clearance)
        .collect();
    rows.iter()
        .map(|row| {
            let mut s = scene.clone();
            s.boundary.walls = Some(row.condition());
            s.boundary.obstacles = Some(row.condition());
            s.boundary.goal = Some(BoundaryCondition::Dirichlet(0.0));
            for o in &mut s.obstacles {
                o.boundary = None;
            }
            let paths = Planner::new(&s)?.plan_many(starts);
            Ok(BcResult {
                row: *row,
                d: paths
                    .iter()
                    .zip(&reference)
                    .map(|(p, d_d)| 100.0 * p.min_clearance / d_d)
                    .collect(),
                clearance: paths.iter().map(|p| p.min_clearance).collect(),
                reached: paths.iter().map(|p| p.status.reached_goal()).collect(),
                length: paths.iter().map(|p| p.length).collect(),
                min_gradient: paths.iter().map(|p| p.min_gradient).collect(),
            })
        })
        .collect()
}

impl BcRow {
    /// The condition the row's printed triple gives when read literally:
    /// a·∂φ/∂n + b·φ = K on walls and obstacles (φ = K/b where a = 0). With the goal at
    /// φ = 0 this is linear in K, so every row with a = b = 1 and K > 0 gives K times one
    /// field (the same paths), and K = 0 gives φ ≡ 0 (no path).
    pub fn literal_condition(&self) -> BoundaryCondition {
        if self.a == 0.0 {
            BoundaryCondition::Dirichlet(self.k / self.b)
        } else {
            BoundaryCondition::Robin {
                a: self.a,
                b: self.b,
                g: self.k,
            }
        }
    }
}

/// A row of the literal reading: d for each start, or why there is no path.
#[derive(Clone, Debug, Serialize)]
pub struct LiteralResult {
    /// The row.
    #[serde(flatten)]
    pub row: BcRow,
    /// d (%) for each start against the documented Dirichlet row's clearance (the literal
    /// Dirichlet row has no path), `None` where the literal field gives no path.
    pub d: Vec<Option<f64>>,
    /// Why the literal field gives no path (`None` when it does).
    pub no_path: Option<String>,
}

/// The table under the literal reading of each row's (a, b, K), against `reference`, the
/// documented Dirichlet row's clearance per start.
pub fn bc_table_literal(
    scene: &Scene,
    starts: &[[f64; 2]],
    rows: &[BcRow],
    reference: &[f64],
) -> Vec<LiteralResult> {
    rows.iter()
        .map(|row| {
            let mut s = scene.clone();
            s.boundary.walls = Some(row.literal_condition());
            s.boundary.obstacles = Some(row.literal_condition());
            s.boundary.goal = Some(BoundaryCondition::Dirichlet(0.0));
            for o in &mut s.obstacles {
                o.boundary = None;
            }
            match Planner::new(&s) {
                Err(e) => LiteralResult {
                    row: *row,
                    d: vec![None; starts.len()],
                    no_path: Some(e.to_string()),
                },
                Ok(planner) => {
                    let paths = planner.plan_many(starts);
                    let flat = planner.potential().psi().iter().all(|&v| v == 0.0);
                    LiteralResult {
                        row: *row,
                        d: paths
                            .iter()
                            .zip(reference)
                            .map(|(p, d_d)| {
                                (p.status.reached_goal() && !flat)
                                    .then(|| 100.0 * p.min_clearance / d_d)
                            })
                            .collect(),
                        no_path: flat.then(|| "φ ≡ 0: the field is constant".to_string()),
                    }
                }
            }
        })
        .collect()
}
