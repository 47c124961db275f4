//! # harmonic-control
//!
//! Kim & Khosla's (1992, §§4–5) real-time control of robots that are not points, on any
//! planar harmonic flow: a [`Flow`] gives the velocity `(u, v)` a fluid particle (a point
//! robot) would follow — their published panel field, or our FEM potential's gradient — and
//! the controllers here turn it into motions of a body:
//!
//! - the **primary control point** (a bar's leading point, an arm's end effector) follows
//!   the flow;
//! - a **secondary control point** is the robot point closest to an obstacle within the
//!   minimum allowable distance δ; the closest obstacle point carries a point source of the
//!   potential φ_o of their eq. 42 ([`ObstaclePotential`]) that pushes it away, every period
//!   until it leaves δ;
//! - the **bar-shaped mobile robot** ([`bar`], eqs. 43–49): potential operation (43), the
//!   `d_max` normalisation (44–45), the `Δη_max` saturation (46–49), and the obstacle
//!   operation turning the bar by φ_o;
//! - the **redundant planar arm** ([`arm`], eqs. 52–58): the end effector's displacement from
//!   the flow, net motion by the Jacobian's pseudoinverse (53), null motion for the secondary
//!   control points (54), their sum (55) and the energy normalisation (56–58);
//! - **stagnation points** ([`stagnation`]): where the flow stops in front of an obstacle the
//!   robot must pick a side; the guard steers along the saddle's outflow on the chosen side.
//!
//! Every run is checked against the exact obstacle polygons along the whole motion
//! ([`clearance`]): the whole body, sampled so that no body point moves more than a given
//! step between samples.
//!
//! ```
//! use harmonic_control::{BarParams, BarRobot, Obstacles, Uniform, bar::run_bar};
//! use harmonic_mesh::{Point, Vector};
//!
//! // A uniform stream along +x and no obstacle: the bar turns into the stream, then runs
//! // straight to the goal.
//! let flow = Uniform(Vector::new(1.0, 0.0));
//! let robot = BarRobot { length: 1.0 };
//! let run = run_bar(&flow, &Obstacles::default(), None, &robot, [0.0, 0.0, 0.5],
//!                   Point::new(5.0, 0.0), &BarParams::default())?;
//! assert!(run.reached());
//! assert!(run.poses.last().unwrap()[2].abs() < 1e-9);
//! # Ok::<(), harmonic_control::ControlError>(())
//! ```
#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod arm;
pub mod bar;
pub mod clearance;
mod error;
pub mod flow;
pub mod obstacles;
pub mod stagnation;
pub mod svg;

pub use arm::{Arm, ArmParams, ArmRun, NullMotion};
pub use bar::{BarParams, BarRobot, BarRun};
pub use error::ControlError;
pub use flow::{FemFlow, Flow, Source, Uniform};
pub use obstacles::{Contact, ObstaclePotential, Obstacles};
pub use stagnation::{Side, StagnationGuard};

/// How a controller run ended.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "status")]
pub enum RunStatus {
    /// The primary control point came within the goal tolerance.
    Reached,
    /// The step budget ran out first.
    MaxSteps,
    /// The flow is undefined where the primary control point stands (outside the FEM mesh:
    /// in an obstacle, past a wall, inside the goal region before the tolerance).
    OutsideFlow {
        /// Where.
        at: [f64; 2],
    },
    /// The flow vanished at the primary control point away from every known stagnation point.
    Stalled {
        /// Where.
        at: [f64; 2],
    },
    /// Some part of the robot touched an obstacle (exact polygons) during this period.
    Collided {
        /// The period.
        step: usize,
        /// The obstacle.
        obstacle: usize,
    },
}
