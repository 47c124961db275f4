//! The disc robot's free configuration space on the map's own grid, in blocks for the
//! quadtree mesher.
//!
//! A cell is *clear* when every point of its square keeps at least the robot radius from
//! every point of every blocked cell's square (and from the map's edge, past which all is
//! unknown): [`super::bits::clear_cells`]. A robot whose centre stays on clear cells keeps
//! the radius from every blocked cell: the guarantee is exact, with no tracing or
//! simplification margin.
//!
//! The clear cells may be snapped to blocks of `b × b` cells ([`super::Snap`]): a partly
//! clear block is dropped, which loses at most a block's width of the clear space along its
//! edge and makes the mesh's staircase walls step by blocks — on open floor only
//! ([`snapped_on_open_floor`]), or everywhere ([`snapped`]).

use super::bits::BitGrid;

/// Blocks of `b × b` cells (the last row and column of blocks may stick out past the grid):
/// free when every cell of the block is on the grid and clear. Returns the blocks and the
/// block grid's width and height.
pub(super) fn blocks(clear: &[bool], w: usize, h: usize, b: usize) -> (Vec<bool>, usize, usize) {
    let (bw, bh) = (w.div_ceil(b), h.div_ceil(b));
    let mut out = vec![true; bw * bh];
    for j in 0..bh * b {
        let row = (j < h).then(|| &clear[j * w..(j + 1) * w]);
        let dst = &mut out[(j / b) * bw..(j / b + 1) * bw];
        for (bi, o) in dst.iter_mut().enumerate() {
            *o &= row.is_some_and(|r| (bi * b..bi * b + b).all(|i| i < w && r[i]));
        }
    }
    (out, bw, bh)
}

/// The clear cells in blocks of `b × b` cells that are wholly clear (a wall's staircase then
/// steps by whole blocks, which gives up at most a block's width of clear space along it).
pub(super) fn snapped(clear: &[bool], w: usize, h: usize, b: usize) -> Vec<bool> {
    let (full, bw, _) = blocks(clear, w, h, b);
    let mut out = clear.to_vec();
    for (j, row) in out.chunks_mut(w).enumerate() {
        let blocks_row = &full[(j / b) * bw..(j / b + 1) * bw];
        for (i, c) in row.iter_mut().enumerate() {
            *c &= blocks_row[i / b];
        }
    }
    out
}

/// The clear cells snapped to blocks of `b × b` cells on open floor only: a block that is
/// partly clear is dropped when it has wholly clear blocks beside it (8-neighbours) and each
/// of them lies in an `s × s` square of wholly clear blocks (the blocks' morphological
/// opening). Along a wall of a room the staircase then steps by blocks; in a passage or a
/// door narrower than `s` blocks no block is dropped, so it keeps its full width.
pub(super) fn snapped_on_open_floor(
    clear: &[bool],
    w: usize,
    h: usize,
    b: usize,
    s: usize,
) -> Vec<bool> {
    let (full, bw, bh) = blocks(clear, w, h, b);
    // The opening: erode by the s × s square, then dilate by it.
    let square = |src: &[bool], run| {
        let rows = window(src, bw, bh, s, Axis::Row, run);
        window(&rows, bw, bh, s, Axis::Column, run)
    };
    let open = square(&square(&full, Run::AllAhead), Run::AnyBehind);
    let mut drop = vec![false; bw * bh];
    for j in 0..bh {
        for i in 0..bw {
            if full[j * bw + i] {
                continue;
            }
            let (mut beside, mut all_open) = (false, true);
            for (dx, dy) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let (x, y) = (i as isize + dx, j as isize + dy);
                if x < 0 || y < 0 || x as usize >= bw || y as usize >= bh {
                    continue;
                }
                let k = y as usize * bw + x as usize;
                if full[k] {
                    beside = true;
                    all_open &= open[k];
                }
            }
            drop[j * bw + i] = beside && all_open;
        }
    }
    let mut out = clear.to_vec();
    for (j, row) in out.chunks_mut(w).enumerate() {
        let blocks_row = &drop[(j / b) * bw..(j / b + 1) * bw];
        for (i, c) in row.iter_mut().enumerate() {
            *c &= !blocks_row[i / b];
        }
    }
    out
}

/// Along which lines [`window`] runs.
#[derive(Clone, Copy)]
enum Axis {
    Row,
    Column,
}

