//! How many threads the direct solver may use.

/// By default ([`Parallelism::default`]) systems with fewer unknowns than this are factored on
/// one thread: below it a second thread's start-up costs more than it saves (the replanning
/// lattice of a few thousand unknowns factors in a fraction of a millisecond).
pub const PARALLEL_MIN_UNKNOWNS: usize = 50_000;

/// Below this many unknowns a nested-dissection piece is never split over two threads.
const ND_MIN_PARALLEL_PIECE: usize = 64;

/// Threads for the nested-dissection ordering, faer's numeric Cholesky (its dense supernode
/// kernels) and the triangular solves of [`crate::SymbolicCholesky`].
///
/// Either choice gives the same ordering and the same factor structure; the numeric values
/// agree to rounding (faer may split the dense blocks' products across threads), so solutions
/// agree to a few units in the last place.
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
    },
}

impl Default for Parallelism {
    /// rayon's pool from [`PARALLEL_MIN_UNKNOWNS`] unknowns.
    fn default() -> Self {
        Parallelism::Rayon {
            from_unknowns: PARALLEL_MIN_UNKNOWNS,
        }
    }
}

impl Parallelism {
    /// Whether a system of `n` unknowns gets more than one thread.
    pub(crate) fn parallel_for(self, n: usize) -> bool {
        match self {
            Parallelism::Sequential => false,
            Parallelism::Rayon { from_unknowns } => {
                n >= from_unknowns && rayon::current_num_threads() > 1
            }
        }
    }

    /// From how many unknowns a nested-dissection piece of a system of `n` unknowns has its
    /// halves dissected on two threads (`None`: never). Pieces of a quarter of a large system
    /// and up (the top levels, where the work is) split; the numbering does not depend on it.
    pub(crate) fn nd_piece(self, n: usize) -> Option<usize> {
        match self {
            Parallelism::Rayon { from_unknowns } if self.parallel_for(n) => {
                Some((n / 4).min(from_unknowns.max(1)).max(ND_MIN_PARALLEL_PIECE))
            }
            _ => None,
        }
    }

    /// faer's parallelism for a system of `n` unknowns.
    pub(crate) fn faer(self, n: usize) -> faer::Par {
        if self.parallel_for(n) {
            faer::Par::rayon(0)
        } else {
            faer::Par::Seq
        }
    }
}
