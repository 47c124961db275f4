//! Occupancy grids as rows of bits: the per-cell passes of the map planners (the robot's
//! clear cells, the goal's component, its outline) at 64 cells a word.
//!
//! A [`BitGrid`] holds one bit per cell, row by row from the bottom, each row padded to whole
//! 64-bit words (the padding bits are always zero). On Nav2's 2000 × 2000-cell maps a pass
//! over a grid of bools took a few milliseconds; a pass over its rows of words takes a tenth
//! of that.

/// One bit per cell of a `width × height` grid, row by row from the bottom; bit `i % 64` of
/// word `i / 64` of a row is column `i`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct BitGrid {
    width: usize,
    height: usize,
    /// Words per row.
    stride: usize,
    words: Vec<u64>,
}

impl BitGrid {
    /// All cells unset.
    pub(crate) fn new(width: usize, height: usize) -> BitGrid {
        let stride = width.div_ceil(64);
        BitGrid {
            width,
            height,
            stride,
            words: vec![0; stride * height],
        }
    }

    /// The cells for which `set(column, row)` holds.
    pub(crate) fn from_fn(
        width: usize,
        height: usize,
        mut set: impl FnMut(usize, usize) -> bool,
    ) -> BitGrid {
        let mut g = BitGrid::new(width, height);
        for j in 0..height {
            let row = &mut g.words[j * g.stride..(j + 1) * g.stride];
            for (w, word) in row.iter_mut().enumerate() {
                let mut bits = 0u64;
                for b in 0..64.min(width - 64 * w) {
                    bits |= u64::from(set(64 * w + b, j)) << b;
                }
                *word = bits;
            }
        }
        g
    }

    /// The grid of the cells of `cells` (row by row, `width` per row) for which `set` holds:
    /// [`BitGrid::from_fn`] over a slice, a word at a time from 64 consecutive cells.
    pub(crate) fn from_slice<T: Copy>(
        width: usize,
        height: usize,
        cells: &[T],
        set: impl Fn(T) -> bool,
    ) -> BitGrid {
        let mut g = BitGrid::new(width, height);
        if width == 0 {
            return g;
        }
        for (j, row) in cells.chunks_exact(width).take(height).enumerate() {
            let words = &mut g.words[j * g.stride..(j + 1) * g.stride];
            for (word, chunk) in words.iter_mut().zip(row.chunks(64)) {
                *word = chunk
                    .iter()
                    .enumerate()
                    .fold(0u64, |bits, (b, &c)| bits | u64::from(set(c)) << b);
            }
        }
        g
    }

    pub(crate) fn width(&self) -> usize {
        self.width
    }

    pub(crate) fn height(&self) -> usize {
        self.height
    }

    /// Row `j`'s words.
    pub(crate) fn row(&self, j: usize) -> &[u64] {
        &self.words[j * self.stride..(j + 1) * self.stride]
    }

    fn row_mut(&mut self, j: usize) -> &mut [u64] {
        &mut self.words[j * self.stride..(j + 1) * self.stride]
    }

    /// Whether cell `(i, j)` is set; cells off the grid are not.
    pub(crate) fn get(&self, i: isize, j: isize) -> bool {
        if i < 0 || j < 0 || i as usize >= self.width || j as usize >= self.height {
            return false;
        }
        let (i, j) = (i as usize, j as usize);
        self.words[j * self.stride + i / 64] >> (i % 64) & 1 == 1
    }

    /// Sets cell `(i, j)` (on the grid).
    pub(crate) fn set(&mut self, i: usize, j: usize) {
        self.put(i, j, true);
    }

    /// Sets cell `(i, j)` (on the grid) to `value`.
    pub(crate) fn put(&mut self, i: usize, j: usize, value: bool) {
        let word = &mut self.words[j * self.stride + i / 64];
        *word = (*word & !(1 << (i % 64))) | (u64::from(value) << (i % 64));
    }

