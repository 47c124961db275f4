//! Connolly, Burns & Weiss (1990), §4: Gauss–Seidel on the 5-point Laplacian in **k-bit
//! integer arithmetic**, with the flat-region count and the left shift by `c` bits:
//!
//! 1. solve with Gauss–Seidel in integers (each free node replaced by the floor of the
//!    average of its four neighbours) until a sweep changes no node;
//! 2. count the flat regions — free nodes none of whose neighbours is strictly smaller;
//! 3. if there are any, shift every value (boundary values too) left by `c` bits and go to 1;
//! 4. stop: every non-boundary node has a neighbour with a smaller value.
//!
//! The goal nodes hold 0 and walls and obstacles the high value `2^bits`, so the precision
//! grows by `c` bits per pass. Values are `u128`, so `bits` stops at 124 (the paper needed
//! at most 80). The grid is any `width × height` array of [`Cell`]s; its outer ring must be
//! blocked (walls or goals).

use std::collections::VecDeque;

use serde::Serialize;

use crate::{BaselineError, Cell};

/// The most bits the `u128` nodes can take (four summed values must not overflow).
pub const MAX_BITS: u32 = 124;

/// Settings of [`IntegerRelaxation::solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegerOptions {
    /// Bits of the first pass (the high boundary value is `2^initial_bits`).
    pub initial_bits: u32,
    /// `c`: bits added by each left shift.
    pub shift: u32,
    /// `k`: the most bits allowed; the procedure stops there even if flat regions remain.
    pub max_bits: u32,
    /// Sweeps allowed in all passes together.
    pub max_sweeps: usize,
}

impl IntegerOptions {
    /// One pass at `k` bits, no shift: Connolly's "64-bit integer arithmetic" run.
    pub fn fixed(bits: u32) -> Self {
        IntegerOptions {
            initial_bits: bits,
            shift: 0,
            max_bits: bits,
            max_sweeps: 10_000_000,
        }
    }
}

impl Default for IntegerOptions {
    /// Start at 8 bits and shift by 8 up to 124.
    fn default() -> Self {
        IntegerOptions {
            initial_bits: 8,
            shift: 8,
            max_bits: MAX_BITS,
            max_sweeps: 10_000_000,
        }
    }
}

/// One pass of the procedure: Gauss–Seidel at `bits` until nothing changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct IntegerPass {
    /// Bits of precision in this pass.
    pub bits: u32,
    /// Sweeps until no node changed (the last sweep changed nothing).
    pub sweeps: usize,
    /// Flat free nodes after it.
    pub flat_nodes: usize,
    /// Flat regions (4-connected groups of flat nodes) after it.
    pub flat_regions: usize,
}

/// How the procedure ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegerOutcome {
    /// No flat region: every free node has a strictly smaller neighbour.
    NoFlatRegion,
    /// Flat regions remain at `max_bits`.
    OutOfBits,
    /// `max_sweeps` ran out before a pass converged.
    SweepLimit,
}

/// The solved integer grid.
#[derive(Clone, Debug)]
pub struct IntegerRelaxation {
    width: usize,
    height: usize,
    cells: Vec<Cell>,
    values: Vec<u128>,
    bits: u32,
    passes: Vec<IntegerPass>,
    outcome: IntegerOutcome,
}

