//! The flows a controller follows: the velocity `(u, v)` of their eqs. 36–37 at a point.
//!
//! [`PanelField`] (the published panel method) is one; [`FemFlow`] gives our FEM potential's
//! recovered gradient ∇ψ (ψ rises toward the goal), so the same controller runs on both
//! fields; [`Uniform`] and [`Source`] are the hand-built flows the tests check the equations
//! on.

use std::cell::Cell;

use harmonic_baselines::PanelField;
use harmonic_fem::Potential;
use harmonic_mesh::{Point, Vector};

/// A planar flow: the velocity a point robot at `p` follows.
pub trait Flow {
    /// The velocity at `p`, or `None` where the flow is undefined (outside an FEM mesh).
    fn velocity(&self, p: Point) -> Option<Vector>;
}

/// A uniform stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Uniform(pub Vector);

impl Flow for Uniform {
    fn velocity(&self, _p: Point) -> Option<Vector> {
        Some(self.0)
    }
}

/// A point source of strength `strength` at `at` (negative: a sink): velocity
/// `strength / (2π) · (p − at) / |p − at|²`, undefined at `at` itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Source {
    /// Where.
    pub at: Point,
    /// Its strength.
    pub strength: f64,
}

impl Flow for Source {
    fn velocity(&self, p: Point) -> Option<Vector> {
        let r = p - self.at;
        let r2 = r.norm_squared();
        (r2 > 0.0).then(|| r * (self.strength / (2.0 * std::f64::consts::PI * r2)))
    }
}

impl Flow for PanelField {
    fn velocity(&self, p: Point) -> Option<Vector> {
        let v = PanelField::velocity(self, p);
        (v.x.is_finite() && v.y.is_finite()).then_some(v)
    }
}

/// Our FEM potential as a flow: the recovered (continuous, piecewise linear) gradient of ψ,
/// which rises from the walls and obstacles (ψ = 0) to the goal; undefined off the mesh.
#[derive(Debug)]
pub struct FemFlow<'a> {
    potential: &'a Potential,
    hint: Cell<Option<u32>>,
}

impl<'a> FemFlow<'a> {
    /// The flow of `potential`.
    pub fn new(potential: &'a Potential) -> Self {
        FemFlow {
            potential,
            hint: Cell::new(None),
        }
    }

    /// The potential.
    pub fn potential(&self) -> &'a Potential {
        self.potential
    }
}

impl Flow for FemFlow<'_> {
    fn velocity(&self, p: Point) -> Option<Vector> {
        let t = self.potential.locate(p, self.hint.get()).ok()?;
        self.hint.set(Some(t));
        self.potential.recovered_gradient_psi_at(p, Some(t)).ok()
    }
}

/// The unit direction of `v`, `None` for a zero or non-finite vector.
pub(crate) fn unit(v: Vector) -> Option<Vector> {
    let n = v.x.hypot(v.y);
    (n.is_finite() && n > 0.0).then(|| v / n)
}