    /// The number of set cells.
    #[cfg(test)]
    pub(crate) fn count(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// The union of two grids of one size.
    pub(crate) fn or(&self, other: &BitGrid) -> BitGrid {
        BitGrid {
            words: self
                .words
                .iter()
                .zip(&other.words)
                .map(|(a, b)| a | b)
                .collect(),
            ..self.clone_shape()
        }
    }

    /// An empty grid of this one's size.
    fn clone_shape(&self) -> BitGrid {
        BitGrid {
            width: self.width,
            height: self.height,
            stride: self.stride,
            words: Vec::new(),
        }
    }

    /// The cells `[i0, i0 + w) × [j0, j0 + h)` as a grid of their own; cells of the window
    /// off this grid are set to `off`.
    pub(crate) fn window(&self, i0: isize, j0: isize, w: usize, h: usize, off: bool) -> BitGrid {
        let inside =
            i0 >= 0 && j0 >= 0 && i0 as usize + w <= self.width && j0 as usize + h <= self.height;
        if inside && i0 % 64 == 0 {
            // Whole words, row by row.
            let (k0, j0) = (i0 as usize / 64, j0 as usize);
            let mut out = BitGrid::new(w, h);
            let mask = out.last_mask();
            let stride = out.stride;
            for j in 0..h {
                let dst = out.row_mut(j);
                dst.copy_from_slice(&self.row(j0 + j)[k0..k0 + stride]);
                if let Some(last) = dst.last_mut() {
                    *last &= mask;
                }
            }
            return out;
        }
        BitGrid::from_fn(w, h, |i, j| {
            let (x, y) = (i0 + i as isize, j0 + j as isize);
            let on = x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height;
            if on { self.get(x, y) } else { off }
        })
    }

    /// The rows and the words of each row holding an unset cell: `(first row, last row + 1,
    /// first word, last word + 1)`, or `None` when every cell is set.
    fn unset_span(&self) -> Option<(usize, usize, usize, usize)> {
        let mask = self.last_mask();
        let (mut j0, mut j1, mut w0, mut w1) = (usize::MAX, 0, usize::MAX, 0);
        for j in 0..self.height {
            for (k, &word) in self.row(j).iter().enumerate() {
                let full = if k + 1 == self.stride { mask } else { u64::MAX };
                if word & full != full {
                    j0 = j0.min(j);
                    j1 = j + 1;
                    w0 = w0.min(k);
                    w1 = w1.max(k + 1);
                }
            }
        }
        (j1 > 0).then_some((j0, j1, w0, w1))
    }

    /// The smallest box holding every unset cell, `[i0, i1, j0, j1]` (half-open columns and
    /// rows), or `None` when every cell is set.
    pub(crate) fn unset_bounds(&self) -> Option<[usize; 4]> {
        let (j0, j1, w0, w1) = self.unset_span()?;
        let mask = self.last_mask();
        let (mut i0, mut i1) = (usize::MAX, 0);
        for j in j0..j1 {
            let row = self.row(j);
            for (k, &word) in row.iter().enumerate().take(w1).skip(w0) {
                let full = if k + 1 == self.stride { mask } else { u64::MAX };
                let unset = !word & full;
                if unset != 0 {
                    i0 = i0.min(64 * k + unset.trailing_zeros() as usize);
                    i1 = i1.max(64 * k + 64 - unset.leading_zeros() as usize);
                }
            }
        }
        Some([i0, i1, j0, j1])
    }

    /// Whether every cell is set.
    pub(crate) fn all(&self) -> bool {
        let mask = self.last_mask();
        (0..self.height).all(|j| {
            let row = self.row(j);
            let (last, full) = row.split_last().expect("a row has a word");
            full.iter().all(|&w| w == u64::MAX) && *last & mask == mask
        })
    }

    /// One bool per cell, row by row from the bottom.
    pub(crate) fn to_bools(&self) -> Vec<bool> {
        let mut out = Vec::with_capacity(self.width * self.height);
        for j in 0..self.height {
            let row = self.row(j);
            out.extend((0..self.width).map(|i| row[i / 64] >> (i % 64) & 1 == 1));
        }
        out
    }

    /// The mask of the last word's bits that are cells.
    fn last_mask(&self) -> u64 {
        match self.width % 64 {
            0 => u64::MAX,
            r => (1u64 << r) - 1,
        }
    }

    /// The runs of set cells of row `j`, as half-open column ranges from left to right,
    /// appended to `out`.
    pub(crate) fn runs(&self, j: usize, out: &mut Vec<(u32, u32)>) {
        let mut open: Option<u32> = None;
        for (w, &word) in self.row(j).iter().enumerate() {
            let base = 64 * w as u32;
            let mut at = 0u32;
            // Alternately the end of the open run (its first unset cell) and the start of
            // the next (the next set cell).
            while at < 64 {
                let rest = word >> at;
                match open {
                    Some(start) => {
                        at += rest.trailing_ones();
                        if at >= 64 {
                            break;
                        }
                        out.push((start, base + at));
                        open = None;
                    }
                    None => {
                        if rest == 0 {
                            break;
                        }
                        at += rest.trailing_zeros();
                        open = Some(base + at);
                    }
                }
            }
        }
        if let Some(start) = open {
            out.push((start, self.width as u32));
        }
    }
}

impl BitGrid {
    /// The cells within `by` cells of a set cell, Chebyshev (a square of side 2·by + 1):
    /// each row grown sideways, then each row the union of the `by` rows either side.
    pub(crate) fn dilated(&self, by: usize) -> BitGrid {
        let mask = self.last_mask();
        let mut wide = self.clone();
        let mut tmp = vec![0u64; self.stride];
        for j in 0..self.height {
            grow_row(wide.row_mut(j), &mut tmp, by, mask);
        }
        let mut out = BitGrid::new(self.width, self.height);
        for j in 0..self.height {
            let rows = j.saturating_sub(by)..(j + by + 1).min(self.height);
            let dst = &mut out.words[j * self.stride..(j + 1) * self.stride];
            for r in rows {
                for (d, s) in dst.iter_mut().zip(wide.row(r)) {
                    *d |= s;
                }
            }
        }
        out
    }

