//! Connolly's grid harmonic planner: the 5-point Laplacian on an occupancy grid, relaxed by
//! Gauss–Seidel or red–black SOR, then followed by its bilinear interpolant.

use std::time::{Duration, Instant};

use harmonic_mesh::{Point, Vector};
use harmonic_trajectory::{Fallback, Field, Locate, Segment};

use crate::raster::UNREACHED;
use crate::{BaselineError, Cell, Connectivity, Raster};

/// Which quantity the relaxation iterates on.
///
/// Far from the goal a Dirichlet potential becomes flat: `1 − φ` falls below the float
/// spacing near 1 and `φ` rounds to exactly 1, leaving cells with no lower neighbour.
/// Iterating on `ψ = 1 − φ` (goal 1, walls 0) keeps ψ's relative precision however small it
/// gets, as the FEM solver does (ARCHITECTURE.md, "Numerical conventions").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Unknown {
    /// `ψ = 1 − φ`: goal cells 1, wall and obstacle cells 0 (the default).
    #[default]
    Psi,
    /// Connolly's original `φ`: goal cells 0, wall and obstacle cells 1.
    Phi,
}

/// The relaxation scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Relaxation {
    /// Lexicographic Gauss–Seidel (row by row, ω = 1).
    GaussSeidel,
    /// Successive over-relaxation with red–black ordering. `omega: None` picks the optimal
    /// `ω = 2 / (1 + sin(π / n))` for an `n × n` grid.
    RedBlackSor {
        /// Relaxation factor in (0, 2), or `None` for the optimum.
        omega: Option<f64>,
    },
}

/// When the relaxation stops (besides `max_iterations`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopRule {
    /// Stop when no cell changed by more than this in a sweep.
    MaxUpdate(f64),
    /// Stop when the max-norm residual of the normalised 5-point equations (each divided by
    /// its diagonal, so in units of the potential) is below this. Costs one more pass a sweep
    /// near the end.
    Residual(f64),
    /// Stop when every cell's normalised residual is below this fraction of the cell's own
    /// value: relative precision everywhere, however small ψ gets far from the goal (the grid
    /// counterpart of storing ψ). Checked every 16 sweeps and at the end of each stage.
    ///
    /// Over-relaxed sweeps carry the rounding noise of the largest values they update
    /// (~1e-15 for ψ ≤ 1 at n = 256) across the grid, so they cannot resolve smaller values;
    /// Gauss–Seidel sweeps damp that noise like the solution itself, but slowly. With
    /// red–black SOR the relaxation therefore runs as a cascade of stages: the first
    /// over-relaxes every cell until no change exceeds 1e-13 (or the largest change has not
    /// decreased for 256 sweeps); each further stage holds the cells that are now resolved
    /// and over-relaxes only those below 1e-5 of the previous threshold, until no change
    /// exceeds 1e-13 of the new threshold. When no cell is left below it (or on φ, whose
    /// small quantity is 1 − φ), Gauss–Seidel sweeps of every cell finish the job. On the
    /// bundled maze at n = 256 (ψ down to ~1e-44) this takes about 4 400 sweeps, against
    /// 12 000 with Gauss–Seidel right after the first stage.
    RelativeResidual(f64),
}

/// The condition on the workspace's outer walls (obstacles and goals stay Dirichlet), in
/// terms of `φ` with `n` the outward normal of free space (into the wall).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum WallCondition {
    /// `φ = 1` at the wall cells' centres (Connolly's original).
    #[default]
    Dirichlet,
    /// `a ∂φ/∂n + b φ = g` on the cell face between a free cell and a wall cell, with
    /// `∂φ/∂n ≈ (φ_wall − φ_cell)/h` and `φ_face ≈ (φ_wall + φ_cell)/2`. Neumann is
    /// `a = 1, b = 0`; `g = b` keeps walls at the Dirichlet value 1 "softly".
    Robin {
        /// Weight of the normal derivative (≥ 0).
        a: f64,
        /// Weight of the value (≥ 0; `a + b > 0`).
        b: f64,
        /// Right-hand side.
        g: f64,
    },
}

/// Options of [`GridHarmonic::solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SorOptions {
    /// The relaxation scheme.
    pub relaxation: Relaxation,
    /// The stopping rule.
    pub stop: StopRule,
    /// Give up after this many sweeps (the result then has `converged == false`).
    pub max_iterations: usize,
    /// Which quantity to iterate on.
    pub unknown: Unknown,
    /// The condition on the outer walls.
    pub walls: WallCondition,
}

impl Default for SorOptions {
    /// Red–black SOR with the optimal ω until every cell's residual is below 1e-6 of its
    /// value ([`StopRule::RelativeResidual`]); at most 100 000 sweeps, on ψ.
    ///
    /// An absolute tolerance cannot serve: ψ decays exponentially along corridors (to ~1e-44
    /// in the bundled maze at n = 256), so every absolute tolerance leaves the far cells
    /// unresolved. Stopped at an absolute residual of 1e-13, the maze's far cells still hold
    /// ~1e-15 of noise, some of it negative, and 6286 free cells have no higher neighbour:
    /// the tracer stalled from 16 of 24 starts (office 12 of 27, clutter 3 of 26). The
    /// relative rule leaves none, for 1 200–4 400 sweeps (0.12–0.4 s) on the bundled scenes
    /// instead of 1 100 (0.1 s).
    fn default() -> Self {
        SorOptions {
            relaxation: Relaxation::RedBlackSor { omega: None },
            stop: StopRule::RelativeResidual(1e-6),
            max_iterations: 100_000,
            unknown: Unknown::Psi,
            walls: WallCondition::Dirichlet,
        }
    }
}

