//! Keys grouped by a vertex and sorted within each group; the tetrahedra around each vertex;
//! a tetrahedral mesh's edges numbered from them.
//!
//! A mesh's edges (and faces, [`face_neighbors`](crate::face_neighbors)) are found where
//! they meet their smallest vertex: every tetrahedron that holds one holds that vertex. So
//! the tetrahedra are grouped by vertex once, four `u32` each — a counting sort in two
//! linear passes, no global sort — and each vertex sorts the few tens of edges (or faces) it
//! owns on its own, the vertices on every core. The order is a global sort's (smaller
//! vertex, then larger), so results do not depend on the thread count. Measured on me766's
//! 5.58 M tetrahedra (2 cores, side by side in one run): its 6.5 M edges numbered in
//! 0.41–0.63 s from the table of tetrahedra around each vertex that the mesh kept from
//! finding its faces' neighbours, against 0.81–0.95 s when all 33.5 M per-tetrahedron edge
//! keys were grouped by the smaller vertex (and 0.70 s, in a quieter hour, by one parallel
//! sort of them all).

use rayon::prelude::*;

/// Keys grouped by vertex: the keys of vertex `v` are `keys[start[v]..start[v + 1]]`, sorted.
#[derive(Clone, Debug, PartialEq)]
pub struct Grouped<K> {
    /// Where each vertex's keys begin (`vertices + 1` entries).
    pub start: Vec<usize>,
    /// The keys, by vertex, each group sorted.
    pub keys: Vec<K>,
}

impl<K: Ord + Copy + Default + Send> Grouped<K> {
    /// The keys that `items` calls its argument with (`(vertex, key)`, `vertex <
    /// vertices`), grouped by vertex and sorted. `items` is called twice and must give the
    /// same keys both times (once to count, once to place).
    ///
    /// ```
    /// use harmonic_types::Grouped;
    /// let pairs = [(2u32, 7u64), (0, 5), (2, 1), (0, 9), (1, 3)];
    /// let g = Grouped::by_vertex(3, |emit| pairs.iter().for_each(|&(v, k)| emit(v, k)));
    /// assert_eq!(g.start, vec![0, 2, 3, 5]);
    /// assert_eq!(g.keys, vec![5, 9, 3, 1, 7]);
    /// ```
    pub fn by_vertex(vertices: usize, items: impl Fn(&mut dyn FnMut(u32, K))) -> Self {
        let mut start = vec![0usize; vertices + 1];
        items(&mut |v, _| start[v as usize + 1] += 1);
        for v in 0..vertices {
            start[v + 1] += start[v];
        }
        let mut next = start.clone();
        let mut keys = vec![K::default(); start[vertices]];
        items(&mut |v, k| {
            let slot = &mut next[v as usize];
            keys[*slot] = k;
            *slot += 1;
        });
        drop(next);
        // Each group sorted, a run of vertices per task.
        let mut pieces = Vec::new();
        let mut rest: &mut [K] = &mut keys;
        for (v, end) in vertex_runs(vertices) {
            let (piece, tail) = rest.split_at_mut(start[end] - start[v]);
            pieces.push((v, end, piece));
            rest = tail;
        }
        pieces.into_par_iter().for_each(|(v0, v1, piece)| {
            let base = start[v0];
            for v in v0..v1 {
                piece[start[v] - base..start[v + 1] - base].sort_unstable();
            }
        });
        Grouped { start, keys }
    }

    /// The keys of vertex `v`.
    pub fn of(&self, v: usize) -> &[K] {
        &self.keys[self.start[v]..self.start[v + 1]]
    }
}