/// What [`window`] asks of the `s` cells of a run.
#[derive(Clone, Copy)]
enum Run {
    /// All of the `s` cells from this one on are set (false when they leave the grid).
    AllAhead,
    /// Any of the `s` cells up to this one is set.
    AnyBehind,
}

/// A running count over windows of `s` cells along rows or columns.
fn window(src: &[bool], w: usize, h: usize, s: usize, axis: Axis, run: Run) -> Vec<bool> {
    let (lines, len) = match axis {
        Axis::Row => (h, w),
        Axis::Column => (w, h),
    };
    let at = |line: usize, t: usize| match axis {
        Axis::Row => line * w + t,
        Axis::Column => t * w + line,
    };
    let mut out = vec![false; w * h];
    for line in 0..lines {
        let mut count = 0usize;
        match run {
            Run::AllAhead => {
                // Walk backwards: the window is [t, t + s).
                for t in (0..len).rev() {
                    count += usize::from(src[at(line, t)]);
                    if t + s < len {
                        count -= usize::from(src[at(line, t + s)]);
                    }
                    out[at(line, t)] = t + s <= len && count == s;
                }
            }
            Run::AnyBehind => {
                // The window is (t − s, t].
                for t in 0..len {
                    count += usize::from(src[at(line, t)]);
                    if t >= s {
                        count -= usize::from(src[at(line, t - s)]);
                    }
                    out[at(line, t)] = count > 0;
                }
            }
        }
    }
    out
}

/// The Euler number (components − holes) of the cells `inside`, 4-connected, by Gray's
/// bit-quad count over every 2 × 2 window of the grid padded by one empty cell:
/// `(n₁ − n₃ + 2 n_d) / 4`, with n₁ and n₃ the windows holding one or three inside cells and
/// n_d those holding two diagonal ones.
pub(super) fn euler_number(inside: &[bool], w: usize, h: usize) -> i64 {
    let empty = vec![false; w];
    let row = |j: isize| -> &[bool] {
        if j < 0 || j as usize >= h {
            &empty
        } else {
            &inside[j as usize * w..(j as usize + 1) * w]
        }
    };
    let (mut n1, mut n3, mut nd) = (0i64, 0i64, 0i64);
    for j in -1..h as isize {
        let (lo, hi) = (row(j), row(j + 1));
        let mut left = (false, false);
        for i in 0..=w {
            let right = if i < w {
                (lo[i], hi[i])
            } else {
                (false, false)
            };
            let q = [left.0, right.0, left.1, right.1];
            match q.iter().filter(|&&c| c).count() {
                1 => n1 += 1,
                3 => n3 += 1,
                2 if q[0] == q[3] => nd += 1,
                _ => {}
            }
            left = right;
        }
    }
    (n1 - n3 + 2 * nd) / 4
}

/// Leads a start outside the mesh into it over the robot's clear cells: the shortest
/// 4-connected walk from the start's cell over cells clear for the robot radius (exactly,
/// with no margin) to a cell whose centre is in the mesh, through the cells' centres. Each
/// step joins the centres of two side-by-side clear squares inside their union, so the robot
/// keeps its radius along it. The clear cells are found at the first start that needs them.
pub(super) struct CellEntry {
    /// The blocked cells.
    pub(super) blocked: BitGrid,
    /// The robot radius in cells.
    pub(super) radius: f64,
    /// The cells clear for `radius`, when the mesher has them; otherwise each lead-in finds
    /// them in a window around its start.
    pub(super) clear: Option<BitGrid>,
    /// Grid coordinates (cells) to world coordinates and back.
    pub(super) frame: super::GridFrame,
    /// The longest walk searched, in cells (the mesh lies within a few cells of every clear
    /// cell it left out).
    pub(super) reach: usize,
    /// The goal's cell and point (world coordinates), for a planner towards one point goal.
    pub(super) goal: Option<((usize, usize), [f64; 2])>,
    /// The cells clear for `radius` that are 4-connected to the goal's cell, found at the
    /// first start that needs them (to tell an unreachable start from a blocked one).
    pub(super) reachable: std::sync::OnceLock<BitGrid>,
}

