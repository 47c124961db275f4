//! Stagnation points: where the flow stops in front of an obstacle (their eq. 41; the
//! panel field's search is [`PanelField::stagnation_points`]), a robot on the dividing
//! streamline would stop. The paper: "if the robot gets to this stagnation point, then it will
//! make a sharp left or right turn. We have to make the robot choose one direction."
//!
//! A stagnation point of a planar harmonic flow is a saddle of its potential: the flow comes
//! in along one axis and leaves along the other (the eigenvector of the velocity gradient's
//! positive eigenvalue). [`StagnationGuard`] steers a primary control point that the flow
//! carries toward a stagnation point, within a radius, along that outflow on the chosen
//! [`Side`], until the flow carries it away again. [`fem_stagnation_points`] finds the
//! discrete saddles of an FEM potential.
//!
//! [`PanelField::stagnation_points`]: harmonic_baselines::PanelField::stagnation_points

use harmonic_fem::Potential;
use harmonic_mesh::{Point, Vector};
use nalgebra::{Matrix2, SymmetricEigen};
use serde::Serialize;

use crate::flow::{Flow, unit};

/// Which way to turn at a stagnation point, seen along the incoming flow.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Turn left (counter-clockwise from the incoming direction).
    Left,
    /// Turn right.
    Right,
}

/// One stagnation point the guard knows, with its outflow axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Saddle {
    /// Where the flow stops.
    pub at: Point,
    /// A unit vector along the outflow axis (either sign), `None` where the flow's gradient
    /// there has no clear axis (then the guard turns perpendicular to the incoming flow).
    pub outflow: Option<Vector>,
}

impl Saddle {
    /// The inflow axis: perpendicular to the outflow (a harmonic flow's velocity gradient is
    /// symmetric, so its eigenvectors are orthogonal).
    pub fn inflow(&self) -> Option<Vector> {
        self.outflow.map(|o| Vector::new(-o.y, o.x))
    }

    /// The point `distance` upstream on the inflow axis (the dividing streamline, locally):
    /// of the two points on the axis, the one where `flow` carries toward the saddle.
    pub fn upstream(&self, flow: &dyn Flow, distance: f64) -> Option<Point> {
        let axis = self.inflow()?;
        [self.at + axis * distance, self.at - axis * distance]
            .into_iter()
            .filter_map(|p| Some((p, flow.velocity(p)?.dot(&(self.at - p)))))
            .filter(|(_, toward)| *toward > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(p, _)| p)
    }
}

/// Steers primary control points around known stagnation points.
#[derive(Clone, Debug, PartialEq)]
pub struct StagnationGuard {
    /// The stagnation points and their outflow axes.
    pub saddles: Vec<Saddle>,
    /// A point the flow carries toward a stagnation point within this distance is steered.
    pub radius: f64,
    /// Which way.
    pub side: Side,
}

/// A turn the guard made.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Turn {
    /// The period.
    pub step: usize,
    /// The stagnation point.
    pub stagnation_point: [f64; 2],
    /// Where the primary control point was.
    pub at: [f64; 2],
    /// Which way it turned.
    pub side: Side,
}

impl StagnationGuard {
    /// A guard for `points` of `flow`: the outflow axis of each from the symmetric part of
    /// the velocity gradient, by central differences over `radius / 20`.
    pub fn new(flow: &dyn Flow, points: &[Point], radius: f64, side: Side) -> Self {
        let h = radius / 20.0;
        let saddles = points
            .iter()
            .map(|&at| Saddle {
                at,
                outflow: outflow_axis(flow, at, h),
            })
            .collect();
        StagnationGuard {
            saddles,
            radius,
            side,
        }
    }

    /// The stagnation points.
    pub fn points(&self) -> Vec<Point> {
        self.saddles.iter().map(|s| s.at).collect()
    }

