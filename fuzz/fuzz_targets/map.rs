//! Fuzz target: bytes → a `map_server` YAML document and its image → `OccupancyMap` →
//! both meshers' planners on grids of up to 128 × 128 cells → `plan`. Errors are expected;
//! panics are bugs (see `fuzz/src/map.rs`).

#![no_main]

use libfuzzer_sys::fuzz_target;

/// Shared with the corpus replay in `tests/map.rs`, which includes it the same way.
#[path = "../src/map.rs"]
mod map;

fuzz_target!(|data: &[u8]| {
    map::run_map(data);
});