impl CellEntry {
    /// The cell of a world point, if it is on the grid (not for NaN or infinite points).
    fn cell_of(&self, p: harmonic_mesh::Point) -> Option<(usize, usize)> {
        let g = self.frame.world_to_grid([p.x, p.y]);
        let (w, h) = (self.blocked.width() as f64, self.blocked.height() as f64);
        (g[0] >= 0.0 && g[1] >= 0.0 && g[0] < w && g[1] < h).then(|| (g[0] as usize, g[1] as usize))
    }

    /// The clear cells around cell `(i, j)`: the mesher's, or those of a window `half` cells
    /// either side of it with the blocked cells within the radius of it (the window's edge
    /// counts as blocked, which only takes clear cells away near it).
    fn clear_around(&self, i: usize, j: usize, half: usize) -> ClearWindow<'_> {
        match &self.clear {
            Some(c) => ClearWindow {
                cells: std::borrow::Cow::Borrowed(c),
                i0: 0,
                j0: 0,
            },
            None => {
                let half = half as isize;
                let (i0, j0) = (i as isize - half, j as isize - half);
                let size = 2 * half as usize + 1;
                let blocked = self.blocked.window(i0, j0, size, size, true);
                ClearWindow {
                    cells: std::borrow::Cow::Owned(super::bits::clear_cells(&blocked, self.radius)),
                    i0,
                    j0,
                }
            }
        }
    }

    /// The clear cells (exactly, for the radius) 4-connected to the goal's cell.
    fn reachable(&self) -> Option<&BitGrid> {
        let ((gi, gj), _) = self.goal?;
        Some(self.reachable.get_or_init(|| {
            let clear = match &self.clear {
                Some(c) => std::borrow::Cow::Borrowed(c),
                None => {
                    std::borrow::Cow::Owned(super::bits::clear_cells(&self.blocked, self.radius))
                }
            };
            super::bits::component(&clear, gi, gj)
        }))
    }
}

impl crate::planner::StartEntry for CellEntry {
    fn goal_point(&self, j: u32) -> Option<harmonic_mesh::Point> {
        let (_, g) = self.goal.filter(|_| j == 0)?;
        Some(harmonic_mesh::Point::new(g[0], g[1]))
    }

    fn direct(&self, start: harmonic_mesh::Point) -> Option<[harmonic_mesh::Point; 2]> {
        let (cell, g) = self.goal?;
        // The goal's cell is clear for the radius (the planner was built), and so is every
        // point of its square: the segment inside it keeps the radius.
        (self.cell_of(start) == Some(cell)).then(|| [start, harmonic_mesh::Point::new(g[0], g[1])])
    }

    fn refusal(&self, start: harmonic_mesh::Point) -> harmonic_trajectory::TraceStatus {
        use harmonic_trajectory::TraceStatus;
        let Some((i, j)) = self.cell_of(start) else {
            // Off this grid but on the map it was cut from: a blocked cell.
            return if self.frame.on_map([start.x, start.y]) {
                TraceStatus::StartInObstacle
            } else {
                TraceStatus::OutsideWorkspace
            };
        };
        if self.blocked.get(i as isize, j as isize) {
            return TraceStatus::StartInObstacle;
        }
        let near = self.radius.ceil() as usize + 2;
        if !self.clear_around(i, j, near).get(i as isize, j as isize) {
            // Too close to a blocked cell for the radius: the robot would touch it.
            return TraceStatus::StartInObstacle;
        }
        match self.reachable() {
            Some(r) if !r.get(i as isize, j as isize) => TraceStatus::Unreachable,
            // Connected, yet no way in was found: the lead-in's reach fell short.
            _ => TraceStatus::Stalled { at: start },
        }
    }

