//! The numeric phase of the accurate LDLᵀ ([`super::AccurateLdlt`], and [`crate::WideLdlt`]
//! in extended-exponent numbers): multifrontal, on dense fronts, subtrees on the thread pool.
//!
//! The columns of `L` are grouped into relaxed supernodes (chains of columns, each the next
//! one's child in the elimination tree, whose patterns nest exactly or nearly: a front may
//! hold a few explicit zeros). A supernode with columns `S` and the rows `R` below its last
//! column owns a dense *front* over `S ∪ R`
//! (column-major, lower triangle): its own magnitudes `w_ij` and excesses `s_j` are scattered
//! in, its children's *update matrices* (the Schur complement magnitudes and excess increments
//! they leave on their rows `R_c ⊆ S ∪ R`) are added in, the columns of `S` are eliminated, and
//! what is left on `R × R` is its own update matrix, passed to its parent.
//!
//! The elimination is GTH's, as in the module above: within a front, column `j` receives from
//! every eliminated `k < j` (in increasing `k`) `s_j += l_jk s_k` and `w_ij += l_ik (l_jk d_k)`,
//! then, if `j ∈ S`, its pivot is recomputed as `d_j = s_j + Σ_i w_ij` and `l_ij = w_ij / d_j`.
//! Every operation adds or multiplies non-negative numbers, in whatever grouping, so the
//! entrywise accuracy argument is unchanged; only the memory access is dense and contiguous
//! (the simplicial left-looking loop it replaces spent its time in scattered gathers).
//!
//! Threads: subtrees of the supernodal tree are factored as independent tasks, and the columns
//! a front's panel of pivots updates are updated in parallel. Each number is computed by the
//! same operations in the same order whatever the split (a front adds its children's update
//! matrices in postorder, a column receives its updates in increasing `k`), so the factor is
//! the same bit for bit at any thread count.

use std::collections::BinaryHeap;
use std::ops::{Add, AddAssign, Div, Mul, Range};

use rayon::prelude::*;

use super::MMatrix;
use crate::error::SolverError;
use crate::wide::Wide;

/// The numbers the elimination runs in: `f64`, or [`Wide`] where `f64` underflows.
pub(crate) trait Magnitude:
    Copy + Send + Sync + Add<Output = Self> + AddAssign + Mul<Output = Self> + Div<Output = Self>
{
    const ZERO: Self;
    fn of(x: f64) -> Self;
    fn is_zero(self) -> bool;
    /// Whether a pivot is usable: positive and finite.
    fn is_pivot(self) -> bool;
}

impl Magnitude for f64 {
    const ZERO: f64 = 0.0;
    #[inline]
    fn of(x: f64) -> f64 {
        x
    }
    #[inline]
    fn is_zero(self) -> bool {
        self == 0.0
    }
    #[inline]
    fn is_pivot(self) -> bool {
        self > 0.0 && self.is_finite()
    }
}

impl Magnitude for Wide {
    const ZERO: Wide = Wide::ZERO;
    #[inline]
    fn of(x: f64) -> Wide {
        Wide::from_f64(x)
    }
    #[inline]
    fn is_zero(self) -> bool {
        Wide::is_zero(self)
    }
    #[inline]
    fn is_pivot(self) -> bool {
        self > Wide::ZERO && self.mantissa().is_finite()
    }
}

const NONE: usize = usize::MAX;

/// Pivots eliminated together before the columns to their right are updated.
const PANEL: usize = 32;

/// Updates (multiply-adds) below which a panel's updates stay on the calling thread.
const PARALLEL_PANEL_WORK: usize = 1 << 16;

/// Total work (multiply-adds) below which subtrees are not split into tasks.
const PARALLEL_TREE_WORK: f64 = 4e6;

/// The supernodes of `L` and their tree.
struct Tree {
    /// Supernode `s` owns the columns `first[s]..first[s + 1]`.
    first: Vec<usize>,
    /// Supernodes in postorder (children before their parent, in increasing order).
    post: Vec<usize>,
    /// `post[at[s]] = s`.
    at: Vec<usize>,
    /// Number of supernodes in each supernode's subtree (itself included).
    size: Vec<usize>,
    /// Multiply-adds of each supernode's subtree (about).
    work: Vec<f64>,
    /// Each supernode's children, in increasing order (`child_ptr` indexes `child`).
    child_ptr: Vec<usize>,
    child: Vec<usize>,
    /// Each supernode's parent ([`NONE`] for roots).
    parent: Vec<usize>,
}

