//! # harmonic-planner
//!
//! Local-minimum-free robot path planning with harmonic potentials solved by the finite
//! element method.

pub mod scene;

pub use scene::{Scene, SceneError};
pub mod render;
