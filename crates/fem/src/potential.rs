//! The solved potential: nodal values of ψ = c − φ on a mesh, point evaluation, gradients,
//! recovery, an error indicator and the discrete maximum principle check.

use std::sync::{Arc, OnceLock};

use rayon::prelude::*;

use harmonic_types::{Mesh, NO_NEIGHBOR, Point, Vector, geom::twice_signed_area};

use crate::FemError;
use crate::solve::EXTENDED_BELOW;
use harmonic_solver::Wide;

/// A P1 potential on a mesh, stored as ψ = c − φ at every vertex (see the crate docs).
///
/// The robot ascends ψ, i.e. descends φ: the direction of motion is
/// [`Evaluation::grad_psi`] = −∇φ.
#[derive(Clone, Debug)]
pub struct Potential {
    mesh: Arc<Mesh>,
    psi: Vec<f64>,
    reference: f64,
    nodal_gradients: OnceLock<Vec<Vector>>,
    /// ψ with exponents, when some ψ lies below [`EXTENDED_BELOW`] (`psi` then holds the
    /// nearest floats, 0 where they underflow).
    extended: Option<Extended>,
}

/// ψ past the double range: ψᵢ = `mantissa[i]` · 2^`exponent[i]`, and the recovered nodal
/// gradients in the same form (computed once).
#[derive(Clone, Debug)]
struct Extended {
    mantissa: Vec<f64>,
    exponent: Vec<i32>,
    nodal_gradients: OnceLock<(Vec<Vector>, Vec<i32>)>,
}

/// `(x, y)` as one mantissa vector on the scale of the larger exponent.
fn wide_vector(x: Wide, y: Wide) -> (Vector, i32) {
    let e = match (x.is_zero(), y.is_zero()) {
        (true, true) => 0,
        (true, false) => y.exponent(),
        (false, true) => x.exponent(),
        (false, false) => x.exponent().max(y.exponent()),
    };
    (Vector::new(x.scaled(e), y.scaled(e)), e)
}

/// The potential at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evaluation {
    /// The triangle containing the point (pass it as the next `hint`).
    pub triangle: u32,
    /// ψ = c − φ, linearly interpolated.
    pub psi: f64,
    /// φ, linearly interpolated.
    pub phi: f64,
    /// ∇ψ = −∇φ on the triangle (constant per triangle).
    pub grad_psi: Vector,
}

impl Potential {
    /// A potential from ψ at every vertex of `mesh` and the reference value `c` (φ = c − ψ).
    pub fn new(mesh: Arc<Mesh>, psi: Vec<f64>, reference: f64) -> Result<Self, FemError> {
        if psi.len() != mesh.vertices().len() {
            return Err(FemError::LengthMismatch {
                what: "ψ values per mesh vertex",
                expected: mesh.vertices().len(),
                got: psi.len(),
            });
        }
        Ok(Potential {
            mesh,
            psi,
            reference,
            nodal_gradients: OnceLock::new(),
            extended: None,
        })
    }

    /// A potential from ψ in extended-exponent form (as [`crate::Solver::solve_wide`] gives
    /// it). If every non-zero ψ lies above [`EXTENDED_BELOW`] this is exactly
    /// [`Potential::new`] of the floats; otherwise the exponents are kept
    /// ([`Potential::is_extended`]) and [`psi`](Self::psi) holds the nearest floats (0 where
    /// they underflow).
    pub fn from_wide(mesh: Arc<Mesh>, psi: Vec<Wide>, reference: f64) -> Result<Self, FemError> {
        let floats: Vec<f64> = psi.iter().map(|w| w.to_f64()).collect();
        let below = Wide::from_f64(EXTENDED_BELOW);
        let mut potential = Potential::new(mesh, floats, reference)?;
        if psi.iter().any(|w| !w.is_zero() && w.abs() < below) {
            potential.extended = Some(Extended {
                mantissa: psi.iter().map(|w| w.mantissa()).collect(),
                exponent: psi.iter().map(|w| w.exponent()).collect(),
                nodal_gradients: OnceLock::new(),
            });
        }
        Ok(potential)
    }

    /// Whether ψ is kept with exponents (some ψ below [`EXTENDED_BELOW`]): then follow
    /// [`psi_extended`](Self::psi_extended) and
    /// [`nodal_gradients_extended`](Self::nodal_gradients_extended) rather than the floats.
    pub fn is_extended(&self) -> bool {
        self.extended.is_some()
    }

