//! The smooth tracer: adaptive Dormand–Prince 5(4) integration of the normalised descent
//! direction `−∇value / |∇value|` (constant speed: |∇value| varies by orders of magnitude
//! across a scene), with point location by walking from the previous cell. One tracer for
//! every dimension: the plane (`D = 2`), volumes and configuration spaces (`D = 3`).
//!
//! Every accepted step is checked with [`Field::segment`] so it never crosses a wall or an
//! obstacle; a step that would is shortened, and when steps get too short (against a wall,
//! at a stagnation point) the tracer takes one [`Field::fallback_step`] (for P1 fields, one
//! move of the exact tracer) and resumes.

use nalgebra::{Point, SVector};

use crate::{Fallback, Field, Locate, Path, PathPoint, Segment, TraceError, TraceStatus};

/// `|v|` without underflow or overflow: ψ's gradients go far below 1e-154 (where the squared
/// norm underflows to zero) in the far rooms of large scenes.
#[inline]
fn magnitude<const D: usize>(v: &SVector<f64, D>) -> f64 {
    let n2 = v.norm_squared();
    if (1e-280..1e280).contains(&n2) {
        return n2.sqrt();
    }
    let m = v.amax();
    if m > 0.0 && m.is_finite() {
        m * (v / m).norm()
    } else {
        m
    }
}

/// Options of the smooth tracer. Lengths are in scene units: build them with
/// [`SmoothOptions::for_scale`] from the scene's size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothOptions {
    /// First step length.
    pub initial_step: f64,
    /// Largest step length.
    pub max_step: f64,
    /// Steps shorter than this give way to a fallback step.
    pub min_step: f64,
    /// Largest local error (distance between the 5th- and 4th-order solutions) per step.
    pub tolerance: f64,
    /// Largest number of accepted steps and fallback steps.
    pub max_steps: usize,
    /// The path ends `Stalled` after this many steps without lowering the field's value.
    pub stall_steps: usize,
}

impl SmoothOptions {
    /// Options for a scene of the given size (its bounding box's larger side): steps of at
    /// most 1/50 of it, a local error of 1e-5 of it.
    pub fn for_scale(scale: f64) -> Self {
        SmoothOptions {
            initial_step: 1e-3 * scale,
            max_step: 0.02 * scale,
            min_step: 1e-9 * scale,
            tolerance: 1e-5 * scale,
            max_steps: 100_000,
            stall_steps: 500,
        }
    }

    /// Checks that the lengths are positive and ordered.
    pub fn validate(&self) -> Result<(), TraceError> {
        let check = |name, value: f64| {
            if value > 0.0 && value.is_finite() {
                Ok(())
            } else {
                Err(TraceError::InvalidOption {
                    name,
                    value,
                    reason: "must be positive and finite",
                })
            }
        };
        check("initial_step", self.initial_step)?;
        check("max_step", self.max_step)?;
        check("min_step", self.min_step)?;
        check("tolerance", self.tolerance)?;
        if self.min_step > self.max_step {
            return Err(TraceError::InvalidOption {
                name: "min_step",
                value: self.min_step,
                reason: "must not exceed max_step",
            });
        }
        Ok(())
    }
}

impl Default for SmoothOptions {
    /// [`SmoothOptions::for_scale`] for a scene of size 10.
    fn default() -> Self {
        SmoothOptions::for_scale(10.0)
    }
}

const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights minus 4th-order weights: the error estimate's coefficients.
const E: [f64; 7] = [
    35.0 / 384.0 - 5179.0 / 57600.0,
    0.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
];

/// The unit descent direction at `q` reached in a straight line from `from` in `cell`.
enum Eval<C, const D: usize> {
    Dir(SVector<f64, D>, C, f64),
    Goal(u32),
    Blocked,
    Flat,
}

fn eval<const D: usize, F: Field<Point = Point<f64, D>, Vector = SVector<f64, D>>>(
    field: &F,
    cell: F::Cell,
    from: Point<f64, D>,
    q: Point<f64, D>,
) -> Eval<F::Cell, D> {
    match field.segment(cell, from, q) {
        Segment::Inside(c) => {
            let g = field.gradient(c, q);
            let n = magnitude(&g);
            if n > 0.0 && n.is_finite() {
                Eval::Dir(-g / n, c, n)
            } else {
                Eval::Flat
            }
        }
        Segment::Goal(j) => Eval::Goal(j),
        Segment::Blocked => Eval::Blocked,
    }
}

/// Follows `field` downhill from `start` with an adaptive Dormand–Prince 5(4) integrator, in
/// the plane or in space (a field of [`harmonic_types::Point`]s or of
/// [`harmonic_types::Point3`]s).
///
/// The path's points are the accepted steps (and fallback moves); `cells_crossed` counts
/// the steps that ended in a different cell than they started (a step may pass several
/// cells), and `min_gradient` is the smallest |∇value| at a step's end. Paths that reach a
/// goal end on its boundary (to 2⁻⁴⁰ of the last step).
///
/// Errors only for invalid options; how the path ended is in its `status`.
///
/// ```
/// use harmonic_mesh::{BoundaryTag, Mesh, Point};
/// use harmonic_trajectory::{P1Field, SmoothOptions, TraceStatus, trace_smooth};
/// let mesh = Mesh::from_parts(
///     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)],
///     vec![[0, 1, 2], [0, 2, 3]],
///     &[(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Wall),
///       (2, 3, BoundaryTag::Goal(0)), (3, 0, BoundaryTag::Wall)],
/// )?;
/// let psi = [0.0, 0.0, 1.0, 1.0];
/// let field = P1Field::ascending(&mesh, &psi)?;
/// let path = trace_smooth(&field, Point::new(0.7, 0.2), &SmoothOptions::for_scale(1.0))?;
/// assert_eq!(path.status, TraceStatus::ReachedGoal(0));
/// assert!((path.length - 0.8).abs() < 1e-6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn trace_smooth<const D: usize, F: Field<Point = Point<f64, D>, Vector = SVector<f64, D>>>(
    field: &F,
    start: Point<f64, D>,
    opts: &SmoothOptions,
) -> Result<Path<Point<f64, D>>, TraceError>
where
    Point<f64, D>: PathPoint,
{
    trace_smooth_with_hint(field, start, None, opts)
}