impl Tree {
    fn new(col_ptr: &[usize], row_idx: &[u32]) -> Tree {
        let n = col_ptr.len() - 1;
        let count = |j: usize| col_ptr[j + 1] - col_ptr[j];
        let parent_col = |j: usize| match count(j) {
            0 => NONE,
            _ => row_idx[col_ptr[j]] as usize,
        };
        // Column j joins the supernode of j − 1 when j is j − 1's parent and the front keeps
        // few explicit zeros (relaxed amalgamation, CHOLMOD's default thresholds): a front
        // over columns g..=j and the rows below j holds `width · mm − width (width − 1) / 2`
        // entries, of which `Σ (1 + count)` over its columns are in L's pattern.
        let mut first = Vec::new();
        let mut of_col = vec![0; n];
        let (mut g, mut pattern) = (0usize, 0usize);
        // Zeros of a front over columns g..=j (whose pattern entries so far are `pattern`).
        let zeros_of = |g: usize, j: usize, pattern: usize| {
            let width = j + 1 - g;
            let mm = width + count(j);
            let entries = width * mm - width * (width - 1) / 2;
            (entries - pattern, entries)
        };
        for (j, of) in of_col.iter_mut().enumerate() {
            let joins = j > 0 && parent_col(j - 1) == j && {
                let width = j + 1 - g;
                let (zeros, entries) = zeros_of(g, j, pattern + 1 + count(j));
                let (before, _) = zeros_of(g, j - 1, pattern);
                let fraction = zeros as f64 / entries as f64;
                zeros == before
                    || width <= 4
                    || (width <= 16 && fraction < 0.8)
                    || (width <= 48 && fraction < 0.1)
                    || fraction < 0.05
            };
            if !joins {
                first.push(j);
                (g, pattern) = (j, 0);
            }
            pattern += 1 + count(j);
            *of = first.len() - 1;
        }
        first.push(n);
        let ns = first.len() - 1;
        let parent: Vec<usize> = (0..ns)
            .map(|s| match parent_col(first[s + 1] - 1) {
                NONE => NONE,
                p => of_col[p],
            })
            .collect();
        let mut children = vec![0; ns];
        for &p in &parent {
            if p != NONE {
                children[p] += 1;
            }
        }
        let mut child_ptr = vec![0; ns + 1];
        for s in 0..ns {
            child_ptr[s + 1] = child_ptr[s] + children[s];
        }
        let mut fill = child_ptr.clone();
        let mut child = vec![0; child_ptr[ns]];
        for (s, &p) in parent.iter().enumerate() {
            if p != NONE {
                child[fill[p]] = s;
                fill[p] += 1;
            }
        }
        // A parent's number is above its children's: sizes and work accumulate upwards.
        let mut size = vec![1; ns];
        let mut work: Vec<f64> = (0..ns)
            .map(|s| {
                let width = (first[s + 1] - first[s]) as f64;
                let m = width + count(first[s + 1] - 1) as f64;
                width * m * m
            })
            .collect();
        for s in 0..ns {
            if parent[s] != NONE {
                size[parent[s]] += size[s];
                work[parent[s]] += work[s];
            }
        }
        let mut post = Vec::with_capacity(ns);
        let mut next = child_ptr[..ns].to_vec();
        let mut stack = Vec::new();
        for root in (0..ns).filter(|&s| parent[s] == NONE) {
            stack.push(root);
            while let Some(&s) = stack.last() {
                if next[s] < child_ptr[s + 1] {
                    stack.push(child[next[s]]);
                    next[s] += 1;
                } else {
                    stack.pop();
                    post.push(s);
                }
            }
        }
        let mut at = vec![0; ns];
        for (p, &s) in post.iter().enumerate() {
            at[s] = p;
        }
        Tree {
            first,
            post,
            at,
            size,
            work,
            child_ptr,
            child,
            parent,
        }
    }

    /// Supernode `s`'s columns, and the positions of its entries of `L` in the pattern.
    fn columns(&self, s: usize, col_ptr: &[usize]) -> (Range<usize>, Range<usize>) {
        let (f, e) = (self.first[s], self.first[s + 1]);
        (f..e, col_ptr[f]..col_ptr[e])
    }