    /// ψ as mantissas and binary exponents (ψᵢ = mᵢ·2^eᵢ) when [`is_extended`](Self::is_extended).
    pub fn psi_extended(&self) -> Option<(&[f64], &[i32])> {
        self.extended
            .as_ref()
            .map(|x| (x.mantissa.as_slice(), x.exponent.as_slice()))
    }

    /// ψ at vertex `v` with its exponent (exact for an extended potential, else the float).
    /// Panics if `v` is out of range.
    pub fn psi_wide(&self, v: u32) -> Wide {
        match &self.extended {
            Some(x) => Wide::from_parts(x.mantissa[v as usize], x.exponent[v as usize]),
            None => Wide::from_f64(self.psi[v as usize]),
        }
    }

    /// log₁₀ ψ at every vertex (−∞ where ψ is 0), exact past the double range.
    pub fn log10_psi(&self) -> Vec<f64> {
        (0..self.psi.len() as u32)
            .map(|v| self.psi_wide(v).log10())
            .collect()
    }

    /// The recovered nodal gradients of ψ as mantissa vectors and binary exponents (∇ψᵢ =
    /// gᵢ·2^eᵢ) when [`is_extended`](Self::is_extended): the area-weighted average of the
    /// triangle gradients, each computed from the vertex values rescaled by the triangle's
    /// largest exponent, summed in extended arithmetic. Computed once.
    pub fn nodal_gradients_extended(&self) -> Option<(&[Vector], &[i32])> {
        let x = self.extended.as_ref()?;
        let (g, e) = x.nodal_gradients.get_or_init(|| {
            let nv = self.mesh.vertices().len();
            let mut sum = vec![(Wide::ZERO, Wide::ZERO); nv];
            let mut area = vec![0.0; nv];
            for (t, tri) in self.mesh.triangles().iter().enumerate() {
                let a = self.mesh.triangle_area(t as u32);
                let (g, e) = self.triangle_gradient_psi_scaled(t as u32);
                let gx = Wide::from_parts(g.x * a, e);
                let gy = Wide::from_parts(g.y * a, e);
                for &v in tri {
                    let s = &mut sum[v as usize];
                    s.0 += gx;
                    s.1 += gy;
                    area[v as usize] += a;
                }
            }
            sum.iter()
                .zip(&area)
                .map(|(&(x, y), &a)| {
                    let inv = Wide::from_f64(if a > 0.0 { 1.0 / a } else { 1.0 });
                    wide_vector(x * inv, y * inv)
                })
                .unzip()
        });
        Some((g.as_slice(), e.as_slice()))
    }

    /// ∇ψ on triangle `t` as a mantissa vector and a binary exponent (∇ψ = g·2^e): the
    /// vertex values rescaled by their largest exponent, so it never underflows. For a
    /// potential that is not extended the exponent is 0 and `g` is
    /// [`triangle_gradient_psi`](Self::triangle_gradient_psi). Panics if `t` is out of range.
    pub fn triangle_gradient_psi_scaled(&self, t: u32) -> (Vector, i32) {
        let Some(x) = &self.extended else {
            return (self.triangle_gradient_psi(t), 0);
        };
        let tri = self.mesh.triangles()[t as usize];
        let w = tri.map(|v| Wide::from_parts(x.mantissa[v as usize], x.exponent[v as usize]));
        let e = w
            .iter()
            .filter(|w| !w.is_zero())
            .map(|w| w.exponent())
            .max()
            .unwrap_or(0);
        let [s0, s1, s2] = w.map(|w| w.scaled(e));
        (self.gradient_from(t, [s0, s1, s2]), e)
    }

    /// The P1 gradient on triangle `t` of the vertex values `s`.
    fn gradient_from(&self, t: u32, [s0, s1, s2]: [f64; 3]) -> Vector {
        let [p0, p1, p2] = self.mesh.triangle_points(t);
        let rot = |d: Vector| Vector::new(-d.y, d.x);
        (rot(p2 - p1) * s0 + rot(p0 - p2) * s1 + rot(p1 - p0) * s2) / twice_signed_area(p0, p1, p2)
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }
    /// ψ = c − φ at every vertex.
    pub fn psi(&self) -> &[f64] {
        &self.psi
    }
    /// The reference value `c`.
    pub fn reference(&self) -> f64 {
        self.reference
    }
    /// φ = c − ψ at every vertex (loses ψ's relative precision where φ ≈ c).
    pub fn phi_at_vertices(&self) -> Vec<f64> {
        self.psi.iter().map(|&s| self.reference - s).collect()
    }