/// Vertices `0..vertices` in runs `(first, end)`, one per parallel task: about 64 runs a
/// thread, each of at least 256 vertices.
///
/// ```
/// let runs = harmonic_types::vertex_runs(1000);
/// assert_eq!(runs.first().map(|r| r.0), Some(0));
/// assert_eq!(runs.last().map(|r| r.1), Some(1000));
/// assert!(runs.windows(2).all(|w| w[0].1 == w[1].0));
/// ```
pub fn vertex_runs(vertices: usize) -> Vec<(usize, usize)> {
    let per_task = vertices
        .div_ceil(64 * rayon::current_num_threads().max(1))
        .max(256);
    (0..vertices)
        .step_by(per_task)
        .map(|v| (v, (v + per_task).min(vertices)))
        .collect()
}

impl Grouped<u32> {
    /// The tetrahedra around each of `vertices` vertices, ascending: four `u32` per
    /// tetrahedron, where a face or an edge is found among the few tens of tetrahedra around
    /// its smallest vertex.
    ///
    /// ```
    /// use harmonic_types::Grouped;
    /// let around = Grouped::tets_around(5, &[[0, 1, 2, 3], [0, 2, 1, 4]]);
    /// assert_eq!(around.of(0), &[0, 1]);
    /// assert_eq!(around.of(4), &[1]);
    /// ```
    pub fn tets_around(vertices: usize, tets: &[[u32; 4]]) -> Self {
        Grouped::by_vertex(vertices, |emit| {
            for (t, tet) in tets.iter().enumerate() {
                for &v in tet {
                    emit(v, t as u32);
                }
            }
        })
    }
}

/// The distinct edges of a tetrahedral mesh, and each tetrahedron's edges among them.
#[derive(Clone, Debug, PartialEq)]
pub struct TetEdges {
    /// The edges `[a, b]`, `a < b`, in increasing order of `(a, b)`.
    pub edges: Vec<[u32; 2]>,
    /// Per tetrahedron: the index in `edges` of each of its [`EDGES`](crate::EDGES).
    pub of_tet: Vec<[u32; 6]>,
}

impl TetEdges {
    /// The edges of tetrahedra `tets` over `vertices` vertices, found around their smaller
    /// vertex ([`TetEdges::around`]). Fewer than 2³² / 6 tetrahedra.
    ///
    /// ```
    /// use harmonic_types::TetEdges;
    /// // Two tetrahedra sharing the face (0, 1, 2): 9 edges.
    /// let e = TetEdges::of(5, &[[0, 1, 2, 3], [0, 2, 1, 4]]);
    /// assert_eq!(e.edges.len(), 9);
    /// assert_eq!(e.edges[0], [0, 1]);
    /// assert_eq!(e.of_tet[0][0], e.of_tet[1][1]); // edge (0, 1) of both
    /// ```
    pub fn of(vertices: usize, tets: &[[u32; 4]]) -> TetEdges {
        Self::around(tets, &Grouped::tets_around(vertices, tets))
    }