    /// The number of children of supernode `s`.
    fn children(&self, s: usize) -> usize {
        self.child_ptr[s + 1] - self.child_ptr[s]
    }

    /// The postorder positions of `s`'s subtree.
    fn range(&self, s: usize) -> Range<usize> {
        self.at[s] + 1 - self.size[s]..self.at[s] + 1
    }

    /// Disjoint subtrees to factor as tasks (in postorder), none when one thread would do:
    /// the largest subtree is split (its root left to the caller) until every subtree is at
    /// most a quarter of a thread's share of the work.
    fn tasks(&self, threads: usize) -> Vec<usize> {
        let roots = (0..self.post.len()).filter(|&s| self.parent[s] == NONE);
        let total: f64 = roots.clone().map(|s| self.work[s]).sum();
        if threads < 2 || total < PARALLEL_TREE_WORK {
            return Vec::new();
        }
        let small = total / (4 * threads) as f64;
        #[derive(PartialEq)]
        struct ByWork(f64, usize);
        impl Eq for ByWork {}
        impl PartialOrd for ByWork {
            fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
                Some(self.cmp(other))
            }
        }
        impl Ord for ByWork {
            fn cmp(&self, other: &Self) -> std::cmp::Ordering {
                self.0.total_cmp(&other.0).then(other.1.cmp(&self.1))
            }
        }
        let mut heap: BinaryHeap<ByWork> = roots.map(|s| ByWork(self.work[s], s)).collect();
        let mut tasks = Vec::new();
        while let Some(ByWork(work, s)) = heap.pop() {
            let kids = &self.child[self.child_ptr[s]..self.child_ptr[s + 1]];
            if work <= small || kids.is_empty() || heap.len() + tasks.len() >= 16 * threads {
                tasks.push(s);
            } else {
                heap.extend(kids.iter().map(|&c| ByWork(self.work[c], c)));
            }
        }
        tasks.sort_by_key(|&s| self.at[s]);
        tasks
    }
}

/// What the elimination reads: the matrix and the symbolic factor.
struct Input<'a> {
    m: &'a MMatrix,
    perm: &'a [usize],
    inv: &'a [usize],
    col_ptr: &'a [usize],
    row_idx: &'a [u32],
}

/// The update matrices waiting for their parents, last pushed on top: each `r × r`,
/// column-major, lower triangle (the diagonal holds excess increments), over the rows below
/// its supernode's last column, all in one buffer.
struct Updates<T> {
    data: Vec<T>,
    /// (supernode, start in `data`) of each update, bottom first.
    tops: Vec<(usize, usize)>,
}

impl<T: Magnitude> Updates<T> {
    fn new() -> Self {
        Updates {
            data: Vec::new(),
            tops: Vec::new(),
        }
    }

    fn push(&mut self, s: usize, u: &[T]) {
        self.tops.push((s, self.data.len()));
        self.data.extend_from_slice(u);
    }

    /// The update on top, removed.
    fn pop(&mut self) -> Option<Update<T>> {
        let (s, start) = self.tops.pop()?;
        Some((s, self.data.split_off(start)))
    }
}

/// A supernode to factor and where its columns of L and its pivots go.
type Front<'a, T> = (usize, &'a mut [T], &'a mut [T]);

/// A subtree root's update matrix: (supernode, `r × r` entries).
type Update<T> = (usize, Vec<T>);

/// Per-thread scratch: the front and the map from rows to front positions.
struct Scratch<T> {
    front: Vec<T>,
    pos: Vec<usize>,
    excess: Vec<T>,
    pivot: Vec<T>,
}

impl<T: Magnitude> Scratch<T> {
    fn new(n: usize) -> Self {
        Scratch {
            front: Vec::new(),
            pos: vec![NONE; n],
            excess: Vec::new(),
            pivot: Vec::new(),
        }
    }
}

