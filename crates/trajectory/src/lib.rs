//! # harmonic-trajectory
//!
//! Following a potential field from a start to a goal: the exact triangle-to-triangle
//! gradient tracer for P1 (finite element) potentials, a smooth adaptive integrator, saddle
//! escape, the non-holonomic car stepper of Garrido et al. (2010, §7), and path metrics.
//!
//! Everything here knows a field only through the small [`Field`] trait (locate a point,
//! value, gradient), so the FEM potential ([`P1Field`], [`SmoothP1Field`], borrowing the mesh
//! and nodal values without copying) and the baselines' grid or analytic fields are followed
//! by the same code. A field's `value` decreases toward the goal; a potential that increases
//! toward it (ψ = φ_wall − φ) is wrapped with [`P1Field::ascending`].

#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod car;
mod descend;
mod exact;
mod field;
mod metrics;
mod path;
mod smooth;
pub mod volume;

pub use car::{CarOptions, CarSpeed, CarTarget, Collision, Footprint, drive};
pub use descend::{Tracer, descend};
pub use exact::{ExactOptions, trace_exact, trace_exact_with_hint};

pub use field::{Fallback, Field, Locate, NOT_A_GOAL, P1Field, Segment, SmoothP1Field};
pub use harmonic_types::geom::polyline_length;
pub use metrics::{PathMetrics, max_curvature, max_pose_curvature, path_metrics};
pub use path::{CarPath, Path, PathPoint, TraceStatus};
pub use smooth::{SmoothOptions, trace_smooth, trace_smooth_with_hint};

/// Errors from building fields or from invalid tracer options.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TraceError {
    /// A per-vertex slice does not have one entry per mesh vertex.
    #[error("{what}: expected {expected} entries (one per mesh vertex), got {got}")]
    LengthMismatch {
        /// Which input.
        what: &'static str,
        /// The number of mesh vertices.
        expected: usize,
        /// The slice's length.
        got: usize,
    },
    /// An input holds NaN or an infinity.
    #[error("{what}[{index}] is not a finite number")]
    NotFinite {
        /// Which input.
        what: &'static str,
        /// The first offending index.
        index: usize,
    },
    /// A tracer or car option is out of range.
    #[error("option `{name}` = {value} is invalid: {reason}")]
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is required.
        reason: &'static str,
    },
}
