//! Solving the tetrahedral system: the entrywise-accurate M-matrix elimination where it is
//! small, faer's Cholesky (AMD ordering) on small systems, IC(0)-PCG beyond (in 3D the
//! factors' fill makes PCG far cheaper from a few ten thousand unknowns), multigrid-PCG on
//! large ones; and the planning solve, which checks the field's maximum principle and falls
//! back (clamped weights, IC(0), the far field layer by layer, Cholesky) until it holds.

use std::sync::Arc;
use std::time::Instant;

use harmonic_solver::{
    AccurateLdlt, AggregationOptions, Multigrid, Ordering, PcgOptions, Preconditioner,
    SymbolicCholesky, SymmetricCsc, pcg,
};
use harmonic_types::TetMesh;

use super::FemError;
use super::assemble::{NegativeWeights, VolumeAssembler, VolumeSystem};
use super::potential::VolumePotential;
use crate::bc::BoundaryConditions;

/// Up to this many unknowns [`VolumeSolveMethod::Auto`] uses the accurate solve on M-matrix
/// systems: the elimination's 3D fill makes it slower than Cholesky beyond (measured on the
/// bench scene, clamped weights, 51 k unknowns: 4.4 s against Cholesky's 1.9 s and IC(0)-PCG's
/// 0.12 s; 69 s when the elimination was simplicial).
pub const AUTO_ACCURATE_MAX_UNKNOWNS_3D: usize = 15_000;
/// Up to this many unknowns [`VolumeSolveMethod::Auto`] factors with Cholesky; above, IC(0)-PCG,
/// which wins by far in 3D (50.6k unknowns: PCG 0.16 s in 40 iterations, Cholesky 3.9 s;
/// `H=0.3 cargo test --release -p harmonic-fem --test volume_solvers -- --ignored --nocapture`).
pub const AUTO_CHOLESKY_MAX_UNKNOWNS: usize = 20_000;

/// From this many unknowns [`VolumeSolveMethod::Auto`] uses the smoothed-aggregation
/// multigrid instead of IC(0) (the planning solve's clamped try: from
/// [`SPECULATIVE_MAX_UNKNOWNS`], see [`PLANNING_PCG_TOL`]): measured on this project's
/// 2-core machine, me766's 891 k unknowns in 18 iterations and 1.9 s against IC(0)'s 6.2 s,
/// a 3-link arm's 125 k in 23–24 iterations and 0.24–0.43 s against 0.7–0.8 s; at the 40 k of
/// the seeded volume scenes the two are even (`cargo run --release --example volume_reach`).
pub const AUTO_MULTIGRID_MIN_UNKNOWNS: usize = 80_000;

/// Iteration bound of a multigrid solve (it converges in 10–30).
const MULTIGRID_MAX_ITER: usize = 500;

/// Up to this many unknowns the planning solve tries the clamped system on another core while
/// the Galerkin one is solved; above, one solve at a time, each on every core (me766's 891 k
/// unknowns: 2.7 s against 3.8 s for both at once, and 0.4 GB less).
pub const SPECULATIVE_MAX_UNKNOWNS: usize = 400_000;

/// How to solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VolumeSolveMethod {
    /// Accurate on small M-matrices, else Cholesky, PCG on large systems, multigrid-PCG
    /// from `AUTO_MULTIGRID_MIN_UNKNOWNS`.
    #[default]
    Auto,
    /// [`AccurateLdlt`] (needs an M-matrix).
    Accurate,
    /// faer's supernodal Cholesky with AMD.
    Cholesky,
    /// Conjugate gradients with IC(0), to relative residual 1e-10.
    Pcg,
    /// Conjugate gradients with a smoothed-aggregation multigrid V-cycle
    /// ([`Multigrid::aggregation`]), to relative residual 1e-10.
    Multigrid,
}

/// What a solve did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeSolveReport {
    /// The method that produced ψ.
    pub method: VolumeSolveMethod,
    /// PCG iterations (0 for direct solves).
    pub iterations: usize,
    /// Seconds spent.
    pub seconds: f64,
}

/// Solves `system` by `method`; returns ψ at every vertex.
pub fn solve_volume(
    system: &VolumeSystem,
    method: VolumeSolveMethod,
) -> Result<(Vec<f64>, VolumeSolveReport), FemError> {
    solve_volume_to(system, method, 1e-10)
}

