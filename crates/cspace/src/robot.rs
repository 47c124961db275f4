//! The robots: a rigid polygon with configuration (x, y, θ), and a planar arm of two or
//! three revolute joints with configuration (q1, …, qn). Each gives its convex parts placed at
//! a configuration, its outline (for pictures and the exact checks), how far a robot point
//! moves per unit of each coordinate, and the scale that makes the coordinates comparable.

use std::f64::consts::TAU;

use parry2d_f64::math::{Pose, Rotation, Vector};
use parry2d_f64::shape::{Cuboid, Segment};

use crate::error::CspaceError;
use crate::geometry::{Part, checked_ring, convex_parts};

/// A rigid polygon robot.
#[derive(Clone, Debug)]
pub struct RigidRobot {
    /// The body-frame outline, counter-clockwise.
    pub ring: Vec<[f64; 2]>,
    parts: Vec<Part>,
    /// Radius of gyration about the body origin: `√(∫|p|² dA / A)`.
    pub radius_of_gyration: f64,
    /// The largest distance of a body point from the origin.
    pub max_radius: f64,
}

impl RigidRobot {
    /// A validated robot (`robot.polygon` named in errors).
    pub fn new(ring: &[[f64; 2]]) -> Result<RigidRobot, CspaceError> {
        let ring = checked_ring(ring, "robot.polygon")?;
        let parts = convex_parts(&ring, "robot.polygon")?;
        // Polar moment about the origin of a polygon: Σ (x_i y_{i+1} − x_{i+1} y_i)
        // (x_i² + x_i x_{i+1} + x_{i+1}² + y_i² + y_i y_{i+1} + y_{i+1}²) / 12.
        let n = ring.len();
        let mut j = 0.0;
        for i in 0..n {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            let cross = a[0] * b[1] - b[0] * a[1];
            j += cross
                * (a[0] * a[0]
                    + a[0] * b[0]
                    + b[0] * b[0]
                    + a[1] * a[1]
                    + a[1] * b[1]
                    + b[1] * b[1])
                / 12.0;
        }
        let area = harmonic_mesh::geom::signed_area(&ring);
        let radius_of_gyration = (j / area).sqrt();
        let max_radius = ring.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
        Ok(RigidRobot {
            ring,
            parts,
            radius_of_gyration,
            max_radius,
        })
    }

    /// The outline placed at `q = [x, y, θ]`.
    pub fn outline(&self, q: &[f64]) -> Vec<[f64; 2]> {
        let (s, c) = q[2].sin_cos();
        self.ring
            .iter()
            .map(|p| [q[0] + c * p[0] - s * p[1], q[1] + s * p[0] + c * p[1]])
            .collect()
    }

    /// The convex parts placed at `q`.
    pub fn placed(&self, q: &[f64]) -> Vec<(Pose, &Part)> {
        let pose = Pose::new(Vector::new(q[0], q[1]), q[2]);
        self.parts.iter().map(|p| (pose, p)).collect()
    }
}

/// A planar arm: links from a fixed base, revolute joints, link `i` at absolute angle
/// `q1 + … + qi`.
#[derive(Clone, Debug)]
pub struct Arm {
    /// The base.
    pub base: [f64; 2],
    /// Link lengths.
    pub links: Vec<f64>,
    /// Link width (0: segments).
    pub width: f64,
    /// Per joint: `Some([lo, hi])` for a limited joint, `None` for one that turns freely
    /// (limits spanning a full turn are free).
    pub limits: Vec<Option<[f64; 2]>>,
}