    /// [`TetEdges::of`] with the tetrahedra around each vertex given
    /// ([`Grouped::tets_around`], as [`TetMesh::tets_around`](crate::TetMesh::tets_around)
    /// keeps them): each vertex numbers the edges it is the smaller end of, found among its
    /// tetrahedra, in order of their larger end — the vertices on every core, in two
    /// passes (count, then place), so the numbering is the same at any thread count.
    pub fn around(tets: &[[u32; 4]], around: &Grouped<u32>) -> TetEdges {
        use std::sync::atomic::{AtomicU32, Ordering};
        let nv = around.start.len() - 1;
        // The edges `a` is the smaller end of: (larger end, slot 6·t + e), sorted.
        let owned = |a: usize, keys: &mut Vec<u64>| {
            keys.clear();
            let a32 = a as u32;
            for &t in around.of(a) {
                let tet = &tets[t as usize];
                for (e, &[i, j]) in crate::EDGES.iter().enumerate() {
                    let (x, y) = (tet[i].min(tet[j]), tet[i].max(tet[j]));
                    if x == a32 {
                        keys.push((y as u64) << 32 | (t * 6 + e as u32) as u64);
                    }
                }
            }
            keys.sort_unstable();
        };
        let distinct = |keys: &[u64]| {
            keys.iter()
                .enumerate()
                .filter(|&(i, k)| i == 0 || keys[i - 1] >> 32 != k >> 32)
                .count()
        };
        let chunks = vertex_runs(nv);
        // 1. How many edges each run of vertices owns.
        let counts: Vec<usize> = chunks
            .par_iter()
            .map(|&(v0, v1)| {
                let mut keys = Vec::new();
                (v0..v1)
                    .map(|a| {
                        owned(a, &mut keys);
                        distinct(&keys)
                    })
                    .sum()
            })
            .collect();
        // 2. Each run places its edges in its own slice and points its slots at them.
        let mut edges = vec![[0u32; 2]; counts.iter().sum()];
        let of_tet: Vec<[AtomicU32; 6]> = (0..tets.len())
            .into_par_iter()
            .map(|_| std::array::from_fn(|_| AtomicU32::new(0)))
            .collect();
        let mut pieces = Vec::with_capacity(chunks.len());
        let (mut rest, mut first) = (edges.as_mut_slice(), 0usize);
        for (&run, &n) in chunks.iter().zip(&counts) {
            let (piece, tail) = std::mem::take(&mut rest).split_at_mut(n);
            pieces.push((run, first, piece));
            rest = tail;
            first += n;
        }
        pieces.into_par_iter().for_each(|((v0, v1), first, piece)| {
            let mut keys = Vec::new();
            let mut next = 0usize;
            for a in v0..v1 {
                owned(a, &mut keys);
                let mut last = None;
                for &k in &keys {
                    let (b, slot) = ((k >> 32) as u32, k as u32);
                    if last != Some(b) {
                        piece[next] = [a as u32, b];
                        next += 1;
                        last = Some(b);
                    }
                    of_tet[(slot / 6) as usize][(slot % 6) as usize]
                        .store((first + next - 1) as u32, Ordering::Relaxed);
                }
            }
        });
        TetEdges {
            edges,
            of_tet: of_tet
                .into_par_iter()
                .map(|e| e.map(AtomicU32::into_inner))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_a_global_sort() {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        };
        let items: Vec<(u32, u64)> = (0..20_000)
            .map(|_| ((next() % 997) as u32, next()))
            .collect();
        let g = Grouped::by_vertex(1000, |emit| items.iter().for_each(|&(v, k)| emit(v, k)));
        let mut sorted = items.clone();
        sorted.sort_unstable();
        assert_eq!(g.keys, sorted.iter().map(|p| p.1).collect::<Vec<_>>());
        for v in 0..1000 {
            assert!(g.of(v).len() == sorted.iter().filter(|p| p.0 as usize == v).count());
        }
    }

    #[test]
    fn tet_edges_are_the_distinct_sorted_edges_each_tetrahedron_points_at() {
        // Random quadruples of distinct vertices (not a mesh: only the numbering is tested).
        let mut state = 777u64;
        let mut next = |n: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n) as u32
        };
        let tets: Vec<[u32; 4]> = (0..20_000)
            .map(|_| {
                let mut t = [0u32; 4];
                let mut k = 0;
                while k < 4 {
                    let v = next(2000);
                    if !t[..k].contains(&v) {
                        t[k] = v;
                        k += 1;
                    }
                }
                t
            })
            .collect();
        let e = TetEdges::of(2000, &tets);
        let mut expected: Vec<[u32; 2]> = tets
            .iter()
            .flat_map(|t| crate::EDGES.map(|[i, j]| [t[i].min(t[j]), t[i].max(t[j])]))
            .collect();
        expected.sort_unstable();
        expected.dedup();
        assert_eq!(e.edges, expected);
        for (t, te) in tets.iter().zip(&e.of_tet) {
            for (k, &[i, j]) in crate::EDGES.iter().enumerate() {
                assert_eq!(e.edges[te[k] as usize], [t[i].min(t[j]), t[i].max(t[j])]);
            }
        }
    }
}
