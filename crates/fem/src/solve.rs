//! Solving the reduced system: a sparse Cholesky factorisation with reusable symbolic analysis,
//! or the entrywise-accurate M-matrix LDLᵀ that keeps ψ's relative precision down to 1e-300.

use std::sync::{Arc, Mutex};

use harmonic_solver::{
    AccurateLdlt, LdltAnalysis, Ordering, Parallelism, SymbolicCholesky, Wide, WideLdlt,
};
use harmonic_types::Mesh;

use crate::FemError;
use crate::assemble::{Assembler, AssemblyOptions, LinearSystem, NotMMatrix};
use crate::bc::BoundaryConditions;
use crate::potential::{Potential, unsound};

/// Up to this many unknowns [`SolveMethod::Auto`] uses the accurate solve outright: there it
/// costs about as much as the Cholesky factorisation or less (0.63–1.11× of it from 14 k to
/// 148 k unknowns, 1.12–1.19× at 296 k: see the crate docs), while a flat field above it costs
/// both.
pub const AUTO_ACCURATE_MAX_UNKNOWNS: usize = 150_000;

/// Above [`AUTO_ACCURATE_MAX_UNKNOWNS`], [`SolveMethod::Auto`] redoes a Cholesky solution
/// with the accurate solve when the smallest ψ at an unknown is below this fraction of the
/// largest (or not positive): there a Cholesky ψ may have lost its relative precision.
pub const AUTO_FLAT_RATIO: f64 = 1e-12;

/// An accurate solution with a ψ at an unknown below this (or a zero ψ beside a positive
/// one, which the M-matrix's positive inverse rules out) may have underflowed on the way:
/// it is redone in extended-exponent arithmetic ([`WideLdlt`]), and a [`Potential`] holding
/// non-zero values below it keeps them with their exponents. Above it, nothing changes.
pub const EXTENDED_BELOW: f64 = 1e-250;

/// How [`Solver`] solves the reduced system.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SolveMethod {
    /// faer's supernodal Cholesky: the fastest on large meshes; ψ is accurate relative to
    /// its largest value (normwise), so values far below it may lose their digits.
    Cholesky,
    /// The GTH-style LDLᵀ of the M-matrix given by its off-diagonal magnitudes and row
    /// excesses ([`LinearSystem::m_matrix`]): every ψ to a small *relative* error however small
    /// (down to the underflow threshold). Needs a Delaunay mesh and lumped Robin mass, else
    /// [`FemError::NotMMatrix`]. Multifrontal; about 1.2× Cholesky's time from 300 k unknowns.
    Accurate,
    /// Accurate up to [`AUTO_ACCURATE_MAX_UNKNOWNS`] unknowns (no slower than Cholesky there);
    /// above, Cholesky, redone accurately if ψ spans more than 1/[`AUTO_FLAT_RATIO`].
    /// Falls back to Cholesky when the system is not an M-matrix (reported by
    /// [`Solver::solve_with_report`]).
    #[default]
    Auto,
}

/// What a solve actually did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveReport {
    /// The factorisation whose solution was returned: `Cholesky` or `Accurate`.
    pub method: SolveMethod,
    /// Set when [`SolveMethod::Auto`] could not use the accurate solve because the system is
    /// not an M-matrix, so the Cholesky solution (normwise accurate only) was returned.
    pub fell_back: Option<NotMMatrix>,
    /// Whether the ordinary accurate solve underflowed and ψ was redone in extended-exponent
    /// arithmetic (see [`EXTENDED_BELOW`]).
    pub extended: bool,
    /// Whether [`SolveMethod::Auto`] kept a Cholesky ψ spanning more than 1/[`AUTO_FLAT_RATIO`]
    /// because the check [`Solver::potential`] runs found it sound: no negative value and no
    /// interior local extremum (the maximum principle holds, so the tracer cannot stop).
    pub flat_but_sound: bool,
}

