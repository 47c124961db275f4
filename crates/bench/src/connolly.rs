//! Connolly, Burns & Weiss (1990): their §4 integer procedure on reconstructions of their
//! experiments' grids (§5), and the superposition counter-example of their §3 (mazes A–D,
//! eqs. 4–12).
//!
//! **The domains are reconstructions.** Figures 1–5 are not in the text; what it gives is each
//! grid's size, the number of goals, and what the domain is: a maze with two goals (Figure 2,
//! 55 × 44, "approximately 200 × 200 units"), "a region with obstacles" and one goal
//! (Figure 3, 30 × 41), "a more complicated domain" (Figure 4, 50 × 50) and one "with a large
//! interior obstacle" (Figure 5, 70 × 70). The grids below have those sizes and kinds; the
//! maze is a seeded random maze with loops, 3-node corridors and 1-node walls.

use harmonic_baselines::{Cell, IntegerOptions, IntegerOutcome, IntegerPass, IntegerRelaxation};
use serde::Serialize;

use crate::paper::CONNOLLY_RUNS;

/// A grid of cells, `index = j * width + i`.
#[derive(Clone, Debug, PartialEq)]
pub struct CellGrid {
    /// Nodes a row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// The cells.
    pub cells: Vec<Cell>,
}

impl CellGrid {
    /// All free inside a wall ring.
    pub fn open(width: usize, height: usize) -> Self {
        let mut cells = vec![Cell::Wall; width * height];
        for j in 1..height - 1 {
            for i in 1..width - 1 {
                cells[j * width + i] = Cell::Free;
            }
        }
        CellGrid {
            width,
            height,
            cells,
        }
    }

    /// Sets the rectangle of columns `i0..i1`, rows `j0..j1` (clipped inside the ring).
    pub fn fill(&mut self, i0: usize, j0: usize, i1: usize, j1: usize, cell: Cell) {
        for j in j0.max(1)..j1.min(self.height - 1) {
            for i in i0.max(1)..i1.min(self.width - 1) {
                self.cells[j * self.width + i] = cell;
            }
        }
    }

    /// From rows of `#` (wall), `.` (free), `G` (goal) and any other character (free),
    /// top row first.
    pub fn from_rows(rows: &[&str]) -> Self {
        let height = rows.len();
        let width = rows.first().map_or(0, |r| r.chars().count());
        let mut cells = vec![Cell::Wall; width * height];
        for (r, row) in rows.iter().enumerate() {
            let j = height - 1 - r;
            for (i, ch) in row.chars().enumerate() {
                cells[j * width + i] = match ch {
                    '#' => Cell::Wall,
                    'G' => Cell::Goal(0),
                    _ => Cell::Free,
                };
            }
        }
        CellGrid {
            width,
            height,
            cells,
        }
    }
}

/// A small seeded generator (SplitMix64), so the maze is the same on every machine.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Figure 2's reconstruction: a 55 × 44 maze of 13 × 10 rooms (3-node corridors, 1-node
/// walls) carved depth first from a seed, a third of the remaining inner walls knocked out
/// (loops, as a hand-drawn maze has), and two goals in opposite rooms.
pub fn fig2_maze() -> CellGrid {
    let (w, h) = (55, 44);
    let (rooms_x, rooms_y) = (13, 10);
    let mut g = CellGrid {
        width: w,
        height: h,
        cells: vec![Cell::Wall; w * h],
    };
    // Room (a, b) occupies columns 1 + 4a .. 4 + 4a, rows 1 + 4b .. 4 + 4b (with the two
    // spare columns and rows past the last room left as wall).
    let room = |g: &mut CellGrid, a: usize, b: usize| {
        g.fill(1 + 4 * a, 1 + 4 * b, 4 + 4 * a, 4 + 4 * b, Cell::Free)
    };
    let open_between = |g: &mut CellGrid, a: usize, b: usize, da: usize, db: usize| {
        if da == 1 {
            g.fill(4 + 4 * a, 1 + 4 * b, 5 + 4 * a, 4 + 4 * b, Cell::Free);
        } else if db == 1 {
            g.fill(1 + 4 * a, 4 + 4 * b, 4 + 4 * a, 5 + 4 * b, Cell::Free);
        }
    };
    let mut rng = SplitMix(1990);
    let mut seen = vec![false; rooms_x * rooms_y];
    let mut stack = vec![(0usize, 0usize)];
    seen[0] = true;
    room(&mut g, 0, 0);
    let mut closed: Vec<(usize, usize, usize, usize)> = Vec::new();
    while let Some(&(a, b)) = stack.last() {
        let mut next = Vec::new();
        if a + 1 < rooms_x && !seen[b * rooms_x + a + 1] {
            next.push((a + 1, b));
        }
        if a > 0 && !seen[b * rooms_x + a - 1] {
            next.push((a - 1, b));
        }
        if b + 1 < rooms_y && !seen[(b + 1) * rooms_x + a] {
            next.push((a, b + 1));
        }
        if b > 0 && !seen[(b - 1) * rooms_x + a] {
            next.push((a, b - 1));
        }
        if next.is_empty() {
            stack.pop();
            continue;
        }
        let (na, nb) = next[rng.below(next.len())];
        seen[nb * rooms_x + na] = true;
        room(&mut g, na, nb);
        let (lo_a, lo_b) = (a.min(na), b.min(nb));
        open_between(&mut g, lo_a, lo_b, a.abs_diff(na), b.abs_diff(nb));
        stack.push((na, nb));
    }
    for b in 0..rooms_y {
        for a in 0..rooms_x {
            if a + 1 < rooms_x {
                closed.push((a, b, 1, 0));
            }
            if b + 1 < rooms_y {
                closed.push((a, b, 0, 1));
            }
        }
    }
    for (a, b, da, db) in closed {
        if rng.below(3) == 0 {
            open_between(&mut g, a, b, da, db);
        }
    }
    // Two goals: the middle node of the rooms at two opposite corners.
    g.cells[2 * w + 2] = Cell::Goal(0);
    let (ga, gb) = (rooms_x - 1, rooms_y - 1);
    g.cells[(2 + 4 * gb) * w + 2 + 4 * ga] = Cell::Goal(1);
    g
}

