//! # harmonic-bench
//!
//! The workspace's experiments, not published: the comparison [`compare::Arena`] that runs
//! every planner on the same scene and measures it against the exact geometry, the
//! shortest-path oracle it measures against ([`compare::VisibilityGraph`]), and the seed
//! papers' tables ([`tables`]). The examples and benches that reproduce the papers depend on
//! this crate; library users depend on `harmonic-planner` and never compile it.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod compare;
pub mod connolly;
pub mod kim_khosla;
pub mod kim_khosla_arm;
pub mod kim_khosla_control;
pub mod me766;
pub mod paper;
pub mod tables;