/// Factors on the pattern `col_ptr`/`row_idx` (from [`super::symbolic`]) in the order `perm`:
/// the magnitudes of `L` (stored as the pattern) and the pivots.
pub(crate) fn numeric<T: Magnitude>(
    m: &MMatrix,
    perm: &[usize],
    inv: &[usize],
    col_ptr: &[usize],
    row_idx: &[u32],
) -> Result<(Vec<T>, Vec<T>), SolverError> {
    let n = perm.len();
    let mut l = vec![T::ZERO; row_idx.len()];
    let mut d = vec![T::ZERO; n];
    if n == 0 {
        return Ok((l, d));
    }
    let input = Input {
        m,
        perm,
        inv,
        col_ptr,
        row_idx,
    };
    let tree = Tree::new(col_ptr, row_idx);
    let tasks = tree.tasks(rayon::current_num_threads());
    // One scratch per worker thread, made when first needed (its row map is n entries: made
    // per rayon split, as `map_init` does, it was filled a dozen times on a large map). A
    // task that a thread takes up while its own is waiting in a join finds the slot busy
    // and makes its own. Which scratch a front uses changes no number: a front reads only
    // the positions it has just written.
    let slots: Vec<std::sync::Mutex<Option<Scratch<T>>>> = (0..rayon::current_num_threads())
        .map(|_| std::sync::Mutex::new(None))
        .collect();
    // Each supernode's columns of L and pivots, as disjoint slices of the outputs (the
    // supernodes are numbered in column order), handed to the task that factors it: every
    // front writes its columns in place (copied from buffers of the tasks' own, they were
    // faulted and written twice).
    let mut parts: Vec<Option<(&mut [T], &mut [T])>> = Vec::with_capacity(tree.post.len());
    let (mut l_rest, mut d_rest) = (&mut l[..], &mut d[..]);
    for s in 0..tree.post.len() {
        let (cols, entries) = tree.columns(s, col_ptr);
        let (l_part, l_after) = std::mem::take(&mut l_rest).split_at_mut(entries.len());
        let (d_part, d_after) = std::mem::take(&mut d_rest).split_at_mut(cols.len());
        (l_rest, d_rest) = (l_after, d_after);
        parts.push(Some((l_part, d_part)));
    }
    let mut take = |s: usize| {
        parts[s]
            .take()
            .expect("each supernode is factored once, by one task or after them")
    };
    let work: Vec<Vec<Front<'_, T>>> = tasks
        .iter()
        .map(|&root| {
            tree.range(root)
                .map(|p| {
                    let s = tree.post[p];
                    let (l_part, d_part) = take(s);
                    (s, l_part, d_part)
                })
                .collect()
        })
        .collect();
    let updates: Vec<Result<Option<Update<T>>, SolverError>> = work
        .into_par_iter()
        .map(|fronts| {
            let mut slot = rayon::current_thread_index()
                .and_then(|i| slots.get(i))
                .and_then(|m| m.try_lock().ok());
            let mut own = None;
            let scratch = match slot.as_deref_mut() {
                Some(kept) => kept.get_or_insert_with(|| Scratch::new(n)),
                None => own.insert(Scratch::new(n)),
            };
            let mut stack = Updates::new();
            for (s, l_part, d_part) in fronts {
                front(&input, &tree, s, &mut stack, scratch, l_part, d_part)?;
            }
            Ok(stack.pop())
        })
        .collect();
    let mut task_at = vec![NONE; tree.post.len()];
    for (t, &root) in tasks.iter().enumerate() {
        task_at[tree.range(root).start] = t;
    }
    let mut updates = updates.into_iter();
    let mut scratch = Scratch::new(n);
    let mut stack = Updates::new();
    let mut p = 0;
    while p < tree.post.len() {
        if task_at[p] != NONE {
            if let Some((s, u)) = updates.next().expect("one result per task")? {
                stack.push(s, &u);
            }
            p = tree.range(tasks[task_at[p]]).end;
            continue;
        }
        let s = tree.post[p];
        let (l_part, d_part) = take(s);
        front(&input, &tree, s, &mut stack, &mut scratch, l_part, d_part)?;
        p += 1;
    }
    Ok((l, d))
}