    /// ∇ψ on triangle `t` (= −∇φ), from the float ψ (so it underflows to 0 where ψ does;
    /// see [`triangle_gradient_psi_scaled`](Self::triangle_gradient_psi_scaled)). Panics if
    /// `t` is out of range.
    pub fn triangle_gradient_psi(&self, t: u32) -> Vector {
        let tri = self.mesh.triangles()[t as usize];
        // ∇λ_k = rot90(p_{k+2} − p_{k+1}) / 2A; sum ψ_k ∇λ_k.
        self.gradient_from(t, tri.map(|v| self.psi[v as usize]))
    }

    /// ∇ψ on every triangle.
    pub fn triangle_gradients_psi(&self) -> Vec<Vector> {
        (0..self.mesh.triangles().len() as u32)
            .map(|t| self.triangle_gradient_psi(t))
            .collect()
    }

    /// Recovered nodal gradients of ψ: the area-weighted average of the gradients of the
    /// triangles around each vertex (zero at vertices used by no triangle). Computed once.
    pub fn nodal_gradients_psi(&self) -> &[Vector] {
        self.nodal_gradients.get_or_init(|| {
            let nv = self.mesh.vertices().len();
            let mut sum = vec![Vector::zeros(); nv];
            let mut area = vec![0.0; nv];
            for (t, tri) in self.mesh.triangles().iter().enumerate() {
                let a = self.mesh.triangle_area(t as u32);
                let g = self.triangle_gradient_psi(t as u32) * a;
                for &v in tri {
                    sum[v as usize] += g;
                    area[v as usize] += a;
                }
            }
            sum.iter()
                .zip(&area)
                .map(|(&s, &a)| if a > 0.0 { s / a } else { s })
                .collect()
        })
    }

    /// The triangle containing `p` (`hint`: a triangle near `p`, e.g. the previous one).
    pub fn locate(&self, p: Point, hint: Option<u32>) -> Result<u32, FemError> {
        self.mesh
            .locate(p, hint)
            .ok_or(FemError::OutsideMesh { at: p.into() })
    }

    /// Barycentric coordinates of `p` in triangle `t` (negative outside it).
    fn barycentric(&self, t: u32, p: Point) -> [f64; 3] {
        harmonic_types::geom::barycentric(self.mesh.triangle_points(t), p)
    }

    /// ψ interpolated on triangle `t` at `p` (linear extrapolation if `p` is outside `t`).
    pub fn psi_in_triangle(&self, t: u32, p: Point) -> f64 {
        let l = self.barycentric(t, p);
        let tri = self.mesh.triangles()[t as usize];
        (0..3).map(|k| l[k] * self.psi[tri[k] as usize]).sum()
    }

    /// Value and gradient at `p`.
    pub fn evaluate(&self, p: Point, hint: Option<u32>) -> Result<Evaluation, FemError> {
        let t = self.locate(p, hint)?;
        let psi = self.psi_in_triangle(t, p);
        Ok(Evaluation {
            triangle: t,
            psi,
            phi: self.reference - psi,
            grad_psi: self.triangle_gradient_psi(t),
        })
    }

    /// ψ at `p`.
    pub fn psi_at(&self, p: Point, hint: Option<u32>) -> Result<f64, FemError> {
        Ok(self.evaluate(p, hint)?.psi)
    }

    /// φ at `p`.
    pub fn phi_at(&self, p: Point, hint: Option<u32>) -> Result<f64, FemError> {
        Ok(self.evaluate(p, hint)?.phi)
    }

    /// The recovered (continuous, piecewise linear) gradient of ψ at `p`: the nodal gradients
    /// of [`nodal_gradients_psi`](Self::nodal_gradients_psi) interpolated linearly.
    pub fn recovered_gradient_psi_at(
        &self,
        p: Point,
        hint: Option<u32>,
    ) -> Result<Vector, FemError> {
        let t = self.locate(p, hint)?;
        let l = self.barycentric(t, p);
        let g = self.nodal_gradients_psi();
        let tri = self.mesh.triangles()[t as usize];
        Ok((0..3).map(|k| g[tri[k] as usize] * l[k]).sum())
    }

