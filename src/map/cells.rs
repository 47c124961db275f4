//! The disc robot's free configuration space on the map's own grid, in blocks for the
//! quadtree mesher.
//!
//! A cell is *clear* when every point of its square keeps at least the robot radius from
//! every point of every blocked cell's square (and from the map's edge, past which all is
//! unknown). Between two cell squares `(di, dj)` cells apart the distance is
//! `√(max(|di| − 1, 0)² + max(|dj| − 1, 0)²)` cells, which is the distance between the
//! centres of the first square and of the nearest cell of the second square grown by one
//! cell all round: so the clear cells are those whose centre is at least the radius from
//! the blocked cells dilated by a 3 × 3 square, an exact squared distance on the lattice
//! computed column by column (capped at the radius) and then row by row. A robot whose
//! centre stays on clear cells keeps the radius from every blocked cell: the guarantee is
//! exact, with no tracing or simplification margin.
//!
//! The clear cells may be snapped to blocks of `b × b` cells ([`super::Snap`]): a partly
//! clear block is dropped, which loses at most a block's width of the clear space along its
//! edge and makes the mesh's staircase walls step by blocks — on open floor only
//! ([`snapped_on_open_floor`]), or everywhere ([`snapped`]).

/// The clear cells of a `w × h` grid whose blocked cells are `blocked` (row by row from the
/// bottom), for a robot of `radius` cells. With a radius of zero the clear cells are the
/// cells that are not blocked.
pub(super) fn clear_cells(blocked: &[bool], w: usize, h: usize, radius: f64) -> Vec<bool> {
    if radius <= 0.0 {
        return blocked.iter().map(|&b| !b).collect();
    }
    let grown = dilate(blocked, w, h);
    // Distances at or beyond the radius block nothing: cap there.
    let cap = radius.ceil().min(f64::from(u16::MAX - 1)) as u16;
    let vertical = column_distances(&grown, w, h, cap);
    // A squared lattice distance v is below radius² exactly when v < ⌈radius²⌉.
    let limit = (radius * radius).ceil().min(f64::from(u32::MAX)) as u32;
    let reach = usize::from(cap).saturating_sub(1);
    let mut clear = vec![true; w * h];
    let (mut nearest, mut base) = (vec![0u32; w], vec![0u32; w]);
    for j in 0..h {
        let g = &vertical[j * w..(j + 1) * w];
        for (n, &d) in nearest.iter_mut().zip(g) {
            *n = u32::from(d) * u32::from(d);
        }
        base.copy_from_slice(&nearest);
        for dx in 1..=reach.min(w.saturating_sub(1)) {
            let dx2 = (dx * dx) as u32;
            // Blocked cells dx to the right, then dx to the left.
            for (n, &v) in nearest[..w - dx].iter_mut().zip(&base[dx..]) {
                *n = (*n).min(v + dx2);
            }
            for (n, &v) in nearest[dx..].iter_mut().zip(&base[..w - dx]) {
                *n = (*n).min(v + dx2);
            }
        }
        for (c, &n) in clear[j * w..(j + 1) * w].iter_mut().zip(&nearest) {
            *c = n >= limit;
        }
    }
    clear
}

/// The blocked cells grown by one cell all round (a 3 × 3 square); the map's edge counts as
/// blocked, so the outer ring of cells is always grown over.
fn dilate(blocked: &[bool], w: usize, h: usize) -> Vec<bool> {
    let mut rows = vec![true; w * h];
    for j in 0..h {
        let (src, dst) = (&blocked[j * w..(j + 1) * w], &mut rows[j * w..(j + 1) * w]);
        // The first and last cells stay grown (the map's edge is beside them).
        for (i, d) in dst.iter_mut().enumerate().take(w.saturating_sub(1)).skip(1) {
            *d = src[i - 1] | src[i] | src[i + 1];
        }
    }
    let mut out = vec![false; w * h];
    for j in 0..h {
        if j == 0 || j + 1 == h {
            out[j * w..(j + 1) * w].fill(true);
            continue;
        }
        let (below, here, above) = (
            &rows[(j - 1) * w..j * w],
            &rows[j * w..(j + 1) * w],
            &rows[(j + 1) * w..(j + 2) * w],
        );
        for (o, ((&a, &b), &c)) in out[j * w..(j + 1) * w]
            .iter_mut()
            .zip(below.iter().zip(here).zip(above))
        {
            *o = a | b | c;
        }
    }
    out
}