impl Arm {
    /// A validated arm (errors name `robot.arm.…`).
    pub fn new(
        base: [f64; 2],
        links: &[f64],
        width: f64,
        limits: Option<&[[f64; 2]]>,
    ) -> Result<Arm, CspaceError> {
        let bad = |path: &str, message: String| CspaceError::Invalid {
            path: format!("robot.arm.{path}"),
            message,
        };
        if !base.iter().all(|c| c.is_finite()) {
            return Err(bad("base", "must be finite".into()));
        }
        if !(2..=3).contains(&links.len()) {
            return Err(bad(
                "links",
                format!("an arm has 2 or 3 links, got {}", links.len()),
            ));
        }
        if let Some(i) = links.iter().position(|l| !(l.is_finite() && *l > 0.0)) {
            return Err(bad(
                &format!("links[{i}]"),
                "a link length must be positive".into(),
            ));
        }
        if !(width.is_finite() && width >= 0.0) {
            return Err(bad("width", "must be finite and ≥ 0".into()));
        }
        let limits = match limits {
            None => vec![None; links.len()],
            Some(l) => {
                if l.len() != links.len() {
                    return Err(bad(
                        "joint_limits",
                        format!("{} limits for {} joints", l.len(), links.len()),
                    ));
                }
                let mut out = Vec::new();
                for (i, &[lo, hi]) in l.iter().enumerate() {
                    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                        return Err(bad(
                            &format!("joint_limits[{i}]"),
                            format!("needs finite lo < hi, got [{lo}, {hi}]"),
                        ));
                    }
                    // A full turn (to the 5 decimals a scene writes π with) is no limit.
                    out.push(if hi - lo >= TAU - 1e-4 {
                        None
                    } else {
                        Some([lo, hi])
                    });
                }
                out
            }
        };
        Ok(Arm {
            base,
            links: links.to_vec(),
            width,
            limits,
        })
    }

    /// The joint positions: base, the end of each link (the last is the tip).
    pub fn joints(&self, q: &[f64]) -> Vec<[f64; 2]> {
        let mut p = self.base;
        let mut angle = 0.0;
        let mut out = vec![p];
        for (l, qi) in self.links.iter().zip(q) {
            angle += qi;
            let (s, c) = angle.sin_cos();
            p = [p[0] + l * c, p[1] + l * s];
            out.push(p);
        }
        out
    }

    /// The end effector at `q` (the last of [`Arm::joints`], with no list made).
    pub fn tip(&self, q: &[f64]) -> [f64; 2] {
        let mut p = self.base;
        let mut angle = 0.0;
        for (l, qi) in self.links.iter().zip(q) {
            angle += qi;
            let (s, c) = angle.sin_cos();
            p = [p[0] + l * c, p[1] + l * s];
        }
        p
    }

    /// The links' outlines at `q`: segments (2 points) or rectangles (4).
    pub fn outlines(&self, q: &[f64]) -> Vec<Vec<[f64; 2]>> {
        let j = self.joints(q);
        j.windows(2)
            .map(|w| {
                if self.width == 0.0 {
                    vec![w[0], w[1]]
                } else {
                    let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
                    let len = dx.hypot(dy);
                    let (nx, ny) = (-dy / len * 0.5 * self.width, dx / len * 0.5 * self.width);
                    vec![
                        [w[0][0] - nx, w[0][1] - ny],
                        [w[1][0] - nx, w[1][1] - ny],
                        [w[1][0] + nx, w[1][1] + ny],
                        [w[0][0] + nx, w[0][1] + ny],
                    ]
                }
            })
            .collect()
    }

    /// The links as convex parts placed at `q` (owned: they move with `q`).
    pub fn placed_parts(&self, q: &[f64]) -> Vec<(Pose, Part)> {
        // The joints of [`Arm::joints`] and each link's rotation from one sine and cosine.
        let mut p = self.base;
        let mut angle = 0.0;
        let mut out = Vec::with_capacity(self.links.len());
        for (l, qi) in self.links.iter().zip(q) {
            angle += qi;
            let (s, c) = angle.sin_cos();
            let end = [p[0] + l * c, p[1] + l * s];
            let mid = Vector::new(0.5 * (p[0] + end[0]), 0.5 * (p[1] + end[1]));
            p = end;
            let pose = Pose::from_parts(mid, Rotation::from_cos_sin_unchecked(c, s));
            let part = if self.width == 0.0 {
                Part::Segment(Segment::new(
                    Vector::new(-0.5 * l, 0.0),
                    Vector::new(0.5 * l, 0.0),
                ))
            } else {
                Part::Cuboid(Cuboid::new(Vector::new(0.5 * l, 0.5 * self.width)))
            };
            out.push((pose, part));
        }
        out
    }

    /// How far a robot point can move per radian of joint `i`: the reach beyond it (half
    /// the width included).
    pub fn reach_from(&self, i: usize) -> f64 {
        self.links[i..].iter().sum::<f64>() + 0.5 * self.width
    }
}

/// Either robot.
#[derive(Clone, Debug)]
pub enum Robot {
    /// A rigid polygon, configuration (x, y, θ).
    Rigid(RigidRobot),
    /// A planar arm, configuration (q1, …, qn).
    Arm(Arm),
}

impl Robot {
    /// Degrees of freedom.
    pub fn dof(&self) -> usize {
        match self {
            Robot::Rigid(_) => 3,
            Robot::Arm(a) => a.links.len(),
        }
    }

    /// The outlines of the robot's pieces at `q` (one polygon, or one per link).
    pub fn outlines(&self, q: &[f64]) -> Vec<Vec<[f64; 2]>> {
        match self {
            Robot::Rigid(r) => vec![r.outline(q)],
            Robot::Arm(a) => a.outlines(q),
        }
    }

    /// A bound on how far any robot point moves along the straight motion `a → b` in
    /// configuration space (rotation about the body origin / the joints).
    pub fn sweep_bound(&self, a: &[f64], b: &[f64]) -> f64 {
        match self {
            Robot::Rigid(r) => {
                (b[0] - a[0]).hypot(b[1] - a[1]) + r.max_radius * (b[2] - a[2]).abs()
            }
            Robot::Arm(arm) => (0..arm.links.len())
                .map(|i| arm.reach_from(i) * (b[i] - a[i]).abs())
                .sum(),
        }
    }
}