impl IntegerRelaxation {
    /// Runs the procedure on a `width × height` grid (row by row, `index = j * width + i`).
    ///
    /// Errors if the sizes disagree, the grid is smaller than 3 × 3, its outer ring holds a
    /// free node, it has no goal node, or the bit counts are out of range.
    ///
    /// ```
    /// use harmonic_baselines::{Cell, IntegerOptions, IntegerOutcome, IntegerRelaxation};
    /// // A 1-wide corridor 30 nodes long, goal at the left end.
    /// let (w, h) = (32, 3);
    /// let mut cells = vec![Cell::Wall; w * h];
    /// for i in 1..w - 1 { cells[w + i] = Cell::Free; }
    /// cells[w] = Cell::Goal(0);
    /// // 8 bits: the far end goes flat; shifting by 8 bits at a time cures it.
    /// let short = IntegerRelaxation::solve(w, h, cells.clone(), &IntegerOptions::fixed(8)).unwrap();
    /// assert_eq!(short.outcome(), IntegerOutcome::OutOfBits);
    /// let cured = IntegerRelaxation::solve(w, h, cells, &IntegerOptions::default()).unwrap();
    /// assert_eq!(cured.outcome(), IntegerOutcome::NoFlatRegion);
    /// assert_eq!(cured.flat_nodes(), 0);
    /// ```
    pub fn solve(
        width: usize,
        height: usize,
        cells: Vec<Cell>,
        options: &IntegerOptions,
    ) -> Result<Self, BaselineError> {
        if cells.len() != width * height {
            return Err(BaselineError::InvalidParameter {
                name: "cells",
                value: cells.len() as f64,
                reason: "needs width × height cells",
            });
        }
        if width < 3 || height < 3 {
            return Err(BaselineError::GridTooSmall {
                n: width.min(height),
                min: 3,
            });
        }
        let ring_free = (0..width * height).any(|k| {
            let (i, j) = (k % width, k / width);
            (i == 0 || j == 0 || i == width - 1 || j == height - 1) && cells[k] == Cell::Free
        });
        if ring_free {
            return Err(BaselineError::InvalidParameter {
                name: "cells",
                value: 0.0,
                reason: "the grid's outer ring must be walls, obstacles or goals",
            });
        }
        if !cells.iter().any(|c| matches!(c, Cell::Goal(_))) {
            return Err(BaselineError::NoGoal);
        }
        for (name, v) in [
            ("initial_bits", options.initial_bits),
            ("max_bits", options.max_bits),
        ] {
            if v == 0 || v > MAX_BITS {
                return Err(BaselineError::InvalidParameter {
                    name,
                    value: v as f64,
                    reason: "bits must be between 1 and 124",
                });
            }
        }
        if options.initial_bits > options.max_bits {
            return Err(BaselineError::InvalidParameter {
                name: "initial_bits",
                value: options.initial_bits as f64,
                reason: "must not exceed max_bits",
            });
        }
        let high = 1u128 << options.initial_bits;
        let values = cells
            .iter()
            .map(|c| match c {
                Cell::Goal(_) => 0,
                _ => high,
            })
            .collect();
        let mut grid = IntegerRelaxation {
            width,
            height,
            cells,
            values,
            bits: options.initial_bits,
            passes: Vec::new(),
            outcome: IntegerOutcome::SweepLimit,
        };
        let mut budget = options.max_sweeps;
        loop {
            let (sweeps, converged) = grid.gauss_seidel(budget);
            budget -= sweeps;
            let flat = grid.flat_mask();
            grid.passes.push(IntegerPass {
                bits: grid.bits,
                sweeps,
                flat_nodes: flat.iter().filter(|&&f| f).count(),
                flat_regions: grid.regions(&flat),
            });
            if !converged {
                grid.outcome = IntegerOutcome::SweepLimit;
                break;
            }
            if !flat.iter().any(|&f| f) {
                grid.outcome = IntegerOutcome::NoFlatRegion;
                break;
            }
            if options.shift == 0 || grid.bits + options.shift > options.max_bits {
                grid.outcome = IntegerOutcome::OutOfBits;
                break;
            }
            grid.bits += options.shift;
            for v in &mut grid.values {
                *v <<= options.shift;
            }
        }
        Ok(grid)
    }

    /// Gauss–Seidel sweeps until one changes nothing, at most `budget`; returns the sweeps
    /// made and whether the last changed nothing.
    fn gauss_seidel(&mut self, budget: usize) -> (usize, bool) {
        let w = self.width;
        for sweep in 1..=budget {
            let mut changed = false;
            for k in 0..self.values.len() {
                if self.cells[k] != Cell::Free {
                    continue;
                }
                let s = self.values[k - 1]
                    + self.values[k + 1]
                    + self.values[k - w]
                    + self.values[k + w];
                let v = s >> 2;
                if v != self.values[k] {
                    self.values[k] = v;
                    changed = true;
                }
            }
            if !changed {
                return (sweep, true);
            }
        }
        (budget, false)
    }

