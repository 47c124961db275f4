//! How many threads the direct solver may use.

/// By default ([`Parallelism::default`]) systems with fewer unknowns than this are factored on
/// one thread: below it a second thread's start-up costs more than it saves (the replanning
/// lattice of a few thousand unknowns factors in a fraction of a millisecond).
pub const PARALLEL_MIN_UNKNOWNS: usize = 50_000;

/// Below this many unknowns a nested-dissection piece is never split over two threads.
const ND_MIN_PARALLEL_PIECE: usize = 64;

/// Threads for the nested-dissection ordering and, optionally, faer's numeric Cholesky (its
/// dense supernode kernels) and the triangular solves of [`crate::SymbolicCholesky`].
///
/// Either choice gives the same ordering and the same factor structure; the numeric values
/// agree to rounding (faer may split the dense blocks' products across threads), so solutions
/// agree to a few units in the last place.
///
/// By default only the ordering runs on the pool. On this project's 2-core machine faer's
/// parallel dense kernels made the numeric factorisation slower, not faster: 0.99–1.03 s
/// against 0.66–0.70 s on one thread for the 1 M-triangle reference system (500 k unknowns),
/// 0.30–0.39 s against 0.17–0.22 s at 300 k triangles, alternating runs of
/// `cargo run --release --example probe -- meshes/reference.json --max-area A --at 8,3 --json
/// [--sequential]`; the parallel ordering is the faster one there (0.30–0.32 s against
/// 0.39–0.45 s). `dense_kernels: true` puts faer's kernels on the pool too, for machines with
/// more cores.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parallelism {
    /// Everything on the calling thread.
    Sequential,
    /// rayon's current thread pool (all cores, or `RAYON_NUM_THREADS`, or a pool the caller
    /// installed) for systems of at least `from_unknowns` unknowns; smaller ones run
    /// sequentially.
    Rayon {
        /// The smallest system that uses the pool.
        from_unknowns: usize,
        /// Whether faer's numeric factorisation and the triangular solves use the pool as
        /// well as the ordering.
        dense_kernels: bool,
    },
}

impl Default for Parallelism {
    /// rayon's pool for the ordering from [`PARALLEL_MIN_UNKNOWNS`] unknowns; faer's kernels
    /// on the calling thread.
    fn default() -> Self {
        Parallelism::Rayon {
            from_unknowns: PARALLEL_MIN_UNKNOWNS,
            dense_kernels: false,
        }
    }
}

impl Parallelism {
    /// Whether a system of `n` unknowns gets more than one thread.
    pub(crate) fn parallel_for(self, n: usize) -> bool {
        match self {
            Parallelism::Sequential => false,
            Parallelism::Rayon { from_unknowns, .. } => {
                n >= from_unknowns && rayon::current_num_threads() > 1
            }
        }
    }

    /// From how many unknowns a nested-dissection piece of a system of `n` unknowns has its
    /// halves dissected on two threads (`None`: never). Pieces of a quarter of a large system
    /// and up (the top levels, where the work is) split; the numbering does not depend on it.
    pub(crate) fn nd_piece(self, n: usize) -> Option<usize> {
        match self {
            Parallelism::Rayon { from_unknowns, .. } if self.parallel_for(n) => {
                Some((n / 4).min(from_unknowns.max(1)).max(ND_MIN_PARALLEL_PIECE))
            }
            _ => None,
        }
    }

    /// faer's parallelism for a system of `n` unknowns.
    pub(crate) fn faer(self, n: usize) -> faer::Par {
        let dense = matches!(
            self,
            Parallelism::Rayon {
                dense_kernels: true,
                ..
            }
        );
        if dense && self.parallel_for(n) {
            faer::Par::rayon(0)
        } else {
            faer::Par::Seq
        }
    }
}
