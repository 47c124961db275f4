//! P1 on a periodic mesh (a configuration space whose angles wrap around): the system of the
//! slab of one period (`harmonic_volume::PeriodicMesh::slab`) is assembled as any other, its
//! two end surfaces given the natural condition (no term), and then *folded*: every pair of
//! identified vertices becomes one unknown, `A' = Pᵀ A P` and `b' = Pᵀ b` with `P` the 0/1
//! map from the slab's unknowns to the periodic ones. Every element's stiffness is counted
//! once, so `A'` is exactly the stiffness of the periodic mesh; folding adds rows of a
//! diagonally dominant M-matrix (identified vertices share no edge), so it stays one and the
//! accurate elimination applies as before. A vertex of one end may lie on a held face while
//! its image at the other end does not (the face belongs to the other end's tetrahedra): the
//! assembler is told the identification (`VolumeAssembler::with_identified`) so that both
//! are held alike.

use std::sync::Arc;

use harmonic_solver::SymmetricCsc;
use harmonic_types::{SEAM_PART, TetMesh};

use super::FemError;
use super::assemble::{NegativeWeights, VolumeAssembler, VolumeAssemblyOptions, VolumeSystem};
use super::potential::VolumePotential;
use super::solve::{VolumeSolveReport, solve_clamped_for_planning};
use crate::bc::{BoundaryCondition, BoundaryConditions};

/// `bcs` with the slab's end faces (`Obstacle(SEAM_PART)`) under the natural condition.
pub fn periodic_conditions(bcs: &BoundaryConditions) -> BoundaryConditions {
    let mut out = bcs.clone();
    out.obstacle_overrides
        .insert(SEAM_PART, BoundaryCondition::Neumann(0.0));
    out
}

/// Folds `system` (assembled on a slab) so that vertex `v` and `images[v]` are one unknown;
/// [`VolumeSystem::expand`] of the folded system gives both the same ψ.
pub fn identify_periodic(system: &VolumeSystem, images: &[u32]) -> Result<VolumeSystem, FemError> {
    Fold::of(system, images)?.apply(system)
}

/// The folding of one slab pattern ([`identify_periodic`]): found once, it applies to every
/// system assembled on that pattern (the Galerkin and the clamped one alike).
struct Fold {
    /// The slab vertex of each folded unknown (those that are their own image).
    free: Arc<Vec<u32>>,
    /// The folded unknown of each slab unknown.
    fold: Vec<usize>,
    /// The folded matrix's pattern, every value zero.
    template: SymmetricCsc,
    /// The slab's pattern (shared), which every folded system must have.
    slab_pattern: SymmetricCsc,
    /// Where each stored entry of the slab's matrix is added in the folded one.
    slot: Vec<u32>,
    /// Per stored entry of the folded matrix below its diagonal: (the entry, its mirror
    /// above the diagonal).
    mirror: Vec<(u32, u32)>,
    images: Arc<Vec<u32>>,
}

