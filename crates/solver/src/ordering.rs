//! Fill-reducing orderings: faer's AMD, or a geometric nested dissection from coordinates.

use std::sync::atomic::AtomicU32;
use std::sync::atomic::Ordering::Relaxed;

use crate::csc::SymmetricCsc;
use crate::error::SolverError;
use crate::parallel::Parallelism;

/// Fill-reducing ordering used by the direct Cholesky factorisation.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Ordering {
    /// Approximate minimum degree (faer's AMD). Needs nothing but the pattern, so it is the default.
    #[default]
    Amd,
    /// Geometric nested dissection: recursively bisects the unknowns at the median of the longer
    /// bounding-box axis and numbers the vertices on the cut (a vertex separator of the matrix
    /// graph) last. `coords[i]` is the position of unknown `i` (for the FEM, its mesh vertex).
    /// On 2D meshes this gives less fill and a faster factorisation than AMD (see the crate
    /// documentation for figures), but needs the coordinates.
    NestedDissection {
        /// One 2D position per unknown.
        coords: Vec<[f64; 2]>,
    },
    /// The caller's numbering, no reordering (for tests and already-ordered systems).
    Natural,
}

/// Below this many unknowns a nested-dissection piece is numbered as it comes.
const ND_LEAF: usize = 16;

/// Nested-dissection permutation `perm[new] = old` of the unknowns of `a` from their coordinates.
/// The permutation is the same whatever `parallelism`.
pub(crate) fn nested_dissection(
    a: &SymmetricCsc,
    coords: &[[f64; 2]],
    parallelism: Parallelism,
) -> Result<Vec<usize>, SolverError> {
    dissection(a, coords, parallelism, true)
}

/// [`nested_dissection`], scanning only the band along each cut (`banded`) or every unknown of
/// the piece (the plain method, which the tests hold the band to).
fn dissection(
    a: &SymmetricCsc,
    coords: &[[f64; 2]],
    parallelism: Parallelism,
    banded: bool,
) -> Result<Vec<usize>, SolverError> {
    let n = a.n();
    if coords.len() != n {
        return Err(SolverError::DimensionMismatch {
            what: "nested-dissection coordinates",
            expected: n,
            found: coords.len(),
        });
    }
    if let Some(index) = coords
        .iter()
        .position(|c| !(c[0].is_finite() && c[1].is_finite()))
    {
        return Err(SolverError::NonFinite {
            what: "nested-dissection coordinates",
            index,
        });
    }
    let nd = Dissector {
        a,
        stamp: (0..n).map(|_| AtomicU32::new(0)).collect(),
        next_stamp: AtomicU32::new(0),
        parallel_piece: parallelism.nd_piece(n),
        banded,
    };
    // How far each unknown's neighbours lie from it along either axis: an unknown further
    // than that from a cut's median cannot touch the other side, and is neither stamped nor
    // scanned (the same separators, found on the band along the cut only).
    let reach = |v: usize| {
        let at = coords[v];
        a.column(v).0.iter().fold(0.0f64, |r, &u| {
            let d = (coords[u][0] - at[0])
                .abs()
                .max((coords[u][1] - at[1]).abs());
            r.max(d)
        })
    };
    if u32::try_from(n).is_err() {
        return Err(SolverError::Backend(format!(
            "{n} unknowns: the nested dissection numbers unknowns with 32 bits"
        )));
    }
    // The reach in single precision, rounded up: a band at least as wide as the exact one.
    let rounded_up = |d: f64| {
        let r = d as f32;
        if f64::from(r) < d { r.next_up() } else { r }
    };
    let mut all: Vec<Item> = coords
        .iter()
        .enumerate()
        .map(|(v, &at)| Item {
            at,
            reach: rounded_up(reach(v)),
            v: v as u32,
            touches: false,
        })
        .collect();
    let mut perm = vec![0; n];
    nd.dissect(&mut all, &mut perm);
    Ok(perm)
}

/// An unknown of a piece being dissected, its position beside it (the median split reads
/// positions many times; kept here they are not fetched through the unknown's number), in
/// 32 bytes: the median splits move items about, and 40-byte ones cost a fifth more.
#[derive(Clone, Copy)]
struct Item {
    at: [f64; 2],
    /// The largest distance along either axis from the unknown to a neighbour, rounded up.
    reach: f32,
    v: u32,
    /// Whether it touches the other half of its piece's latest cut.
    touches: bool,
}

const _: () = assert!(std::mem::size_of::<Item>() == 32);