/// Figure 3's reconstruction: a 30 × 41 region with four rectangular obstacles and one goal.
pub fn fig3_obstacles() -> CellGrid {
    let mut g = CellGrid::open(30, 41);
    g.fill(4, 8, 14, 12, Cell::Obstacle(0));
    g.fill(17, 15, 26, 19, Cell::Obstacle(1));
    g.fill(5, 23, 12, 31, Cell::Obstacle(2));
    g.fill(15, 28, 25, 31, Cell::Obstacle(3));
    g.fill(24, 36, 26, 38, Cell::Goal(0));
    g
}

/// Figure 4's reconstruction: a 50 × 50 domain of interleaved walls (three, from alternate
/// sides, each two thirds of the way across) and two blocks, the goal behind the last wall.
pub fn fig4_domain() -> CellGrid {
    let mut g = CellGrid::open(50, 50);
    for (k, x) in [12usize, 24, 36].into_iter().enumerate() {
        if k % 2 == 0 {
            g.fill(x, 1, x + 2, 34, Cell::Obstacle(k as u32));
        } else {
            g.fill(x, 16, x + 2, 49, Cell::Obstacle(k as u32));
        }
    }
    g.fill(4, 20, 8, 24, Cell::Obstacle(3));
    g.fill(28, 6, 32, 10, Cell::Obstacle(4));
    g.fill(45, 44, 48, 47, Cell::Goal(0));
    g
}

/// Figure 5's reconstruction: a 70 × 70 domain with a large interior obstacle (a 36 × 36
/// block) and three small ones, the goal in a corner.
pub fn fig5_domain() -> CellGrid {
    let mut g = CellGrid::open(70, 70);
    g.fill(17, 17, 53, 53, Cell::Obstacle(0));
    g.fill(5, 40, 12, 44, Cell::Obstacle(1));
    g.fill(58, 10, 62, 30, Cell::Obstacle(2));
    g.fill(30, 58, 45, 62, Cell::Obstacle(3));
    g.fill(62, 62, 66, 66, Cell::Goal(0));
    g
}

/// One of Connolly's experiments: the paper's numbers beside ours on its reconstruction.
#[derive(Clone, Debug, Serialize)]
pub struct ConnollyRow {
    /// The paper's figure.
    pub figure: u8,
    /// Grid size (columns × rows).
    pub grid: (usize, usize),
    /// The paper's iterations ("to converge to a zero error solution"), where given.
    pub paper_iterations: Option<usize>,
    /// The paper's seconds (Lisp on a TI Explorer II).
    pub paper_seconds: f64,
    /// The bits the paper names (64 for Figure 2; "no more than 80" for Figures 4–5).
    pub paper_bits: Option<u32>,
    /// One pass at the paper's bits (64 where it names none): sweeps to no change.
    pub fixed_sweeps: usize,
    /// Flat nodes that pass leaves.
    pub fixed_flat_nodes: usize,
    /// The §4 procedure from 8 bits, shifting by 8: sweeps over all passes.
    pub shifted_sweeps: usize,
    /// Its passes.
    pub passes: Vec<IntegerPass>,
    /// The bits it ended at.
    pub shifted_bits: u32,
    /// How it ended.
    pub outcome: IntegerOutcome,
    /// Our seconds for the procedure (this machine).
    pub seconds: f64,
}