/// How the relaxation went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveReport {
    /// Sweeps done (one sweep updates every free cell once, or in the later stages of
    /// [`StopRule::RelativeResidual`] every cell of the stage).
    pub iterations: usize,
    /// Final max-norm residual of the normalised equations.
    pub residual: f64,
    /// Final largest ratio of a cell's residual to its value (0/0 counts as 0).
    pub relative_residual: f64,
    /// Largest change of a cell in the last sweep.
    pub max_update: f64,
    /// Whether the stopping rule was met within `max_iterations`.
    pub converged: bool,
    /// The relaxation factor used (1 for Gauss–Seidel).
    pub omega: f64,
    /// Wall-clock time of the relaxation.
    pub time: Duration,
}

/// A harmonic potential on an occupancy grid (Connolly, Burns & Weiss 1990).
///
/// Free cells satisfy the 5-point Laplace equation; goal cells are held at the low value and
/// wall and obstacle cells at the high value (as ψ: goal 1, walls 0). Between cell centres the
/// potential is interpolated bilinearly.
#[derive(Clone, Debug)]
pub struct GridHarmonic {
    raster: Raster,
    values: Vec<f64>,
    unknown: Unknown,
    report: SolveReport,
    /// Whether each cell is 4-connected to a goal cell through traversable cells.
    reaches_goal: Vec<bool>,
}

/// The largest change per sweep, relative to the largest value updated, below which
/// over-relaxation stops helping [`StopRule::RelativeResidual`]: red–black SOR on ψ ≤ 1
/// levels off at changes of ~2e-15 (its rounding noise).
const SOR_NOISE_FLOOR: f64 = 1e-13;

/// Each stage of [`StopRule::RelativeResidual`]'s cascade over-relaxes only the cells below
/// the previous stage's threshold divided by this.
const CASCADE_STEP: f64 = 1e5;

/// Below this threshold the cascade hands over to Gauss–Seidel (values near the subnormal
/// range have no relative precision left to gain).
const CASCADE_END: f64 = 1e-280;

/// Sweeps without a new smallest largest-change after which [`StopRule::RelativeResidual`]
/// takes the over-relaxation to have reached its noise floor anyway.
const STAGNATION_SWEEPS: usize = 256;

/// How far above the residual tolerance the largest change of a sweep may still be for the
/// (costly) residual to be computed.
const RESIDUAL_GATE: f64 = 1000.0;

/// Updates the cells in `order` in place; returns the largest change.
#[inline]
fn sweep(v: &mut [f64], order: &[u32], n: usize, cx: f64, cy: f64, omega: f64) -> f64 {
    let mut max_change = 0.0f64;
    for &k in order {
        let k = k as usize;
        let target = cx * (v[k - 1] + v[k + 1]) + cy * (v[k - n] + v[k + n]);
        let change = omega * (target - v[k]);
        v[k] += change;
        // A plain comparison, not f64::max: no NaN handling on the loop-carried chain.
        let size = change.abs();
        if size > max_change {
            max_change = size;
        }
    }
    max_change
}

/// A free cell next to a Robin wall: its equation is `v = (S + r)·s` with `S` the usual
/// stencil sum (the wall cells holding their Dirichlet value).
#[derive(Clone, Copy, Debug)]
struct RobinCell {
    k: u32,
    r: f64,
    s: f64,
}

/// The cells of one colour (or all cells, in Gauss–Seidel order): plain 5-point cells and
/// cells next to a Robin wall. Cells of one colour do not couple, so updating the plain ones
/// before the Robin ones is still red–black SOR.
#[derive(Clone, Debug, Default)]
struct Order {
    plain: Vec<u32>,
    robin: Vec<RobinCell>,
}

impl Order {
    /// The cells of this order for which `keep` holds.
    fn filtered(&self, keep: impl Fn(usize) -> bool) -> Order {
        Order {
            plain: self
                .plain
                .iter()
                .copied()
                .filter(|&k| keep(k as usize))
                .collect(),
            robin: self
                .robin
                .iter()
                .copied()
                .filter(|c| keep(c.k as usize))
                .collect(),
        }
    }

    fn is_empty(&self) -> bool {
        self.plain.is_empty() && self.robin.is_empty()
    }

    fn sweep(&self, v: &mut [f64], n: usize, cx: f64, cy: f64, omega: f64) -> f64 {
        let mut max_change = sweep(v, &self.plain, n, cx, cy, omega);
        for c in &self.robin {
            let k = c.k as usize;
            let target = (cx * (v[k - 1] + v[k + 1]) + cy * (v[k - n] + v[k + n]) + c.r) * c.s;
            let change = omega * (target - v[k]);
            v[k] += change;
            max_change = max_change.max(change.abs());
        }
        max_change
    }

    /// The largest residual, absolute or relative to each cell's value.
    fn residual(&self, v: &[f64], n: usize, cx: f64, cy: f64, relative: bool) -> f64 {
        self.robin
            .iter()
            .fold(residual(v, &self.plain, n, cx, cy, relative), |r, c| {
                let k = c.k as usize;
                let target = (cx * (v[k - 1] + v[k + 1]) + cy * (v[k - n] + v[k + n]) + c.r) * c.s;
                r.max(scaled((target - v[k]).abs(), v[k], relative))
            })
    }
}

/// `r` itself, or `r / |value|` when `relative` (0 for 0/0, ∞ for r/0).
#[inline]
fn scaled(r: f64, value: f64, relative: bool) -> f64 {
    if !relative || r == 0.0 {
        r
    } else {
        r / value.abs()
    }
}

fn residual(v: &[f64], order: &[u32], n: usize, cx: f64, cy: f64, relative: bool) -> f64 {
    order.iter().fold(0.0f64, |r, &k| {
        let k = k as usize;
        let target = cx * (v[k - 1] + v[k + 1]) + cy * (v[k - n] + v[k + n]);
        r.max(scaled((target - v[k]).abs(), v[k], relative))
    })
}

