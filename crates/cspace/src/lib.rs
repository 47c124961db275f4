//! # harmonic-cspace
//!
//! Configuration spaces of robots that are not discs, for the harmonic planner: a rigid
//! polygon moving in the plane (configuration (x, y, θ)) and a planar arm of two or three
//! revolute joints (configuration (q1, …, qn)), in a workspace polygon with polygonal and
//! circular obstacles.
//!
//! * [`World`], [`RigidRobot`], [`Arm`]: validated shapes (errors name their JSON path), cut
//!   into convex parts whose exact distances parry2d computes.
//! * [`ConfigSpace`]: the free configuration space (the robot grown by a safety margin ε,
//!   joint limits, minus the goal region) as a [`harmonic_volume::ImplicitDomain`] in scaled
//!   coordinates (θ by the radius of gyration, joints by their reach), meshed by
//!   [`harmonic_volume::stuff_periodic`] on a lattice that closes on itself along θ and free
//!   joints ([`harmonic_volume::PeriodicMesh`]: the slab of one period with its ends
//!   identified, and a covering for tracing with the angles unwrapped).
//! * [`check`]: exact, sampled collision checks of motions with `harmonic_mesh::geom` —
//!   independent of the geometry the mesh was built from.
//! * [`svg`]: the robot drawn along its motion.
//!
//! ```
//! use harmonic_cspace::{ConfigGoal, ConfigSpace, ObstacleInput, RigidRobot, Robot, World};
//! let world = World::new(
//!     &[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]],
//!     &[ObstacleInput::Circle { center: [2.0, 2.0], radius: 0.5 }],
//! )?;
//! let robot = Robot::Rigid(RigidRobot::new(&[[-0.4, -0.1], [0.4, -0.1], [0.4, 0.1], [-0.4, 0.1]])?);
//! let goal = ConfigGoal::Pose { pose: [3.2, 3.2, 0.0], position: 0.3, angle: 0.5 };
//! let space = ConfigSpace::new(robot, world, goal, 0.02, 0.25)?;
//! let (mesh, report) = space.mesh(1_000_000)?;
//! assert!(report.seam_faces > 0);
//! assert!(mesh.covering.tetrahedra().len() > 2 * mesh.slab.tetrahedra().len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod check;
mod error;
mod geometry;
mod robot;
mod space;
pub mod svg;

pub use error::CspaceError;
pub use geometry::{
    Nearest, Obstacle, ObstacleInput, Pair, Part, World, checked_ring, convex_parts, self_clearance,
};
pub use robot::{Arm, RigidRobot, Robot};
pub use space::{
    ANTIGOAL_PART, Axis, ConfigClass, ConfigGoal, ConfigSpace, CspaceMeshReport,
    DEFAULT_MAX_TETRAHEDRA, EXTRUDE_PART,
};