    /// The direction to move from `p`, where the flow's velocity is `v`, if a stagnation
    /// point needs handling: the index of the saddle and a unit direction. `None`: follow the
    /// flow.
    pub fn steer(&self, p: Point, v: Vector) -> Option<(usize, Vector)> {
        let (k, s) = self
            .saddles
            .iter()
            .enumerate()
            .filter(|(_, s)| (s.at - p).norm() <= self.radius)
            .min_by(|a, b| (a.1.at - p).norm().total_cmp(&(b.1.at - p).norm()))?;
        let toward = s.at - p;
        // Carried toward it (or stopped there): the flow's component along `toward` is
        // positive, or the flow has no direction at all.
        let incoming = match unit(v) {
            Some(dir) => {
                if dir.dot(&toward) <= 0.0 {
                    return None;
                }
                dir
            }
            None => unit(toward)?,
        };
        let left = Vector::new(-incoming.y, incoming.x);
        let wanted = match self.side {
            Side::Left => left,
            Side::Right => -left,
        };
        let d = match s.outflow {
            Some(axis) if axis.dot(&wanted) >= 0.0 => axis,
            Some(axis) => -axis,
            None => wanted,
        };
        Some((k, d))
    }
}

/// The outflow axis of a stagnation point: the eigenvector of the largest eigenvalue of the
/// symmetric part of ∂v/∂x (for a harmonic flow, ∂v/∂x is itself symmetric and traceless:
/// eigenvalues ±λ, the positive one's eigenvector the outflow). `None` without a clear axis.
fn outflow_axis(flow: &dyn Flow, at: Point, h: f64) -> Option<Vector> {
    let d = |e: Vector| -> Option<Vector> {
        Some((flow.velocity(at + e * h)? - flow.velocity(at - e * h)?) / (2.0 * h))
    };
    let dx = d(Vector::new(1.0, 0.0))?;
    let dy = d(Vector::new(0.0, 1.0))?;
    let j = Matrix2::new(dx.x, dy.x, dx.y, dy.y);
    let s = (j + j.transpose()) * 0.5;
    let eig = SymmetricEigen::new(s);
    let (i, lam) = if eig.eigenvalues[0] >= eig.eigenvalues[1] {
        (0, eig.eigenvalues[0])
    } else {
        (1, eig.eigenvalues[1])
    };
    let other = eig.eigenvalues[1 - i];
    if lam.is_nan() || lam <= 0.0 || lam - other <= 1e-12 * lam.abs().max(other.abs()) {
        return None;
    }
    let v = eig.eigenvectors.column(i);
    unit(Vector::new(v[0], v[1]))
}

/// The discrete saddles of an FEM potential: interior vertices around which ψ − ψ(v) changes
/// sign at least four times (the link of a P1 saddle), merged within `merge` of one another
/// (the one with the smallest recovered gradient kept). Boundary vertices are left out.
pub fn fem_stagnation_points(potential: &Potential, merge: f64) -> Vec<Point> {
    let mesh = potential.mesh();
    let psi = potential.psi();
    let nv = mesh.vertices().len();
    let mut changes = vec![0u32; nv];
    let tags = mesh.vertex_tags();
    for tri in mesh.triangles() {
        for k in 0..3 {
            let v = tri[k] as usize;
            let (a, b) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            let (sa, sb) = (psi[a] > psi[v], psi[b] > psi[v]);
            if sa != sb {
                changes[v] += 1;
            }
        }
    }
    let grads = potential.nodal_gradients_psi();
    let mut found: Vec<(Point, f64)> = (0..nv)
        .filter(|&v| changes[v] >= 4 && tags.get(v).is_none_or(|t| t.is_none()))
        .map(|v| (mesh.vertices()[v], grads[v].norm()))
        .collect();
    found.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut kept: Vec<Point> = Vec::new();
    for (p, _) in found {
        if kept.iter().all(|q| (q - p).norm() > merge) {
            kept.push(p);
        }
    }
    kept
}
