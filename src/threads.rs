//! The `threads` option ([`crate::PlannerOptions::threads`]): how many cores a planner's
//! build and its many-start traces use. `None` is rayon's global pool (every core, or
//! `RAYON_NUM_THREADS`); `Some(n)` a pool of `n` threads the planner keeps. Every stage's
//! results are independent of the count (`tests/parallel.rs`).

use std::sync::Arc;

use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::planner::{PlanError, Planner, PlannerOptions};

/// The pool `threads` asks for (`None`: the global one).
pub(crate) fn pool(threads: Option<usize>) -> Result<Option<Arc<ThreadPool>>, PlanError> {
    match threads {
        None => Ok(None),
        Some(0) => Err(PlanError::Threads {
            threads: 0,
            message: "at least one thread is needed".into(),
        }),
        Some(n) => ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(|p| Some(Arc::new(p)))
            .map_err(|e| PlanError::Threads {
                threads: n,
                message: e.to_string(),
            }),
    }
}

/// Runs `f` in `pool` (or where it is called, for the global pool).
pub(crate) fn install<R: Send>(pool: Option<&ThreadPool>, f: impl FnOnce() -> R + Send) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

/// Builds a planner with `build` in the pool of `options.threads`, which the planner then
/// keeps; `build` gets the options with `threads` taken (one pool, not one per layer), and a
/// pool that cannot be had is `refused`'s error.
pub(crate) fn build_in<E: Send>(
    options: &PlannerOptions,
    refused: impl FnOnce(PlanError) -> E,
    build: impl FnOnce(&PlannerOptions) -> Result<Planner, E> + Send,
) -> Result<Planner, E> {
    if options.threads.is_none() {
        return build(options);
    }
    let pool = self::pool(options.threads).map_err(refused)?;
    let inner = PlannerOptions {
        threads: None,
        ..options.clone()
    };
    let mut planner = install(pool.as_deref(), || build(&inner))?;
    planner.pool = pool;
    Ok(planner)
}