impl Fold {
    /// The folding of `system`'s unknowns and pattern by `images`; errors where a vertex and
    /// its image are not both unknowns or both prescribed.
    fn of(system: &VolumeSystem, images: &[u32]) -> Result<Fold, FemError> {
        let nv = images.len();
        if system.psi_fixed.len() != nv {
            return Err(FemError::LengthMismatch {
                what: "periodic images",
                expected: system.psi_fixed.len(),
                got: nv,
            });
        }
        const NONE: usize = usize::MAX;
        let mut unknown_of = vec![NONE; nv];
        for (i, &v) in system.free.iter().enumerate() {
            unknown_of[v as usize] = i;
        }
        // New numbering: the unknowns that are their own image.
        let mut new_of_vertex = vec![NONE; nv];
        let mut free = Vec::new();
        for &v in system.free.iter() {
            if images[v as usize] == v {
                new_of_vertex[v as usize] = free.len();
                free.push(v);
            }
        }
        let mut fold = vec![NONE; system.free.len()];
        for (i, &v) in system.free.iter().enumerate() {
            let r = images[v as usize] as usize;
            if r >= nv || new_of_vertex[r] == NONE {
                return Err(FemError::PeriodicMismatch {
                    vertex: v,
                    image: r as u32,
                });
            }
            fold[i] = new_of_vertex[r];
        }
        // A prescribed vertex must be identified with a prescribed one.
        for v in 0..nv {
            let r = images[v] as usize;
            if r < nv && (unknown_of[v] == NONE) != (unknown_of[r] == NONE) {
                return Err(FemError::PeriodicMismatch {
                    vertex: v as u32,
                    image: r as u32,
                });
            }
        }
        // The slab's entries grouped by folded column (a counting sort), then each column's
        // rows sorted and merged: entry k of the slab's matrix lands in `slot[k]`.
        let n = free.len();
        let a = &system.matrix;
        let (a_ptr, a_rows) = (a.col_ptr(), a.row_idx());
        let mut start = vec![0usize; n + 1];
        for j in 0..a.n() {
            start[fold[j] + 1] += a_ptr[j + 1] - a_ptr[j];
        }
        for c in 0..n {
            start[c + 1] += start[c];
        }
        // Entries and folded rows are numbered in 32 bits (the assembler's matrices are).
        if a_rows.len() >= u32::MAX as usize {
            return Err(FemError::TooLarge { nnz: a_rows.len() });
        }
        let mut next = start.clone();
        // (folded row, slab entry), by folded column.
        let mut grouped = vec![(0u32, 0u32); a_rows.len()];
        for j in 0..a.n() {
            let c = &mut next[fold[j]];
            for k in a_ptr[j]..a_ptr[j + 1] {
                grouped[*c] = (fold[a_rows[k]] as u32, k as u32);
                *c += 1;
            }
        }
        drop(next);
        let mut slot = vec![0u32; a_rows.len()];
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(a_rows.len());
        col_ptr.push(0);
        for c in 0..n {
            let column = &mut grouped[start[c]..start[c + 1]];
            column.sort_unstable();
            for &(i, k) in column.iter() {
                let i = i as usize;
                if row_idx.len() == *col_ptr.last().unwrap_or(&0) || row_idx.last() != Some(&i) {
                    row_idx.push(i);
                }
                slot[k as usize] = (row_idx.len() - 1) as u32;
            }
            col_ptr.push(row_idx.len());
        }
        let nnz = row_idx.len();
        let template =
            SymmetricCsc::try_from_symmetric_pattern(n, col_ptr, row_idx, vec![0.0; nnz])?;
        let mirror = mirrors(&template);
        Ok(Fold {
            free: Arc::new(free),
            fold,
            template,
            slab_pattern: SymmetricCsc::zeros_like(a),
            slot,
            mirror,
            images: Arc::new(images.to_vec()),
        })
    }

    /// `system` folded: its matrix's entries, right-hand side and excesses summed into the
    /// folded unknowns (in the slab's order, so the sums do not depend on anything else).
    fn apply(&self, system: &VolumeSystem) -> Result<VolumeSystem, FemError> {
        let a = &system.matrix;
        if !a.shares_pattern(&self.slab_pattern) || system.rhs.len() != self.fold.len() {
            return Err(FemError::LengthMismatch {
                what: "a system folded by another assembly's pattern",
                expected: self.fold.len(),
                got: system.rhs.len(),
            });
        }
        let n = self.free.len();
        let mut matrix = SymmetricCsc::zeros_like(&self.template);
        let values = matrix.values_mut();
        for (&k, &x) in self.slot.iter().zip(a.values()) {
            values[k as usize] += x;
        }
        // An entry and its mirror sum the same slab entries in different orders, which can
        // round apart: the matrix is made symmetric to the bit (the accurate elimination
        // refuses anything else).
        for &(lower, upper) in &self.mirror {
            values[upper as usize] = values[lower as usize];
        }
        let mut rhs = vec![0.0; n];
        let mut excess = vec![0.0; n];
        for (i, &f) in self.fold.iter().enumerate() {
            rhs[f] += system.rhs[i];
            excess[f] += system.excess[i];
        }
        Ok(VolumeSystem {
            matrix,
            rhs,
            excess,
            psi_fixed: system.psi_fixed.clone(),
            reference: system.reference,
            not_m_matrix: system.not_m_matrix,
            free: Arc::clone(&self.free),
            positive_offdiagonals: system.positive_offdiagonals,
            clamped: system.clamped,
            images: Some(Arc::clone(&self.images)),
        })
    }
}

/// Per stored entry of `a` below the diagonal, (the entry, its mirror above the diagonal),
/// for a pattern symmetric by construction: columns in increasing order meet the entries of
/// column `i` above its diagonal in increasing row order too, so a cursor per column finds
/// each mirror without a search.
fn mirrors(a: &SymmetricCsc) -> Vec<(u32, u32)> {
    let (ptr, rows) = (a.col_ptr(), a.row_idx());
    let mut cursor: Vec<usize> = ptr[..a.n()].to_vec();
    let mut out = Vec::with_capacity(rows.len() / 2);
    for j in 0..a.n() {
        for k in ptr[j]..ptr[j + 1] {
            let i = rows[k];
            if i > j {
                let m = cursor[i];
                debug_assert_eq!(rows[m], j, "the pattern is symmetric");
                cursor[i] += 1;
                out.push((k as u32, m as u32));
            }
        }
    }
    out
}

