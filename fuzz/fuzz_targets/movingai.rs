//! Fuzz target: bytes → the MovingAI `.map` and `.scen` readers (see `fuzz/src/movingai.rs`).
//! Errors are expected; panics are bugs.

#![no_main]

use libfuzzer_sys::fuzz_target;

/// Shared with the corpus replay in `tests/grid_completeness.rs`, which includes it the same
/// way.
#[path = "../src/movingai.rs"]
mod movingai;

fuzz_target!(|data: &[u8]| {
    movingai::run_movingai(data);
});