/// A sparse solver for the systems of one [`Assembler`]. The ordering and symbolic analysis
/// are done once; each [`solve`](Solver::solve) only factors numerically, so new boundary
/// values cost only the numeric part.
pub struct Solver {
    method: SolveMethod,
    /// Ordering for the accurate factorisation, which is built on first use.
    ordering: Ordering,
    /// `None` when there are no unknowns or the Cholesky path is never needed.
    symbolic: Option<SymbolicCholesky>,
    accurate: Mutex<Option<AccurateLdlt>>,
    n: usize,
    nnz: usize,
}

impl std::fmt::Debug for Solver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solver")
            .field("method", &self.method)
            .field("unknowns", &self.n)
            .field("nnz", &self.nnz)
            .finish_non_exhaustive()
    }
}

impl Solver {
    /// [`Solver::with_method`] with [`SolveMethod::Auto`].
    pub fn new(system: &LinearSystem, ordering: Ordering) -> Result<Self, FemError> {
        Self::with_method(system, ordering, SolveMethod::Auto)
    }

    /// Prepares to solve systems with `system`'s pattern by `method`, with `ordering`
    /// ([`Assembler::nested_dissection`] is the fastest on meshes; `Ordering::Amd` needs no
    /// coordinates). For [`SolveMethod::Accurate`] fails with [`FemError::NotMMatrix`] if
    /// `system` is not an M-matrix.
    pub fn with_method(
        system: &LinearSystem,
        ordering: Ordering,
        method: SolveMethod,
    ) -> Result<Self, FemError> {
        Self::with_parallelism(system, ordering, method, Parallelism::default())
    }

    /// [`Solver::with_method`], with the threads the Cholesky path (ordering, factorisation,
    /// solves) may use. The accurate LDLᵀ is sequential either way. Both give the same ψ to
    /// rounding.
    pub fn with_parallelism(
        system: &LinearSystem,
        ordering: Ordering,
        method: SolveMethod,
        parallelism: Parallelism,
    ) -> Result<Self, FemError> {
        let a = system.matrix();
        let needs_cholesky = match method {
            SolveMethod::Cholesky => true,
            SolveMethod::Accurate => {
                if let Some(reason) = system.not_m_matrix() {
                    return Err(FemError::NotMMatrix(reason));
                }
                false
            }
            SolveMethod::Auto => {
                a.n() > AUTO_ACCURATE_MAX_UNKNOWNS || system.not_m_matrix().is_some()
            }
        };
        let symbolic = if a.n() > 0 && needs_cholesky {
            Some(SymbolicCholesky::analyze_with(
                a,
                ordering.clone(),
                parallelism,
            )?)
        } else {
            None
        };
        Ok(Solver {
            method,
            ordering,
            symbolic,
            accurate: Mutex::new(None),
            n: a.n(),
            nnz: a.nnz(),
        })
    }

    /// The method this solver was built with.
    pub fn method(&self) -> SolveMethod {
        self.method
    }

    /// Factors `system`'s matrix and solves; returns ψ at every mesh vertex (values past the
    /// double range underflow to 0 here: [`Solver::potential`] keeps them).
    pub fn solve(&self, system: &LinearSystem) -> Result<Vec<f64>, FemError> {
        Ok(self.solve_with_report(system)?.0)
    }

    /// [`solve`](Self::solve), also saying which factorisation produced ψ.
    pub fn solve_with_report(
        &self,
        system: &LinearSystem,
    ) -> Result<(Vec<f64>, SolveReport), FemError> {
        let (x, report) = self.solve_unknowns(system, None)?;
        let x = match x {
            Unknowns::Plain(x) => x,
            Unknowns::Wide(x) => x.iter().map(|w| w.to_f64()).collect(),
        };
        Ok((system.expand(&x)?, report))
    }

    /// ψ at every mesh vertex in extended-exponent form: [`solve_with_report`]'s values where
    /// they lie in the double range, and the extended accurate solve's where the ordinary one
    /// underflowed (see [`EXTENDED_BELOW`]; `report.extended` says whether it ran).
    ///
    /// [`solve_with_report`]: Self::solve_with_report
    pub fn solve_wide(&self, system: &LinearSystem) -> Result<(Vec<Wide>, SolveReport), FemError> {
        self.solve_wide_checked(system, None)
    }