/// The SOR relaxation factor ω of `relaxation` on an `n × n` grid (1 for Gauss–Seidel, the
/// optimum `2 / (1 + sin(π / n))` if none is given); an error unless it is in (0, 2).
fn relaxation_factor(relaxation: Relaxation, n: usize) -> Result<f64, BaselineError> {
    let omega = match relaxation {
        Relaxation::GaussSeidel => 1.0,
        Relaxation::RedBlackSor { omega: None } => {
            2.0 / (1.0 + (std::f64::consts::PI / n as f64).sin())
        }
        Relaxation::RedBlackSor { omega: Some(w) } => w,
    };
    if !(omega > 0.0 && omega < 2.0) {
        return Err(BaselineError::InvalidParameter {
            name: "omega",
            value: omega,
            reason: "SOR converges only for 0 < ω < 2",
        });
    }
    Ok(omega)
}

/// Checks the stopping rule's tolerance (positive and finite) and the sweep budget (at
/// least 1).
fn check_stopping(options: &SorOptions) -> Result<(), BaselineError> {
    let tol = match options.stop {
        StopRule::MaxUpdate(t) | StopRule::Residual(t) | StopRule::RelativeResidual(t) => t,
    };
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(BaselineError::InvalidParameter {
            name: "tolerance",
            value: tol,
            reason: "must be positive and finite",
        });
    }
    if options.max_iterations == 0 {
        return Err(BaselineError::InvalidParameter {
            name: "max_iterations",
            value: 0.0,
            reason: "must be at least 1",
        });
    }
    Ok(())
}

/// The goal and wall values `(goal, wall)` of the iterated quantity: ψ is 1 at goals and 0
/// at walls, φ the other way round.
fn boundary_values(unknown: Unknown) -> (f64, f64) {
    match unknown {
        Unknown::Psi => (1.0, 0.0),
        Unknown::Phi => (0.0, 1.0),
    }
}

/// The Robin wall coefficients `(a, b, g)` of `options` with `g` in the iterated quantity's
/// terms (`b − g` for ψ), `None` for Dirichlet walls; an error if they are not finite, not a
/// valid Robin condition, or leave nothing but the goal to drive the potential.
fn robin_walls(
    options: &SorOptions,
    raster: &Raster,
) -> Result<Option<(f64, f64, f64)>, BaselineError> {
    let WallCondition::Robin { a, b, g } = options.walls else {
        return Ok(None);
    };
    for (name, v) in [("robin a", a), ("robin b", b), ("robin g", g)] {
        if !v.is_finite() {
            return Err(BaselineError::NonFinite {
                what: name.to_string(),
                value: v,
            });
        }
    }
    if a < 0.0 || b < 0.0 || a + b <= 0.0 {
        return Err(BaselineError::InvalidParameter {
            name: "robin a, b",
            value: a.min(b),
            reason: "need a ≥ 0, b ≥ 0 and a + b > 0",
        });
    }
    let driven = b > 0.0
        || g != 0.0
        || raster
            .cells()
            .iter()
            .any(|c| matches!(c, Cell::Obstacle(_)));
    if !driven {
        return Err(BaselineError::InvalidParameter {
            name: "robin b",
            value: b,
            reason: "homogeneous Neumann walls and no obstacle: only the goal is \
                     Dirichlet and the potential is constant",
        });
    }
    // In the unknown's own terms (ψ = 1 − φ turns g into b − g).
    let g = match options.unknown {
        Unknown::Psi => b - g,
        Unknown::Phi => g,
    };
    Ok(Some((a, b, g)))
}

/// The 5-point stencil of a grid: `n` cells a side, cells `hx × hy` (workspace units), and
/// the weights `cx`, `cy` of the horizontal and vertical neighbours in the normalised
/// equation (`2 (cx + cy) = 1`).
#[derive(Clone, Copy, Debug)]
struct Stencil {
    n: usize,
    hx: f64,
    hy: f64,
    cx: f64,
    cy: f64,
}

impl Stencil {
    /// The stencil of `raster`'s grid.
    fn of(raster: &Raster) -> Stencil {
        let (hx, hy) = raster.cell_size();
        let (wx, wy) = (1.0 / (hx * hx), 1.0 / (hy * hy));
        Stencil {
            n: raster.n(),
            hx,
            hy,
            cx: wx / (2.0 * (wx + wy)),
            cy: wy / (2.0 * (wx + wy)),
        }
    }
}

/// The starting values (goal cells at the goal value, every other cell at the wall value)
/// and the free cells split into red and black, a cell next to a Robin wall with its own
/// equation.
fn initial_values(
    raster: &Raster,
    unknown: Unknown,
    robin: Option<(f64, f64, f64)>,
    stencil: Stencil,
) -> (Vec<f64>, Order, Order) {
    let Stencil { n, hx, hy, cx, cy } = stencil;
    let (goal_value, wall_value) = boundary_values(unknown);
    // Free cells never touch the grid's edge (the outer ring is wall), so k ± 1 and
    // k ± n stay in range.
    let cells = raster.cells();
    let mut values = Vec::with_capacity(n * n);
    let mut red = Order::default();
    let mut black = Order::default();
    for (k, cell) in cells.iter().enumerate() {
        values.push(match cell {
            Cell::Goal(_) => goal_value,
            _ => wall_value,
        });
        if *cell != Cell::Free {
            continue;
        }
        let order = if (k % n + k / n).is_multiple_of(2) {
            &mut red
        } else {
            &mut black
        };
        // Each Robin face adds c·α·(g − b v) to the balance Σ c (v_nb − v) = 0, with
        // α = 1 / (a/h + b/2), in place of c·(v_wall − v).
        let mut special = None;
        if let Some((a, b, g)) = robin {
            for (m, c, h) in [
                (k - 1, cx, hx),
                (k + 1, cx, hx),
                (k - n, cy, hy),
                (k + n, cy, hy),
            ] {
                if cells[m] == Cell::Wall {
                    let alpha = 1.0 / (a / h + 0.5 * b);
                    let (r, d) = special.unwrap_or((0.0, 1.0));
                    special = Some((r + c * (alpha * g - wall_value), d - c * (1.0 - alpha * b)));
                }
            }
        }
        match special {
            Some((r, d)) => order.robin.push(RobinCell {
                k: k as u32,
                r,
                s: 1.0 / d,
            }),
            None => order.plain.push(k as u32),
        }
    }
    (values, red, black)
}