/// What [`solve_periodic_for_planning`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicSolveReport {
    /// The solve that produced ψ.
    pub solve: VolumeSolveReport,
    /// Edges clamped: those whose Galerkin weight was negative beyond round-off, the
    /// positive off-diagonals the Galerkin slab matrix would have had (it is not assembled,
    /// see [`solve_periodic_for_planning`]).
    pub clamped_edges: usize,
    /// Unknowns of the folded system.
    pub unknowns: usize,
}

/// The planning solve of a configuration space on its periodic slab: assemble with the
/// clamped stiffness ([`NegativeWeights::Clamp`], ends natural), fold by `images`, and solve
/// as the clamped redo of [`super::solve_assembled_for_planning`] does (the accurate
/// elimination up to its size, else IC(0)-PCG checked for interior extrema).
///
/// No Galerkin try comes first, as it does for a volume: a slab's stuffed and graded
/// tetrahedra have obtuse dihedral angles by the tens of thousands, and on every configuration
/// space measured (the contract's polygon robot and arms, the bundled robots, seeded 3-link
/// arms) the Galerkin field had interior extrema and the clamped field was the one kept. The
/// try cost a second assembly on the way and a core for its solve.
pub fn solve_periodic_for_planning(
    slab: Arc<TetMesh>,
    images: &[u32],
    bcs: &BoundaryConditions,
) -> Result<(VolumePotential, PeriodicSolveReport), FemError> {
    let system = assemble_periodic_for_planning(&slab, images, bcs)?;
    solve_folded_for_planning(&slab, &system)
}

/// The first half of [`solve_periodic_for_planning`]: the folded clamped system (a caller
/// may then solve it beside other work).
pub fn assemble_periodic_for_planning(
    slab: &Arc<TetMesh>,
    images: &[u32],
    bcs: &BoundaryConditions,
) -> Result<VolumeSystem, FemError> {
    let bcs = periodic_conditions(bcs);
    let assembler = VolumeAssembler::with_identified(
        Arc::clone(slab),
        &bcs,
        VolumeAssemblyOptions::default(),
        Arc::new(images.to_vec()),
    )?;
    let a = assembler.assemble_weighted(&bcs, None, NegativeWeights::Clamp)?;
    Fold::of(&a, images)?.apply(&a)
}