    /// [`solve_wide`](Self::solve_wide), keeping a flat Cholesky ψ when `sound` accepts it
    /// (given the unknowns).
    fn solve_wide_checked(
        &self,
        system: &LinearSystem,
        sound: Option<SoundCheck<'_>>,
    ) -> Result<(Vec<Wide>, SolveReport), FemError> {
        let (x, report) = self.solve_unknowns(system, sound)?;
        let psi = match x {
            Unknowns::Plain(x) => system.expand(&x)?.into_iter().map(Wide::from_f64).collect(),
            Unknowns::Wide(x) => {
                let fixed = system.expand(&vec![0.0; x.len()])?;
                let mut psi: Vec<Wide> = fixed.into_iter().map(Wide::from_f64).collect();
                for (&v, &xi) in system.free_vertices().iter().zip(&x) {
                    psi[v as usize] = xi;
                }
                psi
            }
        };
        Ok((psi, report))
    }

    fn solve_unknowns(
        &self,
        system: &LinearSystem,
        sound: Option<SoundCheck<'_>>,
    ) -> Result<(Unknowns, SolveReport), FemError> {
        let a = system.matrix();
        if a.n() != self.n || a.nnz() != self.nnz {
            return Err(FemError::ForeignSystem);
        }
        let report = |method, fell_back, x: &Unknowns| SolveReport {
            method,
            fell_back,
            extended: matches!(x, Unknowns::Wide(_)),
            flat_but_sound: false,
        };
        if self.n == 0 {
            let x = Unknowns::Plain(vec![]);
            let r = report(self.method, None, &x);
            return Ok((x, r));
        }
        Ok(match self.method {
            SolveMethod::Cholesky => {
                let x = Unknowns::Plain(self.cholesky(system)?);
                let r = report(SolveMethod::Cholesky, None, &x);
                (x, r)
            }
            SolveMethod::Accurate => {
                let x = self.accurate(system)?;
                let r = report(SolveMethod::Accurate, None, &x);
                (x, r)
            }
            SolveMethod::Auto => match system.not_m_matrix() {
                Some(reason) => {
                    let x = Unknowns::Plain(self.cholesky(system)?);
                    let r = report(SolveMethod::Cholesky, Some(reason), &x);
                    (x, r)
                }
                None if self.n <= AUTO_ACCURATE_MAX_UNKNOWNS => {
                    let x = self.accurate(system)?;
                    let r = report(SolveMethod::Accurate, None, &x);
                    (x, r)
                }
                None => {
                    let x = self.cholesky(system)?;
                    let max = x.iter().copied().fold(0.0, f64::max);
                    let min = x.iter().copied().fold(f64::INFINITY, f64::min);
                    let flat = min <= AUTO_FLAT_RATIO * max;
                    if !flat || sound.is_some_and(|ok| ok(&x)) {
                        let x = Unknowns::Plain(x);
                        let mut r = report(SolveMethod::Cholesky, None, &x);
                        r.flat_but_sound = flat;
                        (x, r)
                    } else {
                        let x = self.accurate(system)?;
                        let r = report(SolveMethod::Accurate, None, &x);
                        (x, r)
                    }
                }
            },
        })
    }

    fn cholesky(&self, system: &LinearSystem) -> Result<Vec<f64>, FemError> {
        let symbolic = self
            .symbolic
            .as_ref()
            .expect("the symbolic Cholesky is analysed whenever the Cholesky path can run");
        Ok(symbolic.factor(system.matrix())?.solve(system.rhs())?)
    }