/// All free cells in row-by-row order for Gauss–Seidel (empty for red–black SOR, which
/// sweeps the colours).
fn lexicographic_order(relaxation: Relaxation, red: &Order, black: &Order) -> Order {
    match relaxation {
        Relaxation::GaussSeidel => {
            let mut all = Order {
                plain: red.plain.iter().chain(&black.plain).copied().collect(),
                robin: red.robin.iter().chain(&black.robin).copied().collect(),
            };
            all.plain.sort_unstable();
            all.robin.sort_unstable_by_key(|c| c.k);
            all
        }
        Relaxation::RedBlackSor { .. } => Order::default(),
    }
}

/// Per cell: whether it is 4-connected to a goal cell through traversable cells.
fn goal_reachability(raster: &Raster) -> Vec<bool> {
    raster
        .goal_distances(Connectivity::Four)
        .into_iter()
        .map(|d| d != UNREACHED)
        .collect()
}

/// The relaxation: the cells to sweep, the stencil and the stopping rule.
struct Relax<'a> {
    red: &'a Order,
    black: &'a Order,
    /// Every free cell in Gauss–Seidel order (empty for red–black SOR).
    lexicographic: &'a Order,
    stencil: Stencil,
    reaches_goal: &'a [bool],
    options: &'a SorOptions,
}

/// The current stage of the relaxation: the relaxation factor and the cells over-relaxed
/// (all of them, except in the later stages of [`StopRule::RelativeResidual`]'s cascade,
/// which over-relaxes only the cells below `tau`), with the smallest largest change of a
/// sweep seen in the stage and the sweep that saw it.
struct Stage {
    omega: f64,
    tau: f64,
    red: Order,
    black: Order,
    smallest_update: f64,
    smallest_at: usize,
}

impl Relax<'_> {
    /// Sweeps `values` until the stopping rule holds or the budget is spent; returns the
    /// sweeps done, the largest change in the last one and whether the rule was met.
    fn run(&self, values: &mut [f64], omega: f64) -> (usize, f64, bool) {
        let mut iterations = 0;
        let mut max_update = f64::INFINITY;
        let mut stage = Stage {
            omega,
            tau: 1.0,
            red: self.red.clone(),
            black: self.black.clone(),
            smallest_update: f64::INFINITY,
            smallest_at: 0,
        };
        while iterations < self.options.max_iterations {
            iterations += 1;
            max_update = self.sweep(values, &stage);
            let done = match self.options.stop {
                StopRule::MaxUpdate(t) => max_update < t,
                // The full residual pass costs as much as half a sweep: run it only once the
                // largest change (ω times the residual each cell saw when it was updated) is
                // within a factor RESIDUAL_GATE of the tolerance. It only delays the check.
                StopRule::Residual(t) => {
                    max_update < RESIDUAL_GATE * t && self.residual(values, false) < t
                }
                StopRule::RelativeResidual(t) => {
                    self.relative_done(values, &mut stage, iterations, max_update, t)
                }
            };
            if done {
                return (iterations, max_update, true);
            }
        }
        (iterations, max_update, false)
    }

    /// One sweep of the stage's cells (of every cell for Gauss–Seidel); the largest change.
    fn sweep(&self, values: &mut [f64], stage: &Stage) -> f64 {
        let Stencil { n, cx, cy, .. } = self.stencil;
        match self.options.relaxation {
            Relaxation::GaussSeidel => self.lexicographic.sweep(values, n, cx, cy, 1.0),
            Relaxation::RedBlackSor { .. } => {
                let a = stage.red.sweep(values, n, cx, cy, stage.omega);
                a.max(stage.black.sweep(values, n, cx, cy, stage.omega))
            }
        }
    }

    /// The largest residual of every free cell, absolute or relative to the cell's value.
    fn residual(&self, values: &[f64], relative: bool) -> f64 {
        let Stencil { n, cx, cy, .. } = self.stencil;
        self.red
            .residual(values, n, cx, cy, relative)
            .max(self.black.residual(values, n, cx, cy, relative))
    }

    /// [`StopRule::RelativeResidual`] with tolerance `t` after sweep `iterations`: whether
    /// every cell is resolved; moves `stage` on to the next stage of the cascade when the
    /// current one has reached its noise floor.
    fn relative_done(
        &self,
        values: &[f64],
        stage: &mut Stage,
        iterations: usize,
        max_update: f64,
        t: f64,
    ) -> bool {
        let Stencil { n, cx, cy, .. } = self.stencil;
        if max_update < stage.smallest_update {
            (stage.smallest_update, stage.smallest_at) = (max_update, iterations);
        }
        let floor = max_update < SOR_NOISE_FLOOR * stage.tau
            || iterations - stage.smallest_at >= STAGNATION_SWEEPS;
        let active_done = || {
            stage
                .red
                .residual(values, n, cx, cy, true)
                .max(stage.black.residual(values, n, cx, cy, true))
                < t
        };
        if stage.omega == 1.0 {
            iterations.is_multiple_of(16) && self.residual(values, true) < t
        } else if !floor {
            // A stage may already have resolved everything.
            iterations.is_multiple_of(16) && active_done() && self.residual(values, true) < t
        } else if self.residual(values, true) < t {
            true
        } else {
            self.next_stage(values, stage, iterations);
            false
        }
    }

    /// The next stage of the cascade, from sweep `iterations` on.
    fn next_stage(&self, values: &[f64], stage: &mut Stage, iterations: usize) {
        // Cells of at least `tau / CASCADE_STEP` are now resolved to about 1e-10 of their
        // value: hold them, and over-relax the rest, whose rounding noise is now that much
        // smaller.
        stage.tau /= CASCADE_STEP;
        let tau = stage.tau;
        let below = |k: usize| self.reaches_goal[k] && values[k] < tau;
        stage.red = self.red.filtered(below);
        stage.black = self.black.filtered(below);
        (stage.smallest_update, stage.smallest_at) = (f64::INFINITY, iterations);
        let empty = stage.red.is_empty() && stage.black.is_empty();
        if self.options.unknown == Unknown::Phi || empty || tau < CASCADE_END {
            (stage.omega, stage.red, stage.black) = (1.0, self.red.clone(), self.black.clone());
        }
    }
}

