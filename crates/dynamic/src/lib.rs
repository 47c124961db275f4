//! Dynamic replanning (Garrido et al. 2010, §6): a local map around the robot, rebuilt and
//! solved at every step from the known map and what the laser sees.
//!
//! The pieces, in the order of the paper's Figure 10 loop:
//! - [`LaserScan`] / [`scan_obstacles`]: a scan (points in the robot frame plus the robot's pose)
//!   becomes obstacles: points explained by the known map are dropped, the rest are clustered by
//!   distance, and each cluster becomes its convex hull grown by a margin (the hull of
//!   octagons circumscribing discs around the points, so the growth is conservative).
//! - [`DynamicPlanner`]: the known map's global potential (built once), obstacles that can be
//!   added, moved and removed, and [`DynamicPlanner::replan`], which meshes a square window
//!   around the robot with the known and sensed obstacles in it, puts the goal on the global
//!   path where it leaves the window (or uses the real goal when it lies inside), solves and
//!   traces the local potential.
//! - [`World`] and [`run`]: a simulated world with moving and unmapped obstacles, a simulated
//!   laser ([`World::scan`]) and the loop itself — sense, solve, trace, move a step sized by
//!   the distance to the nearest moving obstacle, repeat — with the distance to the true
//!   obstacles checked at every step.
//!
//! The local map is a fixed background lattice of right triangles with the obstacles cut in
//! by blocking vertices ([`LocalMapMode::Lattice`]): a replan builds, factors and solves only
//! its own unknowns, numbered by an elimination order kept from earlier windows — about 0.3 ms
//! for the paper's 3200-triangle map. Where the lattice's safety margin
//! (up to `h/√2` beyond the robot's radius) traps the robot or seals its way, the window is
//! remeshed exactly instead ([`LocalMapMode::Remesh`] always does). What else stays valid
//! between replans is reused: the known map's domain, global potential and blocked lattice
//! vertices, the global path (traced again only when the robot has left it) and the local
//! waypoint (kept while it stays valid).
//!
//! ```
//! use harmonic_dynamic::{DynamicPlanner, LocalMapOptions};
//! use harmonic_planner::Scene;
//! let scene = Scene::from_json(r#"{
//!     "workspace": [[0, 0], [8, 0], [8, 3], [0, 3]],
//!     "goal": {"circle": {"center": [7.5, 1.5], "radius": 0.15}},
//!     "mesh": {"max_area": 0.02}
//! }"#)?;
//! let opts = LocalMapOptions { size: 2.0, max_area: 0.01, ..LocalMapOptions::default() };
//! let mut planner = DynamicPlanner::new(&scene, opts)?;
//! // An obstacle seen on the way: the local path goes around it.
//! planner.set_obstacle(7, vec![[1.4, 1.2], [1.7, 1.2], [1.7, 1.8], [1.4, 1.8]]);
//! let plan = planner.replan([0.5, 1.5])?;
//! assert!(plan.path.status.reached_goal());
//! assert!(plan.local_goal[0] > 1.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

use harmonic_planner::PlanError;
use harmonic_planner::scene::Region;
use harmonic_trajectory::TraceStatus;

mod lattice;
mod perception;
mod planner;
mod world;

pub use perception::{LaserScan, ScanOptions, cluster_points, inflated_hull, scan_obstacles};
pub use planner::{DynamicPlanner, LocalMapMode, LocalMapOptions, LocalPlan, ReplanTimings};
pub use world::{Run, RunOptions, World, WorldObstacle, run};

/// Why a local plan could not be made.
#[derive(Debug, thiserror::Error)]
pub enum DynamicError {
    /// Building the global or the local planner failed.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The robot is outside the known map's workspace.
    #[error("robot at ({x}, {y}) is outside the workspace")]
    OutsideWorkspace {
        /// Robot position.
        x: f64,
        /// Robot position.
        y: f64,
    },
    /// The global potential gives no path from the robot's position (it is in an obstacle of
    /// the known map or cut off from the goal).
    #[error("no global path from ({x}, {y}): {status}")]
    NoGlobalPath {
        /// Robot position.
        x: f64,
        /// Robot position.
        y: f64,
        /// The global tracer's status.
        status: TraceStatus,
    },
    /// Every candidate local goal on the global path is blocked by a sensed obstacle.
    #[error("no free local goal on the global path from ({x}, {y})")]
    NoLocalGoal {
        /// Robot position.
        x: f64,
        /// Robot position.
        y: f64,
    },
    /// An option is out of range.
    #[error("invalid option {name} = {value}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
}

/// A goal or obstacle region as a polygon (a circle as `segments` points on it); `None` for
/// a point.
pub(crate) fn region_polygon(region: &Region, segments: usize) -> Option<Vec<[f64; 2]>> {
    match (&region.polygon, &region.circle, &region.point) {
        (Some(p), _, _) => Some(p.clone()),
        (None, Some(c), _) => Some(circle_points(c.center, c.radius, segments)),
        _ => None,
    }
}

/// `segments` points evenly spaced on the circle of `center` and `radius`, counter-clockwise.
pub(crate) fn circle_points(center: [f64; 2], radius: f64, segments: usize) -> Vec<[f64; 2]> {
    (0..segments)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / segments as f64;
            [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
        })
        .collect()
}

/// Euclidean distance.
pub(crate) fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}
