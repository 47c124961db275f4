//! The ME766 term paper's relaxation: Laplace's equation reached as the steady state of the
//! heat equation `∂u/∂t = ∇²u`, stepped explicitly (forward in time, central in space) on
//! the occupancy grid:
//!
//! `u ← u + r (u_E + u_W + u_N + u_S − 4u)`,  `r = Δt / h²`,
//!
//! stable for `r ≤ 1/4` in two dimensions (the paper's stability condition; at `r = 1/4`
//! the step is exactly a Jacobi sweep). Goal cells hold the sink value, walls and
//! obstacles either hold the boundary value (Dirichlet) or mirror their free neighbour
//! (Neumann, `∂u/∂n = 0`); the iteration stops when no cell changed by more than the
//! accuracy `ε` in a step, as the paper's step 4 (`‖u_new − u_old‖ ≤ ε`).

use serde::Serialize;

use crate::{BaselineError, Cell, Raster};

/// The largest stable `r = Δt/h²` of the explicit scheme in two dimensions.
pub const STABLE_R: f64 = 0.25;

/// Walls and obstacles in [`Parabolic::solve`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ParabolicWalls {
    /// Held at this value.
    Dirichlet(f64),
    /// `∂u/∂n = 0`: a blocked neighbour counts as the cell itself.
    Neumann,
}

/// Settings of [`Parabolic::solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParabolicOptions {
    /// `r = Δt/h²`; must lie in (0, 1/4].
    pub r: f64,
    /// The value held on goal cells (the paper's sink, −10⁸ with Dirichlet walls).
    pub sink: f64,
    /// Walls and obstacles.
    pub walls: ParabolicWalls,
    /// The field's starting value on free cells.
    pub initial: f64,
    /// Stop when no cell changes by more than this in a step.
    pub accuracy: f64,
    /// Give up after this many steps.
    pub max_steps: usize,
}

impl Default for ParabolicOptions {
    /// The paper's Dirichlet runs: `r = 1/4`, sink −10⁸, boundary 1, start at 0, ε = 10⁻⁴.
    fn default() -> Self {
        ParabolicOptions {
            r: STABLE_R,
            sink: -1e8,
            walls: ParabolicWalls::Dirichlet(1.0),
            initial: 0.0,
            accuracy: 1e-4,
            max_steps: 1_000_000,
        }
    }
}

/// How the stepping ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "outcome")]
pub enum ParabolicOutcome {
    /// No change above the accuracy after `steps` steps.
    Converged {
        /// Steps taken.
        steps: usize,
    },
    /// `max_steps` ran out; the last step's largest change.
    StepLimit {
        /// The largest change in the last step.
        last_change: f64,
    },
}

/// The stepped field.
#[derive(Clone, Debug)]
pub struct Parabolic {
    raster: Raster,
    values: Vec<f64>,
    outcome: ParabolicOutcome,
}

impl Parabolic {
    /// Steps the heat equation on `raster` until it is steady to `options.accuracy`.
    ///
    /// Errors if `r` is outside (0, 1/4] (unstable or no step), or the accuracy, sink or
    /// boundary value is not finite and positive where it must be.
    ///
    /// ```
    /// use harmonic_baselines::{Parabolic, ParabolicOptions, ParabolicOutcome, Raster};
    /// use harmonic_mesh::Point;
    /// let sq = |x0: f64, y0: f64, x1: f64, y1: f64| vec![Point::new(x0, y0), Point::new(x1, y0), Point::new(x1, y1), Point::new(x0, y1)];
    /// let raster = Raster::from_polygons(&sq(0.0, 0.0, 1.0, 1.0), &[], &[sq(0.8, 0.8, 0.9, 0.9)], 20).unwrap();
    /// let opts = ParabolicOptions { sink: 0.0, accuracy: 1e-8, ..ParabolicOptions::default() };
    /// let f = Parabolic::solve(raster, &opts).unwrap();
    /// assert!(matches!(f.outcome(), ParabolicOutcome::Converged { .. }));
    /// // Too large a time step is refused: the scheme would blow up.
    /// let raster = Raster::from_polygons(&sq(0.0, 0.0, 1.0, 1.0), &[], &[sq(0.8, 0.8, 0.9, 0.9)], 20).unwrap();
    /// assert!(Parabolic::solve(raster, &ParabolicOptions { r: 0.3, ..opts }).is_err());
    /// ```
    pub fn solve(raster: Raster, options: &ParabolicOptions) -> Result<Self, BaselineError> {
        if !(options.r > 0.0 && options.r <= STABLE_R) {
            return Err(BaselineError::InvalidParameter {
                name: "r",
                value: options.r,
                reason: "the explicit scheme is stable only for 0 < Δt/h² ≤ 1/4",
            });
        }
        if !(options.accuracy > 0.0 && options.accuracy.is_finite()) {
            return Err(BaselineError::InvalidParameter {
                name: "accuracy",
                value: options.accuracy,
                reason: "must be positive and finite",
            });
        }
        let wall = match options.walls {
            ParabolicWalls::Dirichlet(v) => v,
            ParabolicWalls::Neumann => 0.0,
        };
        for (what, v) in [
            ("sink", options.sink),
            ("walls", wall),
            ("initial", options.initial),
        ] {
            if !v.is_finite() {
                return Err(BaselineError::NonFinite {
                    what: what.to_string(),
                    value: v,
                });
            }
        }
        let n = raster.n();
        let cells = raster.cells().to_vec();
        let mut u: Vec<f64> = cells
            .iter()
            .map(|c| match c {
                Cell::Goal(_) => options.sink,
                Cell::Free => options.initial,
                _ => wall,
            })
            .collect();
        let mut next = u.clone();
        let neumann = options.walls == ParabolicWalls::Neumann;
        let mut outcome = ParabolicOutcome::StepLimit {
            last_change: f64::INFINITY,
        };
        for step in 1..=options.max_steps {
            let mut change = 0.0f64;
            for k in 0..u.len() {
                if cells[k] != Cell::Free {
                    continue;
                }
                let nb = |m: usize| {
                    if neumann && !matches!(cells[m], Cell::Free | Cell::Goal(_)) {
                        u[k]
                    } else {
                        u[m]
                    }
                };
                let lap = nb(k - 1) + nb(k + 1) + nb(k - n) + nb(k + n) - 4.0 * u[k];
                let v = u[k] + options.r * lap;
                change = change.max((v - u[k]).abs());
                next[k] = v;
            }
            std::mem::swap(&mut u, &mut next);
            if change <= options.accuracy {
                outcome = ParabolicOutcome::Converged { steps: step };
                break;
            }
            outcome = ParabolicOutcome::StepLimit {
                last_change: change,
            };
        }
        Ok(Parabolic {
            raster,
            values: u,
            outcome,
        })
    }