impl GridHarmonic {
    /// Relaxes the 5-point Laplace equation on `raster`'s free cells.
    ///
    /// Errors if ω is outside (0, 2), a tolerance is not positive and finite, or
    /// `max_iterations` is 0. Not converging within `max_iterations` is not an error: check
    /// [`SolveReport::converged`].
    ///
    /// ```
    /// use harmonic_baselines::{GridHarmonic, Raster, SorOptions};
    /// use harmonic_mesh::Point;
    /// let ws = vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)];
    /// let goal = vec![Point::new(0.8, 0.8), Point::new(0.9, 0.8), Point::new(0.9, 0.9), Point::new(0.8, 0.9)];
    /// let raster = Raster::from_polygons(&ws, &[], &[goal], 32).unwrap();
    /// let field = GridHarmonic::solve(raster, &SorOptions::default()).unwrap();
    /// assert!(field.report().converged);
    /// assert_eq!(field.flat_cells(), 0);
    /// ```
    pub fn solve(raster: Raster, options: &SorOptions) -> Result<Self, BaselineError> {
        let omega = relaxation_factor(options.relaxation, raster.n())?;
        check_stopping(options)?;
        let robin = robin_walls(options, &raster)?;
        let stencil = Stencil::of(&raster);
        let (mut values, red, black) = initial_values(&raster, options.unknown, robin, stencil);
        let lexicographic = lexicographic_order(options.relaxation, &red, &black);
        let reaches_goal = goal_reachability(&raster);
        let start = Instant::now();
        let relax = Relax {
            red: &red,
            black: &black,
            lexicographic: &lexicographic,
            stencil,
            reaches_goal: &reaches_goal,
            options,
        };
        let (iterations, max_update, converged) = relax.run(&mut values, omega);
        let report = SolveReport {
            iterations,
            residual: relax.residual(&values, false),
            relative_residual: relax.residual(&values, true),
            max_update,
            converged,
            omega,
            time: start.elapsed(),
        };
        Ok(GridHarmonic {
            raster,
            values,
            unknown: options.unknown,
            report,
            reaches_goal,
        })
    }

    /// The occupancy grid the potential lives on.
    pub fn raster(&self) -> &Raster {
        &self.raster
    }

    /// Cell values (ψ or φ, see [`GridHarmonic::unknown`]), row by row.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Which quantity [`GridHarmonic::values`] holds.
    pub fn unknown(&self) -> Unknown {
        self.unknown
    }

    /// How the relaxation went.
    pub fn report(&self) -> &SolveReport {
        &self.report
    }

    /// The cell values as a potential that decreases toward the goal: `φ` as iterated, or
    /// `−ψ` (not `1 − ψ`, which would throw away ψ's small values).
    fn descent_value(&self, k: usize) -> f64 {
        match self.unknown {
            Unknown::Psi => -self.values[k],
            Unknown::Phi => self.values[k],
        }
    }

    /// Connolly's flatness count: free cells connected to a goal none of whose four
    /// neighbours is strictly closer to the goal (strictly lower in φ). Zero for a converged
    /// harmonic field in exact arithmetic; positive where the field went numerically flat or
    /// has a local minimum. (Cells cut off from every goal are constant by construction and
    /// not counted: [`Field::goal_reachable`] reports them.)
    pub fn flat_cells(&self) -> usize {
        let n = self.raster.n();
        self.raster
            .cells()
            .iter()
            .enumerate()
            .filter(|&(k, c)| {
                *c == Cell::Free && self.reaches_goal[k] && {
                    let v = self.descent_value(k);
                    [k - 1, k + 1, k - n, k + n]
                        .iter()
                        .all(|&m| self.descent_value(m) >= v)
                }
            })
            .count()
    }

    /// Bilinear interpolation of the descent potential (`φ`, or `−ψ`) at `p`, with its
    /// gradient. `None` outside the span of cell centres.
    pub fn value_and_gradient(&self, p: Point) -> Option<(f64, Vector)> {
        let n = self.raster.n();
        let o = self.raster.origin();
        let (hx, hy) = self.raster.cell_size();
        let u = (p.x - o.x) / hx - 0.5;
        let v = (p.y - o.y) / hy - 0.5;
        let last = (n - 1) as f64;
        if !(u >= 0.0 && v >= 0.0 && u <= last && v <= last) {
            return None;
        }
        let i = (u.floor() as usize).min(n - 2);
        let j = (v.floor() as usize).min(n - 2);
        let (fu, fv) = (u - i as f64, v - j as f64);
        let k = j * n + i;
        let v00 = self.descent_value(k);
        let v10 = self.descent_value(k + 1);
        let v01 = self.descent_value(k + n);
        let v11 = self.descent_value(k + n + 1);
        let value = (1.0 - fv) * ((1.0 - fu) * v00 + fu * v10) + fv * ((1.0 - fu) * v01 + fu * v11);
        let gx = ((1.0 - fv) * (v10 - v00) + fv * (v11 - v01)) / hx;
        let gy = ((1.0 - fu) * (v01 - v00) + fu * (v11 - v10)) / hy;
        Some((value, Vector::new(gx, gy)))
    }
}