/// [`trace_smooth`] with a cell that probably holds `start` (for instance the triangle the
/// caller already knows the robot is in): the start is located by walking from it, so no
/// point-location structure is built. A wrong hint costs a longer walk, never a wrong answer.
pub fn trace_smooth_with_hint<
    const D: usize,
    F: Field<Point = Point<f64, D>, Vector = SVector<f64, D>>,
>(
    field: &F,
    start: Point<f64, D>,
    hint: Option<F::Cell>,
    opts: &SmoothOptions,
) -> Result<Path<Point<f64, D>>, TraceError>
where
    Point<f64, D>: PathPoint,
{
    opts.validate()?;
    let single = |s| Ok(Path::new(vec![start], s, f64::INFINITY, 0));
    let mut cell = match field.locate(start, hint) {
        Locate::Inside(c) => c,
        Locate::Goal(j) => return single(TraceStatus::ReachedGoal(j)),
        Locate::InObstacle => return single(TraceStatus::StartInObstacle),
        Locate::OutsideWorkspace => return single(TraceStatus::OutsideWorkspace),
    };
    if !field.goal_reachable(cell) {
        return single(TraceStatus::Unreachable);
    }
    let mut points = vec![start];
    let mut x = start;
    let mut min_gradient = f64::INFINITY;
    let mut crossed = 0;
    let mut h = opts.initial_step.min(opts.max_step);
    let mut best = field.value(cell, x);
    let mut since_best = 0;
    let mut k1: Option<SVector<f64, D>> = None;
    let mut steps = 0;
    let status = 'outer: loop {
        if steps >= opts.max_steps {
            break TraceStatus::MaxSteps;
        }
        if since_best > opts.stall_steps {
            break TraceStatus::Stalled { at: x };
        }
        let first = match k1 {
            Some(k) => Some(k),
            None => match eval(field, cell, x, x) {
                Eval::Dir(d, _, n) => {
                    min_gradient = min_gradient.min(n);
                    Some(d)
                }
                Eval::Goal(j) => break TraceStatus::ReachedGoal(j),
                Eval::Blocked | Eval::Flat => None,
            },
        };
        let Some(first) = first.filter(|_| h >= opts.min_step) else {
            // No usable direction here, or steps keep failing: one guaranteed move.
            steps += 1;
            since_best += 1;
            match field.fallback_step(cell, x) {
                Fallback::Moved(q, c) => {
                    crossed += usize::from(c != cell);
                    x = q;
                    cell = c;
                    points.push(q);
                    k1 = None;
                    h = opts.initial_step.min(opts.max_step);
                    let v = field.value(cell, x);
                    if v < best {
                        best = v;
                        since_best = 0;
                    }
                    continue;
                }
                Fallback::Goal(j) => break TraceStatus::ReachedGoal(j),
                Fallback::Stuck => break TraceStatus::Stalled { at: x },
            }
        };
        k1 = Some(first);
        // Stages.
        let mut k = [SVector::<f64, D>::zeros(); 7];
        k[0] = first;
        let mut last = None;
        for s in 1..7 {
            let mut q = x.coords;
            for (j, kj) in k.iter().enumerate().take(s) {
                q += kj * (h * A[s][j]);
            }
            let q = Point::from(q);
            match eval(field, cell, x, q) {
                Eval::Dir(d, c, n) => {
                    k[s] = d;
                    if s == 6 {
                        last = Some((q, c, n));
                    }
                }
                Eval::Goal(_) => {
                    // A stage lies in the goal: if the straight step along the current
                    // direction enters it, the path ends there.
                    let q = x + first * h;
                    if let Segment::Goal(g) = field.segment(cell, x, q) {
                        points.push(crate::field::goal_crossing(field, cell, x, q));
                        break 'outer TraceStatus::ReachedGoal(g);
                    }
                    h *= 0.5;
                    continue 'outer;
                }
                Eval::Blocked | Eval::Flat => {
                    h *= 0.5;
                    continue 'outer;
                }
            }
        }
        let Some((y, c, n)) = last else {
            h *= 0.5;
            continue;
        };
        let err = k
            .iter()
            .zip(E)
            .fold(SVector::<f64, D>::zeros(), |acc, (kk, e)| acc + kk * e)
            .norm()
            * h;
        if err.is_nan() || err > opts.tolerance {
            h *= (0.9 * (opts.tolerance / err).powf(0.2)).clamp(0.1, 0.5);
            continue;
        }
        // Accept.
        steps += 1;
        crossed += usize::from(c != cell);
        x = y;
        cell = c;
        points.push(y);
        min_gradient = min_gradient.min(n);
        k1 = Some(k[6]);
        let v = field.value(cell, x);
        if v < best {
            best = v;
            since_best = 0;
        } else {
            since_best += 1;
        }
        let grow = if err > 0.0 {
            0.9 * (opts.tolerance / err).powf(0.2)
        } else {
            5.0
        };
        h = (h * grow.clamp(0.2, 5.0)).min(opts.max_step);
    };
    Ok(Path::new(points, status, min_gradient, crossed))
}