/// Runs the four reconstructions.
pub fn connolly_table() -> Result<Vec<ConnollyRow>, harmonic_baselines::BaselineError> {
    let grids = [fig2_maze(), fig3_obstacles(), fig4_domain(), fig5_domain()];
    let paper_bits = [Some(64), None, Some(80), Some(80)];
    let mut rows = Vec::new();
    for ((g, run), bits) in grids.into_iter().zip(CONNOLLY_RUNS).zip(paper_bits) {
        let fixed = IntegerRelaxation::solve(
            g.width,
            g.height,
            g.cells.clone(),
            &IntegerOptions::fixed(bits.unwrap_or(64)),
        )?;
        let clock = std::time::Instant::now();
        let shifted =
            IntegerRelaxation::solve(g.width, g.height, g.cells, &IntegerOptions::default())?;
        let seconds = clock.elapsed().as_secs_f64();
        rows.push(ConnollyRow {
            figure: run.figure,
            grid: run.grid,
            paper_iterations: run.iterations,
            paper_seconds: run.seconds,
            paper_bits: bits,
            fixed_sweeps: fixed.sweeps(),
            fixed_flat_nodes: fixed.flat_nodes(),
            shifted_sweeps: shifted.sweeps(),
            passes: shifted.passes().to_vec(),
            shifted_bits: shifted.bits(),
            outcome: shifted.outcome(),
            seconds,
        });
    }
    Ok(rows)
}

/// The four mazes of the superposition argument (their Figure 1, reconstructed): the same
/// two door positions relative to P (four nodes left and right of it), two wall layouts, in
/// coordinates with P at the origin on a 17 × 15 grid inside a ring of exterior goal nodes.
///
/// Walls A/B: P's corridor runs straight to both doors; past each door a passage leads out
/// (up from the right door, down from the left). Walls C/D: P's corridor is three nodes
/// long; its left end winds down, right under everything and up to the far side of the
/// *right* door, its right end up, left over the top and down to the far side of the *left*
/// door, and past each door a passage leads out. So in A and C the right door is open, in
/// B and D the left, but the way out from P is right in A and D, left in B and C.
fn maze_free(layout_cd: bool) -> Vec<(i32, i32)> {
    let mut free = Vec::new();
    let mut run = |x0: i32, y0: i32, x1: i32, y1: i32| {
        for x in x0.min(x1)..=x0.max(x1) {
            for y in y0.min(y1)..=y0.max(y1) {
                free.push((x, y));
            }
        }
    };
    if !layout_cd {
        run(-3, 0, 3, 0);
        run(5, 0, 5, 7);
        run(-5, 0, -5, -7);
    } else {
        run(-1, 0, 1, 0);
        // Left end: down, right along the bottom, up, to the right door's far side.
        run(-1, 0, -1, -4);
        run(-1, -4, 6, -4);
        run(6, -4, 6, 0);
        run(5, 0, 6, 0);
        // Past the right door: up and out.
        run(3, 0, 3, 7);
        // Right end: up, left along the top, down, to the left door's far side.
        run(1, 0, 1, 5);
        run(-6, 5, 1, 5);
        run(-6, 5, -6, 0);
        run(-6, 0, -5, 0);
        // Past the left door: down and out.
        run(-3, 0, -3, -7);
    }
    free
}

/// The maze's grid and P's node: `left_open`/`right_open` say which door (the nodes at
/// (−4, 0) and (4, 0)) is free; a closed door is a wall node.
fn maze(layout_cd: bool, left_open: bool, right_open: bool) -> (CellGrid, (usize, usize)) {
    let (w, h) = (19usize, 17usize);
    let to_k = |x: i32, y: i32| ((y + 8) as usize) * w + (x + 9) as usize;
    let mut cells = vec![Cell::Wall; w * h];
    for j in 0..h {
        for i in 0..w {
            if i == 0 || j == 0 || i == w - 1 || j == h - 1 {
                cells[j * w + i] = Cell::Goal(0);
            }
        }
    }
    for (x, y) in maze_free(layout_cd) {
        cells[to_k(x, y)] = Cell::Free;
    }
    if left_open {
        cells[to_k(-4, 0)] = Cell::Free;
    }
    if right_open {
        cells[to_k(4, 0)] = Cell::Free;
    }
    (
        CellGrid {
            width: w,
            height: h,
            cells,
        },
        (9, 8),
    )
}

/// Which way a field moves the effector at P.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// `+x`.
    Right,
    /// `−x`.
    Left,
}