    /// A per-triangle error indicator: η_T = (½ Σ_e |e|² [∂ψ/∂n]_e²)^½ over the interior
    /// edges `e` of `T`, with `[∂ψ/∂n]` the jump of the normal gradient across `e` (the edge
    /// part of the standard residual estimator; the element residual vanishes for P1).
    pub fn error_indicator(&self) -> Vec<f64> {
        let grads = self.triangle_gradients_psi();
        let mesh = &*self.mesh;
        mesh.triangles()
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let mut sum = 0.0;
                for k in 0..3 {
                    let nb = mesh.neighbors()[t][k];
                    if nb == NO_NEIGHBOR {
                        continue;
                    }
                    let d = mesh.vertices()[tri[(k + 2) % 3] as usize]
                        - mesh.vertices()[tri[(k + 1) % 3] as usize];
                    // |e| n = (d.y, −d.x); the jump times |e| is (g_T − g_N)·(|e| n).
                    let jump_times_len =
                        (grads[t] - grads[nb as usize]).dot(&Vector::new(d.y, -d.x));
                    sum += 0.5 * jump_times_len * jump_times_len;
                }
                sum.sqrt()
            })
            .collect()
    }

    /// The number of interior vertices (on no boundary) whose φ is a strict local minimum or
    /// maximum among their edge neighbours. Zero for a harmonic potential on a Delaunay mesh
    /// (discrete maximum principle).
    pub fn interior_local_extrema(&self) -> usize {
        let e = self.local_extrema();
        e.minima + e.maxima
    }

    /// The strict interior local extrema of φ ([`interior_local_extrema`]), compared on the
    /// extended ψ when the potential is extended (the floats tie where they underflow).
    pub fn local_extrema(&self) -> LocalExtrema {
        match &self.extended {
            None => interior_local_extrema(&self.mesh, &self.psi),
            Some(_) => {
                let psi: Vec<Wide> = (0..self.psi.len() as u32)
                    .map(|v| self.psi_wide(v))
                    .collect();
                extrema_of(&self.mesh, &psi, |_| false)
            }
        }
    }
}

/// Counts of interior vertices where φ (= c − ψ) is a strict local extremum.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LocalExtrema {
    /// Vertices whose φ is below every edge neighbour's (ψ above): where a robot would stop.
    pub minima: usize,
    /// Vertices whose φ is above every edge neighbour's (ψ below).
    pub maxima: usize,
}

/// The strict local extrema of the nodal values `psi` over the interior vertices (on no
/// boundary) of `mesh`, each vertex compared with the vertices it shares an edge with. The
/// discrete maximum principle says both counts are zero for a harmonic potential on a mesh
/// whose stiffness is an M-matrix.
pub fn interior_local_extrema(mesh: &Mesh, psi: &[f64]) -> LocalExtrema {
    interior_local_extrema_except(mesh, psi, |_| false)
}

/// [`interior_local_extrema`] over the interior vertices that are not `excluded`: for a
/// field whose goal is held at interior vertices, which are its maxima of ψ by design.
pub fn interior_local_extrema_except(
    mesh: &Mesh,
    psi: &[f64],
    excluded: impl Fn(u32) -> bool + Sync,
) -> LocalExtrema {
    extrema_of(mesh, psi, excluded)
}

/// Why a ψ solved to a normwise accuracy (a Cholesky ψ, a multigrid ψ) cannot be handed to
/// the tracer as it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unsound {
    /// A negative (or not-a-number) value at an unknown.
    Negative,
    /// A zero at an unknown beside a positive value: ψ underflowed there (the M-matrix's
    /// inverse is positive, so a goal's ψ is positive at every vertex connected to it), and
    /// a start there would not move.
    Underflow,
    /// An interior local extremum at an unknown, where the tracer could stop.
    InteriorExtremum,
}

/// Whether the discrete maximum principle holds for `psi` on `mesh` as the tracer needs it,
/// over the unknowns `free_vertices` (every other vertex is held by a condition): no
/// negative value, no zero beside a positive one, no interior local extremum.
pub(crate) fn unsound(mesh: &Mesh, psi: &[f64], free_vertices: &[u32]) -> Option<Unsound> {
    if free_vertices
        .par_iter()
        .any(|&v| psi[v as usize].is_nan() || psi[v as usize] < 0.0)
    {
        return Some(Unsound::Negative);
    }
    let mut held = vec![true; psi.len()];
    for &v in free_vertices {
        held[v as usize] = false;
    }
    let underflow = mesh.triangles().par_iter().any(|t| {
        let zero = t
            .iter()
            .any(|&v| !held[v as usize] && psi[v as usize] == 0.0);
        zero && t.iter().any(|&v| psi[v as usize] > 0.0)
    });
    if underflow {
        return Some(Unsound::Underflow);
    }
    let e = interior_local_extrema_except(mesh, psi, |v| held[v as usize]);
    (e.minima + e.maxima > 0).then_some(Unsound::InteriorExtremum)
}