struct Dissector<'a> {
    a: &'a SymmetricCsc,
    /// `stamp[v] == a piece's stamp` marks the half of that piece `v` is in. Pieces dissected
    /// at the same time hold disjoint vertices and draw distinct stamps, so a stamp read
    /// across a piece's border (relaxed: any value is fine there) never matches this piece's.
    stamp: Vec<AtomicU32>,
    next_stamp: AtomicU32,
    /// Pieces from this many unknowns split their halves over rayon's pool.
    parallel_piece: Option<usize>,
    /// Whether only the band along a cut is stamped and scanned.
    banded: bool,
}

impl Dissector<'_> {
    fn stamp_of(&self, v: usize) -> u32 {
        self.stamp[v].load(Relaxed)
    }

    /// Numbers `piece` into `perm` in increasing order of the unknowns (a piece too small
    /// or too dense to cut).
    fn number_as_they_come(piece: &mut [Item], perm: &mut [usize]) {
        piece.sort_unstable_by_key(|item| item.v);
        for (p, item) in perm.iter_mut().zip(piece.iter()) {
            *p = item.v as usize;
        }
    }

    /// Numbers the unknowns of `piece` into `perm` (of the same length): the positions
    /// `start..start + piece.len()` of the whole permutation.
    fn dissect(&self, piece: &mut [Item], perm: &mut [usize]) {
        let len = piece.len();
        if len <= ND_LEAF {
            Self::number_as_they_come(piece, perm);
            return;
        }
        // Median split along the longer side of the bounding box.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for item in piece.iter() {
            for d in 0..2 {
                lo[d] = lo[d].min(item.at[d]);
                hi[d] = hi[d].max(item.at[d]);
            }
        }
        let axis = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
        let half = len / 2;
        piece.select_nth_unstable_by(half, |p, q| {
            p.at[axis].total_cmp(&q.at[axis]).then(p.v.cmp(&q.v))
        });
        // Mark the halves, then take as separator the smaller of the two one-sided boundaries
        // (vertices of one half that touch the other), which is a vertex separator either way.
        // Only the band along the cut is marked and scanned: the first half lies at or below
        // the median coordinate `m`, the second at or above it, so an unknown whose reach does
        // not get it to `m` has no neighbour on the other side; and a neighbour on the other
        // side of an unknown is itself in the band (its reach covers the edge between them),
        // so the stamps the scan compares were all written here.
        let m = piece[half].at[axis];
        let in_band =
            |item: &Item| !self.banded || (item.at[axis] - m).abs() <= f64::from(item.reach);
        let stamp_a = self.next_stamp.fetch_add(2, Relaxed) + 1;
        let stamp_b = stamp_a + 1;
        for item in piece[..half].iter().filter(|i| in_band(i)) {
            self.stamp[item.v as usize].store(stamp_a, Relaxed);
        }
        for item in piece[half..].iter().filter(|i| in_band(i)) {
            self.stamp[item.v as usize].store(stamp_b, Relaxed);
        }
        let count = |items: &mut [Item], other: u32| {
            let mut count = 0;
            for item in items {
                item.touches = in_band(item)
                    && self
                        .a
                        .column(item.v as usize)
                        .0
                        .iter()
                        .any(|&u| self.stamp_of(u) == other);
                count += usize::from(item.touches);
            }
            count
        };
        let count_a = count(&mut piece[..half], stamp_b);
        let count_b = count(&mut piece[half..], stamp_a);
        // Move the separator to the end of its half (stable for the rest), then, if it is in the
        // first half, rotate it past the second half to the end of the piece.
        let (lo_start, lo_end) = if count_a <= count_b {
            (0, half)
        } else {
            (half, len)
        };
        let mut keep = lo_start;
        for k in lo_start..lo_end {
            if !piece[k].touches {
                piece.swap(keep, k);
                keep += 1;
            }
        }
        let sep = lo_end - keep;
        if count_a <= count_b {
            piece[keep..].rotate_left(sep);
        }
        let a_len = if count_a <= count_b { keep } else { half };
        let (a_part, rest) = piece.split_at_mut(a_len);
        let (b_part, separator) = rest.split_at_mut(len - a_len - sep);
        if a_part.is_empty() || b_part.is_empty() {
            // Degenerate cut (e.g. a dense block): stop dissecting this piece.
            Self::number_as_they_come(piece, perm);
            return;
        }
        let (perm_a, perm_rest) = perm.split_at_mut(a_part.len());
        let (perm_b, perm_sep) = perm_rest.split_at_mut(b_part.len());
        Self::number_as_they_come(separator, perm_sep);
        if self.parallel_piece.is_some_and(|min| len >= min) {
            rayon::join(
                || self.dissect(a_part, perm_a),
                || self.dissect(b_part, perm_b),
            );
        } else {
            self.dissect(a_part, perm_a);
            self.dissect(b_part, perm_b);
        }
    }
}