    /// How it ended.
    pub fn outcome(&self) -> ParabolicOutcome {
        self.outcome
    }

    /// Steps taken (the limit when it did not converge).
    pub fn steps(&self, options: &ParabolicOptions) -> usize {
        match self.outcome {
            ParabolicOutcome::Converged { steps } => steps,
            ParabolicOutcome::StepLimit { .. } => options.max_steps,
        }
    }

    /// The cell values.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The raster.
    pub fn raster(&self) -> &Raster {
        &self.raster
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_mesh::Point;

    fn sq(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
        vec![
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ]
    }

    #[test]
    fn the_steady_state_is_the_five_point_harmonic_function() {
        let raster = Raster::from_polygons(
            &sq(0.0, 0.0, 1.0, 1.0),
            &[sq(0.3, 0.3, 0.5, 0.7)],
            &[sq(0.8, 0.1, 0.9, 0.2)],
            24,
        )
        .unwrap();
        let opts = ParabolicOptions {
            sink: 0.0,
            accuracy: 1e-13,
            ..ParabolicOptions::default()
        };
        let f = Parabolic::solve(raster.clone(), &opts).unwrap();
        assert!(matches!(f.outcome(), ParabolicOutcome::Converged { .. }));
        let n = raster.n();
        let u = f.values();
        for (k, c) in raster.cells().iter().enumerate() {
            if *c == Cell::Free {
                let mean = 0.25 * (u[k - 1] + u[k + 1] + u[k - n] + u[k + n]);
                assert!((u[k] - mean).abs() < 1e-10, "cell {k}");
            }
        }
        // A smaller time step takes proportionally more steps to the same accuracy.
        let half = Parabolic::solve(
            raster,
            &ParabolicOptions {
                r: 0.125,
                accuracy: 1e-6,
                ..opts
            },
        )
        .unwrap();
        let full = Parabolic::solve(
            f.raster().clone(),
            &ParabolicOptions {
                accuracy: 1e-6,
                ..opts
            },
        )
        .unwrap();
        let (h, g) = (half.steps(&opts), full.steps(&opts));
        assert!(h > g && (h as f64) < 2.5 * g as f64, "{h} vs {g}");
    }

    #[test]
    fn neumann_walls_keep_the_field_between_sink_and_start() {
        let raster =
            Raster::from_polygons(&sq(0.0, 0.0, 1.0, 1.0), &[], &[sq(0.8, 0.8, 0.9, 0.9)], 16)
                .unwrap();
        let opts = ParabolicOptions {
            sink: -0.5,
            walls: ParabolicWalls::Neumann,
            accuracy: 1e-6,
            ..ParabolicOptions::default()
        };
        let f = Parabolic::solve(raster, &opts).unwrap();
        assert!(f.values().iter().all(|&v| (-0.5..=0.0).contains(&v)));
    }

    #[test]
    fn rejects_unstable_steps() {
        let raster =
            Raster::from_polygons(&sq(0.0, 0.0, 1.0, 1.0), &[], &[sq(0.8, 0.8, 0.9, 0.9)], 8)
                .unwrap();
        for r in [0.0, 0.26, f64::NAN] {
            let o = ParabolicOptions {
                r,
                ..ParabolicOptions::default()
            };
            assert!(Parabolic::solve(raster.clone(), &o).is_err());
        }
    }
}