/// [`solve_volume`] with the iterative methods stopped at relative residual `pcg_tol` (at most
/// 1e-10).
fn solve_volume_to(
    system: &VolumeSystem,
    method: VolumeSolveMethod,
    pcg_tol: f64,
) -> Result<(Vec<f64>, VolumeSolveReport), FemError> {
    let pcg_tol = pcg_tol.min(1e-10);
    let start = Instant::now();
    let method = match method {
        VolumeSolveMethod::Auto => auto_method(system, AUTO_MULTIGRID_MIN_UNKNOWNS),
        m => m,
    };
    let (x, iterations) = solve_unknowns(system, method, pcg_tol)?;
    let psi = system.expand(&x)?;
    Ok((
        psi,
        VolumeSolveReport {
            method,
            iterations,
            seconds: start.elapsed().as_secs_f64(),
        },
    ))
}

/// The method [`VolumeSolveMethod::Auto`] takes for `system`: the accurate elimination on
/// small M-matrices, Cholesky on small systems, else [`iterative_method`] with the multigrid
/// from `multigrid_from` unknowns ([`AUTO_MULTIGRID_MIN_UNKNOWNS`] but for a volume's
/// Galerkin try).
fn auto_method(system: &VolumeSystem, multigrid_from: usize) -> VolumeSolveMethod {
    let n = system.matrix().n();
    if n == 0 {
        VolumeSolveMethod::Cholesky
    } else if system.not_m_matrix().is_none() && n <= AUTO_ACCURATE_MAX_UNKNOWNS_3D {
        VolumeSolveMethod::Accurate
    } else if n <= AUTO_CHOLESKY_MAX_UNKNOWNS {
        VolumeSolveMethod::Cholesky
    } else {
        iterative_method(n, multigrid_from)
    }
}

/// Multigrid-PCG from `multigrid_from` unknowns, IC(0)-PCG below.
fn iterative_method(n: usize, multigrid_from: usize) -> VolumeSolveMethod {
    if n >= multigrid_from {
        VolumeSolveMethod::Multigrid
    } else {
        VolumeSolveMethod::Pcg
    }
}

/// The unknowns by `method` (not [`VolumeSolveMethod::Auto`], taken as Cholesky), and the
/// iterations it took (0 for direct solves).
fn solve_unknowns(
    system: &VolumeSystem,
    method: VolumeSolveMethod,
    pcg_tol: f64,
) -> Result<(Vec<f64>, usize), FemError> {
    let n = system.matrix().n();
    if n == 0 {
        return Ok((Vec::new(), 0));
    }
    Ok(match method {
        VolumeSolveMethod::Accurate => {
            let m = system.m_matrix()?;
            (
                AccurateLdlt::factor(&m, Ordering::Amd)?.solve(system.rhs())?,
                0,
            )
        }
        VolumeSolveMethod::Cholesky | VolumeSolveMethod::Auto => {
            let x = SymbolicCholesky::analyze(system.matrix(), Ordering::Amd)?
                .factor(system.matrix())?
                .solve(system.rhs())?;
            (x, 0)
        }
        VolumeSolveMethod::Pcg => {
            let mut x = vec![0.0; n];
            let opts = PcgOptions {
                preconditioner: Preconditioner::IncompleteCholesky,
                rel_tol: pcg_tol,
                max_iter: 20_000,
            };
            let report = pcg(system.matrix(), system.rhs(), &mut x, &opts)?;
            if report.rel_residual.is_nan() || report.rel_residual > pcg_tol {
                return Err(FemError::NotConverged {
                    iterations: report.iterations,
                    residual: report.rel_residual,
                });
            }
            (x, report.iterations)
        }
        VolumeSolveMethod::Multigrid => {
            let mg = Multigrid::aggregation(system.matrix(), AggregationOptions::default())?;
            let mut x = vec![0.0; n];
            // A converged solve returns; one that stalls is an error.
            let report = mg.solve(system.rhs(), &mut x, pcg_tol, MULTIGRID_MAX_ITER)?;
            (x, report.iterations)
        }
    })
}

/// Below this ratio of the smallest to the largest ψ at the unknowns, a Cholesky ψ may
/// have lost its relative precision far from the goal; the planning solve then redoes it with
/// the accurate elimination (as the 2D `AUTO_FLAT_RATIO`).
pub const FLAT_RATIO_3D: f64 = 1e-12;

/// Largest system the planning solve hands to the accurate elimination when it must (a few
/// seconds at most; larger flat fields keep the normwise-accurate solution).
pub const PLANNING_ACCURATE_MAX_UNKNOWNS: usize = 25_000;