/// Assembles supernode `s`'s front (its own entries, its children's update matrices from the
/// top of `stack`), eliminates its columns into `l_out` and `d_out` and pushes its update
/// matrix.
fn front<T: Magnitude>(
    input: &Input<'_>,
    tree: &Tree,
    s: usize,
    stack: &mut Updates<T>,
    scratch: &mut Scratch<T>,
    l_out: &mut [T],
    d_out: &mut [T],
) -> Result<(), SolverError> {
    let Input {
        m,
        perm,
        inv,
        col_ptr,
        row_idx,
    } = *input;
    let arch = pulp::Arch::new();
    let (f, e) = (tree.first[s], tree.first[s + 1]);
    let width = e - f;
    // The front's rows: the supernode's columns, then R, the rows below its last column.
    let below = &row_idx[col_ptr[e - 1]..col_ptr[e]];
    let mm = width + below.len();
    let pos = &mut scratch.pos;
    for (t, p) in pos[f..e].iter_mut().enumerate() {
        *p = t;
    }
    for (t, &i) in below.iter().enumerate() {
        pos[i as usize] = width + t;
    }
    // Column t of the front is read and written only from its diagonal down (rows are in
    // increasing order of `pos`), so only that part is cleared; what lies above it is left
    // from earlier fronts and never read.
    if scratch.front.len() < mm * mm {
        scratch.front.resize(mm * mm, T::ZERO);
    }
    let a = &mut scratch.front[..mm * mm];
    for t in 0..mm {
        a[t * mm + t..(t + 1) * mm].fill(T::ZERO);
    }
    for t in 0..width {
        let c = f + t;
        a[t * mm + t] = T::of(m.excess[perm[c]]);
        let (rows, vals) = m.offdiag.column(perm[c]);
        for (&old_i, &w) in rows.iter().zip(vals) {
            let i = inv[old_i];
            if i > c {
                a[t * mm + pos[i]] = T::of(w);
            }
        }
    }
    let kids = tree.children(s);
    let bottom = stack.tops.len() - kids;
    for &(c, start) in stack.tops[bottom..].iter().rev() {
        let u = &stack.data[start..];
        let last = tree.first[c + 1] - 1;
        let rows = &row_idx[col_ptr[last]..col_ptr[last + 1]];
        let r = rows.len();
        for (b, &rb) in rows.iter().enumerate() {
            let col = &mut a[pos[rb as usize] * mm..][..mm];
            for (&ra, &v) in rows[b..].iter().zip(&u[b * r + b..(b + 1) * r]) {
                col[pos[ra as usize]] += v;
            }
        }
    }
    if kids > 0 {
        stack.data.truncate(stack.tops[bottom].1);
        stack.tops.truncate(bottom);
    }
    let (excess, pivot) = (&mut scratch.excess, &mut scratch.pivot);
    excess.clear();
    excess.resize(width, T::ZERO);
    pivot.clear();
    pivot.resize(width, T::ZERO);
    for p0 in (0..width).step_by(PANEL) {
        let p1 = (p0 + PANEL).min(width);
        // Left-looking within the panel: column j receives k in p0..j, then is a pivot.
        for j in p0..p1 {
            let (done, rest) = a.split_at_mut(j * mm);
            let col = &mut rest[..mm];
            arch.dispatch(|| receive(col, j, &done[p0 * mm..], p0, excess, pivot, mm));
            let sj = col[j];
            let mut dj = sj;
            for &x in &col[j + 1..] {
                dj += x;
            }
            if !dj.is_pivot() {
                return Err(SolverError::Singular {
                    column: perm[f + j],
                });
            }
            excess[j] = sj;
            pivot[j] = dj;
            for x in &mut col[j + 1..] {
                *x = *x / dj;
            }
        }
        // Every column to the right receives the panel's pivots.
        let (done, rest) = a.split_at_mut(p1 * mm);
        let panel = &done[p0 * mm..];
        let (excess, pivot) = (&*excess, &*pivot);
        let receive_one = |(t, col): (usize, &mut [T])| {
            arch.dispatch(|| receive(col, p1 + t, panel, p0, excess, pivot, mm));
        };
        let work = (mm - p1) * (mm - p1) * (p1 - p0) / 2;
        if work >= PARALLEL_PANEL_WORK && rayon::current_num_threads() > 1 {
            rest.par_chunks_mut(mm)
                .with_min_len(8)
                .enumerate()
                .for_each(receive_one);
        } else {
            rest.chunks_mut(mm).enumerate().for_each(receive_one);
        }
    }
    d_out.copy_from_slice(pivot);
    // Each column's entries of L's pattern (an amalgamated front also holds zeros outside it).
    let mut o = 0;
    for t in 0..width {
        let col = &a[t * mm..(t + 1) * mm];
        for &i in &row_idx[col_ptr[f + t]..col_ptr[f + t + 1]] {
            l_out[o] = col[pos[i as usize]];
            o += 1;
        }
    }
    let r = mm - width;
    if r > 0 {
        let start = stack.data.len();
        stack.tops.push((s, start));
        stack.data.resize(start + r * r, T::ZERO);
        let u = &mut stack.data[start..];
        for b in 0..r {
            let col = &a[(width + b) * mm + width..(width + b + 1) * mm];
            u[b * r + b..(b + 1) * r].copy_from_slice(&col[b..]);
        }
    }
    Ok(())
}