    /// Whether every set cell of this grid is set in `other` (of the same size).
    pub(crate) fn subset_of(&self, other: &BitGrid) -> bool {
        self.words
            .iter()
            .zip(&other.words)
            .all(|(a, b)| a & !b == 0)
    }

    /// The Euler number (components − holes) of the set cells, 4-connected: Gray's bit-quad
    /// count `(n₁ − n₃ + 2 n_d) / 4` over every 2 × 2 window of the grid padded by one unset
    /// cell, 64 windows a word (n₁, n₃: windows holding one or three set cells, n_d: two
    /// diagonal ones).
    pub(crate) fn euler_number(&self) -> i64 {
        let mask = self.last_mask();
        let n = self.stride;
        let word = |j: Option<usize>, k: usize| -> u64 {
            match j {
                Some(j) if k < n => {
                    let w = self.words[j * n + k];
                    if k + 1 == n { w & mask } else { w }
                }
                _ => 0,
            }
        };
        let (mut n1, mut n3, mut nd) = (0i64, 0i64, 0i64);
        for j in 0..=self.height {
            let below = j.checked_sub(1);
            let above = (j < self.height).then_some(j);
            // Window p spans cells p − 1 and p of the rows below and above; its bit is p.
            for k in 0..=n {
                let a1 = word(below, k);
                let b1 = word(above, k);
                let carry = |row: Option<usize>| if k > 0 { word(row, k - 1) >> 63 } else { 0 };
                let a0 = a1 << 1 | carry(below);
                let b0 = b1 << 1 | carry(above);
                let (s1, c1, s2, c2) = (a0 ^ a1, a0 & a1, b0 ^ b1, b0 & b1);
                let one = (s1 & !s2 & !c2) | (s2 & !s1 & !c1);
                let three = (c1 & s2) | (c2 & s1);
                let diagonal = (a0 & b1 & !a1 & !b0) | (a1 & b0 & !a0 & !b1);
                n1 += i64::from(one.count_ones());
                n3 += i64::from(three.count_ones());
                nd += i64::from(diagonal.count_ones());
            }
        }
        (n1 - n3 + 2 * nd) / 4
    }
}

/// `dst |= src` shifted `s` cells towards higher columns (`up`) or lower ones, within a row
/// of `mask`-padded words.
fn or_shifted(dst: &mut [u64], src: &[u64], s: usize, up: bool) {
    let (q, b) = (s / 64, (s % 64) as u32);
    let n = src.len();
    if q >= n {
        return;
    }
    if up {
        for k in (q..n).rev() {
            let lo = src[k - q] << b;
            let carry = if b > 0 && k > q {
                src[k - q - 1] >> (64 - b)
            } else {
                0
            };
            dst[k] |= lo | carry;
        }
    } else {
        for k in 0..n - q {
            let hi = src[k + q] >> b;
            let carry = if b > 0 && k + q + 1 < n {
                src[k + q + 1] << (64 - b)
            } else {
                0
            };
            dst[k] |= hi | carry;
        }
    }
}

/// Grows the set cells of a row `by` cells left and right (`row` becomes the union of its
/// shifts by −by..=by), by doubling steps; `tmp` is scratch of the row's length.
fn grow_row(row: &mut [u64], tmp: &mut [u64], by: usize, mask: u64) {
    let mut reach = 0;
    while reach < by {
        // The union of [−reach, reach] shifted by [−s, s] is gapless when s ≤ reach + 1.
        let s = (reach + 1).min(by - reach);
        if s < 64 {
            // One pass: each word ORs its neighbours' bits shifted in, read before they
            // change (0 < s < 64, so no shift overflows).
            let (s, n) = (s as u32, row.len());
            let mut before = 0u64;
            for k in 0..n {
                let word = row[k];
                let after = if k + 1 < n { row[k + 1] } else { 0 };
                row[k] = word | word << s | word >> s | before >> (64 - s) | after << (64 - s);
                before = word;
            }
        } else {
            tmp.copy_from_slice(row);
            or_shifted(row, tmp, s, true);
            or_shifted(row, tmp, s, false);
        }
        if let Some(last) = row.last_mut() {
            *last &= mask;
        }
        reach += s;
    }
}

/// The cells of a robot of `radius` cells that keep the radius from every blocked cell: a
/// cell is clear when every point of its square is at least `radius` from every point of
/// every blocked cell's square and of the world past the grid's edge.
///
/// Between cells `(di, dj)` apart the squares are `√(max(|di| − 1, 0)² + max(|dj| − 1, 0)²)`
/// apart, so a blocked cell rules out the cells within a rounded square around it: in the
/// rows `|dj| ≤ 1` the `|di| ≤ H(0)` nearest, in the row `|dj| = 1 + e` the `|di| ≤ H(e)`
/// nearest, with `H(e) = 1 + max{m : m² + e² < radius²}`. The blocked rows are gathered
/// vertically and grown horizontally at once, by the differences of `H` from the widest row
/// offset to the narrowest (Horner's scheme), a few word operations per cell.
pub(crate) fn clear_cells(blocked: &BitGrid, radius: f64) -> BitGrid {
    let (w, h) = (blocked.width, blocked.height);
    let mut clear = BitGrid::new(w, h);
    let mask = clear.last_mask();
    if radius.is_nan() || radius <= 0.0 {
        for j in 0..h {
            let out = clear.row_mut(j);
            for (c, &b) in out.iter_mut().zip(blocked.row(j)) {
                *c = !b;
            }
            if let Some(last) = out.last_mut() {
                *last &= mask;
            }
        }
        return clear;
    }
    // A squared lattice distance v is below radius² exactly when v < ⌈radius²⌉.
    let limit = (radius * radius).ceil().min(1e12) as u64;
    let isqrt = |v: u64| -> u64 {
        let mut r = (v as f64).sqrt() as u64;
        while r * r > v {
            r -= 1;
        }
        while (r + 1) * (r + 1) <= v {
            r += 1;
        }
        r
    };
    // The row offsets that reach: |dj| ≤ 1 (e = 0) and |dj| = 1 + e for e = 1..k.
    let k = (isqrt(limit - 1) + 1) as usize;
    // Rows and columns within k of the edge see the world past it.
    if 2 * k >= h || 2 * k >= w {
        return clear;
    }
    let reach: Vec<usize> = (0..k as u64)
        .map(|e| 1 + isqrt(limit - 1 - e * e) as usize)
        .collect();
    // Only cells that are not blocked can be clear: the rows holding some, and the words
    // holding some together with the words the growth reaches from beside them.
    let Some((j0, j1, w0, w1)) = blocked.unset_span() else {
        return clear;
    };
    let spread = k.div_ceil(64) + 1;
    let (w0, w1) = (w0.saturating_sub(spread), (w1 + spread).min(blocked.stride));
    let mask = if w1 == blocked.stride { mask } else { u64::MAX };
    let mut acc = vec![0u64; w1 - w0];
    let mut tmp = vec![0u64; w1 - w0];
    let or_row = |acc: &mut [u64], j: usize| {
        acc.iter_mut()
            .zip(&blocked.row(j)[w0..w1])
            .for_each(|(a, &b)| *a |= b);
    };
    for j in j0.max(k)..j1.min(h - k) {
        // Horner: the widest row offset's rows first, each step grown by the difference of
        // its reach and the next one's, so the rows at offset e are grown by reach[e] in all.
        acc.fill(0);
        for e in 0..k {
            if e == 0 {
                (j - 1..=j + 1).for_each(|r| or_row(&mut acc, r));
            } else {
                or_row(&mut acc, j - 1 - e);
                or_row(&mut acc, j + 1 + e);
            }
            let next = reach.get(e + 1).copied().unwrap_or(0);
            grow_row(&mut acc, &mut tmp, reach[e] - next, mask);
        }
        let out = clear.row_mut(j);
        for (o, &a) in out[w0..w1].iter_mut().zip(&acc) {
            *o = !a;
        }
        // The columns within k of either edge see the world past it.
        for i in (0..k).chain(w - k..w) {
            out[i / 64] &= !(1u64 << (i % 64));
        }
        if let Some(last) = out.last_mut() {
            *last &= mask;
        }
    }
    clear
}

/// The 4-connected component of the set cells of `grid` that holds cell `(i, j)` (empty
/// when that cell is not set): a search over the rows' runs, each run overlapping a run of
/// the row above or below joined at once.
pub(crate) fn component(grid: &BitGrid, i: usize, j: usize) -> BitGrid {
    let (w, h) = (grid.width, grid.height);
    let mut out = BitGrid::new(w, h);
    if !grid.get(i as isize, j as isize) {
        return out;
    }
    // The runs of every row, one list, with each row's first run.
    let mut runs: Vec<(u32, u32)> = Vec::new();
    let mut first = Vec::with_capacity(h + 1);
    for r in 0..h {
        first.push(runs.len());
        grid.runs(r, &mut runs);
    }
    first.push(runs.len());
    let row_of = |run: usize| first.partition_point(|&f| f <= run) - 1;
    let mut seen = vec![false; runs.len()];
    let start = (first[j]..first[j + 1])
        .find(|&r| runs[r].0 as usize <= i && i < runs[r].1 as usize)
        .expect("a set cell lies in a run of its row");
    seen[start] = true;
    let mut stack = vec![start];
    while let Some(r) = stack.pop() {
        let row = row_of(r);
        let (a, b) = runs[r];
        fill(out.row_mut(row), a as usize, b as usize);
        for next in [row.wrapping_sub(1), row + 1] {
            if next >= h {
                continue;
            }
            let lo = first[next];
            let hi = first[next + 1];
            // The runs of the next row that overlap [a, b): from the first that ends after a.
            let from = lo + runs[lo..hi].partition_point(|&(_, e)| e <= a);
            for (q, seen) in seen.iter_mut().enumerate().take(hi).skip(from) {
                if runs[q].0 >= b {
                    break;
                }
                if !*seen {
                    *seen = true;
                    stack.push(q);
                }
            }
        }
    }
    out
}

/// Sets the cells `[a, b)` of a row.
fn fill(row: &mut [u64], a: usize, b: usize) {
    let mut i = a;
    while i < b {
        let (w, bit) = (i / 64, i % 64);
        let n = (64 - bit).min(b - i);
        let ones = if n == 64 {
            u64::MAX
        } else {
            ((1u64 << n) - 1) << bit
        };
        row[w] |= ones;
        i += n;
    }
}

/// Marching squares on the cell centres of `inside` (cells off the grid are outside), with
/// the boundary crossing each centre-to-centre step halfway, on the side the two cells share.
/// Returns closed rings in grid coordinates (cell `(i, j)` is `[i, i + 1] × [j, j + 1]`) with
/// the inside on their left: outer rings counter-clockwise, holes clockwise, no vertex in the
/// middle of a straight run. Where two inside cells touch only at a corner the contour passes
/// between them (the inside is 4-connected), so every ring is simple and rings are disjoint.
///
/// Every point of a ring and of the region it bounds lies within a quarter cell of the union
/// of the inside cells' squares: the contour cuts across an outside cell only at a corner
/// where three inside cells meet it, by a quarter cell.
pub(crate) fn contours(inside: &BitGrid) -> Vec<Vec<[f64; 2]>> {
    let (w, h) = (inside.width as isize, inside.height as isize);
    // Crossings of horizontal centre-to-centre steps: step (i − 1, j)–(i, j) is bit i of row j
    // of `done`, i = 0..=w.
    let mut done = BitGrid::new(inside.width + 1, inside.height);
    let at = |i: isize, j: isize| inside.get(i, j);
    let mut rings = Vec::new();
    for j in 0..h {
        let row = inside.row(j as usize);
        for (wi, &word) in row.iter().enumerate() {
            // Bit b set: cells 64 wi + b − 1 and 64 wi + b differ (the cell left of the
            // row's first is outside).
            let left = (word << 1) | if wi > 0 { row[wi - 1] >> 63 } else { 0 };
            let mut diff = word ^ left;
            while diff != 0 {
                let b = diff.trailing_zeros() as isize;
                diff &= diff - 1;
                let i = 64 * wi as isize + b;
                if i > w || done.get(i, j) {
                    continue;
                }
                rings.push(trace(&at, &mut done, i, j));
            }
        }
        // The step past the row's last cell (i = w) when the last cell is inside.
        if at(w - 1, j) && !done.get(w, j) {
            rings.push(trace(&at, &mut done, w, j));
        }
    }
    rings
}

/// Follows one contour from the crossing between cells `(i − 1, j)` and `(i, j)`.
fn trace(
    at: &impl Fn(isize, isize) -> bool,
    done: &mut BitGrid,
    i: isize,
    j: isize,
) -> Vec<[f64; 2]> {
    // The crossing is between an inside cell `pin` and an outside one `pout`; the contour
    // moves along `d` with the inside on its left.
    let (mut pin, mut pout) = if at(i - 1, j) {
        ((i - 1, j), (i, j))
    } else {
        ((i, j), (i - 1, j))
    };
    let left = |d: (isize, isize)| (-d.1, d.0);
    let right = |d: (isize, isize)| (d.1, -d.0);
    // left(d) points from pout to pin.
    let to_in = (pin.0 - pout.0, pin.1 - pout.1);
    let mut d = right(to_in);
    let start = (pin, pout, d);
    let mut ring: Vec<[f64; 2]> = Vec::new();
    loop {
        if pin.1 == pout.1 {
            let i = pin.0.max(pout.0);
            done.set(i as usize, pin.1 as usize);
        }
        let p = [
            0.5 * (pin.0 + pout.0) as f64 + 0.5,
            0.5 * (pin.1 + pout.1) as f64 + 0.5,
        ];
        // Drop the middle of three collinear points.
        let n = ring.len();
        if n >= 2 && collinear(ring[n - 2], ring[n - 1], p) {
            ring.pop();
        }
        ring.push(p);
        let ahead_in = (pin.0 + d.0, pin.1 + d.1);
        let ahead_out = (pout.0 + d.0, pout.1 + d.1);
        match (at(ahead_in.0, ahead_in.1), at(ahead_out.0, ahead_out.1)) {
            // Straight on between the two cells ahead.
            (true, false) => (pin, pout) = (ahead_in, ahead_out),
            // Around the outside cell: turn right.
            (true, true) => {
                pin = ahead_out;
                d = right(d);
            }
            // Around the inside cell (also where the cells ahead touch ours only at
            // corners: the inside stays 4-connected): turn left.
            (false, _) => {
                pout = ahead_in;
                d = left(d);
            }
        }
        if (pin, pout, d) == start {
            break;
        }
    }
    // The start (and the last point) may be the middle of a straight run.
    while ring.len() >= 3 && collinear(ring[ring.len() - 2], ring[ring.len() - 1], ring[0]) {
        ring.pop();
    }
    while ring.len() >= 3 && collinear(ring[ring.len() - 1], ring[0], ring[1]) {
        ring.remove(0);
    }
    ring
}

/// Whether `b` is on the line through `a` and `c` (exact on the contours' half-cell points).
fn collinear(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    (b[0] - a[0]) * (c[1] - b[1]) == (b[1] - a[1]) * (c[0] - b[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_mesh::geom::signed_area as area;

    fn bits(cells: &[bool], w: usize, h: usize) -> BitGrid {
        BitGrid::from_slice(w, h, cells, |c| c)
    }

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
    fn euler_numbers_and_dilation_match_the_cell_by_cell_ones() {
        // Widths across word boundaries (63, 64, 65, 130), sparse and dense grids.
        for (w, h, seed, one_in) in [
            (63, 9, 1u64, 2),
            (64, 12, 2, 3),
            (65, 7, 3, 5),
            (130, 20, 4, 2),
        ] {
            let mut rng = harmonic_fixtures::Rng(seed);
            let set: Vec<bool> = (0..w * h).map(|_| rng.below(one_in) == 0).collect();
            let grid = bits(&set, w, h);
            assert_eq!(
                grid.euler_number(),
                super::super::cells::euler_number(&set, w, h),
                "{w} × {h}"
            );
            for by in [0usize, 1, 3] {
                let near = grid.dilated(by).to_bools();
                for j in 0..h {
                    for i in 0..w {
                        let brute = (j.saturating_sub(by)..(j + by + 1).min(h)).any(|b| {
                            (i.saturating_sub(by)..(i + by + 1).min(w)).any(|a| set[b * w + a])
                        });
                        assert_eq!(near[j * w + i], brute, "{w} × {h}, by {by}, ({i}, {j})");
                    }
                }
                assert!(grid.subset_of(&grid.dilated(by)));
            }
        }
    }

    #[test]
    fn clear_cells_match_the_exact_square_distance() {
        // Widths across word boundaries, radii across the row-offset table.
        for (w, h, seed) in [(23, 17, 1u64), (70, 40, 2), (130, 31, 3), (64, 64, 4)] {
            let mut rng = harmonic_fixtures::Rng(seed);
            let blocked: Vec<bool> = (0..w * h).map(|_| rng.below(37) == 0).collect();
            let grid = bits(&blocked, w, h);
            let free: Vec<bool> = blocked.iter().map(|b| !b).collect();
            assert_eq!(clear_cells(&grid, 0.0).to_bools(), free, "a point robot");
            for radius in [0.5, 1.0, 2.2, 3.0, 4.4, 6.01, 9.5, 14.0] {
                assert_eq!(
                    clear_cells(&grid, radius).to_bools(),
                    brute_clear(&blocked, w, h, radius),
                    "{w} × {h}, radius {radius}"
                );
            }
        }
    }

    #[test]
    fn runs_and_components_are_4_connected() {
        let rows = [
            "##..#####.......",
            "#...#...#.......",
            "###.#.#.#......#",
            "....#.#........#",
        ];
        let (w, h) = (rows[0].len(), rows.len());
        let cells: Vec<bool> = rows
            .iter()
            .rev()
            .flat_map(|r| r.chars().map(|c| c == '#'))
            .collect();
        let grid = bits(&cells, w, h);
        let mut runs = Vec::new();
        grid.runs(3, &mut runs);
        assert_eq!(runs, vec![(0, 2), (4, 9)]);
        // From (0, 3): the left blob only (the diagonal at (2, 1)–(3, 2)... is not a link).
        let c = component(&grid, 0, 3);
        let expect: Vec<bool> = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                cells[k] && (i < 4 && j >= 1)
            })
            .collect();
        assert_eq!(c.to_bools(), expect);
        assert_eq!(component(&grid, 3, 0).count(), 0, "an unset seed");
        // Long runs across words.
        let wide = BitGrid::from_fn(200, 3, |i, j| j != 1 || i == 150);
        assert_eq!(component(&wide, 0, 0).count(), 401);
    }

    #[test]
    fn contours_bound_the_inside_with_quarter_cells_cut_at_corners() {
        // A 3 × 2 block: one ring through the cell-edge midpoints, its corners cut.
        let g = BitGrid::from_fn(6, 5, |i, j| (1..4).contains(&i) && (1..3).contains(&j));
        let rings = contours(&g);
        assert_eq!(rings.len(), 1);
        assert_eq!(rings[0].len(), 8);
        // 6 cells less four corner triangles of 1/8.
        assert!((area(&rings[0]) - 5.5).abs() < 1e-12);
        // A hole: the ring around it is clockwise.
        let g = BitGrid::from_fn(5, 5, |i, j| !(i == 2 && j == 2));
        let mut areas: Vec<f64> = contours(&g).iter().map(|r| area(r)).collect();
        areas.sort_by(f64::total_cmp);
        assert_eq!(areas.len(), 2);
        assert!(areas[0] < 0.0 && areas[1] > 0.0);
        // Diagonal neighbours stay apart: two rings.
        let g = BitGrid::from_fn(4, 4, |i, j| (i, j) == (1, 1) || (i, j) == (2, 2));
        assert_eq!(contours(&g).len(), 2);
    }

    #[test]
    fn contours_of_random_grids_hold_the_inside_area_less_the_corner_cuts() {
        for (w, h, seed) in [(9, 7, 5u64), (70, 12, 6), (131, 9, 7)] {
            let mut rng = harmonic_fixtures::Rng(seed);
            let cells: Vec<bool> = (0..w * h).map(|_| rng.below(3) != 0).collect();
            let g = bits(&cells, w, h);
            let rings = contours(&g);
            let total: f64 = rings.iter().map(|r| area(r)).sum();
            // Each 2 × 2 window with one inside corner cuts 1/8 off, with three adds 1/8,
            // and two diagonal inside corners (kept apart) cut 2/8.
            let at = |i: isize, j: isize| g.get(i, j);
            let mut expect = g.count() as f64;
            for j in -1..h as isize {
                for i in -1..w as isize {
                    let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                    let n = q.iter().filter(|&&c| c).count();
                    expect += match n {
                        1 => -0.125,
                        3 => 0.125,
                        2 if q[0] == q[2] => -0.25,
                        _ => 0.0,
                    };
                }
            }
            assert!(
                (total - expect).abs() < 1e-9,
                "{w} × {h}: {total} vs {expect}"
            );
            // Every horizontal crossing was traced once: the rings' vertices are all at
            // half-cell positions.
            for r in &rings {
                for p in r {
                    assert_eq!((2.0 * p[0]).fract(), 0.0);
                    assert_eq!((2.0 * p[1]).fract(), 0.0);
                }
            }
        }
    }
}