/// [`interior_local_extrema_except`] over any ordered values (floats or [`Wide`] numbers),
/// on every core: each edge of each triangle marks, at both its ends, whether the other end
/// is not below it and whether it is not above it; a vertex with neighbours and no mark of
/// one kind is a strict extremum (a neighbour that does not compare, a NaN, marks both).
fn extrema_of<T: PartialOrd + Copy + Sync>(
    mesh: &Mesh,
    psi: &[T],
    excluded: impl Fn(u32) -> bool + Sync,
) -> LocalExtrema {
    use std::sync::atomic::{AtomicU8, Ordering::Relaxed};
    const HAS_NEIGHBOUR: u8 = 1;
    const NOT_ABOVE_ALL: u8 = 2;
    const NOT_BELOW_ALL: u8 = 4;
    let nv = mesh.vertices().len().min(psi.len());
    let marks: Vec<AtomicU8> = (0..nv).map(|_| AtomicU8::new(0)).collect();
    // Most vertices carry every mark after a few of their edges: look before writing.
    let mark = |v: usize, other: usize| {
        let order = psi[v].partial_cmp(&psi[other]);
        let mut m = HAS_NEIGHBOUR;
        if order != Some(std::cmp::Ordering::Greater) {
            m |= NOT_ABOVE_ALL;
        }
        if order != Some(std::cmp::Ordering::Less) {
            m |= NOT_BELOW_ALL;
        }
        if marks[v].load(Relaxed) & m != m {
            marks[v].fetch_or(m, Relaxed);
        }
    };
    mesh.triangles().par_iter().for_each(|tri| {
        for k in 0..3 {
            let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
            if a < nv && b < nv {
                mark(a, b);
                mark(b, a);
            }
        }
    });
    let tags = mesh.vertex_tags();
    (0..nv)
        .into_par_iter()
        .filter(|&v| tags[v].is_none() && !excluded(v as u32))
        .map(|v| {
            let m = marks[v].load(Relaxed);
            let has = m & HAS_NEIGHBOUR != 0;
            LocalExtrema {
                minima: usize::from(has && m & NOT_ABOVE_ALL == 0),
                maxima: usize::from(has && m & NOT_BELOW_ALL == 0),
            }
        })
        .reduce(LocalExtrema::default, |a, b| LocalExtrema {
            minima: a.minima + b.minima,
            maxima: a.maxima + b.maxima,
        })
}

/// The blended field of the ME766 paper: φ = k·φ_a + (1−k)·φ_b, e.g. `a` from a Dirichlet
/// solve and `b` from one with Neumann walls and obstacles. `k` must lie in [0, 1] (a convex
/// combination keeps the maximum principle); both potentials must share the mesh. Blends the
/// float ψ: an extended potential's values below the double range count as 0.
///
/// ```
/// # use std::sync::Arc;
/// # use harmonic_fem::{Potential, blend};
/// # use harmonic_mesh::{BoundaryTag, Mesh, Point};
/// # let mesh = Arc::new(Mesh::from_parts(
/// #     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0)],
/// #     vec![[0, 1, 2]],
/// #     &[(0, 1, BoundaryTag::Goal(0)), (1, 2, BoundaryTag::Wall), (2, 0, BoundaryTag::Wall)],
/// # )?);
/// let a = Potential::new(mesh.clone(), vec![1.0, 0.0, 0.5], 1.0)?;
/// let b = Potential::new(mesh, vec![3.0, 1.0, 2.0], 2.0)?;
/// let c = blend(0.25, &a, &b)?;
/// let phi = c.phi_at_vertices();
/// assert!((phi[0] - (0.25 * 0.0 + 0.75 * -1.0)).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn blend(k: f64, a: &Potential, b: &Potential) -> Result<Potential, FemError> {
    if !(0.0..=1.0).contains(&k) {
        return Err(FemError::BadWeight { k });
    }
    let same_mesh = Arc::ptr_eq(&a.mesh, &b.mesh)
        || (a.mesh.vertices() == b.mesh.vertices() && a.mesh.triangles() == b.mesh.triangles());
    if !same_mesh {
        return Err(FemError::DifferentMeshes);
    }
    let psi = a
        .psi
        .iter()
        .zip(&b.psi)
        .map(|(&x, &y)| k * x + (1.0 - k) * y)
        .collect();
    Potential::new(
        Arc::clone(&a.mesh),
        psi,
        k * a.reference + (1.0 - k) * b.reference,
    )
}