/// The grid potential as a [`Field`] for the shared tracer: cells are flat grid indices,
/// values and gradients the bilinear interpolant of the descent potential (`−ψ` or `φ`),
/// goal regions the goal cells, and obstacles the obstacle and wall cells.
impl Field for GridHarmonic {
    type Point = Point;
    type Vector = Vector;
    type Cell = usize;

    fn locate(&self, p: Point, _hint: Option<usize>) -> Locate<usize> {
        match self.raster.index_of(p) {
            None => Locate::OutsideWorkspace,
            Some(k) => match self.raster.cells()[k] {
                Cell::Free => Locate::Inside(k),
                Cell::Goal(j) => Locate::Goal(j),
                Cell::Obstacle(_) => Locate::InObstacle,
                Cell::Wall => Locate::OutsideWorkspace,
            },
        }
    }

    fn value(&self, _cell: usize, p: Point) -> f64 {
        self.value_and_gradient(p).map_or(f64::INFINITY, |(v, _)| v)
    }

    fn gradient(&self, _cell: usize, p: Point) -> Vector {
        self.value_and_gradient(p)
            .map_or(Vector::zeros(), |(_, g)| g)
    }

    /// Samples the segment every quarter cell, so it cannot jump over a blocked cell.
    fn segment(&self, cell: usize, from: Point, to: Point) -> Segment<usize> {
        let (hx, hy) = self.raster.cell_size();
        let steps = ((to - from).norm() / (0.25 * hx.min(hy))).ceil().max(1.0) as usize;
        let mut last = cell;
        for s in 1..=steps {
            let p = from + (to - from) * (s as f64 / steps as f64);
            match self.locate(p, Some(last)) {
                Locate::Inside(c) => last = c,
                Locate::Goal(j) => return Segment::Goal(j),
                Locate::InObstacle | Locate::OutsideWorkspace => return Segment::Blocked,
            }
        }
        Segment::Inside(last)
    }

    fn goal_reachable(&self, cell: usize) -> bool {
        self.reaches_goal[cell]
    }