/// Largest clamped system the planning solve factors with Cholesky when IC(0)-PCG's field
/// still has an interior extremum (measured on graded stuffed meshes of 40–60 k unknowns:
/// 19–25 extrema after PCG to 1e-10, none after Cholesky).
pub const PLANNING_CHOLESKY_MAX_UNKNOWNS: usize = 200_000;

/// Relative residual of the planning solve's clamped PCG: deeper than the general 1e-10, since
/// noise where ψ is smaller than the residual is what an interior extremum is made of (on
/// 3-link arms' configuration spaces, 85 k unknowns: 80 iterations against 60).
///
/// Up to `SPECULATIVE_MAX_UNKNOWNS` (400 k) the clamped try is IC(0)-PCG whatever its size:
/// the multigrid's field, on a 3-link arm's 126 k unknowns, had interior extrema where ψ
/// fell to 1e-23 and was solved again by IC(0) (0.5 s each, 89 IC(0) iterations against 25
/// multigrid ones), while IC(0)'s field is what the planning solve keeps.
pub const PLANNING_PCG_TOL: f64 = 1e-13;

/// The planning solve's clamped (M-matrix) redo: the accurate elimination up to
/// [`PLANNING_ACCURATE_MAX_UNKNOWNS`]; beyond, IC(0)-PCG to [`PLANNING_PCG_TOL`], checked for
/// interior extrema, and Cholesky (up to [`PLANNING_CHOLESKY_MAX_UNKNOWNS`]) only when that
/// check fails. Cholesky on 85 k unknowns of a 3-link arm's space took 5.7 s, PCG 0.2 s.
pub(super) fn solve_clamped_for_planning(
    mesh: &Arc<TetMesh>,
    system: &VolumeSystem,
) -> Result<(VolumePotential, VolumeSolveReport), FemError> {
    let first = clamped_first_try(mesh, system)?;
    clamped_checked(mesh, system, first)
}

/// The first solve of [`solve_clamped_for_planning`]: accurate elimination or PCG.
fn clamped_first_try(
    mesh: &Arc<TetMesh>,
    system: &VolumeSystem,
) -> Result<(VolumePotential, VolumeSolveReport), FemError> {
    let (psi, report) = if system.matrix().n() <= PLANNING_ACCURATE_MAX_UNKNOWNS {
        solve_volume(system, VolumeSolveMethod::Accurate)?
    } else {
        let method = iterative_method(system.matrix().n(), SPECULATIVE_MAX_UNKNOWNS + 1);
        solve_volume_to(system, method, PLANNING_PCG_TOL)?
    };
    let potential = VolumePotential::new(Arc::clone(mesh), psi, system.reference())?;
    Ok((potential, report))
}

/// The check of [`solve_clamped_for_planning`]: a field with an interior extremum is solved
/// again, a multigrid one by IC(0)-PCG; one that still has an extremum is redone layer by
/// layer in its far field ([`far_field_layers`]), and (or an IC(0) one) by Cholesky up to
/// [`PLANNING_CHOLESKY_MAX_UNKNOWNS`]. Both iterations stop at the same residual, but only
/// IC(0)'s ψ keeps decaying smoothly far below it: the multigrid's coarse corrections leave
/// noise of about the residual's size everywhere, which makes extrema where ψ is smaller
/// still (the 3D maze at 1 M tetrahedra, ψ down to 1e-66).
fn clamped_checked(
    mesh: &Arc<TetMesh>,
    system: &VolumeSystem,
    (potential, report): (VolumePotential, VolumeSolveReport),
) -> Result<(VolumePotential, VolumeSolveReport), FemError> {
    if potential.interior_local_extrema() == 0 {
        return Ok((potential, report));
    }
    let (potential, report) = if report.method == VolumeSolveMethod::Multigrid {
        let (psi, mut again) = solve_volume_to(system, VolumeSolveMethod::Pcg, PLANNING_PCG_TOL)?;
        again.seconds += report.seconds;
        let potential = VolumePotential::new(Arc::clone(mesh), psi, system.reference())?;
        if potential.interior_local_extrema() == 0 {
            return Ok((potential, again));
        }
        (potential, again)
    } else {
        (potential, report)
    };
    if report.method != VolumeSolveMethod::Pcg {
        return Ok((potential, report));
    }
    let start = Instant::now();
    let x: Vec<f64> = system
        .free_vertices()
        .iter()
        .map(|&v| potential.psi()[v as usize])
        .collect();
    // A layer's solve that fails (it does not converge) leaves the fallbacks below to it.
    if let Ok(Some(x)) = far_field_layers(system.matrix(), system.rhs(), x) {
        let layered =
            VolumePotential::new(Arc::clone(mesh), system.expand(&x)?, system.reference())?;
        if layered.interior_local_extrema() == 0 {
            let report = VolumeSolveReport {
                seconds: report.seconds + start.elapsed().as_secs_f64(),
                ..report
            };
            return Ok((layered, report));
        }
    }
    if system.matrix().n() > PLANNING_CHOLESKY_MAX_UNKNOWNS {
        return Ok((potential, report));
    }
    let (psi, mut fallback) = solve_volume(system, VolumeSolveMethod::Cholesky)?;
    fallback.seconds += report.seconds + start.elapsed().as_secs_f64();
    Ok((
        VolumePotential::new(Arc::clone(mesh), psi, system.reference())?,
        fallback,
    ))
}