/// The second half of [`solve_periodic_for_planning`]: `system`, folded on `slab` by
/// [`assemble_periodic_for_planning`], solved.
pub fn solve_folded_for_planning(
    slab: &Arc<TetMesh>,
    system: &VolumeSystem,
) -> Result<(VolumePotential, PeriodicSolveReport), FemError> {
    let (potential, solve) = solve_clamped_for_planning(slab, system)?;
    let clamped_edges = system.clamped_edges();
    Ok((
        potential,
        PeriodicSolveReport {
            solve,
            clamped_edges,
            unknowns: system.matrix().n(),
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_types::BoundaryTag;
    use harmonic_volume::{
        ImplicitDomain, PeriodicMesh, Point, StuffingOptions, Vector, stuff_periodic,
    };

    /// A box periodic in z, held at φ = 1 on x = 0 and φ = 0 on x = 1 (a goal slab): the
    /// exact solution is φ = 1 − x whatever z, and the folded P1 solution reproduces it (P1
    /// holds linear functions exactly); the slab's ends carry no condition.
    struct Slab;
    impl ImplicitDomain for Slab {
        fn value(&self, p: &Point) -> f64 {
            let y = (p.y - 0.5).abs() - 0.5;
            let x = (p.x - 0.5).abs() - 0.5;
            x.max(y)
        }
        fn tag(&self, p: &Point) -> BoundaryTag {
            if p.x > 0.99 {
                BoundaryTag::Goal(0)
            } else if p.x < 0.01 {
                BoundaryTag::Wall
            } else {
                BoundaryTag::Obstacle(0)
            }
        }
        fn bounds(&self) -> (Point, Point) {
            (Point::new(0.0, 0.0, 0.0), Point::new(1.0, 1.0, 1.0))
        }
    }

    #[test]
    fn folded_slab_reproduces_a_linear_field() {
        let stuffed = stuff_periodic(
            &Slab,
            &StuffingOptions {
                spacing: 0.125,
                max_tetrahedra: 1_000_000,
            },
            [None, None, Some(8)],
        )
        .unwrap();
        let pm = PeriodicMesh::new(&stuffed, 1, &|p| Slab.tag(p)).unwrap();
        assert!(pm.seam_faces > 0);
        let mut bcs = BoundaryConditions::default();
        bcs.obstacle_overrides
            .insert(0, BoundaryCondition::Neumann(0.0));
        let slab = Arc::new(pm.slab);
        let (pot, _) = solve_periodic_for_planning(Arc::clone(&slab), &pm.images, &bcs).unwrap();
        let phi = pot.phi_at_vertices();
        for (v, p) in slab.vertices().iter().enumerate() {
            assert!((phi[v] - (1.0 - p.x)).abs() < 1e-9, "{v} {p:?} {}", phi[v]);
        }
        // The covering glues the copies: a segment across z = 1 stays inside the mesh.
        let cov = &pm.covering;
        let t = cov.locate(&Point::new(0.5, 0.5, 0.99), None).unwrap();
        let t2 = cov.walk(&Point::new(0.5, 0.5, 1.01), t);
        assert!(t2.is_some());
        let _ = Vector::zeros();
    }

    /// One folding serves every system assembled on the slab's pattern (the Galerkin and the
    /// clamped one): each comes out as a fresh fold of its own would make it, entry by entry,
    /// and a system assembled on another pattern is refused.
    #[test]
    fn one_fold_serves_every_system_on_the_pattern() {
        let stuffed = stuff_periodic(
            &Slab,
            &StuffingOptions {
                spacing: 0.15,
                max_tetrahedra: 1_000_000,
            },
            [None, None, Some(7)],
        )
        .unwrap();
        let pm = PeriodicMesh::new(&stuffed, 1, &|p| Slab.tag(p)).unwrap();
        let bcs = periodic_conditions(&BoundaryConditions::default());
        let slab = Arc::new(pm.slab);
        let assembler = VolumeAssembler::with_identified(
            Arc::clone(&slab),
            &bcs,
            VolumeAssemblyOptions::default(),
            Arc::new(pm.images.clone()),
        )
        .unwrap();
        let galerkin = assembler.assemble(&bcs).unwrap();
        let clamped = assembler
            .assemble_weighted(&bcs, None, NegativeWeights::Clamp)
            .unwrap();
        let fold = Fold::of(&galerkin, &pm.images).unwrap();
        for system in [&galerkin, &clamped] {
            let once = fold.apply(system).unwrap();
            let fresh = identify_periodic(system, &pm.images).unwrap();
            assert!(
                once.matrix().n() < system.matrix().n(),
                "vertices were identified"
            );
            assert_eq!(once.matrix().col_ptr(), fresh.matrix().col_ptr());
            assert_eq!(once.matrix().row_idx(), fresh.matrix().row_idx());
            assert_eq!(once.matrix().values(), fresh.matrix().values());
            assert_eq!(once.rhs(), fresh.rhs());
            assert_eq!(once.excess(), fresh.excess());
            assert_eq!(once.free_vertices(), fresh.free_vertices());
        }
        // Independently: each folded entry (i, j) is the sum of the slab's entries (k, l)
        // with fold[k] = i and fold[l] = j, and nothing else is stored.
        for system in [&galerkin, &clamped] {
            let a = system.matrix();
            let mut sums: std::collections::HashMap<(usize, usize), f64> = Default::default();
            for l in 0..a.n() {
                let (rows, values) = a.column(l);
                for (&k, &x) in rows.iter().zip(values) {
                    *sums.entry((fold.fold[k], fold.fold[l])).or_default() += x;
                }
            }
            let folded = fold.apply(system).unwrap();
            let m = folded.matrix();
            let mut stored = 0;
            for j in 0..m.n() {
                let (rows, values) = m.column(j);
                for (&i, &x) in rows.iter().zip(values) {
                    let want = sums[&(i, j)];
                    assert!(
                        (x - want).abs() <= 1e-14 * want.abs().max(1.0),
                        "({i}, {j})"
                    );
                    // Symmetric to the bit, whatever order the two sums were taken in.
                    let (mirror_rows, mirror_values) = m.column(i);
                    let at = mirror_rows.binary_search(&j).expect("a symmetric pattern");
                    assert_eq!(mirror_values[at].to_bits(), x.to_bits(), "({i}, {j})");
                    stored += 1;
                }
            }
            assert_eq!(stored, sums.len());
        }
        // Another assembly (its own pattern) is not folded by this one's.
        let other = VolumeAssembler::with_identified(
            Arc::clone(&slab),
            &bcs,
            VolumeAssemblyOptions::default(),
            Arc::new(pm.images.clone()),
        )
        .unwrap()
        .assemble(&bcs)
        .unwrap();
        assert!(matches!(
            fold.apply(&other),
            Err(FemError::LengthMismatch { .. })
        ));
    }
}