    /// One move of discrete steepest descent: to the centre of the edge neighbour with the
    /// lowest value, if it is lower than this cell's (always so in a converged field without
    /// flat cells).
    fn fallback_step(&self, cell: usize, _p: Point) -> Fallback<usize> {
        let n = self.raster.n();
        let cells = self.raster.cells();
        if cell >= cells.len() || cells[cell] != Cell::Free {
            return Fallback::Stuck;
        }
        let best = [cell - 1, cell + 1, cell - n, cell + n]
            .into_iter()
            .filter(|&m| cells[m].is_traversable())
            .min_by(|&a, &b| self.descent_value(a).total_cmp(&self.descent_value(b)));
        match best {
            Some(m) if self.descent_value(m) < self.descent_value(cell) => match cells[m] {
                Cell::Goal(j) => Fallback::Goal(j),
                _ => Fallback::Moved(self.raster.centre(m), m),
            },
            _ => Fallback::Stuck,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
        vec![
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ]
    }

    /// A one-cell-high corridor on an `n × n` grid of unit cells: row centre y = 5.5 is free
    /// from x = 1.5 to x = n − 2.5, the goal is the cell at x = 0.5, the wall ring at the right.
    fn corridor(n: usize) -> Raster {
        let w = (n - 2) as f64;
        Raster::from_polygons(
            &rect(0.0, 0.0, w, w),
            &[rect(0.0, 0.0, w, 5.0), rect(0.0, 6.0, w, w)],
            &[rect(0.0, 5.0, 1.0, 6.0)],
            n,
        )
        .unwrap()
    }

    fn tight(relaxation: Relaxation, unknown: Unknown) -> SorOptions {
        SorOptions {
            relaxation,
            stop: StopRule::Residual(1e-14),
            max_iterations: 200_000,
            unknown,
            walls: WallCondition::Dirichlet,
        }
    }

    #[test]
    fn neumann_walls_make_a_strip_exactly_linear() {
        // A 10 × 3 strip: goal column x < 1 (ψ = 1), obstacle column x > 9 (ψ = 0), Neumann
        // walls above and below. With n = 22, hx = 0.5: the last goal centre is x = 0.75 and
        // the first obstacle centre x = 9.25, so ψ = (9.25 − x) / 8.5 on every free cell.
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 3.0),
            &[rect(9.0, 0.0, 10.0, 3.0)],
            &[rect(0.0, 0.0, 1.0, 3.0)],
            22,
        )
        .unwrap();
        for (relaxation, unknown) in [
            (Relaxation::RedBlackSor { omega: None }, Unknown::Psi),
            (Relaxation::GaussSeidel, Unknown::Phi),
        ] {
            let opts = SorOptions {
                walls: WallCondition::Robin {
                    a: 1.0,
                    b: 0.0,
                    g: 0.0,
                },
                ..tight(relaxation, unknown)
            };
            let f = GridHarmonic::solve(raster.clone(), &opts).unwrap();
            assert!(f.report().converged);
            let mut free = 0;
            for (k, c) in f.raster().cells().iter().enumerate() {
                if *c == Cell::Free {
                    free += 1;
                    let psi = (9.25 - f.raster().centre(k).x) / 8.5;
                    let v = match unknown {
                        Unknown::Psi => f.values()[k],
                        Unknown::Phi => 1.0 - f.values()[k],
                    };
                    assert!((v - psi).abs() < 1e-10, "cell {k}: {v} vs {psi}");
                }
            }
            assert_eq!(free, 16 * 20);
        }
    }

    #[test]
    fn robin_walls_lift_the_far_field_and_are_validated() {
        // Robin walls with a small b hold the walls only softly, so ψ far from the goal is
        // larger than with Dirichlet walls (the paper's remedy for flat fields).
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[],
            &[rect(8.0, 8.0, 9.0, 9.0)],
            32,
        )
        .unwrap();
        let dirichlet = GridHarmonic::solve(raster.clone(), &SorOptions::default()).unwrap();
        let robin = SorOptions {
            walls: WallCondition::Robin {
                a: 1.0,
                b: 0.1,
                g: 0.1,
            },
            ..SorOptions::default()
        };
        let soft = GridHarmonic::solve(raster.clone(), &robin).unwrap();
        let far = raster.index_of(Point::new(0.5, 0.5)).unwrap();
        assert!(
            soft.values()[far] > 10.0 * dirichlet.values()[far],
            "Robin {} vs Dirichlet {}",
            soft.values()[far],
            dirichlet.values()[far]
        );
        assert_eq!(soft.flat_cells(), 0);
        let neumann_only = SorOptions {
            walls: WallCondition::Robin {
                a: 1.0,
                b: 0.0,
                g: 0.0,
            },
            ..SorOptions::default()
        };
        let open = Raster::from_polygons(
            &rect(0.0, 0.0, 1.0, 1.0),
            &[],
            &[rect(0.4, 0.4, 0.6, 0.6)],
            8,
        )
        .unwrap();
        assert!(matches!(
            GridHarmonic::solve(open, &neumann_only),
            Err(BaselineError::InvalidParameter {
                name: "robin b",
                ..
            })
        ));
        let negative = SorOptions {
            walls: WallCondition::Robin {
                a: -1.0,
                b: 1.0,
                g: 0.0,
            },
            ..SorOptions::default()
        };
        assert!(GridHarmonic::solve(raster, &negative).is_err());
    }

    #[test]
    fn corridor_matches_the_exact_discrete_solution() {
        // Along the corridor ψ_i = (ψ_{i-1} + ψ_{i+1}) / 4 (the cells above and below are
        // obstacles at 0), with ψ = 1 at the goal and 0 at the far wall: the exact solution
        // is ψ_i = sinh((m+1-i)θ) / sinh((m+1)θ) with cosh θ = 2.
        let n = 12;
        let raster = corridor(n);
        assert_eq!(raster.counts().0, n - 3);
        for relaxation in [
            Relaxation::GaussSeidel,
            Relaxation::RedBlackSor { omega: None },
        ] {
            let f = GridHarmonic::solve(raster.clone(), &tight(relaxation, Unknown::Psi)).unwrap();
            assert!(f.report().converged);
            let theta = 2.0f64.acosh();
            let m1 = (n - 2) as f64;
            for i in 1..n - 2 {
                let k = 6 * n + 1 + i;
                assert_eq!(f.raster().cells()[k], Cell::Free);
                let exact = ((m1 - i as f64) * theta).sinh() / (m1 * theta).sinh();
                assert!(
                    (f.values()[k] - exact).abs() < 1e-12,
                    "cell {i}: {} vs {exact}",
                    f.values()[k]
                );
            }
        }
    }

    #[test]
    fn red_black_sor_needs_far_fewer_sweeps_than_gauss_seidel() {
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[rect(3.0, 2.0, 4.0, 8.0)],
            &[rect(8.0, 8.0, 9.0, 9.0)],
            48,
        )
        .unwrap();
        let opts = |relaxation| SorOptions {
            relaxation,
            stop: StopRule::Residual(1e-9),
            ..SorOptions::default()
        };
        let gs = GridHarmonic::solve(raster.clone(), &opts(Relaxation::GaussSeidel)).unwrap();
        let sor =
            GridHarmonic::solve(raster, &opts(Relaxation::RedBlackSor { omega: None })).unwrap();
        assert!(gs.report().converged && sor.report().converged);
        assert!(
            sor.report().iterations * 10 < gs.report().iterations,
            "SOR {} vs GS {} sweeps",
            sor.report().iterations,
            gs.report().iterations
        );
        // Both converge to the same discrete solution.
        let diff = gs
            .values()
            .iter()
            .zip(sor.values())
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff < 1e-6, "GS and SOR differ by {diff}");
    }

    #[test]
    fn converged_field_has_no_interior_local_minima() {
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[
                rect(2.0, 2.0, 3.0, 8.0),
                vec![
                    Point::new(4.0, 7.0),
                    Point::new(7.0, 7.0),
                    Point::new(6.0, 9.0),
                ],
                rect(5.0, 4.0, 9.0, 5.0),
            ],
            &[rect(8.2, 1.2, 8.8, 1.8)],
            64,
        )
        .unwrap();
        let f = GridHarmonic::solve(raster, &SorOptions::default()).unwrap();
        assert!(f.report().converged);
        assert!(f.report().residual < 1e-10);
        assert_eq!(f.flat_cells(), 0);
    }

    #[test]
    fn phi_goes_flat_in_a_long_corridor_where_psi_does_not() {
        // ψ decays by 2 − √3 ≈ 0.27 a cell along the corridor: after ~28 cells 1 − ψ rounds
        // to 1, so φ iterated directly is flat there while ψ keeps every cell distinct.
        let raster = corridor(62);
        let psi = GridHarmonic::solve(
            raster.clone(),
            &tight(Relaxation::GaussSeidel, Unknown::Psi),
        )
        .unwrap();
        let phi =
            GridHarmonic::solve(raster, &tight(Relaxation::GaussSeidel, Unknown::Phi)).unwrap();
        assert_eq!(psi.flat_cells(), 0);
        assert!(
            phi.flat_cells() > 20,
            "only {} flat cells",
            phi.flat_cells()
        );
    }

    #[test]
    fn relative_residual_resolves_tiny_psi_where_an_absolute_tolerance_does_not() {
        // ψ falls to ~1e-34 at the corridor's far end. Over-relaxed iterates stopped by an
        // absolute tolerance leave the tiny values unconverged (cells without a higher
        // neighbour); the relative rule gets every cell to relative precision.
        let n = 62;
        let absolute = SorOptions {
            stop: StopRule::Residual(1e-13),
            ..SorOptions::default()
        };
        let absolute = GridHarmonic::solve(corridor(n), &absolute).unwrap();
        let relative = SorOptions {
            stop: StopRule::RelativeResidual(1e-9),
            ..SorOptions::default()
        };
        let f = GridHarmonic::solve(corridor(n), &relative).unwrap();
        assert!(
            f.report().converged && f.report().relative_residual < 1e-9,
            "{:?}",
            f.report()
        );
        assert!(absolute.flat_cells() > 0);
        assert_eq!(f.flat_cells(), 0);
        let theta = 2.0f64.acosh();
        let m1 = (n - 2) as f64;
        for i in 1..n - 2 {
            let exact = ((m1 - i as f64) * theta).sinh() / (m1 * theta).sinh();
            let got = f.values()[6 * n + 1 + i];
            assert!(
                ((got - exact) / exact).abs() < 1e-6,
                "cell {i}: {got} vs {exact}"
            );
        }
    }

    #[test]
    fn the_relative_cascade_resolves_a_serpentine_in_few_sweeps() {
        // Five barriers leave a gap at alternating ends: ψ decays along a long winding
        // corridor, to ~1e-43 in its last leg.
        let barriers: Vec<Vec<Point>> = (1..6)
            .map(|i| {
                let y = 10.0 * i as f64 / 6.0;
                if i % 2 == 1 {
                    rect(0.0, y - 0.15, 8.5, y + 0.15)
                } else {
                    rect(1.5, y - 0.15, 10.0, y + 0.15)
                }
            })
            .collect();
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &barriers,
            &[rect(0.3, 0.3, 0.9, 0.9)],
            96,
        )
        .unwrap();
        let f = GridHarmonic::solve(raster, &SorOptions::default()).unwrap();
        let r = f.report();
        assert!(r.converged && r.relative_residual < 1e-6, "{r:?}");
        assert_eq!(f.flat_cells(), 0);
        let far = f.raster().index_of(Point::new(5.0, 9.5)).unwrap();
        assert!(f.values()[far] < 1e-40, "{}", f.values()[far]);
        // Handing over to Gauss–Seidel right after the first over-relaxed stage takes 3072
        // sweeps here; the cascade of over-relaxed stages on ever smaller values 1840.
        assert!(r.iterations < 2400, "{} sweeps", r.iterations);
    }

    #[test]
    fn bilinear_interpolation_reproduces_cell_values_and_gradient_points_to_goal() {
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[],
            &[rect(8.0, 8.0, 9.0, 9.0)],
            32,
        )
        .unwrap();
        let f = GridHarmonic::solve(raster, &SorOptions::default()).unwrap();
        let k = 10 * 32 + 7;
        let (v, _) = f.value_and_gradient(f.raster().centre(k)).unwrap();
        assert_eq!(v, -f.values()[k]);
        let (_, g) = f.value_and_gradient(Point::new(2.0, 2.0)).unwrap();
        // Descent direction −∇ points up and to the right, toward the goal.
        assert!(g.x < 0.0 && g.y < 0.0, "gradient {g:?}");
        assert!(f.value_and_gradient(Point::new(-5.0, 2.0)).is_none());
    }

    #[test]
    fn the_shared_tracer_follows_the_grid_field_to_the_goal() {
        use harmonic_trajectory::{SmoothOptions, TraceStatus, trace_smooth};
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[rect(2.0, 2.0, 3.0, 8.0), rect(5.0, 4.0, 9.0, 5.0)],
            &[rect(8.2, 1.2, 8.8, 1.8)],
            64,
        )
        .unwrap();
        let f = GridHarmonic::solve(raster, &SorOptions::default()).unwrap();
        for start in [
            Point::new(1.0, 9.0),
            Point::new(0.5, 5.0),
            Point::new(8.0, 8.0),
        ] {
            let path = trace_smooth(&f, start, &SmoothOptions::for_scale(10.0)).unwrap();
            assert_eq!(path.status, TraceStatus::ReachedGoal(0), "from {start}");
            for p in &path.points {
                assert!(
                    f.raster().cell_at(*p).is_some_and(Cell::is_traversable),
                    "{p}"
                );
            }
        }
        let blocked = trace_smooth(&f, Point::new(2.5, 5.0), &SmoothOptions::for_scale(10.0));
        assert_eq!(blocked.unwrap().status, TraceStatus::StartInObstacle);
    }

    #[test]
    fn fallback_moves_to_the_lowest_neighbour() {
        let f = GridHarmonic::solve(corridor(12), &SorOptions::default()).unwrap();
        let n = 12;
        let k = 6 * n + 5;
        assert_eq!(
            f.fallback_step(k, f.raster().centre(k)),
            Fallback::Moved(f.raster().centre(k - 1), k - 1)
        );
        assert_eq!(
            f.fallback_step(6 * n + 2, Point::origin()),
            Fallback::Goal(0)
        );
        assert_eq!(f.fallback_step(0, Point::origin()), Fallback::Stuck);
    }

    #[test]
    fn rejects_bad_omega_and_tolerance() {
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 1.0, 1.0),
            &[],
            &[rect(0.4, 0.4, 0.6, 0.6)],
            8,
        )
        .unwrap();
        let bad = SorOptions {
            relaxation: Relaxation::RedBlackSor { omega: Some(2.0) },
            ..SorOptions::default()
        };
        assert!(matches!(
            GridHarmonic::solve(raster.clone(), &bad),
            Err(BaselineError::InvalidParameter { name: "omega", .. })
        ));
        let bad = SorOptions {
            stop: StopRule::MaxUpdate(f64::NAN),
            ..SorOptions::default()
        };
        assert!(GridHarmonic::solve(raster, &bad).is_err());
    }
}