    fn lead_in(
        &self,
        start: harmonic_mesh::Point,
        in_mesh: &dyn Fn(harmonic_mesh::Point) -> bool,
    ) -> Option<Vec<harmonic_mesh::Point>> {
        let (w, h) = (self.blocked.width(), self.blocked.height());
        let g = self.frame.world_to_grid([start.x, start.y]);
        let (si, sj) = self.cell_of(start)?;
        if self.blocked.get(si as isize, sj as isize) {
            return None; // in an occupied (or unknown) cell: no way in, whatever the radius
        }
        // The clear cells: every walk searched, and the blocked cells within the radius of it.
        let clear = self.clear_around(si, sj, self.reach + 4 + self.radius.ceil() as usize + 2);
        let centre = |(i, j): (usize, usize)| {
            let p = self.frame.grid_to_world([i as f64 + 0.5, j as f64 + 0.5]);
            harmonic_mesh::Point::new(p[0], p[1])
        };
        // The first step: to the centre of a clear cell around the start's along a segment
        // that keeps the radius (checked against the blocked cells' squares), nearest first.
        let mut firsts: Vec<(usize, usize)> = (sj.saturating_sub(2)..(sj + 3).min(h))
            .flat_map(|j| (si.saturating_sub(2)..(si + 3).min(w)).map(move |i| (i, j)))
            .filter(|&(i, j)| clear.get(i as isize, j as isize))
            .collect();
        firsts.sort_by_key(|&(i, j)| i.abs_diff(si).max(j.abs_diff(sj)));
        let first = firsts
            .into_iter()
            .find(|&(i, j)| self.segment_keeps_radius(g, [i as f64 + 0.5, j as f64 + 0.5]))?;
        // Breadth-first over clear cells within `reach` (Chebyshev) of the first cell.
        let (si, sj) = first;
        let near = |i: usize, j: usize| i.abs_diff(si).max(j.abs_diff(sj)) <= self.reach;
        let mut from: std::collections::HashMap<(usize, usize), (usize, usize)> =
            Default::default();
        from.insert(first, first);
        let mut queue = std::collections::VecDeque::from([first]);
        // The goal's cell ends a walk too: its centre may lie inside the goal's boundary,
        // which the mesh leaves out (a goal cell that only the mesh's goal hole covers).
        let goal_cell = self.goal.map(|(c, _)| c);
        let found = loop {
            let (i, j) = queue.pop_front()?;
            if Some((i, j)) == goal_cell || in_mesh(centre((i, j))) {
                break (i, j);
            }
            let steps = [
                (i > 0).then(|| (i - 1, j)),
                (i + 1 < w).then(|| (i + 1, j)),
                (j > 0).then(|| (i, j - 1)),
                (j + 1 < h).then(|| (i, j + 1)),
            ];
            for (a, b) in steps.into_iter().flatten() {
                if clear.get(a as isize, b as isize) && near(a, b) && !from.contains_key(&(a, b)) {
                    from.insert((a, b), (i, j));
                    queue.push_back((a, b));
                }
            }
        };
        let mut cells = vec![found];
        while let Some(&k) = cells.last().and_then(|k| from.get(k)) {
            if k == *cells.last()? {
                break;
            }
            cells.push(k);
        }
        cells.reverse();
        // From the start to the first cell's centre, and on from centre to centre; a start
        // on the first cell's centre (to rounding: NavFn's requests are cell centres) does
        // not step to it.
        let on_first = (g[0] - (first.0 as f64 + 0.5))
            .abs()
            .max((g[1] - (first.1 as f64 + 0.5)).abs())
            < 1e-9;
        let skip = usize::from(on_first && cells.len() >= 2);
        let mut lead = vec![start];
        lead.extend(cells.iter().skip(skip).map(|&k| centre(k)));
        if let Some((cell, g)) = self.goal
            && cell == found
        {
            // On to the goal point, inside the goal's clear square (each walk's step joins
            // two side-by-side clear squares, so the last one reaches the goal's).
            if let Some(last) = lead.last_mut().filter(|_| cells.len() > skip) {
                *last = harmonic_mesh::Point::new(g[0], g[1]);
            } else {
                lead.push(harmonic_mesh::Point::new(g[0], g[1]));
            }
        }
        Some(lead)
    }
}

/// Clear cells of a window of the map, addressed by the map's columns and rows.
struct ClearWindow<'a> {
    cells: std::borrow::Cow<'a, BitGrid>,
    i0: isize,
    j0: isize,
}

impl ClearWindow<'_> {
    fn get(&self, i: isize, j: isize) -> bool {
        self.cells.get(i - self.i0, j - self.j0)
    }
}