/// Column `j` of a front receives the eliminated columns `k0, k0 + 1, …` stored from the
/// start of `done` (each `mm` long): `s_j += l_jk s_k` on the diagonal, `w_ij += l_ik (l_jk
/// d_k)` below it. Four columns at a time (the column is read and written once per four),
/// their contributions summed first: a fixed grouping, as the panels are fixed.
///
/// Inlined into `pulp`'s run-time dispatch, so the loops are compiled for AVX2 where the
/// processor has it: twice the lanes, the same roundings (no multiply-add is fused unless
/// asked for), the same factor bit for bit. One thread factors willow_garage's 88 k unknowns
/// in 50 ms instead of 70; two threads, held back by the page faults of L's first writes
/// and the split of the work, take 32 ms either way.
#[inline(always)]
fn receive<T: Magnitude>(
    col: &mut [T],
    j: usize,
    done: &[T],
    k0: usize,
    excess: &[T],
    pivot: &[T],
    mm: usize,
) {
    let count = (j - k0).min(done.len() / mm);
    let done = &done[..count * mm];
    let mut quads = done.chunks_exact(4 * mm);
    for (q, quad) in quads.by_ref().enumerate() {
        let k = k0 + 4 * q;
        let (l0, rest) = quad.split_at(mm);
        let (l1, rest) = rest.split_at(mm);
        let (l2, l3) = rest.split_at(mm);
        let a = [l0[j], l1[j], l2[j], l3[j]];
        if a.iter().all(|x| x.is_zero()) {
            continue;
        }
        col[j] += (a[0] * excess[k] + a[1] * excess[k + 1])
            + (a[2] * excess[k + 2] + a[3] * excess[k + 3]);
        let w = [
            a[0] * pivot[k],
            a[1] * pivot[k + 1],
            a[2] * pivot[k + 2],
            a[3] * pivot[k + 3],
        ];
        let below = j + 1..mm;
        for ((((x, &y0), &y1), &y2), &y3) in col[below.clone()]
            .iter_mut()
            .zip(&l0[below.clone()])
            .zip(&l1[below.clone()])
            .zip(&l2[below.clone()])
            .zip(&l3[below])
        {
            *x += (y0 * w[0] + y1 * w[1]) + (y2 * w[2] + y3 * w[3]);
        }
    }
    let base = k0 + 4 * (count / 4);
    for (dk, lk) in quads.remainder().chunks_exact(mm).enumerate() {
        let k = base + dk;
        let ljk = lk[j];
        if ljk.is_zero() {
            continue;
        }
        col[j] += ljk * excess[k];
        let w = ljk * pivot[k];
        for (x, &y) in col[j + 1..].iter_mut().zip(&lk[j + 1..]) {
            *x += y * w;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Tree;
    use crate::gallery::triangulated_grid_laplacian;
    use crate::mmatrix::symbolic;
    use crate::ordering::{Ordering, permutation};

    /// The thread-count test in `tests/accurate.rs` compares factors; this checks that a
    /// system of its size is really split, into disjoint subtrees.
    #[test]
    fn a_large_tree_is_split_into_disjoint_subtrees() {
        let (a, coords) = triangulated_grid_laplacian(200, 150);
        let perm = permutation(&a, &Ordering::NestedDissection { coords }).unwrap();
        let mut inv = vec![0; perm.len()];
        for (new, &old) in perm.iter().enumerate() {
            inv[old] = new;
        }
        let (col_ptr, row_idx) = symbolic(&a, &perm, &inv);
        let tree = Tree::new(&col_ptr, &row_idx);
        assert!(tree.tasks(1).is_empty());
        for threads in [2, 4] {
            let tasks = tree.tasks(threads);
            assert!(
                tasks.len() >= threads,
                "{threads} threads: {} tasks",
                tasks.len()
            );
            let ranges: Vec<_> = tasks.iter().map(|&t| tree.range(t)).collect();
            for w in ranges.windows(2) {
                assert!(w[0].end <= w[1].start, "{threads} threads: {ranges:?}");
            }
        }
    }
}