    fn accurate(&self, system: &LinearSystem) -> Result<Unknowns, FemError> {
        // A poisoned lock only means another solve panicked; the factor is refactored anyway.
        let mut guard = self
            .accurate
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let m = match guard.as_mut() {
            Some(factor) => {
                let m = system.m_matrix()?;
                factor.refactor(&m)?;
                m
            }
            None => {
                // The order and L's pattern need only the matrix's pattern: found while the
                // M-matrix (the off-diagonal magnitudes and the excess) is copied out.
                let (m, analysis) = rayon::join(
                    || system.m_matrix(),
                    || LdltAnalysis::of(system.matrix(), self.ordering.clone()),
                );
                let m = m?;
                *guard = Some(analysis?.factor(&m)?);
                m
            }
        };
        let factor = guard.as_ref().expect("factored just above");
        let x = factor.solve(system.rhs())?;
        if !may_have_underflowed(system, &x) {
            return Ok(Unknowns::Plain(x));
        }
        // The same elimination (order and pattern of L) in extended-exponent numbers: where
        // nothing underflowed it rounds exactly as the ordinary one, so only the entries that
        // left the double range change.
        let wide = WideLdlt::factor_like(factor, &m)?;
        Ok(Unknowns::Wide(wide.solve(system.rhs())?))
    }

    /// Solves `system` and wraps the result as a [`Potential`] on `mesh` (the mesh the system
    /// was assembled on).
    /// The potential keeps ψ with exponents where it lies below [`EXTENDED_BELOW`]
    /// ([`Potential::from_wide`]).
    ///
    /// With [`SolveMethod::Auto`], a Cholesky ψ that spans more than 1/[`AUTO_FLAT_RATIO`] is
    /// checked on `mesh` before the accurate solve is run for it: kept when no value is
    /// negative and no interior vertex (on no boundary, not held) is a strict local extremum
    /// — the discrete maximum principle, which is what the tracer needs. On the 994 k-triangle
    /// reference scene that keeps the 1.0 s Cholesky ψ instead of a 3.4 s accurate redo, and
    /// the path is the same.
    pub fn potential(&self, mesh: Arc<Mesh>, system: &LinearSystem) -> Result<Potential, FemError> {
        Ok(self.potential_with_report(mesh, system)?.0)
    }

    /// [`potential`](Self::potential), also saying how ψ was obtained.
    pub fn potential_with_report(
        &self,
        mesh: Arc<Mesh>,
        system: &LinearSystem,
    ) -> Result<(Potential, SolveReport), FemError> {
        let sound = |x: &[f64]| -> bool {
            system
                .expand(x)
                .is_ok_and(|psi| unsound(&mesh, &psi, system.free_vertices()).is_none())
        };
        let (psi, report) = self.solve_wide_checked(system, Some(&sound))?;
        Ok((Potential::from_wide(mesh, psi, system.reference())?, report))
    }
}

/// Whether a flat Cholesky solution (the unknowns) may be kept.
type SoundCheck<'a> = &'a dyn Fn(&[f64]) -> bool;

/// The reduced system's solution: ordinary floats, or extended-exponent numbers when the
/// ordinary accurate solve underflowed.
enum Unknowns {
    Plain(Vec<f64>),
    Wide(Vec<Wide>),
}

/// Whether an accurate solution may have lost entries to underflow: a positive entry below
/// [`EXTENDED_BELOW`], or a zero entry coupled to a positive one (in an irreducible
/// M-matrix block every entry of the solution is positive or every one is zero).
fn may_have_underflowed(system: &LinearSystem, x: &[f64]) -> bool {
    let a = system.matrix();
    x.iter().enumerate().any(|(i, &xi)| {
        (xi > 0.0 && xi < EXTENDED_BELOW)
            || (xi == 0.0 && a.column(i).0.iter().any(|&j| x[j] > 0.0))
    })
}

/// One-shot convenience: assemble (lumped Robin mass), analyse in [`Assembler::ordering`]
/// (nested dissection but for small systems), factor and solve ([`SolveMethod::Auto`]).
/// For repeated solves on one mesh keep the [`Assembler`] and [`Solver`] instead.
pub fn solve_potential(mesh: Arc<Mesh>, bcs: &BoundaryConditions) -> Result<Potential, FemError> {
    let assembler = Assembler::new(Arc::clone(&mesh), bcs, AssemblyOptions::default())?;
    let system = assembler.assemble(bcs)?;
    let solver = Solver::new(&system, assembler.ordering())?;
    solver.potential(mesh, &system)
}