impl CellEntry {
    /// Whether every point of the segment from `a` to `b` (grid coordinates) keeps the radius
    /// from every blocked cell's square and from the grid's edge.
    fn segment_keeps_radius(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        let (w, h) = (self.blocked.width() as f64, self.blocked.height() as f64);
        let r = self.radius;
        let edge = |p: [f64; 2]| p[0].min(p[1]).min(w - p[0]).min(h - p[1]);
        if edge(a) < r || edge(b) < r {
            return false;
        }
        let reach = r.ceil() as isize + 1;
        let (i0, j0) = (
            a[0].min(b[0]).floor() as isize - reach,
            a[1].min(b[1]).floor() as isize - reach,
        );
        let (i1, j1) = (
            a[0].max(b[0]).floor() as isize + reach,
            a[1].max(b[1]).floor() as isize + reach,
        );
        let point = |x: f64, y: f64| harmonic_mesh::Point::new(x, y);
        for j in j0..=j1 {
            for i in i0..=i1 {
                if !self.blocked.get(i, j) {
                    continue;
                }
                let (x, y) = (i as f64, j as f64);
                let square = [
                    point(x, y),
                    point(x + 1.0, y),
                    point(x + 1.0, y + 1.0),
                    point(x, y + 1.0),
                ];
                let d = harmonic_mesh::geom::segment_polygon_distance(
                    point(a[0], a[1]),
                    point(b[0], b[1]),
                    &square,
                );
                if d < r {
                    return false;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_numbers_count_components_less_holes() {
        let grid = |rows: &[&str]| -> (Vec<bool>, usize, usize) {
            let (w, h) = (rows[0].len(), rows.len());
            let cells = rows
                .iter()
                .rev()
                .flat_map(|r| r.chars().map(|c| c == '#'))
                .collect();
            (cells, w, h)
        };
        let cases: [(&[&str], i64); 5] = [
            (&["#"], 1),
            (&["###", "#.#", "###"], 0),
            (&["#.", ".#"], 2), // diagonal cells are apart (4-connected)
            (&["#####", "#.#.#", "#####"], -1),
            (&["##.##", "#...#", "#####"], 1), // the hole opens to the outside
        ];
        for (rows, e) in cases {
            let (cells, w, h) = grid(rows);
            assert_eq!(euler_number(&cells, w, h), e, "{rows:?}");
        }
    }

    #[test]
    fn open_floor_snaps_but_doors_and_passages_keep_their_width() {
        // Two 64 × 40-cell rooms split by a 2-cell wall at rows 40–41 with a 6-cell door at
        // columns 29–34 (it straddles blocks of 2: columns 28–29 and 34–35 are partly
        // clear). A notch on open floor at (40, 20) leaves block (20, 10) partly clear.
        let (w, h) = (64, 82);
        let mut clear = vec![true; w * h];
        for j in 40..42 {
            for i in 0..w {
                if !(29..35).contains(&i) {
                    clear[j * w + i] = false;
                }
            }
        }
        clear[20 * w + 40] = false;
        let out = snapped_on_open_floor(&clear, w, h, 2, 8);
        assert!(
            !out[20 * w + 41] && !out[21 * w + 40],
            "open floor snaps to the block"
        );
        for j in 40..42 {
            for i in 29..35 {
                assert!(out[j * w + i], "the door keeps cell ({i}, {j})");
            }
        }
        // Snapping everywhere narrows the door to 4 cells.
        let all = snapped(&clear, w, h, 2);
        assert!(!all[40 * w + 29] && !all[40 * w + 34] && all[40 * w + 30]);
    }

    #[test]
    fn snapping_keeps_the_wholly_clear_blocks() {
        let (w, h) = (6, 4);
        let mut clear = vec![true; w * h];
        clear[w + 3] = false; // row 1, column 3: block (1, 0) of 2 × 2 is partly clear
        let out = snapped(&clear, w, h, 2);
        for j in 0..h {
            for i in 0..w {
                assert_eq!(
                    out[j * w + i],
                    !(j < 2 && (2..4).contains(&i)),
                    "({i}, {j})"
                );
            }
        }
    }

    #[test]
    fn blocks_are_free_only_when_all_their_cells_are_clear() {
        // 5 × 3 cells in blocks of 2: the last column of blocks sticks out and is not free.
        let mut clear = vec![true; 15];
        let (b, bw, bh) = blocks(&clear, 5, 3, 2);
        assert_eq!((bw, bh), (3, 2));
        assert_eq!(b, vec![true, true, false, false, false, false]);
        clear[5 + 2] = false; // row 1, column 2: in block (1, 0)
        let (b, _, _) = blocks(&clear, 5, 3, 2);
        assert_eq!(b, vec![true, false, false, false, false, false]);
    }
}