/// Each layer of [`far_field_layers`] takes the unknowns below this fraction of the
/// previous layer's threshold (the first: of the largest ψ).
const LAYER_RATIO: f64 = 1e-6;

/// At most this many layers (each resolves about six more orders of magnitude).
const MAX_LAYERS: usize = 60;

/// The far field of an iterative solution `x` of `a x = b` (an M-matrix) solved again, layer
/// by layer: the unknowns below [`LAYER_RATIO`] of the largest are solved on their own, the
/// rest held at their values (a principal submatrix of an M-matrix, its right-hand side the couplings to
/// the held unknowns: non-negative), then those below the ratio again of that threshold, and
/// so on. A residual-based stop leaves an error of about the residual's size everywhere,
/// which swamps ψ where it is many orders smaller (behind a narrow passage of a
/// configuration space, ψ falls to 1e-27); each layer's own solve is accurate relative to
/// its own values, which are held by the previous layer where it was still accurate (to
/// about 1e-10 / [`LAYER_RATIO`] relatively). `None` when there is no far field.
pub(crate) fn far_field_layers(
    a: &SymmetricCsc,
    b: &[f64],
    mut x: Vec<f64>,
) -> Result<Option<Vec<f64>>, FemError> {
    let n = a.n();
    let max = x.iter().copied().fold(0.0, f64::max);
    if max <= 0.0 {
        return Ok(None);
    }
    let mut level = max;
    let mut layered = false;
    for _ in 0..MAX_LAYERS {
        level *= LAYER_RATIO;
        let far: Vec<usize> = (0..n).filter(|&i| x[i] < level).collect();
        if far.is_empty() || far.len() == n {
            break;
        }
        let mut local = vec![usize::MAX; n];
        for (k, &i) in far.iter().enumerate() {
            local[i] = k;
        }
        let mut col_ptr = Vec::with_capacity(far.len() + 1);
        let (mut row_idx, mut values) = (Vec::new(), Vec::new());
        let mut rhs = vec![0.0; far.len()];
        col_ptr.push(0);
        for (k, &i) in far.iter().enumerate() {
            let (rows, vals) = a.column(i);
            rhs[k] = b[i];
            for (&j, &v) in rows.iter().zip(vals) {
                if local[j] == usize::MAX {
                    rhs[k] -= v * x[j];
                } else {
                    row_idx.push(local[j]);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        if rhs.iter().all(|&r| r == 0.0) {
            // Nothing couples the far unknowns to the rest: their ψ is zero.
            for &i in &far {
                x[i] = 0.0;
            }
            layered = true;
            break;
        }
        // Rows keep their order (`local` increases with the row), so each column stays sorted.
        let sub = SymmetricCsc::try_from_symmetric_pattern(far.len(), col_ptr, row_idx, values)?;
        let mut y = vec![0.0; far.len()];
        let opts = PcgOptions {
            preconditioner: Preconditioner::IncompleteCholesky,
            rel_tol: PLANNING_PCG_TOL,
            max_iter: 20_000,
        };
        pcg(&sub, &rhs, &mut y, &opts)?;
        for (&i, &yi) in far.iter().zip(&y) {
            x[i] = yi;
        }
        layered = true;
    }
    Ok(layered.then_some(x))
}

/// The direct method for a clamped (M-matrix) system of `n` unknowns: the accurate elimination
/// up to [`PLANNING_ACCURATE_MAX_UNKNOWNS`], else Cholesky up to
/// [`PLANNING_CHOLESKY_MAX_UNKNOWNS`], else [`VolumeSolveMethod::Auto`].
pub fn planning_method(n: usize) -> VolumeSolveMethod {
    if n <= PLANNING_ACCURATE_MAX_UNKNOWNS {
        VolumeSolveMethod::Accurate
    } else if n <= PLANNING_CHOLESKY_MAX_UNKNOWNS {
        VolumeSolveMethod::Cholesky
    } else {
        VolumeSolveMethod::Auto
    }
}

/// One-shot for planning: assemble `bcs` on `mesh` with the Galerkin stiffness and solve
/// ([`VolumeSolveMethod::Auto`]). If that solution has an interior local extremum (possible
/// where the mesh has obtuse dihedral angles), or ψ spans more than 1/[`FLAT_RATIO_3D`] (a
/// far field a Cholesky solve cannot resolve), assemble again with [`NegativeWeights::Clamp`]
/// — an M-matrix, so no interior extremum — and solve that as `solve_clamped_for_planning`
/// says.
pub fn solve_volume_potential(
    mesh: Arc<TetMesh>,
    bcs: &BoundaryConditions,
) -> Result<VolumePotential, FemError> {
    Ok(solve_volume_potential_with_report(mesh, bcs)?.0)
}

/// [`solve_volume_potential`], also returning the report of the solve that produced ψ and
/// whether the clamped (M-matrix) stiffness was used.
pub fn solve_volume_potential_with_report(
    mesh: Arc<TetMesh>,
    bcs: &BoundaryConditions,
) -> Result<(VolumePotential, VolumeSolveReport, bool), FemError> {
    let assembler = VolumeAssembler::new(mesh, bcs)?;
    let system = assembler.assemble(bcs)?;
    let (potential, report, clamped) = solve_assembled_for_planning(&assembler, bcs, &system)?;
    Ok((potential, report, clamped.is_some()))
}

/// The planning solve of [`solve_volume_potential_with_report`] for a `system` that
/// `assembler` assembled from `bcs` with the Galerkin stiffness (so a caller can time the
/// assembly apart): solve, and redo with the clamped M-matrix, on the same pattern, where the
/// field has an interior extremum or is too flat for a Cholesky solve. The last item is the
/// number of clamped edges when the redo ran.
pub fn solve_assembled_for_planning(
    assembler: &VolumeAssembler,
    bcs: &BoundaryConditions,
    system: &VolumeSystem,
) -> Result<(VolumePotential, VolumeSolveReport, Option<usize>), FemError> {
    planning_solve(assembler.mesh(), system, || {
        assembler.assemble_weighted(bcs, None, NegativeWeights::Clamp)
    })
}

/// From this many unknowns a volume's Galerkin try is solved by the multigrid (below, by
/// IC(0)-PCG; the clamped try takes the multigrid from [`AUTO_MULTIGRID_MIN_UNKNOWNS`]
/// either way). A volume's Galerkin field often passes the check, and where ψ falls many
/// orders of magnitude only IC(0)'s does: the 3D maze at 1 M tetrahedra (147 k unknowns, ψ
/// down to 1e-66) built in 1.89 s on one thread with IC(0) and 2.45 s with the multigrid,
/// whose field failed the check on both systems. (A configuration space makes no Galerkin
/// try: see `solve_periodic_for_planning`.) Above this size no clamped try runs beside the
/// Galerkin one, and IC(0) is far slower than the multigrid (me766: 6.2 s against 1.9 s).
pub const VOLUME_GALERKIN_MULTIGRID_MIN_UNKNOWNS: usize = SPECULATIVE_MAX_UNKNOWNS;

/// The planning solve on `mesh`: the Galerkin `system` first;
/// when its field is flat or has an interior extremum, `clamped()` assembles the M-matrix and
/// [`solve_clamped_for_planning`] solves it. Returns the clamped edges when the redo ran.
fn planning_solve(
    mesh: &Arc<TetMesh>,
    system: &VolumeSystem,
    clamped: impl FnOnce() -> Result<VolumeSystem, FemError> + Send,
) -> Result<(VolumePotential, VolumeSolveReport, Option<usize>), FemError> {
    let galerkin = || galerkin_checked(mesh, system);
    // A large system's clamped try runs on another core while the Galerkin one is solved (the
    // graded meshes of small goals almost always need it); it is dropped if the Galerkin field
    // passes. Either way the result is the one the sequential order gives.
    let n = system.matrix().n();
    if n > PLANNING_ACCURATE_MAX_UNKNOWNS
        && n <= SPECULATIVE_MAX_UNKNOWNS
        && rayon::current_num_threads() > 1
    {
        let speculative = || -> Result<_, FemError> {
            let system = clamped()?;
            let first = clamped_first_try(mesh, &system)?;
            Ok((system, first))
        };
        let (galerkin, speculative) = rayon::join(galerkin, speculative);
        let (potential, report, passed) = galerkin?;
        if passed {
            return Ok((potential, report, None));
        }
        let (system, first) = speculative?;
        let (potential, report) = clamped_checked(mesh, &system, first)?;
        return Ok((potential, report, Some(system.clamped_edges())));
    }
    let (potential, report, passed) = galerkin()?;
    if passed {
        return Ok((potential, report, None));
    }
    let system = clamped()?;
    let (potential, report) = solve_clamped_for_planning(mesh, &system)?;
    Ok((potential, report, Some(system.clamped_edges())))
}

/// The Galerkin solve of [`planning_solve`] and whether its field passes: solved by the
/// accurate elimination, or neither flat (where the accurate elimination would take it) nor
/// with an interior extremum.
fn galerkin_checked(
    mesh: &Arc<TetMesh>,
    system: &VolumeSystem,
) -> Result<(VolumePotential, VolumeSolveReport, bool), FemError> {
    let method = auto_method(system, VOLUME_GALERKIN_MULTIGRID_MIN_UNKNOWNS);
    let (psi, report) = solve_volume(system, method)?;
    let flat = {
        let free = system.free_vertices();
        let (lo, hi) = free.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| {
            (a.min(psi[v as usize]), b.max(psi[v as usize]))
        });
        !free.is_empty() && (lo.is_nan() || lo <= FLAT_RATIO_3D * hi)
    };
    let potential = VolumePotential::new(Arc::clone(mesh), psi, system.reference())?;
    let accurate_already = report.method == VolumeSolveMethod::Accurate;
    // A flat field is only worth redoing when the accurate elimination will take it.
    let flat = flat && system.matrix().n() <= PLANNING_ACCURATE_MAX_UNKNOWNS;
    let passed = accurate_already || (!flat && potential.interior_local_extrema() == 0);
    Ok((potential, report, passed))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain whose every unknown leaks to the walls: ψ falls by about 60 a step from the
    /// goal's end, to 1e-89 at the far end. From values wrong by 1e-14 of the largest everywhere, the layers
    /// recover every value to 1e-3 relatively.
    #[test]
    fn far_field_layers_recover_a_decay_far_below_the_residual() {
        let n: usize = 50;
        let (diag, off) = (62.0, -1.0);
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for (i, v) in [(j.wrapping_sub(1), off), (j, diag), (j + 1, off)] {
                if i < n {
                    row_idx.push(i);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let a = SymmetricCsc::try_new(n, col_ptr, row_idx, values).expect("a chain");
        let mut b = vec![0.0; n];
        b[0] = 1.0;
        // The exact solution by elimination from the far end: d_k = 62 − 1/d_{k+1} (1/d is
        // below 0.02: no cancellation), then x_0 = b_0/d_0 and x_k = x_{k−1}/d_k, each entry
        // to a few roundings relatively however small.
        let mut d = vec![0.0; n];
        d[n - 1] = diag;
        for k in (0..n - 1).rev() {
            d[k] = diag - 1.0 / d[k + 1];
        }
        let mut exact = vec![0.0; n];
        exact[0] = b[0] / d[0];
        for k in 1..n {
            exact[k] = exact[k - 1] / d[k];
        }
        // What a residual-based stop leaves: the solution with an absolute error of about
        // 1e-14 of the largest value everywhere, which swamps the far end.
        let x: Vec<f64> = (0..n)
            .map(|k| exact[k] + 1e-14 * exact[0] * (((k * 7919) % 13) as f64 / 6.0 - 1.0))
            .collect();
        assert!(((x[n - 2] - exact[n - 2]) / exact[n - 2]).abs() > 1.0);
        let layered = far_field_layers(&a, &b, x)
            .expect("solves")
            .expect("a far field");
        for k in 0..n {
            let rel = ((layered[k] - exact[k]) / exact[k]).abs();
            assert!(rel < 1e-3, "unknown {k}: {} vs {}", layered[k], exact[k]);
        }
    }
}