impl Ordering {
    /// The permutation `perm[new] = old` this ordering gives `a`'s unknowns (only the pattern
    /// is read). A caller that factors many systems whose unknowns are subsets of one fixed
    /// set (a lattice with varying obstacles) can compute it once and number each subset in
    /// this order, then factor with [`Ordering::Natural`].
    ///
    /// ```
    /// use harmonic_solver::{Ordering, SymmetricCsc};
    /// // The path graph 0 - 1 - 2.
    /// let a = SymmetricCsc::try_new(3, vec![0, 1, 3, 4], vec![1, 0, 2, 1], vec![-1.0; 4])?;
    /// let perm = Ordering::NestedDissection { coords: vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]] }
    ///     .permutation(&a)?;
    /// let mut sorted = perm.clone();
    /// sorted.sort();
    /// assert_eq!(sorted, [0, 1, 2]);
    /// assert_eq!(Ordering::Natural.permutation(&a)?, [0, 1, 2]);
    /// # Ok::<(), harmonic_solver::SolverError>(())
    /// ```
    pub fn permutation(&self, a: &SymmetricCsc) -> Result<Vec<usize>, SolverError> {
        permutation(a, self)
    }
}

/// Fill-reducing permutation `perm[new] = old` of `a`'s pattern, computed here rather than by
/// faer's symbolic Cholesky (for the factorisations of this crate that do not go through faer).
pub(crate) fn permutation(
    a: &SymmetricCsc,
    ordering: &Ordering,
) -> Result<Vec<usize>, SolverError> {
    let n = a.n();
    match ordering {
        Ordering::Natural => Ok((0..n).collect()),
        Ordering::NestedDissection { coords } => {
            nested_dissection(a, coords, Parallelism::default())
        }
        Ordering::Amd => {
            use faer::dyn_stack::{MemBuffer, MemStack};
            use faer::sparse::SymbolicSparseColMatRef;
            use faer::sparse::linalg::amd;
            let mut perm = vec![0usize; n];
            let mut inv = vec![0usize; n];
            let pattern =
                SymbolicSparseColMatRef::new_checked(n, n, a.col_ptr(), None, a.row_idx());
            let mut mem = MemBuffer::try_new(amd::order_scratch::<usize>(n, a.nnz()))
                .map_err(|_| SolverError::Backend("out of memory for AMD workspace".into()))?;
            amd::order(
                &mut perm,
                &mut inv,
                pattern,
                amd::Control::default(),
                MemStack::new(&mut mem),
            )
            .map_err(|e| SolverError::Backend(format!("AMD ordering: {e:?}")))?;
            Ok(perm)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A jittered 40 × 40 grid with one diagonal per square and a few long edges (which give
    /// their ends a wide reach), as a symmetric pattern.
    fn jittered_mesh_graph(seed: u64) -> (SymmetricCsc, Vec<[f64; 2]>) {
        let side = 40;
        let n = side * side;
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let coords: Vec<[f64; 2]> = (0..n)
            .map(|v| {
                let (i, j) = ((v % side) as f64, (v / side) as f64);
                [i + 0.4 * (next() - 0.5), j + 0.4 * (next() - 0.5)]
            })
            .collect();
        let mut columns = vec![Vec::new(); n];
        let mut edge = |u: usize, v: usize| {
            columns[u].push(v);
            columns[v].push(u);
        };
        for v in 0..n {
            let (i, j) = (v % side, v / side);
            if i + 1 < side {
                edge(v, v + 1);
            }
            if j + 1 < side {
                edge(v, v + side);
            }
            if i + 1 < side && j + 1 < side {
                edge(v, v + side + 1);
            }
        }
        for _ in 0..30 {
            let (u, v) = ((next() * n as f64) as usize, (next() * n as f64) as usize);
            if u != v {
                edge(u, v);
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for column in &mut columns {
            column.sort_unstable();
            column.dedup();
            row_idx.extend_from_slice(column);
            col_ptr.push(row_idx.len());
        }
        let values = vec![-1.0; row_idx.len()];
        let a = SymmetricCsc::try_new(n, col_ptr, row_idx, values).expect("symmetric pattern");
        (a, coords)
    }

    #[test]
    fn the_band_along_each_cut_finds_the_same_order_as_scanning_every_unknown() {
        for seed in 1..=5 {
            let (a, coords) = jittered_mesh_graph(seed);
            for parallelism in [Parallelism::Sequential, Parallelism::default()] {
                let banded = dissection(&a, &coords, parallelism, true).expect("banded");
                let plain = dissection(&a, &coords, parallelism, false).expect("plain");
                assert_eq!(banded, plain, "seed {seed}");
                let mut sorted = banded.clone();
                sorted.sort_unstable();
                assert!(
                    sorted.iter().copied().eq(0..a.n()),
                    "seed {seed}: a permutation"
                );
            }
        }
    }
}
