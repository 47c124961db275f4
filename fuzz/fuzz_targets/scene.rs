//! Fuzz target: scene bytes → `Scene::from_json` → mesh capped at ~20k triangles →
//! `Planner::new` → `plan` from the scene's starts. Errors are expected; panics are bugs.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    harmonic_planner_fuzz::run(data);
});