    /// Free nodes that reach a goal through free nodes (the others are constant by
    /// construction and never counted as flat).
    fn reaches_goal(&self) -> Vec<bool> {
        let w = self.width;
        let mut seen: Vec<bool> = self
            .cells
            .iter()
            .map(|c| matches!(c, Cell::Goal(_)))
            .collect();
        let mut queue: VecDeque<usize> = (0..seen.len()).filter(|&k| seen[k]).collect();
        while let Some(k) = queue.pop_front() {
            let (i, j) = (k % w, k / w);
            let mut visit = |m: usize| {
                if !seen[m] && self.cells[m] == Cell::Free {
                    seen[m] = true;
                    queue.push_back(m);
                }
            };
            if i > 0 {
                visit(k - 1);
            }
            if i + 1 < w {
                visit(k + 1);
            }
            if j > 0 {
                visit(k - w);
            }
            if j + 1 < self.height {
                visit(k + w);
            }
        }
        seen
    }

    fn flat_mask(&self) -> Vec<bool> {
        let w = self.width;
        let reach = self.reaches_goal();
        (0..self.values.len())
            .map(|k| {
                self.cells[k] == Cell::Free
                    && reach[k]
                    && [k - 1, k + 1, k - w, k + w]
                        .iter()
                        .all(|&m| self.values[m] >= self.values[k])
            })
            .collect()
    }

    fn regions(&self, flat: &[bool]) -> usize {
        let w = self.width;
        let mut seen = vec![false; flat.len()];
        let mut count = 0;
        for start in 0..flat.len() {
            if !flat[start] || seen[start] {
                continue;
            }
            count += 1;
            seen[start] = true;
            let mut stack = vec![start];
            while let Some(k) = stack.pop() {
                for m in [k - 1, k + 1, k - w, k + w] {
                    if flat[m] && !seen[m] {
                        seen[m] = true;
                        stack.push(m);
                    }
                }
            }
        }
        count
    }

    /// Flat free nodes now (Connolly's count; 0 when [`IntegerOutcome::NoFlatRegion`]).
    pub fn flat_nodes(&self) -> usize {
        self.flat_mask().iter().filter(|&&f| f).count()
    }

    /// Flat regions now (4-connected groups of flat nodes).
    pub fn flat_regions(&self) -> usize {
        self.regions(&self.flat_mask())
    }

    /// Every pass, the first at `initial_bits`.
    pub fn passes(&self) -> &[IntegerPass] {
        &self.passes
    }

    /// Sweeps over all passes.
    pub fn sweeps(&self) -> usize {
        self.passes.iter().map(|p| p.sweeps).sum()
    }

    /// How it ended.
    pub fn outcome(&self) -> IntegerOutcome {
        self.outcome
    }

    /// Bits of the last pass.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// The node values (goal 0, walls `2^bits`).
    pub fn values(&self) -> &[u128] {
        &self.values
    }

    /// The cells.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// `(width, height)`.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The value at column `i`, row `j` as a fraction of the wall value (`φ ∈ [0, 1]`).
    pub fn phi(&self, i: usize, j: usize) -> f64 {
        self.values[j * self.width + i] as f64 / (1u128 << self.bits) as f64
    }