/// For each cell, the distance in cells to the nearest `grown` cell in its column, capped
/// at `cap` (two sweeps over whole rows, so memory is read in order).
fn column_distances(grown: &[bool], w: usize, h: usize, cap: u16) -> Vec<u16> {
    let mut d = vec![cap; w * h];
    for (dj, &g) in d[..w].iter_mut().zip(&grown[..w]) {
        *dj = if g { 0 } else { cap };
    }
    for j in 1..h {
        let (done, rest) = d.split_at_mut(j * w);
        let below = &done[(j - 1) * w..];
        for ((dj, &g), &b) in rest[..w].iter_mut().zip(&grown[j * w..]).zip(below) {
            *dj = if g { 0 } else { (b + 1).min(cap) };
        }
    }
    for j in (0..h.saturating_sub(1)).rev() {
        let (head, tail) = d.split_at_mut((j + 1) * w);
        for (dj, &a) in head[j * w..].iter_mut().zip(&tail[..w]) {
            *dj = (*dj).min((a + 1).min(cap));
        }
    }
    d
}

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

/// Leads a start on a clear cell outside the meshed blocks into the mesh: the shortest
/// 4-connected walk over clear cells to a meshed cell, through the cells' centres. Each step
/// joins the centres of two side-by-side clear squares inside their union, so the robot keeps
/// its radius along it.
pub(super) struct CellEntry {
    pub(super) width: usize,
    pub(super) height: usize,
    /// Clear cells, row by row from the bottom.
    pub(super) clear: Vec<bool>,
    /// Cells inside the mesh (the goal's component, less the goal's cell).
    pub(super) meshed: Vec<bool>,
    /// Grid coordinates (cells) to world coordinates and back.
    pub(super) frame: super::GridFrame,
    /// The longest walk searched, in cells (a few blocks: the clear cells the blocks left out
    /// lie within a block of the mesh).
    pub(super) reach: usize,
}

impl crate::planner::StartEntry for CellEntry {
    fn lead_in(&self, start: harmonic_mesh::Point) -> Option<Vec<harmonic_mesh::Point>> {
        let (w, h) = (self.width, self.height);
        let g = self.frame.world_to_grid([start.x, start.y]);
        if !(g[0] >= 0.0 && g[1] >= 0.0 && g[0] < w as f64 && g[1] < h as f64) {
            return None;
        }
        let seed = g[1] as usize * w + g[0] as usize;
        if !self.clear[seed] {
            return None;
        }
        // Breadth-first over clear cells within `reach` (Chebyshev) of the start's cell.
        let (si, sj) = (seed % w, seed / w);
        let near = |k: usize| (k % w).abs_diff(si).max((k / w).abs_diff(sj)) <= self.reach;
        let mut from: std::collections::HashMap<usize, usize> = Default::default();
        from.insert(seed, seed);
        let mut queue = std::collections::VecDeque::from([seed]);
        let found = loop {
            let k = queue.pop_front()?;
            if self.meshed[k] {
                break k;
            }
            let (i, j) = (k % w, k / w);
            let steps = [
                (i > 0).then(|| k - 1),
                (i + 1 < w).then(|| k + 1),
                (j > 0).then(|| k - w),
                (j + 1 < h).then(|| k + w),
            ];
            for n in steps.into_iter().flatten() {
                if self.clear[n] && near(n) && !from.contains_key(&n) {
                    from.insert(n, k);
                    queue.push_back(n);
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
        let centre = |k: usize| {
            let p = self
                .frame
                .grid_to_world([(k % w) as f64 + 0.5, (k / w) as f64 + 0.5]);
            harmonic_mesh::Point::new(p[0], p[1])
        };
        // From the start within its own cell to the next cell's centre, and on.
        let mut lead = vec![start];
        lead.extend(cells.iter().skip(1).map(|&k| centre(k)));
        if lead.len() == 1 {
            lead.push(centre(found));
        }
        Some(lead)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact rule, by brute force: the smallest square-to-square distance to a blocked
    /// cell or to the outside of the grid, in cells.
    fn brute_clear(blocked: &[bool], w: usize, h: usize, radius: f64) -> Vec<bool> {
        let sq = |d: isize| (d.abs() - 1).max(0) as f64;
        (0..w * h)
            .map(|k| {
                let (i, j) = ((k % w) as isize, (k / w) as isize);
                let mut best = f64::INFINITY;
                for jj in -1..=h as isize {
                    for ii in -1..=w as isize {
                        let outside = ii < 0 || jj < 0 || ii >= w as isize || jj >= h as isize;
                        if outside || blocked[jj as usize * w + ii as usize] {
                            best = best.min(sq(ii - i).hypot(sq(jj - j)));
                        }
                    }
                }
                best >= radius
            })
            .collect()
    }

    #[test]
    fn clear_cells_match_the_exact_square_distance() {
        let (w, h) = (23, 17);
        let mut rng = harmonic_fixtures::Rng(12345);
        let blocked: Vec<bool> = (0..w * h).map(|_| rng.below(29) == 0).collect();
        for radius in [0.5, 1.0, 2.2, 3.0, 4.4, 6.01] {
            assert_eq!(
                clear_cells(&blocked, w, h, radius),
                brute_clear(&blocked, w, h, radius),
                "radius {radius}"
            );
        }
        assert_eq!(
            clear_cells(&blocked, w, h, 0.0),
            blocked.iter().map(|b| !b).collect::<Vec<_>>()
        );
    }

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