/// One maze of the counter-example.
#[derive(Clone, Debug, Serialize)]
pub struct MazeRow {
    /// `"A"` … `"D"`.
    pub maze: &'static str,
    /// The direction the paper requires at P.
    pub desired: Direction,
    /// The harmonic solution (integer Gauss–Seidel, the §4 procedure): where P's lower
    /// neighbour lies.
    pub harmonic: Direction,
    /// The superposed point potentials' descent direction at P (x-component's sign).
    pub superposition: Direction,
    /// The superposed descent vector −∇φ at P.
    pub superposition_step: [f64; 2],
}

/// The counter-example's result.
#[derive(Clone, Debug, Serialize)]
pub struct SuperpositionResult {
    /// Mazes A–D.
    pub mazes: Vec<MazeRow>,
    /// `(s_a − s_b)·(s_c − s_d)` of the desired unit steps: −4.
    pub desired_dot: f64,
    /// `(∇φ_a − ∇φ_b)·(∇φ_c − ∇φ_d)` of the superposed potentials (eq. 12: `> 0`, since the
    /// two differences are the same vector).
    pub superposition_dot: f64,
    /// `|(∇φ_a − ∇φ_b) − (∇φ_c − ∇φ_d)|`: zero up to rounding (eqs. 8–11).
    pub difference_mismatch: f64,
}

/// Superposed point potentials: a unit source (φ = −ln r) at every wall node of the maze
/// and at every closed door node, a sink (φ = +w ln r) at every exterior goal node with
/// the same total strength as all walls of layout A/B; `−∇φ` at P.
fn superposed_step(g: &CellGrid, p: (usize, usize)) -> [f64; 2] {
    let (px, py) = (p.0 as f64, p.1 as f64);
    let sources = g.cells.iter().filter(|c| **c == Cell::Wall).count() as f64;
    let goals = g
        .cells
        .iter()
        .filter(|c| matches!(c, Cell::Goal(_)))
        .count() as f64;
    let w = sources / goals;
    let (mut gx, mut gy) = (0.0, 0.0);
    for (k, c) in g.cells.iter().enumerate() {
        let (x, y) = ((k % g.width) as f64, (k / g.width) as f64);
        let (dx, dy) = (px - x, py - y);
        let r2 = dx * dx + dy * dy;
        if r2 == 0.0 {
            continue;
        }
        let s = match c {
            Cell::Wall => -1.0,
            Cell::Goal(_) => w,
            _ => 0.0,
        };
        // ∇(s ln r) = s (p − q) / r².
        gx += s * dx / r2;
        gy += s * dy / r2;
    }
    [-gx, -gy]
}

/// Runs the counter-example: the four mazes' harmonic and superposed directions at P.
pub fn superposition_counterexample()
-> Result<SuperpositionResult, harmonic_baselines::BaselineError> {
    let cases: [(&'static str, bool, bool, bool, Direction); 4] = [
        ("A", false, false, true, Direction::Right),
        ("B", false, true, false, Direction::Left),
        ("C", true, false, true, Direction::Left),
        ("D", true, true, false, Direction::Right),
    ];
    let mut mazes = Vec::new();
    let mut grads = Vec::new();
    for (name, layout_cd, left_open, right_open, desired) in cases {
        let (g, p) = maze(layout_cd, left_open, right_open);
        let solved = IntegerRelaxation::solve(
            g.width,
            g.height,
            g.cells.clone(),
            &IntegerOptions::default(),
        )?;
        let k = p.1 * g.width + p.0;
        let (left, right) = (solved.values()[k - 1], solved.values()[k + 1]);
        let left_free = g.cells[k - 1].is_traversable();
        let right_free = g.cells[k + 1].is_traversable();
        let harmonic = match (left_free, right_free) {
            (true, true) if right < left => Direction::Right,
            (true, _) => Direction::Left,
            _ => Direction::Right,
        };
        let step = superposed_step(&g, p);
        grads.push([-step[0], -step[1]]);
        mazes.push(MazeRow {
            maze: name,
            desired,
            harmonic,
            superposition: if step[0] > 0.0 {
                Direction::Right
            } else {
                Direction::Left
            },
            superposition_step: step,
        });
    }
    let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
    let (ab, cd) = (sub(grads[0], grads[1]), sub(grads[2], grads[3]));
    let unit = |d: Direction| if d == Direction::Right { 1.0 } else { -1.0 };
    let s: Vec<f64> = mazes.iter().map(|m| unit(m.desired)).collect();
    Ok(SuperpositionResult {
        desired_dot: (s[0] - s[1]) * (s[2] - s[3]),
        superposition_dot: ab[0] * cd[0] + ab[1] * cd[1],
        difference_mismatch: ((ab[0] - cd[0]).powi(2) + (ab[1] - cd[1]).powi(2)).sqrt(),
        mazes,
    })
}