    /// Steepest descent over the grid nodes from `(i, j)` (to the 4-neighbour with the
    /// smallest value, as the paper's paths), up to a goal; `None` if it starts on a blocked
    /// node or stops at a node with no smaller neighbour.
    pub fn descend(&self, i: usize, j: usize) -> Option<Vec<(usize, usize)>> {
        let w = self.width;
        let mut k = j * w + i;
        if !self.cells.get(k)?.is_traversable() {
            return None;
        }
        let mut path = vec![(i, j)];
        while self.cells[k] == Cell::Free {
            let next = [k - 1, k + 1, k - w, k + w]
                .into_iter()
                .filter(|&m| self.cells[m].is_traversable())
                .min_by_key(|&m| self.values[m])?;
            if self.values[next] >= self.values[k] {
                return None;
            }
            k = next;
            path.push((k % w, k / w));
        }
        Some(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A maze from rows of `#` (wall), `.` (free) and `G` (goal), top row first.
    fn maze(rows: &[&str]) -> (usize, usize, Vec<Cell>) {
        let h = rows.len();
        let w = rows[0].len();
        let mut cells = vec![Cell::Wall; w * h];
        for (r, row) in rows.iter().enumerate() {
            let j = h - 1 - r;
            for (i, ch) in row.chars().enumerate() {
                cells[j * w + i] = match ch {
                    '.' => Cell::Free,
                    'G' => Cell::Goal(0),
                    _ => Cell::Wall,
                };
            }
        }
        (w, h, cells)
    }

    /// A serpentine of 3-wide corridors, the goal at the top left.
    const SERPENTINE: [&str; 17] = [
        "#######################",
        "#G....................#",
        "#.....................#",
        "#.....................#",
        "#################.....#",
        "#.....................#",
        "#.....................#",
        "#.....................#",
        "#.....#################",
        "#.....................#",
        "#.....................#",
        "#.....................#",
        "#################.....#",
        "#.....................#",
        "#.....................#",
        "#.....................#",
        "#######################",
    ];

    #[test]
    fn the_shift_procedure_leaves_no_flat_region_in_a_maze() {
        let (w, h, cells) = maze(&SERPENTINE);
        // Too few bits: the far end of the serpentine is flat.
        let coarse =
            IntegerRelaxation::solve(w, h, cells.clone(), &IntegerOptions::fixed(12)).unwrap();
        assert_eq!(coarse.outcome(), IntegerOutcome::OutOfBits);
        assert!(coarse.flat_nodes() > 0 && coarse.flat_regions() > 0);
        // Connolly's procedure: shift until none is left.
        let g = IntegerRelaxation::solve(w, h, cells, &IntegerOptions::default()).unwrap();
        assert_eq!(
            g.outcome(),
            IntegerOutcome::NoFlatRegion,
            "{:?}",
            g.passes()
        );
        assert_eq!(g.flat_nodes(), 0);
        assert!(g.passes().len() >= 2);
        assert!(g.passes().windows(2).all(|p| p[1].bits == p[0].bits + 8));
        assert_eq!(g.passes().last().unwrap().flat_nodes, 0);
        // Every free node descends to the goal over the grid.
        for j in 0..h {
            for i in 0..w {
                if g.cells()[j * w + i] == Cell::Free {
                    let path = g.descend(i, j).expect("no flat node stops a descent");
                    assert_eq!(
                        g.cells()[{
                            let (a, b) = *path.last().unwrap();
                            b * w + a
                        }],
                        Cell::Goal(0)
                    );
                }
            }
        }
    }

    #[test]
    fn integer_fixed_point_is_the_discrete_harmonic_function_to_a_unit() {
        // A square with the goal on one side: the integer fixed point differs from the
        // float Gauss–Seidel solution by a few units of the last place.
        let n = 12;
        let mut cells = vec![Cell::Wall; n * n];
        for j in 1..n - 1 {
            for i in 1..n - 1 {
                cells[j * n + i] = Cell::Free;
            }
        }
        for c in &mut cells[1..n - 1] {
            *c = Cell::Goal(0);
        }
        let g = IntegerRelaxation::solve(n, n, cells.clone(), &IntegerOptions::fixed(40)).unwrap();
        assert_eq!(g.outcome(), IntegerOutcome::NoFlatRegion);
        let mut u: Vec<f64> = cells
            .iter()
            .map(|c| if matches!(c, Cell::Goal(_)) { 0.0 } else { 1.0 })
            .collect();
        for _ in 0..5000 {
            for k in 0..u.len() {
                if cells[k] == Cell::Free {
                    u[k] = 0.25 * (u[k - 1] + u[k + 1] + u[k - n] + u[k + n]);
                }
            }
        }
        for j in 1..n - 1 {
            for i in 1..n - 1 {
                assert!((g.phi(i, j) - u[j * n + i]).abs() < 1e-9, "({i}, {j})");
            }
        }
    }

    #[test]
    fn rejects_bad_grids() {
        let (w, h, mut cells) = maze(&SERPENTINE);
        assert!(
            IntegerRelaxation::solve(w, h, cells[1..].to_vec(), &IntegerOptions::default())
                .is_err()
        );
        let opts = IntegerOptions {
            max_bits: 125,
            ..IntegerOptions::default()
        };
        assert!(IntegerRelaxation::solve(w, h, cells.clone(), &opts).is_err());
        cells[0] = Cell::Free;
        assert!(IntegerRelaxation::solve(w, h, cells.clone(), &IntegerOptions::default()).is_err());
        let no_goal: Vec<Cell> = cells
            .iter()
            .map(|&c| {
                if matches!(c, Cell::Goal(_)) {
                    Cell::Free
                } else {
                    Cell::Wall
                }
            })
            .map(|c| if c == Cell::Free { Cell::Wall } else { c })
            .collect();
        assert_eq!(
            IntegerRelaxation::solve(w, h, no_goal, &IntegerOptions::default()).unwrap_err(),
            BaselineError::NoGoal
        );
    }
}
